#pragma once

#include "devices/ros/ros_messages.h"
#include "frame/camera_model.h"

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace dc::devices::ros {

// A recording's tf frames (ROS's /tf and /tf_static) for finding where one frame sits: each frame has at
// most one parent, fixed (/tf_static) or moving (/tf, one transform per stamp).
class TfTree {
public:
    // Where a frame sits in the root of its chain: p_root = toRoot.apply(p_frame).
    struct Located {
        frame::RigidTransform toRoot;
        std::string root;
        bool moving = false; // a moving link is on the chain (else the answer holds at any time)
    };

    void add(const RosTransformStamped& transform, bool fixed);
    // Orders each moving frame's transforms by stamp: once every transform is added, before locate().
    void finish();
    bool empty() const { return fixed_.empty() && moving_.empty(); }
    // `frameId` in the root of its chain at `stampNs`: fixed links as they are, each moving link by its
    // transform stamped nearest `stampNs`. Nothing when a moving link has none within `toleranceNs`.
    std::optional<Located> locate(const std::string& frameId, std::int64_t stampNs,
                                  std::int64_t toleranceNs) const;

private:
    struct Link {
        std::int64_t stampNs = 0;
        std::string parent;
        frame::RigidTransform toParent;
    };
    const Link* nearest(const std::vector<Link>& track, std::int64_t stampNs, std::int64_t toleranceNs) const;

    std::map<std::string, Link> fixed_;               // by child frame
    std::map<std::string, std::vector<Link>> moving_; // by child frame
};

// A tf transform (a unit quaternion and a translation) as a rigid transform from the child's frame into the
// parent's (composing and inverting them: frame::compose, frame::inverse).
frame::RigidTransform rigidOf(const RosTransform& transform);

} // namespace dc::devices::ros
