#pragma once

#include "devices/v4l2/syscalls.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <sys/types.h>
#include <utility>

namespace dc::devices::v4l2 {

// Owns one file descriptor (libcamera's UniqueFD): move-only, closes on destruction through the syscall
// layer that opened it, and logs a failed close instead of ignoring it.
class UniqueFd {
public:
    UniqueFd() = default;
    UniqueFd(int fd, Syscalls& sys) : fd_(fd), sys_(&sys) {}
    UniqueFd(UniqueFd&& other) noexcept : fd_(other.release()), sys_(other.sys_) {}
    UniqueFd& operator=(UniqueFd&& other) noexcept;
    UniqueFd(const UniqueFd&) = delete;
    UniqueFd& operator=(const UniqueFd&) = delete;
    ~UniqueFd() { reset(); }

    int get() const { return fd_; }
    bool valid() const { return fd_ >= 0; }
    [[nodiscard]] int release() { return std::exchange(fd_, -1); }
    void reset();

private:
    int fd_ = -1;
    Syscalls* sys_ = nullptr;
};

// One mmap()ed region (a V4L2 buffer), unmapped on destruction. Default-constructed it maps nothing, so
// a node can hold its buffers before streaming starts.
class MappedBuffer {
public:
    MappedBuffer() = default;
    MappedBuffer(MappedBuffer&& other) noexcept;
    MappedBuffer& operator=(MappedBuffer&& other) noexcept;
    MappedBuffer(const MappedBuffer&) = delete;
    MappedBuffer& operator=(const MappedBuffer&) = delete;
    ~MappedBuffer() { unmap(); }

    // Maps `length` bytes of `fd` at `offset` read-only; 0 or -errno.
    int map(Syscalls& sys, int fd, std::size_t length, off_t offset);
    void unmap();
    bool mapped() const { return address_ != nullptr; }
    std::span<const std::uint8_t> bytes() const {
        return {static_cast<const std::uint8_t*>(address_), length_};
    }
    std::size_t length() const { return length_; }

private:
    void* address_ = nullptr;
    std::size_t length_ = 0;
    Syscalls* sys_ = nullptr;
};

// A counter fd that wakes a poll() from another thread (libcamera stops its event loops this way). Only
// signal() may be called concurrently with a poll on fd().
class EventFd {
public:
    EventFd() = default;
    // Creates the fd (non-blocking); 0 or -errno.
    int create(Syscalls& sys);
    bool valid() const { return fd_.valid(); }
    int fd() const { return fd_.get(); }
    int signal();
    // Consumes pending signals; true when there was at least one.
    bool clear();

private:
    UniqueFd fd_;
    Syscalls* sys_ = nullptr;
};

} // namespace dc::devices::v4l2
