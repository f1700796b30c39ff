// `depthcloud bench upsample` end to end on a tiny data set of the noisy-Middlebury layout: it must print
// the table and the protocol check, and write a valid JSON report and PNG chart. Seconds, not minutes.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <string>
#include <sys/wait.h>

namespace {

namespace fs = std::filesystem;

// A 96x64 scene: a slanted background and a square in front, a colour guide with the square's edge, and
// the four noisy inputs at 1/2 .. 1/16 (area-downsampled plus noise, as the real benchmark's).
void writeTinyScene(const fs::path& dir) {
    fs::create_directories(dir / "tiny");
    cv::Mat truth(64, 96, CV_8U), color(64, 96, CV_8UC3);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 96; ++x) {
            const bool square = x > 30 && x < 70 && y > 15 && y < 50;
            truth.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(square ? 200 : 60 + x / 2);
            color.at<cv::Vec3b>(y, x) = square ? cv::Vec3b(40, 60, 200) : cv::Vec3b(180, 170, 150);
        }
    cv::imwrite((dir / "tiny" / "tiny_big.png").string(), truth);
    cv::imwrite((dir / "tiny" / "tiny_color.png").string(), color);
    cv::RNG rng(5);
    for (int k = 1; k <= 4; ++k) {
        cv::Mat low, noise(64 >> k, 96 >> k, CV_32F);
        cv::resize(truth, low, noise.size(), 0, 0, cv::INTER_AREA);
        rng.fill(noise, cv::RNG::NORMAL, 0.0, 5.0);
        low.convertTo(low, CV_32F);
        cv::Mat noisy = low + noise;
        noisy.convertTo(low, CV_8U);
        cv::imwrite((dir / "tiny" / ("depth_" + std::to_string(k) + "_n.png")).string(), low);
    }
    std::ofstream(dir / "PROVENANCE.txt") << "made by bench_upsample_test\n";
    std::ofstream(dir / "rcg_mad.txt")
        << "# scene factor mad\ntiny 2 0.5\ntiny 4 1.0\ntiny 8 2.0\ntiny 16 4.0\n";
}

struct Output {
    int exitCode = -1;
    std::string text;
};

Output runBinary(const std::string& arguments, const std::string& binary = DEPTHCLOUD_BINARY) {
    Output out;
    FILE* pipe = ::popen((binary + " " + arguments + " 2>&1").c_str(), "r");
    if (!pipe)
        return out;
    char buffer[4096];
    for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;)
        out.text.append(buffer, n);
    const int status = ::pclose(pipe);
    out.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return out;
}

TEST(BenchUpsample, WritesTableJsonAndChartOnTinyInputs) {
    const fs::path dir =
        fs::temp_directory_path() / ("depthcloud-bench-upsample-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    writeTinyScene(dir / "data");
    const std::string json = (dir / "report.json").string(), chart = (dir / "chart.png").string();
    const Output out = runBinary("bench upsample --quick --runs 10 --data " + (dir / "data").string() +
                                 " --json " + json + " --chart " + chart);
    ASSERT_EQ(out.exitCode, 0) << out.text;
    EXPECT_NE(out.text.find("median ms"), std::string::npos) << out.text;
    EXPECT_TRUE(std::regex_search(out.text, std::regex("ours fast s=4 +tiny +x16"))) << "a table row";
    EXPECT_NE(out.text.find("protocol check"), std::string::npos);
    EXPECT_NE(out.text.find("whole chain per ARKit frame"), std::string::npos);
    EXPECT_NE(out.text.find("temporal smoothing"), std::string::npos);

    std::ifstream in(json);
    const nlohmann::json report = nlohmann::json::parse(in);
    ASSERT_EQ(report["middlebury"].size(), 4u * 14u) << "4 factors x 14 methods";
    for (const auto& row : report["middlebury"]) {
        EXPECT_GE(row["mad"].get<double>(), 0.0);
        EXPECT_GT(row["medianMs"].get<double>(), 0.0);
    }
    const auto global = std::find_if(report["rcg"].begin(), report["rcg"].end(),
                                     [](const nlohmann::json& m) { return m["method"] == "ours global"; });
    ASSERT_NE(global, report["rcg"].end()) << "ratios to rcg_mad.txt's figures";
    ASSERT_EQ((*global)["cases"].size(), 4u);
    for (const auto& c : (*global)["cases"])
        EXPECT_NEAR(c["ratio"].get<double>(), c["mad"].get<double>() / c["rcgMad"].get<double>(), 1e-9);
    EXPECT_EQ((*global)["cases"][3]["rcgMad"].get<double>(), 4.0) << "x16 read from the file";
    const auto wholeLevels =
        std::find_if(report["middlebury"].begin(), report["middlebury"].end(),
                     [](const nlohmann::json& r) { return r["method"] == "ours quality, whole levels"; });
    ASSERT_NE(wholeLevels, report["middlebury"].end())
        << "the quality mode rounded, beside RCG's 8-bit outputs";
    EXPECT_TRUE(report["chain"]["fast"].contains("medianMs"));
    EXPECT_TRUE(report["chain"]["global"].contains("medianMs")) << "the chain with the global smoother too";
    EXPECT_GT(report["smoothing"]["flickerReduction"].get<double>(), 1.0);

    const cv::Mat png = cv::imread(chart, cv::IMREAD_COLOR);
    ASSERT_FALSE(png.empty()) << "a PNG OpenCV can decode";
    EXPECT_GT(png.cols, png.rows) << "two panels side by side";
    cv::Scalar mean, stddev;
    cv::meanStdDev(png.reshape(1), mean, stddev);
    EXPECT_GT(stddev[0], 5.0) << "not blank";
    fs::remove_all(dir);
}

TEST(BenchUpsample, RejectsTooFewRunsAndAMissingDataDirectory) {
    EXPECT_EQ(runBinary("bench upsample --runs 3").exitCode, 2);
    EXPECT_EQ(runBinary("bench upsample --data /nonexistent/depthcloud").exitCode, 2);
}

// The peers live in a module beside the binary, which an installed depthcloud lacks: the binary itself does
// not link OpenCV's contrib filters, and the bench without its peers says so instead of measuring ours alone.
TEST(BenchUpsample, ThePeersAreAModuleOfTheirOwnAndTheBenchRefusesToRunWithoutThem) {
    Output linked;
    FILE* pipe = ::popen(("ldd " + std::string(DEPTHCLOUD_BINARY)).c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    char buffer[4096];
    for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;)
        linked.text.append(buffer, n);
    ASSERT_EQ(::pclose(pipe), 0);
    EXPECT_NE(linked.text.find("libopencv_core"), std::string::npos) << linked.text;
    EXPECT_EQ(linked.text.find("libopencv_ximgproc"), std::string::npos) << linked.text;

    const fs::path alone =
        fs::temp_directory_path() / ("depthcloud-without-peers-" + std::to_string(::getpid()));
    fs::create_directories(alone);
    fs::copy_file(DEPTHCLOUD_BINARY, alone / "depthcloud");
    const Output out = runBinary("bench upsample --quick", (alone / "depthcloud").string());
    EXPECT_EQ(out.exitCode, 1) << out.text;
    EXPECT_NE(out.text.find("depthcloud-upsample-peers.so"), std::string::npos) << out.text;
    EXPECT_EQ(out.text.find("ours"), std::string::npos) << "no table of ours alone";
    fs::remove_all(alone);
}

} // namespace
