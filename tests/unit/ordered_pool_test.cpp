// The ordered pool: jobs run in parallel and their results reach the consumer in the order the jobs went in,
// whatever order they finish in; a job that throws yields its error; a full pool refuses; destruction joins.

#include "base/ordered_pool.h"

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <stdexcept>
#include <vector>

namespace dc::base {
namespace {

// Only a guard against a deadlock: every wait below that should end does so long before.
constexpr std::chrono::seconds kDeadlockGuard{10};

// What the consumer got: each result's value, or -1 for an error (its message kept).
struct Delivered {
    std::mutex mutex;
    std::vector<int> values;
    std::vector<std::string> errors;

    OrderedPool<int, int>::Consume consumer() {
        return [this](Expected<int> result) {
            const std::lock_guard lock(mutex);
            values.push_back(result ? *result : -1);
            if (!result)
                errors.push_back(result.error().message);
        };
    }
    std::vector<int> snapshot() {
        const std::lock_guard lock(mutex);
        return values;
    }
};

// A gate jobs wait at until the test opens it, and a count of the jobs that reached it.
struct Gate {
    std::mutex mutex;
    std::condition_variable changed;
    bool open = false;
    int arrived = 0;

    void pass() {
        std::unique_lock lock(mutex);
        ++arrived;
        changed.notify_all();
        ASSERT_TRUE(changed.wait_for(lock, kDeadlockGuard, [this] { return open; }));
    }
    void waitArrived(int jobs) {
        std::unique_lock lock(mutex);
        ASSERT_TRUE(changed.wait_for(lock, kDeadlockGuard, [&] { return arrived >= jobs; }));
    }
    void release() {
        const std::lock_guard lock(mutex);
        open = true;
        changed.notify_all();
    }
};

TEST(OrderedPool, DeliversInSubmissionOrderAlthoughLaterJobsFinishFirst) {
    constexpr int kJobs = 4;
    // Job i finishes only after every later job has: the durations are inverse to the index, by
    // construction rather than by sleeping.
    std::mutex mutex;
    std::condition_variable finished;
    std::vector<int> finishOrder;
    Delivered delivered;
    {
        OrderedPool<int, int> pool(
            {"test pool", "job failed", kJobs, kJobs},
            [&](int& job, std::uint64_t, std::size_t) {
                std::unique_lock lock(mutex);
                const bool later = finished.wait_for(lock, kDeadlockGuard, [&] {
                    return finishOrder.size() == static_cast<std::size_t>(kJobs - 1 - job);
                });
                EXPECT_TRUE(later) << "job " << job;
                finishOrder.push_back(job);
                finished.notify_all();
                return job * 10;
            },
            delivered.consumer());
        for (int i = 0; i < kJobs; ++i)
            ASSERT_TRUE(pool.trySubmit(i));
        pool.finish();
        EXPECT_EQ(pool.pending(), 0u);
    }
    EXPECT_EQ(finishOrder, (std::vector<int>{3, 2, 1, 0}));
    EXPECT_EQ(delivered.snapshot(), (std::vector<int>{0, 10, 20, 30}));
}

TEST(OrderedPool, AThrowingJobYieldsItsErrorAndLaterJobsStillArriveInOrder) {
    Delivered delivered;
    std::vector<std::uint64_t> indices(6);
    OrderedPool<int, int> pool(
        {"test pool", "job failed", 2, 6},
        [&](int& job, std::uint64_t index, std::size_t) {
            indices[static_cast<std::size_t>(job)] = index;
            if (job == 2)
                throw std::runtime_error("corrupt input");
            return job;
        },
        delivered.consumer());
    for (int i = 0; i < 6; ++i)
        ASSERT_TRUE(pool.trySubmit(i));
    pool.finish();
    EXPECT_EQ(delivered.snapshot(), (std::vector<int>{0, 1, -1, 3, 4, 5}));
    ASSERT_EQ(delivered.errors.size(), 1u);
    EXPECT_EQ(delivered.errors[0], "job failed: corrupt input");
    EXPECT_EQ(indices, (std::vector<std::uint64_t>{0, 1, 2, 3, 4, 5})) << "index counts accepted jobs";
}

TEST(OrderedPool, AFullPoolRefusesAndDroppedJobsAreNeverDelivered) {
    Gate gate;
    Delivered delivered;
    OrderedPool<int, int> pool(
        {"test pool", "job failed", 1, 3},
        [&](int& job, std::uint64_t, std::size_t) {
            if (job == 0)
                gate.pass();
            return job;
        },
        delivered.consumer());
    for (int i = 0; i < 3; ++i)
        ASSERT_TRUE(pool.trySubmit(i));
    EXPECT_FALSE(pool.trySubmit(3)) << "three accepted and not delivered: full";
    gate.waitArrived(1);
    EXPECT_EQ(pool.dropQueued(), 2u) << "the one worker is in job 0; jobs 1 and 2 are queued";
    EXPECT_EQ(pool.pending(), 1u);
    ASSERT_TRUE(pool.trySubmit(4)) << "dropping made room";
    gate.release();
    pool.finish();
    EXPECT_EQ(delivered.snapshot(), (std::vector<int>{0, 4}));
    EXPECT_FALSE(pool.trySubmit(5)) << "nothing is accepted after finish()";
}

TEST(OrderedPool, DestructionWithQueuedJobsJoinsWithoutHanging) {
    Gate gate;
    Delivered delivered;
    {
        OrderedPool<int, int> pool(
            {"test pool", "job failed", 1, 10},
            [&](int& job, std::uint64_t, std::size_t) {
                if (job == 0)
                    gate.pass();
                return job;
            },
            delivered.consumer());
        for (int i = 0; i < 10; ++i)
            ASSERT_TRUE(pool.trySubmit(i));
        gate.waitArrived(1);
        gate.release();
    }
    // Whatever the worker took before the destructor dropped the rest was delivered, in order.
    const std::vector<int> values = delivered.snapshot();
    ASSERT_FALSE(values.empty());
    for (std::size_t i = 0; i < values.size(); ++i)
        EXPECT_EQ(values[i], static_cast<int>(i));
}

} // namespace
} // namespace dc::base
