#include "base/mapped_file.h"

#include "base/log.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <utility>

namespace dc::base {

MappedRegion::MappedRegion(MappedRegion&& other) noexcept
    : address_(std::exchange(other.address_, nullptr)), length_(std::exchange(other.length_, 0)),
      calls_(other.calls_) {}

MappedRegion& MappedRegion::operator=(MappedRegion&& other) noexcept {
    if (this != &other) {
        reset();
        address_ = std::exchange(other.address_, nullptr);
        length_ = std::exchange(other.length_, 0);
        calls_ = other.calls_;
    }
    return *this;
}

void MappedRegion::reset() {
    void* address = std::exchange(address_, nullptr);
    if (!address)
        return;
    if (const int r = calls_->munmap(address, std::exchange(length_, 0)); r < 0)
        logWarning(std::string("munmap failed: ") + std::strerror(-r));
}

Expected<MappedRegion> mapFile(const std::string& path) {
    UniqueFd file(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
    if (!file.valid())
        return Error{"cannot open " + path + ": " + std::strerror(errno)};
    struct stat st {};
    if (::fstat(file.get(), &st) != 0)
        return Error{"cannot stat " + path + ": " + std::strerror(errno)};
    if (!S_ISREG(st.st_mode))
        return Error{path + " is not a regular file"};
    if (st.st_size == 0)
        return MappedRegion();
    const auto length = static_cast<std::size_t>(st.st_size);
    void* address = ::mmap(nullptr, length, PROT_READ, MAP_PRIVATE, file.get(), 0);
    if (address == MAP_FAILED)
        return Error{"cannot map " + path + ": " + std::strerror(errno)};
    return MappedRegion(address, length);
}

} // namespace dc::base
