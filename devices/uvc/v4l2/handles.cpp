#include "devices/uvc/v4l2/handles.h"

#include <cerrno>
#include <sys/eventfd.h>
#include <sys/mman.h>

namespace dc::devices::v4l2 {

int mapBuffer(Syscalls& sys, int fd, std::size_t length, off_t offset, base::MappedRegion& region) {
    void* address = nullptr;
    if (const int r = sys.mmap(&address, length, PROT_READ, fd, offset); r < 0)
        return r;
    region = base::MappedRegion(address, length, sys);
    return 0;
}

int EventFd::create(Syscalls& sys) {
    const int fd = sys.eventfd(0, EFD_NONBLOCK);
    if (fd < 0)
        return fd;
    fd_ = base::UniqueFd(fd, sys);
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
