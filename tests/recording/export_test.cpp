// Export: PLY written then parsed back, the Stray layout imported back, 16-bit PNGs, frame ranges.

#include "devices/replay/importers.h"
#include "exporting/export.h"
#include "processing/point_cloud.h"
#include "tests/recording/recording_test_support.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>

namespace dc::exporting {
namespace {

using test::TempDir;

struct PlyFile {
    std::vector<std::string> properties;
    std::size_t vertices = 0;
    std::vector<processing::CloudPoint> points;
};

// A strict reader of what encodePly writes: the standard header, then packed little-endian vertices.
PlyFile parsePly(const std::vector<std::uint8_t>& bytes) {
    PlyFile ply;
    const std::string text(bytes.begin(), bytes.end());
    const auto end = text.find("end_header\n");
    EXPECT_NE(end, std::string::npos);
    std::istringstream header(text.substr(0, end));
    std::string line;
    std::getline(header, line);
    EXPECT_EQ(line, "ply");
    std::getline(header, line);
    EXPECT_EQ(line, "format binary_little_endian 1.0");
    while (std::getline(header, line)) {
        if (line.starts_with("element vertex "))
            ply.vertices = std::stoul(line.substr(15));
        else if (line.starts_with("property "))
            ply.properties.push_back(line.substr(9));
    }
    const std::size_t data = end + 11;
    EXPECT_EQ(bytes.size() - data, ply.vertices * 16);
    for (std::size_t i = 0; i < ply.vertices && data + 16 * (i + 1) <= bytes.size(); ++i) {
        processing::CloudPoint p;
        const std::uint8_t* v = bytes.data() + data + 16 * i;
        std::memcpy(&p.x, v, 4);
        std::memcpy(&p.y, v + 4, 4);
        std::memcpy(&p.z, v + 8, 4);
        p.r = v[12];
        p.g = v[13];
        p.b = v[14];
        p.confidence = v[15];
        ply.points.push_back(p);
    }
    return ply;
}

class Export : public ::testing::Test {
protected:
    void SetUp() override {
        frames_ = test::syntheticFrames(6);
        test::writeRecording(dir_.path("r.dcrec"), frames_);
        auto source = devices::replay::openRecordingSource(dir_.path("r.dcrec"));
        ASSERT_TRUE(source);
        source_ = std::move(*source);
    }
    TempDir dir_;
    std::vector<frame::FramePtr> frames_;
    std::unique_ptr<devices::replay::ReplaySource> source_;
};

TEST_F(Export, PlyPerFrameParsesBackToTheCloudOfThatFrame) {
    std::vector<std::size_t> progress;
    auto result = exportFrames(*source_, {ExportFormat::Ply, dir_.path("ply"), {2, 5}, false, {}},
                               [&](std::size_t done, std::size_t total) {
                                   EXPECT_EQ(total, 3u);
                                   progress.push_back(done);
                                   return true;
                               });
    ASSERT_TRUE(result) << result.error().message;
    EXPECT_EQ(result->framesWritten, 3u);
    EXPECT_EQ(progress, (std::vector<std::size_t>{1, 2, 3}));
    EXPECT_FALSE(std::filesystem::exists(dir_.path("ply/000001.ply")));
    const PlyFile ply = parsePly(test::readBytes(dir_.path("ply/000003.ply")));
    EXPECT_EQ(ply.properties, (std::vector<std::string>{"float x", "float y", "float z", "uchar red",
                                                        "uchar green", "uchar blue", "uchar confidence"}));
    const auto expected = processing::buildPointCloud(*frames_[3], frame::Confidence::Low, 0.0f);
    ASSERT_EQ(ply.vertices, expected.size());
    ASSERT_GT(expected.size(), 100u);
    for (std::size_t i = 0; i < expected.size(); i += 37) {
        EXPECT_EQ(ply.points[i].x, expected[i].x);
        EXPECT_EQ(ply.points[i].z, expected[i].z);
        EXPECT_EQ(ply.points[i].g, expected[i].g);
        EXPECT_EQ(ply.points[i].confidence, expected[i].confidence);
    }
}

std::string readText(const std::string& path) {
    const auto bytes = test::readBytes(path);
    return {bytes.begin(), bytes.end()};
}

// Open3D (Debian's python3-open3d for Debian's /usr/bin/python3, installed by scripts/setup.sh) reads what
// CloudCompare and other tools will read: the same points with the same colours.
TEST_F(Export, OpenThreeDLoadsThePly) {
    ASSERT_TRUE(exportFrames(*source_, {ExportFormat::Ply, dir_.path("o3d"), {3, 4}, false, {}}));
    const std::string ply = dir_.path("o3d/000003.ply"), out = dir_.path("o3d.txt");
    const std::string command =
        "/usr/bin/python3 -c 'import sys, open3d as o3d; p = o3d.io.read_point_cloud(sys.argv[1]); "
        "print(len(p.points)); print(*p.points[41]); print(*p.colors[41])' " +
        ply + " > " + out + " 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << readText(out);
    std::istringstream read(readText(out));
    std::size_t count = 0;
    double x = 0, y = 0, z = 0, r = 0, g = 0, b = 0;
    read >> count >> x >> y >> z >> r >> g >> b;
    ASSERT_TRUE(read) << readText(out);
    const auto expected = processing::buildPointCloud(*frames_[3], frame::Confidence::Low, 0.0f);
    ASSERT_EQ(count, expected.size());
    const auto& p = expected[41];
    EXPECT_FLOAT_EQ(static_cast<float>(x), p.x);
    EXPECT_FLOAT_EQ(static_cast<float>(y), p.y);
    EXPECT_FLOAT_EQ(static_cast<float>(z), p.z);
    EXPECT_NEAR(r * 255.0, p.r, 1e-3);
    EXPECT_NEAR(g * 255.0, p.g, 1e-3);
    EXPECT_NEAR(b * 255.0, p.b, 1e-3);
}

TEST_F(Export, PlyInWorldCoordinatesAppliesThePose) {
    ASSERT_TRUE(exportFrames(*source_, {ExportFormat::Ply, dir_.path("w"), {1, 2}, true, {}}));
    const PlyFile ply = parsePly(test::readBytes(dir_.path("w/000001.ply")));
    const auto camera = processing::buildPointCloud(*frames_[1], frame::Confidence::Low, 0.0f);
    ASSERT_EQ(ply.vertices, camera.size());
    const auto& m = frames_[1]->pose->cameraToWorld;
    const auto& c = camera[10];
    EXPECT_NEAR(ply.points[10].x, m[0] * c.x + m[4] * c.y + m[8] * c.z + m[12], 1e-5);
    EXPECT_NEAR(ply.points[10].z, m[2] * c.x + m[6] * c.y + m[10] * c.z + m[14], 1e-5);
}

TEST_F(Export, StrayLayoutImportsBackWithTheSameFrames) {
    // Stray stores orientation as a quaternion, so it carries rotations only; the synthetic scene's
    // y-up world makes its poses reflections (determinant -1). Give the frames proper rotations.
    std::vector<frame::FramePtr> rotated;
    for (std::size_t i = 0; i < frames_.size(); ++i) {
        auto f = std::make_shared<frame::Frame>(*frames_[i]);
        const double t[3] = {0.1 * i, -0.2, 1.5};
        const double angle = 0.3 * static_cast<double>(i);
        const double q[4] = {std::sin(angle / 2) * 0.6, std::sin(angle / 2) * 0.8, 0.0, std::cos(angle / 2)};
        f->pose = devices::replay::poseFromQuaternion(t, q);
        rotated.push_back(f);
    }
    frames_ = rotated;
    test::writeRecording(dir_.path("rotated.dcrec"), frames_);
    auto rotatedSource = devices::replay::openRecordingSource(dir_.path("rotated.dcrec"));
    ASSERT_TRUE(rotatedSource);
    source_ = std::move(*rotatedSource);
    auto result = exportFrames(*source_, {ExportFormat::Stray, dir_.path("stray"), {}, false, {}});
    ASSERT_TRUE(result) << result.error().message;
    auto back = devices::replay::openReplaySource(dir_.path("stray"));
    ASSERT_TRUE(back) << back.error().message;
    ASSERT_EQ((*back)->frameCount(), frames_.size());
    EXPECT_TRUE((*back)->capabilities().confidence);
    for (std::size_t i = 0; i < frames_.size(); ++i) {
        auto f = devices::replay::loadFrame(**back, i);
        ASSERT_TRUE(f) << f.error().message;
        EXPECT_EQ(f->timestampNs, frames_[i]->timestampNs);
        const auto& original = frames_[i]->sceneDepth->depthMeters;
        const auto& imported = f->sceneDepth->depthMeters;
        ASSERT_EQ(imported.width, original.width);
        for (std::size_t p = 0; p < original.pixels.size(); ++p)
            EXPECT_NEAR(imported.pixels[p], original.pixels[p], 0.0005) << "millimetre depth, frame " << i;
        EXPECT_EQ(f->sceneDepth->confidence.pixels, frames_[i]->sceneDepth->confidence.pixels);
        for (std::size_t k = 0; k < 16; ++k)
            EXPECT_NEAR(f->pose->cameraToWorld[k], frames_[i]->pose->cameraToWorld[k], 1e-6);
        EXPECT_DOUBLE_EQ(f->cameraIntrinsics.fx, frames_[i]->cameraIntrinsics.fx);
        EXPECT_EQ(f->capturedImage.width, frames_[i]->capturedImage.width);
    }
}

TEST_F(Export, Png16HoldsMillimetres) {
    ASSERT_TRUE(exportFrames(*source_, {ExportFormat::Png16, dir_.path("png"), {0, 1}, false, {}}));
    const cv::Mat png = cv::imread(dir_.path("png/depth/000000.png"), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(png.type(), CV_16UC1);
    const auto& depth = frames_[0]->sceneDepth->depthMeters;
    for (int y = 0; y < depth.height; y += 5)
        for (int x = 0; x < depth.width; x += 5)
            EXPECT_EQ(png.at<std::uint16_t>(y, x),
                      static_cast<std::uint16_t>(std::lround(depth.at(x, y) * 1000.0)));
}

TEST_F(Export, CancelAndBadRangesAreErrors) {
    auto cancelled = exportFrames(*source_, {ExportFormat::Png16, dir_.path("c"), {}, false, {}},
                                  [](std::size_t done, std::size_t) { return done < 2; });
    ASSERT_FALSE(cancelled);
    EXPECT_NE(cancelled.error().message.find("cancelled after 2 frames"), std::string::npos);
    EXPECT_FALSE(parseFrameRange("3:3", 6));
    EXPECT_FALSE(parseFrameRange("0:7", 6));
    EXPECT_FALSE(parseFrameRange("a:b", 6));
    EXPECT_FALSE(parseFrameRange("4", 6));
    auto open = parseFrameRange("4:", 6);
    ASSERT_TRUE(open);
    EXPECT_EQ(open->first, 4u);
    EXPECT_EQ(open->end, 6u);
    EXPECT_EQ(parseFrameRange(":2", 6)->end, 2u);
}

} // namespace
} // namespace dc::exporting
