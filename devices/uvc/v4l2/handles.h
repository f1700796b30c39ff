#pragma once

#include "base/mapped_file.h"
#include "base/unique_fd.h"
#include "devices/uvc/v4l2/syscalls.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <sys/types.h>
#include <utility>

namespace dc::devices::v4l2 {

// A V4L2 buffer mmap()ed read-only through the seam; 0 or -errno.
int mapBuffer(Syscalls& sys, int fd, std::size_t length, off_t offset, base::MappedRegion& region);

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
    base::UniqueFd fd_;
    Syscalls* sys_ = nullptr;
};

} // namespace dc::devices::v4l2
