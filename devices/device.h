#pragma once

#include "base/expected.h"
#include "devices/sensor_controls.h"
#include "frame/camera_model.h"
#include "frame/frame.h"

#include <chrono>
#include <memory>
#include <string>

namespace dc::devices {

// What a source can deliver (ARKit's frame semantics, plus what a live camera may lack).
struct Capabilities {
    bool sceneDepth = false;
    bool smoothedSceneDepth = false;
    bool confidence = false;
    bool color = false;
    bool pose = false;
    bool reconnects = false; // after Disconnected, reconnect() can bring the same camera back
    // No calibration is known: the intrinsics come from a default field of view, so the cloud's geometry is
    // approximate. The session says so in its first event (kApproximateIntrinsicsMessage).
    bool approximateIntrinsics = false;
    // Colour comes from a sensor of its own (a separate colour node) and no two-sensor calibration relates
    // it to the depth sensor: each point takes the colour at its own pixel, not where the colour sensor saw
    // it, so colours are misplaced by the sensors' baseline and differing fields of view.
    bool unregisteredColour = false;
    // Frame timestamps are CLOCK_MONOTONIC capture times, so now - timestampNs is the frame's age.
    bool monotonicTimestamps = false;
    // Frame timestamps are CLOCK_REALTIME publish times (a ROS publisher's header stamps, on this machine or
    // one whose clock is in sync), so now - timestampNs is the frame's age too.
    bool realtimeTimestamps = false;
    // The frame rate the source promises (0: unknown). A session delivering clearly less cannot keep it.
    double nominalFps = 0.0;
};

inline constexpr const char* kApproximateIntrinsicsMessage =
    "approximate geometry: no calibration file, intrinsics assume a default field of view (add calib=FILE)";

inline constexpr const char* kUnregisteredColourMessage =
    "colours not registered: separate colour sensor without a two-sensor calibration (add calib=FILE)";

// What the consumers of a source's frames need right now, so the source can leave out what nobody shows
// (a replay skips decoding its video; a live camera could skip converting its colour).
struct SourceDemand {
    bool cameraImage = true;

    bool operator==(const SourceDemand&) const = default;
};

// Closed -> Open -> Streaming -> Stopped (-> Streaming again, or -> Closed). Disconnected and Stalled are
// entered from Streaming by live devices when the hardware goes away or stops delivering.
enum class DeviceState { Closed, Open, Streaming, Stopped, Disconnected, Stalled };

const char* toString(DeviceState state);

// The outcome of one capture attempt on the capture thread.
struct CaptureResult {
    // Stalled: streaming, but no frame for longer than the device's dequeue watchdog allows.
    enum class Kind { Frame, Timeout, EndOfStream, Disconnected, Stalled, Error };
    Kind kind = Kind::Timeout;
    frame::FramePtr frame; // set when kind == Frame
    std::string message;   // set for Disconnected, Stalled and Error
};

// A depth source. The public methods check the state machine and call the do*() hooks that a device
// implements, so every device gets the same transitions and the same error for a misuse. Not
// thread-safe by itself: a Session serialises access (open/start/stop on the caller's thread while the
// capture thread is not running; capture() on the capture thread only).
class Device {
public:
    virtual ~Device() = default;
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;

    virtual std::string description() const = 0;
    virtual Capabilities capabilities() const = 0;

    Status open();
    Status start();
    Status stop();
    void close();
    DeviceState state() const { return state_; }

    // Waits at most `timeout` for the next frame. Only valid while Streaming or Stalled (a frame ends the
    // stall).
    CaptureResult capture(std::chrono::milliseconds timeout);
    // Disconnected -> Streaming when the camera is back (capabilities().reconnects); called on the capture
    // thread, which retries until it succeeds or the session stops.
    Status reconnect();
    // Wakes a capture() blocked on the capture thread. May be called from any thread.
    virtual void interruptCapture() {}
    // Tells the device what its consumers need from the frames it has not produced yet. May be called from
    // any thread, at any state; a device that cannot leave anything out ignores it.
    virtual void setDemand(const SourceDemand&) {}
    // The camera's controls for the window, or null for a source without any (all but live cameras).
    virtual std::shared_ptr<SensorControls> sensorControls() const { return nullptr; }
    // Places the source in the world (its spec's pose=): each frame's pose becomes cameraToWorld after the
    // frame's own pose (a camera that tracks itself moves within the placed frame), or cameraToWorld alone.
    // Each frame is then a copy of the one the source made.
    void place(const frame::RigidTransform& cameraToWorld) { placement_ = cameraToWorld; }

protected:
    Device() = default;
    virtual Status doOpen() = 0;
    virtual Status doStart() = 0;
    virtual void doStop() = 0;
    virtual void doClose() {}
    virtual CaptureResult doCapture(std::chrono::milliseconds timeout) = 0;
    virtual Status doReconnect() { return Error{description() + " cannot reconnect"}; }

private:
    Status transitionError(const char* action) const;

    DeviceState state_ = DeviceState::Closed;
    std::optional<frame::RigidTransform> placement_;
};

} // namespace dc::devices
