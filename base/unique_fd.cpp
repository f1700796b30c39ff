#include "base/unique_fd.h"

#include "base/log.h"

#include <cerrno>
#include <cstring>
#include <string>
#include <sys/mman.h>
#include <unistd.h>

namespace dc::base {

namespace {

class SystemReleaseCalls final : public ReleaseCalls {
public:
    int close(int fd) override { return ::close(fd) == 0 ? 0 : -errno; }
    int munmap(void* address, std::size_t length) override {
        return ::munmap(address, length) == 0 ? 0 : -errno;
    }
};

} // namespace

ReleaseCalls& systemReleaseCalls() {
    static SystemReleaseCalls calls;
    return calls;
}

UniqueFd& UniqueFd::operator=(UniqueFd&& other) noexcept {
    if (this != &other) {
        reset();
        calls_ = other.calls_;
        fd_ = other.release();
    }
    return *this;
}

void UniqueFd::reset(int fd) {
    const int old = std::exchange(fd_, fd);
    if (old < 0)
        return;
    // Never retried: on Linux the descriptor is released even when close() reports EINTR.
    if (const int r = calls_->close(old); r < 0 && r != -EINTR)
        logWarning("close(" + std::to_string(old) + ") failed: " + std::strerror(-r));
}

} // namespace dc::base
