#include "devices/ros/tf_tree.h"

#include <algorithm>
#include <cstdlib>
#include <iterator>

namespace dc::devices::ros {

namespace {

// Longer chains than any robot's are a loop in a damaged recording.
constexpr int kMaxChain = 64;

} // namespace

frame::RigidTransform rigidOf(const RosTransform& t) {
    return frame::rigidFromQuaternion(t.translationMeters, t.rotationXyzw);
}

void TfTree::add(const RosTransformStamped& t, bool fixed) {
    Link link{t.stampNs, t.parentFrameId, rigidOf(t.transform)};
    if (fixed) {
        fixed_[t.childFrameId] = std::move(link);
        return;
    }
    moving_[t.childFrameId].push_back(std::move(link));
}

void TfTree::finish() {
    for (auto& [child, track] : moving_)
        std::stable_sort(track.begin(), track.end(),
                         [](const Link& a, const Link& b) { return a.stampNs < b.stampNs; });
}

const TfTree::Link* TfTree::nearest(const std::vector<Link>& track, std::int64_t stampNs,
                                    std::int64_t toleranceNs) const {
    const auto next = std::lower_bound(track.begin(), track.end(), stampNs,
                                       [](const Link& link, std::int64_t ns) { return link.stampNs < ns; });
    auto best = next;
    if (next == track.end() ||
        (next != track.begin() && stampNs - std::prev(next)->stampNs < next->stampNs - stampNs))
        best = std::prev(next);
    return std::llabs(best->stampNs - stampNs) <= toleranceNs ? &*best : nullptr;
}

std::optional<TfTree::Located> TfTree::locate(const std::string& frameId, std::int64_t stampNs,
                                              std::int64_t toleranceNs) const {
    Located out{{}, frameId, false};
    for (int links = 0; links < kMaxChain; ++links) {
        const Link* link = nullptr;
        if (const auto f = fixed_.find(out.root); f != fixed_.end()) {
            link = &f->second;
        } else if (const auto m = moving_.find(out.root); m != moving_.end()) {
            link = nearest(m->second, stampNs, toleranceNs);
            if (!link)
                return std::nullopt;
            out.moving = true;
        } else {
            return out;
        }
        out.toRoot = frame::compose(link->toParent, out.toRoot);
        out.root = link->parent;
    }
    return std::nullopt;
}

} // namespace dc::devices::ros
