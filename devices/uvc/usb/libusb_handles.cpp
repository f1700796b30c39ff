#include "devices/uvc/usb/libusb_handles.h"

#include <string>

namespace dc::devices::usb {

Expected<UsbContext> UsbContext::create() {
    UsbContext context;
    if (const int r = libusb_init(&context.context_); r < 0) {
        context.context_ = nullptr;
        return Error{std::string("cannot initialise libusb: ") + libusb_error_name(r)};
    }
    return context;
}

UsbContext& UsbContext::operator=(UsbContext&& other) noexcept {
    if (this != &other) {
        reset();
        context_ = std::exchange(other.context_, nullptr);
    }
    return *this;
}

void UsbContext::reset() {
    if (libusb_context* c = std::exchange(context_, nullptr))
        libusb_exit(c);
}

UsbDeviceList::UsbDeviceList(const UsbContext& context) {
    count_ = libusb_get_device_list(context.get(), &list_);
    if (count_ < 0)
        list_ = nullptr;
}

UsbDeviceList::~UsbDeviceList() {
    if (list_)
        libusb_free_device_list(list_, 1);
}

int UsbDeviceHandle::open(libusb_device* device) {
    reset();
    libusb_device_handle* handle = nullptr;
    if (const int r = libusb_open(device, &handle); r < 0)
        return r;
    handle_ = handle;
    return 0;
}

UsbDeviceHandle& UsbDeviceHandle::operator=(UsbDeviceHandle&& other) noexcept {
    if (this != &other) {
        reset();
        handle_ = std::exchange(other.handle_, nullptr);
    }
    return *this;
}

void UsbDeviceHandle::reset() {
    if (libusb_device_handle* h = std::exchange(handle_, nullptr))
        libusb_close(h);
}

UsbConfigDescriptor::UsbConfigDescriptor(libusb_device* device) {
    if (libusb_get_active_config_descriptor(device, &config_) < 0)
        config_ = nullptr;
}

UsbConfigDescriptor::~UsbConfigDescriptor() {
    if (config_)
        libusb_free_config_descriptor(config_);
}

} // namespace dc::devices::usb
