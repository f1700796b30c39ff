#include "frame/calibration_fields.h"
#include "frame/calibration_formats.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace dc::frame::formats {

namespace {

using fields::fieldError;

// One camera block: camera_model pinhole, intrinsics [fu, fv, pu, pv], distortion radtan (k1 k2 p1 p2) or
// none, resolution [width, height].
Expected<CameraModel> readCamera(const YAML::Node& cam, const std::string& name, const std::string& origin) {
    if (!cam.IsMap())
        return fieldError(origin, name, "missing");
    const std::string model = fields::text(fields::child(cam, "camera_model"));
    if (fields::has(cam, "camera_model") && model != "pinhole")
        return fieldError(origin, name + ".camera_model", "'" + model + "' is not supported (pinhole)");
    auto k = fields::numbers(fields::child(cam, "intrinsics"), name + ".intrinsics", origin, 4);
    if (!k)
        return k.error();
    auto size = fields::imageSize(fields::child(cam, "resolution"), name + ".resolution", origin);
    if (!size)
        return size.error();
    CameraModel camera{{(*k)[0], (*k)[1], (*k)[2], (*k)[3], (*size)[0], (*size)[1]}, {}};
    if (Status s = fields::checkIntrinsics(camera.intrinsics, name + ".intrinsics", origin); !s)
        return s.error();
    const std::string distortion = fields::text(fields::child(cam, "distortion_model"));
    if (distortion == "radtan") {
        auto d =
            fields::numbers(fields::child(cam, "distortion_coeffs"), name + ".distortion_coeffs", origin, 4);
        if (!d)
            return d.error();
        camera.lens = {LensModel::BrownConrady, {(*d)[0], (*d)[1], (*d)[2], (*d)[3], 0.0}};
    } else if (fields::has(cam, "distortion_model") && distortion != "none") {
        return fieldError(origin, name + ".distortion_model",
                          "'" + distortion + "' is not supported (radtan or none)");
    }
    return camera;
}

Expected<RigidTransform> readTransform(const YAML::Node& cam1, const std::string& origin) {
    const std::string field = "cam1.T_cn_cnm1";
    auto t = fields::homogeneousMatrix(fields::child(cam1, "T_cn_cnm1"), field, origin);
    if (!t)
        return t.error();
    if (Status s = fields::checkTransform(*t, field, field, origin); !s)
        return s.error();
    return t;
}

std::string listOf(std::initializer_list<double> values) {
    std::string out = "[";
    char number[32];
    for (double v : values) {
        std::snprintf(number, sizeof number, "%.17g", v);
        out += (out.size() > 1 ? ", " : "") + std::string(number);
    }
    return out + "]";
}

std::string cameraBlock(const CameraModel& camera) {
    const Intrinsics& k = camera.intrinsics;
    const auto& c = camera.lens.coefficients;
    std::ostringstream out;
    out << "  camera_model: pinhole\n  intrinsics: " << listOf({k.fx, k.fy, k.cx, k.cy}) << "\n";
    if (camera.lens.model == LensModel::None)
        out << "  distortion_model: none\n  distortion_coeffs: []\n";
    else
        out << "  distortion_model: radtan\n  distortion_coeffs: " << listOf({c[0], c[1], c[2], c[3]})
            << "\n";
    out << "  resolution: [" << k.width << ", " << k.height << "]\n";
    return out.str();
}

} // namespace

bool isKalibr(const YAML::Node& root) {
    return fields::child(root, "cam0").IsMap();
}

Expected<Calibration> readKalibr(const YAML::Node& root, const std::string& origin) {
    auto depth = readCamera(fields::child(root, "cam0"), "cam0", origin);
    if (!depth)
        return depth.error();
    auto colour = readCamera(fields::child(root, "cam1"), "cam1", origin);
    if (!colour)
        return colour.error();
    auto transform = readTransform(fields::child(root, "cam1"), origin);
    if (!transform)
        return transform.error();
    Calibration result{colour->intrinsics, "Kalibr camchain", RigCalibration{}, "cam0.resolution",
                       "cam1.resolution"};
    result.rig = RigCalibration{*depth, *colour, *transform, origin + " (Kalibr camchain)", false};
    return result;
}

Expected<std::string> writeKalibr(const RigCalibration& rig) {
    for (const CameraModel* camera : {&rig.depth, &rig.colour}) {
        if (camera->lens.model == LensModel::InverseBrownConrady)
            return Error{"Kalibr has no inverse Brown-Conrady lens model"};
        if (camera->lens.coefficients[4] != 0.0)
            return Error{"Kalibr's radtan model has no k3"};
    }
    const auto& r = rig.depthToColour.rotation;
    const auto& t = rig.depthToColour.translationMeters;
    std::ostringstream out;
    out << "cam0:\n" << cameraBlock(rig.depth) << "cam1:\n  T_cn_cnm1:\n";
    for (int row = 0; row < 3; ++row)
        out << "  - " << listOf({r[3 * row], r[3 * row + 1], r[3 * row + 2], t[row]}) << "\n";
    out << "  - [0, 0, 0, 1]\n" << cameraBlock(rig.colour);
    return out.str();
}

} // namespace dc::frame::formats
