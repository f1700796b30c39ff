#include "devices/source_pose.h"

#include "frame/camera_pose.h"
#include "frame/multi_camera_extrinsics.h"

#include <array>
#include <charconv>
#include <string_view>
#include <vector>

namespace dc::devices {

namespace {

constexpr std::string_view kPoseKey = "pose=";

// Every part between ':' separators, empty ones included, so that joining them again gives back the spec.
std::vector<std::string> specParts(const std::string& spec) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (std::size_t colon = spec.find(':'); colon != std::string::npos; colon = spec.find(':', start)) {
        parts.push_back(spec.substr(start, colon - start));
        start = colon + 1;
    }
    parts.push_back(spec.substr(start));
    return parts;
}

// The seven comma-separated numbers of pose=X,Y,Z,QX,QY,QZ,QW.
Expected<frame::RigidTransform> inlinePose(const std::string& value) {
    std::array<double, 7> numbers{};
    std::size_t count = 0, start = 0;
    for (bool last = false; !last; ++count) {
        const std::size_t comma = value.find(',', start);
        last = comma == std::string::npos;
        const std::string item = value.substr(start, last ? std::string::npos : comma - start);
        start = comma + 1;
        if (count >= numbers.size())
            continue;
        const char* end = item.data() + item.size();
        const auto [ptr, ec] = std::from_chars(item.data(), end, numbers[count]);
        if (item.empty() || ec != std::errc() || ptr != end)
            return Error{"'" + item + "' is not a number"};
    }
    if (count != numbers.size())
        return Error{"expected 7 numbers X,Y,Z,QX,QY,QZ,QW (meters, then a unit quaternion), found " +
                     std::to_string(count)};
    return frame::poseFromQuaternion(numbers);
}

// FILE#CAMERA: that camera of a rig's extrinsics file.
Expected<frame::RigidTransform> rigCameraPose(const std::string& path, const std::string& camera) {
    auto rig = frame::loadCameraExtrinsics(path);
    if (!rig)
        return rig.error();
    if (const frame::CameraExtrinsics* found = rig->find(camera))
        return found->cameraToWorld;
    std::string names;
    for (const frame::CameraExtrinsics& c : rig->cameras)
        names += (names.empty() ? "" : ", ") + c.name;
    return Error{path + " has no camera '" + camera + "' (it has " + names + ")"};
}

} // namespace

Expected<frame::RigidTransform> parsePoseValue(const std::string& value) {
    if (value.empty())
        return Error{"expected X,Y,Z,QX,QY,QZ,QW or a pose file"};
    // A file's name has no comma in practice; seven numbers always do.
    if (value.find(',') != std::string::npos)
        return inlinePose(value);
    if (const auto hash = value.rfind('#'); hash != std::string::npos)
        return rigCameraPose(value.substr(0, hash), value.substr(hash + 1));
    return frame::loadPoseFile(value);
}

Expected<SourcePlacement> sourcePlacement(const std::string& spec) {
    std::vector<std::string> parts = specParts(spec);
    SourcePlacement placement{spec, std::nullopt};
    // The first part is the kind (or a replay's path): an option starts after it.
    for (std::size_t i = 1; i < parts.size(); ++i) {
        if (!parts[i].starts_with(kPoseKey))
            continue;
        if (placement.cameraToWorld)
            return Error{"pose= is given twice in --source"};
        auto pose = parsePoseValue(parts[i].substr(kPoseKey.size()));
        if (!pose)
            return Error{parts[i] + " in --source: " + pose.error().message};
        placement.cameraToWorld = *pose;
        parts.erase(parts.begin() + static_cast<std::ptrdiff_t>(i--));
    }
    if (!placement.cameraToWorld)
        return placement;
    placement.spec = parts[0];
    for (std::size_t i = 1; i < parts.size(); ++i)
        placement.spec += ":" + parts[i];
    return placement;
}

} // namespace dc::devices
