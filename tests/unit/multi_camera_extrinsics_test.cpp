#include "frame/camera_pose.h"
#include "frame/multi_camera_extrinsics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace dc::frame {
namespace {

// Three cameras as Kalibr writes them (intrinsics included, which these readers skip). cam1 sees cam0's
// points turned a quarter turn about z and moved 10 cm along x; cam2 sees cam1's moved 50 cm back along z.
constexpr const char* kThreeCameraChain = R"(cam0:
  camera_model: pinhole
  intrinsics: [460.0, 460.0, 320.0, 240.0]
  resolution: [640, 480]
cam1:
  T_cn_cnm1:
  - [0.0, -1.0, 0.0, 0.1]
  - [1.0, 0.0, 0.0, 0.0]
  - [0.0, 0.0, 1.0, 0.0]
  - [0.0, 0.0, 0.0, 1.0]
  camera_model: pinhole
  intrinsics: [460.0, 460.0, 320.0, 240.0]
  resolution: [640, 480]
cam2:
  T_cn_cnm1:
  - [1.0, 0.0, 0.0, 0.0]
  - [0.0, 1.0, 0.0, 0.0]
  - [0.0, 0.0, 1.0, -0.5]
  - [0.0, 0.0, 0.0, 1.0]
)";

void expectNearTransform(const RigidTransform& actual, const RigidTransform& expected,
                         const std::string& what) {
    for (int i = 0; i < 9; ++i)
        EXPECT_NEAR(actual.rotation[i], expected.rotation[i], 1e-9) << what << " rotation " << i;
    for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(actual.translationMeters[i], expected.translationMeters[i], 1e-9)
            << what << " translation " << i;
}

RigidTransform posed(double x, double y, double z, double qx, double qy, double qz, double qw) {
    auto pose = poseFromQuaternion({x, y, z, qx, qy, qz, qw});
    EXPECT_TRUE(pose.ok());
    return pose.ok() ? *pose : RigidTransform{};
}

CameraExtrinsicsSet threeCameraRig(const std::string& prefix) {
    return {{{prefix + "0", RigidTransform{}},
             {prefix + "1", posed(0.25, -0.1, 0.05, 0.1, -0.2, 0.3, 0.927)},
             {prefix + "2", posed(-1.5, 2.0, 0.75, -0.5, 0.5, 0.5, 0.5)}},
            ""};
}

void expectSameCameras(const CameraExtrinsicsSet& actual, const CameraExtrinsicsSet& expected) {
    ASSERT_EQ(actual.cameras.size(), expected.cameras.size());
    for (std::size_t i = 0; i < expected.cameras.size(); ++i) {
        EXPECT_EQ(actual.cameras[i].name, expected.cameras[i].name);
        expectNearTransform(actual.cameras[i].cameraToWorld, expected.cameras[i].cameraToWorld,
                            expected.cameras[i].name);
    }
}

void expectExtrinsicsError(const std::string& text, const std::string& problem) {
    auto set = parseCameraExtrinsics(text, "rig.yaml");
    ASSERT_FALSE(set.ok()) << text;
    const std::string& message = set.error().message;
    EXPECT_NE(message.find("rig.yaml"), std::string::npos) << message;
    EXPECT_NE(message.find(problem), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(MultiCameraExtrinsics, AKalibrChainPlacesEachCameraInCam0sFrame) {
    auto set = parseCameraExtrinsics(kThreeCameraChain, "camchain.yaml");
    ASSERT_TRUE(set.ok()) << set.error().message;
    EXPECT_EQ(set->format, "Kalibr camchain");
    ASSERT_EQ(set->cameras.size(), 3u);
    // By hand: cam1 to cam0 is the inverse quarter turn, its origin at (0, 0.1, 0) in cam0's frame; cam2 is
    // cam1 turned alike, 50 cm further along cam1's (and cam0's) z.
    const RigidTransform turnBack{{0, 1, 0, -1, 0, 0, 0, 0, 1}, {0, 0, 0}};
    RigidTransform cam1 = turnBack, cam2 = turnBack;
    cam1.translationMeters = {0, 0.1, 0};
    cam2.translationMeters = {0, 0.1, 0.5};
    EXPECT_EQ(set->cameras[0].name, "cam0");
    EXPECT_TRUE(set->cameras[0].cameraToWorld.isIdentity());
    EXPECT_EQ(set->cameras[1].name, "cam1");
    expectNearTransform(set->cameras[1].cameraToWorld, cam1, "cam1");
    EXPECT_EQ(set->cameras[2].name, "cam2");
    expectNearTransform(set->cameras[2].cameraToWorld, cam2, "cam2");
    // A point 1 m in front of cam2 lies 1.5 m in front of cam0, 10 cm up its y.
    const auto p = set->cameras[2].cameraToWorld.apply({0, 0, 1});
    EXPECT_NEAR(p[0], 0.0, 1e-12);
    EXPECT_NEAR(p[1], 0.1, 1e-12);
    EXPECT_NEAR(p[2], 1.5, 1e-12);
    ASSERT_NE(set->find("cam2"), nullptr);
    EXPECT_EQ(set->find("cam2"), &set->cameras[2]);
    EXPECT_EQ(set->find("cam3"), nullptr);
}

TEST(MultiCameraExtrinsics, OpenCvFileStorageReadsBackWhatItWrote) {
    CameraExtrinsicsSet rig = threeCameraRig("camera_");
    rig.cameras[0].cameraToWorld = posed(0.5, 0, 1.2, 0, 0.3826834, 0, 0.9238795);
    auto text = writeCameraExtrinsics(rig, ExtrinsicsFormat::OpenCvYaml);
    ASSERT_TRUE(text.ok()) << text.error().message;
    EXPECT_NE(text->find("camera_count: 3"), std::string::npos) << *text;
    EXPECT_NE(text->find("!!opencv-matrix"), std::string::npos) << *text;
    auto back = parseCameraExtrinsics(*text, "extrinsics.yml");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->format, "OpenCV extrinsics");
    expectSameCameras(*back, rig);
}

TEST(MultiCameraExtrinsics, KalibrReadsBackWhatItWrote) {
    const CameraExtrinsicsSet rig = threeCameraRig("cam");
    auto text = writeCameraExtrinsics(rig, ExtrinsicsFormat::KalibrCamchain);
    ASSERT_TRUE(text.ok()) << text.error().message;
    auto back = parseCameraExtrinsics(*text, "camchain.yaml");
    ASSERT_TRUE(back.ok()) << back.error().message;
    expectSameCameras(*back, rig);
    // Kalibr has no place for cam0 other than the world's origin.
    CameraExtrinsicsSet moved = rig;
    moved.cameras[0].cameraToWorld.translationMeters[0] = 0.01;
    auto refused = writeCameraExtrinsics(moved, ExtrinsicsFormat::KalibrCamchain);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("first camera (cam0) must be at the identity"), std::string::npos);
    EXPECT_FALSE(writeCameraExtrinsics({}, ExtrinsicsFormat::OpenCvYaml).ok());
}

TEST(MultiCameraExtrinsics, MalformedKalibrChainsNameTheCameraAndField) {
    const std::string row = "  - [1, 0, 0, 0]\n  - [0, 1, 0, 0]\n  - [0, 0, 1, 0]\n  - [0, 0, 0, 1]\n";
    expectExtrinsicsError("cam0: {}\ncam1:\n  T_cn_cnm1:\n" + row + "cam2:\n  camera_model: pinhole\n",
                          "cam2.T_cn_cnm1: missing");
    expectExtrinsicsError(
        "cam0: {}\ncam1:\n  T_cn_cnm1:\n  - [2, 0, 0, 0]\n  - [0, 1, 0, 0]\n  - [0, 0, 1, 0]\n"
        "  - [0, 0, 0, 1]\n",
        "cam1.T_cn_cnm1: not rigid");
    expectExtrinsicsError(
        "cam0: {}\ncam1:\n  T_cn_cnm1:\n  - [1, 0, 0, 0]\n  - [0, 1, 0, 0]\n  - [0, 0, 1, 0]\n",
        "cam1.T_cn_cnm1: expected 16 values, found 12");
    expectExtrinsicsError(
        "cam0: {}\ncam1:\n  T_cn_cnm1:\n  - [1, 0, 0, 0]\n  - [0, 1, 0, 0]\n  - [0, 0, 1, 0]\n"
        "  - [0, 0, 1, 1]\n",
        "cam1.T_cn_cnm1: the last row must be [0, 0, 0, 1]");
    expectExtrinsicsError("cam0: {}\ncam2:\n  T_cn_cnm1:\n" + row,
                          "cam1: missing (the chain goes on to cam2)");
}

TEST(MultiCameraExtrinsics, MalformedOpenCvFilesNameTheCameraAndField) {
    const std::string identity = "!!opencv-matrix\n  rows: 4\n  cols: 4\n  dt: d\n"
                                 "  data: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\n";
    const std::string header = "%YAML:1.0\n---\ncamera_count: 2\ncamera_0: " + identity;
    EXPECT_TRUE(parseCameraExtrinsics(header + "camera_1: " + identity, "rig.yaml").ok());
    expectExtrinsicsError(header, "camera_1: missing");
    expectExtrinsicsError(header + "camera_1: !!opencv-matrix\n  rows: 3\n  cols: 3\n  dt: d\n"
                                   "  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n",
                          "camera_1: expected 16 values, found 9");
    expectExtrinsicsError(header + "camera_1: !!opencv-matrix\n  rows: 4\n  cols: 4\n  dt: d\n"
                                   "  data: [1, 0.5, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\n",
                          "camera_1: not rigid");
    expectExtrinsicsError(header + "camera_1: " + identity + "camera_2: " + identity,
                          "camera_2: beyond camera_count 2");
    expectExtrinsicsError("camera_count: 0\n", "camera_count: expected the number of cameras");
    expectExtrinsicsError("camera_0: " + identity,
                          "not a Kalibr camchain (cam0, cam1...) nor OpenCV extrinsics");
}

} // namespace
} // namespace dc::frame
