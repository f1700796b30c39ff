#include "frame/frame.h"

#include "frame/camera_model.h"

#include <cmath>

namespace dc::frame {

Intrinsics Intrinsics::scaledTo(int newWidth, int newHeight) const {
    const double sx = static_cast<double>(newWidth) / width;
    const double sy = static_cast<double>(newHeight) / height;
    return {fx * sx, fy * sy, cx * sx, cy * sy, newWidth, newHeight};
}

bool Intrinsics::valid() const {
    return width > 0 && height > 0 && std::isfinite(fx) && std::isfinite(fy) && std::isfinite(cx) &&
           std::isfinite(cy) && fx > 0.0 && fy > 0.0;
}

const char* toString(PixelFormat format) {
    switch (format) {
    case PixelFormat::Nv12:
        return "NV12";
    case PixelFormat::Yuyv:
        return "YUYV";
    case PixelFormat::Rgb24:
        return "RGB24";
    case PixelFormat::Jpeg:
        return "JPEG";
    }
    return "unknown";
}

std::size_t CapturedImage::byteSize(PixelFormat format, int width, int height) {
    const auto w = static_cast<std::size_t>(width);
    const auto h = static_cast<std::size_t>(height);
    switch (format) {
    case PixelFormat::Nv12:
        return w * h + 2 * ((w + 1) / 2) * ((h + 1) / 2);
    case PixelFormat::Yuyv:
        return 4 * ((w + 1) / 2) * h; // 4 bytes per horizontal pixel pair
    case PixelFormat::Rgb24:
        return 3 * w * h;
    case PixelFormat::Jpeg:
        return 0;
    }
    return 0;
}

Intrinsics Frame::depthIntrinsics() const {
    if (!sceneDepth || sceneDepth->depthMeters.empty())
        return {};
    return depthIntrinsicsAt(sceneDepth->depthMeters.width, sceneDepth->depthMeters.height);
}

Intrinsics Frame::depthIntrinsicsAt(int width, int height) const {
    return (rig ? rig->depth.intrinsics : cameraIntrinsics).scaledTo(width, height);
}

} // namespace dc::frame
