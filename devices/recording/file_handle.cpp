#include "devices/recording/file_handle.h"

#include "devices/log.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <unistd.h>

namespace dc::devices::recording {

void UniqueFile::reset(int fd) {
    const int old = std::exchange(fd_, fd);
    // Never retried: on Linux the descriptor is released even when close() reports EINTR.
    if (old >= 0 && ::close(old) != 0 && errno != EINTR)
        logWarning("close(" + std::to_string(old) + ") failed: " + std::strerror(errno));
}

int writeAll(int fd, std::span<const std::uint8_t> first, std::span<const std::uint8_t> second) {
    iovec parts[2] = {{const_cast<std::uint8_t*>(first.data()), first.size()},
                      {const_cast<std::uint8_t*>(second.data()), second.size()}};
    int index = 0;
    while (index < 2) {
        if (parts[index].iov_len == 0) {
            ++index;
            continue;
        }
        const ssize_t n = ::writev(fd, parts + index, 2 - index);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            return -errno;
        }
        auto left = static_cast<std::size_t>(n);
        while (index < 2 && left >= parts[index].iov_len) {
            left -= parts[index].iov_len;
            ++index;
        }
        if (index < 2) {
            parts[index].iov_base = static_cast<std::uint8_t*>(parts[index].iov_base) + left;
            parts[index].iov_len -= left;
        }
    }
    return 0;
}

MappedFile& MappedFile::operator=(MappedFile&& other) noexcept {
    if (this != &other) {
        unmap();
        address_ = std::exchange(other.address_, nullptr);
        size_ = std::exchange(other.size_, 0);
    }
    return *this;
}

void MappedFile::unmap() {
    if (address_ && ::munmap(address_, size_) != 0)
        logWarning(std::string("munmap failed: ") + std::strerror(errno));
    address_ = nullptr;
    size_ = 0;
}

Expected<MappedFile> MappedFile::open(const std::string& path) {
    UniqueFile file(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
    if (!file.valid())
        return Error{"cannot open " + path + ": " + std::strerror(errno)};
    struct stat st {};
    if (::fstat(file.get(), &st) != 0)
        return Error{"cannot stat " + path + ": " + std::strerror(errno)};
    if (!S_ISREG(st.st_mode))
        return Error{path + " is not a regular file"};
    MappedFile mapped;
    if (st.st_size == 0)
        return mapped;
    void* address =
        ::mmap(nullptr, static_cast<std::size_t>(st.st_size), PROT_READ, MAP_PRIVATE, file.get(), 0);
    if (address == MAP_FAILED)
        return Error{"cannot map " + path + ": " + std::strerror(errno)};
    mapped.address_ = address;
    mapped.size_ = static_cast<std::size_t>(st.st_size);
    return mapped;
}

} // namespace dc::devices::recording
