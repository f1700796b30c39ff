#include "devices/uvc/v4l2/v4l2_node.h"

#include "devices/uvc/v4l2/pixel_formats.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <linux/videodev2.h>

namespace dc::devices::v4l2 {

namespace {

constexpr std::uint32_t kCaptureType = V4L2_BUF_TYPE_VIDEO_CAPTURE;
// Enumeration loops stop here even if a broken driver never returns EINVAL.
constexpr std::uint32_t kMaxEnumerated = 256;

std::string fixedString(const std::uint8_t* text, std::size_t size) {
    return std::string(reinterpret_cast<const char*>(text),
                       strnlen(reinterpret_cast<const char*>(text), size));
}

double fps(const v4l2_fract& interval) {
    return interval.numerator ? static_cast<double>(interval.denominator) / interval.numerator : 0.0;
}

std::int64_t timestampNs(const timeval& t) {
    return static_cast<std::int64_t>(t.tv_sec) * 1'000'000'000 + static_cast<std::int64_t>(t.tv_usec) * 1000;
}

} // namespace

bool V4l2Capability::canCapture() const {
    return (deviceCaps & V4L2_CAP_VIDEO_CAPTURE) != 0;
}

bool V4l2Capability::canCaptureMetadata() const {
    return (deviceCaps & V4L2_CAP_META_CAPTURE) != 0;
}

bool V4l2Capability::canStream() const {
    return (deviceCaps & V4L2_CAP_STREAMING) != 0;
}

std::uint32_t V4l2Node::bufferType() const {
    return kind_ == BufferKind::Video ? kCaptureType : static_cast<std::uint32_t>(V4L2_BUF_TYPE_META_CAPTURE);
}

v4l2_buffer V4l2Node::mmapBuffer(unsigned index) const {
    v4l2_buffer b{};
    b.type = bufferType();
    b.memory = V4L2_MEMORY_MMAP;
    b.index = index;
    return b;
}

int V4l2Node::open(const std::string& path) {
    close();
    const int fd = xopen(*sys_, path.c_str(), O_RDWR | O_NONBLOCK);
    if (fd < 0)
        return fd;
    fd_ = base::UniqueFd(fd, *sys_);
    path_ = path;
    v4l2_capability cap{};
    if (const int r = ioctl(VIDIOC_QUERYCAP, &cap); r < 0) {
        fd_.reset();
        return r;
    }
    capability_.driver = fixedString(cap.driver, sizeof cap.driver);
    capability_.card = fixedString(cap.card, sizeof cap.card);
    capability_.busInfo = fixedString(cap.bus_info, sizeof cap.bus_info);
    capability_.deviceCaps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
    return 0;
}

void V4l2Node::close() {
    if (streaming_ || !buffers_.empty())
        streamOff();
    fd_.reset();
}

std::vector<std::uint32_t> V4l2Node::formats() {
    std::vector<std::uint32_t> result;
    for (std::uint32_t i = 0; i < kMaxEnumerated; ++i) {
        v4l2_fmtdesc desc{};
        desc.index = i;
        desc.type = bufferType();
        if (ioctl(VIDIOC_ENUM_FMT, &desc) < 0)
            break;
        result.push_back(desc.pixelformat);
    }
    return result;
}

std::vector<double> V4l2Node::frameRates(std::uint32_t fourcc, int width, int height) {
    std::vector<double> rates;
    for (std::uint32_t i = 0; i < kMaxEnumerated; ++i) {
        v4l2_frmivalenum ival{};
        ival.index = i;
        ival.pixel_format = fourcc;
        ival.width = static_cast<std::uint32_t>(width);
        ival.height = static_cast<std::uint32_t>(height);
        if (ioctl(VIDIOC_ENUM_FRAMEINTERVALS, &ival) < 0)
            break;
        if (ival.type == V4L2_FRMIVAL_TYPE_DISCRETE) {
            rates.push_back(fps(ival.discrete));
            continue;
        }
        rates.push_back(fps(ival.stepwise.max)); // the longest interval is the lowest rate
        rates.push_back(fps(ival.stepwise.min));
        break;
    }
    std::erase_if(rates, [](double r) { return !(r > 0.0); });
    std::sort(rates.begin(), rates.end(), std::greater<>());
    rates.erase(std::unique(rates.begin(), rates.end()), rates.end());
    return rates;
}

std::vector<V4l2Mode> V4l2Node::modes(std::uint32_t fourcc) {
    std::vector<V4l2Mode> result;
    auto add = [&](std::uint32_t w, std::uint32_t h) {
        const int width = static_cast<int>(w);
        const int height = static_cast<int>(h);
        result.push_back({fourcc, width, height, frameRates(fourcc, width, height)});
    };
    for (std::uint32_t i = 0; i < kMaxEnumerated; ++i) {
        v4l2_frmsizeenum size{};
        size.index = i;
        size.pixel_format = fourcc;
        if (ioctl(VIDIOC_ENUM_FRAMESIZES, &size) < 0)
            break;
        if (size.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
            add(size.discrete.width, size.discrete.height);
            continue;
        }
        add(size.stepwise.min_width, size.stepwise.min_height);
        add(size.stepwise.max_width, size.stepwise.max_height);
        break;
    }
    if (result.empty()) { // drivers without ENUM_FRAMESIZES: the current size is the one we know of
        V4l2Format current;
        if (getFormat(current) == 0 && current.fourcc == fourcc)
            add(static_cast<std::uint32_t>(current.width), static_cast<std::uint32_t>(current.height));
    }
    return result;
}

std::vector<V4l2Mode> V4l2Node::allModes() {
    std::vector<V4l2Mode> result;
    for (std::uint32_t fourcc : formats()) {
        std::vector<V4l2Mode> m = modes(fourcc);
        result.insert(result.end(), m.begin(), m.end());
    }
    return result;
}

int V4l2Node::getFormat(V4l2Format& format) {
    v4l2_format f{};
    f.type = kCaptureType;
    if (const int r = ioctl(VIDIOC_G_FMT, &f); r < 0)
        return r;
    format = {f.fmt.pix.pixelformat, static_cast<int>(f.fmt.pix.width), static_cast<int>(f.fmt.pix.height),
              f.fmt.pix.bytesperline, f.fmt.pix.sizeimage};
    return 0;
}

int V4l2Node::setFormat(V4l2Format& format) {
    v4l2_format f{};
    f.type = kCaptureType;
    f.fmt.pix.width = static_cast<std::uint32_t>(format.width);
    f.fmt.pix.height = static_cast<std::uint32_t>(format.height);
    f.fmt.pix.pixelformat = format.fourcc;
    f.fmt.pix.field = V4L2_FIELD_NONE;
    if (const int r = ioctl(VIDIOC_S_FMT, &f); r < 0)
        return r;
    format = {f.fmt.pix.pixelformat, static_cast<int>(f.fmt.pix.width), static_cast<int>(f.fmt.pix.height),
              f.fmt.pix.bytesperline, f.fmt.pix.sizeimage};
    format_ = format;
    return 0;
}

int V4l2Node::setMetadataFormat(std::uint32_t dataFormat) {
    v4l2_format f{};
    f.type = V4L2_BUF_TYPE_META_CAPTURE;
    f.fmt.meta.dataformat = dataFormat;
    if (const int r = ioctl(VIDIOC_S_FMT, &f); r < 0)
        return r;
    format_ = {f.fmt.meta.dataformat, 0, 0, 0, f.fmt.meta.buffersize};
    return 0;
}

int V4l2Node::setFrameRate(double framesPerSecond) {
    if (!(framesPerSecond > 0.0))
        return -EINVAL;
    v4l2_streamparm parm{};
    parm.type = kCaptureType;
    // 1000 / (fps * 1000) keeps fractional rates such as 29.97 exact enough.
    parm.parm.capture.timeperframe.numerator = 1000;
    parm.parm.capture.timeperframe.denominator =
        static_cast<std::uint32_t>(std::lround(framesPerSecond * 1000.0));
    return ioctl(VIDIOC_S_PARM, &parm);
}

int V4l2Node::subscribeSourceChange() {
    v4l2_event_subscription sub{};
    sub.type = V4L2_EVENT_SOURCE_CHANGE;
    return ioctl(VIDIOC_SUBSCRIBE_EVENT, &sub);
}

int V4l2Node::subscribeControlChanges(const std::vector<std::uint32_t>& ids) {
    for (const std::uint32_t id : ids) {
        v4l2_event_subscription sub{};
        sub.type = V4L2_EVENT_CTRL;
        sub.id = id;
        if (const int r = ioctl(VIDIOC_SUBSCRIBE_EVENT, &sub); r < 0)
            return r;
    }
    return 0;
}

bool V4l2Node::takeControlChanges() {
    bool changed = false;
    for (std::uint32_t i = 0; i < kMaxEnumerated; ++i) {
        v4l2_event event{};
        if (ioctl(VIDIOC_DQEVENT, &event) < 0)
            break;
        changed |= event.type == V4L2_EVENT_CTRL;
    }
    return changed;
}

bool V4l2Node::takeSourceChange() {
    bool changed = false;
    for (std::uint32_t i = 0; i < kMaxEnumerated; ++i) {
        v4l2_event event{};
        if (ioctl(VIDIOC_DQEVENT, &event) < 0)
            break;
        changed |= event.type == V4L2_EVENT_SOURCE_CHANGE;
    }
    return changed;
}

int V4l2Node::allocateBuffers(unsigned count) {
    if (!buffers_.empty())
        return -EBUSY;
    v4l2_requestbuffers req{};
    req.count = count;
    req.type = bufferType();
    req.memory = V4L2_MEMORY_MMAP;
    if (const int r = ioctl(VIDIOC_REQBUFS, &req); r < 0)
        return r;
    if (req.count == 0)
        return -ENOMEM;
    buffers_.resize(req.count);
    queued_.assign(req.count, false);
    for (unsigned i = 0; i < req.count; ++i) {
        v4l2_buffer b = mmapBuffer(i);
        int r = ioctl(VIDIOC_QUERYBUF, &b);
        if (r == 0)
            r = mapBuffer(*sys_, fd_.get(), b.length, static_cast<off_t>(b.m.offset), buffers_[i]);
        if (r < 0) {
            streamOff();
            return r;
        }
    }
    return static_cast<int>(req.count);
}

int V4l2Node::streamOn() {
    for (unsigned i = 0; i < buffers_.size(); ++i) {
        if (queued_[i])
            continue;
        v4l2_buffer b = mmapBuffer(i);
        if (const int r = ioctl(VIDIOC_QBUF, &b); r < 0)
            return r;
        queued_[i] = true;
    }
    int type = static_cast<int>(bufferType());
    if (const int r = ioctl(VIDIOC_STREAMON, &type); r < 0)
        return r;
    streaming_ = true;
    return 0;
}

void V4l2Node::streamOff() {
    if (fd_.valid()) {
        int type = static_cast<int>(bufferType());
        (void)ioctl(VIDIOC_STREAMOFF, &type);
    }
    streaming_ = false;
    // vb2 refuses to free buffers that are still mapped: unmap first, then release them.
    const bool hadBuffers = !buffers_.empty();
    buffers_.clear();
    queued_.clear();
    if (hadBuffers && fd_.valid()) {
        v4l2_requestbuffers req{};
        req.type = bufferType();
        req.memory = V4L2_MEMORY_MMAP;
        (void)ioctl(VIDIOC_REQBUFS, &req);
    }
}

DequeueResult V4l2Node::dropped(unsigned index, std::string message) {
    if (const int r = requeue(index); r < 0)
        message += "; requeueing it failed: " + std::string(std::strerror(-r));
    DequeueResult result;
    result.kind = DequeueResult::Kind::Dropped;
    result.message = path_ + ": " + message;
    return result;
}

DequeueResult V4l2Node::dequeue() {
    DequeueResult result;
    v4l2_buffer b = mmapBuffer();
    if (const int r = ioctl(VIDIOC_DQBUF, &b); r < 0) {
        result.kind = r == -EAGAIN ? DequeueResult::Kind::NotReady : DequeueResult::Kind::Failed;
        result.error = r;
        result.message = describe("VIDIOC_DQBUF", r);
        return result;
    }
    if (b.index >= buffers_.size() || !queued_[b.index]) {
        // Not a buffer we queued: there is nothing safe to read or to requeue.
        result.kind = DequeueResult::Kind::Dropped;
        result.message = path_ + ": driver returned buffer " + std::to_string(b.index) +
                         ", which is not queued (" + std::to_string(buffers_.size()) + " buffers)";
        return result;
    }
    queued_[b.index] = false;
    const base::MappedRegion& mapping = buffers_[b.index];
    if (b.flags & V4L2_BUF_FLAG_ERROR)
        return dropped(b.index,
                       "frame " + std::to_string(b.sequence) + " marked corrupted (V4L2_BUF_FLAG_ERROR)");
    if (b.bytesused > mapping.length())
        return dropped(b.index, "bytesused " + std::to_string(b.bytesused) + " exceeds the buffer's " +
                                    std::to_string(mapping.length()) + " bytes");
    // A metadata buffer has no least size: an empty one says the camera's headers added nothing.
    if (kind_ == BufferKind::Video) {
        const std::size_t needed =
            minimumFrameBytes(format_.fourcc, format_.width, format_.height, format_.bytesPerLine);
        if (b.bytesused == 0 || b.bytesused < needed)
            return dropped(b.index, "short frame " + std::to_string(b.sequence) + ": " +
                                        std::to_string(b.bytesused) + " of " + std::to_string(needed) +
                                        " bytes");
    }
    result.kind = DequeueResult::Kind::Buffer;
    result.buffer.index = b.index;
    result.buffer.bytes = mapping.bytes().first(b.bytesused);
    result.buffer.sequence = b.sequence;
    result.buffer.timestampNs = timestampNs(b.timestamp);
    result.buffer.monotonicTimestamp =
        (b.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
    // V4L2_BUF_FLAG_TSTAMP_SRC_EOF is 0: a driver that says nothing stamps the end of the frame.
    result.buffer.startOfExposure = (b.flags & V4L2_BUF_FLAG_TSTAMP_SRC_MASK) == V4L2_BUF_FLAG_TSTAMP_SRC_SOE;
    return result;
}

int V4l2Node::requeue(unsigned index) {
    if (index >= buffers_.size() || queued_[index])
        return -EINVAL;
    v4l2_buffer b = mmapBuffer(index);
    if (const int r = ioctl(VIDIOC_QBUF, &b); r < 0)
        return r;
    queued_[index] = true;
    return 0;
}

unsigned V4l2Node::queuedBuffers() const {
    return static_cast<unsigned>(std::count(queued_.begin(), queued_.end(), true));
}

std::string V4l2Node::describe(const char* operation, int error) const {
    return path_ + ": " + operation + " failed: " + std::strerror(-error);
}

int waitForNodes(Syscalls& sys, std::span<V4l2Node* const> nodes, EventFd* stop, int timeoutMs,
                 std::vector<NodeReadiness>& ready) {
    std::vector<pollfd> fds;
    for (const V4l2Node* node : nodes)
        fds.push_back({node->fd(), POLLIN | POLLPRI, 0});
    if (stop && stop->valid())
        fds.push_back({stop->fd(), POLLIN, 0});
    const int r = xpoll(sys, fds.data(), fds.size(), timeoutMs);
    ready.assign(nodes.size(), {});
    if (r <= 0)
        return r;
    if (stop && stop->valid() && (fds.back().revents & POLLIN)) {
        stop->clear();
        return -ECANCELED;
    }
    int count = 0;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const short ev = fds[i].revents;
        ready[i] = {(ev & (POLLIN | POLLRDNORM)) != 0, (ev & POLLPRI) != 0,
                    (ev & (POLLERR | POLLHUP | POLLNVAL)) != 0};
        count += ready[i].buffer || ready[i].event || ready[i].error;
    }
    return count;
}

} // namespace dc::devices::v4l2
