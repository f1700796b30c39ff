#include "tool/gpu_clock.h"

#include <dlfcn.h>

#include <array>
#include <cstring>

namespace dc::tool {

namespace {

// NVML's C interface, declared here so that the build needs neither the library nor its header: nvmlReturn_t
// is an int (0 success), nvmlDevice_t an opaque pointer, nvmlClockType_t's graphics clock 0.
using Init = int (*)();
using Shutdown = int (*)();
using DeviceCount = int (*)(unsigned*);
using DeviceByIndex = int (*)(unsigned, void**);
using DeviceName = int (*)(void*, char*, unsigned);
using ClockInfo = int (*)(void*, int, unsigned*);
constexpr int kSuccess = 0;
constexpr int kGraphicsClock = 0;

template <class F> F symbol(void* handle, const char* name) {
    return reinterpret_cast<F>(dlsym(handle, name));
}

} // namespace

struct GpuClock::Library {
    void* handle = nullptr;
    ClockInfo clock = nullptr;

    ~Library() {
        if (const auto shutdown = symbol<Shutdown>(handle, "nvmlShutdown"))
            shutdown();
        dlclose(handle);
    }
};

std::optional<GpuClock> GpuClock::open(std::string_view glRenderer) {
    void* handle = dlopen("libnvidia-ml.so.1", RTLD_NOW | RTLD_LOCAL);
    if (!handle)
        return std::nullopt;
    const auto init = symbol<Init>(handle, "nvmlInit_v2");
    if (!init || init() != kSuccess) {
        dlclose(handle);
        return std::nullopt;
    }
    auto library = std::make_shared<Library>();
    library->handle = handle;
    library->clock = symbol<ClockInfo>(handle, "nvmlDeviceGetClockInfo");
    const auto count = symbol<DeviceCount>(handle, "nvmlDeviceGetCount_v2");
    const auto byIndex = symbol<DeviceByIndex>(handle, "nvmlDeviceGetHandleByIndex_v2");
    const auto name = symbol<DeviceName>(handle, "nvmlDeviceGetName");
    const auto maxClock = symbol<ClockInfo>(handle, "nvmlDeviceGetMaxClockInfo");
    unsigned devices = 0;
    if (!library->clock || !count || !byIndex || !name || !maxClock || count(&devices) != kSuccess)
        return std::nullopt;
    for (unsigned i = 0; i < devices; ++i) {
        void* device = nullptr;
        std::array<char, 96> text{};
        unsigned maxMhz = 0;
        if (byIndex(i, &device) != kSuccess || name(device, text.data(), text.size()) != kSuccess)
            continue;
        const std::string_view deviceName(text.data(), std::strlen(text.data()));
        if (glRenderer.substr(0, deviceName.size()) == deviceName &&
            maxClock(device, kGraphicsClock, &maxMhz) == kSuccess)
            return GpuClock(std::move(library), device, maxMhz);
    }
    return std::nullopt;
}

std::optional<unsigned> GpuClock::graphicsMhz() const {
    unsigned mhz = 0;
    if (library_->clock(device_, kGraphicsClock, &mhz) != kSuccess)
        return std::nullopt;
    return mhz;
}

} // namespace dc::tool
