// depthcloud-video.so: the video interface (video_codec.h) over OpenCV's videoio, in a module of its own so
// that only a process that opens a video loads videoio and FFmpeg.
#include "devices/video/video_module.h"

#include <opencv2/videoio.hpp>

namespace dc::devices::video {

namespace {

class OpenCvReader final : public VideoReader {
public:
    bool open(const std::string& path) { return capture_.open(path, cv::CAP_FFMPEG); }
    bool read(cv::Mat& bgr) override { return capture_.read(bgr) && !bgr.empty(); }
    bool grab() override { return capture_.grab(); }
    void seek(std::size_t index) override {
        capture_.set(cv::CAP_PROP_POS_FRAMES, static_cast<double>(index));
    }
    long long frameCount() const override {
        return static_cast<long long>(capture_.get(cv::CAP_PROP_FRAME_COUNT));
    }

private:
    // get() is not const in OpenCV's interface, though it changes nothing a caller sees.
    mutable cv::VideoCapture capture_;
};

class OpenCvWriter final : public VideoWriter {
public:
    bool open(const std::string& path, const std::string& fourcc, double fps, cv::Size size) {
        return fourcc.size() == 4 &&
               writer_.open(path, cv::VideoWriter::fourcc(fourcc[0], fourcc[1], fourcc[2], fourcc[3]), fps,
                            size);
    }
    void write(const cv::Mat& bgr) override { writer_.write(bgr); }
    void close() override { writer_.release(); }

private:
    cv::VideoWriter writer_;
};

// OpenCV throws where a backend fails outright; the interface reports that as "cannot open".
std::unique_ptr<VideoReader> openReader(const std::string& path) {
    try {
        auto reader = std::make_unique<OpenCvReader>();
        return reader->open(path) ? std::move(reader) : nullptr;
    } catch (const cv::Exception&) {
        return nullptr;
    }
}

std::unique_ptr<VideoWriter> openWriter(const std::string& path, const std::string& fourcc, double fps,
                                        cv::Size size) {
    try {
        auto writer = std::make_unique<OpenCvWriter>();
        return writer->open(path, fourcc, fps, size) ? std::move(writer) : nullptr;
    } catch (const cv::Exception&) {
        return nullptr;
    }
}

constexpr VideoModule kModule{kVideoModuleVersion, openReader, openWriter};

} // namespace

} // namespace dc::devices::video

extern "C" const dc::devices::video::VideoModule* dcVideoModule() {
    return &dc::devices::video::kModule;
}
