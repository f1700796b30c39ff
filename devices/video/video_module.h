#pragma once

#include "devices/video/video_codec.h"

// What depthcloud-video.so exports to the loader (video_codec.cpp): one table, found by name with dlsym.
// The version changes with the table or the interfaces, so a module from another build is refused rather
// than called through a stale layout.
namespace dc::devices::video {

inline constexpr int kVideoModuleVersion = 1;
inline constexpr const char* kVideoModuleEntry = "dcVideoModule";

struct VideoModule {
    int version;
    // nullptr where the file cannot be opened or decoded.
    std::unique_ptr<VideoReader> (*openReader)(const std::string& path);
    // nullptr where no encoder accepts `fourcc`, four characters such as "avc1".
    std::unique_ptr<VideoWriter> (*openWriter)(const std::string& path, const std::string& fourcc, double fps,
                                               cv::Size size);
};

} // namespace dc::devices::video

extern "C" const dc::devices::video::VideoModule* dcVideoModule();
