#include "base/mailbox.h"

#include <gtest/gtest.h>

#include <thread>

namespace dc::devices {
namespace {

TEST(Mailbox, LatestValueWinsAndReplacedValuesAreCountedAsDropped) {
    base::Mailbox<int> box;
    EXPECT_FALSE(box.take().has_value());
    box.post(1);
    box.post(2);
    box.post(3);
    EXPECT_EQ(box.dropped(), 2u);
    EXPECT_EQ(box.posted(), 3u);
    EXPECT_EQ(box.take(), 3);
    EXPECT_FALSE(box.take().has_value()) << "a value is delivered once";
    box.post(4);
    EXPECT_EQ(box.take(), 4);
    EXPECT_EQ(box.dropped(), 2u) << "taking before the next post drops nothing";
}

TEST(Mailbox, WaitTakeWakesOnPostAndTimesOutWhenEmpty) {
    base::Mailbox<int> box;
    EXPECT_FALSE(box.waitTake(std::chrono::milliseconds(10)).has_value());
    std::thread producer([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        box.post(7);
    });
    EXPECT_EQ(box.waitTake(std::chrono::seconds(5)), 7);
    producer.join();
}

TEST(Mailbox, ConcurrentProducerNeverLosesCount) {
    base::Mailbox<int> box;
    constexpr int kPosts = 20000;
    std::uint64_t taken = 0;
    std::thread producer([&] {
        for (int i = 0; i < kPosts; ++i)
            box.post(i);
    });
    int last = -1;
    while (last != kPosts - 1) {
        if (auto v = box.take()) {
            EXPECT_GT(*v, last) << "values arrive in order";
            last = *v;
            ++taken;
        }
    }
    producer.join();
    EXPECT_EQ(taken + box.dropped(), static_cast<std::uint64_t>(kPosts));
}

} // namespace
} // namespace dc::devices
