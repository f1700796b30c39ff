// The methods and scenes of `depthcloud bench upsample`.

#include "devices/synthetic/synthetic_scene.h"
#include "frame/png_codec.h"
#include "processing/camera_image.h"
#include "processing/global_smoother.h"
#include "processing/guided_filter.h"
#include "processing/quality.h"
#include "processing/upsampling_stage.h"
#include "tool/bench_upsample.h"
#include "tool/bench_upsample_inputs.h"

#include <opencv2/imgproc.hpp>

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

namespace dc::tool::upsample {

namespace {

using frame::Plane;

Plane<float> ours(const Problem& p, int subsample, bool fitWeighted) {
    processing::GuidedFilterParams params;
    params.subsample = subsample;
    params.fitWeighted = fitWeighted;
    params.fitNoise = p.fitNoise;
    params.radius = fitWeighted ? radiusFor(p.factor, 6.0, 1.0) : radiusFor(p.factor, 0.0, 1.5);
    params.epsilon = fitWeighted ? 1e-3f : 1e-4f;
    const processing::GrayView guide{p.guideGray.ptr<std::uint8_t>(0), p.guideGray.cols, p.guideGray.rows,
                                     static_cast<std::ptrdiff_t>(p.guideGray.step[0])};
    return processing::guidedUpsample(p.low, guide, p.truth.width, p.truth.height, params).depthMeters;
}

// The global smoother as the upsampling stage runs it (its parameters from globalSmootherParams), with the
// RGB guide at the output size and its buffers kept between calls.
Plane<float> oursGlobal(const Problem& p, processing::UpsamplingMethod method) {
    thread_local processing::GlobalSmoother smoother;
    processing::UpsamplingParams params;
    params.method = method;
    const cv::Mat& guide = guideAtOutput(p.guideColor, outputSize(p));
    const processing::ColorView view{guide.ptr<std::uint8_t>(0), guide.cols, guide.rows,
                                     static_cast<std::ptrdiff_t>(guide.step[0])};
    return smoother.upsample(p.low, view, processing::globalSmootherParams(params, p.factor, p.noise))
        .depthMeters;
}

// The quality mode with its output rounded to whole disparity levels, on the benchmark's scenes only (the
// synthetic scene's meters are left as they are): the ground truth holds whole levels (8-bit), as published
// output images such as RCG's as a rule do, and on a slanted surface a continuous estimate differs from the
// truth's integer staircase by a quarter level on average where a rounded one mostly matches it. A reading
// aid for the comparison with RCG, not a mode: depthcloud's depths are not quantised.
Plane<float> oursQualityWholeLevels(const Problem& p) {
    Plane<float> out = oursGlobal(p, processing::UpsamplingMethod::Quality);
    if (p.units == "levels")
        for (float& level : out.pixels)
            level = std::round(level);
    return out;
}

// The OpenCV contrib peers, from the module built beside this binary (none where it is missing or cannot be
// loaded: an installed depthcloud ships without it). Loaded once and kept loaded for the process.
std::vector<Method> loadPeers() {
    std::error_code error;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
    if (error)
        return {};
    void* module = ::dlopen((self.parent_path() / kPeersModule).c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!module)
        return {};
    using Entry = void (*)(std::vector<Method>&);
    const auto entry = reinterpret_cast<Entry>(::dlsym(module, "dcUpsamplePeers"));
    std::vector<Method> peers;
    if (entry)
        entry(peers);
    return peers;
}

Plane<float> resizedWith(const Problem& p, int interpolation) {
    cv::Mat out;
    cv::resize(asMat(p.low.depthMeters), out, outputSize(p), 0, 0, interpolation);
    return toPlane(out);
}

double keys(double x) {
    constexpr double a = -0.5;
    x = std::abs(x);
    if (x < 1.0)
        return ((a + 2.0) * x - (a + 3.0)) * x * x + 1.0;
    if (x < 2.0)
        return ((a * x - 5.0 * a) * x + 8.0 * a) * x - 4.0 * a;
    return 0.0;
}

// Taps of one axis: pixel centres aligned, edge samples repeated, weights normalised.
struct CubicTaps {
    std::vector<std::array<int, 4>> index;
    std::vector<std::array<double, 4>> weight;
};

CubicTaps cubicTaps(int from, int to) {
    CubicTaps taps{std::vector<std::array<int, 4>>(to), std::vector<std::array<double, 4>>(to)};
    for (int d = 0; d < to; ++d) {
        const double s = (d + 0.5) * from / to - 0.5;
        const int base = static_cast<int>(std::floor(s)) - 1;
        double total = 0.0;
        for (int k = 0; k < 4; ++k) {
            taps.index[d][k] = std::clamp(base + k, 0, from - 1);
            taps.weight[d][k] = keys(s - (base + k));
            total += taps.weight[d][k];
        }
        for (double& w : taps.weight[d])
            w /= total;
    }
    return taps;
}

} // namespace

Plane<float> bicubic(const Plane<float>& low, int width, int height) {
    const CubicTaps tx = cubicTaps(low.width, width), ty = cubicTaps(low.height, height);
    std::vector<double> rows(static_cast<std::size_t>(low.height) * width);
    for (int y = 0; y < low.height; ++y)
        for (int x = 0; x < width; ++x) {
            double v = 0.0;
            for (int k = 0; k < 4; ++k)
                v += tx.weight[x][k] * low.at(tx.index[x][k], y);
            rows[static_cast<std::size_t>(y) * width + x] = v;
        }
    Plane<float> out(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            double v = 0.0;
            for (int k = 0; k < 4; ++k)
                v += ty.weight[y][k] * rows[static_cast<std::size_t>(ty.index[y][k]) * width + x];
            out.at(x, y) = static_cast<float>(v);
        }
    return out;
}

const std::vector<Method>& peerMethods() {
    static const std::vector<Method> peers = loadPeers();
    return peers;
}

std::vector<Method> allMethods() {
    std::vector<Method> methods = {
        {"nearest", [](const Problem& p) { return resizedWith(p, cv::INTER_NEAREST); }},
        {"bilinear", [](const Problem& p) { return resizedWith(p, cv::INTER_LINEAR); }},
        {"bicubic",
         [](const Problem& p) { return bicubic(p.low.depthMeters, p.truth.width, p.truth.height); }},
        {"ours He GF", [](const Problem& p) { return ours(p, 1, false); }},
        {"ours full", [](const Problem& p) { return ours(p, 1, true); }},
        {"ours fast s=2", [](const Problem& p) { return ours(p, 2, true); }},
        {"ours fast s=4", [](const Problem& p) { return ours(p, 4, true); }},
        {"ours fast s=8", [](const Problem& p) { return ours(p, 8, true); }},
        {"ours global", [](const Problem& p) { return oursGlobal(p, processing::UpsamplingMethod::Global); }},
        {"ours quality",
         [](const Problem& p) { return oursGlobal(p, processing::UpsamplingMethod::Quality); }},
        {"ours quality, whole levels", oursQualityWholeLevels},
    };
    const std::vector<Method>& peers = peerMethods();
    methods.insert(methods.begin() + 3, peers.begin(), peers.end());
    return methods;
}

const Method& methodNamed(const std::string& name) {
    static const std::vector<Method> methods = allMethods();
    return *std::find_if(methods.begin(), methods.end(), [&](const Method& m) { return m.name == name; });
}

namespace {

// An 8-bit gray PNG, as every Middlebury depth map here is; anything else is refused, not converted.
Expected<cv::Mat> readGray8(const std::string& path) {
    auto image = frame::readPng(path);
    if (image && image->type() != CV_8UC1)
        return Error{path + ": expected an 8-bit gray PNG"};
    return image;
}

Expected<Problem> middleburyProblem(const std::filesystem::path& dir, const std::string& scene, int factor) {
    const int level = static_cast<int>(std::lround(std::log2(factor)));
    const std::string input = "depth_" + std::to_string(level) + "_n.png";
    auto truthPng = readGray8((dir / (scene + "_big.png")).string());
    if (!truthPng)
        return truthPng.error();
    auto rgb = frame::readPng((dir / (scene + "_color.png")).string(), frame::PngPixels::Rgb8);
    if (!rgb)
        return rgb.error();
    auto lowPng = readGray8((dir / input).string());
    if (!lowPng)
        return lowPng.error();
    const cv::Mat& truth = *truthPng;
    const cv::Mat& low = *lowPng;
    cv::Mat color;
    cv::cvtColor(*rgb, color, cv::COLOR_RGB2BGR);
    if (color.size() != truth.size())
        return Error{dir.string() + ": " + scene + "_color.png and " + scene + "_big.png differ in size"};
    Problem p;
    p.scene = scene;
    p.factor = static_cast<double>(truth.cols) / low.cols;
    p.low.depthMeters = toPlane(low);
    p.guideColor = color;
    cv::cvtColor(color, p.guideGray, cv::COLOR_BGR2GRAY);
    p.truth = toPlane(truth);
    p.fitNoise = 0.25f; // a quarter disparity level: the 8-bit quantisation step's spread is 0.29
    // The inputs' Gaussian noise (Park et al.): 5.2 levels by the median absolute difference of
    // horizontal neighbours in every input (median |d(x+1) - d(x)| = 5 = 0.954 sigma).
    p.noise = 5.0f;
    p.units = "levels";
    return p;
}

} // namespace

Expected<std::vector<Problem>> middleburyProblems(const std::string& dataDir,
                                                  const std::vector<int>& factors) {
    std::vector<std::filesystem::path> scenes;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dataDir, ec))
        if (entry.is_directory() &&
            std::filesystem::exists(entry.path() / (entry.path().filename().string() + "_big.png")))
            scenes.push_back(entry.path());
    if (ec || scenes.empty())
        return Error{"--data " + dataDir + ": no <scene>/<scene>_big.png found"};
    std::sort(scenes.begin(), scenes.end());
    std::vector<Problem> problems;
    for (const auto& dir : scenes)
        for (int factor : factors) {
            auto p = middleburyProblem(dir, dir.filename().string(), factor);
            if (!p)
                return p.error();
            problems.push_back(std::move(*p));
        }
    return problems;
}

Problem syntheticProblem(int depthWidth, int depthHeight, int cameraWidth, int cameraHeight) {
    const devices::SyntheticScene scene;
    const frame::Pose pose = devices::SyntheticScene::cameraPose(0.0, false);
    const frame::Intrinsics camera = devices::SyntheticScene::cameraIntrinsics(cameraWidth, cameraHeight);
    const int outWidth = (cameraWidth + 1) / 2, outHeight = (cameraHeight + 1) / 2;
    Problem p;
    p.scene = "synthetic";
    p.factor = static_cast<double>(outWidth) / depthWidth;
    p.low = scene.sensorDepth(camera.scaledTo(depthWidth, depthHeight), pose, 1);
    const frame::CapturedImage image = scene.renderImage(camera, pose);
    std::vector<std::uint8_t> scratch;
    const processing::GrayView luma = processing::lumaView(image, scratch);
    p.guideGray = cv::Mat(luma.height, luma.width, CV_8U, const_cast<std::uint8_t*>(luma.pixels)).clone();
    const std::vector<std::uint8_t> rgb = processing::cameraRgb(image, cameraWidth, cameraHeight);
    cv::cvtColor(cv::Mat(cameraHeight, cameraWidth, CV_8UC3, const_cast<std::uint8_t*>(rgb.data())),
                 p.guideColor, cv::COLOR_RGB2BGR);
    p.truth = scene.trueDepth(camera.scaledTo(outWidth, outHeight), pose);
    // Evaluated: true depth exists and the sensor measured the pixel's whole bilinear footprint, so every
    // method has data there and holes do not decide the score.
    p.evaluated = processing::measuredFootprint(p.low.depthMeters, outWidth, outHeight);
    for (std::size_t i = 0; i < p.evaluated.pixels.size(); ++i)
        p.evaluated.pixels[i] = p.evaluated.pixels[i] && p.truth.pixels[i] > 0.0f;
    p.fitNoise = 0.005f; // the sensor's noise at about 1.5 m
    p.noise = 0.005f;
    p.units = "m";
    return p;
}

Provenance readProvenance(const std::string& path) {
    Provenance prov;
    std::ifstream in(path);
    const std::regex bicubicRow(R"(^\s*([a-z]+)\s+((x\d+\s+[\d.]+/[\d.]+\s*)+)$)");
    const std::regex pair(R"(x(\d+)\s+([\d.]+)/([\d.]+))");
    const std::regex header(R"(^\s*method\s+(.*)$)");
    const std::regex publishedRow(R"(^\s*([A-Za-z]+)\s+((?:[\d.]+\s*){12})$)");
    std::string line;
    std::smatch m;
    while (std::getline(in, line)) {
        if (std::regex_match(line, m, bicubicRow)) {
            const std::string scene = m[1], rest = m[2];
            for (std::sregex_iterator it(rest.begin(), rest.end(), pair), end; it != end; ++it)
                prov.bicubic.emplace_back(scene, std::stoi((*it)[1]), std::stod((*it)[2]),
                                          std::stod((*it)[3]));
        } else if (std::regex_match(line, m, header)) {
            std::istringstream names(m[1].str());
            prov.publishedScenes.clear();
            for (std::string s; names >> s;)
                prov.publishedScenes.push_back(s);
        } else if (std::regex_match(line, m, publishedRow)) {
            std::istringstream values(m[2].str());
            std::vector<double> mads;
            for (double v; values >> v;)
                mads.push_back(v);
            prov.published.emplace_back(m[1], mads);
        }
    }
    return prov;
}

std::map<std::pair<std::string, int>, double> readRcg(const std::string& path) {
    std::map<std::pair<std::string, int>, double> rcg;
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream fields(line.substr(0, line.find('#')));
        std::string scene;
        int factor = 0;
        double mad = 0.0;
        if (fields >> scene >> factor >> mad)
            rcg[{scene, factor}] = mad;
    }
    return rcg;
}

double medianMilliseconds(int runs, const std::function<void()>& call) {
    call();
    std::vector<double> ms;
    for (int i = 0; i < std::max(runs, 1); ++i) {
        const auto start = std::chrono::steady_clock::now();
        call();
        ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
    std::nth_element(ms.begin(), ms.begin() + static_cast<std::ptrdiff_t>(ms.size() / 2), ms.end());
    return ms[ms.size() / 2];
}

} // namespace dc::tool::upsample
