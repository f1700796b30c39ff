// A Worker is the one way the project starts a thread: what its body throws is logged and kept, the process
// goes on, and destroying the Worker stops and joins its body.

#include "base/worker.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <stdexcept>
#include <thread>

namespace dc::base {
namespace {

// A body that polls its stop token, then says it returned.
std::function<void(std::stop_token)> pollUntilStopped(std::atomic<bool>& returned) {
    return [&returned](std::stop_token stop) {
        while (!stop.stop_requested())
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        returned = true;
    };
}

TEST(Worker, AnExceptionEndsItsThreadNotTheProcessAndIsKeptForItsOwner) {
    Worker worker("decoding failed", [] { throw std::runtime_error("corrupt chunk"); });
    worker.join();
    ASSERT_TRUE(worker.error().has_value());
    EXPECT_EQ(*worker.error(), "decoding failed: corrupt chunk");

    Worker unknown("the writer stopped", [] { throw 42; });
    unknown.join();
    EXPECT_EQ(unknown.error(), "the writer stopped: an exception of unknown type");
}

TEST(Worker, ABodyThatReturnsLeavesNoError) {
    std::atomic<int> runs{0};
    Worker worker("counting", [&] { ++runs; });
    worker.join();
    EXPECT_EQ(runs.load(), 1);
    EXPECT_FALSE(worker.error().has_value());
    EXPECT_FALSE(worker.joinable());
}

TEST(Worker, DestroyingItAsksTheBodyToStopAndWaitsForIt) {
    std::atomic<bool> returned{false};
    {
        Worker worker("polling", pollUntilStopped(returned));
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        EXPECT_FALSE(returned.load());
    }
    EXPECT_TRUE(returned.load()) << "the destructor joined a body that had stopped";
}

TEST(Worker, AssigningAnotherStopsAndJoinsTheFirst) {
    std::atomic<bool> firstReturned{false};
    Worker worker("first", pollUntilStopped(firstReturned));
    worker = Worker("second", [] {});
    EXPECT_TRUE(firstReturned.load());
    worker.join();
}

} // namespace
} // namespace dc::base
