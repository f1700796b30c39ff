#pragma once

#include "base/expected.h"
#include "render/colormap.h"
#include "render/frame_textures.h"
#include "render/gl_objects.h"
#include "render/render_target.h"

#include <array>
#include <functional>

namespace dc::render {

// What the depth panel shows where there is no measurement: black on its own, nothing (alpha 0) as an
// overlay, so that the image beneath shows through.
enum class DepthHoles { Black, Transparent };

// The 2D data panels beside the cloud: depth in a colormap, confidence as red/green/blue (the camera panel
// shows the engine's image as it is). Each fills its whole target with one fullscreen triangle; the caller
// sizes the target, usually to the data's own resolution. Depth and confidence show the sample under each
// pixel without filtering, so a panel at native size is pixel-exact. All leave framebuffer 0 bound.
class PanelRenderer {
public:
    // Compiles the shaders; needs a current context.
    Status init();
    // colormapColor(colormap, (d - minMeters) / (maxMeters - minMeters)), opaque; `holes` says what is
    // drawn where there is no measurement.
    void renderDepth(RenderTarget& target, const FrameTextures& textures, float minMeters, float maxMeters,
                     Colormap colormap = Colormap::Jet, DepthHoles holes = DepthHoles::Black);
    // Low red, medium green, high blue (the sample's colours); black without depth.
    void renderConfidence(RenderTarget& target, const FrameTextures& textures);

private:
    struct Panel {
        gl::Program program;
        GLint viewportSize = -1;
        GLint minMeters = -1;
        GLint inverseRangeMeters = -1;
        GLint holeAlpha = -1;
    };

    void draw(RenderTarget& target, const FrameTextures& textures, const Panel& panel,
              const std::function<void()>& setUniforms) const;

    gl::VertexArray emptyVertexArray_;        // core profile draws need a bound VAO even without attributes
    std::array<Panel, kColormapCount> depth_; // one per colormap (colormapGlsl says why)
    Panel confidence_;
};

} // namespace dc::render
