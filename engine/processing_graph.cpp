#include "engine/processing_graph.h"

#include "processing/aura.h"
#include "processing/camera_image.h"
#include "processing/confidence_filter.h"
#include "processing/decimation.h"
#include "processing/depth_statistics.h"
#include "processing/fog.h"
#include "processing/infrared_image.h"
#include "processing/registration.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace dc::engine {

namespace {

processing::Needs needsOf(const Demand& d) {
    // The pipeline's stages ask only whether any depth is shown and whether confidence is read
    // (Stage::wanted). Which panels show the depth is left out, so that it is also left out of the depth
    // memo's key: opening the depth panel or turning fog on must not redo the confidence estimate or
    // upsampling of a frame whose shown depth it does not change. The camera panel alone needs no depth.
    processing::Needs needs;
    needs.cloud = d.needsDepth();
    needs.depthPanel = false;
    needs.confidencePanel = false;
    needs.cameraPanel = false;
    needs.confidence = d.readsConfidence() && d.needsDepth();
    return needs;
}

// The settings the depth pipeline reads; fog and aura settings do not change the shown depth.
processing::ProcessingSettings depthSettings(const processing::ProcessingSettings& s) {
    processing::ProcessingSettings depth = s;
    depth.fog = {};
    depth.aura = {};
    return depth;
}

// The polygon of `q` fitted to a width x height map: each vertex clamped into it (empty for a preset).
processing::Polygon fittedPolygon(const QualityDemand& q, int width, int height) {
    if (q.roiPercent > 0 || width <= 0 || height <= 0)
        return {};
    processing::Polygon polygon = q.polygon;
    for (auto& [x, y] : polygon) {
        x = std::clamp(x, 0.0, static_cast<double>(width));
        y = std::clamp(y, 0.0, static_cast<double>(height));
    }
    return polygon;
}

// The region of interest fitted to a width x height map: a preset centred in it, a rectangle or a polygon's
// bounding box clamped into it (a source that changed size keeps a region, never one outside its map).
processing::Roi fittedRoi(const QualityDemand& q, int width, int height) {
    if (q.roiPercent > 0)
        return processing::centredRoi(width, height, q.roiPercent);
    if (width <= 0 || height <= 0)
        return {};
    processing::Roi r =
        q.polygon.empty() ? q.roi : processing::polygonBounds(fittedPolygon(q, width, height));
    r.x = std::clamp(r.x, 0, width - 1);
    r.y = std::clamp(r.y, 0, height - 1);
    r.width = std::clamp(r.width, 1, width - r.x);
    r.height = std::clamp(r.height, 1, height - r.y);
    return r;
}

processing::QualityParams qualityParams(const QualityDemand& q, const processing::Roi& roi,
                                        processing::Polygon polygon) {
    processing::QualityParams p;
    p.roi = roi;
    p.polygon = std::move(polygon);
    p.nearMeters = q.nearMeters;
    p.farMeters = q.farMeters;
    p.flyingThresholdMeters = q.flyingThresholdMeters;
    p.groundTruthMeters = q.groundTruthMeters;
    p.baselineMeters = q.baselineMeters;
    p.designSubpixelRms = q.designSubpixelRms;
    return p;
}

// The per-pixel map of `kind`, from the frame's figures (the residual) or the noise window (the
// temporal deviation, the fill); null when none is asked for or a residual has no plane.
std::shared_ptr<const processing::QualityMapImage>
qualityMap(processing::QualityMap kind, const frame::DepthData& depth, const frame::Intrinsics& intrinsics,
           const processing::ShownQuality& quality, const processing::NoiseWindow& noise) {
    using processing::QualityMap;
    frame::Plane<float> values;
    if (kind == QualityMap::PlaneResidual && quality.figures && quality.figures->plane)
        values = processing::planeResidualMm(depth, intrinsics, quality.roi, quality.figures->causes,
                                             quality.figures->plane->plane);
    else if (kind == QualityMap::TemporalStd)
        values = noise.temporalStdMapMm();
    else if (kind == QualityMap::FillOverWindow)
        values = noise.fillMapPercent();
    if (values.empty())
        return nullptr;
    return std::make_shared<const processing::QualityMapImage>(
        processing::colourMap(kind, std::move(values)));
}

} // namespace

bool ProcessingGraph::DepthKey::operator==(const DepthKey& o) const {
    return frame == o.frame && settings == o.settings && needs == o.needs;
}

ProcessingGraph::ProcessingGraph() : pipeline_(processing::makeDefaultPipeline()) {}

void ProcessingGraph::reset() {
    pipeline_.reset();
    decoded_.clear();
    depth_.clear();
    pointColours_.clear();
    cloudColours_.clear();
    colourOverlay_.clear();
    cameraImage_.clear();
    effectsImage_.clear();
    alignedDepth_.clear();
    infraredImage_.clear();
    fog_.clear();
    aura_.clear();
    range_.clear();
    cloud_.clear();
    count_.clear();
    panelSamples_.clear();
    quality_.clear();
    noise_.reset();
    noiseKey_.reset();
    noiseFedNs_.reset();
}

std::uint64_t ProcessingGraph::runs(std::string_view stage) const {
    const auto it = runs_.find(stage);
    return it == runs_.end() ? 0 : it->second;
}

template <class Key, class Value, class Make>
const Value& ProcessingGraph::cached(Memo<Key, Value>& memo, const Key& key, std::string_view stage,
                                     Make&& make) {
    if (memo.key && *memo.key == key)
        return memo.value;
    const auto start = std::chrono::steady_clock::now();
    try {
        if (fault_)
            fault_(stage);
        memo.value = make();
    } catch (const std::exception& e) {
        // Named by its stage, so that the log says which one failed.
        throw std::runtime_error(std::string(stage) + ": " + e.what());
    }
    memo.key = key;
    const std::chrono::duration<double, std::milli> took = std::chrono::steady_clock::now() - start;
    timings_->push_back({std::string(stage), took.count()});
    ++runs_[std::string(stage)];
    return memo.value;
}

// A camera that sends JPEG (MJPEG) has its image decoded here, once per frame and only when a stage reads
// its pixels; every stage after sees the decoded frame.
frame::FramePtr ProcessingGraph::decodedFrame(const frame::FramePtr& captured, const Demand& demand) {
    if (captured->capturedImage.raw() || captured->capturedImage.empty() || !demand.needsCameraImage())
        return captured;
    return cached(decoded_, captured, kCameraDecodeStage, [&] {
        auto copy = std::make_shared<frame::Frame>(*captured);
        auto image = jpegDecoder_.decode(captured->capturedImage);
        // A frame the camera garbled shows no camera colours rather than wrong ones.
        copy->capturedImage = image ? std::move(*image) : frame::CapturedImage{};
        return frame::FramePtr(std::move(copy));
    });
}

processing::ShownFramePtr ProcessingGraph::run(const frame::FramePtr& captured, const Demand& demand,
                                               std::uint64_t generation, bool newFrame) {
    auto shown = std::make_shared<processing::ShownFrame>();
    shown->demandGeneration = generation;
    shown->newFrame = newFrame;
    timings_ = &shown->timings;
    const frame::FramePtr frame = decodedFrame(captured, demand);
    shown->frame = frame;
    if (demand.needsDepth())
        shown->depth = shownDepth(frame, demand);
    addCameraImage(*shown, *frame, demand);
    addInfrared(*shown, frame, demand);
    addEffects(*shown, *frame, demand);
    addDepthOverCamera(*shown, *frame, demand);
    addDepthProducts(*shown, demand);
    addPanelSamples(*shown, demand);
    addPointColours(*shown, *frame, demand);
    addQuality(*shown, demand);
    timings_ = nullptr;
    return shown;
}

// The depth pipeline (confidence estimate, smoothing, upsampling) and the one map it makes the shown one.
processing::ShownDepth ProcessingGraph::shownDepth(const frame::FramePtr& frame, const Demand& demand) {
    const DepthKey key{frame, depthSettings(demand.processing), needsOf(demand)};
    if (depth_.key && *depth_.key == key)
        return depth_.value;
    const frame::FramePtr out = pipeline_.run(frame, key.settings, key.needs);
    for (const processing::StageTiming& t : pipeline_.lastTimings()) {
        timings_->push_back(t);
        ++runs_[t.name];
    }
    processing::ShownDepth shown;
    if (const frame::DepthData* depth = processing::shownDepth(*out, demand.processing.depthSource)) {
        shown.data = std::shared_ptr<const frame::DepthData>(out, depth); // keeps the processed frame alive
        shown.intrinsics = out->depthIntrinsicsAt(shown.width(), shown.height());
        shown.smoothed = processing::showsSmoothed(*out, demand.processing.depthSource);
        shown.upsampled = frame->sceneDepth && frame->sceneDepth->depthMeters.width != shown.width();
    }
    depth_.key = key;
    depth_.value = shown;
    return shown;
}

// The camera panel's picture, at the size it is shown, unless the GL path converts the image itself.
void ProcessingGraph::addCameraImage(processing::ShownFrame& shown, const frame::Frame& frame,
                                     const Demand& demand) {
    const frame::CapturedImage& image = frame.capturedImage;
    if (demand.cameraPanelWidth > 0 && !image.empty() && !demand.gpuCameraColours) {
        const auto [w, h] = processing::cameraPanelImageSize(image, demand.cameraPanelWidth);
        shown.cameraImage = cached(cameraImage_, ImageKey{image.bytes, w, h}, kCameraImageStage, [&] {
            return std::make_shared<const processing::RgbImage>(processing::cameraRgbImage(image, w, h));
        });
    }
}

// Accumulation (this source's, or another's that gathers its frames) and the depth panel's colour overlay
// read a colour for every shown sample; the cloud reads
// colours only for the samples it draws (after decimation), and none when its shader colours them (nor the
// overlay then: the GL path makes it from the camera's planes).
void ProcessingGraph::addPointColours(processing::ShownFrame& shown, const frame::Frame& frame,
                                      const Demand& demand) {
    if (!shown.depth.data)
        return;
    const frame::CapturedImage& image = frame.capturedImage;
    const bool shaded = demand.gpuCameraColours && processing::shaderCanColour(frame.rig.get());
    // The GL path makes the colour overlay in a shader too, at the size the depth panel is drawn.
    const bool overlay = demand.colourOverDepth && !image.empty() && !shaded;
    const bool cloudColours = demand.cloud && demand.pointColours && !shaded && shown.cloud.depth.data;
    const bool whole = shown.cloud.factor <= 1;
    if (demand.accumulate || demand.gathered || overlay || (cloudColours && whole)) {
        const int w = shown.depth.width(), h = shown.depth.height();
        const ColoursKey key{ImageKey{image.bytes, w, h}, frame.rig ? shown.depth.data : nullptr};
        const processing::PointColours& colours = cached(pointColours_, key, kPointColoursStage, [&] {
            return processing::framePointColours(frame, shown.depth.data->depthMeters, colourTable_);
        });
        shown.pointColours = colours.colours;
        shown.pointSeen = colours.seen;
        if (overlay)
            shown.colourOverDepth = cached(colourOverlay_, colours.colours, kColourOverlayStage, [&] {
                return std::make_shared<const processing::RgbaImage>(processing::seenColourOverlay(colours));
            });
    }
    if (!cloudColours)
        return;
    if (whole) {
        shown.cloud.colours = shown.pointColours;
        return;
    }
    const processing::ShownDepth& cloud = shown.cloud.depth;
    const ColoursKey key{ImageKey{image.bytes, cloud.width(), cloud.height()},
                         frame.rig ? cloud.data : nullptr};
    shown.cloud.colours = cached(cloudColours_, key, kPointColoursStage, [&] {
        return processing::framePointColours(frame, cloud.data->depthMeters, cloud.intrinsics, colourTable_)
            .colours;
    });
}

// The camera panel's depth overlay of a two-sensor frame, at the size fog and aura align the depth to:
// one aligned depth serves all three. The GL path draws it itself, from the depth samples into the colour
// camera's view, when its shaders register the rig.
void ProcessingGraph::addDepthOverCamera(processing::ShownFrame& shown, const frame::Frame& frame,
                                         const Demand& demand) {
    if (!demand.depthOverCamera || frame.capturedImage.empty() ||
        (demand.gpuCameraColours && processing::shaderCanColour(frame.rig.get())))
        return;
    const auto [w, h] = processing::halfCameraSize(frame.capturedImage);
    const std::shared_ptr<const frame::DepthData> depth = colourViewDepth(shown, frame, w, h);
    if (depth != shown.depth.data)
        shown.depthOverCamera = depth;
}

// The infrared panel's picture, made only while the panel is shown.
void ProcessingGraph::addInfrared(processing::ShownFrame& shown, const frame::FramePtr& frame,
                                  const Demand& demand) {
    if (!demand.infraredPanel || !frame->infrared || frame->infrared->empty())
        return;
    const StretchedInfrared& stretched = cached(infraredImage_, frame, kInfraredImageStage, [&] {
        const frame::Plane<std::uint16_t>& infrared = *frame->infrared;
        const processing::IntensityRange range = processing::infraredContrastRange(infrared);
        return StretchedInfrared{
            std::make_shared<const processing::RgbImage>(processing::infraredRgbImage(infrared, range)),
            range};
    });
    shown.infraredImage = stretched.image;
    shown.infraredRange = stretched.range;
}

// Fog and aura share one conversion of the camera image to their size, and the depth they are made from.
void ProcessingGraph::addEffects(processing::ShownFrame& shown, const frame::Frame& frame,
                                 const Demand& demand) {
    if ((!demand.fog && !demand.aura) || frame.capturedImage.empty())
        return;
    const frame::CapturedImage& image = frame.capturedImage;
    const auto [w, h] = processing::halfCameraSize(image);
    const auto camera = cached(effectsImage_, ImageKey{image.bytes, w, h}, kEffectsImageStage, [&] {
        return std::make_shared<const processing::RgbImage>(processing::cameraRgbImage(image, w, h));
    });
    const std::shared_ptr<const frame::DepthData> depth = colourViewDepth(shown, frame, w, h);
    // The aura's matte measures pixels physically, with the camera of the depth it is made from.
    const bool aligned = depth != shown.depth.data;
    const frame::Intrinsics intrinsics =
        aligned ? frame.rig->colour.intrinsics.scaledTo(w, h) : frame.depthIntrinsics();
    const processing::ProcessingSettings& p = demand.processing;
    if (demand.fog) {
        const EffectKey key{camera, depth, p.fog, {}, 0};
        shown.fog = cached(fog_, key, kFogStage, [&] {
            return std::make_shared<const processing::RgbaImage>(
                processing::renderFog(*camera, depth.get(), p.fog));
        });
    }
    if (demand.aura) {
        // The pulse follows the frame's own clock: a paused frame keeps its look, a replay looks the same
        // every time.
        const EffectKey key{camera, depth, {}, p.aura, frame.timestampNs};
        shown.aura = cached(aura_, key, kAuraStage, [&] {
            return std::make_shared<const processing::RgbaImage>(processing::renderAura(
                *camera, depth.get(), intrinsics, p.aura, static_cast<double>(frame.timestampNs) * 1e-9));
        });
    }
}

// Fog, aura and the camera panel's depth overlay mix depth into the camera image pixel by pixel, so with
// two sensors they need the depth as the colour sensor would see it; a single camera's depth already shares
// the image's view and is used as it is. The aligned depth has no confidence: which colour pixel a sample
// covers is not a property the sensor measured, so fog's confidence overlay shows nothing there rather than a
// guess.
std::shared_ptr<const frame::DepthData> ProcessingGraph::colourViewDepth(const processing::ShownFrame& shown,
                                                                         const frame::Frame& frame, int width,
                                                                         int height) {
    const std::shared_ptr<const frame::DepthData>& depth = shown.depth.data;
    if (!depth || !frame.rig || processing::isSingleCamera(*frame.rig))
        return depth;
    return cached(alignedDepth_, AlignedKey{depth, frame.rig, width, height}, kAlignedDepthStage, [&] {
        auto aligned = std::make_shared<frame::DepthData>();
        aligned->depthMeters = processing::alignDepthToColour(depth->depthMeters, *frame.rig, width, height);
        return std::shared_ptr<const frame::DepthData>(std::move(aligned));
    });
}

// The depth and confidence panels shown smaller than the map need only the samples nearest sampling shows:
// picked here rather than on the GL thread, which then uploads a fraction of the map and nothing else.
void ProcessingGraph::addPanelSamples(processing::ShownFrame& shown, const Demand& demand) {
    const std::shared_ptr<const frame::DepthData>& depth = shown.depth.data;
    const int step = processing::panelSampleStep(shown.depth.width(), demand.dataPanelWidth);
    if (!depth || step < 2 || (!demand.depthImage && !demand.confidencePanel))
        return;
    shown.panelSamples = cached(panelSamples_, PanelSamplesKey{depth, step}, kPanelSamplesStage, [&] {
        return std::make_shared<const frame::DepthData>(processing::sampleCellCentres(*depth, step));
    });
    shown.panelStep = step;
}

void ProcessingGraph::addDepthProducts(processing::ShownFrame& shown, const Demand& demand) {
    const std::shared_ptr<const frame::DepthData>& depth = shown.depth.data;
    if (!depth)
        return;
    if (demand.automaticRange)
        shown.automaticRange = cached(range_, depth, kDepthRangeStage,
                                      [&] { return processing::percentileRange(depth->depthMeters); });
    if (!demand.cloud && !demand.accumulate)
        return;
    shown.cloud = shownCloud(shown, demand);
    const std::shared_ptr<const frame::DepthData>& drawn = shown.cloud.depth.data;
    shown.pointCount =
        cached(count_, CountKey{drawn, demand.minConfidence, demand.nearMeters}, kPointCountStage, [&] {
            return processing::countDrawablePoints(*drawn, demand.minConfidence, demand.nearMeters);
        });
}

processing::ShownCloud ProcessingGraph::shownCloud(const processing::ShownFrame& shown,
                                                   const Demand& demand) {
    const processing::ShownDepth& depth = shown.depth;
    const int factor = demand.cloudDecimation > 0 ? demand.cloudDecimation
                                                  : processing::footprintFactor(depth.width(), depth.height(),
                                                                                demand.cloudPanelPixels);
    if (factor <= 1 || !demand.cloud)
        return {depth, nullptr, 1};
    return cached(cloud_, DecimationKey{depth.data, factor, demand.minConfidence, demand.nearMeters},
                  kDecimationStage, [&] {
                      processing::DecimatedDepth d = processing::decimateNearest(
                          *depth.data, depth.intrinsics, factor, demand.minConfidence, demand.nearMeters);
                      processing::ShownDepth cloud = depth;
                      cloud.data = std::move(d.data);
                      cloud.intrinsics = d.intrinsics;
                      return processing::ShownCloud{cloud, nullptr, factor};
                  });
}

void ProcessingGraph::addQuality(processing::ShownFrame& shown, const Demand& demand) {
    if (!demand.quality || !shown.depth.data)
        return;
    const QualityDemand& q = *demand.quality;
    const processing::ShownDepth& depth = shown.depth;
    const QualityKey key{depth.data, q, fittedRoi(q, depth.width(), depth.height()),
                         depthSettings(demand.processing)};
    shown.quality = cached(quality_, key, kQualityStage,
                           [&] { return measureQuality(key, depth.intrinsics, *shown.frame); });
}

// The colour registered onto the shown depth and its edges compared with the depth's over the region.
void ProcessingGraph::addAlignment(processing::ShownQuality& quality, const frame::Frame& frame,
                                   const frame::DepthData& depth, const frame::Intrinsics& intrinsics) {
    if (frame.capturedImage.empty()) {
        quality.alignmentError = "the frame has no camera image";
        return;
    }
    const frame::Plane<float>& map = depth.depthMeters;
    const processing::RgbImage colour =
        processing::colourAlignedToDepth(frame, map, map.width, map.height, colourTable_);
    auto alignment = processing::measureEdgeAlignment(map, colour, intrinsics, quality.roi, quality.polygon);
    if (alignment)
        quality.alignment = *alignment;
    else
        quality.alignmentError = alignment.error().message;
}

// Runs once per shown depth and question (the memo's key): a new capture's depth enters the noise window
// once; a redo of the same frame for another panel's sake, or the same capture delivered again, does not
// count it twice.
std::shared_ptr<const processing::ShownQuality>
ProcessingGraph::measureQuality(const QualityKey& key, const frame::Intrinsics& intrinsics,
                                const frame::Frame& frame) {
    const frame::Plane<float>& map = key.depth->depthMeters;
    const processing::QualityParams params =
        qualityParams(key.quality, key.roi, fittedPolygon(key.quality, map.width, map.height));
    auto out = std::make_shared<processing::ShownQuality>();
    out->roi = key.roi;
    out->polygon = params.polygon;
    out->sequence = frame.sequence;
    QualityKey question = key;
    question.depth = nullptr;
    question.quality.causeOverlay = false; // showing the causes or a map asks nothing new of the window
    question.quality.map = processing::QualityMap::None;
    question.quality.alignment = false;
    if (!noise_ || noiseKey_ != question) {
        noise_.emplace(params, key.quality.windowFrames);
        noiseKey_ = question;
        noiseFedNs_.reset();
    }
    Expected<processing::FrameQuality> measured =
        processing::measureFrameQuality(*key.depth, intrinsics, params);
    if (measured) {
        const auto rms = measured->plane ? std::optional(measured->plane->planeFitRmsMm) : std::nullopt;
        if (noiseFedNs_ != frame.timestampNs)
            noise_->add(*key.depth, measured->causes, rms);
        noiseFedNs_ = frame.timestampNs;
        if (key.quality.causeOverlay)
            out->causeOverlay = std::make_shared<const processing::RgbaImage>(
                processing::causeOverlay(measured->causes, key.roi.width, key.roi.height));
        out->figures = std::move(*measured);
    } else {
        out->error = measured.error().message;
    }
    const Expected<double> temporal = noise_->temporalNoiseMm();
    const Expected<double> spatial = noise_->spatialNoiseMm();
    if (temporal)
        out->temporalNoiseMm = *temporal;
    if (spatial)
        out->spatialNoiseMm = *spatial;
    out->noiseError = !temporal ? temporal.error().message : !spatial ? spatial.error().message : "";
    out->windowFilled = noise_->frames();
    out->windowFrames = static_cast<std::size_t>(std::max(key.quality.windowFrames, 1));
    out->map = qualityMap(key.quality.map, *key.depth, intrinsics, *out, *noise_);
    if (key.quality.alignment)
        addAlignment(*out, frame, *key.depth, intrinsics);
    return out;
}

} // namespace dc::engine
