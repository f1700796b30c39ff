#include "devices/uvc/live_device_watcher.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <fcntl.h>
#include <thread>
#include <unistd.h>

namespace dc::devices {
namespace {

using namespace std::chrono_literals;

LiveDeviceListing listingOf(int cameras) {
    LiveDeviceListing listing;
    for (int i = 0; i < cameras; ++i) {
        LiveDeviceInfo d;
        d.depthNode = "/dev/video" + std::to_string(2 * i);
        d.sourceSpec = "v4l2:" + d.depthNode;
        listing.devices.push_back(d);
    }
    return listing;
}

// Polls takeUpdate() for up to five seconds.
std::optional<LiveDeviceListing> awaitUpdate(LiveDeviceWatcher& watcher) {
    for (auto waited = 0ms; waited < 5s; waited += 10ms) {
        if (auto update = watcher.takeUpdate())
            return update;
        std::this_thread::sleep_for(10ms);
    }
    return std::nullopt;
}

// Device events through a pipe: a byte written is an event (udev's monitor in use).
class PipeEvents final : public DeviceEventSource {
public:
    PipeEvents(int readFd) : read_(readFd) {}
    int fd() const override { return read_.get(); }
    bool drain() override {
        char buffer[64];
        bool any = false;
        while (::read(read_.get(), buffer, sizeof buffer) > 0)
            any = true;
        return any;
    }
    std::string name() const override { return "test pipe"; }

private:
    base::UniqueFd read_;
};

// The test's end of the pipe, and the factory that gives the watcher the other end.
struct EventPipe {
    base::UniqueFd write;
    LiveDeviceWatcher::EventSourceFactory factory() {
        int fds[2];
        EXPECT_EQ(::pipe2(fds, O_NONBLOCK | O_CLOEXEC), 0);
        write = base::UniqueFd(fds[1]);
        return [readFd = fds[0]]() -> Expected<std::unique_ptr<DeviceEventSource>> {
            return std::unique_ptr<DeviceEventSource>(std::make_unique<PipeEvents>(readFd));
        };
    }
    void event() { ASSERT_EQ(::write(write.get(), "e", 1), 1); }
};

Expected<std::unique_ptr<DeviceEventSource>> noEvents() {
    return Error{"no netlink here"};
}

TEST(LiveDeviceWatcher, WithoutEventsItPollsAndPublishesOnlyChanges) {
    std::atomic<int> cameras{0};
    std::atomic<int> listings{0};
    LiveDeviceWatcher watcher(
        50ms,
        [&] {
            ++listings;
            return listingOf(cameras);
        },
        noEvents);
    EXPECT_FALSE(watcher.watchingEvents());
    auto first = awaitUpdate(watcher);
    ASSERT_TRUE(first) << "an empty first listing is still published: the picker learns there is none";
    EXPECT_TRUE(first->devices.empty());

    while (listings < 4)
        std::this_thread::sleep_for(10ms);
    EXPECT_FALSE(watcher.takeUpdate()) << "re-listing the same cameras publishes nothing";

    cameras = 2; // without events, only the poll can find it
    auto plugged = awaitUpdate(watcher);
    ASSERT_TRUE(plugged);
    ASSERT_EQ(plugged->devices.size(), 2u);
    EXPECT_EQ(plugged->devices[1].sourceSpec, "v4l2:/dev/video2");
}

TEST(LiveDeviceWatcher, WithEventsItListsAfterEachBurstAndNeverPolls) {
    std::atomic<int> cameras{0};
    std::atomic<int> listings{0};
    EventPipe pipe;
    LiveDeviceWatcher watcher(
        10ms, // the fallback: it must not be used while events work
        [&] {
            ++listings;
            return listingOf(cameras);
        },
        pipe.factory());
    EXPECT_TRUE(watcher.watchingEvents());
    ASSERT_TRUE(awaitUpdate(watcher));
    cameras = 1;
    std::this_thread::sleep_for(500ms);
    EXPECT_EQ(listings, 1) << "no event, no listing: a 10 ms poll would have listed about 50 times";
    EXPECT_FALSE(watcher.takeUpdate());

    for (int i = 0; i < 5; ++i) // one camera's burst: USB device, interfaces, nodes
        ASSERT_NO_FATAL_FAILURE(pipe.event());
    auto plugged = awaitUpdate(watcher);
    ASSERT_TRUE(plugged);
    EXPECT_EQ(plugged->devices.size(), 1u);
    EXPECT_EQ(listings, 2) << "the burst was listed once";

    cameras = 0;
    ASSERT_NO_FATAL_FAILURE(pipe.event());
    auto unplugged = awaitUpdate(watcher);
    ASSERT_TRUE(unplugged);
    EXPECT_TRUE(unplugged->devices.empty());
}

TEST(LiveDeviceWatcher, AnEventSourceThatFailsFallsBackToPolling) {
    std::atomic<int> cameras{0};
    EventPipe pipe;
    LiveDeviceWatcher watcher(
        50ms, [&] { return listingOf(cameras); }, pipe.factory());
    ASSERT_TRUE(awaitUpdate(watcher));
    pipe.write.reset(); // the monitor's socket hangs up
    cameras = 1;
    auto found = awaitUpdate(watcher);
    ASSERT_TRUE(found) << "found by polling";
    EXPECT_EQ(found->devices.size(), 1u);
}

TEST(LiveDeviceWatcher, StopsPromptlyWhileIdle) {
    for (const bool withEvents : {false, true}) {
        EventPipe pipe;
        const auto start = std::chrono::steady_clock::now();
        {
            LiveDeviceWatcher watcher(
                1h, [] { return listingOf(1); },
                withEvents ? pipe.factory() : LiveDeviceWatcher::EventSourceFactory(noEvents));
            ASSERT_TRUE(awaitUpdate(watcher));
        }
        EXPECT_LT(std::chrono::steady_clock::now() - start, 5s)
            << "the destructor must not wait for the poll";
    }
}

} // namespace
} // namespace dc::devices
