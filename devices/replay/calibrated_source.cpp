#include "devices/replay/importers.h"
#include "frame/calibration.h"

namespace dc::devices::replay {

namespace {

class CalibratedSource final : public ReplaySource {
public:
    CalibratedSource(std::unique_ptr<ReplaySource> inner, frame::Intrinsics calibration, std::string path)
        : inner_(std::move(inner)), calibration_(calibration), path_(std::move(path)) {}

    std::string description() const override { return inner_->description() + ", calibration " + path_; }
    Capabilities capabilities() const override { return inner_->capabilities(); }
    std::size_t frameCount() const override { return inner_->frameCount(); }
    std::int64_t timestampNs(std::size_t i) const override { return inner_->timestampNs(i); }
    std::vector<std::string> warnings() const override { return inner_->warnings(); }
    void setDecodeColor(bool decode) override { inner_->setDecodeColor(decode); }

    Expected<frame::Frame> frame(std::size_t i) override {
        auto frame = inner_->frame(i);
        if (!frame)
            return frame;
        // The matrix belongs to the camera image, scaled to the size it is captured at here.
        int w = frame->cameraIntrinsics.width, h = frame->cameraIntrinsics.height;
        if (!frame->capturedImage.empty()) {
            w = frame->capturedImage.width;
            h = frame->capturedImage.height;
        } else if ((w <= 0 || h <= 0) && frame->sceneDepth) {
            w = frame->sceneDepth->depthMeters.width;
            h = frame->sceneDepth->depthMeters.height;
        }
        frame->cameraIntrinsics = calibration_.scaledTo(w, h);
        return frame;
    }

private:
    std::unique_ptr<ReplaySource> inner_;
    frame::Intrinsics calibration_;
    std::string path_;
};

} // namespace

Expected<std::unique_ptr<ReplaySource>> withCalibration(std::unique_ptr<ReplaySource> source,
                                                        const std::string& calibrationPath) {
    auto calibration = frame::loadCalibration(calibrationPath);
    if (!calibration)
        return calibration.error();
    return std::unique_ptr<ReplaySource>(
        std::make_unique<CalibratedSource>(std::move(source), calibration->intrinsics, calibrationPath));
}

} // namespace dc::devices::replay
