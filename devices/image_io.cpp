#include "devices/image_io.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <unistd.h>

namespace dc::devices {

namespace {

std::string temporaryName(const std::string& path) { return path + ".tmp." + std::to_string(::getpid()); }

Status commit(const std::string& tmp, const std::string& path) {
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const std::string reason = std::strerror(errno);
        std::remove(tmp.c_str());
        return Error{"cannot rename " + tmp + " to " + path + ": " + reason};
    }
    return {};
}

} // namespace

Status writeRgbaPng(const std::string& path, int width, int height, const std::uint8_t* rgba) {
    if (width <= 0 || height <= 0 || rgba == nullptr)
        return Error{"cannot write " + path + ": empty image"};
    const cv::Mat view(height, width, CV_8UC4, const_cast<std::uint8_t*>(rgba));
    cv::Mat bgra;
    cv::cvtColor(view, bgra, cv::COLOR_RGBA2BGRA);
    const std::string tmp = temporaryName(path);
    bool written = false;
    try {
        written = cv::imwrite(tmp, bgra, {cv::IMWRITE_PNG_COMPRESSION, 3});
    } catch (const cv::Exception& e) {
        std::remove(tmp.c_str());
        return Error{"cannot write " + path + ": " + e.what()};
    }
    if (!written) {
        std::remove(tmp.c_str());
        return Error{"cannot write " + path + " (is the directory writable?)"};
    }
    return commit(tmp, path);
}

Status writeTextFile(const std::string& path, const std::string& text) {
    const std::string tmp = temporaryName(path);
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out)
            return Error{"cannot write " + path + ": " + std::strerror(errno)};
        out << text;
        out.flush();
        if (!out) {
            out.close();
            std::remove(tmp.c_str());
            return Error{"cannot write " + path + ": write failed"};
        }
    }
    return commit(tmp, path);
}

} // namespace dc::devices
