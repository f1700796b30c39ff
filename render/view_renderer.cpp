#include "render/view_renderer.h"

#include "processing/decimation.h"
#include "processing/registration.h"

#include <algorithm>
#include <array>

namespace dc::render {

const char* toString(CloudPath path) {
    return path == CloudPath::Splat ? "CPU splat" : "GL points";
}

bool isSoftwareRenderer(std::string_view glRenderer) {
    constexpr std::array<std::string_view, 5> kSoftware = {"llvmpipe", "softpipe", "swrast",
                                                           "Software Rasterizer", "Basic Render Driver"};
    return std::any_of(kSoftware.begin(), kSoftware.end(), [&](std::string_view name) {
        return glRenderer.find(name) != std::string_view::npos;
    });
}

Status ViewRenderer::init() {
    if (Status s = cloudRenderer_.init(); !s)
        return s;
    if (Status s = panels_.init(); !s)
        return s;
    if (Status s = accumulated_.init(); !s)
        return s;
    if (Status s = cameraColours_.init(); !s)
        return s;
    const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    glRenderer_ = name ? name : "";
    // An instrument shows the sensor's own samples, not blends of neighbours; the cloud is drawn 1:1.
    cloudTarget_.setSampling(Sampling::Nearest);
    return {};
}

template <class T, class Upload>
void ViewRenderer::uploadOnce(const std::shared_ptr<const T>& product, std::shared_ptr<const T>& uploaded,
                              Upload&& upload) {
    if (!product || product == uploaded)
        return;
    upload(*product);
    uploaded = product;
    ++uploads_;
}

void ViewRenderer::sync(const processing::ShownFrame& shown) {
    // The GPU's overlays are made from the depth and the camera image: either new redraws them.
    const auto imageBytes = [](const frame::FramePtr& f) { return f ? f->capturedImage.bytes : nullptr; };
    const bool newImage = imageBytes(shown.frame) != imageBytes(frame_);
    const bool newDepth = shown.depth.data != depth_.data || newImage;
    if (newDepth)
        panelsDrawnWith_.reset();
    depth_ = shown.depth;
    shownPanelSamples_ = shown.panelSamples;
    shownPanelStep_ = shown.panelStep;
    if (shown.depthOverCamera != depthOverCamera_ || (newDepth && !shown.depthOverCamera))
        overlayDrawnWith_.reset();
    colourOverDepthFromEngine_ = shown.colourOverDepth != nullptr;
    if (colourOverDepthFromEngine_)
        colourOverDepthFromGpu_ = false;
    depthOverCamera_ = shown.depthOverCamera;
    pointColours_ = shown.pointColours;
    cloud_ = shown.cloud;
    frame_ = shown.frame;
    cameraFromEngine_ = shown.cameraImage != nullptr;
    uploadOnce(shown.cameraImage, cameraUploaded_, [this](const processing::RgbImage& image) {
        camera_.uploadRgb(image.width, image.height, image.pixels.data());
    });
    uploadOnce(shown.infraredImage, infraredUploaded_, [this](const processing::RgbImage& image) {
        infrared_.uploadRgb(image.width, image.height, image.pixels.data());
    });
    uploadOnce(shown.fog, fogUploaded_, [this](const processing::RgbaImage& image) {
        fog_.upload(image.width, image.height, image.pixels.data());
    });
    uploadOnce(shown.aura, auraUploaded_, [this](const processing::RgbaImage& image) {
        aura_.upload(image.width, image.height, image.pixels.data());
    });
    uploadOnce(shown.colourOverDepth, colourOverDepthUploaded_, [this](const processing::RgbaImage& image) {
        colourOverDepth_.upload(image.width, image.height, image.pixels.data());
    });
    uploadOnce(shown.quality ? shown.quality->causeOverlay : nullptr, causeOverlayUploaded_,
               [this](const processing::RgbaImage& image) {
                   causeOverlay_.upload(image.width, image.height, image.pixels.data());
               });
    uploadOnce(shown.quality ? shown.quality->map : nullptr, qualityMapUploaded_,
               [this](const processing::QualityMapImage& map) {
                   qualityMap_.upload(map.image.width, map.image.height, map.image.pixels.data());
               });
}

const FrameTextures& ViewRenderer::texturesFor(UploadedDepth& uploaded, const processing::ShownDepth& depth,
                                               const std::shared_ptr<const processing::RgbImage>& colours,
                                               bool withColours) {
    if (depth.data != uploaded.depth) {
        uploaded.textures.uploadDepth(depth);
        uploaded.depth = depth.data;
        uploaded.coloursUploaded = false; // the colour texture follows the depth map's size
        ++uploads_;
    }
    if (withColours && (!uploaded.coloursUploaded || colours != uploaded.colours)) {
        uploaded.textures.uploadColours(colours.get());
        uploaded.colours = colours;
        uploaded.coloursUploaded = true;
        ++uploads_;
    }
    return uploaded.textures;
}

const FrameTextures& ViewRenderer::textures() {
    return texturesFor(panelDepth_, depth_, pointColours_, true);
}

const FrameTextures& ViewRenderer::cloudTextures() {
    UploadedDepth& uploaded = cloud_.factor > 1 ? cloudDepth_ : panelDepth_;
    return texturesFor(uploaded, cloud_.depth, cloud_.colours, cloud_.colours != nullptr);
}

void ViewRenderer::syncAccumulated(processing::AccumulationWorker& worker) {
    worker.tryRead([this](processing::PointAccumulator& points) { accumulated_.sync(points); });
}

void ViewRenderer::renderPanels(const PanelParams& params) {
    const bool panels = panelsDrawnWith_ != params && depth_.data && (params.depth || params.confidence);
    const bool overlay =
        overlayDrawnWith_ != params && params.depthOverCamera &&
        (depthOverCamera_ || (params.gpuOverlays && params.cameraShownWidth > 0 && alignsOnGpu()));
    if (!panels && !overlay)
        return;
    // The last frame's drawing samples these panel textures. Debian 12's llvmpipe now and then lost a pass
    // that redrew them before that drawing had finished (the panel read back unchanged after a colormap
    // change in two test runs of three; a glFlush did not help): the passes start once it has. By now
    // that is the previous frame's composite alone, and a redraw happens only when what it shows changes.
    // A GPU orders its passes itself: waiting there would only stall the GL thread.
    if (softwareGl())
        glFinish();
    if (panels)
        drawDataPanels(params);
    if (overlay)
        drawDepthOverCamera(params);
}

void ViewRenderer::renderPanelsWhole() {
    if (!panelsDrawnWith_ || panelStep_ == 1)
        return;
    PanelParams whole = *panelsDrawnWith_;
    whole.shownWidth = 0;
    renderPanels(whole);
}

Expected<std::vector<processing::PanelPicture>> ViewRenderer::panelPictures(bool withCloud) {
    renderPanelsWhole();
    const std::pair<const char*, const RenderTarget*> panels[] = {
        {"cloud.png", &cloudTarget_}, {"depth.png", &depthTarget_}, {"confidence.png", &confidenceTarget_}};
    std::vector<processing::PanelPicture> pictures;
    for (const auto& [name, target] : panels) {
        if (target == &cloudTarget_ && !withCloud)
            continue;
        if (target->empty())
            return Error{std::string("cannot write ") + name + ": the panel has not been rendered"};
        pictures.push_back({name, {target->width(), target->height(), target->readRgba()}});
    }
    return pictures;
}

const FrameTextures& ViewRenderer::panelTextures(int step) {
    if (step <= 1)
        return texturesFor(panelDepth_, depth_, pointColours_, false);
    processing::ShownDepth samples;
    samples.data = shownPanelSamples_ && shownPanelStep_ == step ? shownPanelSamples_ : nullptr;
    if (!samples.data) {
        // The panel's width changed after the engine made this frame, or the engine was not told it.
        if (ownSampledFrom_ != depth_.data || ownSampleStep_ != step) {
            ownPanelSamples_ =
                std::make_shared<const frame::DepthData>(processing::sampleCellCentres(*depth_.data, step));
            ownSampledFrom_ = depth_.data;
            ownSampleStep_ = step;
            ++panelSamplings_;
        }
        samples.data = ownPanelSamples_;
    }
    return texturesFor(panelSamples_, samples, nullptr, false);
}

void ViewRenderer::drawDataPanels(const PanelParams& params) {
    // Nearest sampling shows one sample in `step` of a map drawn `step` times smaller than it is: those
    // samples are all the panel needs, and a 1920x1440 map is 11 MB to upload and 2.8 M pixels to draw.
    const int step = processing::panelSampleStep(depth_.width(), params.shownWidth);
    const FrameTextures& textures = panelTextures(step);
    panelStep_ = step;
    panelsMap_ = {depth_.width(), depth_.height()};
    if (params.depth) {
        depthTarget_.resize(textures.depthWidth(), textures.depthHeight());
        panels_.renderDepth(depthTarget_, textures, params.minMeters, params.maxMeters, params.colormap);
    }
    if (params.confidence) {
        confidenceTarget_.resize(textures.depthWidth(), textures.depthHeight());
        panels_.renderConfidence(confidenceTarget_, textures);
    }
    colourOverDepthFromGpu_ = params.depth && params.colourOverDepth && params.gpuOverlays &&
                              !colourOverDepthFromEngine_ && frame_ && !frame_->capturedImage.empty() &&
                              processing::shaderCanColour(frame_->rig.get());
    if (colourOverDepthFromGpu_)
        drawColourOverDepth(step);
    panelsDrawnWith_ = params;
    ++panelRenders_;
}

// The depth panel's colours and range on the depth as the colour camera sees it; where it saw no depth the
// camera image shows through, since a colour there would be a depth nobody measured.
void ViewRenderer::drawDepthOverCamera(const PanelParams& params) {
    if (!depthOverCamera_) {
        const auto [width, height] =
            processing::cameraPanelImageSize(frame_->capturedImage, params.cameraShownWidth);
        prepareCameraColours();
        cameraColours_.renderAlignedDepth(depthOverCameraTarget_,
                                          texturesFor(panelDepth_, depth_, pointColours_, false), width,
                                          height, {params.minMeters, params.maxMeters, params.colormap});
        overlayDrawnWith_ = params;
        ++overlayRenders_;
        return;
    }
    processing::ShownDepth aligned;
    aligned.data = depthOverCamera_;
    const FrameTextures& textures = texturesFor(overlayDepth_, aligned, nullptr, false);
    depthOverCameraTarget_.resize(textures.depthWidth(), textures.depthHeight());
    panels_.renderDepth(depthOverCameraTarget_, textures, params.minMeters, params.maxMeters, params.colormap,
                        DepthHoles::Transparent);
    overlayDrawnWith_ = params;
    ++overlayRenders_;
}

// Made from every sample of the shown depth, so that a sample hidden behind one the panel skips is hidden
// as the CPU's overlay hides it.
void ViewRenderer::drawColourOverDepth(int step) {
    prepareCameraColours();
    cameraColours_.renderSeenColours(colourOverDepthTarget_,
                                     texturesFor(panelDepth_, depth_, pointColours_, false), step);
}

bool ViewRenderer::alignsOnGpu() const {
    if (!frame_ || frame_->capturedImage.empty() || !depth_.data || !frame_->rig)
        return false;
    return !processing::isSingleCamera(*frame_->rig) && processing::shaderCanColour(frame_->rig.get());
}

void ViewRenderer::prepareCameraColours() {
    cameraColours_.uploadImage(frame_->capturedImage);
    cameraColours_.setRig(frame_->rig);
}

void ViewRenderer::renderCameraImage(int shownWidth) {
    if (cameraFromEngine_ || !frame_ || frame_->capturedImage.empty() || shownWidth <= 0)
        return;
    const frame::CapturedImage& image = frame_->capturedImage;
    const auto [width, height] = processing::cameraPanelImageSize(image, shownWidth);
    const CameraDrawing drawing{image.bytes, width, height};
    if (cameraDrawn_ == drawing)
        return;
    cameraColours_.uploadImage(image);
    if (!cameraColours_.hasImage())
        return;
    cameraColours_.renderImage(cameraTarget_, width, height);
    cameraDrawn_ = drawing;
    ++cameraRenders_;
}

void ViewRenderer::setCloudPath(CloudPath path) {
    path_ = path;
    accumulated_.setCpuCopy(path == CloudPath::Splat);
}

void ViewRenderer::renderCloud(CloudParams params, bool accumulated) {
    params.accumulated = accumulated ? &accumulated_ : nullptr;
    const bool shaded = shaderColours(params, accumulated);
    CloudDrawing drawing{params,
                         accumulated ? nullptr : cloud_.depth.data,
                         accumulated ? nullptr : cloud_.colours,
                         shaded ? frame_->capturedImage.bytes : nullptr,
                         accumulated ? accumulated_.version() : 0,
                         path_,
                         cloudTarget_.width(),
                         cloudTarget_.height()};
    if (cloudDrawn_ == drawing)
        return;
    drawCloud(params, accumulated);
    cloudDrawn_ = std::move(drawing);
    ++cloudRenders_;
}

void ViewRenderer::drawCloud(const CloudParams& params, bool accumulated) {
    // The hazard renderPanels() waits out: a pass into the cloud target was lost now and then on llvmpipe,
    // leaving the old picture (a test's anchor cube missing in 3 of 80 runs beside a busy Xvfb). A picture
    // uploaded whole waits by itself; a GPU has no such bug and is not stalled.
    if (softwareGl() && !(path_ == CloudPath::Splat && CloudSplatter::makesPicture(params)))
        glFinish();
    const bool camera = params.coloring == PointColoring::Camera;
    if (path_ == CloudPath::Points) {
        const bool shaded = shaderColours(params, accumulated);
        // Undecimated, the cloud's samples are the panels' own: one set of textures serves both.
        UploadedDepth& uploaded = cloud_.factor > 1 ? cloudDepth_ : panelDepth_;
        const FrameTextures& textures =
            accumulated || !cloud_.depth.data
                ? panelDepth_.textures
                : texturesFor(uploaded, cloud_.depth, cloud_.colours, camera && !shaded);
        if (shaded) {
            prepareCameraColours();
            cameraColours_.renderNearest(textures);
        }
        cloudRenderer_.render(cloudTarget_, textures, params, shaded ? &cameraColours_ : nullptr);
        return;
    }
    const int width = cloudTarget_.width();
    const int height = cloudTarget_.height();
    if (accumulated)
        splatter_.splatWorld(accumulated_.cpuCopy(), accumulated_.pointCount(), params, width, height);
    else if (cloud_.depth.data && cloud_.depth.intrinsics.valid())
        splatter_.splatSources(splatSources(params), params, width, height);
    else
        splatter_.splatWorld({}, 0, params, width, height);
    cloudRenderer_.renderSplat(cloudTarget_, splatter_, params);
}

std::vector<CloudSplatter::SplatSource> ViewRenderer::splatSources(const CloudParams& params) const {
    std::vector<CloudSplatter::SplatSource> sources{{cloud_.depth.data.get(), cloud_.depth.intrinsics,
                                                     cloud_.colours.get(), params.viewProjection,
                                                     std::nullopt, std::nullopt}};
    const auto byte = [](float v) {
        return static_cast<std::uint32_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
    };
    for (const CloudLayer& layer : params.layers) {
        std::optional<std::uint32_t> tint;
        if (layer.tint.a > 0.0f)
            tint = byte(layer.tint.r) | byte(layer.tint.g) << 8 | byte(layer.tint.b) << 16;
        sources.push_back({layer.depth.get(), layer.intrinsics, layer.colours.get(), layer.viewProjection,
                           tint, layer.minConfidence});
    }
    return sources;
}

bool ViewRenderer::shaderColours(const CloudParams& params, bool accumulated) const {
    return path_ == CloudPath::Points && params.coloring == PointColoring::Camera && !accumulated && frame_ &&
           cloud_.depth.data && !cloud_.colours;
}

void ViewRenderer::resizeCloud(int width, int height) {
    width = std::max(width, 1);
    height = std::max(height, 1);
    if (width == cloudTarget_.width() && height == cloudTarget_.height())
        return;
    cloudTarget_.resize(width, height);
    ++cloudResizes_; // the texture holds nothing drawn until the cloud is drawn again
}

} // namespace dc::render
