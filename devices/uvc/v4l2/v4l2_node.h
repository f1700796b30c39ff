#pragma once

#include "devices/uvc/v4l2/handles.h"
#include "devices/uvc/v4l2/syscalls.h"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

struct v4l2_buffer; // <linux/videodev2.h>

namespace dc::devices::v4l2 {

struct V4l2Capability {
    std::string driver;
    std::string card;
    std::string busInfo;
    std::uint32_t deviceCaps = 0; // V4L2_CAP_* of this node (not of the whole device)

    bool canCapture() const;         // single-planar video capture
    bool canCaptureMetadata() const; // a metadata node (uvcvideo's second node per streaming interface)
    bool canStream() const;          // mmap streaming I/O
};

struct V4l2Format {
    std::uint32_t fourcc = 0;
    int width = 0;
    int height = 0;
    std::uint32_t bytesPerLine = 0;
    std::uint32_t sizeImage = 0;
};

// One frame size of one pixel format with the rates the driver offers for it (stepwise ranges are
// reported by their ends).
struct V4l2Mode {
    std::uint32_t fourcc = 0;
    int width = 0;
    int height = 0;
    std::vector<double> framesPerSecond;
};

// A dequeued buffer that is safe to read: its index is ours, it is not marked bad and it holds a whole frame.
// `bytes` stays valid until the buffer is requeued or streaming stops.
struct V4l2Buffer {
    unsigned index = 0;
    std::span<const std::uint8_t> bytes; // the first bytesused bytes of the mapping
    std::uint32_t sequence = 0;
    std::int64_t timestampNs = 0;    // as the driver stamped it
    bool monotonicTimestamp = false; // CLOCK_MONOTONIC (V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC)
    bool startOfExposure = false;    // V4L2_BUF_FLAG_TSTAMP_SRC_SOE; otherwise the end of the frame (EOF)
};

struct DequeueResult {
    enum class Kind {
        Buffer,   // `buffer` is valid; hand it back with requeue()
        NotReady, // nothing to dequeue yet (EAGAIN)
        Dropped,  // the driver returned a buffer we cannot use; it was requeued where possible, see message
        Failed,   // VIDIOC_DQBUF failed: `error` (-errno), e.g. -ENODEV when the device was unplugged
    };
    Kind kind = Kind::NotReady;
    V4l2Buffer buffer;
    int error = 0;
    std::string message;
};

// What a node's buffers hold: video frames (V4L2_BUF_TYPE_VIDEO_CAPTURE) or a metadata node's blocks
// (V4L2_BUF_TYPE_META_CAPTURE), which have no size of their own and may be empty.
enum class BufferKind { Video, Metadata };

// One V4L2 video capture node (libcamera's V4L2VideoDevice, cut down to single-planar mmap capture), or a
// metadata capture node streamed the same way. Every call goes through the syscall funnel and returns 0
// or -errno; describe() turns an error into a message that names the node and the ioctl. The node never
// logs: the device that owns it decides what to say. Not thread-safe; one thread drives a node.
class V4l2Node {
public:
    static constexpr unsigned kBufferCount = 4;

    explicit V4l2Node(Syscalls& sys = systemSyscalls(), BufferKind kind = BufferKind::Video)
        : sys_(&sys), kind_(kind) {}
    ~V4l2Node() { close(); }
    V4l2Node(V4l2Node&&) noexcept = default;
    V4l2Node& operator=(V4l2Node&&) noexcept = default;
    V4l2Node(const V4l2Node&) = delete;
    V4l2Node& operator=(const V4l2Node&) = delete;

    // Opens (non-blocking) and queries the capabilities.
    int open(const std::string& path);
    // Stops streaming, frees the buffers and closes; safe to call at any time, also after an unplug.
    void close();
    bool isOpen() const { return fd_.valid(); }
    int fd() const { return fd_.get(); }
    const std::string& path() const { return path_; }
    const V4l2Capability& capability() const { return capability_; }

    std::vector<std::uint32_t> formats();
    // Sizes and rates of one format (ENUM_FRAMESIZES x ENUM_FRAMEINTERVALS).
    std::vector<V4l2Mode> modes(std::uint32_t fourcc);
    std::vector<V4l2Mode> allModes();
    int getFormat(V4l2Format& format);
    // S_FMT: the driver may adjust the request; `format` returns what it chose.
    int setFormat(V4l2Format& format);
    // S_FMT of a metadata node: its data format (V4L2_META_FMT_*); the driver's buffer size becomes
    // format().sizeImage.
    int setMetadataFormat(std::uint32_t dataFormat);
    int setFrameRate(double framesPerSecond);
    const V4l2Format& format() const { return format_; }
    // Subscribes to V4L2_EVENT_SOURCE_CHANGE (optional: many drivers have no events).
    int subscribeSourceChange();
    // V4L2_EVENT_CTRL for each control in `ids`: a change of its value or flags by anyone becomes an event.
    int subscribeControlChanges(const std::vector<std::uint32_t>& ids);
    // Takes every pending control event; whether there was one.
    bool takeControlChanges();
    // Dequeues pending events; true when one of them says the format changed under us.
    bool takeSourceChange();

    // REQBUFS(mmap) + QUERYBUF + mmap; returns the number of buffers or -errno.
    int allocateBuffers(unsigned count = kBufferCount);
    // Queues every buffer and starts streaming.
    int streamOn();
    // Stops streaming and releases the buffers (errors after an unplug are expected and ignored).
    void streamOff();
    bool streaming() const { return streaming_; }
    DequeueResult dequeue();
    int requeue(unsigned index);
    unsigned queuedBuffers() const;

    std::string describe(const char* operation, int error) const;

private:
    int ioctl(unsigned long request, void* arg) { return xioctl(*sys_, fd_.get(), request, arg); }
    std::uint32_t bufferType() const;
    v4l2_buffer mmapBuffer(unsigned index = 0) const;
    std::vector<double> frameRates(std::uint32_t fourcc, int width, int height);
    DequeueResult dropped(unsigned index, std::string message);

    Syscalls* sys_;
    BufferKind kind_ = BufferKind::Video;
    base::UniqueFd fd_;
    std::string path_;
    V4l2Capability capability_;
    V4l2Format format_;
    std::vector<base::MappedRegion> buffers_;
    std::vector<bool> queued_;
    bool streaming_ = false;
};

// What poll() found on one node.
struct NodeReadiness {
    bool buffer = false; // a buffer can be dequeued
    bool event = false;  // a V4L2 event is pending
    bool error = false;  // POLLERR/POLLHUP: not streaming, queue error, or the device is gone
};

// Waits until one of `nodes` has a buffer, an event or an error, `stop` is signalled (from any thread), or
// `timeoutMs` passes. Returns the number of nodes with something to handle, 0 on timeout, -ECANCELED when
// stopped (the signal is consumed), or -errno. `ready` gets one entry per node.
int waitForNodes(Syscalls& sys, std::span<V4l2Node* const> nodes, EventFd* stop, int timeoutMs,
                 std::vector<NodeReadiness>& ready);

} // namespace dc::devices::v4l2
