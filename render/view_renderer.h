#pragma once

#include "base/expected.h"
#include "processing/accumulation_worker.h"
#include "processing/shown_frame.h"
#include "render/accumulated_points.h"
#include "render/colormap.h"
#include "render/frame_textures.h"
#include "render/panel_renderer.h"
#include "render/point_cloud_renderer.h"
#include "render/render_target.h"
#include "render/rgba_texture.h"

#include <cstdint>
#include <memory>
#include <optional>

namespace dc::render {

// How the depth and confidence panels are drawn.
struct PanelParams {
    bool depth = true;
    bool confidence = true;
    float minMeters = 0.0f;
    float maxMeters = 2.5f;
    Colormap colormap = Colormap::Jet;

    bool operator==(const PanelParams&) const = default;
};

// Everything the GL thread draws, in one place: the engine's products uploaded as textures, the cloud, the
// depth and confidence panels, accumulated points. It only uploads and draws: a product already on the GPU
// is not uploaded again, and a panel whose data and parameters did not change is not drawn again.
// Lives and dies on the GL thread with a context current.
class ViewRenderer {
public:
    Status init();
    // Uploads the products of `shown` that are not on the GPU yet.
    void sync(const processing::ShownFrame& shown);
    // Brings accumulated points up to date, unless the worker is adding right now (then the points uploaded
    // last time are drawn again).
    void syncAccumulated(processing::AccumulationWorker& worker);
    // Draws the depth and confidence panels at the depth map's size if their data or `params` changed.
    void renderPanels(const PanelParams& params);
    // Draws the cloud into cloudTarget() (params.accumulated is filled in by accumulate mode).
    void renderCloud(CloudParams params, bool accumulated);
    void resizeCloud(int width, int height);

    const RenderTarget& cloudTarget() const { return cloudTarget_; }
    const RenderTarget& depthTarget() const { return depthTarget_; }
    const RenderTarget& confidenceTarget() const { return confidenceTarget_; }
    const RgbaTexture& cameraTexture() const { return camera_; }
    const RgbaTexture& fogTexture() const { return fog_; }
    const RgbaTexture& auraTexture() const { return aura_; }
    const FrameTextures& textures() const { return textures_; }
    // Work done, for tests that check that nothing is redone for nothing.
    std::uint64_t uploads() const { return uploads_; }
    std::uint64_t panelRenders() const { return panelRenders_; }

private:
    // Uploads `product` unless it is the one uploaded last (held, so its address is never reused).
    template <class T, class Upload> void uploadOnce(const std::shared_ptr<const T>& product,
                                                    std::shared_ptr<const T>& uploaded, Upload&& upload);

    FrameTextures textures_;
    PointCloudRenderer cloud_;
    PanelRenderer panels_;
    AccumulatedPoints accumulated_;
    RenderTarget cloudTarget_;
    RenderTarget depthTarget_{Sampling::Nearest};
    RenderTarget confidenceTarget_{Sampling::Nearest};
    RgbaTexture camera_;
    RgbaTexture fog_;
    RgbaTexture aura_;
    std::shared_ptr<const frame::DepthData> depthUploaded_;
    std::shared_ptr<const processing::RgbImage> colorsUploaded_;
    std::shared_ptr<const processing::RgbImage> cameraUploaded_;
    std::shared_ptr<const processing::RgbaImage> fogUploaded_;
    std::shared_ptr<const processing::RgbaImage> auraUploaded_;
    std::optional<PanelParams> panelsDrawnWith_; // reset by a new depth map
    std::uint64_t uploads_ = 0;
    std::uint64_t panelRenders_ = 0;
};

} // namespace dc::render
