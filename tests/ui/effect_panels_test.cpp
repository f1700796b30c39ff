// The Fog panel's blur control: dragging it changes the blur of the fog and so the fog image.

#include "devices/synthetic/synthetic_device.h"
#include "panel_fixture.h"
#include "processing/fog.h"
#include "ui/panels.h"

namespace dc::ui::test {
namespace {

TEST_F(PanelTest, TheFogBlurControlChangesTheFogImage) {
    devices::SyntheticConfig config;
    config.cameraWidth = 640;
    config.cameraHeight = 480;
    config.paced = false;
    devices::SyntheticDevice device(config);
    ASSERT_TRUE(device.open().ok());
    const frame::FramePtr scene = device.makeFrame(1, 0.0);

    processing::FogSettings fog;
    bool open = true, changed = false;
    draw_ = [&] { changed |= drawFogPanel({}, fog, &open); };
    frame();
    const processing::RgbaImage before = processing::renderFog(*scene, fog, processing::DepthSource::Raw);
    const auto blur = locate(kFogTitle, "Blur");
    ASSERT_TRUE(blur);
    drag(*blur, ImVec2(blur->x + 400.0f, blur->y)); // past the slider's right end: its largest sigma
    EXPECT_TRUE(changed);
    EXPECT_FLOAT_EQ(fog.blurSigmaPixels, 20.0f);
    const processing::RgbaImage after = processing::renderFog(*scene, fog, processing::DepthSource::Raw);
    ASSERT_EQ(after.pixels.size(), before.pixels.size());
    std::size_t differing = 0;
    for (std::size_t i = 0; i < after.pixels.size(); ++i)
        differing += after.pixels[i] != before.pixels[i];
    EXPECT_GT(differing, after.pixels.size() / 100) << "the fog's edges at the apple, book and desk soften";
}

} // namespace
} // namespace dc::ui::test
