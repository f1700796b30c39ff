#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

namespace dc::frame {

// Pinhole intrinsics of an image of `width` x `height` pixels, in pixels. Pixel (u, v) with depth z
// unprojects to ((u - cx) z / fx, (v - cy) z / fy, z) in the camera frame (OpenCV axes: x right, y down,
// z forward), as the Depth Cloud sample does.
struct Intrinsics {
    double fx = 0.0;
    double fy = 0.0;
    double cx = 0.0;
    double cy = 0.0;
    int width = 0;
    int height = 0;

    // The intrinsics of the same camera resampled to another resolution. ARKit derives the depth map's
    // intrinsics this way (a plain per-axis scale of the capturedImage intrinsics); so do we.
    Intrinsics scaledTo(int newWidth, int newHeight) const;
    // Finite, positive focal lengths and a positive size: anything else cannot place points in 3D.
    bool valid() const;
    bool operator==(const Intrinsics&) const = default;
};

// A dense single-channel image owned by value, row-major with no padding.
template <class T> struct Plane {
    int width = 0;
    int height = 0;
    std::vector<T> pixels;

    Plane() = default;
    Plane(int w, int h, T fill = T{}) : width(w), height(h), pixels(static_cast<std::size_t>(w) * h, fill) {}

    bool empty() const { return pixels.empty(); }
    T& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
    const T& at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

enum class PixelFormat {
    Nv12,  // full-range BT.601 Y plane, then interleaved Cb/Cr at half resolution (ARKit's capturedImage)
    Yuyv,  // packed 4:2:2
    Rgb24, // packed 8-bit R, G, B
    Jpeg,  // a compressed frame as the camera sent it (MJPEG): decoded (frame/jpeg_codec.h) only where its
           // pixels are used, never on the capture thread
};

const char* toString(PixelFormat format);

// The camera image exactly as the source captured it. The bytes are shared and never modified, so a
// static scene can hand the same image to every frame without copying 4 MB per frame.
struct CapturedImage {
    PixelFormat format = PixelFormat::Nv12;
    int width = 0;
    int height = 0;
    std::shared_ptr<const std::vector<std::uint8_t>> bytes;

    bool empty() const { return !bytes || bytes->empty(); }
    // Pixels can be read from the bytes as they are (every format but Jpeg).
    bool raw() const { return format != PixelFormat::Jpeg; }
    // Expected byte count for the format and size; a source whose buffer differs is malformed. 0 for Jpeg,
    // whose size varies per frame.
    static std::size_t byteSize(PixelFormat format, int width, int height);
};

// A depth sample that holds a measurement: positive and finite (0, NaN and inf are "none").
inline bool isMeasured(float depthMeters) {
    return depthMeters > 0.0f && depthMeters < std::numeric_limits<float>::infinity(); // NaN fails both
}

// ARConfidenceLevel: how much the sensor trusts each depth sample.
enum class Confidence : std::uint8_t { Low = 0, Medium = 1, High = 2 };

// One depth map with its per-pixel confidence (ARDepthData). depthMeters == 0 means "no measurement".
// `confidence` is empty when the source provides none; otherwise it has the depth map's size.
struct DepthData {
    Plane<float> depthMeters;
    Plane<std::uint8_t> confidence;
    // The sensor gave no confidence and `confidence` was estimated from the depth map itself
    // (processing/confidence_estimator.h): the UI labels it "estimated".
    bool confidenceEstimated = false;
};

// Camera-to-world rigid transform, column-major 4x4 (OpenCV camera axes, meters).
struct Pose {
    std::array<double, 16> cameraToWorld{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
};

// Where a replayed frame sits in its recording. A consumer that asked for a seek compares
// seekGeneration with the value the seek returned: an older generation is a frame decoded before the
// seek (still in flight), the first frame with the new generation is exactly the one asked for.
struct ReplayPosition {
    std::size_t index = 0;
    std::size_t count = 0;
    std::uint64_t seekGeneration = 0;
};

// Which instant of a capture a timestamp marks (V4L2_BUF_FLAG_TSTAMP_SRC_*), so that a latency "from
// exposure" says what it measures.
enum class TimestampSource : std::uint8_t {
    Unknown,         // the source does not say (recordings, synthetic scenes, ROS)
    StartOfExposure, // V4L2_BUF_FLAG_TSTAMP_SRC_SOE: uvcvideo stamps the first packet of the frame
    EndOfFrame,      // V4L2_BUF_FLAG_TSTAMP_SRC_EOF: the driver had the whole frame (vivid, most drivers)
    Arrival,         // the application's clock at dequeue: the driver's stamp was not CLOCK_MONOTONIC
};

// One stream's view of a capture as its driver reported it.
struct StreamTiming {
    // v4l2_buffer.sequence, counting every frame the driver saw (it wraps at 2^32): a gap between two
    // frames the application got is frames lost before it, in the camera, on the USB link or in the driver.
    std::optional<std::uint32_t> driverSequence;
    std::int64_t sensorNs = 0; // the buffer's timestamp; 0: none
    TimestampSource source = TimestampSource::Unknown;
    // sensorNs is CLOCK_MONOTONIC of this machine: comparable with arrival and display times.
    bool monotonic = false;
    // The exposure the frame was taken with, where the camera's metadata says it (V4L2_META_FMT_D4XX's
    // depth control block); none where it does not.
    std::optional<std::uint32_t> exposureUs;
};

// What a UVC camera's metadata node says about a depth frame besides its exposure (StreamTiming::exposureUs),
// each value only where the camera's metadata gives it.
struct CameraMetadata {
    std::optional<std::uint32_t> frameCounter; // the camera's own frame count (D4xx capture timing)
    std::optional<std::uint32_t> gain;         // the depth sensor's gain, in V4L2_CID_GAIN's units (D4xx)
    std::optional<std::uint32_t> laserPowerMw; // the projector's power, 0-360 mW (D4xx)
    // The UVC payload header's clocks, in ticks of the camera's clock (its dwClockFrequency): PTS at the
    // start of exposure, SCR sampled at the USB frame scrUsbFrame (11 bits).
    std::optional<std::uint32_t> ptsTicks;
    std::optional<std::uint32_t> scrTicks;
    std::optional<std::uint16_t> scrUsbFrame;
};

// Per-frame metadata for the timing view: what the drivers said about the depth capture and, from a
// separate colour node, the image paired with it. Times the application adds later (arrival, processing,
// display) are recorded beside the frame, by the session and the engine.
struct FrameTiming {
    StreamTiming depth;
    std::optional<StreamTiming> colour;
    CameraMetadata depthMetadata; // from the depth node's metadata node
};

struct RigCalibration; // frame/camera_model.h

// One capture: an immutable value handed between threads as FramePtr (ARFrame, made explicit).
struct Frame {
    std::uint64_t sequence = 0;
    std::int64_t timestampNs = 0;
    CapturedImage capturedImage;
    Intrinsics cameraIntrinsics; // of capturedImage
    std::optional<DepthData> sceneDepth;
    std::optional<DepthData> smoothedSceneDepth;
    std::optional<Pose> pose;
    std::optional<ReplayPosition> replay; // set by replay sources only
    FrameTiming timing;
    // Depth and colour from two sensors (RealSense, Orbbec, Kinect): each sensor's own intrinsics and lens
    // and the transform between them. Null for one camera whose image covers the depth map's field of
    // view (ARKit, TUM, the default synthetic scene): then cameraIntrinsics serves both.
    std::shared_ptr<const RigCalibration> rig;
    // The depth sensor's infrared image when the source has one (RealSense's Infrared_N, a GREY/Y16
    // node): raw sensor intensity as the sensor reports it, 0-255 for 8-bit streams and 0-65535 for 16-bit
    // ones. One 16-bit plane holds both without loss. Its own size, usually the depth map's.
    std::optional<Plane<std::uint16_t>> infrared;

    // Depth intrinsics are never stored: they follow from the image intrinsics (or the rig's depth sensor)
    // and the depth map size.
    Intrinsics depthIntrinsics() const;
    // The depth sensor's intrinsics for a depth map of width x height (a smoothed, decimated or upsampled
    // version of sceneDepth).
    Intrinsics depthIntrinsicsAt(int width, int height) const;
};

using FramePtr = std::shared_ptr<const Frame>;

} // namespace dc::frame
