#include "tests/unit/live/fake_v4l2.h"

#include "base/clock.h"
#include "devices/frame_pacer.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <linux/videodev2.h>

namespace dc::devices::v4l2::testing {

namespace {

// The fake never blocks longer than this, so a test cannot hang on it.
constexpr int kMaxPollSleepMs = 100;

std::uint32_t bytesPerPixel(std::uint32_t fourcc) {
    switch (fourcc) {
    case V4L2_PIX_FMT_RGB24:
        return 3;
    case V4L2_PIX_FMT_GREY:
    case V4L2_PIX_FMT_NV12:
    case V4L2_PIX_FMT_MJPEG:
        return 1;
    default:
        return 2;
    }
}

void copyName(std::uint8_t* out, std::size_t size, const std::string& text) {
    std::memset(out, 0, size);
    std::memcpy(out, text.data(), std::min(size - 1, text.size()));
}

} // namespace

struct FakeV4l2::Node {
    FakeNodeSpec spec;
    bool present = true;
    std::uint32_t fourcc = 0;
    int width = 0;
    int height = 0;
    std::vector<std::shared_ptr<std::vector<std::uint8_t>>> buffers;
    std::deque<unsigned> queued;
    std::deque<FakeFrame> frames;
    bool streaming = false;
    bool eventPending = false;
    std::uint32_t sequence = 0;

    bool metadata() const { return (spec.deviceCaps & V4L2_CAP_META_CAPTURE) != 0; }
    std::uint32_t bufferType() const {
        return metadata() ? V4L2_BUF_TYPE_META_CAPTURE : V4L2_BUF_TYPE_VIDEO_CAPTURE;
    }
    std::uint32_t bytesPerLine() const { return static_cast<std::uint32_t>(width) * bytesPerPixel(fourcc); }
    std::uint32_t sizeImage() const {
        if (metadata())
            return spec.metaBufferSize;
        const std::uint32_t rows = fourcc == V4L2_PIX_FMT_NV12 ? static_cast<std::uint32_t>(height * 3 / 2)
                                                               : static_cast<std::uint32_t>(height);
        return bytesPerLine() * rows;
    }
    bool offersMetaFormat(std::uint32_t f) const {
        return std::find(spec.metaFormats.begin(), spec.metaFormats.end(), f) != spec.metaFormats.end();
    }
    const FakeMode* mode(std::uint32_t f, int w, int h) const {
        for (const FakeMode& m : spec.modes)
            if (m.fourcc == f && (w == 0 || (m.width == w && m.height == h)))
                return &m;
        return nullptr;
    }
    std::vector<std::uint32_t> fourccs() const {
        if (metadata())
            return spec.metaFormats;
        std::vector<std::uint32_t> out;
        for (const FakeMode& m : spec.modes)
            if (std::find(out.begin(), out.end(), m.fourcc) == out.end())
                out.push_back(m.fourcc);
        return out;
    }
};

void FakeV4l2::addNode(const std::string& path, FakeNodeSpec spec) {
    std::lock_guard lock(mutex_);
    auto node = std::make_shared<Node>();
    if (spec.deviceCaps == 0)
        spec.deviceCaps = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING;
    node->spec = std::move(spec);
    if (node->metadata() && !node->spec.metaFormats.empty())
        node->fourcc = node->spec.metaFormats[0];
    if (!node->spec.modes.empty()) {
        node->fourcc = node->spec.modes[0].fourcc;
        node->width = node->spec.modes[0].width;
        node->height = node->spec.modes[0].height;
    }
    nodes_[path] = node;
}

void FakeV4l2::pushFrame(const std::string& path, FakeFrame frame) {
    std::lock_guard lock(mutex_);
    nodes_.at(path)->frames.push_back(std::move(frame));
    changed_.notify_all();
}

void FakeV4l2::interruptIoctl(unsigned long request, int count) {
    std::lock_guard lock(mutex_);
    interrupts_[request] += count;
}

void FakeV4l2::interruptPolls(int count) {
    std::lock_guard lock(mutex_);
    pollInterrupts_ += count;
}

void FakeV4l2::failIoctl(unsigned long request, int error, int count) {
    std::lock_guard lock(mutex_);
    failures_[request] = {error, count};
}

void FakeV4l2::unplug(const std::string& path) {
    std::lock_guard lock(mutex_);
    nodes_.at(path)->present = false;
    changed_.notify_all();
}

void FakeV4l2::replug(const std::string& path) {
    FakeNodeSpec spec;
    {
        std::lock_guard lock(mutex_);
        spec = nodes_.at(path)->spec;
    }
    addNode(path, spec); // a new driver instance: open fds keep the old, unplugged one
}

void FakeV4l2::changeFormat(const std::string& path, int width, int height) {
    std::lock_guard lock(mutex_);
    Node& node = *nodes_.at(path);
    node.width = width;
    node.height = height;
    node.eventPending = true;
    changed_.notify_all();
}

int FakeV4l2::openFds() const {
    std::lock_guard lock(mutex_);
    return static_cast<int>(nodeFds_.size() + eventFds_.size());
}

int FakeV4l2::mappings() const {
    std::lock_guard lock(mutex_);
    return static_cast<int>(maps_.size());
}

unsigned FakeV4l2::queued(const std::string& path) const {
    std::lock_guard lock(mutex_);
    return static_cast<unsigned>(nodes_.at(path)->queued.size());
}

bool FakeV4l2::streaming(const std::string& path) const {
    std::lock_guard lock(mutex_);
    return nodes_.at(path)->streaming;
}

std::uint32_t FakeV4l2::currentFormat(const std::string& path) const {
    std::lock_guard lock(mutex_);
    return nodes_.at(path)->fourcc;
}

int FakeV4l2::ioctlCalls(unsigned long request) const {
    std::lock_guard lock(mutex_);
    const auto it = calls_.find(request);
    return it == calls_.end() ? 0 : it->second;
}

int FakeV4l2::open(const char* path, int) {
    std::lock_guard lock(mutex_);
    const auto it = nodes_.find(path);
    if (it == nodes_.end() || !it->second->present)
        return -ENOENT;
    const int fd = nextFd_++;
    nodeFds_[fd] = it->second;
    return fd;
}

int FakeV4l2::close(int fd) {
    std::lock_guard lock(mutex_);
    if (nodeFds_.erase(fd) || eventFds_.erase(fd))
        return 0;
    return -EBADF;
}

int FakeV4l2::ioctl(int fd, unsigned long request, void* arg) {
    std::lock_guard lock(mutex_);
    ++calls_[request];
    if (int& pending = interrupts_[request]; pending > 0) {
        --pending;
        return -EINTR;
    }
    if (auto it = failures_.find(request); it != failures_.end() && it->second.second > 0) {
        --it->second.second;
        return it->second.first;
    }
    const auto it = nodeFds_.find(fd);
    if (it == nodeFds_.end())
        return -EBADF;
    if (!it->second->present)
        return -ENODEV;
    return nodeIoctl(*it->second, request, arg);
}

// What a driver checks first: the buffer type of a format, buffer or stream request is the node's.
bool FakeV4l2::typeMatches(const Node& node, unsigned long request, void* arg) {
    switch (request) {
    case VIDIOC_ENUM_FMT:
        return static_cast<v4l2_fmtdesc*>(arg)->type == node.bufferType();
    case VIDIOC_G_FMT:
    case VIDIOC_S_FMT:
        return static_cast<v4l2_format*>(arg)->type == node.bufferType();
    case VIDIOC_REQBUFS:
        return static_cast<v4l2_requestbuffers*>(arg)->type == node.bufferType();
    case VIDIOC_QUERYBUF:
    case VIDIOC_QBUF:
    case VIDIOC_DQBUF:
        return static_cast<v4l2_buffer*>(arg)->type == node.bufferType();
    case VIDIOC_STREAMON:
    case VIDIOC_STREAMOFF:
        return static_cast<std::uint32_t>(*static_cast<int*>(arg)) == node.bufferType();
    default:
        return true;
    }
}

int FakeV4l2::metaFormatIoctl(Node& node, unsigned long request, v4l2_format& f) {
    if (request == VIDIOC_S_FMT) {
        if (node.streaming || !node.buffers.empty())
            return -EBUSY;
        if (node.offersMetaFormat(f.fmt.meta.dataformat)) // like uvcvideo: anything else keeps the current
            node.fourcc = f.fmt.meta.dataformat;
    }
    f.fmt.meta.dataformat = node.fourcc;
    f.fmt.meta.buffersize = node.sizeImage();
    return 0;
}

int FakeV4l2::nodeIoctl(Node& node, unsigned long request, void* arg) {
    if (!typeMatches(node, request, arg))
        return -EINVAL;
    if ((request == VIDIOC_G_FMT || request == VIDIOC_S_FMT) && node.metadata())
        return metaFormatIoctl(node, request, *static_cast<v4l2_format*>(arg));
    switch (request) {
    case VIDIOC_QUERYCAP: {
        auto* cap = static_cast<v4l2_capability*>(arg);
        copyName(cap->driver, sizeof cap->driver, node.spec.driver);
        copyName(cap->card, sizeof cap->card, node.spec.card);
        copyName(cap->bus_info, sizeof cap->bus_info, node.spec.busInfo);
        cap->device_caps = node.spec.deviceCaps;
        cap->capabilities = node.spec.deviceCaps | V4L2_CAP_DEVICE_CAPS;
        return 0;
    }
    case VIDIOC_ENUM_FMT: {
        auto* desc = static_cast<v4l2_fmtdesc*>(arg);
        const auto fourccs = node.fourccs();
        if (desc->index >= fourccs.size())
            return -EINVAL;
        desc->pixelformat = fourccs[desc->index];
        return 0;
    }
    case VIDIOC_ENUM_FRAMESIZES: {
        auto* size = static_cast<v4l2_frmsizeenum*>(arg);
        std::uint32_t i = 0;
        for (const FakeMode& m : node.spec.modes)
            if (m.fourcc == size->pixel_format && i++ == size->index) {
                size->type = V4L2_FRMSIZE_TYPE_DISCRETE;
                size->discrete = {static_cast<std::uint32_t>(m.width), static_cast<std::uint32_t>(m.height)};
                return 0;
            }
        return -EINVAL;
    }
    case VIDIOC_ENUM_FRAMEINTERVALS: {
        auto* ival = static_cast<v4l2_frmivalenum*>(arg);
        const FakeMode* m =
            node.mode(ival->pixel_format, static_cast<int>(ival->width), static_cast<int>(ival->height));
        if (!m || ival->index >= m->fps.size())
            return -EINVAL;
        ival->type = V4L2_FRMIVAL_TYPE_DISCRETE;
        ival->discrete = {1000, static_cast<std::uint32_t>(m->fps[ival->index] * 1000)};
        return 0;
    }
    case VIDIOC_G_FMT:
    case VIDIOC_S_FMT: {
        auto* f = static_cast<v4l2_format*>(arg);
        if (request == VIDIOC_S_FMT) {
            if (node.streaming || !node.buffers.empty())
                return -EBUSY;
            const int w = static_cast<int>(f->fmt.pix.width), h = static_cast<int>(f->fmt.pix.height);
            const FakeMode* m = node.mode(f->fmt.pix.pixelformat, w, h);
            if (!m)
                m = node.mode(f->fmt.pix.pixelformat, 0, 0);
            if (m) { // like drivers: an unknown format leaves the current one
                node.fourcc = m->fourcc;
                node.width = m->width;
                node.height = m->height;
            }
        }
        f->fmt.pix.pixelformat = node.fourcc;
        f->fmt.pix.width = static_cast<std::uint32_t>(node.width);
        f->fmt.pix.height = static_cast<std::uint32_t>(node.height);
        f->fmt.pix.bytesperline = node.bytesPerLine();
        f->fmt.pix.sizeimage = node.sizeImage();
        return 0;
    }
    case VIDIOC_S_PARM:
        return 0;
    case VIDIOC_SUBSCRIBE_EVENT:
        return node.spec.events ? 0 : -EINVAL;
    case VIDIOC_DQEVENT: {
        if (!node.eventPending)
            return -ENOENT;
        node.eventPending = false;
        static_cast<v4l2_event*>(arg)->type = V4L2_EVENT_SOURCE_CHANGE;
        return 0;
    }
    case VIDIOC_REQBUFS: {
        auto* req = static_cast<v4l2_requestbuffers*>(arg);
        if (node.streaming)
            return -EBUSY;
        for (const auto& b : node.buffers) // vb2: buffers still mapped cannot be freed
            for (const auto& [address, storage] : maps_)
                if (storage == b)
                    return -EBUSY;
        node.buffers.clear();
        node.queued.clear();
        for (std::uint32_t i = 0; i < std::min<std::uint32_t>(req->count, 8); ++i)
            node.buffers.push_back(std::make_shared<std::vector<std::uint8_t>>(node.sizeImage()));
        req->count = static_cast<std::uint32_t>(node.buffers.size());
        return 0;
    }
    case VIDIOC_QUERYBUF: {
        auto* b = static_cast<v4l2_buffer*>(arg);
        if (b->index >= node.buffers.size())
            return -EINVAL;
        b->length = static_cast<std::uint32_t>(node.buffers[b->index]->size());
        b->m.offset = b->index * 0x100000u;
        return 0;
    }
    case VIDIOC_QBUF: {
        auto* b = static_cast<v4l2_buffer*>(arg);
        if (b->index >= node.buffers.size() ||
            std::find(node.queued.begin(), node.queued.end(), b->index) != node.queued.end())
            return -EINVAL;
        node.queued.push_back(b->index);
        return 0;
    }
    case VIDIOC_DQBUF: {
        if (!node.streaming)
            return -EINVAL;
        if (node.frames.empty() || node.queued.empty())
            return -EAGAIN;
        FakeFrame frame = std::move(node.frames.front());
        node.frames.pop_front();
        const unsigned index = node.queued.front();
        node.queued.pop_front();
        auto& storage = *node.buffers[index];
        std::copy_n(frame.bytes.begin(), std::min(frame.bytes.size(), storage.size()), storage.begin());
        auto* b = static_cast<v4l2_buffer*>(arg);
        b->index = frame.index.value_or(index);
        b->bytesused = frame.bytesused.value_or(static_cast<std::uint32_t>(frame.bytes.size()));
        b->flags = frame.flags | V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
        b->sequence = frame.sequence.value_or(node.sequence);
        node.sequence = b->sequence + 1;
        const std::int64_t ns = frame.timestampNs ? frame.timestampNs : base::monotonicNowNs();
        b->timestamp = {static_cast<time_t>(ns / 1'000'000'000),
                        static_cast<suseconds_t>(ns % 1'000'000'000 / 1000)};
        return 0;
    }
    case VIDIOC_STREAMON:
        node.streaming = true;
        return 0;
    case VIDIOC_STREAMOFF:
        node.streaming = false;
        node.queued.clear();
        return 0;
    default:
        return -ENOTTY;
    }
}

int FakeV4l2::mmap(void** address, std::size_t length, int, int fd, off_t offset) {
    std::lock_guard lock(mutex_);
    const auto it = nodeFds_.find(fd);
    if (it == nodeFds_.end())
        return -EBADF;
    const auto index = static_cast<std::size_t>(offset / 0x100000);
    if (index >= it->second->buffers.size() || it->second->buffers[index]->size() != length)
        return -EINVAL;
    auto storage = it->second->buffers[index];
    *address = storage->data();
    maps_[*address] = storage;
    return 0;
}

int FakeV4l2::munmap(void* address, std::size_t) {
    std::lock_guard lock(mutex_);
    return maps_.erase(address) ? 0 : -EINVAL;
}

short FakeV4l2::readiness(int fd) const {
    if (const auto e = eventFds_.find(fd); e != eventFds_.end())
        return e->second > 0 ? POLLIN : 0;
    const auto it = nodeFds_.find(fd);
    if (it == nodeFds_.end())
        return POLLNVAL;
    const Node& node = *it->second;
    if (!node.present)
        return POLLERR | POLLHUP;
    short events = node.eventPending ? POLLPRI : 0;
    if (!node.streaming)
        return static_cast<short>(events | POLLERR);
    if (!node.frames.empty() && !node.queued.empty())
        events |= POLLIN | POLLRDNORM;
    return events;
}

int FakeV4l2::poll(pollfd* fds, nfds_t count, int timeoutMs) {
    std::unique_lock lock(mutex_);
    if (pollInterrupts_ > 0) {
        --pollInterrupts_;
        return -EINTR;
    }
    const auto check = [&] {
        int ready = 0;
        for (nfds_t i = 0; i < count; ++i) {
            const short mask = static_cast<short>(fds[i].events | POLLERR | POLLHUP | POLLNVAL);
            fds[i].revents = fds[i].fd < 0 ? 0 : static_cast<short>(readiness(fds[i].fd) & mask);
            ready += fds[i].revents != 0;
        }
        return ready;
    };
    // Like the kernel: sleep until something changes (a frame, an unplug, an eventfd write) or time is up.
    const int waitMs = std::min(timeoutMs < 0 ? kMaxPollSleepMs : timeoutMs, kMaxPollSleepMs);
    changed_.wait_for(lock, std::chrono::milliseconds(waitMs), [&] { return check() > 0; });
    return check();
}

ssize_t FakeV4l2::read(int fd, void* buffer, std::size_t size) {
    std::lock_guard lock(mutex_);
    const auto it = eventFds_.find(fd);
    if (it == eventFds_.end() || size < sizeof(std::uint64_t))
        return -EINVAL;
    if (it->second == 0)
        return -EAGAIN;
    std::memcpy(buffer, &it->second, sizeof(std::uint64_t));
    it->second = 0;
    return sizeof(std::uint64_t);
}

ssize_t FakeV4l2::write(int fd, const void* buffer, std::size_t size) {
    std::lock_guard lock(mutex_);
    const auto it = eventFds_.find(fd);
    if (it == eventFds_.end() || size < sizeof(std::uint64_t))
        return -EINVAL;
    std::uint64_t add = 0;
    std::memcpy(&add, buffer, sizeof add);
    it->second += add;
    changed_.notify_all();
    return sizeof(std::uint64_t);
}

int FakeV4l2::eventfd(unsigned initialValue, int) {
    std::lock_guard lock(mutex_);
    const int fd = nextFd_++;
    eventFds_[fd] = initialValue;
    return fd;
}

FakeNodeSpec metadataNodeSpec(std::vector<std::uint32_t> formats) {
    FakeNodeSpec spec;
    spec.deviceCaps = V4L2_CAP_META_CAPTURE | V4L2_CAP_STREAMING;
    spec.metaFormats = std::move(formats);
    return spec;
}

std::vector<std::uint8_t> z16Bytes(const std::vector<std::uint16_t>& pixels) {
    std::vector<std::uint8_t> bytes(pixels.size() * 2);
    for (std::size_t i = 0; i < pixels.size(); ++i) {
        bytes[2 * i] = static_cast<std::uint8_t>(pixels[i] & 0xff);
        bytes[2 * i + 1] = static_cast<std::uint8_t>(pixels[i] >> 8);
    }
    return bytes;
}

} // namespace dc::devices::v4l2::testing
