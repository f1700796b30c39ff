#include "devices/uvc/uvc_device.h"

#include "base/clock.h"
#include "base/log.h"
#include "devices/frame_pacer.h"
#include "devices/uvc/live_source_spec.h"
#include "devices/uvc/usb/known_cameras.h"
#include "devices/uvc/usb/sysfs.h"
#include "devices/uvc/usb/usb_enumeration.h"
#include "devices/uvc/v4l2/pixel_formats.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <linux/videodev2.h>

namespace dc::devices {

namespace {

using Clock = std::chrono::steady_clock;
using v4l2::DequeueResult;

// Errors that mean the camera is gone rather than that one call went wrong.
bool meansUnplugged(int error) {
    return error == -ENODEV || error == -EIO || error == -ENXIO || error == -ESHUTDOWN;
}

// What a buffer's timestamp marks; `driverStamp`: the driver's own monotonic stamp is used, not ours.
frame::TimestampSource stampSource(const v4l2::V4l2Buffer& b, bool driverStamp) {
    if (!driverStamp)
        return frame::TimestampSource::Arrival;
    return b.startOfExposure ? frame::TimestampSource::StartOfExposure : frame::TimestampSource::EndOfFrame;
}

// What the driver said about a stamped buffer. Its v4l2_buffer.sequence is 32 bits wide; the exposure is
// the metadata node's (MetadataStream::fill).
frame::StreamTiming driverTiming(std::uint64_t sequence, std::int64_t stampNs,
                                 frame::TimestampSource source) {
    frame::StreamTiming t;
    t.driverSequence = static_cast<std::uint32_t>(sequence);
    t.sensorNs = stampNs;
    t.source = source;
    t.monotonic = true;
    return t;
}

std::string formatText(const v4l2::V4l2Format& f) {
    return std::to_string(f.width) + "x" + std::to_string(f.height) + " '" + v4l2::fourccToString(f.fourcc) +
           "'";
}

std::string seconds(std::chrono::milliseconds ms) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f s", static_cast<double>(ms.count()) / 1000.0);
    return text;
}

std::optional<v4l2::ProbedNode> probe(v4l2::Syscalls& sys, const std::string& path) {
    int error = 0;
    return v4l2::probeNode(sys, path, error);
}

// Opens `path` on `node` and sets `mode`; the format the driver chose comes back in `format`.
Status openWithMode(v4l2::V4l2Node& node, const std::string& path, const v4l2::ChosenMode& mode,
                    v4l2::V4l2Format& format) {
    if (const int r = node.open(path); r < 0)
        return Error{"cannot open " + path + ": " + std::strerror(-r)};
    format = {mode.fourcc, mode.width, mode.height, 0, 0};
    if (const int r = node.setFormat(format); r < 0)
        return Error{node.describe("VIDIOC_S_FMT", r)};
    if (format.fourcc != mode.fourcc)
        return Error{path + ": the driver replaced '" + v4l2::fourccToString(mode.fourcc) + "' with '" +
                     v4l2::fourccToString(format.fourcc) + "'"};
    if (mode.fps > 0.0) {
        if (const int r = node.setFrameRate(mode.fps); r < 0) // not every driver can: keep its own rate
            logWarning(node.describe("VIDIOC_S_PARM", r) + "; streaming at the driver's rate");
    }
    (void)node.subscribeSourceChange(); // optional: uvcvideo has no source-change events
    return {};
}

// The first of `requests` that `modes` offer; the error is the last one's.
Expected<v4l2::ChosenMode> firstOffered(const std::vector<v4l2::V4l2Mode>& modes,
                                        const std::vector<v4l2::ChosenMode>& requests) {
    Expected<v4l2::ChosenMode> mode = Error{"no mode requested"};
    for (const v4l2::ChosenMode& request : requests)
        if ((mode = v4l2::chooseMode(modes, request)))
            break;
    return mode;
}

// The node that streams depth (Z16 or Y16): a D4xx's depth extension unit belongs to the same interface.
std::string depthNodeOf(v4l2::Syscalls& sys, const std::vector<std::string>& nodes) {
    for (const std::string& path : nodes) {
        v4l2::V4l2Node node(sys);
        if (node.open(path) < 0)
            continue;
        const std::vector<std::uint32_t> formats = node.formats();
        if (std::any_of(formats.begin(), formats.end(),
                        [](std::uint32_t f) { return f == V4L2_PIX_FMT_Z16 || f == V4L2_PIX_FMT_Y16; }))
            return path;
    }
    return {};
}

// The extension unit of the USB device behind `depthNode`: none for a camera not on USB, not in the
// known-camera table, or whose descriptors do not declare the unit the table gives its VID:PID.
v4l2::XuAccess xuAccessOf(const std::string& sysfsRoot, const std::optional<usb::UsbDeviceInfo>& device,
                          const std::string& depthNode) {
    if (!device)
        return {};
    v4l2::XuAccess access = v4l2::xuAccessFor(device->vendorId, device->productId, depthNode);
    if (!access.unit)
        return {};
    // sysfs gives this file a size larger than what it holds: read to its end, not by its size.
    std::ifstream in(sysfsRoot + "/bus/usb/devices/" + device->sysfsName() + "/descriptors",
                     std::ios::binary);
    const std::vector<std::uint8_t> descriptors{std::istreambuf_iterator<char>(in), {}};
    return v4l2::declaresExtensionUnit(descriptors, *access.unit) ? access : v4l2::XuAccess{};
}

} // namespace

UvcDevice::UvcDevice(UvcConfig config, v4l2::Syscalls& sys)
    : config_(std::move(config)), sys_(sys), depth_(sys), color_(sys), metadata_(sys) {
    if (config_.calibration && config_.calibration->rig)
        rig_ = std::make_shared<const frame::RigCalibration>(*config_.calibration->rig);
}

UvcDevice::~UvcDevice() {
    closeNodes();
}

std::string UvcDevice::description() const {
    if (config_.usb) {
        const usb::KnownCamera* known = usb::findKnownCamera(config_.usb->vendorId, config_.usb->productId);
        return "USB camera " + config_.usb->toString() + (known ? std::string(" (") + known->name + ")" : "");
    }
    return "V4L2 " + config_.depthNode;
}

Capabilities UvcDevice::capabilities() const {
    Capabilities c;
    c.sceneDepth = true;
    c.color = config_.color;
    c.reconnects = true;
    c.approximateIntrinsics = !config_.calibration;
    c.unregisteredColour = config_.color && !rig_;
    c.monotonicTimestamps = true;
    c.nominalFps = config_.fps; // the rate asked for; 0 (unknown) when the camera's default is used
    return c;
}

void UvcDevice::interruptCapture() {
    (void)wake_.signal();
}

Status UvcDevice::resolveUsb(const usb::UsbMatch& match) {
    const usb::Sysfs sysfs(config_.sysfsRoot);
    auto devices = usb::enumerateUsbDevices(sysfs);
    if (!devices)
        return devices.error();
    for (const usb::UsbDeviceInfo& device : *devices) {
        if (!device.matches(match))
            continue;
        std::vector<v4l2::ProbedNode> probed;
        for (const std::string& path : sysfs.videoNodesOf(device.sysfsName()))
            if (auto node = probe(sys_, path))
                probed.push_back(std::move(*node));
        const v4l2::NodeRoles roles = v4l2::assignRoles(probed);
        if (roles.depth.empty())
            return Error{"USB camera " + device.id() + " has no V4L2 node with Z16 or Y16 depth (yet)"};
        usbIdentity_ = device;
        depthPath_ = roles.depth;
        if (config_.color && config_.colorNode.empty())
            colorPath_ = roles.color;
        return {};
    }
    return Error{"no USB camera " + match.toString() + " is connected"};
}

void UvcDevice::resolveColorSibling(const std::string& usbName) {
    std::vector<v4l2::ProbedNode> probed;
    for (const std::string& path : usb::Sysfs(config_.sysfsRoot).videoNodesOf(usbName))
        if (path != depthPath_)
            if (auto node = probe(sys_, path))
                probed.push_back(std::move(*node));
    colorPath_ = v4l2::assignRoles(probed).color;
    if (colorPath_.empty()) // assignRoles may have taken a Y16/Z16 node as depth: color is what we want
        for (const v4l2::ProbedNode& node : probed)
            if (node.offersRole(v4l2::FormatRole::Color))
                colorPath_ = node.path;
}

Status UvcDevice::resolveNodes() {
    depthPath_.clear();
    colorPath_.clear();
    if (config_.color && !config_.colorNode.empty())
        colorPath_ = config_.colorNode;
    // A node path seen before belongs to a USB camera: after an unplug its node number may change, so find
    // it again by identity, as a usb: source does.
    if (config_.usb || usbIdentity_) {
        const usb::UsbMatch match =
            config_.usb
                ? *config_.usb
                : usb::UsbMatch{usbIdentity_->vendorId, usbIdentity_->productId, usbIdentity_->serial};
        return resolveUsb(match);
    }
    depthPath_ = config_.depthNode;
    usbIdentity_ = usb::Sysfs(config_.sysfsRoot).usbDeviceOf(depthPath_);
    if (usbIdentity_ && config_.color && config_.colorNode.empty())
        resolveColorSibling(usbIdentity_->sysfsName());
    return {};
}

Status UvcDevice::configureDepth() {
    const auto probed = probe(sys_, depthPath_);
    if (!probed)
        return Error{"cannot use " + depthPath_ +
                     " as a depth node: it cannot be opened or does not capture video"};
    std::uint32_t fourcc = V4L2_PIX_FMT_Z16;
    if (config_.depthFourcc)
        fourcc = *config_.depthFourcc;
    else if (!probed->offers(V4L2_PIX_FMT_Z16))
        fourcc = V4L2_PIX_FMT_Y16;
    if (!config_.depthFourcc && !probed->offers(fourcc))
        return Error{depthPath_ + " offers no Z16 or Y16 depth format (is it the camera's color node?)"};
    std::vector<v4l2::ChosenMode> requests{{fourcc, config_.width, config_.height, config_.fps}};
    // A two-sensor calibration holds for the size each sensor was calibrated at: ask for that one first.
    if (rig_ && config_.width == 0)
        requests.insert(requests.begin(),
                        {fourcc, rig_->depth.intrinsics.width, rig_->depth.intrinsics.height, config_.fps});
    auto mode = firstOffered(probed->modes, requests);
    if (!mode)
        return Error{depthPath_ + ": no usable depth mode: " + mode.error().message};
    if (Status s = openWithMode(depth_, depthPath_, *mode, depthFormat_); !s)
        return s;
    depthFps_ = mode->fps;
    chooseDepthScale();
    chooseIntrinsics();
    return {};
}

// The colour modes of `fourcc` to try, in order: the one the spec asks for alone, else the default choice.
std::vector<v4l2::ChosenMode> UvcDevice::colorRequests(std::uint32_t fourcc) const {
    if (config_.colorWidth > 0)
        return {{fourcc, config_.colorWidth, config_.colorHeight,
                 config_.colorFps > 0.0 ? config_.colorFps : depthFps_}};
    // The calibrated colour size first, then the depth size (same aspect, least to resample), else the
    // default choice.
    std::vector<v4l2::ChosenMode> requests{{fourcc, depthFormat_.width, depthFormat_.height, depthFps_},
                                           {fourcc, 0, 0, depthFps_}};
    if (rig_)
        requests.insert(requests.begin(),
                        {fourcc, rig_->colour.intrinsics.width, rig_->colour.intrinsics.height, depthFps_});
    return requests;
}

Status UvcDevice::openColor() {
    const auto probed = probe(sys_, colorPath_);
    if (!probed)
        return Error{"it cannot be opened or does not capture video"};
    const std::uint32_t fourcc =
        config_.colorFourcc.value_or(v4l2::preferredImageFormat(*probed).value_or(0));
    if (fourcc == 0)
        return Error{"it offers no YUYV/NV12/RGB24/MJPEG/GREY format"};
    if (!probed->offers(fourcc))
        return Error{"it offers no '" + v4l2::fourccToString(fourcc) + "' format (colorformat=)"};
    auto mode = firstOffered(probed->modes, colorRequests(fourcc));
    if (!mode)
        return mode.error();
    return openWithMode(color_, colorPath_, *mode, colorFormat_);
}

// Without a colour mode asked for, a colour node that cannot stream leaves depth alone; a mode asked for
// (the window's mode list) that cannot be had is refused, so that the person sees why.
Status UvcDevice::configureColor() {
    if (colorPath_.empty())
        return {};
    if (Status s = openColor(); !s) {
        color_.close();
        if (config_.colorFourcc || config_.colorWidth > 0)
            return Error{colorPath_ + ": " + s.error().message};
        logWarning("streaming depth without color: " + colorPath_ + ": " + s.error().message);
        colorPath_.clear();
    }
    return {};
}

void UvcDevice::chooseDepthScale() {
    const usb::KnownCamera* known =
        usbIdentity_ ? usb::findKnownCamera(usbIdentity_->vendorId, usbIdentity_->productId) : nullptr;
    if (config_.depthScaleMeters) {
        depthScale_ = *config_.depthScaleMeters;
    } else if (known) {
        depthScale_ = known->depthScaleMeters;
    } else {
        depthScale_ = usb::kDefaultDepthScaleMeters;
        logWarning(description() + ": unknown camera, assuming depth in units of 1 mm (set scale=METERS)");
    }
}

void UvcDevice::chooseIntrinsics() {
    const int w = depthFormat_.width;
    const int h = depthFormat_.height;
    if (rig_) { // checkRigSizes() refuses a stream of another shape
        depthIntrinsics_ = rig_->depth.intrinsics.scaledTo(w, h);
        return;
    }
    if (config_.calibration) {
        const frame::Intrinsics& k = config_.calibration->intrinsics;
        if (std::abs(static_cast<double>(k.width) / k.height - static_cast<double>(w) / h) > 0.01)
            logWarning(description() + ": calibration is for " + std::to_string(k.width) + "x" +
                       std::to_string(k.height) + ", a different aspect than the " + std::to_string(w) + "x" +
                       std::to_string(h) + " stream");
        depthIntrinsics_ = k.scaledTo(w, h);
        return;
    }
    const usb::KnownCamera* known =
        usbIdentity_ ? usb::findKnownCamera(usbIdentity_->vendorId, usbIdentity_->productId) : nullptr;
    const double fov = known ? known->depthHorizontalFovDegrees : usb::kDefaultHorizontalFovDegrees;
    depthIntrinsics_ = frame::intrinsicsFromFieldOfView(w, h, fov);
    logWarning(description() + ": " + kApproximateIntrinsicsMessage + " (" +
               std::to_string(std::lround(fov)) + " degrees horizontal)");
}

// A two-sensor calibration fits only streams of its sensors' shapes: anything else would colour every
// point from the wrong place.
Status UvcDevice::checkRigSizes() const {
    if (!rig_)
        return {};
    const bool color = !colorPath_.empty();
    if (Status s = frame::checkStreamSizes(*config_.calibration, depthFormat_.width, depthFormat_.height,
                                           color ? colorFormat_.width : 0, color ? colorFormat_.height : 0);
        !s)
        return Error{description() + ": " + rig_->name + ": " + s.error().message};
    return {};
}

Status UvcDevice::configureBoth() {
    Status s = resolveNodes();
    if (s)
        s = configureDepth();
    if (s)
        s = configureColor();
    if (s)
        s = checkRigSizes();
    if (s)
        openMetadata();
    return s;
}

// A RealSense D4xx (the known-camera table's depth extension unit) sends Intel's metadata blocks.
bool UvcDevice::isD4xx() const {
    const std::optional<usb::UsbDeviceInfo> device =
        usbIdentity_ ? usbIdentity_ : usb::Sysfs(config_.sysfsRoot).usbDeviceOf(depthPath_);
    const usb::KnownCamera* known =
        device ? usb::findKnownCamera(device->vendorId, device->productId) : nullptr;
    return known && known->realsenseDepthXu;
}

void UvcDevice::openMetadata() {
    metadata_.open(depth_, isD4xx(), description(), config_.sysfsRoot);
    if (!metadata_.path().empty())
        logInfo(description() + ": metadata " + metadata_.path() + " '" +
                v4l2::fourccToString(metadata_.dataFormat()) + "'");
}

Status UvcDevice::doOpen() {
    if (!wake_.valid()) {
        if (const int r = wake_.create(sys_); r < 0)
            return Error{std::string("cannot create the capture thread's wake-up eventfd: ") +
                         std::strerror(-r)};
    }
    if (Status s = configureBoth(); !s) {
        closeNodes();
        return s;
    }
    logInfo(description() + ": depth " + depthPath_ + " " + formatText(depthFormat_) +
            (colorPath_.empty() ? ", no color" : ", color " + colorPath_ + " " + formatText(colorFormat_)) +
            (rig_ ? ", " + frame::describe(*rig_) : ""));
    if (!colorPath_.empty() && !rig_)
        logWarning(description() + ": " + kUnregisteredColourMessage);
    applyPreset();
    return {};
}

std::shared_ptr<SensorControls> UvcDevice::sensorControls() const {
    auto nodes = cameraNodePaths(config_);
    if (!nodes)
        return nullptr;
    v4l2::XuAccess xu = xuAccess(*nodes);
    return std::make_shared<v4l2::V4l2SensorControls>(sys_, std::move(*nodes), std::move(xu));
}

v4l2::XuAccess UvcDevice::xuAccess(const std::vector<std::string>& nodes) const {
    return extensionUnitAccess(sys_, config_, nodes);
}

v4l2::XuAccess extensionUnitAccess(v4l2::Syscalls& sys, const UvcConfig& config,
                                   const std::vector<std::string>& nodes) {
    std::string depth = config.depthNode;
    if (config.usb) {
        const bool known = v4l2::xuAccessFor(config.usb->vendorId, config.usb->productId, {}).unit != nullptr;
        depth = known ? depthNodeOf(sys, nodes) : std::string();
    }
    if (depth.empty())
        return {};
    return xuAccessOf(config.sysfsRoot, usb::Sysfs(config.sysfsRoot).usbDeviceOf(depth), depth);
}

// A value the camera refuses is told and the rest are set: the camera streams either way.
void UvcDevice::applyPreset() {
    if (!config_.preset)
        return;
    std::vector<std::string> nodes{depthPath_};
    if (config_.usb) {
        auto all = cameraNodePaths(config_);
        if (all)
            nodes = std::move(*all);
    } else if (!colorPath_.empty()) {
        nodes.push_back(colorPath_);
    }
    const std::vector<std::string> refused = v4l2::applyPreset(
        sys_, *config_.preset, nodes, xuAccessOf(config_.sysfsRoot, usbIdentity_, depthPath_));
    for (const std::string& message : refused)
        logWarning(description() + ": preset " + config_.presetPath + ": " + message);
    logInfo(description() + ": preset " + config_.presetPath + " applied" +
            (refused.empty() ? "" : ", " + std::to_string(refused.size()) + " value(s) refused"));
}

Status UvcDevice::startStreaming() {
    metadata_.start(); // first, so that the first frames have theirs
    for (v4l2::V4l2Node* node : {&depth_, &color_}) {
        if (!node->isOpen())
            continue;
        int r = node->allocateBuffers();
        if (r >= 0)
            r = node->streamOn();
        if (r < 0) {
            const std::string message = node->describe("starting the stream", r);
            depth_.streamOff();
            color_.streamOff();
            metadata_.stop();
            return Error{message};
        }
    }
    // Half a depth frame period: with equal rates at most one color frame lies that close (see FramePairer).
    const double fps = depthFps_ > 0.0 ? depthFps_ : 30.0;
    pairer_ = FramePairer(static_cast<std::int64_t>(0.5e9 / fps));
    lastFrame_ = Clock::now();
    stalled_ = false;
    return {};
}

Status UvcDevice::doStart() {
    return startStreaming();
}

void UvcDevice::doStop() {
    depth_.streamOff();
    color_.streamOff();
    metadata_.stop();
}

void UvcDevice::doClose() {
    closeNodes();
}

void UvcDevice::closeNodes() {
    depth_.close();
    color_.close();
    metadata_.close();
    pairer_.reset();
    depthOnly_.reset();
}

Status UvcDevice::doReconnect() {
    closeNodes();
    Status s = configureBoth();
    if (s)
        s = startStreaming();
    if (!s)
        closeNodes();
    else
        logInfo(description() + ": reconnected on " + depthPath_);
    return s;
}

CaptureResult UvcDevice::disconnect(const std::string& message) {
    closeNodes();
    return {CaptureResult::Kind::Disconnected, nullptr, message};
}

std::optional<CaptureResult> UvcDevice::checkWatchdog() {
    const auto silent = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - lastFrame_);
    if (stalled_ || silent < config_.watchdog)
        return std::nullopt;
    stalled_ = true;
    return CaptureResult{CaptureResult::Kind::Stalled, nullptr,
                         "no frame from " + depthPath_ + " for " + seconds(silent) + " (dequeue watchdog)"};
}

std::optional<CaptureResult> UvcDevice::restartAfterFormatChange(v4l2::V4l2Node& node) {
    const bool isDepth = &node == &depth_;
    v4l2::V4l2Format now;
    node.streamOff();
    int r = node.getFormat(now);
    // Only the size may change under us; anything else cannot be streamed as this node's role.
    if (r == 0 &&
        (isDepth ? v4l2::roleOf(now.fourcc) != v4l2::FormatRole::Depth : now.fourcc != colorFormat_.fourcc))
        r = -EINVAL;
    if (r == 0)
        r = node.setFormat(now);
    if (r == 0)
        r = node.allocateBuffers();
    if (r >= 0)
        r = node.streamOn();
    if (r < 0)
        return disconnect(node.path() + ": the format changed under us (" + formatText(now) +
                          ") and the stream cannot continue: " + std::strerror(-r));
    (isDepth ? depthFormat_ : colorFormat_) = now;
    if (isDepth) {
        depthIntrinsics_ = depthIntrinsics_.scaledTo(now.width, now.height);
        metadata_.restart();
    }
    if (Status s = checkRigSizes(); !s) // reconnecting asks for the calibrated sizes again
        return disconnect(s.error().message);
    pairer_.reset();
    return CaptureResult{CaptureResult::Kind::Error, nullptr,
                         node.path() + ": the format changed under us; restarted at " + formatText(now)};
}

std::optional<CaptureResult> UvcDevice::takeBuffer(v4l2::V4l2Node& node, bool isDepth) {
    DequeueResult d = node.dequeue();
    switch (d.kind) {
    case DequeueResult::Kind::NotReady:
        return std::nullopt;
    case DequeueResult::Kind::Dropped:
        return CaptureResult{CaptureResult::Kind::Error, nullptr, d.message};
    case DequeueResult::Kind::Failed:
        if (meansUnplugged(d.error))
            return disconnect(d.message);
        return CaptureResult{CaptureResult::Kind::Error, nullptr, d.message};
    case DequeueResult::Kind::Buffer:
        break;
    }
    const v4l2::V4l2Buffer& b = d.buffer;
    const bool driverStamp = b.monotonicTimestamp && b.timestampNs > 0;
    const std::int64_t stamp = driverStamp ? b.timestampNs : base::monotonicNowNs();
    (isDepth ? depthStampSource_ : colorStampSource_) = stampSource(b, driverStamp);
    std::optional<CaptureResult> problem;
    if (isDepth) {
        StampedDepth depth{b.sequence, stamp, {}};
        v4l2::depthToMeters(b.bytes, depthFormat_.width, depthFormat_.height, depthFormat_.bytesPerLine,
                            depthScale_, depth.depthMeters);
        if (color_.streaming())
            pairer_.pushDepth(std::move(depth));
        else
            depthOnly_ = std::move(depth);
    } else if (auto image = v4l2::toCapturedImage(colorFormat_.fourcc, b.bytes, colorFormat_.width,
                                                  colorFormat_.height, colorFormat_.bytesPerLine)) {
        pairer_.pushColor({b.sequence, stamp, std::move(*image)});
    } else {
        problem =
            CaptureResult{CaptureResult::Kind::Error, nullptr, node.path() + ": " + image.error().message};
    }
    if (const int r = node.requeue(b.index); r < 0) {
        if (meansUnplugged(r))
            return disconnect(node.describe("VIDIOC_QBUF", r));
        problem = CaptureResult{CaptureResult::Kind::Error, nullptr, node.describe("VIDIOC_QBUF", r)};
    }
    return problem;
}

std::optional<CaptureResult> UvcDevice::service(v4l2::V4l2Node& node, const v4l2::NodeReadiness& ready,
                                                bool isDepth) {
    if (ready.event && node.takeSourceChange())
        return restartAfterFormatChange(node);
    if (!ready.buffer && !ready.error)
        return std::nullopt;
    std::optional<CaptureResult> result = takeBuffer(node, isDepth);
    if (!result && ready.error && !ready.buffer) // POLLERR with nothing to dequeue: the queue itself failed
        return disconnect(node.path() + ": the capture queue reported an error");
    return result;
}

frame::FramePtr UvcDevice::makeFrame(PairedCapture capture) {
    auto frame = std::make_shared<frame::Frame>();
    frame->sequence = sequence_++;
    frame->timestampNs = capture.depth.timestampNs;
    frame->cameraIntrinsics = depthIntrinsics_;
    frame->timing.depth = driverTiming(capture.depth.sequence, capture.depth.timestampNs, depthStampSource_);
    metadata_.fill(static_cast<std::uint32_t>(capture.depth.sequence), frame->timing);
    if (capture.color) {
        frame->timing.colour =
            driverTiming(capture.color->sequence, capture.color->timestampNs, colorStampSource_);
        frame->capturedImage = std::move(capture.color->image);
        const int w = frame->capturedImage.width, h = frame->capturedImage.height;
        if (rig_) {
            // A rig frame's image intrinsics are the colour sensor's; its depth intrinsics come from the rig.
            frame->rig = rig_;
            frame->cameraIntrinsics = rig_->colour.intrinsics.scaledTo(w, h);
        } else {
            // Without a calibration between the sensors the frame model's single camera stands in: the
            // depth camera's intrinsics (the ones that place points in 3D), scaled to the image. The
            // status line says the colours are not registered.
            frame->cameraIntrinsics = depthIntrinsics_.scaledTo(w, h);
        }
    }
    frame->sceneDepth = frame::DepthData{std::move(capture.depth.depthMeters), {}};
    return frame;
}

CaptureResult UvcDevice::doCapture(std::chrono::milliseconds timeout) {
    if (!depth_.streaming())
        return disconnect(description() + ": the depth node is not streaming");
    if (auto stalled = checkWatchdog())
        return *stalled;
    // The metadata node first: uvcvideo completes a frame's metadata buffer before its video buffer.
    std::vector<v4l2::V4l2Node*> nodes;
    if (metadata_.streaming())
        nodes.push_back(&metadata_.node());
    nodes.push_back(&depth_);
    if (color_.streaming())
        nodes.push_back(&color_);
    const int r = v4l2::waitForNodes(sys_, nodes, &wake_, static_cast<int>(timeout.count()), ready_);
    if (r < 0 && r != -ECANCELED)
        return {CaptureResult::Kind::Error, nullptr, description() + ": poll failed: " + std::strerror(-r)};
    for (std::size_t i = 0; r > 0 && i < nodes.size(); ++i) {
        if (nodes[i] == &metadata_.node())
            metadata_.service(ready_[i]);
        else if (auto result = service(*nodes[i], ready_[i], nodes[i] == &depth_))
            return *result;
    }
    std::optional<PairedCapture> paired;
    if (color_.streaming())
        paired = pairer_.pop();
    else if (depthOnly_)
        paired = PairedCapture{std::exchange(depthOnly_, std::nullopt).value(), std::nullopt};
    if (!paired)
        return checkWatchdog().value_or(CaptureResult{});
    lastFrame_ = Clock::now();
    stalled_ = false;
    return {CaptureResult::Kind::Frame, makeFrame(std::move(*paired)), {}};
}

} // namespace dc::devices
