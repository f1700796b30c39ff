#include "devices/recording/recording_reader.h"
#include "devices/replay/importers.h"

#include <filesystem>

namespace dc::devices::replay {

namespace {

class RecordingSource final : public ReplaySource {
public:
    explicit RecordingSource(recording::RecordingReader reader) : reader_(std::move(reader)) {}

    void init() {
        warnings_ = reader_.warnings();
        for (std::size_t i = 1; i < reader_.frameCount(); ++i) {
            if (reader_.timestampNs(i) < reader_.timestampNs(i - 1)) {
                warnings_.push_back(reader_.name() + ": timestamps go backwards at frame " +
                                    std::to_string(i) +
                                    "; seeking by time uses the first run of increasing timestamps");
                break;
            }
        }
        if (reader_.device()) {
            description_ = reader_.device()->description;
            capabilities_ = reader_.device()->capabilities;
            return;
        }
        // No description chunk: what the first readable frame holds is the best account of the device.
        for (std::size_t i = 0; i < reader_.frameCount(); ++i) {
            auto f = reader_.frame(i);
            if (!f)
                continue;
            capabilities_ = {.sceneDepth = f->sceneDepth.has_value(),
                             .smoothedSceneDepth = f->smoothedSceneDepth.has_value(),
                             .confidence = f->sceneDepth && !f->sceneDepth->confidence.empty(),
                             .color = !f->capturedImage.empty(),
                             .pose = f->pose.has_value()};
            break;
        }
        description_ = "unknown device";
    }

    std::string description() const override {
        return "recording " + std::filesystem::path(reader_.name()).filename().string() + " (" +
               description_ + ")";
    }
    Capabilities capabilities() const override {
        Capabilities c = capabilities_;
        c.nominalFps = recordedFps();
        return c;
    }
    std::size_t frameCount() const override { return reader_.frameCount(); }
    std::int64_t timestampNs(std::size_t i) const override { return reader_.timestampNs(i); }
    Expected<frame::Frame> frame(std::size_t i) override { return reader_.frame(i); }
    std::vector<std::string> warnings() const override { return warnings_; }

private:
    recording::RecordingReader reader_;
    std::string description_;
    Capabilities capabilities_;
    std::vector<std::string> warnings_;
};

} // namespace

Expected<std::unique_ptr<ReplaySource>> openRecordingSource(const std::string& path) {
    auto reader = recording::RecordingReader::open(path);
    if (!reader)
        return reader.error();
    auto source = std::make_unique<RecordingSource>(std::move(*reader));
    source->init();
    return std::unique_ptr<ReplaySource>(std::move(source));
}

} // namespace dc::devices::replay
