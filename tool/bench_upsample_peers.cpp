// The OpenCV contrib filters `depthcloud bench upsample` compares its own with: a module of their own, loaded
// by the bench where it is built beside the binary, so that the shipped depthcloud neither links
// opencv_ximgproc nor depends on OpenCV's contrib package (and what it brings: HDF5, DNN, ...).

#include "tool/bench_upsample.h"
#include "tool/bench_upsample_inputs.h"

#include <opencv2/ximgproc.hpp>

#include <array>

namespace dc::tool::upsample {
namespace {

using frame::Plane;

// What an OpenCV user would feed its filters: the depth scaled bilinearly (holes averaged in) and the
// guide at the output size, into matrices kept from one call to the next as a loop over frames keeps them.
const cv::Mat& bilinearDepth(const Problem& p) {
    thread_local cv::Mat out;
    cv::resize(asMat(p.low.depthMeters), out, outputSize(p), 0, 0, cv::INTER_LINEAR);
    return out;
}

const cv::Mat& unitFloat(const cv::Mat& image8) {
    thread_local cv::Mat out;
    image8.convertTo(out, CV_32F, 1.0 / 255.0);
    return out;
}

// A parameter tuned per factor (x2, x4, x8, x16 on the four public Middlebury scenes), interpolated
// log-linearly in between and held beyond.
double perFactor(double factor, const std::array<double, 4>& values) {
    const double t = std::clamp(std::log2(factor) - 1.0, 0.0, 3.0);
    const int i = std::min(static_cast<int>(t), 2);
    return std::exp(std::log(values[i]) + (t - i) * (std::log(values[i + 1]) - std::log(values[i])));
}

Plane<float> opencvGuided(const Problem& p) {
    thread_local cv::Mat out;
    cv::ximgproc::guidedFilter(unitFloat(guideAtOutput(p.guideColor, outputSize(p))), bilinearDepth(p), out,
                               radiusFor(p.factor, 0.0, 1.0), 1e-2);
    return toPlane(out);
}

Plane<float> opencvJointBilateral(const Problem& p) {
    const double sigmaSpace = std::min(p.factor, 3.0); // its cost grows with sigmaSpace^2
    thread_local cv::Mat out;
    cv::ximgproc::jointBilateralFilter(unitFloat(guideAtOutput(p.guideColor, outputSize(p))),
                                       bilinearDepth(p), out, 2 * static_cast<int>(1.5 * sigmaSpace) + 1, 0.1,
                                       sigmaSpace);
    return toPlane(out);
}

// lambda and sigma_color the best of lambda 30..3000 x sigma 2..16 by mean MAD / RCG's at each factor.
Plane<float> opencvFastGlobalSmoother(const Problem& p) {
    thread_local cv::Mat out;
    cv::ximgproc::fastGlobalSmootherFilter(guideAtOutput(p.guideColor, outputSize(p)), bilinearDepth(p), out,
                                           perFactor(p.factor, {100.0, 100.0, 300.0, 300.0}), 4.0);
    return toPlane(out);
}

} // namespace
} // namespace dc::tool::upsample

// The module's one entry point, found by name with dlsym.
extern "C" void dcUpsamplePeers(std::vector<dc::tool::upsample::Method>& out) {
    using namespace dc::tool::upsample;
    out = {{"opencv guided", opencvGuided},
           {"opencv joint bilateral", opencvJointBilateral},
           {"opencv fast global smoother", opencvFastGlobalSmoother}};
}
