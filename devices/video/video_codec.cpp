#include "devices/video/video_codec.h"

#include "devices/video/video_module.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>

namespace dc::devices::video {

namespace {

namespace fs = std::filesystem;

constexpr const char* kModuleFile = "depthcloud-video.so";
constexpr const char* kNotInstalled = "video support not installed: ";

// Where the module is: DC_VIDEO_MODULE when set, else beside the executable (the build tree) if it is there,
// else where `cmake --install` and the .deb put it, DC_VIDEO_MODULE_DIR relative to the executable's bin/.
fs::path modulePath() {
    if (const char* path = std::getenv("DC_VIDEO_MODULE"); path != nullptr && *path != '\0')
        return path;
    std::error_code ec;
    const fs::path dir = fs::read_symlink("/proc/self/exe", ec).parent_path();
    if (fs::exists(dir / kModuleFile, ec))
        return dir / kModuleFile;
    return (dir / DC_VIDEO_MODULE_DIR / kModuleFile).lexically_normal();
}

// Loaded once and kept for the process: FFmpeg's threads and codecs outlive any one video.
Expected<const VideoModule*> loadModule() {
    const fs::path path = modulePath();
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr)
        return Error{kNotInstalled + std::string(::dlerror())};
    using Entry = const VideoModule* (*)();
    const auto entry = reinterpret_cast<Entry>(::dlsym(handle, kVideoModuleEntry));
    const VideoModule* module = entry != nullptr ? entry() : nullptr;
    if (module == nullptr || module->version != kVideoModuleVersion)
        return Error{kNotInstalled + path.string() + " is not this build's video module"};
    return module;
}

const Expected<const VideoModule*>& videoModule() {
    static const Expected<const VideoModule*> module = loadModule();
    return module;
}

} // namespace

Status loadVideoSupport() {
    const auto& module = videoModule();
    if (!module)
        return module.error();
    return {};
}

bool isVideoSupportMissing(const Error& error) {
    return error.message.find(kNotInstalled) != std::string::npos;
}

Expected<std::unique_ptr<VideoReader>> openVideoReader(const std::string& path) {
    const auto& module = videoModule();
    if (!module)
        return module.error();
    auto reader = (*module)->openReader(path);
    if (!reader)
        return Error{"cannot open " + path};
    return reader;
}

Expected<std::unique_ptr<VideoWriter>>
openVideoWriter(const std::string& path, const std::vector<std::string>& fourccs, double fps, cv::Size size) {
    const auto& module = videoModule();
    if (!module)
        return module.error();
    for (const std::string& fourcc : fourccs)
        if (auto writer = (*module)->openWriter(path, fourcc, fps, size))
            return writer;
    return Error{"cannot create " + path};
}

} // namespace dc::devices::video
