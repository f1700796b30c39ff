#pragma once

#include <memory>
#include <optional>
#include <string_view>

namespace dc::tool {

// The graphics clock of the GPU a benchmark draws on, read through NVIDIA's management library (NVML)
// where the driver installs it. Between frames paced at a camera's rate a GPU may stay at its idle clock,
// where the same commands take several times as long as at its full clock: a GPU time is read with the
// clock it ran at. Absent (open() gives none) on other GPUs, on software GL and without the library.
class GpuClock {
public:
    // The GPU whose NVML name begins GL_RENDERER (NVIDIA's renderer string adds "/PCIe/SSE2").
    static std::optional<GpuClock> open(std::string_view glRenderer);

    // The graphics clock now, in MHz (none if the read fails).
    std::optional<unsigned> graphicsMhz() const;
    unsigned maxGraphicsMhz() const { return maxMhz_; }

private:
    struct Library;
    explicit GpuClock(std::shared_ptr<const Library> library, void* device, unsigned maxMhz)
        : library_(std::move(library)), device_(device), maxMhz_(maxMhz) {}

    std::shared_ptr<const Library> library_;
    void* device_ = nullptr; // NVML's nvmlDevice_t, an opaque handle
    unsigned maxMhz_ = 0;
};

} // namespace dc::tool
