#pragma once

#include "devices/expected.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <utility>

namespace dc::devices::recording {

// A file descriptor opened by this module: move-only, closed on destruction (a failed close is logged).
class UniqueFile {
public:
    UniqueFile() = default;
    explicit UniqueFile(int fd) : fd_(fd) {}
    UniqueFile(UniqueFile&& other) noexcept : fd_(other.release()) {}
    UniqueFile& operator=(UniqueFile&& other) noexcept {
        reset(other.release());
        return *this;
    }
    UniqueFile(const UniqueFile&) = delete;
    UniqueFile& operator=(const UniqueFile&) = delete;
    ~UniqueFile() { reset(); }

    int get() const { return fd_; }
    bool valid() const { return fd_ >= 0; }
    [[nodiscard]] int release() { return std::exchange(fd_, -1); }
    void reset(int fd = -1);

private:
    int fd_ = -1;
};

// Writes every byte of both spans (one writev, retried on EINTR and short writes); 0 or -errno.
int writeAll(int fd, std::span<const std::uint8_t> first, std::span<const std::uint8_t> second = {});

// A whole file mapped read-only, unmapped on destruction. An empty file maps to an empty span.
class MappedFile {
public:
    MappedFile() = default;
    MappedFile(MappedFile&& other) noexcept
        : address_(std::exchange(other.address_, nullptr)), size_(std::exchange(other.size_, 0)) {}
    MappedFile& operator=(MappedFile&& other) noexcept;
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;
    ~MappedFile() { unmap(); }

    static Expected<MappedFile> open(const std::string& path);
    std::span<const std::uint8_t> bytes() const {
        return {static_cast<const std::uint8_t*>(address_), size_};
    }

private:
    void unmap();

    void* address_ = nullptr;
    std::size_t size_ = 0;
};

} // namespace dc::devices::recording
