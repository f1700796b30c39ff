#pragma once

#include "base/expected.h"
#include "base/unique_fd.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace dc::base {

// One mmap()ed region, unmapped on destruction (a failed munmap is logged). Default-constructed it maps
// nothing, so an owner can hold it before the mapping exists.
class MappedRegion {
public:
    MappedRegion() = default;
    MappedRegion(void* address, std::size_t length, ReleaseCalls& calls = systemReleaseCalls())
        : address_(address), length_(length), calls_(&calls) {}
    MappedRegion(MappedRegion&& other) noexcept;
    MappedRegion& operator=(MappedRegion&& other) noexcept;
    MappedRegion(const MappedRegion&) = delete;
    MappedRegion& operator=(const MappedRegion&) = delete;
    ~MappedRegion() { reset(); }

    void reset();
    bool mapped() const { return address_ != nullptr; }
    std::size_t length() const { return length_; }
    std::span<const std::uint8_t> bytes() const {
        return {static_cast<const std::uint8_t*>(address_), length_};
    }

private:
    void* address_ = nullptr;
    std::size_t length_ = 0;
    ReleaseCalls* calls_ = &systemReleaseCalls();
};

// A whole regular file mapped read-only. An empty file maps to an empty region.
Expected<MappedRegion> mapFile(const std::string& path);

} // namespace dc::base
