#include "frame/calibration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

namespace dc::frame {
namespace {

// The layout of OpenCV's stereo_calib sample (intrinsics M1 D1 M2 D2, extrinsics R T) in one file, with
// the image sizes the sample knows but does not write.
constexpr const char* kOpenCvStereo = R"(%YAML:1.0
---
image_size1: [ 848, 480 ]
image_size2: [ 1280, 720 ]
M1: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 425.25, 0., 422.75, 0., 425.5, 241.125, 0., 0., 1. ]
D1: !!opencv-matrix
   rows: 1
   cols: 5
   dt: d
   data: [ 0., 0., 0., 0., 0. ]
M2: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 910.5, 0., 645.25, 0., 909.75, 362.5, 0., 0., 1. ]
D2: !!opencv-matrix
   rows: 1
   cols: 5
   dt: d
   data: [ 0.125, -0.25, 0.001, -0.002, 0.0625 ]
R: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 0.9999875, -0.0049999, 0.0,
           0.0049999, 0.9999875, 0.0,
           0.0, 0.0, 1.0 ]
T: !!opencv-matrix
   rows: 3
   cols: 1
   dt: d
   data: [ -0.015, 0.0001, 0.0002 ]
)";

// The layout of Kalibr's camchain.yaml, with the fields it writes that a depth viewer does not need.
constexpr const char* kKalibr = R"(cam0:
  cam_overlaps: [1]
  camera_model: pinhole
  distortion_coeffs: [0.0, 0.0, 0.0, 0.0]
  distortion_model: radtan
  intrinsics: [385.75, 386.25, 321.5, 238.25]
  resolution: [640, 480]
  rostopic: /camera/depth/image_rect_raw
cam1:
  T_cn_cnm1:
  - [1.0, 0.0, 0.0, -0.0147]
  - [0.0, 1.0, 0.0, 0.0002]
  - [0.0, 0.0, 1.0, 0.0003]
  - [0.0, 0.0, 0.0, 1.0]
  cam_overlaps: [0]
  camera_model: pinhole
  distortion_coeffs: [0.11, -0.21, 0.0005, -0.0007]
  distortion_model: radtan
  intrinsics: [615.5, 615.25, 322.75, 241.5]
  resolution: [640, 480]
  rostopic: /camera/color/image_raw
  timeshift_cam_imu: 0.0
)";

TEST(RigCalibrationFiles, OpenCvStereoLayoutReadsAsDepthThenColour) {
    const auto c = parseCalibration(kOpenCvStereo, "stereo.yml");
    ASSERT_TRUE(c) << c.error().message;
    ASSERT_TRUE(c->rig);
    EXPECT_EQ(c->format, "OpenCV stereo YAML");
    const RigCalibration& rig = *c->rig;
    EXPECT_EQ(rig.depth.intrinsics, (Intrinsics{425.25, 425.5, 422.75, 241.125, 848, 480}));
    EXPECT_EQ(rig.depth.lens.model, LensModel::None);
    EXPECT_EQ(rig.colour.intrinsics, (Intrinsics{910.5, 909.75, 645.25, 362.5, 1280, 720}));
    EXPECT_EQ(rig.colour.lens, (Lens{LensModel::BrownConrady, {0.125, -0.25, 0.001, -0.002, 0.0625}}));
    EXPECT_EQ(rig.depthToColour.rotation[1], -0.0049999);
    EXPECT_EQ(rig.depthToColour.translationMeters, (std::array<double, 3>{-0.015, 0.0001, 0.0002}));
    EXPECT_EQ(c->intrinsics, rig.colour.intrinsics) << "the camera image is the colour sensor's";
    EXPECT_NE(rig.name.find("stereo.yml"), std::string::npos);
    EXPECT_FALSE(rig.approximate);
}

TEST(RigCalibrationFiles, KalibrCamchainReadsCam0AsDepthAndCam1AsColour) {
    const auto c = parseCalibration(kKalibr, "camchain.yaml");
    ASSERT_TRUE(c) << c.error().message;
    ASSERT_TRUE(c->rig);
    EXPECT_EQ(c->format, "Kalibr camchain");
    EXPECT_EQ(c->rig->depth.intrinsics, (Intrinsics{385.75, 386.25, 321.5, 238.25, 640, 480}));
    EXPECT_EQ(c->rig->colour.intrinsics, (Intrinsics{615.5, 615.25, 322.75, 241.5, 640, 480}));
    EXPECT_EQ(c->rig->colour.lens, (Lens{LensModel::BrownConrady, {0.11, -0.21, 0.0005, -0.0007, 0.0}}));
    EXPECT_EQ(c->rig->depthToColour.translationMeters, (std::array<double, 3>{-0.0147, 0.0002, 0.0003}));
    EXPECT_TRUE(c->rig->depthToColour.rotation == RigidTransform{}.rotation);
}

RigCalibration sampleRig(LensModel colourLens, double k3) {
    RigCalibration rig;
    rig.depth.intrinsics = {446.123456789, 446.5, 423.25, 239.75, 848, 480};
    rig.colour.intrinsics = {931.0 / 3.0, 930.125, 639.5, 359.5, 1280, 720};
    rig.colour.lens = {colourLens, {0.1, -0.2, 0.0008, -0.0005, k3}};
    const double c = 0.99999, s = std::sqrt(1.0 - c * c);
    rig.depthToColour = {{c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c}, {-0.015, 1e-4, -2e-4}};
    return rig;
}

void expectSameRig(const RigCalibration& a, const RigCalibration& b) {
    EXPECT_EQ(a.depth, b.depth);
    EXPECT_EQ(a.colour, b.colour);
    EXPECT_EQ(a.depthToColour, b.depthToColour);
}

TEST(RigCalibrationFiles, EachFormatRoundTripsExactly) {
    struct Case {
        CalibrationFormat format;
        RigCalibration rig;
        const char* name;
    };
    for (const Case& t : {Case{CalibrationFormat::OpenCvStereoYaml,
                               sampleRig(LensModel::InverseBrownConrady, 0.05), "OpenCV stereo YAML"},
                          Case{CalibrationFormat::OpenCvStereoJson, sampleRig(LensModel::BrownConrady, 0.05),
                               "OpenCV stereo JSON"},
                          Case{CalibrationFormat::KalibrCamchain, sampleRig(LensModel::BrownConrady, 0.0),
                               "Kalibr camchain"}}) {
        SCOPED_TRACE(t.name);
        Calibration original{t.rig.colour.intrinsics, "", t.rig, "", ""};
        const auto text = writeCalibration(original, t.format);
        ASSERT_TRUE(text) << text.error().message;
        const auto back = parseCalibration(*text, "written");
        ASSERT_TRUE(back) << back.error().message << "\n" << *text;
        ASSERT_TRUE(back->rig);
        EXPECT_EQ(back->format, t.name);
        expectSameRig(*back->rig, t.rig);
        const auto again = writeCalibration(*back, t.format);
        ASSERT_TRUE(again);
        EXPECT_EQ(*again, *text);
    }
}

TEST(RigCalibrationFiles, SingleCameraFormatsRoundTrip) {
    const Intrinsics k{385.5, 386.125, 320.25, 241.75, 640, 480};
    for (auto [format, name] : {std::pair{CalibrationFormat::OpenCvYaml, "OpenCV YAML"},
                                std::pair{CalibrationFormat::RosCameraInfo, "ROS camera_info YAML"}}) {
        const auto text = writeCalibration(Calibration{k, "", std::nullopt, "", ""}, format);
        ASSERT_TRUE(text);
        const auto back = parseCalibration(*text, "written");
        ASSERT_TRUE(back) << back.error().message;
        EXPECT_EQ(back->format, name);
        EXPECT_EQ(back->intrinsics, k);
        EXPECT_FALSE(back->rig);
    }
}

TEST(RigCalibrationFiles, KalibrRefusesWhatItCannotSay) {
    const RigCalibration inverse = sampleRig(LensModel::InverseBrownConrady, 0.0);
    EXPECT_FALSE(writeCalibration(Calibration{{}, "", inverse, "", ""}, CalibrationFormat::KalibrCamchain));
    const RigCalibration k3 = sampleRig(LensModel::BrownConrady, 0.05);
    EXPECT_FALSE(writeCalibration(Calibration{{}, "", k3, "", ""}, CalibrationFormat::KalibrCamchain));
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

TEST(RigCalibrationFiles, EachBadFieldIsAnErrorNamingIt) {
    struct Case {
        std::string text;
        const char* field;
    };
    const std::string cv = kOpenCvStereo, kalibr = kKalibr;
    const Case cases[] = {
        {replaced(cv, "0.9999875, -0.0049999", "0.9, -0.0049999"), "R: not a rotation"},
        {replaced(cv, "0.0, 0.0, 1.0 ]", "0.0, 0.0, -1.0 ]"), "R: not a rotation"}, // a reflection
        {replaced(cv, "[ 910.5,", "[ 0.,"), "M2: focal length must be positive"},
        {replaced(cv, "[ 425.25,", "[ -425.25,"), "M1: focal length must be positive"},
        {replaced(cv, "0.125, -0.25", ".nan, -0.25"), "D2: not a finite number"},
        {replaced(cv, "[ -0.015, 0.0001", "[ -15.0, 0.0001"), "T: the sensors would be more than 1 m apart"},
        {replaced(cv, "image_size2: [ 1280, 720 ]", "image_size2: [ 1280 ]"),
         "image_size2: expected 2 values"},
        {replaced(cv, "image_size1: [ 848, 480 ]", ""), "image_size1: missing"},
        {replaced(cv, "T: !!opencv-matrix", "T_unused: !!opencv-matrix"), "T: missing"},
        {replaced(cv, "0.125, -0.25, 0.001, -0.002, 0.0625 ]", "0.1, 0., 0., 0., 0., 0.2, 0., 0. ]"),
         "D2: expected k1"},
        {replaced(kalibr, "[0.0, 1.0, 0.0, 0.0002]", "[0.0, 2.0, 0.0, 0.0002]"),
         "cam1.T_cn_cnm1: not a rotation"},
        {replaced(kalibr, "[0.0, 0.0, 0.0, 1.0]", "[0.0, 0.0, 1.0, 1.0]"), "cam1.T_cn_cnm1: the last row"},
        {replaced(kalibr, "[385.75, 386.25, 321.5, 238.25]", "[385.75, 321.5, 238.25]"),
         "cam0.intrinsics: expected 4"},
        {replaced(kalibr, "[615.5, 615.25,", "[615.5, -1.0,"),
         "cam1.intrinsics: focal length must be positive"},
        {replaced(kalibr, "distortion_model: radtan\n  intrinsics: [615.5",
                  "distortion_model: equidistant\n  intrinsics: [615.5"),
         "cam1.distortion_model: 'equidistant' is not supported"},
        {replaced(kalibr, "camera_model: pinhole", "camera_model: omni"), "cam0.camera_model"},
        {replaced(kalibr, "resolution: [640, 480]\n  rostopic: /camera/depth",
                  "resolution: [-640, 480]\n  rostopic: /camera/depth"),
         "cam0.resolution"},
        {replaced(kalibr, "[0.11, -0.21,", "[.nan, -0.21,"), "cam1.distortion_coeffs: not a finite number"},
    };
    for (const Case& c : cases) {
        const auto result = parseCalibration(c.text, "bad.yaml");
        ASSERT_FALSE(result) << c.field;
        EXPECT_NE(result.error().message.find(std::string("bad.yaml: ") + c.field), std::string::npos)
            << "expected '" << c.field << "' in: " << result.error().message;
    }
}

// Kalibr's camchain at its own shallow indentation (each sequence at its key's column, as PyYAML writes it),
// annotated the way people annotate it: comments after a key and between rows, intrinsics one per line.
constexpr const char* kKalibrAnnotated = R"(cam0:
  camera_model: pinhole
  distortion_coeffs: [0.0, 0.0, 0.0, 0.0]
  distortion_model: radtan
  intrinsics:  # fu, fv, pu, pv
  - 385.75
  - 386.25
  - 321.5
  - 238.25
  resolution: [640, 480]
cam1:
  T_cn_cnm1: # takes cam0's points to cam1's
  - [0.9999875, -0.0049999, 0.0, -0.0147]
  # the rows of [R | t], then [0, 0, 0, 1]
  - [0.0049999, 0.9999875, 0.0, 0.0002]
  - [0.0, 0.0, 1.0, 0.0003]
  - [0.0, 0.0, 0.0, 1.0]
  camera_model: pinhole
  distortion_coeffs: [0.11, -0.21, 0.0005, -0.0007]
  distortion_model: radtan
  intrinsics: [615.5, 615.25, 322.75, 241.5]
  resolution: [1280, 720]
)";

TEST(RigCalibrationFiles, KalibrCamchainAtItsShallowIndentationReadsWithItsComments) {
    const auto c = parseCalibration(kKalibrAnnotated, "camchain.yaml");
    ASSERT_TRUE(c) << c.error().message;
    ASSERT_TRUE(c->rig);
    EXPECT_EQ(c->format, "Kalibr camchain");
    EXPECT_EQ(c->rig->depth.intrinsics, (Intrinsics{385.75, 386.25, 321.5, 238.25, 640, 480}));
    EXPECT_EQ(c->rig->colour.intrinsics, (Intrinsics{615.5, 615.25, 322.75, 241.5, 1280, 720}));
    EXPECT_EQ(c->rig->depthToColour.rotation,
              (std::array<double, 9>{0.9999875, -0.0049999, 0.0, 0.0049999, 0.9999875, 0.0, 0.0, 0.0, 1.0}));
    EXPECT_EQ(c->rig->depthToColour.translationMeters, (std::array<double, 3>{-0.0147, 0.0002, 0.0003}));
}

TEST(RigCalibrationFiles, AMisnamedOrMissingFieldIsOneLineNamingIt) {
    Calibration stereo{{}, "", sampleRig(LensModel::BrownConrady, 0.0), "", ""};
    const auto json = writeCalibration(stereo, CalibrationFormat::OpenCvStereoJson);
    const auto single =
        writeCalibration(Calibration{{385.5, 385.5, 320.0, 240.0, 640, 480}, "", std::nullopt, "", ""},
                         CalibrationFormat::RosCameraInfo);
    ASSERT_TRUE(json && single);
    const std::string cv = kOpenCvStereo, kalibr = kKalibr;
    const std::pair<std::string, std::string> cases[] = {
        {replaced(kalibr, "  intrinsics: [615.5", "  intrinsic: [615.5"),
         "bad.yaml: cam1.intrinsics: missing"},
        {replaced(kalibr, "T_cn_cnm1:", "T_cam_imu:"), "bad.yaml: cam1.T_cn_cnm1: missing"},
        {replaced(kalibr, "  resolution: [640, 480]\n  rostopic: /camera/depth", "  rostopic: /camera/depth"),
         "bad.yaml: cam0.resolution: missing"},
        {replaced(cv, "R: !!opencv-matrix", "Rot: !!opencv-matrix"), "bad.yaml: R: missing"},
        {replaced(cv, "M2: !!opencv-matrix", "M_2: !!opencv-matrix"), "bad.yaml: K2: missing"},
        {replaced(*json, "\"T\"", "\"t\""), "bad.yaml: T: missing"},
        {replaced(*single, "camera_matrix:", "camera_matrx:"),
         "bad.yaml: no camera_matrix (expected OpenCV or ROS camera_info calibration YAML)"},
    };
    for (const auto& [text, expected] : cases) {
        const auto result = parseCalibration(text, "bad.yaml");
        ASSERT_FALSE(result) << expected;
        EXPECT_EQ(result.error().message, expected);
    }
}

TEST(RigCalibrationFiles, MalformedYamlOrJsonIsAnErrorNamingTheFileAndLine) {
    struct Case {
        std::string text;
        const char* origin;
        const char* where; // file:line: the line yaml-cpp stopped at, counted from 1
    };
    const Case cases[] = {
        // M1's dt, indented deeper than its siblings, on line 8: OpenCV's directive line counts too.
        {replaced(kOpenCvStereo, "   dt: d\n", "     dt: d\n"), "stereo.yml", "stereo.yml:8:"},
        {R"({
    "image_size1": [ 848, 480 ],
    "K1": { "type_id": "opencv-matrix", "rows": 3,
        "cols": 3 ]
})",
         "stereo.json", "stereo.json:4:"},
    };
    for (const Case& c : cases) {
        const auto result = parseCalibration(c.text, c.origin);
        ASSERT_FALSE(result) << c.where;
        const std::string& message = result.error().message;
        EXPECT_EQ(message.rfind(c.where, 0), 0u) << message;
        EXPECT_NE(message.find("malformed calibration YAML or JSON"), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
    // A file, read from disk: its second row one column off the others, on line 12.
    const std::string path = ::testing::TempDir() + "malformed_camchain.yaml";
    std::ofstream(path) << replaced(kKalibr, "  - [0.0, 1.0, 0.0, 0.0002]", "   - [0.0, 1.0, 0.0, 0.0002]");
    const auto loaded = loadCalibration(path);
    ASSERT_FALSE(loaded);
    EXPECT_EQ(loaded.error().message.rfind(path + ":12:", 0), 0u) << loaded.error().message;
}

TEST(RigCalibrationFiles, StreamsOfAnotherShapeAreRefusedNamingTheSizeField) {
    const auto stereo = parseCalibration(kOpenCvStereo, "stereo.yml");
    ASSERT_TRUE(stereo);
    EXPECT_TRUE(checkStreamSizes(*stereo, 848, 480, 1280, 720));
    EXPECT_TRUE(checkStreamSizes(*stereo, 424, 240, 640, 360)) << "the same shape, scaled";
    const Status colour = checkStreamSizes(*stereo, 848, 480, 640, 480);
    ASSERT_FALSE(colour);
    EXPECT_NE(colour.error().message.find("image_size2 1280x720"), std::string::npos)
        << colour.error().message;
    const Status depth = checkStreamSizes(*stereo, 640, 480, 1280, 720);
    ASSERT_FALSE(depth);
    EXPECT_NE(depth.error().message.find("image_size1"), std::string::npos);

    const auto kalibr = parseCalibration(kKalibr, "camchain.yaml");
    ASSERT_TRUE(kalibr);
    const Status k = checkStreamSizes(*kalibr, 640, 480, 1280, 720);
    ASSERT_FALSE(k);
    EXPECT_NE(k.error().message.find("cam1.resolution"), std::string::npos);
}

} // namespace
} // namespace dc::frame
