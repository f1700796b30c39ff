#pragma once

#include "devices/uvc/v4l2/syscalls.h"

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

struct v4l2_format; // <linux/videodev2.h>

namespace dc::devices::v4l2::testing {

struct FakeMode {
    std::uint32_t fourcc = 0;
    int width = 0;
    int height = 0;
    std::vector<double> fps;
};

// One frame the fake driver will hand out on the next DQBUF, with the faults a real driver may produce.
struct FakeFrame {
    std::vector<std::uint8_t> bytes{};        // copied into the buffer (truncated to its length); empty: the
                                              // buffer keeps what it holds (benchmarks: no copy to pay for)
    std::optional<std::uint32_t> bytesused{}; // default: bytes.size()
    std::uint32_t flags = 0;                  // e.g. V4L2_BUF_FLAG_ERROR
    std::optional<std::uint32_t> index{};     // a garbage index instead of the buffer actually used
    std::int64_t timestampNs = 0;             // 0: CLOCK_MONOTONIC now
    std::optional<std::uint32_t> sequence{};  // default: the node's count of buffers so far
};

struct FakeNodeSpec {
    std::string driver = "fakecam";
    std::string card = "Fake depth camera";
    std::string busInfo = "platform:fake";
    std::uint32_t deviceCaps = 0; // 0: video capture + streaming
    std::vector<FakeMode> modes;
    bool events = true; // supports V4L2_EVENT_SOURCE_CHANGE
    // A metadata node (deviceCaps with V4L2_CAP_META_CAPTURE): its V4L2_META_FMT_* data formats, the first
    // the current one, and its buffers' size. Its buffer ioctls take V4L2_BUF_TYPE_META_CAPTURE only.
    std::vector<std::uint32_t> metaFormats{};
    std::uint32_t metaBufferSize = 4096;
};

// A uvcvideo metadata node offering `formats`, on the same bus as the fake's video nodes.
FakeNodeSpec metadataNodeSpec(std::vector<std::uint32_t> formats);

// A V4L2 driver in memory behind the syscall seam: enough of vb2's mmap streaming to run V4l2Node and
// UvcDevice, plus what a kernel cannot be made to do on demand (EINTR storms, corrupt buffers, unplugs,
// format changes). It also keeps score of fds and mappings, so tests can prove nothing leaks. Thread-safe.
class FakeV4l2 final : public Syscalls {
public:
    void addNode(const std::string& path, FakeNodeSpec spec);
    void pushFrame(const std::string& path, FakeFrame frame);
    // The next `count` calls of `request` (or of poll) fail with EINTR.
    void interruptIoctl(unsigned long request, int count);
    void interruptPolls(int count);
    void failIoctl(unsigned long request, int error, int count = 1);
    // The node goes away (open: ENOENT, ioctls on open fds: ENODEV, poll: POLLERR|POLLHUP) / comes back
    // fresh.
    void unplug(const std::string& path);
    void replug(const std::string& path);
    // The driver switches to another size and raises V4L2_EVENT_SOURCE_CHANGE.
    void changeFormat(const std::string& path, int width, int height);

    int openFds() const;  // node and event fds not closed yet
    int mappings() const; // buffers mapped and not unmapped
    unsigned queued(const std::string& path) const;
    bool streaming(const std::string& path) const;
    std::uint32_t currentFormat(const std::string& path) const; // the fourcc or metadata format set
    int ioctlCalls(unsigned long request) const;

    int open(const char* path, int flags) override;
    int close(int fd) override;
    int ioctl(int fd, unsigned long request, void* arg) override;
    int mmap(void** address, std::size_t length, int prot, int fd, off_t offset) override;
    int munmap(void* address, std::size_t length) override;
    int poll(pollfd* fds, nfds_t count, int timeoutMs) override;
    ssize_t read(int fd, void* buffer, std::size_t size) override;
    ssize_t write(int fd, const void* buffer, std::size_t size) override;
    int eventfd(unsigned initialValue, int flags) override;

    struct Node;

private:
    int nodeIoctl(Node& node, unsigned long request, void* arg);
    static bool typeMatches(const Node& node, unsigned long request, void* arg);
    static int metaFormatIoctl(Node& node, unsigned long request, v4l2_format& f);
    short readiness(int fd) const;

    mutable std::mutex mutex_;
    std::condition_variable changed_;
    std::map<std::string, std::shared_ptr<Node>> nodes_;
    std::map<int, std::shared_ptr<Node>> nodeFds_;
    std::map<int, std::uint64_t> eventFds_;
    std::map<void*, std::shared_ptr<std::vector<std::uint8_t>>> maps_;
    std::map<unsigned long, int> interrupts_;
    std::map<unsigned long, std::pair<int, int>> failures_; // request -> (error, count)
    std::map<unsigned long, int> calls_;
    int pollInterrupts_ = 0;
    int nextFd_ = 100;
};

// Little-endian 16-bit pixels as a Z16/Y16 buffer.
std::vector<std::uint8_t> z16Bytes(const std::vector<std::uint16_t>& pixels);

} // namespace dc::devices::v4l2::testing
