#pragma once

#include "base/expected.h"
#include "processing/accumulation_worker.h"
#include "processing/shown_frame.h"
#include "render/accumulated_points.h"
#include "render/camera_colours.h"
#include "render/cloud_splat.h"
#include "render/colormap.h"
#include "render/frame_textures.h"
#include "render/panel_renderer.h"
#include "render/point_cloud_renderer.h"
#include "render/render_target.h"
#include "render/rgba_texture.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace dc::render {

// How the depth and confidence panels are drawn.
struct PanelParams {
    bool depth = true;
    bool confidence = true;
    bool depthOverCamera = false; // the camera panel's overlay of a two-sensor frame's aligned depth
    bool colourOverDepth = false; // the depth panel's overlay of the camera colours
    // The overlays the engine did not make are made here, from the shown depth and the camera's planes
    // (engine::Demand::gpuCameraColours): the colour overlay at the depth panel's drawn size, the depth
    // over the camera at cameraShownWidth (processing::cameraPanelImageSize).
    bool gpuOverlays = false;
    int cameraShownWidth = 0;
    float minMeters = 0.0f;
    float maxMeters = 2.5f;
    Colormap colormap = Colormap::Jet;
    // The widest the depth and confidence panels' images are shown, in pixels (0: unknown). A map at
    // least twice as wide is drawn from every n-th sample (processing::sampleCellCentres) at no less than
    // this width, which is what the screen shows of it, rather than uploaded and drawn whole.
    int shownWidth = 0;

    bool operator==(const PanelParams&) const = default;
};

// How the cloud reaches the screen: GL_POINTS on the GPU, or splatted on the CPU's cores (CloudSplatter)
// and shown as one image. On software GL the splat is several times cheaper; on a GPU the points are.
enum class CloudPath { Points, Splat };
const char* toString(CloudPath path);
// Whether GL_RENDERER names a software rasteriser (Mesa's llvmpipe, softpipe or swrast, Windows' basic
// render driver through D3D12), where the splat path wins.
bool isSoftwareRenderer(std::string_view glRenderer);

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
    // Draws the depth and confidence panels (at the depth map's size, or a fraction of it no smaller than
    // params.shownWidth) with the depth panel's colour overlay, and the depth over the camera, where their
    // data or `params` changed.
    void renderPanels(const PanelParams& params);
    // Draws the depth and confidence panels again at the depth map's own size if they were drawn smaller:
    // for a snapshot, which keeps every sample. The next renderPanels() draws them at the shown size again.
    void renderPanelsWhole();
    // The cloud, depth and confidence panels as cloud.png, depth.png and confidence.png: drawn whole first
    // (renderPanelsWhole), so the depth and confidence keep every sample however small they are shown.
    // An error names a panel not rendered yet.
    // `withCloud` false: the depth and confidence only (a source whose points another source's cloud draws).
    Expected<std::vector<processing::PanelPicture>> panelPictures(bool withCloud = true);
    // The size of the depth map the depth and confidence panels show (their images' shape on screen; the
    // targets may hold every n-th sample of it).
    int panelsMapWidth() const { return panelsMap_.first; }
    int panelsMapHeight() const { return panelsMap_.second; }
    // The camera panel's picture made on the GPU from the image's planes, at the size the panel shows it
    // (processing::cameraPanelImageSize of `shownWidth`), when the engine made none for this frame
    // (engine::Demand::gpuCameraColours); drawn again only when the image or the size changes.
    void renderCameraImage(int shownWidth);
    // Whether the camera panel shows cameraTarget() (made here) rather than cameraTexture() (the engine's).
    bool cameraFromGpu() const { return !cameraFromEngine_ && cameraDrawn_.has_value(); }
    const RenderTarget& cameraTarget() const { return cameraTarget_; }
    // Draws the cloud into cloudTarget() (params.accumulated is filled in by accumulate mode), unless
    // nothing it shows changed since the last time: the same samples, parameters, size and path.
    // params.layers are drawn with the frame's samples, on either path.
    void renderCloud(CloudParams params, bool accumulated);
    void setCloudPath(CloudPath path);
    CloudPath cloudPath() const { return path_; }
    // GL_RENDERER of the context init() ran in, and whether it rasterises in software.
    const std::string& glRenderer() const { return glRenderer_; }
    bool softwareGl() const { return isSoftwareRenderer(glRenderer_); }
    void resizeCloud(int width, int height);

    const RenderTarget& cloudTarget() const { return cloudTarget_; }
    const RenderTarget& depthTarget() const { return depthTarget_; }
    const RenderTarget& confidenceTarget() const { return confidenceTarget_; }
    const RgbaTexture& cameraTexture() const { return camera_; }
    // The shown frame's depth aligned to the colour image in the depth panel's colours, holes transparent;
    // drawn only while params ask for it and the frame has one (ShownFrame::depthOverCamera) or, with
    // params.gpuOverlays, is a two-sensor frame (then drawn here at the camera panel's size).
    const RenderTarget& depthOverCameraTarget() const { return depthOverCameraTarget_; }
    const RgbaTexture& colourOverDepthTexture() const { return colourOverDepth_; }
    // Whether the depth panel's colour overlay is colourOverDepthTarget() (made here) rather than
    // colourOverDepthTexture() (the engine's).
    bool colourOverDepthFromGpu() const { return colourOverDepthFromGpu_; }
    const RenderTarget& colourOverDepthTarget() const { return colourOverDepthTarget_; }
    // Whether the camera panel's depth overlay is depthOverCameraTarget(), the depth aligned to the colour
    // image (a two-sensor frame's, the engine's or, with `gpuOverlays`, made here), rather than the depth
    // panel's image (a single camera's).
    bool alignsDepthOverCamera(bool gpuOverlays) const {
        return depthOverCamera_ != nullptr || (gpuOverlays && alignsOnGpu());
    }
    const RgbaTexture& infraredTexture() const { return infrared_; }
    const RgbaTexture& fogTexture() const { return fog_; }
    const RgbaTexture& auraTexture() const { return aura_; }
    // The Quality region's missing samples in their causes' colours (ShownQuality::causeOverlay), when the
    // shown frame has them.
    const RgbaTexture& causeOverlayTexture() const { return causeOverlay_; }
    // The Quality panel's per-pixel map (ShownQuality::map), when the shown frame has one.
    const RgbaTexture& qualityMapTexture() const { return qualityMap_; }
    // The shown depth as textures, uploaded if it was not yet (the depth panel and GL_POINTS read them).
    const FrameTextures& textures();
    // The cloud's samples (decimated or not) with the engine's point colours, uploaded if they were not
    // yet: what another renderer draws of this source as a CloudLayer.
    const FrameTextures& cloudTextures();
    const processing::ShownCloud& cloud() const { return cloud_; }
    // Work done, for tests that check that nothing is redone for nothing.
    std::uint64_t uploads() const { return uploads_; }
    std::uint64_t panelRenders() const { return panelRenders_; }
    // The panels' samples picked on this thread because the engine's were for another width (or none).
    std::uint64_t panelSamplings() const { return panelSamplings_; }
    std::uint64_t cloudRenders() const { return cloudRenders_; }
    // Moves whenever a texture the panels show gets new contents: a window whose ImGui frame is the same
    // and this the same shows the same picture (ui::FrameDamage).
    std::uint64_t contentVersion() const {
        return uploads_ + panelRenders_ + overlayRenders_ + cloudRenders_ + cloudResizes_ + cameraRenders_;
    }
    // Points the last cloud drawing processed (after decimation; accumulated points in accumulate mode).
    std::size_t cloudPoints() const { return cloudRenderer_.lastPointCount(); }
    // The GPU's camera colours: their uploads and visibility passes, for tests that count work.
    const CameraColours& cameraColours() const { return cameraColours_; }

private:
    // A FrameTextures and the products it holds, so a product is uploaded once.
    struct UploadedDepth {
        FrameTextures textures;
        std::shared_ptr<const frame::DepthData> depth;
        std::shared_ptr<const processing::RgbImage> colours;
        bool coloursUploaded = false;
    };
    // What the last cloud drawing showed: the same again is not drawn again.
    struct CloudDrawing {
        CloudParams params;
        std::shared_ptr<const frame::DepthData> depth;
        std::shared_ptr<const processing::RgbImage> colours;
        std::shared_ptr<const std::vector<std::uint8_t>> cameraBytes; // the image the shader colours from
        std::uint64_t accumulatedVersion = 0;
        CloudPath path = CloudPath::Points;
        int width = 0;
        int height = 0;
        bool operator==(const CloudDrawing&) const = default;
    };

    // Uploads `product` unless it is the one uploaded last (held, so its address is never reused).
    template <class T, class Upload>
    void uploadOnce(const std::shared_ptr<const T>& product, std::shared_ptr<const T>& uploaded,
                    Upload&& upload);
    // Brings `uploaded` to `depth` (and `colours` when the points read them).
    const FrameTextures& texturesFor(UploadedDepth& uploaded, const processing::ShownDepth& depth,
                                     const std::shared_ptr<const processing::RgbImage>& colours,
                                     bool withColours);
    void drawCloud(const CloudParams& params, bool accumulated);
    // The shown cloud's samples and params.layers', for the CPU splat.
    std::vector<CloudSplatter::SplatSource> splatSources(const CloudParams& params) const;
    // Whether the points' camera colours are made by the shader: GL points coloured by the camera with no
    // colours from the engine (engine::Demand::gpuCameraColours).
    bool shaderColours(const CloudParams& params, bool accumulated) const;
    void drawDataPanels(const PanelParams& params);
    // The textures the panels draw from: the shown depth's own, or every `step`-th sample of it (the
    // engine's when it picked them for this step).
    const FrameTextures& panelTextures(int step);
    void drawDepthOverCamera(const PanelParams& params);
    void drawColourOverDepth(int step);
    // A two-sensor frame whose depth the shaders can align to its camera image.
    bool alignsOnGpu() const;
    // The camera's planes and rig of the shown frame, for the shaders' colours.
    void prepareCameraColours();

    UploadedDepth panelDepth_;
    UploadedDepth cloudDepth_; // the cloud's samples when they are decimated
    UploadedDepth overlayDepth_;
    UploadedDepth panelSamples_; // every n-th sample of the shown depth, for panels shown smaller
    std::shared_ptr<const frame::DepthData> shownPanelSamples_; // the engine's (ShownFrame::panelSamples)
    int shownPanelStep_ = 1;
    std::shared_ptr<const frame::DepthData> ownPanelSamples_; // picked here when the engine's do not fit
    std::shared_ptr<const frame::DepthData> ownSampledFrom_;
    int ownSampleStep_ = 1;
    std::uint64_t panelSamplings_ = 0;
    int panelStep_ = 1;
    std::pair<int, int> panelsMap_{0, 0};
    std::shared_ptr<const frame::DepthData> depthOverCamera_;
    processing::ShownDepth depth_;
    std::shared_ptr<const processing::RgbImage> pointColours_;
    processing::ShownCloud cloud_;
    frame::FramePtr frame_; // the shown frame: its camera image and rig, for the shader's colours
    PointCloudRenderer cloudRenderer_;
    CameraColours cameraColours_;
    CloudSplatter splatter_;
    CloudPath path_ = CloudPath::Points;
    std::string glRenderer_;
    std::optional<CloudDrawing> cloudDrawn_;
    PanelRenderer panels_;
    AccumulatedPoints accumulated_;
    RenderTarget cloudTarget_;
    RenderTarget depthTarget_{Sampling::Nearest, DepthBuffer::Without};
    RenderTarget confidenceTarget_{Sampling::Nearest, DepthBuffer::Without};
    RenderTarget depthOverCameraTarget_{Sampling::Nearest, DepthBuffer::With}; // drawn as points on the GPU
    RenderTarget colourOverDepthTarget_{Sampling::Nearest, DepthBuffer::Without};
    bool colourOverDepthFromGpu_ = false;
    bool colourOverDepthFromEngine_ = false; // the shown frame carries the engine's colour overlay
    RenderTarget cameraTarget_{Sampling::Linear, DepthBuffer::Without};
    // The image and size cameraTarget_ holds; whether this frame's camera panel came from the engine.
    struct CameraDrawing {
        std::shared_ptr<const std::vector<std::uint8_t>> bytes;
        int width = 0;
        int height = 0;
        bool operator==(const CameraDrawing&) const = default;
    };
    std::optional<CameraDrawing> cameraDrawn_;
    bool cameraFromEngine_ = false;
    RgbaTexture camera_;
    RgbaTexture infrared_;
    RgbaTexture fog_;
    RgbaTexture aura_;
    RgbaTexture colourOverDepth_{Sampling::Nearest}; // one colour per depth sample, as the depth panel
    RgbaTexture causeOverlay_{Sampling::Nearest};    // one colour per region sample
    RgbaTexture qualityMap_{Sampling::Nearest};
    std::shared_ptr<const processing::RgbImage> cameraUploaded_;
    std::shared_ptr<const processing::RgbImage> infraredUploaded_;
    std::shared_ptr<const processing::RgbaImage> fogUploaded_;
    std::shared_ptr<const processing::RgbaImage> auraUploaded_;
    std::shared_ptr<const processing::RgbaImage> colourOverDepthUploaded_;
    std::shared_ptr<const processing::RgbaImage> causeOverlayUploaded_;
    std::shared_ptr<const processing::QualityMapImage> qualityMapUploaded_;
    std::optional<PanelParams> panelsDrawnWith_;  // reset by a new depth map
    std::optional<PanelParams> overlayDrawnWith_; // reset by a new aligned depth
    std::uint64_t uploads_ = 0;
    std::uint64_t panelRenders_ = 0;
    std::uint64_t overlayRenders_ = 0;
    std::uint64_t cloudResizes_ = 0;
    std::uint64_t cloudRenders_ = 0;
    std::uint64_t cameraRenders_ = 0;
};

} // namespace dc::render
