#include "devices/uvc/usb/usb_enumeration.h"

#include "devices/uvc/usb/libusb_device_info.h"
#include "devices/uvc/usb/libusb_handles.h"

#include <array>

namespace dc::devices::usb {

namespace {

std::string stringDescriptor(const UsbDeviceHandle& handle, std::uint8_t index) {
    if (!handle.get() || index == 0)
        return {};
    std::array<unsigned char, 256> text{};
    const int n =
        libusb_get_string_descriptor_ascii(handle.get(), index, text.data(), static_cast<int>(text.size()));
    return n > 0 ? std::string(reinterpret_cast<const char*>(text.data()), static_cast<std::size_t>(n))
                 : std::string();
}

bool hasVideoInterface(libusb_device* device) {
    const UsbConfigDescriptor config(device);
    if (!config.get())
        return false;
    for (int i = 0; i < config.get()->bNumInterfaces; ++i) {
        const libusb_interface& interface = config.get()->interface[i];
        for (int a = 0; a < interface.num_altsetting; ++a)
            if (interface.altsetting[a].bInterfaceClass == LIBUSB_CLASS_VIDEO)
                return true;
    }
    return false;
}

} // namespace

UsbDeviceInfo describeUsbDevice(libusb_device* device, const Sysfs& sysfs, bool openForStrings) {
    UsbDeviceInfo info;
    libusb_device_descriptor desc{};
    libusb_get_device_descriptor(device, &desc); // cannot fail since libusb 1.0.16
    info.vendorId = desc.idVendor;
    info.productId = desc.idProduct;
    info.bus = libusb_get_bus_number(device);
    info.address = libusb_get_device_address(device);
    std::array<std::uint8_t, 8> ports{};
    const int depth = libusb_get_port_numbers(device, ports.data(), static_cast<int>(ports.size()));
    for (int i = 0; i < depth; ++i)
        info.ports.push_back(ports[static_cast<std::size_t>(i)]);
    info.hasVideoInterface = hasVideoInterface(device); // cached descriptors: no I/O
    if (openForStrings) {
        UsbDeviceHandle handle;
        if (handle.open(device) == 0) {
            info.manufacturer = stringDescriptor(handle, desc.iManufacturer);
            info.product = stringDescriptor(handle, desc.iProduct);
            info.serial = stringDescriptor(handle, desc.iSerialNumber);
        }
    }
    if (const auto fromSysfs = sysfs.usbDevice(info.sysfsName())) {
        if (info.manufacturer.empty())
            info.manufacturer = fromSysfs->manufacturer;
        if (info.product.empty())
            info.product = fromSysfs->product;
        if (info.serial.empty())
            info.serial = fromSysfs->serial;
        info.hasVideoInterface = info.hasVideoInterface || fromSysfs->hasVideoInterface;
    }
    return info;
}

Expected<std::vector<UsbDeviceInfo>> enumerateUsbDevices(const Sysfs& sysfs) {
    auto context = UsbContext::create();
    if (!context)
        return context.error();
    const UsbDeviceList list(*context);
    if (list.error())
        return Error{std::string("cannot list USB devices: ") + libusb_error_name(list.error())};
    std::vector<UsbDeviceInfo> result;
    for (libusb_device* device : list.devices()) {
        if (libusb_get_port_number(device) == 0) // a root hub
            continue;
        result.push_back(describeUsbDevice(device, sysfs, true));
    }
    return result;
}

} // namespace dc::devices::usb
