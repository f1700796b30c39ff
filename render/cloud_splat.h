#pragma once

#include "frame/frame.h"
#include "processing/camera_image.h"
#include "processing/point_accumulator.h"
#include "render/colormap.h"

#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace dc::render {

struct CloudParams;

// The cloud drawn on the CPU, for software OpenGL: on llvmpipe the point raster runs its vertex work on
// one thread and costs more per point than the pixels the point covers, while projecting a point and
// writing a few pixels costs a few nanoseconds on any core. Each point is projected exactly as the
// cloud's vertex shader places it and covers the pixels a GL point of the same size covers; the nearest
// point wins each pixel, as GL's depth test (GL_LESS) decides.
//
// The result is one 64-bit key per pixel, bottom row first like a GL texture: the window depth's float
// bits in the high word (positive floats order like their bits) and the colour (R | G << 8 | B << 16) in
// the low word, so "nearest wins" is a plain minimum. kEmpty where no point landed.
//
// When nothing else is drawn into the cloud (no anchors, see makesPicture), the splat also finishes the
// picture itself: RGBA8 pixels, the background where no point landed, ready to be uploaded as the
// cloud's image. On llvmpipe that saves a GL pass that would decode the keys, and the upload of keys
// twice the picture's size. With anchors, the keys go to that pass, which draws them with depth.
class CloudSplatter {
public:
    static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

    // The frame's samples placed through their intrinsics and coloured as `params` says (point colours:
    // one RGB per sample, or null for mid-gray). Pixels of `width` x `height`.
    void splatSamples(const frame::DepthData& depth, const frame::Intrinsics& intrinsics,
                      const processing::RgbImage* colours, const CloudParams& params, int width, int height);
    // One camera's samples for splatSources: placed through `intrinsics` and then `viewProjection` (which
    // takes the place of params.viewProjection), coloured as params say or all in `tint` (packed RGB),
    // kept from its own confidence level when it has one.
    struct SplatSource {
        const frame::DepthData* depth = nullptr;
        frame::Intrinsics intrinsics;
        const processing::RgbImage* colours = nullptr;
        glm::mat4 viewProjection{1.0f};
        std::optional<std::uint32_t> tint;
        std::optional<frame::Confidence> minConfidence; // none: params.minConfidence
    };
    // Several cameras' samples in one picture, each through its own matrix (sources fused in one world).
    void splatSources(std::span<const SplatSource> sources, const CloudParams& params, int width, int height);
    // Accumulated world points (the first `count` of `points`) through params.worldToClip.
    void splatWorld(const std::vector<processing::WorldPoint>& points, std::size_t count,
                    const CloudParams& params, int width, int height);

    // Whether the splat of `params` finishes the picture (picture() holds it) rather than leaving the
    // keys to a GL pass.
    static bool makesPicture(const CloudParams& params);

    const std::vector<std::uint64_t>& keys() const { return keys_; }
    // The finished picture, bottom row first like keys(): A << 24 | B << 16 | G << 8 | R per pixel, i.e.
    // RGBA bytes. Empty after a splat that did not make it.
    const std::vector<std::uint32_t>& picture() const { return picture_; }
    int width() const { return width_; }
    int height() const { return height_; }
    // Points that were projected (kept by confidence and near limit), whether or not they landed inside.
    std::size_t pointCount() const { return pointCount_; }

    // One splat before it is written: its first covered pixel and its key.
    struct Splat {
        std::int16_t x = 0; // a splat lies within the clip volume, and images are narrower than 32k
        std::int16_t y = 0;
        std::uint16_t size = 1; // pixels on a side
        std::uint64_t key = kEmpty;
    };

private:
    struct ClipBatch;
    struct Placed;
    struct SampleFilter;
    struct PreparedSource;
    std::vector<PreparedSource> prepare(std::span<const SplatSource> sources, const CloudParams& params,
                                        int width, int height) const;
    static std::size_t projectRow(const float* z, const std::uint8_t* levels,
                                  const std::array<std::vector<float>, 4>& columns, glm::vec4 row,
                                  glm::vec4 translation, SampleFilter filter, float footprint,
                                  ClipBatch& batch);
    template <class Project>
    void run(int sourceRows, const CloudParams& params, int width, int height, Project&& project);
    void place(const ClipBatch& batch, std::size_t n, int pointSize, Placed& out) const;
    void write(int band, int bands);
    void paint(int band, int bandRows, std::uint32_t background);

    std::vector<std::uint64_t> keys_;
    std::vector<std::uint32_t> picture_;
    int width_ = 0;
    int height_ = 0;
    std::size_t pointCount_ = 0;
    // [piece][band]: the splats piece `piece` of the sources made that touch rows of band `band`. Kept
    // between frames so a steady cloud allocates nothing.
    std::vector<std::vector<std::vector<Splat>>> splats_;
    std::array<std::uint32_t, 1024> colormapTable_{};
};

} // namespace dc::render
