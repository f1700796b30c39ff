#include "base/files.h"

#include "base/unique_fd.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
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

// The injected result of `step`, else the real call's: 0 or -errno.
template <class Call> int runStep(const AtomicWriteFault& fault, AtomicWriteStep step, Call call) {
    if (fault) {
        if (const int injected = fault(step); injected < 0)
            return injected;
    }
    return call();
}

// Writes and flushes the temporary file; 0 or -errno, leaving no file behind on failure.
int writeTemporary(const std::string& tmp, std::span<const std::uint8_t> bytes,
                   const AtomicWriteFault& fault) {
    UniqueFd fd;
    int r = runStep(fault, AtomicWriteStep::Open, [&] {
        fd.reset(::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
        return fd.valid() ? 0 : -errno;
    });
    if (r < 0)
        return r;
    r = runStep(fault, AtomicWriteStep::Write, [&] { return writeAll(fd.get(), bytes); });
    if (r == 0)
        r = runStep(fault, AtomicWriteStep::Sync, [&] { return fsyncRetried(fd.get()); });
    if (r < 0)
        ::unlink(tmp.c_str());
    return r;
}

} // namespace

Status writeFileAtomically(const std::string& path, std::span<const std::uint8_t> bytes,
                           const AtomicWriteFault& fault) {
    // The pid keeps two processes writing the same path from sharing a temporary file.
    const std::string tmp = path + ".tmp." + std::to_string(::getpid());
    if (const int r = writeTemporary(tmp, bytes, fault); r < 0)
        return Error{"cannot write " + path + ": " + std::strerror(-r)};
    const int renamed = runStep(fault, AtomicWriteStep::Rename,
                                [&] { return ::rename(tmp.c_str(), path.c_str()) == 0 ? 0 : -errno; });
    if (renamed < 0) {
        ::unlink(tmp.c_str());
        return Error{"cannot rename " + tmp + " to " + path + ": " + std::strerror(-renamed)};
    }
    if (const int r = runStep(fault, AtomicWriteStep::SyncDirectory, [&] { return syncDirectoryOf(path); });
        r < 0)
        return Error{"wrote " + path + " but could not flush its directory: " + std::strerror(-r)};
    return {};
}

Status writeTextFile(const std::string& path, const std::string& text) {
    return writeFileAtomically(path, {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
}

Status renameInto(const std::string& from, const std::string& to, bool overwrite,
                  const std::string& existsMessage) {
    const unsigned flags = overwrite ? 0u : RENAME_NOREPLACE;
    if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), flags) == 0)
        return {};
    // Some filesystems refuse the flag (EINVAL); link() gives the same no-replace guarantee there.
    if (errno == EINVAL && flags != 0 && ::link(from.c_str(), to.c_str()) == 0) {
        ::unlink(from.c_str());
        return {};
    }
    if (errno == EEXIST)
        return Error{existsMessage};
    return Error{"cannot rename " + from + " to " + to + ": " + std::strerror(errno)};
}

Expected<std::vector<std::uint8_t>> readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in)
        return Error{"cannot open " + path + ": " + std::strerror(errno)};
    const std::streamoff size = in.tellg(); // -1 for what cannot seek (a pipe): not a capture's file
    if (size < 0)
        return Error{"cannot read " + path + ": not a regular file"};
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(size));
    in.seekg(0);
    if (!in.read(reinterpret_cast<char*>(bytes.data()), size))
        return Error{"cannot read " + path + ": " + std::strerror(errno)};
    return bytes;
}

Expected<std::string> createFreshDirectory(const std::string& parent, const std::string& stem) {
    std::error_code ec;
    std::filesystem::create_directories(parent, ec);
    if (ec)
        return Error{parent + ": cannot create directory: " + ec.message()};
    constexpr int kMaxTries = 10000;
    for (int n = 1; n <= kMaxTries; ++n) {
        const std::string path = parent + "/" + stem + (n == 1 ? "" : "-" + std::to_string(n));
        if (std::filesystem::create_directory(path, ec))
            return path;
        if (ec)
            return Error{path + ": cannot create directory: " + ec.message()};
    }
    return Error{parent + "/" + stem + ": every numbered name up to " + std::to_string(kMaxTries) +
                 " is taken"};
}

} // namespace dc::base
