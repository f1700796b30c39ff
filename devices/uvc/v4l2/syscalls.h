#pragma once

#include "base/unique_fd.h"

#include <cstddef>
#include <poll.h>
#include <sys/types.h>

namespace dc::devices::v4l2 {

// The seam between our V4L2 code and the kernel. Each method makes exactly one system call and returns its
// result (>= 0) or -errno; it never retries and never prints. Unit tests substitute a fake that plays a
// device (EINTR storms, garbage buffers, disconnects) that a real kernel cannot be made to produce on demand.
// The descriptors and buffers it hands out are owned by base::UniqueFd and base::MappedRegion, which give
// them back through the same seam (close, munmap).
class Syscalls : public base::ReleaseCalls {
public:
    virtual ~Syscalls() = default;
    virtual int open(const char* path, int flags) = 0;
    virtual int ioctl(int fd, unsigned long request, void* arg) = 0;
    // Maps `length` bytes of `fd` at `offset`; *address is set on success.
    virtual int mmap(void** address, std::size_t length, int prot, int fd, off_t offset) = 0;
    virtual int poll(pollfd* fds, nfds_t count, int timeoutMs) = 0;
    virtual ssize_t read(int fd, void* buffer, std::size_t size) = 0;
    virtual ssize_t write(int fd, const void* buffer, std::size_t size) = 0;
    virtual int eventfd(unsigned initialValue, int flags) = 0;
};

// The real kernel.
Syscalls& systemSyscalls();

// The funnel every caller goes through: retries EINTR (a signal arriving mid-call is not a failure) and
// returns 0/the call's result or -errno. A storm that never ends is reported as -EINTR after
// kMaxInterruptedRetries attempts instead of spinning forever. Callers log with context; these print nothing.
inline constexpr int kMaxInterruptedRetries = 1000;

int xopen(Syscalls& sys, const char* path, int flags);
int xioctl(Syscalls& sys, int fd, unsigned long request, void* arg);
// Retries with the time that is left, so an interrupted wait does not wait longer in total.
int xpoll(Syscalls& sys, pollfd* fds, nfds_t count, int timeoutMs);
ssize_t xread(Syscalls& sys, int fd, void* buffer, std::size_t size);
ssize_t xwrite(Syscalls& sys, int fd, const void* buffer, std::size_t size);

// "VIDIOC_DQBUF"-style name of an ioctl request for messages ("ioctl" for others).
const char* ioctlName(unsigned long request);

} // namespace dc::devices::v4l2
