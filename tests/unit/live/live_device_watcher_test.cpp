#include "devices/uvc/live_device_watcher.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

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

// Polls takeUpdate() for up to two seconds.
std::optional<LiveDeviceListing> awaitUpdate(LiveDeviceWatcher& watcher) {
    for (auto waited = 0ms; waited < 2s; waited += 10ms) {
        if (auto update = watcher.takeUpdate())
            return update;
        std::this_thread::sleep_for(10ms);
    }
    return std::nullopt;
}

TEST(LiveDeviceWatcher, PublishesTheFirstListingThenOnlyChanges) {
    std::atomic<int> cameras{0};
    std::atomic<int> listings{0};
    LiveDeviceWatcher watcher(50ms, [&] {
        ++listings;
        return listingOf(cameras);
    });
    auto first = awaitUpdate(watcher);
    ASSERT_TRUE(first) << "an empty first listing is still published: the picker learns there is none";
    EXPECT_TRUE(first->devices.empty());

    while (listings < 4)
        std::this_thread::sleep_for(10ms);
    EXPECT_FALSE(watcher.takeUpdate()) << "re-listing the same cameras publishes nothing";

    cameras = 2; // a camera appears where hotplug cannot see it (e.g. v4l2loopback): the poll finds it
    auto plugged = awaitUpdate(watcher);
    ASSERT_TRUE(plugged);
    ASSERT_EQ(plugged->devices.size(), 2u);
    EXPECT_EQ(plugged->devices[1].sourceSpec, "v4l2:/dev/video2");

    cameras = 0;
    auto unplugged = awaitUpdate(watcher);
    ASSERT_TRUE(unplugged);
    EXPECT_TRUE(unplugged->devices.empty());
}

TEST(LiveDeviceWatcher, StopsPromptlyWhileIdle) {
    const auto start = std::chrono::steady_clock::now();
    {
        LiveDeviceWatcher watcher(1h, [] { return listingOf(1); });
        ASSERT_TRUE(awaitUpdate(watcher));
    }
    EXPECT_LT(std::chrono::steady_clock::now() - start, 5s) << "the destructor must not wait for the poll";
}

} // namespace
} // namespace dc::devices
