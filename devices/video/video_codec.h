#pragma once

#include "base/expected.h"

#include <opencv2/core.hpp>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

// Video files (a Stray Scanner capture's rgb.mp4) through OpenCV's videoio, loaded only when a video is
// first opened: videoio links FFmpeg, GStreamer, GDAL and their codecs, a hundred and more libraries that
// nothing else in depthcloud needs. The implementation is a module, depthcloud-video.so, looked for beside
// the executable and then where it is installed (lib/depthcloud/ beside bin/). DC_VIDEO_MODULE=PATH names
// the module to load instead (the tests point it at the build's, or at a missing file to see the error).
namespace dc::devices::video {

class VideoReader {
public:
    virtual ~VideoReader() = default;
    // Decodes the next frame as 8-bit BGR; false at the end or where it cannot be decoded.
    virtual bool read(cv::Mat& bgr) = 0;
    // Decodes the next frame without converting it, to skip it.
    virtual bool grab() = 0;
    // Makes frame `index` the next one read.
    virtual void seek(std::size_t index) = 0;
    // The number of frames the container announces.
    virtual long long frameCount() const = 0;
};

class VideoWriter {
public:
    virtual ~VideoWriter() = default;
    // Appends an 8-bit BGR frame of the size the writer was opened with.
    virtual void write(const cv::Mat& bgr) = 0;
    // Finishes the file (its index); nothing is written after.
    virtual void close() = 0;
};

// Loads the module (once per process; later calls return the first answer): an error says, on one line, why
// no video can be read or written ("video support not installed: " and the loader's reason).
Status loadVideoSupport();
// Whether an error (from any layer above, whatever it prefixed) is loadVideoSupport's: the installation's
// failure rather than the input's, which the command line reports with exit code 1, not 2.
bool isVideoSupportMissing(const Error& error);

// Opens a video file for reading. "video support not installed: ..." where the module cannot be loaded;
// the reason a file cannot be decoded is the caller's to phrase, so that is an error naming nothing more.
Expected<std::unique_ptr<VideoReader>> openVideoReader(const std::string& path);
// Creates a video file with the first of `fourccs` ("avc1", "mp4v", ...) that an encoder accepts; the
// container follows the file's extension.
Expected<std::unique_ptr<VideoWriter>>
openVideoWriter(const std::string& path, const std::vector<std::string>& fourccs, double fps, cv::Size size);

} // namespace dc::devices::video
