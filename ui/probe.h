#pragma once

#include "frame/frame.h"
#include "ui/panel_image.h"

#include <array>
#include <optional>
#include <string>

namespace dc::ui {

// What the hover readout shows: one depth sample, where it is and what the sensor said about it.
struct Probe {
    int u = 0; // depth-map pixel
    int v = 0;
    float depthMeters = 0.0f;                    // 0 when the sample holds no measurement
    std::optional<frame::Confidence> confidence; // none when the source provides no confidence
    std::array<float, 3> point{};                // camera frame (OpenCV axes), meters; zero without depth
    // False where a two-sensor camera's colour sensor cannot see the point (outside its view or hidden
    // behind a nearer surface), so its gray is no colour the camera measured.
    bool seenByColour = true;
    // The raw infrared intensity at the sample (the infrared image scaled to the depth map where their
    // sizes differ); none without an infrared image.
    std::optional<std::uint16_t> infrared;
    // The frame sampled, so a stutter seen in the Timing panel can be matched to it: its number in the
    // source and, from a live camera, the driver's sequence number.
    std::optional<std::uint64_t> frameSequence;
    std::optional<std::uint32_t> driverSequence;
    std::optional<std::uint32_t> exposureUs; // the depth frame's, where its metadata says it
    // What the depth camera's metadata node said about the frame (frame::CameraMetadata), where it did.
    std::optional<std::uint32_t> cameraFrameCounter;
    std::optional<std::uint32_t> gain;
    std::optional<std::uint32_t> laserPowerMw;
};

// The depth the panels show, with the intrinsics that place it.
struct ProbeSource {
    const frame::DepthData* depth = nullptr;
    frame::Intrinsics intrinsics;
    const frame::Plane<std::uint8_t>* colourSeen = nullptr; // the depth's size
    // Without colourSeen, the frame whose rig decides it for the probed sample alone (the GPU coloured the
    // points, so no mask was made); null as well: every point seen.
    const frame::Frame* frame = nullptr;
    const frame::Plane<std::uint16_t>* infrared = nullptr; // the frame's infrared image, when it has one

    bool empty() const { return depth == nullptr || depth->depthMeters.empty(); }
};

// The sample at depth pixel (u, v); nothing outside the map.
std::optional<Probe> probeAt(const ProbeSource& source, int u, int v);

// The sample at a position given as fractions of the depth map's size ((0, 0) top-left), which is also
// where it lies in the camera image: depth and image cover the same field of view.
std::optional<Probe> probeAtFraction(const ProbeSource& source, ImVec2 fraction);

// Millimetres below a metre, where they are the natural unit; meters above; "no depth" for none.
std::string formatDepth(float meters);
const char* confidenceName(frame::Confidence level);

inline constexpr const char* kNotSeenByColour = "not seen by the colour camera";

// The readout's line naming the frame sampled: "frame 42, seq 1234, exposure 8500 µs", each part only where
// known; empty without a frame.
std::string frameReadout(const Probe& probe);
// The readout's line with the camera's own account of the frame: "camera frame 4242, gain 16, laser 150 mW",
// each part only where known; empty when the camera said none of them.
std::string cameraReadout(const Probe& probe);

// The readout as a tooltip next to the mouse.
void showProbeTooltip(const Probe& probe);

} // namespace dc::ui
