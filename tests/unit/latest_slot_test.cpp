// The latest-wins slot between two threads: the newest value wins, what it replaced unseen is counted, a
// consumer can wait for a value that satisfies a predicate, and close() wakes it.

#include "base/latest_slot.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

namespace dc::base {
namespace {

// Only a guard against a deadlock: every wait below that should end does so long before.
constexpr std::chrono::milliseconds kDeadlockGuard{10'000};

TEST(LatestSlot, TheNewestValueWinsAndWhatItReplacedUnseenIsCounted) {
    LatestSlot<int> slot;
    EXPECT_FALSE(slot.take().has_value());
    EXPECT_FALSE(slot.put(1));
    EXPECT_TRUE(slot.put(2));
    EXPECT_TRUE(slot.put(3));
    EXPECT_EQ(slot.take(), 3);
    EXPECT_FALSE(slot.take().has_value()) << "a value is delivered once";
    EXPECT_FALSE(slot.put(4)) << "the slot was empty: nothing replaced";
    EXPECT_EQ(slot.take(), 4);
    const LatestSlot<int>::Counts counts = slot.counts();
    EXPECT_EQ(counts.put, 4u);
    EXPECT_EQ(counts.replaced, 2u);
    EXPECT_EQ(counts.taken, 2u);
}

TEST(LatestSlot, OnReplaceSeesTheUnseenValueAndMayCarryItOver) {
    LatestSlot<int> slot;
    slot.put(10);
    int unseen = 0;
    slot.put(1, [&](const int& old, int& next) {
        unseen = old;
        next += old;
    });
    EXPECT_EQ(unseen, 10);
    EXPECT_EQ(slot.take(), 11);
}

TEST(LatestSlot, WaitTakeWithAPredicateLeavesValuesThatDoNotSatisfyItAndTimesOut) {
    LatestSlot<int> slot;
    const auto even = [](const int& v) { return v % 2 == 0; };
    slot.put(1);
    EXPECT_FALSE(slot.waitTake(std::chrono::milliseconds(1), even).has_value());
    EXPECT_EQ(slot.take(), 1) << "the value that did not satisfy the predicate stays for take()";
    EXPECT_FALSE(slot.waitTake(std::chrono::milliseconds(1)).has_value()) << "empty: times out";
}

TEST(LatestSlot, WaitTakeWakesForTheFirstValueThatSatisfiesThePredicate) {
    LatestSlot<int> slot;
    std::thread producer([&] {
        for (int v = 1; v <= 1000; ++v)
            slot.put(v);
    });
    const std::optional<int> got = slot.waitTake(kDeadlockGuard, [](const int& v) { return v >= 1000; });
    producer.join();
    EXPECT_EQ(got, 1000);
    EXPECT_EQ(slot.counts().taken, 1u) << "the values before it were skipped, not taken";
}

TEST(LatestSlot, CloseWakesAWaiterAndRefusesLaterValues) {
    LatestSlot<int> slot;
    std::optional<int> got = 0;
    std::thread waiter([&] { got = slot.waitTake(kDeadlockGuard); });
    slot.close();
    waiter.join(); // would wait the whole guard if close() did not wake it
    EXPECT_FALSE(got.has_value());
    EXPECT_FALSE(slot.put(5));
    EXPECT_FALSE(slot.take().has_value()) << "a closed slot refuses values";
    slot.reset();
    slot.put(6);
    EXPECT_EQ(slot.waitTake(kDeadlockGuard), 6) << "reset() opens it again";
}

TEST(LatestSlot, AConcurrentProducerNeverLosesCount) {
    LatestSlot<int> slot;
    constexpr int kPuts = 20000;
    std::thread producer([&] {
        for (int i = 0; i < kPuts; ++i)
            slot.put(i);
    });
    int last = -1;
    while (last != kPuts - 1) {
        if (std::optional<int> v = slot.take()) {
            EXPECT_GT(*v, last) << "values arrive in order";
            last = *v;
        }
    }
    producer.join();
    const LatestSlot<int>::Counts counts = slot.counts();
    EXPECT_EQ(counts.taken + counts.replaced, static_cast<std::uint64_t>(kPuts));
}

} // namespace
} // namespace dc::base
