#pragma once

// Sources for the engine tests: real synthetic frames, delivered by a device the test controls, so a test
// can say exactly which frames arrive and when the source goes silent (a paused replay, a stalled camera).

#include "devices/device.h"
#include "devices/frame_pacer.h"
#include "devices/synthetic/synthetic_device.h"
#include "engine/demand.h"

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace dc::engine::test {

// The cloud and every depth panel, without the camera panel's resampled image.
inline Demand cloudAndPanels() {
    Demand d;
    d.cameraPanelWidth = 0;
    return d;
}

// 256x192 depth with a small camera image: every stage runs, but quickly.
inline devices::SyntheticConfig smallScene() {
    devices::SyntheticConfig c;
    c.cameraWidth = 320;
    c.cameraHeight = 240;
    c.motion = true; // every frame differs, so a stage that reran made something new
    return c;
}

// `count` synthetic frames 1/60 s apart, sequences from `first`.
inline std::vector<frame::FramePtr> syntheticFrames(int count, std::uint64_t first = 0) {
    devices::SyntheticDevice device(smallScene());
    (void)device.open();
    std::vector<frame::FramePtr> frames;
    for (int i = 0; i < count; ++i) {
        const std::uint64_t sequence = first + static_cast<std::uint64_t>(i);
        frames.push_back(device.makeFrame(sequence, static_cast<double>(sequence) / 60.0));
    }
    return frames;
}

// A frame of a live camera without sensor confidence (the estimate's input).
inline frame::FramePtr withoutConfidence(const frame::FramePtr& f) {
    auto copy = std::make_shared<frame::Frame>(*f);
    copy->sceneDepth->confidence = {};
    return copy;
}

// As if decoded by a replay after the seek that returned `seekGeneration`.
inline frame::FramePtr asReplayed(const frame::FramePtr& f, std::uint64_t seekGeneration) {
    auto copy = std::make_shared<frame::Frame>(*f);
    copy->replay = frame::ReplayPosition{static_cast<std::size_t>(f->sequence), 1000, seekGeneration};
    return copy;
}

// Delivers exactly the frames pushed to it, in order, each once: at `fps` when given (a paced camera), else
// as soon as pushed. Silent once they are all delivered: capture() times out, as a paused replay's does.
class ScriptedDevice final : public devices::Device {
public:
    explicit ScriptedDevice(double fps = 0.0) : fps_(fps) {}

    void push(std::vector<frame::FramePtr> frames) {
        {
            std::lock_guard lock(mutex_);
            for (frame::FramePtr& f : frames)
                queue_.push_back(std::move(f));
        }
        ready_.notify_all();
    }
    void push(frame::FramePtr frame) { push(std::vector<frame::FramePtr>{std::move(frame)}); }
    std::size_t pending() {
        std::lock_guard lock(mutex_);
        return queue_.size();
    }

    std::string description() const override { return "scripted"; }
    devices::Capabilities capabilities() const override {
        return {.sceneDepth = true, .confidence = true, .color = true, .pose = true};
    }

protected:
    Status doOpen() override { return {}; }
    Status doStart() override {
        if (fps_ > 0.0) {
            pacer_.setRate(fps_);
            pacer_.restart();
        }
        return {};
    }
    void doStop() override {}
    devices::CaptureResult doCapture(std::chrono::milliseconds timeout) override {
        {
            std::unique_lock lock(mutex_);
            if (!ready_.wait_for(lock, timeout, [&] { return !queue_.empty(); }))
                return {devices::CaptureResult::Kind::Timeout, nullptr, {}};
        }
        if (fps_ > 0.0 && !pacer_.waitForNext(timeout))
            return {devices::CaptureResult::Kind::Timeout, nullptr, {}};
        std::lock_guard lock(mutex_);
        frame::FramePtr f = std::move(queue_.front());
        queue_.pop_front();
        return {devices::CaptureResult::Kind::Frame, std::move(f), {}};
    }

private:
    double fps_;
    devices::FramePacer pacer_;
    std::mutex mutex_;
    std::condition_variable ready_;
    std::deque<frame::FramePtr> queue_;
};

// Polls `done` until it holds or `timeout` passes: a bounded wait on a condition, never a fixed sleep.
inline bool waitUntil(const std::function<bool()>& done,
                      std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!done()) {
        if (std::chrono::steady_clock::now() > end)
            return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return true;
}

} // namespace dc::engine::test
