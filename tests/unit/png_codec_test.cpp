// PNG through libpng (frame/png_codec.h) and the capture files read with it, checked against OpenCV's
// imgcodecs: the tests may link it, only the shipped binary must not.

#include "base/files.h"
#include "devices/replay/capture_files.h"
#include "frame/png_codec.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace dc::frame {
namespace {

namespace fs = std::filesystem;

bool same(const cv::Mat& a, const cv::Mat& b) {
    return a.type() == b.type() && a.size() == b.size() && cv::norm(a, b, cv::NORM_INF) == 0.0;
}

class PngFiles : public ::testing::Test {
protected:
    void SetUp() override {
        std::string pattern = (fs::temp_directory_path() / "depthcloud-png-XXXXXX").string();
        ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
        dir_ = pattern;
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }

    fs::path dir_;
};

TEST(PngCodec, SixteenBitGrayRoundTripsExactlyAtTheExtremes) {
    cv::Mat depth(3, 5, CV_16UC1);
    const std::uint16_t values[] = {0,     1,     2,     255,   256, 257, 4095, 32767,
                                    32768, 65279, 65534, 65535, 0,   1,   65535};
    std::copy(std::begin(values), std::end(values), depth.ptr<std::uint16_t>(0));
    for (int level : {0, 1, 9}) {
        auto png = encodePng(depth, level);
        ASSERT_TRUE(png) << png.error().message;
        auto back = decodePng(*png);
        ASSERT_TRUE(back) << back.error().message;
        EXPECT_TRUE(same(*back, depth)) << "level " << level;
        // PNG stores 16-bit samples big-endian: an independent decoder reads the same values.
        EXPECT_TRUE(same(cv::imdecode(*png, cv::IMREAD_UNCHANGED), depth)) << "level " << level;
    }
}

TEST(PngCodec, EightBitGrayRgbAndRgbaRoundTrip) {
    cv::RNG rng(28);
    for (int channels : {1, 3, 4}) {
        cv::Mat image(17, 31, CV_8UC(channels));
        rng.fill(image, cv::RNG::UNIFORM, 0, 256);
        auto png = encodePng(image, 3);
        ASSERT_TRUE(png) << png.error().message;
        auto back = decodePng(*png);
        ASSERT_TRUE(back) << back.error().message;
        EXPECT_TRUE(same(*back, image)) << channels << " channels";
        // Channels are in PNG's order: OpenCV's decoder hands the same pixels back as BGR(A).
        cv::Mat theirs = cv::imdecode(*png, cv::IMREAD_UNCHANGED);
        if (channels == 3)
            cv::cvtColor(theirs, theirs, cv::COLOR_BGR2RGB);
        if (channels == 4)
            cv::cvtColor(theirs, theirs, cv::COLOR_BGRA2RGBA);
        EXPECT_TRUE(same(theirs, image)) << channels << " channels";
    }
}

TEST(PngCodec, RefusesWhatItCannotEncode) {
    EXPECT_FALSE(encodePng(cv::Mat(), 1));
    EXPECT_FALSE(encodePng(cv::Mat(4, 4, CV_32FC1, cv::Scalar(1.0f)), 1));
    EXPECT_FALSE(encodePng(cv::Mat(4, 4, CV_16UC3, cv::Scalar(1, 2, 3)), 1));
}

TEST_F(PngFiles, ATruncatedPngIsAnErrorNamingTheFile) {
    cv::Mat depth(64, 64, CV_16UC1);
    cv::randu(depth, 0, 65535);
    auto png = encodePng(depth, 1);
    ASSERT_TRUE(png);
    const std::vector<std::uint8_t> half(png->begin(), png->begin() + static_cast<long>(png->size() / 2));
    ASSERT_TRUE(base::writeFileAtomically(path("half.png"), half));
    auto read = readPng(path("half.png"));
    ASSERT_FALSE(read);
    EXPECT_NE(read.error().message.find(path("half.png")), std::string::npos) << read.error().message;
    EXPECT_NE(read.error().message.find("truncated"), std::string::npos) << read.error().message;
    EXPECT_EQ(read.error().message.find('\n'), std::string::npos) << "one line";

    auto depthRead = devices::replay::readDepthPng(path("half.png"), 0.001);
    ASSERT_FALSE(depthRead);
    EXPECT_NE(depthRead.error().message.find(path("half.png")), std::string::npos);
}

TEST_F(PngFiles, ACorruptPngIsAnErrorNamingTheFile) {
    cv::Mat gray(32, 32, CV_8UC1, cv::Scalar(7));
    auto png = encodePng(gray, 1);
    ASSERT_TRUE(png);
    std::vector<std::uint8_t> corrupt = *png;
    for (std::size_t i = 40; i < corrupt.size() - 12; ++i) // the image data, past the header chunk
        corrupt[i] ^= 0x5a;
    ASSERT_TRUE(base::writeFileAtomically(path("corrupt.png"), corrupt));
    auto read = readPng(path("corrupt.png"));
    ASSERT_FALSE(read);
    EXPECT_NE(read.error().message.find(path("corrupt.png")), std::string::npos) << read.error().message;
}

TEST_F(PngFiles, ANonPngFileIsAnErrorNamingTheFile) {
    std::ofstream(path("text.png")) << "this is not an image, but long enough for a header";
    auto read = readPng(path("text.png"));
    ASSERT_FALSE(read);
    EXPECT_NE(read.error().message.find(path("text.png")), std::string::npos) << read.error().message;
    EXPECT_NE(read.error().message.find("not a PNG"), std::string::npos) << read.error().message;
    auto color = devices::replay::readColorImage(path("text.png"));
    ASSERT_FALSE(color);
    EXPECT_NE(color.error().message.find(path("text.png")), std::string::npos) << color.error().message;
    auto missing = readPng(path("nothing.png"));
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message.find(path("nothing.png")), std::string::npos);
}

TEST_F(PngFiles, AnEightBitPngIsNotADepthMap) {
    ASSERT_TRUE(writePng(path("gray.png"), cv::Mat(4, 4, CV_8UC1, cv::Scalar(3)), 1));
    auto depth = devices::replay::readDepthPng(path("gray.png"), 0.001);
    ASSERT_FALSE(depth);
    EXPECT_NE(depth.error().message.find("found a 1-channel 8-bit image"), std::string::npos)
        << depth.error().message;
}

// TUM's depth PNG was written by another tool: the values OpenCV reads are the values we read.
TEST(PngCodec, TumDepthDecodesAsOpenCvReadsIt) {
    const std::string file = test::dataPath("tum_frame/TUM_depth.png");
    auto ours = readPng(file);
    ASSERT_TRUE(ours) << ours.error().message;
    const cv::Mat theirs = cv::imread(file, cv::IMREAD_UNCHANGED);
    ASSERT_EQ(theirs.type(), CV_16UC1);
    EXPECT_TRUE(same(*ours, theirs));
    double maxValue = 0.0;
    cv::minMaxLoc(*ours, nullptr, &maxValue);
    EXPECT_GT(maxValue, 255.0) << "both bytes of the samples matter";
}

TEST(PngCodec, TumColorAndAnInterlacedPngDecodeAsOpenCvReadsThem) {
    const std::string color = test::dataPath("tum_frame/TUM_color.png");
    auto ours = readPng(color, PngPixels::Rgb8);
    ASSERT_TRUE(ours) << ours.error().message;
    cv::Mat theirs = cv::imread(color, cv::IMREAD_COLOR);
    cv::cvtColor(theirs, theirs, cv::COLOR_BGR2RGB);
    EXPECT_TRUE(same(*ours, theirs));

    const std::string interlaced = test::dataPath("middlebury_upsampling/dolls/depth_1_n.png");
    auto gray = readPng(interlaced);
    ASSERT_TRUE(gray) << gray.error().message;
    EXPECT_TRUE(same(*gray, cv::imread(interlaced, cv::IMREAD_UNCHANGED)));
}

TEST_F(PngFiles, ColorImagesReadFromPngAndJpegAsRgb) {
    cv::Mat bgr(24, 32, CV_8UC3);
    for (int y = 0; y < bgr.rows; ++y)
        for (int x = 0; x < bgr.cols; ++x)
            bgr.at<cv::Vec3b>(y, x) = {static_cast<std::uint8_t>(8 * x), static_cast<std::uint8_t>(10 * y),
                                       90};
    std::vector<std::uint8_t> jpeg;
    ASSERT_TRUE(cv::imencode(".jpg", bgr, jpeg, {cv::IMWRITE_JPEG_QUALITY, 95}));
    ASSERT_TRUE(base::writeFileAtomically(path("color.jpg"), jpeg));
    cv::Mat rgb;
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    ASSERT_TRUE(writePng(path("color.png"), rgb, 1));
    for (const char* name : {"color.png", "color.jpg"}) {
        auto image = devices::replay::readColorImage(path(name));
        ASSERT_TRUE(image) << image.error().message;
        ASSERT_EQ(image->format, PixelFormat::Rgb24);
        const cv::Mat read(image->height, image->width, CV_8UC3,
                           const_cast<std::uint8_t*>(image->bytes->data()));
        ASSERT_EQ(read.size(), rgb.size()) << name;
        // PNG is lossless; JPEG's quantisation and chroma subsampling stay within a few levels here.
        EXPECT_LE(cv::norm(read, rgb, cv::NORM_INF), std::string(name) == "color.png" ? 0.0 : 24.0) << name;
    }
}

} // namespace
} // namespace dc::frame
