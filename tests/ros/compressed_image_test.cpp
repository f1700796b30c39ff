// sensor_msgs/CompressedImage payloads decompressed as image_transport's plugins write them; the replay of a
// whole recording of them is in mcap_replay_test.cpp (compressed.mcap, PNG written by an independent writer).

#include "devices/ros/compressed_image.h"
#include "frame/jpeg_codec.h"
#include "frame/png_codec.h"
#include "frame/rgb_image.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

namespace dc::devices::ros {
namespace {

// compressed_depth_image_transport's header: the format enum (0, PNG), then the quantisation a and b.
std::vector<std::uint8_t> depthHeader(float a, float b) {
    std::vector<std::uint8_t> header(12, 0);
    std::memcpy(header.data() + 4, &a, sizeof a);
    std::memcpy(header.data() + 8, &b, sizeof b);
    return header;
}

std::vector<std::uint8_t> withPng(std::vector<std::uint8_t> header, const cv::Mat& image) {
    auto png = frame::encodePng(image, 1);
    EXPECT_TRUE(png) << png.error().message;
    header.insert(header.end(), png->begin(), png->end());
    return header;
}

Expected<RosImage> decompress(const std::string& format, const std::vector<std::uint8_t>& data) {
    return decompressImage(format, data.data(), data.size());
}

float floatAt(const RosImage& image, int x, int y) {
    float v = 0.0f;
    std::memcpy(&v, image.data.data() + y * image.step + x * 4, sizeof v);
    return v;
}

// 32FC1 depth goes through the transport as 16-bit inverse depth, value = a / depth + b; zero is no depth.
TEST(CompressedImage, A32FC1CompressedDepthComesBackInMetersWithinItsQuantisation) {
    const float a = 100.0f, b = 10.0f; // the plugin's defaults: depth_quantization 100, depth_max 10 m
    const float meters[] = {0.3f, 1.0f, 2.5f, 6.0f};
    cv::Mat quantised(1, 5, CV_16UC1, cv::Scalar(0));
    for (int x = 0; x < 4; ++x)
        quantised.at<std::uint16_t>(0, x) = static_cast<std::uint16_t>(std::lround(a / meters[x] + b));
    auto image = decompress("32FC1; compressedDepth png", withPng(depthHeader(a, b), quantised));
    ASSERT_TRUE(image) << image.error().message;
    EXPECT_EQ(image->encoding, "32FC1");
    ASSERT_EQ(image->width, 5u);
    for (int x = 0; x < 4; ++x) {
        // Half a quantisation step of inverse depth: d^2 / (2a) meters at depth d.
        const double step = meters[x] * meters[x] / (2.0 * a);
        EXPECT_NEAR(floatAt(*image, x, 0), meters[x], step * 1.01) << x;
    }
    EXPECT_TRUE(std::isnan(floatAt(*image, 4, 0))) << "zero is no depth, not a / -b";
}

TEST(CompressedImage, A16UC1CompressedDepthIsItsMillimetresExactly) {
    cv::Mat mm(2, 3, CV_16UC1);
    for (int i = 0; i < 6; ++i)
        mm.at<std::uint16_t>(i / 3, i % 3) = static_cast<std::uint16_t>(500 + 977 * i);
    auto image = decompress("16UC1; compressedDepth png", withPng(depthHeader(0, 0), mm));
    ASSERT_TRUE(image) << image.error().message;
    EXPECT_EQ(image->encoding, "16UC1");
    ASSERT_EQ(image->step, 6u);
    EXPECT_EQ(0, std::memcmp(image->data.data(), mm.data, 12));
}

TEST(CompressedImage, AJpegBecomesRgbCloseToWhatWasEncoded) {
    std::vector<std::uint8_t> rgb(32 * 16 * 3);
    for (std::size_t i = 0; i < rgb.size(); ++i)
        rgb[i] = static_cast<std::uint8_t>(i % 3 == 0 ? 200 : i % 3 == 1 ? 90 : 30); // one flat colour
    frame::JpegEncoder encoder;
    auto jpeg = encoder.encode(frame::makeRgb24Image(32, 16, rgb), 95);
    ASSERT_TRUE(jpeg) << jpeg.error().message;
    const std::vector<std::uint8_t> bytes(jpeg->begin(), jpeg->end());
    auto image = decompress("rgb8; jpeg compressed bgr8", bytes);
    ASSERT_TRUE(image) << image.error().message;
    EXPECT_EQ(image->encoding, "rgb8");
    ASSERT_EQ(image->width, 32u);
    ASSERT_EQ(image->height, 16u);
    for (std::size_t i = 0; i < rgb.size(); ++i)
        ASSERT_NEAR(image->data[i], rgb[i], 4) << i;
}

TEST(CompressedImage, WhatCannotBeReadIsAnErrorNamingIt) {
    const std::vector<std::uint8_t> garbage(64, 0x5a);
    auto rvl = decompress("16UC1; compressedDepth rvl", garbage);
    ASSERT_FALSE(rvl);
    EXPECT_NE(rvl.error().message.find("RVL"), std::string::npos) << rvl.error().message;
    auto shortDepth = decompress("16UC1; compressedDepth png", std::vector<std::uint8_t>(5, 0));
    ASSERT_FALSE(shortDepth);
    EXPECT_NE(shortDepth.error().message.find("no header"), std::string::npos);
    auto neither = decompress("jpeg", garbage);
    ASSERT_FALSE(neither);
    EXPECT_NE(neither.error().message.find("neither PNG nor readable JPEG"), std::string::npos);
    cv::Mat gray8(2, 2, CV_8UC1, cv::Scalar(7));
    auto eightBitDepth = decompress("16UC1; compressedDepth png", withPng(depthHeader(0, 0), gray8));
    ASSERT_FALSE(eightBitDepth);
    EXPECT_NE(eightBitDepth.error().message.find("not 16-bit gray"), std::string::npos);
}

} // namespace
} // namespace dc::devices::ros
