#include "devices/uvc/v4l2/syscalls.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/eventfd.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

namespace dc::devices::v4l2 {

namespace {

int result(long r) {
    return r < 0 ? -errno : static_cast<int>(r);
}

class SystemSyscalls final : public Syscalls {
public:
    int open(const char* path, int flags) override { return result(::open(path, flags | O_CLOEXEC)); }
    int close(int fd) override { return result(::close(fd)); }
    int ioctl(int fd, unsigned long request, void* arg) override { return result(::ioctl(fd, request, arg)); }
    int mmap(void** address, std::size_t length, int prot, int fd, off_t offset) override {
        void* p = ::mmap(nullptr, length, prot, MAP_SHARED, fd, offset);
        if (p == MAP_FAILED)
            return -errno;
        *address = p;
        return 0;
    }
    int munmap(void* address, std::size_t length) override { return result(::munmap(address, length)); }
    int poll(pollfd* fds, nfds_t count, int timeoutMs) override {
        return result(::poll(fds, count, timeoutMs));
    }
    ssize_t read(int fd, void* buffer, std::size_t size) override {
        const ssize_t r = ::read(fd, buffer, size);
        return r < 0 ? -errno : r;
    }
    ssize_t write(int fd, const void* buffer, std::size_t size) override {
        const ssize_t r = ::write(fd, buffer, size);
        return r < 0 ? -errno : r;
    }
    int eventfd(unsigned initialValue, int flags) override {
        return result(::eventfd(initialValue, flags | EFD_CLOEXEC));
    }
};

template <class Call> auto retryInterrupted(Call call) {
    auto r = call();
    for (int attempt = 1; r == -EINTR && attempt < kMaxInterruptedRetries; ++attempt)
        r = call();
    return r;
}

} // namespace

Syscalls& systemSyscalls() {
    static SystemSyscalls instance;
    return instance;
}

int xopen(Syscalls& sys, const char* path, int flags) {
    return retryInterrupted([&] { return sys.open(path, flags); });
}

int xioctl(Syscalls& sys, int fd, unsigned long request, void* arg) {
    return retryInterrupted([&] { return sys.ioctl(fd, request, arg); });
}

int xpoll(Syscalls& sys, pollfd* fds, nfds_t count, int timeoutMs) {
    using Clock = std::chrono::steady_clock;
    const auto deadline = Clock::now() + std::chrono::milliseconds(timeoutMs);
    int r = sys.poll(fds, count, timeoutMs);
    for (int attempt = 1; r == -EINTR && attempt < kMaxInterruptedRetries; ++attempt) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
        r = sys.poll(fds, count, timeoutMs < 0 ? -1 : static_cast<int>(std::max<long>(left.count(), 0)));
    }
    return r;
}

ssize_t xread(Syscalls& sys, int fd, void* buffer, std::size_t size) {
    return retryInterrupted([&] { return sys.read(fd, buffer, size); });
}

ssize_t xwrite(Syscalls& sys, int fd, const void* buffer, std::size_t size) {
    return retryInterrupted([&] { return sys.write(fd, buffer, size); });
}

const char* ioctlName(unsigned long request) {
    switch (request) {
    case VIDIOC_QUERYCAP:
        return "VIDIOC_QUERYCAP";
    case VIDIOC_ENUM_FMT:
        return "VIDIOC_ENUM_FMT";
    case VIDIOC_ENUM_FRAMESIZES:
        return "VIDIOC_ENUM_FRAMESIZES";
    case VIDIOC_ENUM_FRAMEINTERVALS:
        return "VIDIOC_ENUM_FRAMEINTERVALS";
    case VIDIOC_G_FMT:
        return "VIDIOC_G_FMT";
    case VIDIOC_S_FMT:
        return "VIDIOC_S_FMT";
    case VIDIOC_S_PARM:
        return "VIDIOC_S_PARM";
    case VIDIOC_REQBUFS:
        return "VIDIOC_REQBUFS";
    case VIDIOC_QUERYBUF:
        return "VIDIOC_QUERYBUF";
    case VIDIOC_QBUF:
        return "VIDIOC_QBUF";
    case VIDIOC_DQBUF:
        return "VIDIOC_DQBUF";
    case VIDIOC_STREAMON:
        return "VIDIOC_STREAMON";
    case VIDIOC_STREAMOFF:
        return "VIDIOC_STREAMOFF";
    case VIDIOC_SUBSCRIBE_EVENT:
        return "VIDIOC_SUBSCRIBE_EVENT";
    case VIDIOC_DQEVENT:
        return "VIDIOC_DQEVENT";
    default:
        return "ioctl";
    }
}

} // namespace dc::devices::v4l2
