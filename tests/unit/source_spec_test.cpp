#include "devices/source_spec.h"
#include "devices/synthetic/synthetic_device.h"
#include "devices/uvc/live_source_spec.h"

#include <gtest/gtest.h>

#include <fstream>
#include <utility>

namespace dc::devices {
namespace {

const SyntheticConfig& configOf(const std::unique_ptr<Device>& d) {
    return dynamic_cast<const SyntheticDevice&>(*d).config();
}

TEST(SourceSpec, SyntheticDefaultsToLidarLikeDepth) {
    auto d = openSourceSpec("synthetic");
    ASSERT_TRUE(d.ok());
    EXPECT_EQ(configOf(*d).depthWidth, 256);
    EXPECT_EQ(configOf(*d).depthHeight, 192);
    EXPECT_DOUBLE_EQ(configOf(*d).fps, 60.0);
}

TEST(SourceSpec, SyntheticModeAndOptions) {
    auto d = openSourceSpec("synthetic:640x480@30:motion:exact");
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_EQ(configOf(*d).depthWidth, 640);
    EXPECT_EQ(configOf(*d).depthHeight, 480);
    EXPECT_DOUBLE_EQ(configOf(*d).fps, 30.0);
    EXPECT_TRUE(configOf(*d).motion);
    EXPECT_FALSE(configOf(*d).noise);
    auto sizeOnly = openSourceSpec("synthetic:320x240");
    ASSERT_TRUE(sizeOnly.ok());
    EXPECT_DOUBLE_EQ(configOf(*sizeOnly).fps, 60.0);
}

TEST(SourceSpec, MalformedModesNameTheProblem) {
    for (const char* bad : {"synthetic:640", "synthetic:640x", "synthetic:x480", "synthetic:640x480@",
                            "synthetic:640x480@abc", "synthetic:-5x4", "synthetic:0x480",
                            "synthetic:640x480@0", "synthetic:640x480@-3", "synthetic:64ox480"}) {
        auto d = openSourceSpec(bad);
        ASSERT_FALSE(d.ok()) << bad;
        EXPECT_NE(d.error().message.find("malformed mode"), std::string::npos) << bad;
    }
}

TEST(SourceSpec, APlaneTakesItsDistanceTiltAndNoise) {
    auto d = openSourceSpec("synthetic:640x480:plane=1.5,10,2");
    ASSERT_TRUE(d.ok()) << d.error().message;
    ASSERT_TRUE(configOf(*d).flatTarget.has_value());
    EXPECT_EQ(*configOf(*d).flatTarget, (FlatTarget{1.5, 10.0, 2.0}));
    auto defaultNoise = openSourceSpec("synthetic:plane=0.8,-30");
    ASSERT_TRUE(defaultNoise.ok()) << defaultNoise.error().message;
    EXPECT_EQ(*configOf(*defaultNoise).flatTarget, (FlatTarget{0.8, -30.0, 1.0}));
}

TEST(SourceSpec, ABadPlaneNamesWhatIsWrong) {
    const std::pair<const char*, const char*> cases[] = {
        {"synthetic:plane=", "malformed plane=''"},
        {"synthetic:plane=1.5", "malformed plane='1.5'"},
        {"synthetic:plane=1.5,x", "malformed plane='1.5,x'"},
        {"synthetic:plane=1.5,10,1,4", "malformed plane='1.5,10,1,4'"},
        {"synthetic:plane=0,10", "plane distance must be in (0, 5] m"},
        {"synthetic:plane=6,10", "plane distance must be in (0, 5] m"},
        {"synthetic:plane=1,86", "plane tilt must be within 85 degrees"},
        {"synthetic:plane=1,10,-1", "plane noise must be in [0, 100] mm"}};
    for (const auto& [spec, message] : cases) {
        auto d = openSourceSpec(spec);
        ASSERT_FALSE(d.ok()) << spec;
        EXPECT_NE(d.error().message.find(message), std::string::npos) << spec << ": " << d.error().message;
    }
}

TEST(SourceSpec, UnknownSourceIsRejectedWithTheGrammar) {
    auto d = openSourceSpec("kinect");
    ASSERT_FALSE(d.ok());
    EXPECT_NE(d.error().message.find("unknown source 'kinect'"), std::string::npos);
    EXPECT_NE(d.error().message.find("synthetic[:WxH"), std::string::npos);
}

std::string writePoseFile(const std::string& name, const std::string& text) {
    const std::string path = ::testing::TempDir() + name;
    std::ofstream(path) << text;
    return path;
}

void expectPoseError(const std::string& spec, const std::string& problem) {
    auto placement = sourcePlacement(spec);
    ASSERT_FALSE(placement.ok()) << spec;
    const std::string& message = placement.error().message;
    EXPECT_NE(message.find("pose="), std::string::npos) << spec << ": " << message;
    EXPECT_NE(message.find(problem), std::string::npos) << spec << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << spec << ": " << message;
}

TEST(SourcePose, SevenNumbersGiveTheCameraToWorldTransform) {
    // A quarter turn about z (qz = qw = sqrt(1/2)) at (1, 2, 3) m: the camera's x axis points along world y.
    auto placement = sourcePlacement("synthetic:640x480:pose=1,2,3,0,0,0.70710678,0.70710678:exact");
    ASSERT_TRUE(placement.ok()) << placement.error().message;
    EXPECT_EQ(placement->spec, "synthetic:640x480:exact");
    ASSERT_TRUE(placement->cameraToWorld.has_value());
    const frame::RigidTransform& pose = *placement->cameraToWorld;
    const std::array<double, 9> quarterTurn{0, -1, 0, 1, 0, 0, 0, 0, 1};
    for (int i = 0; i < 9; ++i)
        EXPECT_NEAR(pose.rotation[i], quarterTurn[i], 1e-8) << i;
    EXPECT_EQ(pose.translationMeters, (std::array<double, 3>{1, 2, 3}));
    const auto p = pose.apply({1, 0, 0});
    EXPECT_NEAR(p[0], 1.0, 1e-8);
    EXPECT_NEAR(p[1], 3.0, 1e-8);
    EXPECT_NEAR(p[2], 3.0, 1e-8);
}

TEST(SourcePose, AQuaternionWithinTheToleranceIsNormalised) {
    auto placement = sourcePlacement("synthetic:pose=0,0,0,0,0,0,1.0009");
    ASSERT_TRUE(placement.ok()) << placement.error().message;
    EXPECT_LT(frame::rotationError(placement->cameraToWorld->rotation), 1e-12);
    EXPECT_NEAR(placement->cameraToWorld->rotation[0], 1.0, 1e-12);
}

TEST(SourcePose, TheRestOfTheSpecIsUntouched) {
    const std::pair<const char*, const char*> cases[] = {
        {"replay:/data/a:b.dcrec:pose=0,0,1,0,0,0,1:loop", "replay:/data/a:b.dcrec:loop"},
        {"ros:/cam/depth:pose=0,0,1,0,0,0,1:master=http://robot:11311",
         "ros:/cam/depth:master=http://robot:11311"},
        {"usb:8086:0b07::calib=a.yaml:pose=0,0,1,0,0,0,1", "usb:8086:0b07::calib=a.yaml"},
        {"v4l2:/dev/video2:pose=0,0,1,0,0,0,1", "v4l2:/dev/video2"}};
    for (const auto& [spec, rest] : cases) {
        auto placement = sourcePlacement(spec);
        ASSERT_TRUE(placement.ok()) << spec << ": " << placement.error().message;
        EXPECT_EQ(placement->spec, rest);
        EXPECT_TRUE(placement->cameraToWorld.has_value()) << spec;
    }
}

TEST(SourcePose, ASpecWithoutPoseGivesNone) {
    for (const char* spec : {"synthetic", "synthetic:", "replay:/data/pose=x:loop",
                             "ros:/a:master=http://h:1", "v4l2:/dev/video0::640x480"}) {
        auto placement = sourcePlacement(spec);
        ASSERT_TRUE(placement.ok()) << spec << ": " << placement.error().message;
        EXPECT_EQ(placement->spec, spec);
        EXPECT_FALSE(placement->cameraToWorld.has_value()) << spec;
    }
}

TEST(SourcePose, BadPosesAreOneLineErrorsNamingPose) {
    expectPoseError("synthetic:pose=", "expected X,Y,Z,QX,QY,QZ,QW or a pose file");
    expectPoseError("synthetic:pose=0,0,1,0,0,1", "found 6");
    expectPoseError("synthetic:pose=0,0,1,0,0,0,1,0", "found 8");
    expectPoseError("synthetic:pose=0,0,x,0,0,0,1", "'x' is not a number");
    expectPoseError("synthetic:pose=0,0,1,0,0,,1", "'' is not a number");
    expectPoseError("synthetic:pose=0,0,1,0,0,0,1.01", "norm is 1.01");
    expectPoseError("synthetic:pose=0,0,1,0,0,0,0", "norm is 0");
    expectPoseError("synthetic:pose=0,0,inf,0,0,0,1", "not a finite number");
    expectPoseError("synthetic:pose=/no/such/pose.yaml", "/no/such/pose.yaml");
    expectPoseError("synthetic:pose=0,0,1,0,0,0,1:pose=0,0,2,0,0,0,1", "given twice");
}

TEST(SourcePose, APoseFileHoldsTheSameSevenNumbers) {
    const std::string yaml = writePoseFile("pose.yaml", "pose: [0.5, 0, 1.25, 0, 0, 0, 1]\n");
    const std::string json = writePoseFile("pose.json", "{\"pose\": [0.5, 0, 1.25, 0, 0, 0, 1]}");
    for (const std::string& path : {yaml, json}) {
        auto placement = sourcePlacement("replay:take.dcrec:pose=" + path + ":paused");
        ASSERT_TRUE(placement.ok()) << path << ": " << placement.error().message;
        EXPECT_EQ(placement->spec, "replay:take.dcrec:paused");
        ASSERT_TRUE(placement->cameraToWorld.has_value());
        EXPECT_TRUE(frame::RigidTransform{}.rotation == placement->cameraToWorld->rotation);
        EXPECT_EQ(placement->cameraToWorld->translationMeters, (std::array<double, 3>{0.5, 0, 1.25}));
    }
    expectPoseError("synthetic:pose=" + writePoseFile("short.yaml", "pose: [0, 0, 1, 0, 0, 1]\n"),
                    "pose: expected 7 values, found 6");
    expectPoseError("synthetic:pose=" + writePoseFile("scaled.yaml", "pose: [0, 0, 1, 0, 0, 0, 2]\n"),
                    "norm is 2");
    expectPoseError("synthetic:pose=" + writePoseFile("none.yaml", "position: [0, 0, 1]\n"), "pose: missing");
}

TEST(SourcePose, APoseFileWithACameraNameReadsThatCameraOfARig) {
    // cam1 sees cam0's points 20 cm further along x: it sits 20 cm along cam0's -x.
    const std::string rig = writePoseFile("rig_camchain.yaml", "cam0: {}\ncam1:\n  T_cn_cnm1:\n"
                                                               "  - [1, 0, 0, 0.2]\n  - [0, 1, 0, 0]\n"
                                                               "  - [0, 0, 1, 0]\n  - [0, 0, 0, 1]\n");
    auto placement = sourcePlacement("synthetic:pose=" + rig + "#cam1:exact");
    ASSERT_TRUE(placement.ok()) << placement.error().message;
    EXPECT_EQ(placement->spec, "synthetic:exact");
    ASSERT_TRUE(placement->cameraToWorld.has_value());
    EXPECT_TRUE(frame::RigidTransform{}.rotation == placement->cameraToWorld->rotation);
    EXPECT_EQ(placement->cameraToWorld->translationMeters, (std::array<double, 3>{-0.2, 0, 0}));
    expectPoseError("synthetic:pose=" + rig + "#cam4", "has no camera 'cam4' (it has cam0, cam1)");
}

TEST(SourcePose, EveryKindOpensWithAPoseAndABadOneIsRefused) {
    auto d = openSourceSpec("synthetic:320x240:pose=0,0,1,0,0,0,1");
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_EQ(configOf(*d).depthWidth, 320);
    auto bad = openSourceSpec("synthetic:pose=0,0,1");
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("pose=0,0,1 in --source"), std::string::npos) << bad.error().message;
    auto live = parseLiveSourceSpec("v4l2:/dev/video2:640x480:pose=0,0,1,0,0,0,1:scale=0.001");
    ASSERT_TRUE(live.ok()) << live.error().message;
    EXPECT_EQ(live->width, 640);
}

// The first frame a device captures (the synthetic camera renders it in a few milliseconds).
frame::FramePtr firstFrame(Device& device) {
    EXPECT_TRUE(device.open());
    EXPECT_TRUE(device.start());
    for (int attempt = 0; attempt < 100; ++attempt) {
        CaptureResult r = device.capture(std::chrono::milliseconds(100));
        if (r.kind == CaptureResult::Kind::Frame)
            return r.frame;
    }
    return nullptr;
}

// pose= places every frame: the synthetic camera's own pose (its place at the desk), then the placement,
// a quarter turn about z and a step to (1, 2, 3); the pixels are the unplaced source's.
TEST(SourcePose, APlacedSourcesFramesCarryThePlacementAfterTheirOwnPose) {
    auto plain = openSourceSpec("synthetic:64x48:exact");
    auto placed =
        openSourceSpec("synthetic:64x48:exact:pose=1,2,3,0,0,0.70710678118654752,0.70710678118654752");
    ASSERT_TRUE(plain.ok() && placed.ok());
    const frame::FramePtr a = firstFrame(**plain);
    const frame::FramePtr b = firstFrame(**placed);
    ASSERT_TRUE(a && b && a->pose && b->pose);
    const frame::RigidTransform own = frame::rigidFromPose(*a->pose);
    const std::array<double, 3> p{0.25, -0.5, 2.0}; // a point in the camera's frame
    const std::array<double, 3> atDesk = own.apply(p);
    const std::array<double, 3> expected{1.0 - atDesk[1], 2.0 + atDesk[0], 3.0 + atDesk[2]};
    const std::array<double, 3> got = frame::rigidFromPose(*b->pose).apply(p);
    for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(got[i], expected[i], 1e-12) << i;
    EXPECT_EQ(b->sceneDepth->depthMeters.pixels, a->sceneDepth->depthMeters.pixels);
}

TEST(SourcePose, ALiveCameraKeepsItsPoseInAnotherDepthMode) {
    auto spec = specWithDepthMode("v4l2:/dev/video2:pose=0,0,1,0,0,0,1:scale=0.001", {"Z16", 848, 480, 30.0});
    ASSERT_TRUE(spec.ok()) << spec.error().message;
    EXPECT_EQ(*spec, "v4l2:/dev/video2:848x480@30:format=Z16:pose=0,0,1,0,0,0,1:scale=0.001");
}

// The window's colour mode list reopens a live camera only; the depth mode, pose= and the rest stay.
TEST(SourceSpec, AColourModeIsALiveCamerasAndKeepsTheRestOfItsSpec) {
    auto spec =
        specWithColorMode("v4l2:/dev/video2:640x480@30:format=Z16:pose=0,0,1,0,0,0,1:color=/dev/video4",
                          {"YUYV", 1280, 720, 30.0});
    ASSERT_TRUE(spec.ok()) << spec.error().message;
    EXPECT_EQ(*spec, "v4l2:/dev/video2:colormode=1280x720@30:colorformat=YUYV:640x480@30:format=Z16:"
                     "pose=0,0,1,0,0,0,1:color=/dev/video4");
    const auto again = specWithColorMode(*spec, {"YUYV", 640, 480, 30.0});
    ASSERT_TRUE(again.ok()) << again.error().message;
    EXPECT_EQ(*again, "v4l2:/dev/video2:colormode=640x480@30:colorformat=YUYV:640x480@30:format=Z16:"
                      "pose=0,0,1,0,0,0,1:color=/dev/video4")
        << "the spec's own colour mode is replaced, not repeated";
    const auto replayed = specWithColorMode("synthetic:rig=rgbd", {"YUYV", 640, 480, 30.0});
    ASSERT_FALSE(replayed.ok());
    EXPECT_NE(replayed.error().message.find("not a live camera"), std::string::npos)
        << replayed.error().message;
}

} // namespace
} // namespace dc::devices
