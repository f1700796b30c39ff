#include "frame/calibration_fields.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string_view>

namespace dc::frame::fields {

namespace {

// A rig whose sensors are farther apart than this is a calibration in millimetres read as meters.
constexpr double kMaxBaselineMeters = 1.0;
// R Rᵀ may differ from I by rounding in the file: calibration tools print 6 to 9 digits.
constexpr double kRotationTolerance = 1e-4;
// OpenCV's FileStorage begins its YAML with "%YAML:1.0", a spelling of its own: YAML's directive is
// "%YAML 1.0". yaml-cpp 0.7 happens to skip it as an unknown directive named "YAML:1.0", which another
// version may refuse; written YAML's way it says what FileStorage meant, and every line stays where it was,
// so the line an error names is the file's.
constexpr std::string_view kOpenCvVersionDirective = "%YAML:";

Status appendNumber(const YAML::Node& item, const std::string& field, const std::string& origin,
                    std::vector<double>& out) {
    if (item.IsSequence()) {
        for (const YAML::Node& inner : item)
            if (Status s = appendNumber(inner, field, origin, out); !s)
                return s;
        return {};
    }
    const std::optional<double> value = number(item);
    if (!value)
        return fieldError(origin, field, "expected numbers");
    out.push_back(*value);
    return {};
}

// A yaml-cpp exception as one line naming the file and, when yaml-cpp knows it, the line and column.
Error yamlError(const std::string& origin, const YAML::Exception& e, const std::string& problem) {
    // yaml-cpp counts lines and columns from 0; editors and compilers from 1.
    const std::string where =
        e.mark.is_null() ? ""
                         : ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1);
    return Error{origin + where + ": " + problem + " (" + e.msg + ")"};
}

} // namespace

Expected<YAML::Node> parseDocument(const std::string& text, const std::string& origin) {
    std::string yaml = text;
    if (yaml.starts_with(kOpenCvVersionDirective))
        yaml[kOpenCvVersionDirective.size() - 1] = ' ';
    try {
        return YAML::Load(yaml);
    } catch (const YAML::Exception& e) {
        return yamlError(origin, e, "malformed calibration YAML or JSON");
    }
}

YAML::Node child(const YAML::Node& parent, const std::string& name) {
    if (!parent.IsMap())
        return YAML::Node(YAML::NodeType::Undefined);
    // The const lookup: it inserts nothing, and a key it lacks comes back as a node only IsDefined() may ask.
    const YAML::Node node = parent[name];
    return node.IsDefined() && !node.IsNull() ? node : YAML::Node(YAML::NodeType::Undefined);
}

bool has(const YAML::Node& parent, const std::string& name) {
    return child(parent, name).IsDefined();
}

Named firstOf(const YAML::Node& parent, std::initializer_list<std::string> names) {
    for (const std::string& name : names)
        if (YAML::Node node = child(parent, name); node.IsDefined())
            return {node, name};
    return {YAML::Node(YAML::NodeType::Undefined), *names.begin()};
}

std::string text(const YAML::Node& node) {
    return node.IsScalar() ? node.Scalar() : "";
}

std::optional<double> number(const YAML::Node& node) {
    // yaml-cpp tags a quoted scalar "!": it is text, as in JSON, even when it reads like a number.
    if (!node.IsScalar() || node.Tag() == "!")
        return std::nullopt;
    // yaml-cpp reads YAML's .nan, .NaN and .NAN only; OpenCV writes .Nan, and some tools a bare nan.
    std::string lower = node.Scalar();
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (lower == "nan" || lower == ".nan")
        return std::nan("");
    double value = 0.0;
    if (!YAML::convert<double>::decode(node, value))
        return std::nullopt;
    return value;
}

Error fieldError(const std::string& origin, const std::string& field, const std::string& problem) {
    return Error{origin + ": " + field + ": " + problem};
}

Expected<std::vector<double>> numbers(const YAML::Node& node, const std::string& field,
                                      const std::string& origin, std::size_t count) {
    if (!node.IsDefined())
        return fieldError(origin, field, "missing");
    std::vector<double> out;
    if (Status s = appendNumber(node.IsMap() ? child(node, "data") : node, field, origin, out); !s)
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

Expected<std::array<int, 2>> imageSize(const YAML::Node& node, const std::string& field,
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

Expected<RigidTransform> homogeneousMatrix(const YAML::Node& node, const std::string& field,
                                           const std::string& origin) {
    auto m = numbers(node, field, origin, 16);
    if (!m)
        return m.error();
    const std::vector<double>& v = *m;
    if (v[12] != 0.0 || v[13] != 0.0 || v[14] != 0.0 || v[15] != 1.0)
        return fieldError(origin, field, "the last row must be [0, 0, 0, 1]");
    RigidTransform t;
    t.rotation = {v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10]};
    t.translationMeters = {v[3], v[7], v[11]};
    return t;
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
