#include "devices/v4l2/handles.h"

#include "devices/log.h"

#include <cerrno>
#include <cstring>
#include <string>
#include <sys/eventfd.h>
#include <sys/mman.h>

namespace dc::devices::v4l2 {

UniqueFd& UniqueFd::operator=(UniqueFd&& other) noexcept {
    if (this != &other) {
        reset();
        sys_ = other.sys_;
        fd_ = other.release();
    }
    return *this;
}

void UniqueFd::reset() {
    const int fd = std::exchange(fd_, -1);
    if (fd < 0)
        return;
    // Never retried: on Linux the fd is released even when close() reports EINTR.
    if (const int r = sys_->close(fd); r < 0 && r != -EINTR)
        logWarning("close(" + std::to_string(fd) + ") failed: " + std::strerror(-r));
}

MappedBuffer::MappedBuffer(MappedBuffer&& other) noexcept
    : address_(std::exchange(other.address_, nullptr)), length_(std::exchange(other.length_, 0)),
      sys_(other.sys_) {}

MappedBuffer& MappedBuffer::operator=(MappedBuffer&& other) noexcept {
    if (this != &other) {
        unmap();
        address_ = std::exchange(other.address_, nullptr);
        length_ = std::exchange(other.length_, 0);
        sys_ = other.sys_;
    }
    return *this;
}

int MappedBuffer::map(Syscalls& sys, int fd, std::size_t length, off_t offset) {
    unmap();
    void* address = nullptr;
    if (const int r = sys.mmap(&address, length, PROT_READ, fd, offset); r < 0)
        return r;
    address_ = address;
    length_ = length;
    sys_ = &sys;
    return 0;
}

void MappedBuffer::unmap() {
    void* address = std::exchange(address_, nullptr);
    if (!address)
        return;
    if (const int r = sys_->munmap(address, std::exchange(length_, 0)); r < 0)
        logWarning(std::string("munmap of a V4L2 buffer failed: ") + std::strerror(-r));
}

int EventFd::create(Syscalls& sys) {
    const int fd = sys.eventfd(0, EFD_NONBLOCK);
    if (fd < 0)
        return fd;
    fd_ = UniqueFd(fd, sys);
    sys_ = &sys;
    return 0;
}

int EventFd::signal() {
    if (!valid())
        return -EBADF;
    const std::uint64_t one = 1;
    const ssize_t r = xwrite(*sys_, fd_.get(), &one, sizeof one);
    return r < 0 ? static_cast<int>(r) : 0;
}

bool EventFd::clear() {
    if (!valid())
        return false;
    std::uint64_t count = 0;
    return xread(*sys_, fd_.get(), &count, sizeof count) == static_cast<ssize_t>(sizeof count) && count > 0;
}

} // namespace dc::devices::v4l2
