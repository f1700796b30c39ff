#include "devices/uvc/metadata_stream.h"

#include "base/log.h"
#include "devices/uvc/usb/sysfs.h"
#include "devices/uvc/v4l2/pixel_formats.h"
#include "devices/uvc/v4l2/uvc_metadata.h"

#include <algorithm>
#include <charconv>
#include <cstring>
#include <linux/videodev2.h>

namespace dc::devices {

namespace {

using Clock = std::chrono::steady_clock;

// A bad buffer after the first is told at most this often, with how many there were.
constexpr std::chrono::seconds kBadReportInterval{10};

// Whether sequence `a` comes before `b`, across the wrap at 2^32.
bool before(std::uint32_t a, std::uint32_t b) {
    return static_cast<std::int32_t>(a - b) < 0;
}

// The payload headers' clocks: PTS is the same in every header of a frame; the last SCR is the newest.
void readClocks(const std::vector<v4l2::UvcPayloadHeader>& headers, frame::CameraMetadata& out) {
    for (const v4l2::UvcPayloadHeader& h : headers) {
        if (h.pts && !out.ptsTicks)
            out.ptsTicks = h.pts;
        if (h.scr) {
            out.scrTicks = h.scr->sourceTimeClock;
            out.scrUsbFrame = h.scr->sofToken;
        }
    }
}

// "/dev/video4" -> "/dev/video5"; empty for a path not named so.
std::string nextNodePath(const std::string& path) {
    constexpr std::string_view kPrefix = "/dev/video";
    if (path.rfind(kPrefix, 0) != 0)
        return {};
    int n = 0;
    const char* first = path.data() + kPrefix.size();
    const char* last = path.data() + path.size();
    const auto [end, ec] = std::from_chars(first, last, n);
    if (ec != std::errc() || end != last || first == last)
        return {};
    return std::string(kPrefix) + std::to_string(n + 1);
}

} // namespace

Expected<FrameMetadata> readFrameMetadata(std::uint32_t dataFormat, std::span<const std::uint8_t> bytes) {
    FrameMetadata out;
    if (dataFormat == V4L2_META_FMT_D4XX) {
        auto d4xx = v4l2::parseD4xxMetadata(bytes);
        if (!d4xx)
            return d4xx.error();
        out.exposureUs = d4xx->exposureUs;
        out.camera.frameCounter = d4xx->frameCounter;
        out.camera.gain = d4xx->gain;
        out.camera.laserPowerMw = d4xx->laserPower;
        readClocks(d4xx->headers, out.camera);
        return out;
    }
    auto headers = v4l2::parseUvcMetadata(bytes);
    if (!headers)
        return headers.error();
    readClocks(*headers, out.camera);
    return out;
}

void MetadataWindow::add(std::uint32_t sequence, FrameMetadata metadata) {
    if (lastTaken_ && !before(*lastTaken_, sequence))
        return; // its frame has gone out already
    if (entries_.size() == kSize)
        entries_.pop_front();
    entries_.emplace_back(sequence, std::move(metadata));
}

std::optional<FrameMetadata> MetadataWindow::take(std::uint32_t sequence) {
    lastTaken_ = sequence;
    std::optional<FrameMetadata> found;
    std::erase_if(entries_, [&](auto& entry) {
        if (entry.first == sequence)
            found = std::move(entry.second);
        return !before(sequence, entry.first);
    });
    return found;
}

void MetadataWindow::clear() {
    entries_.clear();
    lastTaken_.reset();
}

void MetadataStream::open(const v4l2::V4l2Node& video, bool d4xx, const std::string& who,
                          const std::string& sysfsRoot) {
    close();
    who_ = who;
    const std::string path = nextNodePath(video.path());
    // Opening a gadget's own node would connect the gadget: it is never a camera's metadata node.
    const bool found = !path.empty() && usb::Sysfs(sysfsRoot).busOf(path) != "gadget" &&
                       node_.open(path) == 0 && node_.capability().canCaptureMetadata() &&
                       node_.capability().canStream() &&
                       node_.capability().busInfo == video.capability().busInfo;
    if (!found) {
        node_.close();
        if (!std::exchange(toldUnavailable_, true))
            logInfo(who_ + ": " + video.path() + " has no metadata node; frames carry none of its metadata");
        return;
    }
    const std::vector<std::uint32_t> offered = node_.formats();
    const auto offers = [&](std::uint32_t f) {
        return std::find(offered.begin(), offered.end(), f) != offered.end();
    };
    const std::uint32_t format = d4xx && offers(V4L2_META_FMT_D4XX) ? V4L2_META_FMT_D4XX : V4L2_META_FMT_UVC;
    if (const int r = node_.setMetadataFormat(format); r < 0 || node_.format().fourcc != format) {
        giveUp(r < 0 ? node_.describe("VIDIOC_S_FMT", r)
                     : path + ": the driver replaced '" + v4l2::fourccToString(format) + "' with '" +
                           v4l2::fourccToString(node_.format().fourcc) + "'");
        return;
    }
    dataFormat_ = format;
}

void MetadataStream::start() {
    if (!node_.isOpen() || node_.streaming())
        return;
    window_.clear();
    int r = node_.allocateBuffers();
    if (r >= 0)
        r = node_.streamOn();
    if (r < 0)
        giveUp(node_.describe("starting the stream", r));
}

void MetadataStream::stop() {
    node_.streamOff();
    window_.clear();
}

void MetadataStream::close() {
    node_.close();
    window_.clear();
    dataFormat_ = 0;
}

void MetadataStream::giveUp(const std::string& message) {
    node_.close();
    if (!std::exchange(toldUnavailable_, true))
        logWarning(who_ + ": streaming without the camera's metadata (no exposure per frame): " + message);
}

void MetadataStream::reportBad(const std::string& message) {
    ++badSinceReport_;
    const Clock::time_point now = Clock::now();
    if (badReported_ && now - lastBadReport_ < kBadReportInterval)
        return;
    const std::uint64_t count = std::exchange(badSinceReport_, 0);
    logWarning(who_ + ": metadata buffer skipped: " + message +
               (count > 1 ? " (" + std::to_string(count) + " bad buffers since the last report)" : ""));
    badReported_ = true;
    lastBadReport_ = now;
}

unsigned MetadataStream::drain() {
    // Bounded: a driver that always has a buffer ready cannot keep the capture thread here.
    unsigned taken = 0;
    for (; taken < 2 * v4l2::V4l2Node::kBufferCount && node_.streaming(); ++taken) {
        v4l2::DequeueResult d = node_.dequeue();
        switch (d.kind) {
        case v4l2::DequeueResult::Kind::NotReady:
            return taken;
        case v4l2::DequeueResult::Kind::Dropped:
            reportBad(d.message);
            continue;
        case v4l2::DequeueResult::Kind::Failed:
            giveUp(d.message);
            return taken;
        case v4l2::DequeueResult::Kind::Buffer:
            break;
        }
        auto metadata = readFrameMetadata(dataFormat_, d.buffer.bytes);
        if (metadata)
            window_.add(d.buffer.sequence, std::move(*metadata));
        else
            reportBad(path() + ": frame " + std::to_string(d.buffer.sequence) + ": " +
                      metadata.error().message);
        if (const int r = node_.requeue(d.buffer.index); r < 0)
            giveUp(node_.describe("VIDIOC_QBUF", r));
    }
    return taken;
}

void MetadataStream::service(const v4l2::NodeReadiness& ready) {
    if (!ready.buffer && !ready.error)
        return;
    if (drain() == 0 && ready.error && node_.streaming()) // POLLERR with nothing to dequeue
        giveUp(path() + ": the metadata queue reported an error");
}

void MetadataStream::fill(std::uint32_t sequence, frame::FrameTiming& timing) {
    if (node_.streaming())
        drain(); // a buffer that became ready after the poll
    if (auto metadata = window_.take(sequence)) {
        timing.depth.exposureUs = metadata->exposureUs;
        timing.depthMetadata = metadata->camera;
    }
}

} // namespace dc::devices
