#pragma once

#include "processing/pipeline.h"

#include <string_view>

namespace dc::processing {

inline constexpr std::string_view kConfidenceEstimateStage = "confidence estimate";

// Thresholds of the confidence estimate, as fractions of the pixel's own depth (so they mean the same at
// 0.5 m and at 5 m, like a depth sensor's relative error).
struct ConfidenceEstimatorParams {
    // Spread (standard deviation) of the valid depths in the 3x3 neighbourhood, relative to the depth.
    float highSpread = 0.01f;
    float mediumSpread = 0.03f;
    // Change against the previous frame's depth at the same pixel, relative to the depth.
    float highChange = 0.02f;
    float mediumChange = 0.05f;
    // Neighbours (of 8) without a measurement.
    int highInvalidNeighbours = 0;
    int mediumInvalidNeighbours = 2;
};

// An estimated confidence for depth maps whose sensor provides none (UVC depth cameras). Each measured pixel
// is judged by three signs that a depth sample is unreliable:
//  - invalid neighbours: samples next to holes sit on object edges or shadow borders ("flying pixels");
//  - local depth variance: a large spread among the 3x3 neighbours means a depth edge or noise;
//  - temporal stability: a sample that jumps against the previous frame is noise (a moving camera also
//    lowers it, which is acceptable for a hint). Unknown on the first frame, where it does not count.
// High when all three are within the "high" limits, Medium within the "medium" limits, Low otherwise;
// pixels without depth are Low. Image borders are mirrored, so they are not penalised.
frame::Plane<std::uint8_t> estimateConfidence(const frame::Plane<float>& depthMeters,
                                              const frame::Plane<float>* previousDepthMeters,
                                              const ConfidenceEstimatorParams& params = {});

// The pipeline stage: fills sceneDepth.confidence with the estimate (and sets confidenceEstimated) when the
// source gave none; frames with sensor confidence pass through untouched. Runs only while something reads
// confidence (Needs::confidence).
class ConfidenceEstimatorStage final : public Stage {
public:
    explicit ConfidenceEstimatorStage(ConfidenceEstimatorParams params = {}) : params_(params) {}

    std::string_view name() const override { return kConfidenceEstimateStage; }
    bool wanted(const ProcessingSettings& settings, const Needs& needs) const override;
    frame::FramePtr process(frame::FramePtr frame, const ProcessingSettings& settings) override;
    void reset() override {
        previous_.reset();
        current_.reset();
    }

private:
    ConfidenceEstimatorParams params_;
    // The frames estimated last and before it (frames are shared and immutable: holding them costs nothing),
    // so a redo of the current frame compares with the same previous depth.
    frame::FramePtr previous_;
    frame::FramePtr current_;
};

} // namespace dc::processing
