#pragma once

#include "base/expected.h"

#include <libusb.h>
#include <span>
#include <utility>

namespace dc::devices::usb {

// Move-only owners of libusb objects: every context, device list and open handle is released exactly once,
// also on early returns. Only devices/usb/*.cpp and tests include this header (the UI sees plain data).

class UsbContext {
public:
    UsbContext() = default;
    static Expected<UsbContext> create();
    UsbContext(UsbContext&& other) noexcept : context_(std::exchange(other.context_, nullptr)) {}
    UsbContext& operator=(UsbContext&& other) noexcept;
    UsbContext(const UsbContext&) = delete;
    UsbContext& operator=(const UsbContext&) = delete;
    ~UsbContext() { reset(); }

    libusb_context* get() const { return context_; }
    void reset();

private:
    libusb_context* context_ = nullptr;
};

// libusb_get_device_list / libusb_free_device_list (which drops the list's references).
class UsbDeviceList {
public:
    explicit UsbDeviceList(const UsbContext& context);
    UsbDeviceList(UsbDeviceList&& other) noexcept
        : list_(std::exchange(other.list_, nullptr)), count_(std::exchange(other.count_, 0)) {}
    UsbDeviceList& operator=(UsbDeviceList&&) = delete;
    UsbDeviceList(const UsbDeviceList&) = delete;
    UsbDeviceList& operator=(const UsbDeviceList&) = delete;
    ~UsbDeviceList();

    // A negative libusb error code when enumeration failed (then devices() is empty).
    int error() const { return count_ < 0 ? static_cast<int>(count_) : 0; }
    std::span<libusb_device* const> devices() const {
        return count_ > 0 ? std::span<libusb_device* const>(list_, static_cast<std::size_t>(count_))
                          : std::span<libusb_device* const>();
    }

private:
    libusb_device** list_ = nullptr;
    ssize_t count_ = 0;
};

class UsbDeviceHandle {
public:
    UsbDeviceHandle() = default;
    // libusb_open; 0 or a libusb error code (LIBUSB_ERROR_ACCESS without permission on the device node).
    int open(libusb_device* device);
    UsbDeviceHandle(UsbDeviceHandle&& other) noexcept : handle_(std::exchange(other.handle_, nullptr)) {}
    UsbDeviceHandle& operator=(UsbDeviceHandle&& other) noexcept;
    UsbDeviceHandle(const UsbDeviceHandle&) = delete;
    UsbDeviceHandle& operator=(const UsbDeviceHandle&) = delete;
    ~UsbDeviceHandle() { reset(); }

    libusb_device_handle* get() const { return handle_; }
    void reset();

private:
    libusb_device_handle* handle_ = nullptr;
};

// libusb_get_active_config_descriptor / libusb_free_config_descriptor.
class UsbConfigDescriptor {
public:
    explicit UsbConfigDescriptor(libusb_device* device);
    UsbConfigDescriptor(const UsbConfigDescriptor&) = delete;
    UsbConfigDescriptor& operator=(const UsbConfigDescriptor&) = delete;
    ~UsbConfigDescriptor();

    const libusb_config_descriptor* get() const { return config_; }

private:
    libusb_config_descriptor* config_ = nullptr;
};

} // namespace dc::devices::usb
