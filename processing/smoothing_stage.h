#pragma once

#include "processing/pipeline.h"
#include "processing/temporal_smoothing.h"

#include <cstdint>
#include <optional>

namespace dc::processing {

// Adds smoothedSceneDepth to frames whose source does not provide it (a source's own, e.g. ARKit's, is
// passed through untouched). Runs only while the shown depth is the smoothed one. The history restarts on
// reset() (new source, seek, resolution change) and by itself when time runs backwards or jumps ahead.
class SmoothingStage final : public Stage {
public:
    // A gap longer than this between frames means a seek or a pause: the old history no longer applies.
    static constexpr std::int64_t kMaxGapNs = 500'000'000;

    std::string_view name() const override { return kSmoothingStage; }
    bool wanted(const ProcessingSettings& settings, const Needs& needs) const override;
    frame::FramePtr process(frame::FramePtr frame, const ProcessingSettings& settings) override;
    void reset() override;

private:
    TemporalSmoother smoother_;
    std::optional<std::int64_t> lastTimestampNs_; // of the frame smoothed last
};

} // namespace dc::processing
