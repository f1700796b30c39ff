// Several sources in the window: companion replays follow the main replay's timeline by their stamps, and
// the Sources panel's buttons refine a companion's placement by ICP and remove it.

#include "devices/source_pose.h"
#include "processing/rigid_alignment.h"
#include "sources_fixture.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace dc::ui::test {
namespace {

namespace fs = std::filesystem;

// 3 degrees about the skew axis (1, 2, -1) and (2, -2, 1) cm: a wrong placement.
const std::string kError =
    "0.02,-0.02,0.01,0.010686694396250128,0.021373388792500257,-0.010686694396250128,0.9996573249755573";

class SourcesPanelTest : public SourcesTest {
protected:
    std::optional<std::size_t> companionIndex() {
        const auto& shown = viewer_->companions()[0].presenter().shown();
        if (!shown || !shown->frame->replay)
            return std::nullopt;
        return shown->frame->replay->index;
    }
    std::optional<std::size_t> mainIndex() {
        const auto& shown = viewer_->shown();
        if (!shown || !shown->frame->replay)
            return std::nullopt;
        return shown->frame->replay->index;
    }
};

TEST_F(SourcesPanelTest, ReplaysWithOffsetClocksStepTogetherByStamp) {
    const OffsetPair pair = recordOffsetPair();
    ASSERT_FALSE(HasFailure());
    const std::string& a = pair.a;
    const std::string& b = pair.b;
    const std::vector<std::int64_t>& stampsA = pair.stampsA;
    const std::vector<std::int64_t>& stampsB = pair.stampsB;
    ASSERT_TRUE(viewer_->openSource("replay:" + a + ":paused").ok());
    ASSERT_TRUE(viewer_->addSource("replay:" + b + ":paused").ok());
    for (const std::size_t target : {std::size_t{13}, std::size_t{2}, std::size_t{19}, std::size_t{7}}) {
        instrument_->seekReplay(target);
        const std::size_t want = nearest(stampsB, stampsB.front() + (stampsA[target] - stampsA.front()));
        EXPECT_TRUE(frameUntil([&] { return mainIndex() == target && companionIndex() == want; }))
            << "main at " << target << " shows " << mainIndex().value_or(999) << ", companion shows "
            << companionIndex().value_or(999) << ", nearest " << want;
    }
    instrument_->stepReplay(1);
    const std::size_t want = nearest(stampsB, stampsB.front() + (stampsA[8] - stampsA.front()));
    EXPECT_TRUE(frameUntil([&] { return mainIndex() == 8u && companionIndex() == want; }));
    EXPECT_FALSE(viewer_->companions()[0].instrument().replay()->status().playing);
    instrument_->replay()->play();
    EXPECT_TRUE(frameUntil([&] { return viewer_->companions()[0].instrument().replay()->status().playing; }))
        << "the companion plays when the main replay does";
}

TEST_F(SourcesPanelTest, RefineMovesAMisplacedCompanionBackAndRemoveTakesItAway) {
    // Companion B views the desk from 20 cm to the right; its pose= is 3 degrees and 3 cm wrong.
    ASSERT_TRUE(viewer_->openSource("synthetic:320x240").ok());
    ASSERT_TRUE(viewer_
                    ->addSource("synthetic:320x240:view=0.2,0,0,0,-0.0697564737441253,0,0.9975640502598242:"
                                "pose=" +
                                kError)
                    .ok());
    viewer_->settings().panels.sources = true;
    ASSERT_TRUE(frameUntil([&] { return viewer_->shown() && viewer_->companions()[0].presenter().shown(); }));
    const auto before = viewer_->companions().overlap(0, viewer_->shown());
    ASSERT_TRUE(before.has_value());
    // The panel's buttons are driven through the actions they return: finding them by hovering every
    // position of a panel this tall takes minutes under the sanitizers.
    SourcesActions refine;
    refine.refine = 0;
    viewer_->applySourcesActions(refine);
    // The correction undoes the pose's error: B is back where its view put it, within 0.2 deg and 2 mm.
    const auto error = devices::parsePoseValue(kError);
    ASSERT_TRUE(error.ok());
    const frame::RigidTransform left = frame::compose(viewer_->companions()[0].look.correction, *error);
    EXPECT_LT(processing::rotationDegrees(left), 0.2);
    const auto& t = left.translationMeters;
    EXPECT_LT(1000.0 * std::hypot(t[0], t[1], t[2]), 2.0);
    ASSERT_TRUE(frameUntil([&] {
        const auto after = viewer_->companions().overlap(0, viewer_->shown());
        return after && after->medianMm < 0.6 * before->medianMm;
    }));
    // Saved, B's placement reads back as where ICP put it: its pose= error undone.
    const fs::path cwd = fs::current_path();
    fs::current_path(dir_);
    SourcesActions save;
    save.savePlacements = true;
    viewer_->applySourcesActions(save);
    fs::current_path(cwd);
    const fs::path saved = dir_ / Viewer::kSnapshotDirectory / "placements";
    ASSERT_TRUE(fs::exists(saved / "rig.yaml"));
    const auto back = devices::parsePoseValue((saved / "rig.yaml").string() + "#camera_1");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_LT(processing::rotationDegrees(*back), 0.2);
    EXPECT_LT(1000.0 * std::hypot(back->translationMeters[0], back->translationMeters[1],
                                  back->translationMeters[2]),
              2.0);
    EXPECT_TRUE(fs::exists(saved / "camchain.yaml")) << "the main source sits at the origin: Kalibr's world";
    // Both files say exactly what the panel placed.
    const frame::RigidTransform placed = frame::compose(viewer_->companions()[0].look.correction, *error);
    const auto kalibr = devices::parsePoseValue((saved / "camchain.yaml").string() + "#cam1");
    ASSERT_TRUE(kalibr.ok()) << kalibr.error().message;
    for (const frame::RigidTransform& read : {*back, *kalibr}) {
        for (int i = 0; i < 9; ++i)
            EXPECT_NEAR(read.rotation[i], placed.rotation[i], 1e-9);
        for (int i = 0; i < 3; ++i)
            EXPECT_NEAR(read.translationMeters[i], placed.translationMeters[i], 1e-9);
    }
    SourcesActions remove;
    remove.remove = 0;
    viewer_->applySourcesActions(remove);
    EXPECT_TRUE(frameUntil([&] { return viewer_->companions().empty(); }));
    EXPECT_FALSE(viewer_->presenter().fusing());
}

// Both cloud paths draw a companion's points among the main source's, placed by its pose: tinted pure
// green, they cover much of the panel; hidden, none of it is green; the main source alone has no such
// colour.
TEST_F(SourcesPanelTest, BothCloudPathsDrawACompanionsPointsInItsTint) {
    Companion* pair = openGreenPair("synthetic:320x240");
    ASSERT_NE(pair, nullptr);
    Companion& b = *pair;
    for (const CloudPathChoice path : {CloudPathChoice::Points, CloudPathChoice::Splat}) {
        SCOPED_TRACE(path == CloudPathChoice::Points ? "GL points" : "CPU splat");
        viewer_->settings().cloud.path = path;
        b.look.visible = true;
        ASSERT_TRUE(frameUntil([&] { return b.presenter().shown() && greenPixels() > 20'000; }))
            << greenPixels() << " green pixels";
        b.look.visible = false;
        EXPECT_TRUE(frameUntil([&] { return greenPixels() == 0; }))
            << greenPixels() << " green pixels with the companion hidden";
    }
}

// Two live cameras' frames are never taken at the same instant: their skew is measured frame by frame, and
// a pairing tolerance tighter than it keeps the second camera out of the cloud until it is loosened.
TEST_F(SourcesPanelTest, APairingToleranceDrawsOnlyFramesCloseInTime) {
    Companion* pair = openGreenPair("synthetic:160x120");
    ASSERT_NE(pair, nullptr);
    Companion& b = *pair;
    ASSERT_TRUE(frameUntil([&] { return greenPixels() > 2'000 && b.skew.count() >= 5; })) << greenPixels();
    const auto skew = viewer_->companions().skewMs(0, *instrument_, viewer_->shown());
    ASSERT_TRUE(skew.has_value());
    EXPECT_NE(*skew, 0.0);
    EXPECT_LT(std::abs(b.skew.median()), 1000.0) << "live stamps on one clock";
    viewer_->settings().sources.pairingToleranceMs = 0.001f; // a microsecond: no two frames are that close
    EXPECT_TRUE(frameUntil([&] { return greenPixels() == 0; })) << greenPixels() << " green pixels";
    EXPECT_FALSE(viewer_->companions().paired(0, *instrument_, viewer_->shown(), 0.001f));
    viewer_->settings().sources.pairingToleranceMs = 0.0f; // off
    EXPECT_TRUE(frameUntil([&] { return greenPixels() > 2'000; })) << greenPixels();
}

// Accumulate mode gathers every source into one world cloud: each further source's frames join the main
// source's, placed where the fused cloud places it. A companion 10 m along the world's x axis, far from
// anything the main camera sees, puts points there.
TEST_F(SourcesPanelTest, AccumulateModeGathersEverySourceIntoOneWorld) {
    ASSERT_TRUE(viewer_->openSource("synthetic:160x120:motion").ok());
    viewer_->settings().accumulate.enabled = true;
    const auto pointsBeyond = [&](float x) {
        std::size_t n = 0;
        const bool read = instrument_->accumulation().tryRead([&](processing::PointAccumulator& points) {
            for (std::size_t i = 0; i < points.size(); ++i)
                n += points.slots()[i].x > x ? 1 : 0;
        });
        return read ? std::optional(n) : std::nullopt;
    };
    ASSERT_TRUE(
        frameUntil([&] { return viewer_->accumulating() && instrument_->accumulation().size() > 1000; }));
    instrument_->accumulation().waitIdle();
    EXPECT_EQ(pointsBeyond(5.0f), std::optional<std::size_t>(0)) << "the main source's points are near it";
    ASSERT_TRUE(viewer_->addSource("synthetic:160x120:pose=10,0,0,0,0,0,1").ok());
    EXPECT_TRUE(frameUntil([&] { return pointsBeyond(5.0f).value_or(0) > 5'000; }))
        << pointsBeyond(5.0f).value_or(0) << " points 5 m or more along x";
    EXPECT_TRUE(viewer_->accumulating());
    EXPECT_TRUE(viewer_->demand().accumulate);
    EXPECT_EQ(viewer_->presenter().pointsShown(), instrument_->accumulation().size());
}

// "Own processing" on: a companion keeps its own processing and cloud confidence whatever the main source's
// become; its depth is what its own processing made, and both cloud paths draw it from its own level.
TEST_F(SourcesPanelTest, OwnProcessingKeepsACompanionsSettingsWhateverTheMainSourcesBecome) {
    Companion* pair = openGreenPair("synthetic:320x240");
    ASSERT_NE(pair, nullptr);
    Companion& b = *pair;
    const auto depthWidth = [](const processing::ShownFramePtr& s) {
        return s && s->depth.data ? s->depth.data->depthMeters.width : 0;
    };
    // Following: the main source's processing reaches it.
    viewer_->settings().processing.upsampling = true;
    ASSERT_TRUE(frameUntil([&] { return depthWidth(b.presenter().shown()) > 320; }));
    viewer_->settings().processing.upsampling = false;
    ASSERT_TRUE(frameUntil([&] { return depthWidth(b.presenter().shown()) == 320; }));
    // Its own (what the checkbox does), upsampled: the main source's stays the sensor's.
    b.own.followsMain = false;
    b.own.processing.upsampling = true;
    ASSERT_TRUE(frameUntil([&] { return depthWidth(b.presenter().shown()) > 320; }));
    EXPECT_EQ(depthWidth(viewer_->shown()), 320);
    viewer_->settings().processing.smoothing = !b.own.processing.smoothing;
    frame(0.0);
    EXPECT_EQ(b.presenter().settings().processing, b.own.processing)
        << "the main source's change stays its own";
    b.own.processing.upsampling = false;
    for (const CloudPathChoice path : {CloudPathChoice::Points, CloudPathChoice::Splat}) {
        SCOPED_TRACE(path == CloudPathChoice::Points ? "GL points" : "CPU splat");
        viewer_->settings().cloud.path = path;
        b.own.minConfidence = frame::Confidence::Low;
        ASSERT_TRUE(frameUntil([&] {
            return depthWidth(b.presenter().shown()) == 320 && greenPixels() > 20'000;
        })) << greenPixels();
        const std::size_t all = greenPixels();
        b.own.minConfidence = frame::Confidence::High;
        EXPECT_TRUE(frameUntil([&] { return greenPixels() < all / 2; })) << greenPixels() << " of " << all;
        // The main source's level is not the companion's.
        viewer_->settings().cloud.minConfidence = frame::Confidence::High;
        b.own.minConfidence = frame::Confidence::Low;
        EXPECT_TRUE(frameUntil([&] { return greenPixels() > all * 9 / 10; }))
            << greenPixels() << " of " << all;
        viewer_->settings().cloud.minConfidence = frame::Confidence::Low;
    }
}

// With several sources the image panels show the source picked over them: the hover readout over the depth
// panel's middle reads the picked source's depth map (a 160x120 companion beside a 320x240 main source),
// and it goes back to the main source's when the companion is removed.
TEST_F(SourcesPanelTest, TheImagePanelsShowTheSourcePickedOverThem) {
    ASSERT_TRUE(viewer_->openSource("synthetic:320x240").ok());
    const auto probeAtPanelMiddle = [&]() -> std::optional<Probe> {
        ImGuiWindow* w = ImGui::FindWindowByName(kDepthTitle);
        if (!w)
            return std::nullopt;
        // Below the middle: clear of the row of names at the top.
        gui_.io().MousePos = ImVec2(w->Pos.x + w->Size.x * 0.5f, w->Pos.y + w->Size.y * 0.55f);
        frame(0.0);
        frame(0.0);
        return viewer_->hoverProbe();
    };
    ASSERT_TRUE(frameUntil([&] { return viewer_->shown() != nullptr; }));
    const auto alone = probeAtPanelMiddle();
    ASSERT_TRUE(alone.has_value());
    EXPECT_NEAR(alone->u, 160, 40);
    ASSERT_TRUE(viewer_->addSource("synthetic:160x120:" + kBesideView).ok());
    ASSERT_TRUE(frameUntil([&] { return viewer_->companions()[0].presenter().shown() != nullptr; }));
    const auto main = probeAtPanelMiddle();
    ASSERT_TRUE(main.has_value());
    EXPECT_NEAR(main->u, 160, 40) << "the main source's, until another is picked";
    viewer_->panelSource() = 1; // what clicking "Source 2" over the images does
    ASSERT_TRUE(frameUntil([&] {
        const auto p = probeAtPanelMiddle();
        return p && std::abs(p->u - 80) < 20;
    })) << "the companion's 160x120 depth under the readout";
    EXPECT_EQ(viewer_->hoverProbe()->frameSequence,
              std::optional(viewer_->companions()[0].presenter().shown()->frame->sequence));
    // The companion removed, the panels go back to the main source.
    viewer_->companions().remove(0);
    const auto back = probeAtPanelMiddle();
    ASSERT_TRUE(back.has_value());
    EXPECT_NEAR(back->u, 160, 40);
    EXPECT_EQ(viewer_->panelSource(), 0u);
}

} // namespace
} // namespace dc::ui::test
