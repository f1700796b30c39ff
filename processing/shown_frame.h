#pragma once

#include "frame/frame.h"
#include "processing/camera_image.h"
#include "processing/depth_quality.h"
#include "processing/edge_alignment.h"
#include "processing/infrared_image.h"
#include "processing/pipeline.h"
#include "processing/point_cloud.h"
#include "processing/quality_maps.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace dc::processing {

// The one depth the instrument shows: raw, smoothed, upsampled or decimated as the settings say, with its
// confidence and the intrinsics at its own resolution. The cloud, the point count, hover and anchors,
// accumulation, the snapshot PLY and export all read this map and nothing else.
struct ShownDepth {
    std::shared_ptr<const frame::DepthData> data;
    frame::Intrinsics intrinsics;
    bool smoothed = false;  // temporally smoothed (the source's own or ours)
    bool upsampled = false; // guided-upsampled to (a fraction of) the camera image's size

    int width() const { return data ? data->depthMeters.width : 0; }
    int height() const { return data ? data->depthMeters.height : 0; }
};

// The samples the cloud draws: the shown depth, or fewer of them (processing/decimation.h) when the panel
// has fewer pixels than the map has samples or the user asks for a decimation. The very objects of
// ShownFrame::depth and ::pointColours when nothing is decimated.
struct ShownCloud {
    ShownDepth depth;
    // The camera's colour of each drawn sample, where it is drawn; null when the points are not coloured
    // by the camera or the GL path's shader colours them (engine::Demand::gpuCameraColours).
    std::shared_ptr<const RgbImage> colours;
    int factor = 1;
};

// A panel's picture as drawn, read back top row first, and the name of the file that keeps it
// (cloud.png, depth.png, ...): what the headless run and a snapshot write.
struct PanelPicture {
    std::string fileName;
    RgbaImage image;
};

// A depth range in meters, e.g. the automatic colormap range.
struct DepthRangeMeters {
    float minMeters = 0.0f;
    float maxMeters = 0.0f;
    bool operator==(const DepthRangeMeters&) const = default;
};

// The depth-quality figures of one shown frame over a region of interest (the Quality panel), with the
// noise over the last frames measured with the same region and settings.
struct ShownQuality {
    Roi roi; // the region measured, in the shown depth's pixels (clamped to the map)
    // The polygon measured (its vertices clamped to the map; `roi` is its bounding box); empty for a
    // rectangle.
    std::vector<std::array<double, 2>> polygon;
    std::uint64_t sequence = 0;          // the frame measured
    std::optional<FrameQuality> figures; // unset: `error` says why (a region outside the map, ...)
    std::string error;
    std::optional<double> temporalNoiseMm; // unset: noiseError says why (too few frames yet, ...)
    std::optional<double> spatialNoiseMm;
    std::string noiseError;
    std::size_t windowFilled = 0; // frames in the noise window
    std::size_t windowFrames = 0; // of its length
    // The region's missing samples in their causes' colours (processing::causeOverlay), roi-sized; null
    // unless asked for (engine::QualityDemand::causeOverlay) or without figures.
    std::shared_ptr<const RgbaImage> causeOverlay;
    // The per-pixel map asked for (engine::QualityDemand::map), roi-sized; null when none was asked for or
    // it has nothing to show yet (a residual without a plane fit).
    std::shared_ptr<const QualityMapImage> map;
    // The colour-to-depth edge alignment over the region, when asked for (engine::QualityDemand::alignment)
    // and the frame has a camera image; else `alignmentError` says why not (empty when not asked).
    std::optional<EdgeAlignment> alignment;
    std::string alignmentError;
};

// What one frame looks like under one demand: everything the GL thread uploads and draws, and nothing it
// did not ask for (an image no panel shows is null). Immutable once published; each product is shared, so
// a product that did not change between two results is the same object and need not be uploaded again.
struct ShownFrame {
    frame::FramePtr frame; // the capture: sequence, timestamp, pose, replay position
    ShownDepth depth;      // data null when the frame has no depth
    // One colour per shown depth sample, made only for a reader of every sample (accumulation, the depth
    // panel's colour overlay) or for a cloud that draws every sample with colours made on the CPU.
    std::shared_ptr<const RgbImage> pointColours;
    // With a two-sensor camera, which of those points the colour camera sees (1) and which it cannot
    // (outside its view or hidden: they are gray); null when it sees them all.
    std::shared_ptr<const frame::Plane<std::uint8_t>> pointSeen;
    std::shared_ptr<const RgbImage> cameraImage; // the camera panel, at the size it is shown
    // The depth and confidence panels' samples when they are shown at 1/panelStep of the map's width
    // (engine::Demand::dataPanelWidth, processing::sampleCellCentres), made here so that the GL thread
    // only uploads them; null while they are shown whole.
    std::shared_ptr<const frame::DepthData> panelSamples;
    int panelStep = 1;
    // The camera panel's depth overlay of a two-sensor frame: the shown depth aligned to the colour image
    // (0 where the depth sensor saw nothing there). Null for a single camera, whose depth panel image
    // already lies over the camera image.
    std::shared_ptr<const frame::DepthData> depthOverCamera;
    // The depth panel's colour overlay: one colour per shown depth sample, transparent where the colour
    // camera does not see it (processing::seenColourOverlay).
    std::shared_ptr<const RgbaImage> colourOverDepth;
    // The infrared panel: the frame's infrared contrast-stretched to gray, at its own size.
    std::shared_ptr<const RgbImage> infraredImage;
    IntensityRange infraredRange; // the raw intensities infraredImage stretches to black..white
    std::shared_ptr<const RgbaImage> fog;
    std::shared_ptr<const RgbaImage> aura;
    std::optional<DepthRangeMeters> automaticRange; // when the colormap follows the data
    ShownCloud cloud;                               // when the cloud or accumulation shows depth
    std::size_t pointCount = 0;                     // points the cloud draws (of `cloud`)
    std::shared_ptr<const ShownQuality> quality;    // while the Quality panel is shown
    std::uint64_t demandGeneration = 0;             // the demand this answers
    bool newFrame = false;                          // a device frame's first result (not a redo)
    std::vector<StageTiming> timings;               // the stages that ran for this result

    CloudSamples samples() const { return {depth.data.get(), depth.intrinsics, pointColours.get()}; }
};

using ShownFramePtr = std::shared_ptr<const ShownFrame>;

} // namespace dc::processing
