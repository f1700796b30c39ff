#include "devices/image_io.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <unistd.h>
#include <vector>

namespace dc::devices {

Status writeFileAtomically(const std::string& path, std::span<const std::uint8_t> bytes) {
    // The pid keeps two processes writing the same path from sharing a temporary file.
    const std::string tmp = path + ".tmp." + std::to_string(::getpid());
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out)
            return Error{"cannot write " + path + ": " + std::strerror(errno)};
        out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
        out.flush();
        if (!out) {
            out.close();
            std::remove(tmp.c_str());
            return Error{"cannot write " + path + ": write failed (disk full?)"};
        }
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const std::string reason = std::strerror(errno);
        std::remove(tmp.c_str());
        return Error{"cannot rename " + tmp + " to " + path + ": " + reason};
    }
    return {};
}

Status writeRgbaPng(const std::string& path, int width, int height, const std::uint8_t* rgba) {
    if (width <= 0 || height <= 0 || rgba == nullptr)
        return Error{"cannot write " + path + ": empty image"};
    const cv::Mat view(height, width, CV_8UC4, const_cast<std::uint8_t*>(rgba));
    cv::Mat bgra;
    cv::cvtColor(view, bgra, cv::COLOR_RGBA2BGRA);
    std::vector<std::uint8_t> encoded;
    try {
        if (!cv::imencode(".png", bgra, encoded, {cv::IMWRITE_PNG_COMPRESSION, 3}))
            return Error{"cannot encode " + path + " as PNG"};
    } catch (const cv::Exception& e) {
        return Error{"cannot encode " + path + " as PNG: " + e.what()};
    }
    return writeFileAtomically(path, encoded);
}

Status writeTextFile(const std::string& path, const std::string& text) {
    return writeFileAtomically(path, {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
}

} // namespace dc::devices
