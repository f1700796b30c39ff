#include "base/files.h"

#include "base/unique_fd.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <sys/uio.h>
#include <unistd.h>

namespace dc::base {

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

namespace {

int fsyncRetried(int fd) {
    while (::fsync(fd) != 0) {
        if (errno != EINTR)
            return -errno;
    }
    return 0;
}

// The directory entry made by rename() is only durable once the directory itself is flushed.
int syncDirectoryOf(const std::string& path) {
    std::string dir = std::filesystem::path(path).parent_path().string();
    if (dir.empty())
        dir = ".";
    UniqueFd fd(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (!fd.valid())
        return -errno;
    return fsyncRetried(fd.get());
}

} // namespace

Status writeFileAtomically(const std::string& path, std::span<const std::uint8_t> bytes) {
    // The pid keeps two processes writing the same path from sharing a temporary file.
    const std::string tmp = path + ".tmp." + std::to_string(::getpid());
    {
        UniqueFd fd(::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
        if (!fd.valid())
            return Error{"cannot write " + path + ": " + std::strerror(errno)};
        int r = writeAll(fd.get(), bytes);
        if (r == 0)
            r = fsyncRetried(fd.get());
        if (r < 0) {
            ::unlink(tmp.c_str());
            return Error{"cannot write " + path + ": " + std::strerror(-r)};
        }
    }
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        const std::string reason = std::strerror(errno);
        ::unlink(tmp.c_str());
        return Error{"cannot rename " + tmp + " to " + path + ": " + reason};
    }
    if (const int r = syncDirectoryOf(path); r < 0)
        return Error{"wrote " + path + " but could not flush its directory: " + std::strerror(-r)};
    return {};
}

Status writeTextFile(const std::string& path, const std::string& text) {
    return writeFileAtomically(path, {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
}

} // namespace dc::base
