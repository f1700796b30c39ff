#pragma once

#include "devices/device.h"
#include "devices/frame_pacer.h"

#include <chrono>
#include <vector>

namespace dc::devices {

// Plays a fixed list of frames in a loop at a steady rate, re-stamping sequence and timestamp so the
// stream looks live. Used where frames must be produced without cost on the capture thread: benchmarks
// of the viewer, and tests that need exact, hand-made frames to flow through a real Session.
class FrameListDevice final : public Device {
public:
    FrameListDevice(std::vector<frame::FramePtr> frames, double fps, std::string description = "frame list");

    std::string description() const override { return description_; }
    Capabilities capabilities() const override;

protected:
    Status doOpen() override;
    Status doStart() override;
    void doStop() override {}
    CaptureResult doCapture(std::chrono::milliseconds timeout) override;

private:
    std::vector<frame::FramePtr> frames_;
    double fps_;
    std::string description_;
    FramePacer pacer_;
    std::uint64_t sequence_ = 0;
};

} // namespace dc::devices
