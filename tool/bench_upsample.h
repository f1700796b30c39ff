#pragma once

// Internals of `depthcloud bench upsample`, shared by its source files.

#include "base/expected.h"
#include "frame/frame.h"
#include "tool/bench_upsample_options.h"

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace dc::tool::upsample {

// One upsampling problem: a low-resolution depth map and a guide image, to be brought to the output size.
struct Problem {
    std::string scene;
    double factor = 1.0;       // output width / input width
    frame::DepthData low;      // depth in the scene's units (meters, or 8-bit disparity levels)
    cv::Mat guideGray;         // 8-bit luma at the guide's own size
    cv::Mat guideColor;        // 8-bit BGR, same size
    frame::Plane<float> truth; // ground truth at the output size
    // Pixels that count (nonzero); empty = all pixels.
    frame::Plane<std::uint8_t> evaluated;
    float fitNoise = 0.0f; // the depth's noise floor in its units (our filter's fitNoise)
    float noise = 0.0f;    // the depth's noise (standard deviation) in its units (our global smoother's)
    std::string units;
};

struct Method {
    std::string name;
    std::function<frame::Plane<float>(const Problem&)> run;
};

// The module that holds the OpenCV contrib peers, beside the depthcloud binary.
inline constexpr const char* kPeersModule = "depthcloud-upsample-peers.so";
// OpenCV guided / joint bilateral / fast global smoother, from kPeersModule; empty where it is not there.
const std::vector<Method>& peerMethods();
// nearest, bilinear, bicubic (Keys a = -0.5), the peers (where present), ours.
std::vector<Method> allMethods();
// The method of that name (one of allMethods()).
const Method& methodNamed(const std::string& name);
// The bicubic used for the reference numbers (Keys a = -0.5, MATLAB/PIL's; OpenCV's INTER_CUBIC is a =
// -0.75).
frame::Plane<float> bicubic(const frame::Plane<float>& low, int width, int height);

// The noisy-Middlebury scenes of `dataDir` (every <scene>/<scene>_big.png with its inputs).
Expected<std::vector<Problem>> middleburyProblems(const std::string& dataDir,
                                                  const std::vector<int>& factors);
// The synthetic desk scene as an ARKit frame: sensor depth at depthWidth x depthHeight, camera image at
// cameraWidth x cameraHeight, output and exact ground truth at half the camera size.
Problem syntheticProblem(int depthWidth, int depthHeight, int cameraWidth, int cameraHeight);

// Reference rows read from a PROVENANCE.txt: "<scene> x<f> MAD/RMSE" for bicubic, published MAD rows.
struct Provenance {
    std::vector<std::tuple<std::string, int, double, double>> bicubic;  // scene, factor, MAD, RMSE
    std::vector<std::pair<std::string, std::vector<double>>> published; // method, 12 MADs (4 scenes x 3)
    std::vector<std::string> publishedScenes;                           // art, book, dolls, laundry
};
Provenance readProvenance(const std::string& path);

// The best published result's MAD per (scene, factor), from lines "<scene> <factor> <mad>" ('#' comments);
// empty when the file is missing.
std::map<std::pair<std::string, int>, double> readRcg(const std::string& path);

// Median wall time of `runs` calls after one warm-up call, milliseconds.
double medianMilliseconds(int runs, const std::function<void()>& call);

// A labelled point of the error-versus-time chart.
struct ChartPoint {
    std::string label;
    double milliseconds = 0.0;
    double error = 0.0;
};
struct ChartPanel {
    std::string title;
    std::string errorLabel;
    std::vector<ChartPoint> points;
};
// Draws the panels side by side (log time axis) and writes them as PNG atomically.
Status writeChart(const std::string& path, const std::vector<ChartPanel>& panels);

// The ARKit case (`problem`: 256x192 depth, 1920x1440 guide, 960x720 output): ours against OpenCV's
// filters at one thread and at all threads.
nlohmann::json benchArkitFrame(const BenchUpsampleOptions& options, const Problem& problem);
// The whole processing chain per ARKit frame: confidence filter, smoothing, upsampling, cloud preparation.
nlohmann::json benchChain(const BenchUpsampleOptions& options);
// Cost of the fog and aura images on the ARKit frame, from sensor and from upsampled depth.
nlohmann::json benchEffects(const BenchUpsampleOptions& options);
// Temporal noise reduction and step lag of the smoothing at its default settings.
nlohmann::json benchSmoothing(const BenchUpsampleOptions& options);

} // namespace dc::tool::upsample
