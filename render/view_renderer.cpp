#include "render/view_renderer.h"

namespace dc::render {

Status ViewRenderer::init() {
    if (Status s = cloud_.init(); !s)
        return s;
    if (Status s = panels_.init(); !s)
        return s;
    if (Status s = accumulated_.init(); !s)
        return s;
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
    if (shown.depth.data != depthUploaded_) {
        textures_.uploadDepth(shown.depth);
        depthUploaded_ = shown.depth.data;
        colorsUploaded_.reset(); // the colour texture follows the depth map's size
        panelsDrawnWith_.reset();
        ++uploads_;
    }
    if (shown.pointColors != colorsUploaded_ || !textures_.colorTexture()) {
        textures_.uploadColors(shown.pointColors.get());
        colorsUploaded_ = shown.pointColors;
        ++uploads_;
    }
    uploadOnce(shown.cameraImage, cameraUploaded_, [this](const processing::RgbImage& image) {
        camera_.uploadRgb(image.width, image.height, image.pixels.data());
    });
    uploadOnce(shown.fog, fogUploaded_, [this](const processing::RgbaImage& image) {
        fog_.upload(image.width, image.height, image.pixels.data());
    });
    uploadOnce(shown.aura, auraUploaded_, [this](const processing::RgbaImage& image) {
        aura_.upload(image.width, image.height, image.pixels.data());
    });
}

void ViewRenderer::syncAccumulated(processing::AccumulationWorker& worker) {
    worker.tryRead([this](processing::PointAccumulator& points) { accumulated_.sync(points); });
}

void ViewRenderer::renderPanels(const PanelParams& params) {
    if (panelsDrawnWith_ == params || !textures_.hasDepth())
        return;
    if (params.depth) {
        depthTarget_.resize(textures_.depthWidth(), textures_.depthHeight());
        panels_.renderDepth(depthTarget_, textures_, params.minMeters, params.maxMeters, params.colormap);
    }
    if (params.confidence) {
        confidenceTarget_.resize(textures_.depthWidth(), textures_.depthHeight());
        panels_.renderConfidence(confidenceTarget_, textures_);
    }
    panelsDrawnWith_ = params;
    ++panelRenders_;
}

void ViewRenderer::renderCloud(CloudParams params, bool accumulated) {
    params.accumulated = accumulated ? &accumulated_ : nullptr;
    cloud_.render(cloudTarget_, textures_, params);
}

void ViewRenderer::resizeCloud(int width, int height) {
    cloudTarget_.resize(std::max(width, 1), std::max(height, 1));
}

} // namespace dc::render
