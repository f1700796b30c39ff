#pragma once

// A camera for the UI tests that delivers a few frames of the small synthetic scene and then fails in one
// way for good (stalls, or is unplugged).

#include "devices/device.h"
#include "devices/synthetic/synthetic_device.h"
#include "ui_fixture.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

namespace dc::ui::test {

class FailingCamera final : public devices::Device {
public:
    // After `frames` frames every capture returns `kind` with `message`; `last` receives the sequence of
    // the last frame delivered.
    FailingCamera(int frames, devices::CaptureResult::Kind kind, std::string message,
                  std::shared_ptr<std::atomic<std::int64_t>> last = nullptr)
        : frames_(frames), kind_(kind), message_(std::move(message)), last_(std::move(last)) {}

    std::string description() const override { return "failing camera"; }
    devices::Capabilities capabilities() const override { return synthetic_.capabilities(); }

protected:
    Status doOpen() override { return synthetic_.open(); }
    Status doStart() override { return synthetic_.start(); }
    void doStop() override {}
    // Counts the frames delivered, not the calls: on a busy machine the synthetic camera's first calls may
    // time out before its first frame is due, and a camera that failed before its first frame would test
    // nothing.
    devices::CaptureResult doCapture(std::chrono::milliseconds timeout) override {
        if (delivered_ >= frames_) {
            std::this_thread::sleep_for(std::min(timeout, std::chrono::milliseconds(20)));
            return {kind_, nullptr, message_};
        }
        devices::CaptureResult result = synthetic_.capture(timeout);
        if (result.frame) {
            ++delivered_;
            if (last_)
                last_->store(static_cast<std::int64_t>(result.frame->sequence));
        }
        return result;
    }

private:
    devices::SyntheticDevice synthetic_{smallScene()};
    int frames_;
    devices::CaptureResult::Kind kind_;
    std::string message_;
    std::shared_ptr<std::atomic<std::int64_t>> last_;
    int delivered_ = 0;
};

} // namespace dc::ui::test
