#pragma once

#include "frame/frame.h"
#include "processing/depth_quality.h"
#include "processing/pipeline.h"
#include "processing/quality_maps.h"

#include <cstddef>
#include <optional>

namespace dc::engine {

// The Quality panel's question: the region of interest and how its samples are judged. The region is a
// centred preset, a rectangle or a polygon; the frame processor fits either to the depth map it is given, so
// a source that changes size never gets a region outside its map.
struct QualityDemand {
    int roiPercent = 40; // DQT's centred region, percent of width and height; 0: `roi`
    processing::Roi roi; // in the shown depth's pixels, when roiPercent is 0
    // A lasso, in the shown depth's pixel coordinates, when roiPercent is 0: the region is the samples
    // inside it and `roi` is ignored (its bounds are measured). Empty: the rectangle.
    processing::Polygon polygon;
    int windowFrames = 30;   // the noise window's length
    float nearMeters = 0.0f; // samples outside [near, far] are out of range
    float farMeters = 10.0f;
    float flyingThresholdMeters = 0.05f;     // processing::QualityParams::flyingThresholdMeters
    std::optional<double> groundTruthMeters; // the target's true distance, for the Z accuracy
    std::optional<double> baselineMeters;    // a stereo camera's, for subpixel RMS and the expected noise
    double designSubpixelRms = 0.08;         // processing::QualityParams::designSubpixelRms
    bool causeOverlay = false;               // the missing samples coloured by cause on the panels
    processing::QualityMap map = processing::QualityMap::None; // the per-pixel map the panel shows
    bool alignment = false; // the colour-to-depth edge alignment (a registration of the colour per frame)
    bool operator==(const QualityDemand&) const = default;
};

// What the UI shows this frame, in data terms (rerun's "query"): which products are visible, at what size,
// with which settings. The frame processor runs exactly the stages this needs, again whenever it changes,
// and a source is told the part that concerns it (SourceDemand). Plain data, compared as a whole.
struct Demand {
    bool cloud = true;        // the point-cloud panel is visible
    bool pointColours = true; // its points take the camera's colour (rather than a depth or confidence map)
    // The cloud's GL path colours camera-coloured points itself, from the camera image and the rig of
    // ShownFrame::frame: no colour per point is made for it here, unless the rig is one a shader cannot
    // register (processing::shaderCanColour). It makes the colour overlay and the depth over the camera
    // the same way, so neither is made here either.
    bool gpuCameraColours = false;
    bool depthImage = true;      // the depth panel, or the camera panel's depth overlay
    bool confidencePanel = true; // the confidence panel
    int cameraPanelWidth = 0;    // pixels the camera panel is shown at; 0 = hidden
    int dataPanelWidth = 0;      // pixels the depth or confidence panel is shown at (the wider); 0 = unknown
    // The camera panel's depth overlay is shown: a two-sensor frame's depth is aligned to the colour image
    // for it (a single camera's is the depth panel's image).
    bool depthOverCamera = false;
    bool colourOverDepth = false; // the depth panel's overlay of the camera colour aligned to the depth
    bool infraredPanel = false;   // the infrared panel (its image is made only while it is shown)
    bool fog = false;
    bool aura = false;
    bool automaticRange = false; // the colormap follows the data (shown depth's percentiles)
    // Which samples become points: the count, accumulation and the snapshot PLY keep what the cloud draws.
    frame::Confidence minConfidence = frame::Confidence::Low;
    float nearMeters = 0.1f;
    // The cloud draws at most one point per panel pixel: each decimation x decimation cell of the shown
    // depth becomes its nearest sample. 0: the smallest factor that fits cloudPanelPixels (0 = unknown).
    int cloudDecimation = 0;
    std::size_t cloudPanelPixels = 0;
    processing::ProcessingSettings processing;
    bool accumulate = false; // posed frames add their points to the world cloud
    // Another source's accumulation gathers this source's frames (a further source, fused): its samples
    // need their colours as accumulate's do, though nothing here accumulates.
    bool gathered = false;
    std::size_t accumulateBudget = 1'000'000;
    float accumulateVoxelMeters = 0.005f;
    std::optional<QualityDemand> quality; // the Quality panel is shown: its figures for every frame

    bool operator==(const Demand&) const = default;

    // Anything that shows depth or is derived from it.
    bool needsDepth() const {
        return cloud || depthImage || confidencePanel || fog || aura || accumulate || gathered ||
               automaticRange || quality.has_value();
    }
    // The confidence panel, a level above "all", or the fog's confidence overlay.
    bool readsConfidence() const {
        return confidencePanel || minConfidence != frame::Confidence::Low ||
               (fog && processing.fog.confidenceOverlay);
    }
    // Camera colours on points: the cloud's or accumulation's.
    bool needsPointColours() const { return (cloud && pointColours) || accumulate || gathered; }
    // One colour for every shown depth sample, not only the drawn ones: accumulation and the depth panel's
    // colour overlay read them.
    bool needsSampleColors() const { return accumulate || gathered || colourOverDepth; }
    // The camera image, for any product above or as the guide of upsampling.
    bool needsCameraImage() const {
        return needsPointColours() || cameraPanelWidth > 0 || colourOverDepth || fog || aura ||
               (processing.upsampling && needsDepth()) || (quality && quality->alignment);
    }
};

} // namespace dc::engine
