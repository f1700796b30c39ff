// Headless UI tests of the instrument features: hover readout, anchors and measurement, zoom on click,
// colormaps and automatic range, the camera panel's fill and depth overlay, stats, log and toasts.

#include "base/log.h"
#include "devices/frame_list_device.h"
#include "devices/synthetic/synthetic_scene.h"
#include "processing/point_cloud.h"
#include "render/colormap.h"
#include "tests/small_rig.h"
#include "ui_fixture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <unistd.h>

namespace dc::ui::test {
namespace {

// The exact desk point seen through depth pixel (u, v) of the fixed camera, in the camera frame: the ray
// through the pixel (the unprojection's own convention) meets the plane y = 0 of the world.
glm::dvec3 analyticDeskPoint(const frame::Intrinsics& k, int u, int v) {
    const double pitch = devices::scene::kCameraPitchDegrees * std::numbers::pi / 180.0;
    const double xn = (u - k.cx) / k.fx, yn = (v - k.cy) / k.fy;
    const double worldDown = -std::cos(pitch) * yn - std::sin(pitch); // world y of the ray per unit camera z
    const double z = -devices::scene::kCameraHeight / worldDown;
    return {xn * z, yn * z, z};
}

class InstrumentTest : public UiTest {
protected:
    void SetUp() override {
        UiTest::SetUp();
        ASSERT_FALSE(HasFatalFailure());
        devices::SyntheticConfig exact = smallScene();
        exact.noise = false;
        ASSERT_NO_FATAL_FAILURE(startViewer(exact));
        viewer_->settings().cloud.motion.enabled = false;
        frame(0.0);
        frame(0.0);
    }

    std::optional<Probe> hoverAt(ImVec2 at) {
        gui_.io().MousePos = at;
        frame(0.0);
        return viewer_->hoverProbe();
    }

    static ImVec2 centreOf(const char* title) {
        ImGuiWindow* w = ImGui::FindWindowByName(title);
        return w ? ImVec2(w->Pos.x + w->Size.x * 0.5f, w->Pos.y + w->Size.y * 0.5f) : ImVec2(-1.0f, -1.0f);
    }

    // Moves the mouse over a 2D panel until the readout reports depth pixel (u, v): the panel's scale is
    // measured from two readouts, then corrected pixel by pixel, so no layout figure is assumed.
    // With `tolerance`, a readout that many pixels off counts too: a panel smaller than the depth map shows
    // some samples at no whole screen pixel.
    std::optional<ImVec2> mouseOverDepthPixel(const char* title, int u, int v, int tolerance = 0) {
        const ImVec2 c = centreOf(title);
        const auto a = hoverAt({c.x - 50.0f, c.y - 30.0f});
        const auto b = hoverAt({c.x + 50.0f, c.y + 30.0f});
        if (!a || !b || b->u == a->u || b->v == a->v)
            return std::nullopt;
        const float sx = 100.0f / static_cast<float>(b->u - a->u);
        const float sy = 60.0f / static_cast<float>(b->v - a->v);
        ImVec2 at{c.x - 50.0f + sx * static_cast<float>(u - a->u) + 0.5f * sx,
                  c.y - 30.0f + sy * static_cast<float>(v - a->v) + 0.5f * sy};
        // Quarter-pixel steps: a panel smaller than the depth map shows a sample less than a screen pixel
        // tall.
        for (int i = 0; i < 24; ++i) {
            const auto p = hoverAt(at);
            if (!p)
                return std::nullopt;
            if (std::abs(p->u - u) <= tolerance && std::abs(p->v - v) <= tolerance &&
                (i >= 12 || tolerance == 0))
                return at;
            if (p->u == u && p->v == v)
                return at;
            at.x += 0.25f * sx * static_cast<float>((u > p->u) - (u < p->u));
            at.y += 0.25f * sy * static_cast<float>((v > p->v) - (v < p->v));
        }
        return std::nullopt;
    }

    // Where depth pixel (u, v) appears on screen in the cloud panel, from the matrix the cloud was drawn
    // with and the panel's content origin.
    ImVec2 screenOfCloudSample(int u, int v) {
        const frame::Intrinsics& k = shown().depth.intrinsics;
        const float z = shown().depth.data->depthMeters.at(u, v);
        const glm::vec4 clip =
            viewer_->cloudViewProjection() * glm::vec4((u - k.cx) * z / k.fx, (v - k.cy) * z / k.fy, z, 1.0f);
        const ImGuiWindow* w = ImGui::FindWindowByName(kCloudTitle);
        const auto& target = renderer_.cloudTarget();
        return {w->DC.CursorStartPos.x + (clip.x / clip.w + 1.0f) * 0.5f * static_cast<float>(target.width()),
                w->DC.CursorStartPos.y +
                    (1.0f - clip.y / clip.w) * 0.5f * static_cast<float>(target.height())};
    }

    void clickAt(ImVec2 at) { click(at, 0.0); }

    // The synthetic two-sensor camera at a quarter of its sizes (quick), noise-free.
    void startSmallRig() {
        devices::SyntheticConfig rig = dc::test::smallRigConfig();
        rig.noise = false;
        ASSERT_NO_FATAL_FAILURE(startViewer(rig));
        frame(0.0);
    }

    std::array<int, 4> screenPixel(ImVec2 at) {
        const auto rgba = gui_.target().readRgba();
        const std::size_t i =
            (static_cast<std::size_t>(at.y) * gui_.target().width() + static_cast<std::size_t>(at.x)) * 4;
        return {rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]};
    }
};

TEST_F(InstrumentTest, HoverOnTheDepthPanelReadsTheKnownDepthAtAKnownPixel) {
    constexpr int kU = 128, kV = 180; // open desk in front of the camera
    const auto at = mouseOverDepthPixel(kDepthTitle, kU, kV);
    ASSERT_TRUE(at.has_value()) << "the readout never reported the pixel";
    const Probe p = *viewer_->hoverProbe();
    const frame::Intrinsics k = shown().depth.intrinsics;
    const glm::dvec3 truth = analyticDeskPoint(k, kU, kV);
    EXPECT_NEAR(p.depthMeters, truth.z, 1e-5 * truth.z);
    ASSERT_TRUE(p.confidence.has_value());
    EXPECT_EQ(*p.confidence, frame::Confidence::High);
    for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(p.point[static_cast<std::size_t>(i)], truth[i], 1e-5) << "axis " << i;
    // The readout names the frame sampled: the one shown then, no newer than the one shown now.
    ASSERT_TRUE(p.frameSequence);
    EXPECT_LE(*p.frameSequence, shown().frame->sequence);
    EXPECT_FALSE(p.driverSequence) << "a synthetic source has no driver";
    EXPECT_EQ(formatDepth(0.734f), "734 mm");
    EXPECT_EQ(formatDepth(1.2344f), "1.234 m") << "meters above one meter";
}

// A two-sensor camera: the status line names its calibration, and the readout tells a point the colour
// sensor sees from one outside its narrower view (the depth map's left margin).
TEST_F(InstrumentTest, ATwoSensorSourceNamesItsCalibrationAndHoverSaysWhatTheColourCameraCannotSee) {
    ASSERT_NO_FATAL_FAILURE(startSmallRig());
    EXPECT_NE(viewer_->statusLine().calibration.find("synthetic rig"), std::string::npos);
    ASSERT_TRUE(mouseOverDepthPixel(kDepthTitle, 2, 60, 1).has_value());
    ASSERT_GT(viewer_->hoverProbe()->depthMeters, 0.0f);
    EXPECT_FALSE(viewer_->hoverProbe()->seenByColour);
    ASSERT_TRUE(mouseOverDepthPixel(kDepthTitle, 106, 60, 1).has_value());
    EXPECT_TRUE(viewer_->hoverProbe()->seenByColour);
}

// The synthetic camera behind another device's face: the devices below change what it announces or what
// its frames carry.
class WrappedSynthetic : public devices::Device {
public:
    explicit WrappedSynthetic(const devices::SyntheticConfig& config) : inner_(config) {}
    devices::Capabilities capabilities() const override { return inner_.capabilities(); }

protected:
    Status doOpen() override { return inner_.open(); }
    Status doStart() override { return inner_.start(); }
    void doStop() override { (void)inner_.stop(); }
    void doClose() override { inner_.close(); }
    devices::CaptureResult doCapture(std::chrono::milliseconds timeout) override {
        return inner_.capture(timeout);
    }

    devices::SyntheticDevice inner_;
};

// A live camera whose colour node is a sensor of its own, opened without a two-sensor calibration: the
// synthetic single camera's frames under such a device's capabilities.
class UnregisteredColourDevice final : public WrappedSynthetic {
public:
    using WrappedSynthetic::WrappedSynthetic;
    std::string description() const override { return "camera with a separate colour node"; }
    devices::Capabilities capabilities() const override {
        devices::Capabilities c = inner_.capabilities();
        c.unregisteredColour = true;
        return c;
    }
};

// A colour sensor that has not delivered yet: the synthetic camera's frames without their image, under
// capabilities that promise colour.
class ColourNotYetDevice final : public WrappedSynthetic {
public:
    using WrappedSynthetic::WrappedSynthetic;
    std::string description() const override { return "camera whose colour sensor starts late"; }

protected:
    devices::CaptureResult doCapture(std::chrono::milliseconds timeout) override {
        devices::CaptureResult r = inner_.capture(timeout);
        if (r.frame) {
            auto depthOnly = std::make_shared<frame::Frame>(*r.frame);
            depthOnly->capturedImage = {};
            r.frame = std::move(depthOnly);
        }
        return r;
    }
};

// The headless run and --out print the names savePanels returns: a frame without the camera's image has
// no camera.png, and none is named.
TEST_F(InstrumentTest, SavingThePanelsNamesExactlyTheFilesItWrote) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("dc-panels-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    ASSERT_NO_FATAL_FAILURE(start(std::make_unique<ColourNotYetDevice>(smallScene()), "late colour"));
    ASSERT_TRUE(viewer_->update(0.0, std::chrono::seconds(5)));
    frame(0.0);
    ASSERT_TRUE(instrument_->capabilities().color) << "the source promises colour";
    const auto written = viewer_->savePanels(dir.string());
    ASSERT_TRUE(written.ok()) << written.error().message;
    EXPECT_EQ(*written, (std::vector<std::string>{"cloud.png", "depth.png", "confidence.png"}));
    std::vector<std::string> present;
    for (const auto& e : std::filesystem::directory_iterator(dir))
        present.push_back(e.path().filename().string());
    std::sort(present.begin(), present.end());
    EXPECT_EQ(present, (std::vector<std::string>{"cloud.png", "confidence.png", "depth.png"}));
    std::filesystem::remove_all(dir);
}

// Frames the old source delivered while nothing took their results were its drops, not the next source's:
// "98 delivered = 46 shown + 440 dropped" after a switch.
TEST_F(InstrumentTest, AfterASourceSwitchTheFrameCountsAreTheNewSourcesOwn) {
    std::this_thread::sleep_for(std::chrono::milliseconds(500)); // 120 fps, nothing taken: results replaced
    ASSERT_GT(instrument_->status().frames.dropped, 0u);
    ASSERT_TRUE(viewer_->openSource("synthetic:64x48@30").ok());
    const engine::FrameCounts first = instrument_->status().frames;
    EXPECT_LE(first.shown + first.dropped, first.delivered);
    ASSERT_TRUE(frameUntil([&] { return instrument_->status().frames.shown >= 5; }));
    const engine::FrameCounts later = instrument_->status().frames;
    EXPECT_LE(later.shown + later.dropped, later.delivered);
}

// A result awaitFrame() took before a switch (a file dropped on the window after the wait) is the old
// source's: the next update does not show it.
TEST_F(InstrumentTest, AFrameAwaitedBeforeASwitchIsNotShownAfterIt) {
    ASSERT_TRUE(viewer_->awaitFrame(std::chrono::seconds(5)));
    ASSERT_TRUE(viewer_->openSource("synthetic:64x48@30").ok());
    viewer_->update(0.0);
    const processing::ShownFramePtr& shown = viewer_->shown();
    EXPECT_TRUE(!shown || shown->depth.width() == 64)
        << "the old source's frame, " << shown->depth.width() << " samples wide";
}

// The UI may hold a result of the source it switched away from and present it after the switch (the monkey
// met it: shown + dropped exceeded delivered by 2 after a click); that frame is not the new source's.
TEST_F(InstrumentTest, AFrameOfTheOldSourcePresentedAfterASwitchIsNotTheNewSourcesShownFrame) {
    ASSERT_TRUE(viewer_->update(0.0, std::chrono::seconds(5))); // taken, not yet presented
    const frame::FramePtr old = shown().frame;
    instrument_->switchSource(std::make_unique<devices::FrameListDevice>(std::vector{old}, 0.001, "idle"),
                              "idle");
    viewer_->presented();
    EXPECT_EQ(instrument_->status().frames.shown, 0u);
    ASSERT_TRUE(frameUntil([&] { return instrument_->status().frames.shown == 1; }))
        << "the new source's own frame counts";
    const engine::FrameCounts counts = instrument_->status().frames;
    EXPECT_LE(counts.shown + counts.dropped, counts.delivered);
}

TEST_F(InstrumentTest, AColourSensorWithoutCalibrationIsSaidToBeUnregisteredOnTheStatusLine) {
    EXPECT_TRUE(viewer_->statusLine().calibration.empty()) << "one camera: nothing to say";
    ASSERT_NO_FATAL_FAILURE(start(std::make_unique<UnregisteredColourDevice>(smallScene()), "uvc"));
    ASSERT_TRUE(viewer_->update(0.0, std::chrono::seconds(5)));
    frame(0.0);
    EXPECT_EQ(viewer_->statusLine().calibration, devices::kUnregisteredColourMessage);
}

// The depth panel's colour overlay ("Colour overlay"): the camera's colour appears over the depth the colour
// camera sees, and the depth it cannot see (the depth map's margins) stays as the depth panel draws it.
TEST_F(InstrumentTest, ColourOverDepthCheckboxLaysTheSeenColourOverTheDepthPanel) {
    ASSERT_NO_FATAL_FAILURE(startSmallRig());
    viewer_->settings().depthRange.automatic = false; // fixed colours: only the overlay changes the panel
    frame(0.0);
    const auto seen = mouseOverDepthPixel(kDepthTitle, 106, 60, 1);
    const auto unseen = mouseOverDepthPixel(kDepthTitle, 2, 60, 1);
    ASSERT_TRUE(seen && unseen);
    ASSERT_FALSE(viewer_->hoverProbe()->seenByColour);
    gui_.io().MousePos = {0.0f, 0.0f};
    frame(0.0);
    const auto seenBefore = screenPixel(*seen);
    const auto unseenBefore = screenPixel(*unseen);
    EXPECT_FALSE(viewer_->demand().colourOverDepth);

    const auto toggle = locate(kControlsTitle, "Colour overlay", 1.0f, 8.0f);
    ASSERT_TRUE(toggle.has_value()) << "the checkbox is in the View group, reachable without scrolling";
    clickAt(*toggle);
    ASSERT_TRUE(viewer_->settings().depthView.colourOverlay);
    gui_.io().MousePos = {0.0f, 0.0f};
    ASSERT_TRUE(frameUntil([&] { return viewer_->shown()->colourOverDepth != nullptr; }));
    frame(0.0);
    EXPECT_TRUE(viewer_->demand().colourOverDepth);
    EXPECT_NE(screenPixel(*seen), seenBefore) << "the colour is laid over the depth";
    EXPECT_EQ(screenPixel(*unseen), unseenBefore) << "no colour where the colour camera sees nothing";

    clickAt(*toggle);
    gui_.io().MousePos = {0.0f, 0.0f};
    frame(0.0);
    EXPECT_FALSE(viewer_->demand().colourOverDepth) << "nothing made for an overlay that is off";
    EXPECT_EQ(screenPixel(*seen), seenBefore) << "off again: the plain depth panel";
}

// The camera panel's "Depth over camera" of a two-sensor frame: the depth aligned to the colour image in
// the depth panel's colours and range, transparent exactly where no depth sample covers a colour pixel.
TEST_F(InstrumentTest, DepthOverCameraOfATwoSensorFrameIsTheAlignedDepthInTheDepthPanelsColours) {
    ASSERT_NO_FATAL_FAILURE(startSmallRig());
    viewer_->settings().camera.depthOverlay = true;
    ASSERT_TRUE(frameUntil([&] { return viewer_->shown()->depthOverCamera != nullptr; }));
    frame(0.0);
    const frame::Plane<float>& aligned = shown().depthOverCamera->depthMeters;
    const auto& target = renderer_.depthOverCameraTarget();
    ASSERT_EQ(target.width(), aligned.width);
    ASSERT_EQ(target.height(), aligned.height);
    ASSERT_NE(aligned.width, shown().depth.width()) << "the colour image's geometry, not the depth map's";
    const DepthLegend legend = viewer_->depthLegend();
    const auto rgba = target.readRgba();
    std::size_t holes = 0;
    for (int v = 0; v < aligned.height; ++v) {
        for (int u = 0; u < aligned.width; ++u) {
            const float d = aligned.at(u, v);
            const std::size_t i = (static_cast<std::size_t>(v) * aligned.width + u) * 4;
            if (!(d > 0.0f)) {
                ++holes;
                ASSERT_EQ(rgba[i + 3], 0) << "a hole at " << u << ", " << v << " is transparent";
                continue;
            }
            ASSERT_EQ(rgba[i + 3], 255) << "at " << u << ", " << v;
            const auto expected = render::colormapColor(
                legend.colormap, (d - legend.minMeters) / (legend.maxMeters - legend.minMeters));
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(rgba[i + c], expected[static_cast<std::size_t>(c)] * 255.0f, 2.0f)
                    << "at " << u << ", " << v << " channel " << c;
        }
    }
    EXPECT_GT(holes, 0u) << "the depth sensor's shadows leave colour pixels without depth";

    // The camera panel lays this image over the camera's, not the depth panel's image.
    auto drawsTexture = [&](unsigned texture) {
        const ImDrawList* list = ImGui::FindWindowByName(kCameraTitle)->DrawList;
        return std::any_of(list->CmdBuffer.begin(), list->CmdBuffer.end(), [&](const ImDrawCmd& cmd) {
            return cmd.TextureId == reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(texture));
        });
    };
    EXPECT_TRUE(drawsTexture(target.colorTexture()));
    EXPECT_FALSE(drawsTexture(renderer_.depthTarget().colorTexture()));
}

TEST_F(InstrumentTest, ConfidenceAndCameraPanelsReadOutTheSameSample) {
    for (const char* title : {kConfidenceTitle, kCameraTitle}) {
        const auto at = mouseOverDepthPixel(title, 100, 170, 1);
        ASSERT_TRUE(at.has_value()) << title;
        const Probe p = *viewer_->hoverProbe();
        EXPECT_FLOAT_EQ(p.depthMeters, shown().depth.data->depthMeters.at(p.u, p.v)) << title;
    }
}

TEST_F(InstrumentTest, AnchorsOnTheDeskLandOnTheAnalyticPointsAndMeasureTheirDistance) {
    const frame::Intrinsics k = shown().depth.intrinsics;
    const int pixels[2][2] = {{110, 178}, {150, 186}};
    for (const auto& px : pixels)
        clickAt(screenOfCloudSample(px[0], px[1]));
    ASSERT_EQ(viewer_->anchors().size(), 2u);
    const auto inCamera = viewer_->anchors().inCameraFrame(shown().frame->pose);
    for (std::size_t i = 0; i < 2; ++i) {
        const glm::dvec3 truth = analyticDeskPoint(k, pixels[i][0], pixels[i][1]);
        const glm::dvec3 anchor(inCamera[i]);
        EXPECT_LT(glm::length(anchor - truth), 1e-3 * truth.z) << "anchor " << i << " within 1 mm per meter";
    }
    const double truthDistance = glm::length(analyticDeskPoint(k, 110, 178) - analyticDeskPoint(k, 150, 186));
    EXPECT_NEAR(viewer_->anchors().segmentMeters(0), truthDistance, 1e-3);

    // Rotating the view keeps the anchors where they are in the world.
    viewer_->settings().cloud.orbit.yawRadians = 0.6f;
    frame(0.0);
    EXPECT_NEAR(viewer_->anchors().segmentMeters(0), truthDistance, 1e-3);
    clickAt(screenOfCloudSample(130, 170));
    ASSERT_EQ(viewer_->anchors().size(), 3u);
    EXPECT_GT(viewer_->anchors().areaSquareMeters(), 1e-4) << "three anchors span an area";
    pressKey('Z', 0.0);
    EXPECT_EQ(viewer_->anchors().size(), 2u) << "Z undoes the last anchor";
}

TEST_F(InstrumentTest, EitherCloudPathAndAnyDecimationKeepAnchorsOnTheAnalyticPoints) {
    const frame::Intrinsics k = shown().depth.intrinsics;
    const std::pair<CloudPathChoice, const char*> paths[] = {{CloudPathChoice::Points, "GL points"},
                                                             {CloudPathChoice::Splat, "CPU splat"}};
    double time = 0.0;
    int u = 90;
    for (const auto& [path, name] : paths)
        for (const int decimation : {1, 3}) {
            time += 1.0;
            u += 12; // a new place each time: two clicks on one place would make a double-click
            viewer_->settings().cloud.path = path;
            viewer_->settings().cloud.decimation = decimation;
            while (!viewer_->anchors().empty())
                pressKey('Z', time);
            frame(time);
            EXPECT_EQ(viewer_->cloudPathText().rfind(name, 0), 0u) << viewer_->cloudPathText();
            EXPECT_EQ(shown().cloud.factor, decimation);
            EXPECT_EQ(renderer_.cloudPath() == render::CloudPath::Splat, path == CloudPathChoice::Splat);
            ASSERT_EQ(viewer_->anchors().size(), 0u);
            click(screenOfCloudSample(u, 178), time);
            ASSERT_EQ(viewer_->anchors().size(), 1u) << name << " " << decimation;
            const glm::dvec3 anchor(viewer_->anchors().inCameraFrame(shown().frame->pose)[0]);
            const glm::dvec3 truth = analyticDeskPoint(k, u, 178);
            EXPECT_LT(glm::length(anchor - truth), 1e-3 * truth.z) << name << " " << decimation;
        }
}

TEST_F(InstrumentTest, ThreeAnchorsCloseAPolygonWithLabelsThatDoNotOverlap) {
    // Close together on the desk, so the labels at the edges' midpoints would collide where they are.
    const int pixels[3][2] = {{122, 180}, {134, 180}, {128, 186}};
    std::vector<ImVec2> screen;
    for (const auto& px : pixels) {
        screen.push_back(screenOfCloudSample(px[0], px[1]));
        clickAt(screen.back());
    }
    ASSERT_EQ(viewer_->anchors().size(), 3u);
    gui_.io().MousePos = {0.0f, 0.0f};
    frame(0.0);
    const std::vector<LabelBox>& labels = viewer_->measurementLabels();
    ASSERT_EQ(labels.size(), 4u) << "three edges, the closing one included, and the area";
    for (std::size_t i = 0; i < 3; ++i) {
        const ImVec2 a = screen[i], b = screen[(i + 1) % 3];
        EXPECT_NEAR(labels[i].anchor.x, (a.x + b.x) * 0.5f, 1.5f) << "edge " << i << " at its midpoint";
        EXPECT_NEAR(labels[i].anchor.y, (a.y + b.y) * 0.5f, 1.5f) << "edge " << i;
    }
    EXPECT_NEAR(labels[3].anchor.x, (screen[0].x + screen[1].x + screen[2].x) / 3.0f, 1.5f) << "the centroid";
    EXPECT_NEAR(labels[3].anchor.y, (screen[0].y + screen[1].y + screen[2].y) / 3.0f, 1.5f);
    for (std::size_t i = 0; i < labels.size(); ++i) {
        for (std::size_t j = i + 1; j < labels.size(); ++j) {
            const bool apart = labels[i].max.x <= labels[j].min.x || labels[j].max.x <= labels[i].min.x ||
                               labels[i].max.y <= labels[j].min.y || labels[j].max.y <= labels[i].min.y;
            EXPECT_TRUE(apart) << "labels " << i << " and " << j << " overlap";
        }
    }
    EXPECT_GT(viewer_->anchors().closingMeters(), 0.0);
}

TEST_F(InstrumentTest, AClickWhereTheMouseJumpedWithinTheFrameDropsAnAnchorAndDoesNotOrbit) {
    gui_.io().MousePos = centreOf(kControlsTitle); // the mouse comes from another panel...
    frame(0.0);
    gui_.io().MousePos = screenOfCloudSample(128, 170); // ...and is pressed in the same frame it arrives
    gui_.io().MouseDown[0] = true;
    frame(0.0);
    gui_.io().MouseDown[0] = false;
    frame(0.0);
    EXPECT_EQ(viewer_->anchors().size(), 1u);
    EXPECT_EQ(viewer_->settings().cloud.orbit.yawRadians, 0.0f);
    EXPECT_EQ(viewer_->settings().cloud.orbit.pitchRadians, 0.0f);
}

// Stats, log, fog, aura and infrared float over the cloud: opaque, so no point shows through them.
TEST_F(InstrumentTest, PanelsOverTheCloudAreOpaque) {
    frame(0.0);
    EXPECT_EQ(ImGui::GetStyle().Colors[ImGuiCol_WindowBg].w, 1.0f);
}

TEST_F(InstrumentTest, AnchorsAreDrawnAsCubesInTheCloud) {
    viewer_->settings().cloud.pointSizePixels = 1.0f;
    frame(0.0);
    const auto without = renderer_.cloudTarget().readRgba();
    clickAt(screenOfCloudSample(128, 150));
    ASSERT_EQ(viewer_->anchors().size(), 1u);
    viewer_->update(0.0);
    const auto with = renderer_.cloudTarget().readRgba();
    std::size_t yellowish = 0;
    for (std::size_t i = 0; i < with.size(); i += 4)
        yellowish += with[i] != without[i] && with[i] > 80 && with[i + 1] > 60 && with[i + 2] < with[i] / 2;
    EXPECT_GT(yellowish, 20u) << "a lit cube covers some pixels";
}

TEST_F(InstrumentTest, ClickingAPanelOpensItLargeAndClickingAgainBringsItBack) {
    ImGuiWindow* w = ImGui::FindWindowByName(kDepthTitle);
    ASSERT_NE(w, nullptr);
    const ImVec2 size = w->Size;
    clickAt(centreOf(kDepthTitle));
    EXPECT_EQ(viewer_->zoomedPanel(), kDepthTitle);
    frame(0.0);
    EXPECT_GT(ImGui::FindWindowByName(kDepthTitle)->Size.x, size.x * 2.0f);
    clickAt(centreOf(kDepthTitle));
    EXPECT_TRUE(viewer_->zoomedPanel().empty());
    frame(0.0);
    EXPECT_FLOAT_EQ(ImGui::FindWindowByName(kDepthTitle)->Size.x, size.x);

    const auto zoom = locate(kCloudTitle, "Zoom", 1.0f);
    ASSERT_TRUE(zoom.has_value()) << "the cloud has a zoom button, as clicks on it place anchors";
    clickAt(*zoom);
    EXPECT_EQ(viewer_->zoomedPanel(), kCloudTitle);
    EXPECT_EQ(viewer_->anchors().size(), 0u);
    pressKey(ImGui::GetKeyIndex(ImGuiKey_Escape), 0.0);
    EXPECT_TRUE(viewer_->zoomedPanel().empty());
}

TEST_F(InstrumentTest, ColormapAndAutomaticRangeReachTheDepthPanel) {
    ASSERT_TRUE(viewer_->settings().depthRange.automatic) << "the default";
    viewer_->settings().depthRange.colormap = render::Colormap::Viridis;
    frame(0.0);
    const DepthLegend legend = viewer_->depthLegend();
    EXPECT_TRUE(legend.automatic);
    EXPECT_EQ(legend.colormap, render::Colormap::Viridis);
    EXPECT_GT(legend.minMeters, 0.2f) << "the nearest desk is farther than 20 cm";
    EXPECT_LT(legend.maxMeters, 5.0f);
    const auto& target = renderer_.depthTarget();
    const auto rgba = target.readRgba();
    const int u = 128, v = 180;
    const float d = shown().depth.data->depthMeters.at(u, v);
    const auto expected = render::colormapColor(
        render::Colormap::Viridis, (d - legend.minMeters) / (legend.maxMeters - legend.minMeters));
    const std::size_t i = (static_cast<std::size_t>(v) * target.width() + u) * 4;
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(rgba[i + c], expected[c] * 255.0f, 2.0f) << "channel " << c;
}

TEST_F(InstrumentTest, DepthOverlayAndFillChangeTheCameraPanel) {
    const ImVec2 c = centreOf(kCameraTitle);
    auto pixelAt = [&](ImVec2 at) {
        const auto rgba = gui_.target().readRgba();
        const int x = static_cast<int>(at.x), y = static_cast<int>(at.y);
        const std::size_t i = (static_cast<std::size_t>(y) * gui_.target().width() + x) * 4;
        return std::array<int, 3>{rgba[i], rgba[i + 1], rgba[i + 2]};
    };
    gui_.io().MousePos = {0.0f, 0.0f};
    frame(0.0);
    const auto plain = pixelAt(c);
    ASSERT_NO_FATAL_FAILURE(openControlsGroup("Camera panel"));
    const auto overlay = locate(kControlsTitle, "Depth over camera");
    ASSERT_TRUE(overlay.has_value());
    clickAt(*overlay);
    ASSERT_TRUE(viewer_->settings().camera.depthOverlay);
    gui_.io().MousePos = {0.0f, 0.0f};
    frame(0.0);
    EXPECT_NE(pixelAt(c), plain) << "the depth colours tint the camera image";
    const auto fill = locate(kControlsTitle, "Fill camera panel");
    ASSERT_TRUE(fill.has_value());
    clickAt(*fill);
    EXPECT_TRUE(viewer_->settings().camera.fill);
}

TEST_F(InstrumentTest, StatsLogAndToastsShowWhatHappened) {
    pressKey('S', 0.0);
    pressKey('L', 0.0);
    ASSERT_TRUE(viewer_->settings().panels.stats);
    ASSERT_TRUE(viewer_->settings().panels.log);
    logError("disk full while writing /tmp/x.dcrec");
    for (int i = 0; i < 20; ++i)
        nextFrame(i / 60.0);
    EXPECT_NE(ImGui::FindWindowByName(kStatsTitle), nullptr);
    EXPECT_NE(ImGui::FindWindowByName(kLogTitle), nullptr);
    const StatsView stats = viewer_->statsView();
    EXPECT_GT(stats.residentMebibytes, 10.0);
    ASSERT_TRUE(stats.latencyMs.has_value()) << "synthetic frames carry the monotonic clock";
    bool cloudPlotted = false;
    for (const StageHistory& s : stats.stages)
        cloudPlotted |= s.name == "cloud" && s.history.size() >= 10;
    EXPECT_TRUE(cloudPlotted);
    bool logged = false;
    for (const LogEntry& e : viewer_->log().snapshot())
        logged |= e.level == LogLevel::Error && e.message.find("disk full") != std::string::npos;
    EXPECT_TRUE(logged);
    bool toast = false;
    for (ImGuiWindow* w : ImGui::GetCurrentContext()->Windows)
        toast |= std::string(w->Name).rfind("##toast", 0) == 0 && w->Active;
    EXPECT_TRUE(toast) << "an error shows as a toast";
}

TEST_F(InstrumentTest, AccumulateGathersWorldPointsWithinTheBudget) {
    devices::SyntheticConfig moving = smallScene();
    moving.motion = true;
    ASSERT_NO_FATAL_FAILURE(startViewer(moving));
    viewer_->settings().cloud.motion.enabled = false;
    const auto box = locate(kControlsTitle, "Accumulate");
    ASSERT_TRUE(box.has_value());
    clickAt(*box);
    ASSERT_TRUE(viewer_->settings().accumulate.enabled);
    viewer_->settings().accumulate.budgetThousands = 300;
    const std::size_t onePose = shown().pointCount;
    for (int i = 0; i < 12; ++i)
        nextFrame(0.1 * i);
    ASSERT_TRUE(viewer_->accumulating());
    processing::AccumulationWorker& worker = instrument_->accumulation();
    worker.waitIdle();
    const std::size_t gathered = worker.size();
    EXPECT_GT(gathered, onePose) << "frames from other poses add points";
    EXPECT_LE(gathered, 300'000u);
    EXPECT_EQ(viewer_->statusLine().pointsDrawn, gathered);
    viewer_->settings().accumulate.budgetThousands = 10;
    nextFrame(2.0);
    worker.waitIdle();
    EXPECT_EQ(worker.size(), 10'000u) << "a smaller budget keeps only the newest points";
    frame(2.0);
    EXPECT_GT(litPixels(renderer_.cloudTarget().readRgba()), 1000u);
}

TEST_F(InstrumentTest, TheSourcePickerSwitchesSourcesAndRefusesBadOnes) {
    pressKey('O', 0.0);
    ASSERT_TRUE(viewer_->settings().panels.source);
    frame(0.0);
    const auto entry = locate(kSourceTitle, "Synthetic desk, 640x480 @ 30 Hz", 1.0f);
    ASSERT_TRUE(entry.has_value());
    click(*entry, 0.0);
    for (int i = 0; i < 20 && viewer_->summary().depthWidth != 640; ++i)
        nextFrame(0.0);
    EXPECT_EQ(viewer_->summary().depthWidth, 640);
    EXPECT_EQ(viewer_->settings().recentSources.front(), "synthetic:640x480@30");
    EXPECT_FALSE(viewer_->openSource("synthetic:12x").ok());
    nextFrame(0.0);
    EXPECT_EQ(viewer_->summary().depthWidth, 640) << "a bad spec leaves the current source running";
    EXPECT_TRUE(instrument_->status().running);
}

// Two snapshots of one frame (a paused replay, or P pressed twice) are two snapshots, and each says where
// it went, on screen.
TEST_F(InstrumentTest, TwoSnapshotsOfOneFrameGoToTwoFoldersAndEachSaysWhere) {
    const std::filesystem::path parent =
        std::filesystem::temp_directory_path() / ("dc-snapshot2-" + std::to_string(::getpid()));
    const auto first = viewer_->saveSnapshot(parent.string());
    const auto second = viewer_->saveSnapshot(parent.string());
    ASSERT_TRUE(first.ok() && second.ok());
    EXPECT_NE(*first, *second);
    for (const auto& dir : {*first, *second})
        EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(dir) / "cloud.ply")) << dir;
    frame(0.0);
    std::size_t said = 0;
    for (const LogEntry& e : viewer_->log().snapshot()) {
        if (e.level != LogLevel::Notice || e.message.find(parent.string()) == std::string::npos)
            continue;
        ++said;
        const ImGuiWindow* toast = ImGui::FindWindowByName((kToastPrefix + std::to_string(e.id)).c_str());
        EXPECT_TRUE(toast && toast->Active) << e.message << " is shown as a toast";
    }
    EXPECT_EQ(said, 2u);
    std::filesystem::remove_all(parent);
}

// A snapshot that cannot be written says so and why, in the log and on screen: a press of P that writes
// nothing and says nothing reads as a snapshot taken.
TEST_F(InstrumentTest, AFailedSnapshotSaysWhyOnScreen) {
    const std::filesystem::path file =
        std::filesystem::temp_directory_path() / ("dc-snapshot-file-" + std::to_string(::getpid()));
    std::ofstream(file) << "a file where the snapshots' folder would go";
    const auto dir = viewer_->saveSnapshot((file / "snapshots").string());
    std::filesystem::remove(file);
    ASSERT_FALSE(dir.ok());
    frame(0.0);
    std::size_t said = 0;
    for (const LogEntry& e : viewer_->log().snapshot()) {
        if (e.level != LogLevel::Error || e.message.find("snapshot not saved") == std::string::npos)
            continue;
        ++said;
        EXPECT_NE(e.message.find(dir.error().message), std::string::npos) << e.message << " says why";
        const ImGuiWindow* toast = ImGui::FindWindowByName((kToastPrefix + std::to_string(e.id)).c_str());
        EXPECT_TRUE(toast && toast->Active) << e.message << " is shown as a toast";
    }
    EXPECT_EQ(said, 1u);
}

TEST_F(InstrumentTest, SnapshotWritesEveryPanelAndThePointCloud) {
    const std::filesystem::path parent =
        std::filesystem::temp_directory_path() / ("dc-snapshot-" + std::to_string(::getpid()));
    const auto dir = viewer_->saveSnapshot(parent.string());
    ASSERT_TRUE(dir.ok()) << dir.error().message;
    for (const char* name : {"cloud.png", "depth.png", "confidence.png", "camera.png", "cloud.ply"})
        EXPECT_GT(std::filesystem::file_size(std::filesystem::path(*dir) / name), 100u) << name;
    // The camera's image at the resolution it was captured at, not at the panel's size.
    std::ifstream png(std::filesystem::path(*dir) / "camera.png", std::ios::binary);
    unsigned char ihdr[24] = {};
    ASSERT_TRUE(png.read(reinterpret_cast<char*>(ihdr), sizeof ihdr));
    const auto bigEndian = [&](int at) {
        return (ihdr[at] << 24) | (ihdr[at + 1] << 16) | (ihdr[at + 2] << 8) | ihdr[at + 3];
    };
    EXPECT_EQ(bigEndian(16), shown().frame->capturedImage.width) << "IHDR width";
    EXPECT_EQ(bigEndian(20), shown().frame->capturedImage.height) << "IHDR height";
    std::ifstream ply(std::filesystem::path(*dir) / "cloud.ply", std::ios::binary);
    std::string header((std::istreambuf_iterator<char>(ply)), {});
    const auto points = processing::buildPointCloud(*shown().frame, frame::Confidence::Low,
                                                    viewer_->settings().cloud.nearMeters);
    EXPECT_NE(header.find("element vertex " + std::to_string(points.size())), std::string::npos);
    std::filesystem::remove_all(parent);
}

TEST_F(InstrumentTest, RecordButtonNumbersTakesKeepsItsPlaceAndRecordsAsChosen) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("dc-takes-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    viewer_->settings().record = {dir.string(), true, 55};
    frame(0.0);
    openControlsGroup("Record");
    const auto record = locate(kControlsTitle, kRecordButtonId);
    ASSERT_TRUE(record);
    const auto takeFrames = [&](double t) {
        const auto button =
            locate(kControlsTitle, kRecordButtonId); // where it is now, the group may have grown
        ASSERT_TRUE(button);
        click(*button, t);
        for (int i = 0; i < 200 && instrument_->recording().frames < 3; ++i)
            nextFrame(t);
    };
    takeFrames(0.1);
    engine::RecordingStatus take = instrument_->recording();
    ASSERT_TRUE(take.recording);
    EXPECT_EQ(take.path, (dir / "depthcloud-recording-001.dcrec").string());
    EXPECT_EQ(take.options.color, devices::recording::ColorStorage::Jpeg);
    EXPECT_EQ(take.options.jpegQuality, 55);
    const auto stop = locate(kControlsTitle, kRecordButtonId);
    ASSERT_TRUE(stop);
    EXPECT_EQ(stop->x, record->x) << "Stop is where Record was";
    EXPECT_EQ(stop->y, record->y);
    click(*record, 0.2);
    EXPECT_FALSE(instrument_->recording().recording);
    EXPECT_TRUE(std::filesystem::exists(dir / "depthcloud-recording-001.dcrec"));

    viewer_->settings().record.jpegColor = false;
    takeFrames(1.3); // a second apart: two clicks on the button within ImGui's double-click time are one
    take = instrument_->recording();
    EXPECT_EQ(take.path, (dir / "depthcloud-recording-002.dcrec").string());
    EXPECT_EQ(take.options.color, devices::recording::ColorStorage::AsCaptured);
    click(*locate(kControlsTitle, kRecordButtonId), 1.4);
    EXPECT_TRUE(std::filesystem::exists(dir / "depthcloud-recording-002.dcrec"));
    std::filesystem::remove_all(dir);
}

class InstrumentNoPose : public UiTest {
protected:
    void SetUp() override { ASSERT_NO_FATAL_FAILURE(initGl()); }
};

TEST_F(InstrumentNoPose, AccumulateIsDisabledWithoutPoses) {
    frame::Frame f;
    const devices::SyntheticScene scene;
    f.cameraIntrinsics = devices::SyntheticScene::cameraIntrinsics(64, 48);
    f.sceneDepth = scene.sensorDepth(f.cameraIntrinsics, devices::SyntheticScene::cameraPose(0.0, false), 1);
    Settings settings;
    settings.accumulate.enabled = true;
    start(std::make_unique<devices::FrameListDevice>(
              std::vector<frame::FramePtr>{std::make_shared<const frame::Frame>(f)}, 60.0),
          "frames", settings);
    for (int i = 0; i < 5; ++i)
        nextFrame(i / 60.0);
    EXPECT_FALSE(viewer_->accumulating());
    instrument_->accumulation().waitIdle();
    EXPECT_EQ(instrument_->accumulation().size(), 0u);
}

} // namespace
} // namespace dc::ui::test
