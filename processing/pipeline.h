#pragma once

#include "frame/frame.h"
#include "processing/settings.h"

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace dc::processing {

// Stage names, as the UI and the status line show them.
inline constexpr std::string_view kSmoothingStage = "smoothing";
inline constexpr std::string_view kUpsamplingStage = "upsampling";

struct ProcessingSettings {
    bool smoothing = false;  // temporal smoothing into smoothedSceneDepth
    bool upsampling = false; // guided upsampling of depth and confidence to the camera image
    SmoothingParams smoothingParams;
    UpsamplingParams upsamplingParams;
    // Which depth the cloud, depth panel, fog and aura show; smoothing runs only when it is Smoothed.
    DepthSource depthSource = DepthSource::Smoothed;
    FogSettings fog;
    AuraSettings aura;

    bool operator==(const ProcessingSettings&) const = default;
};

// The depth map that `source` selects in `frame` (smoothed when asked for and present, else sceneDepth);
// null when the frame has no depth. Consumers use it (or showsSmoothed) so they all show the same map.
const frame::DepthData* shownDepth(const frame::Frame& frame, DepthSource source);
bool showsSmoothed(const frame::Frame& frame, DepthSource source);

// What the visible panels and running exports need from a frame. A stage whose output nobody needs is
// not run ("leave out what the scene does not need").
struct Needs {
    bool cloud = true;
    bool depthPanel = true;
    bool confidencePanel = true;
    bool cameraPanel = true;
    bool fogPanel = false;
    bool auraPanel = false;
    // Something reads confidence: the confidence panel, a level above "all", the fog's confidence overlay.
    bool confidence = true;

    bool anyDepth() const { return cloud || depthPanel || confidencePanel || fogPanel || auraPanel; }
    bool operator==(const Needs&) const = default;
};

// One processing step: takes a frame and returns a new one (frames are immutable; a stage that changes
// nothing returns its input). A stage with temporal state treats a frame with the same timestamp as the one
// it processed last as that frame again (a redo after a settings change, or the same capture re-delivered
// with its colour): it starts from the state it had before that frame, so a redo never advances history.
class Stage {
public:
    virtual ~Stage() = default;
    virtual std::string_view name() const = 0;
    // Whether the settings switch this stage on and a visible consumer needs its output.
    virtual bool wanted(const ProcessingSettings& settings, const Needs& needs) const = 0;
    virtual frame::FramePtr process(frame::FramePtr frame, const ProcessingSettings& settings) = 0;
    // Drops temporal state (resolution change, seek, new source).
    virtual void reset() {}
};

struct StageTiming {
    std::string name;
    double milliseconds = 0.0;
};

class Pipeline {
public:
    void add(std::unique_ptr<Stage> stage);
    // Runs the wanted stages in order; the frame's resolution changing resets every stage first.
    frame::FramePtr run(frame::FramePtr frame, const ProcessingSettings& settings, const Needs& needs);
    void reset();
    bool hasStage(std::string_view name) const;
    // Timings of the stages that made something in the last run() (stages skipped, or that passed the frame
    // through, are absent).
    const std::vector<StageTiming>& lastTimings() const { return timings_; }

private:
    std::vector<std::unique_ptr<Stage>> stages_;
    std::vector<StageTiming> timings_;
    int lastWidth_ = -1;
    int lastHeight_ = -1;
};

// The pipeline with every stage this build implements, in the order they must run (see pipeline.cpp).
Pipeline makeDefaultPipeline();

} // namespace dc::processing
