#include "devices/frame_pairer.h"

#include <cstdlib>

namespace dc::devices {

namespace {

bool stamped(std::int64_t timestampNs) {
    return timestampNs != 0;
}

} // namespace

void FramePairer::pushDepth(StampedDepth depth) {
    depth_.push_back(std::move(depth));
}

void FramePairer::pushColor(StampedImage color) {
    colors_.push_back(std::move(color));
    while (colors_.size() > kMaxColors)
        colors_.pop_front();
}

const StampedImage* FramePairer::match(const StampedDepth& depth) const {
    const StampedImage* best = nullptr;
    std::int64_t bestSkew = 0;
    for (const StampedImage& color : colors_) {
        if (!stamped(depth.timestampNs) || !stamped(color.timestampNs)) {
            if (color.sequence == depth.sequence)
                return &color;
            continue;
        }
        const std::int64_t skew = std::llabs(color.timestampNs - depth.timestampNs);
        if (skew <= maxSkewNs_ && (!best || skew < bestSkew)) {
            best = &color;
            bestSkew = skew;
        }
    }
    return best;
}

bool FramePairer::colorCannotCome(const StampedDepth& depth) const {
    if (depth_.size() > kMaxPendingDepth)
        return true;
    if (colors_.empty())
        return false;
    const StampedImage& newest = colors_.back();
    // Colors arrive in order: once one is past the window (in time, or in sequence), later ones are too.
    if (stamped(depth.timestampNs) && stamped(newest.timestampNs))
        return newest.timestampNs > depth.timestampNs + maxSkewNs_;
    return newest.sequence > depth.sequence;
}

std::optional<PairedCapture> FramePairer::pop() {
    if (depth_.empty())
        return std::nullopt;
    const StampedDepth& oldest = depth_.front();
    const StampedImage* color = match(oldest);
    if (!color && !colorCannotCome(oldest))
        return std::nullopt;
    PairedCapture out{std::move(depth_.front()), std::nullopt};
    if (color) {
        out.color = *color; // the image bytes are shared, not copied
        ++paired_;
    } else {
        ++unpaired_;
    }
    depth_.pop_front();
    return out;
}

void FramePairer::reset() {
    depth_.clear();
    colors_.clear();
}

} // namespace dc::devices
