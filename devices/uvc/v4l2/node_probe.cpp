#include "devices/uvc/v4l2/node_probe.h"

#include <algorithm>
#include <cmath>
#include <linux/videodev2.h>

namespace dc::devices::v4l2 {

bool ProbedNode::offers(std::uint32_t fourcc) const {
    return std::any_of(modes.begin(), modes.end(), [&](const V4l2Mode& m) { return m.fourcc == fourcc; });
}

bool ProbedNode::offersRole(FormatRole role) const {
    return std::any_of(modes.begin(), modes.end(),
                       [&](const V4l2Mode& m) { return roleOf(m.fourcc) == role; });
}

std::optional<ProbedNode> probeNode(Syscalls& sys, const std::string& path, int& error) {
    V4l2Node node(sys);
    error = node.open(path);
    if (error < 0)
        return std::nullopt;
    if (!node.capability().canCapture())
        return std::nullopt;
    return ProbedNode{path, node.capability(), node.allModes()};
}

NodeRoles assignRoles(const std::vector<ProbedNode>& nodes) {
    NodeRoles roles;
    auto first = [&](auto predicate) -> std::string {
        for (const ProbedNode& n : nodes)
            if (n.path != roles.depth && n.path != roles.color && predicate(n))
                return n.path;
        return {};
    };
    roles.depth = first([](const ProbedNode& n) { return n.offers(V4L2_PIX_FMT_Z16); });
    if (roles.depth.empty())
        roles.depth = first([](const ProbedNode& n) { return n.offers(V4L2_PIX_FMT_Y16); });
    roles.color = first([](const ProbedNode& n) { return n.offersRole(FormatRole::Color); });
    roles.infrared =
        first([](const ProbedNode& n) { return n.offers(V4L2_PIX_FMT_GREY) || n.offers(V4L2_PIX_FMT_Y16); });
    return roles;
}

FormatRole roleOfNode(const NodeRoles& roles, const ProbedNode& node) {
    if (node.path == roles.depth)
        return FormatRole::Depth;
    if (node.path == roles.color)
        return FormatRole::Color;
    if (node.path == roles.infrared)
        return FormatRole::Guide;
    return FormatRole::Other;
}

std::optional<std::uint32_t> preferredImageFormat(const ProbedNode& node) {
    for (std::uint32_t fourcc :
         {V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_NV12, V4L2_PIX_FMT_RGB24, V4L2_PIX_FMT_MJPEG, V4L2_PIX_FMT_GREY})
        if (node.offers(fourcc))
            return fourcc;
    return std::nullopt;
}

namespace {

constexpr long kMaxDefaultArea = 1280L * 720L;
constexpr double kDefaultFps = 30.0;

long area(const V4l2Mode& m) {
    return static_cast<long>(m.width) * m.height;
}

std::string offeredSizes(const std::vector<const V4l2Mode*>& candidates) {
    std::string text;
    for (const V4l2Mode* m : candidates)
        text += (text.empty() ? "" : ", ") + std::to_string(m->width) + "x" + std::to_string(m->height);
    return text;
}

const V4l2Mode* defaultSize(const std::vector<const V4l2Mode*>& candidates) {
    const V4l2Mode* best = nullptr;
    for (const V4l2Mode* m : candidates)
        if (area(*m) <= kMaxDefaultArea && (!best || area(*m) > area(*best)))
            best = m;
    if (best)
        return best;
    for (const V4l2Mode* m : candidates)
        if (!best || area(*m) < area(*best))
            best = m;
    return best;
}

double chooseRate(const std::vector<double>& offered, double requested) {
    if (offered.empty())
        return requested;
    const double target = requested > 0.0 ? requested : kDefaultFps;
    const auto exact = std::find_if(offered.begin(), offered.end(),
                                    [&](double r) { return std::abs(r - target) < 0.01 * target; });
    if (exact != offered.end())
        return *exact;
    if (requested <= 0.0)
        return *std::max_element(offered.begin(), offered.end());
    return *std::min_element(offered.begin(), offered.end(), [&](double a, double b) {
        return std::abs(a - requested) < std::abs(b - requested);
    });
}

} // namespace

Expected<ChosenMode> chooseMode(const std::vector<V4l2Mode>& modes, const ChosenMode& request) {
    std::vector<const V4l2Mode*> candidates;
    for (const V4l2Mode& m : modes)
        if (m.fourcc == request.fourcc)
            candidates.push_back(&m);
    if (candidates.empty())
        return Error{"format '" + fourccToString(request.fourcc) + "' is not offered"};
    const V4l2Mode* mode = nullptr;
    if (request.width > 0 && request.height > 0) {
        for (const V4l2Mode* m : candidates)
            if (m->width == request.width && m->height == request.height)
                mode = m;
        if (!mode)
            return Error{std::to_string(request.width) + "x" + std::to_string(request.height) +
                         " is not offered for '" + fourccToString(request.fourcc) +
                         "' (offered: " + offeredSizes(candidates) + ")"};
    } else {
        mode = defaultSize(candidates);
    }
    return ChosenMode{mode->fourcc, mode->width, mode->height,
                      chooseRate(mode->framesPerSecond, request.fps)};
}

} // namespace dc::devices::v4l2
