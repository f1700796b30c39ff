#include "frame/calibration_fields.h"

#include <cmath>

namespace dc::frame::fields {

namespace {

// A rig whose sensors are farther apart than this is a calibration in millimetres read as meters.
constexpr double kMaxBaselineMeters = 1.0;
// R Rᵀ may differ from I by rounding in the file: calibration tools print 6 to 9 digits.
constexpr double kRotationTolerance = 1e-4;

Status appendNumber(const cv::FileNode& item, const std::string& field, const std::string& origin,
                    std::vector<double>& out) {
    if (item.isSeq()) {
        for (const cv::FileNode& inner : item)
            if (Status s = appendNumber(inner, field, origin, out); !s)
                return s;
        return {};
    }
    if (item.isString() && (item.string() == ".nan" || item.string() == "nan")) {
        out.push_back(std::nan(""));
        return {};
    }
    if (!item.isInt() && !item.isReal())
        return fieldError(origin, field, "expected numbers");
    out.push_back(static_cast<double>(item));
    return {};
}

} // namespace

Error fieldError(const std::string& origin, const std::string& field, const std::string& problem) {
    return Error{origin + ": " + field + ": " + problem};
}

Named firstOf(const cv::FileNode& parent, std::initializer_list<const char*> names) {
    for (const char* name : names) {
        cv::FileNode node = parent[name];
        if (!node.empty())
            return {node, name};
    }
    return {{}, *names.begin()};
}

Expected<std::vector<double>> numbers(const cv::FileNode& node, const std::string& field,
                                      const std::string& origin, std::size_t count) {
    if (node.empty())
        return fieldError(origin, field, "missing");
    std::vector<double> out;
    if (Status s = appendNumber(node.isMap() ? node["data"] : node, field, origin, out); !s)
        return s.error();
    if (count > 0 && out.size() != count)
        return fieldError(origin, field,
                          "expected " + std::to_string(count) + " values, found " +
                              std::to_string(out.size()));
    for (double v : out)
        if (!std::isfinite(v))
            return fieldError(origin, field, "not a finite number");
    return out;
}

Expected<std::array<int, 2>> imageSize(const cv::FileNode& node, const std::string& field,
                                       const std::string& origin) {
    auto size = numbers(node, field, origin, 2);
    if (!size)
        return size.error();
    const double w = (*size)[0], h = (*size)[1];
    if (!(w >= 1 && h >= 1 && w <= 65535 && h <= 65535) || w != std::floor(w) || h != std::floor(h))
        return fieldError(origin, field, "expected [width, height] in whole pixels");
    return std::array<int, 2>{static_cast<int>(w), static_cast<int>(h)};
}

Status checkIntrinsics(const Intrinsics& k, const std::string& field, const std::string& origin) {
    if (!std::isfinite(k.fx) || !std::isfinite(k.fy) || !std::isfinite(k.cx) || !std::isfinite(k.cy))
        return fieldError(origin, field, "not a finite number");
    if (!(k.fx > 0.0 && k.fy > 0.0))
        return fieldError(origin, field, "focal length must be positive");
    return {};
}

Status checkTransform(const RigidTransform& transform, const std::string& rotationField,
                      const std::string& translationField, const std::string& origin) {
    const double error = rotationError(transform.rotation);
    if (!(error <= kRotationTolerance))
        return fieldError(origin, rotationField, "not a rotation (orthonormal with determinant +1)");
    const auto& t = transform.translationMeters;
    if (!(std::hypot(t[0], t[1], t[2]) <= kMaxBaselineMeters))
        return fieldError(origin, translationField,
                          "the sensors would be more than 1 m apart (the translation is in meters)");
    return {};
}

} // namespace dc::frame::fields
