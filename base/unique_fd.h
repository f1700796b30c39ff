#pragma once

#include <cstddef>
#include <utility>

namespace dc::base {

// How a descriptor or a mapping goes back to the kernel. The real calls by default; the V4L2 layer passes
// its syscall seam, so its tests can play a driver whose close() or munmap() fails.
class ReleaseCalls {
public:
    virtual int close(int fd) = 0;                             // 0 or -errno
    virtual int munmap(void* address, std::size_t length) = 0; // 0 or -errno

protected:
    ~ReleaseCalls() = default;
};

// The kernel's own close() and munmap().
ReleaseCalls& systemReleaseCalls();

// Owns one file descriptor (libcamera's UniqueFD): move-only, closed on destruction, and a failed close is
// logged rather than ignored.
class UniqueFd {
public:
    UniqueFd() = default;
    explicit UniqueFd(int fd, ReleaseCalls& calls = systemReleaseCalls()) : fd_(fd), calls_(&calls) {}
    UniqueFd(UniqueFd&& other) noexcept : fd_(other.release()), calls_(other.calls_) {}
    UniqueFd& operator=(UniqueFd&& other) noexcept;
    UniqueFd(const UniqueFd&) = delete;
    UniqueFd& operator=(const UniqueFd&) = delete;
    ~UniqueFd() { reset(); }

    int get() const { return fd_; }
    bool valid() const { return fd_ >= 0; }
    [[nodiscard]] int release() { return std::exchange(fd_, -1); }
    // Closes the descriptor held (if any) and takes `fd`, released through the same calls.
    void reset(int fd = -1);

private:
    int fd_ = -1;
    ReleaseCalls* calls_ = &systemReleaseCalls();
};

} // namespace dc::base
