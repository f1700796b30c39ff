#pragma once

#include "devices/device.h"
#include "devices/frame_pairer.h"
#include "devices/uvc/metadata_stream.h"
#include "devices/uvc/usb/usb_device_info.h"
#include "devices/uvc/v4l2/control_preset.h"
#include "devices/uvc/v4l2/handles.h"
#include "devices/uvc/v4l2/node_probe.h"
#include "devices/uvc/v4l2/v4l2_node.h"
#include "frame/calibration.h"

#include <chrono>
#include <memory>
#include <optional>
#include <string>

namespace dc::devices {

// What to open and how. A camera is named either by its depth node (v4l2:/dev/videoN) or by its USB ids
// (usb:VID:PID[:SERIAL]); either way its color node is found among the same USB device's nodes.
struct UvcConfig {
    std::string depthNode;            // v4l2:/dev/videoN
    std::optional<usb::UsbMatch> usb; // usb:VID:PID[:SERIAL]
    std::string colorNode;            // an explicit color node; empty: the camera's own, if it has one
    bool color = true;                // false: depth only
    std::optional<std::uint32_t> depthFourcc; // 'Z16 ' or 'Y16 '; default: Z16 when offered, else Y16
    int width = 0;                            // 0: the largest depth size up to 1280x720
    int height = 0;
    double fps = 0.0; // 0: 30 when offered, else the highest rate
    // The colour node's mode (colormode=, colorformat=): a mode asked for must be offered. Default: the
    // preferred image format, at the calibrated colour size, else the depth size, else the default choice.
    std::optional<std::uint32_t> colorFourcc;
    int colorWidth = 0; // 0: no size asked for
    int colorHeight = 0;
    double colorFps = 0.0;                 // 0: the depth's rate
    std::optional<float> depthScaleMeters; // meters per unit; default: known-camera table, else 1 mm
    // Default: a field-of-view guess, flagged approximate. A two-sensor file (`rig`) places the colour
    // node's image with its own sensor's model and the transform between the sensors.
    std::optional<frame::Calibration> calibration;
    std::chrono::milliseconds watchdog{2000}; // no frame for this long while streaming: Stalled
    // preset=FILE: control values set each time the camera opens (also after a replug).
    std::optional<v4l2::ControlPreset> preset;
    std::string presetPath;
    std::string sysfsRoot = "/sys";
};

// A live UVC/V4L2 depth camera: a depth node and an optional color node, streamed with mmap buffers. The
// capture thread dequeues, converts Z16/Y16 to meters (once, here), copies the color image, requeues, and
// pairs depth with color by timestamp; nothing else heavy runs there. An unplug (ENODEV/EIO) becomes
// Disconnected and the session's reconnect() finds the camera again by its USB identity (VID:PID, serial)
// when it returns; a dequeue watchdog turns silence into Stalled.
class UvcDevice final : public Device {
public:
    explicit UvcDevice(UvcConfig config, v4l2::Syscalls& sys = v4l2::systemSyscalls());
    ~UvcDevice() override;

    std::string description() const override;
    // The camera's nodes as a preset names them (live_source_spec.h cameraNodePaths): from the
    // configuration alone, which no thread changes, so the window may use them while the camera streams.
    std::shared_ptr<SensorControls> sensorControls() const override;
    Capabilities capabilities() const override;
    void interruptCapture() override;

    const UvcConfig& config() const { return config_; }
    // What was negotiated (valid after open).
    const v4l2::V4l2Format& depthFormat() const { return depthFormat_; }
    const v4l2::V4l2Format& colorFormat() const { return colorFormat_; }
    float depthScaleMeters() const { return depthScale_; }
    const frame::Intrinsics& depthIntrinsics() const { return depthIntrinsics_; }
    const std::string& depthNodePath() const { return depthPath_; }
    const std::string& colorNodePath() const { return colorPath_; }
    // The depth node's metadata node and its V4L2_META_FMT_* (empty and 0 without one).
    std::string metadataNodePath() const { return metadata_.path(); }
    std::uint32_t metadataFormat() const { return metadata_.dataFormat(); }
    const FramePairer& pairer() const { return pairer_; }
    // The two-sensor calibration the frames carry (null without one).
    const std::shared_ptr<const frame::RigCalibration>& rig() const { return rig_; }

protected:
    Status doOpen() override;
    Status doStart() override;
    void doStop() override;
    void doClose() override;
    CaptureResult doCapture(std::chrono::milliseconds timeout) override;
    Status doReconnect() override;

private:
    Status resolveNodes();
    Status resolveUsb(const usb::UsbMatch& match);
    void resolveColorSibling(const std::string& usbName);
    Status configureDepth();
    Status configureColor();
    Status openColor();
    std::vector<v4l2::ChosenMode> colorRequests(std::uint32_t fourcc) const;
    void openMetadata();
    bool isD4xx() const;
    void chooseDepthScale();
    void chooseIntrinsics();
    Status checkRigSizes() const;
    void applyPreset();
    v4l2::XuAccess xuAccess(const std::vector<std::string>& nodes) const;
    Status configureBoth();
    Status startStreaming();
    void closeNodes();

    std::optional<CaptureResult> service(v4l2::V4l2Node& node, const v4l2::NodeReadiness& ready,
                                         bool isDepth);
    std::optional<CaptureResult> takeBuffer(v4l2::V4l2Node& node, bool isDepth);
    std::optional<CaptureResult> restartAfterFormatChange(v4l2::V4l2Node& node);
    CaptureResult disconnect(const std::string& message);
    std::optional<CaptureResult> checkWatchdog();
    frame::FramePtr makeFrame(PairedCapture capture);

    UvcConfig config_;
    v4l2::Syscalls& sys_;
    v4l2::V4l2Node depth_;
    v4l2::V4l2Node color_;
    MetadataStream metadata_;
    v4l2::EventFd wake_;
    std::string depthPath_;
    std::string colorPath_;
    std::optional<usb::UsbDeviceInfo> usbIdentity_; // the camera's USB device, when it has one
    v4l2::V4l2Format depthFormat_;
    v4l2::V4l2Format colorFormat_;
    double depthFps_ = 0.0;
    float depthScale_ = 0.001f;
    frame::Intrinsics depthIntrinsics_;
    std::shared_ptr<const frame::RigCalibration> rig_;
    FramePairer pairer_{0};

    std::optional<StampedDepth> depthOnly_; // the newest depth frame when there is no color to pair with
    std::vector<v4l2::NodeReadiness> ready_;
    std::uint64_t sequence_ = 0;
    // What each node's timestamps mark, as its last buffer said (a driver stamps all its buffers alike).
    frame::TimestampSource depthStampSource_ = frame::TimestampSource::Unknown;
    frame::TimestampSource colorStampSource_ = frame::TimestampSource::Unknown;
    std::chrono::steady_clock::time_point lastFrame_{};
    bool stalled_ = false;
};

// The camera's extension unit, from the configuration alone (UvcDevice::sensorControls, `depthcloud
// controls`): a usb: source's nodes are probed for its depth node only when the known-camera table gives its
// VID:PID an extension unit, and the unit is reached only where the device's descriptors declare it.
v4l2::XuAccess extensionUnitAccess(v4l2::Syscalls& sys, const UvcConfig& config,
                                   const std::vector<std::string>& nodes);

} // namespace dc::devices
