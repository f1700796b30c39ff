#include "devices/replay/importers.h"
#include "frame/calibration.h"

namespace dc::devices::replay {

namespace {

class CalibratedSource final : public ReplaySource {
public:
    CalibratedSource(std::unique_ptr<ReplaySource> inner, frame::Calibration calibration, std::string path)
        : inner_(std::move(inner)), calibration_(std::move(calibration)), path_(std::move(path)) {
        if (calibration_.rig)
            rig_ = std::make_shared<const frame::RigCalibration>(*calibration_.rig);
    }

    std::string description() const override {
        return inner_->description() + ", calibration " + path_ + " (" + calibration_.format + ")";
    }
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
        frame->cameraIntrinsics = calibration_.intrinsics.scaledTo(w, h);
        if (rig_)
            return withRig(std::move(*frame));
        return frame;
    }

private:
    // A two-sensor file fits only streams of its sensors' shapes: anything else would colour every point
    // from the wrong place.
    Expected<frame::Frame> withRig(frame::Frame frame) const {
        const auto depthSize = [&](bool width) {
            return frame.sceneDepth
                       ? (width ? frame.sceneDepth->depthMeters.width : frame.sceneDepth->depthMeters.height)
                       : 0;
        };
        const int colourWidth = frame.capturedImage.empty() ? 0 : frame.capturedImage.width;
        const int colourHeight = frame.capturedImage.empty() ? 0 : frame.capturedImage.height;
        if (Status s = frame::checkStreamSizes(calibration_, depthSize(true), depthSize(false), colourWidth,
                                               colourHeight);
            !s)
            return Error{path_ + ": " + s.error().message};
        frame.rig = rig_;
        return frame;
    }

    std::unique_ptr<ReplaySource> inner_;
    frame::Calibration calibration_;
    std::shared_ptr<const frame::RigCalibration> rig_;
    std::string path_;
};

} // namespace

Expected<std::unique_ptr<ReplaySource>> withCalibration(std::unique_ptr<ReplaySource> source,
                                                        const std::string& calibrationPath) {
    auto calibration = frame::loadCalibration(calibrationPath);
    if (!calibration)
        return calibration.error();
    return std::unique_ptr<ReplaySource>(
        std::make_unique<CalibratedSource>(std::move(source), std::move(*calibration), calibrationPath));
}

} // namespace dc::devices::replay
