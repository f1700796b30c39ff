#include "devices/uvc/v4l2/uvc_metadata.h"

#include <bit>
#include <cstdio>
#include <cstring>
#include <string>

namespace dc::devices::v4l2 {

static_assert(std::endian::native == std::endian::little, "metadata buffers are little-endian");

namespace {

constexpr std::size_t kUvcMetaDriverFields = 10;  // u64 ns, u16 sof: the driver's, before the camera's header
constexpr std::size_t kUvcMetaSmallestHeader = 2; // u8 length, u8 flags
constexpr std::size_t kUvcMetaPtsSize = 4;
constexpr std::size_t kUvcMetaScrSize = 6; // u32 source time clock, u16 SOF token
constexpr std::uint16_t kUvcMetaSofTokenMask = 0x07ff;

// Intel's block ids (the kernel's metafmt-d4xx documentation; librealsense's metadata.h).
constexpr std::uint32_t kD4xxDepthControlId = 0x80000000;
constexpr std::uint32_t kD4xxCaptureTimingId = 0x80000001;
constexpr std::size_t kD4xxBlockHeaderSize = 8; // u32 id, u32 size
// Each block: u32 version, u32 flags (which fields are valid), then the fields. The smallest block that
// holds every field read here: capture timing up to the frame counter, depth control up to laser power.
constexpr std::size_t kD4xxCaptureTimingNeeds = 20;
constexpr std::size_t kD4xxDepthControlNeeds = 28;
constexpr std::uint32_t kD4xxFrameCounterValid = 0x01;
constexpr std::uint32_t kD4xxGainValid = 0x01;
constexpr std::uint32_t kD4xxExposureValid = 0x02;
constexpr std::uint32_t kD4xxLaserPowerValid = 0x04;

// Callers have checked that `at + sizeof(T)` lies inside `bytes`.
template <class T> T uvcMetaLoad(std::span<const std::uint8_t> bytes, std::size_t at) {
    T value;
    std::memcpy(&value, bytes.data() + at, sizeof(T));
    return value;
}

std::string uvcMetaAt(std::size_t offset) {
    return " (byte " + std::to_string(offset) + ")";
}

std::string uvcMetaHex(std::uint32_t value) {
    char text[16];
    std::snprintf(text, sizeof text, "0x%x", value);
    return text;
}

// What the flags say the header holds besides its length and flags.
std::size_t uvcMetaStandardLength(std::uint8_t flags) {
    return kUvcMetaSmallestHeader + ((flags & kUvcHeaderHasPts) ? kUvcMetaPtsSize : 0) +
           ((flags & kUvcHeaderHasScr) ? kUvcMetaScrSize : 0);
}

struct UvcMetaBlock {
    UvcPayloadHeader header;
    std::span<const std::uint8_t> vendorBytes; // the header's bytes after the standard fields
    std::size_t vendorAt = 0;                  // their offset in the buffer
    std::size_t size = 0;                      // of the whole block
};

// The block at `at`. `wholeHeader`: the node copied the camera's whole header (D4XX), not only the
// standard fields (UVC), so the block is as long as the header's length says.
Expected<UvcMetaBlock> uvcMetaBlockAt(std::span<const std::uint8_t> buffer, std::size_t at,
                                      bool wholeHeader) {
    const std::size_t left = buffer.size() - at;
    if (left < kUvcMetaDriverFields + kUvcMetaSmallestHeader)
        return Error{"metadata block cut short: " + std::to_string(left) + " bytes, a block has at least " +
                     std::to_string(kUvcMetaDriverFields + kUvcMetaSmallestHeader) + uvcMetaAt(at)};
    UvcMetaBlock block;
    UvcPayloadHeader& h = block.header;
    h.hostNs = uvcMetaLoad<std::uint64_t>(buffer, at);
    h.hostSof = uvcMetaLoad<std::uint16_t>(buffer, at + 8);
    h.length = buffer[at + kUvcMetaDriverFields];
    h.flags = buffer[at + kUvcMetaDriverFields + 1];
    const std::size_t standard = uvcMetaStandardLength(h.flags);
    if (h.length < standard)
        return Error{"UVC payload header of " + std::to_string(h.length) + " bytes cannot hold the " +
                     std::to_string(standard) + " its flags (" + uvcMetaHex(h.flags) + ") declare" +
                     uvcMetaAt(at + kUvcMetaDriverFields)};
    const std::size_t copied = wholeHeader ? h.length : standard;
    if (left - kUvcMetaDriverFields < copied)
        return Error{"metadata block cut short: its header has " + std::to_string(copied) + " bytes, " +
                     std::to_string(left - kUvcMetaDriverFields) + " are left" +
                     uvcMetaAt(at + kUvcMetaDriverFields)};
    std::size_t field = at + kUvcMetaDriverFields + kUvcMetaSmallestHeader;
    if (h.flags & kUvcHeaderHasPts) {
        h.pts = uvcMetaLoad<std::uint32_t>(buffer, field);
        field += kUvcMetaPtsSize;
    }
    if (h.flags & kUvcHeaderHasScr) {
        const auto token = uvcMetaLoad<std::uint16_t>(buffer, field + 4);
        h.scr = UvcScr{uvcMetaLoad<std::uint32_t>(buffer, field),
                       static_cast<std::uint16_t>(token & kUvcMetaSofTokenMask)};
        field += kUvcMetaScrSize;
    }
    block.vendorBytes = buffer.subspan(field, copied - standard);
    block.vendorAt = field;
    block.size = kUvcMetaDriverFields + copied;
    return block;
}

// A field of an Intel block, or nothing where the block's flags mark it invalid.
std::optional<std::uint32_t> d4xxField(std::span<const std::uint8_t> block, std::uint32_t validBit,
                                       std::size_t at) {
    if (!(uvcMetaLoad<std::uint32_t>(block, 12) & validBit))
        return std::nullopt;
    return uvcMetaLoad<std::uint32_t>(block, at);
}

// Reads the blocks this parser knows from a header's vendor bytes (at `base` in the buffer) into `out`.
Status d4xxReadBlocks(std::span<const std::uint8_t> bytes, std::size_t base, D4xxMetadata& out) {
    for (std::size_t at = 0; at < bytes.size();) {
        const std::size_t left = bytes.size() - at;
        if (left < kD4xxBlockHeaderSize)
            return Error{"D4XX metadata: " + std::to_string(left) +
                         " bytes after the last block, too few for a block" + uvcMetaAt(base + at)};
        const auto id = uvcMetaLoad<std::uint32_t>(bytes, at);
        const auto size = uvcMetaLoad<std::uint32_t>(bytes, at + 4);
        if (size < kD4xxBlockHeaderSize || size > left)
            return Error{"D4XX metadata: block " + uvcMetaHex(id) + " of " + std::to_string(size) +
                         " bytes does not fit the " + std::to_string(left) + " left" + uvcMetaAt(base + at)};
        const auto block = bytes.subspan(at, size);
        const std::size_t needs = id == kD4xxCaptureTimingId  ? kD4xxCaptureTimingNeeds
                                  : id == kD4xxDepthControlId ? kD4xxDepthControlNeeds
                                                              : 0;
        if (size < needs)
            return Error{"D4XX metadata: block " + uvcMetaHex(id) + " of " + std::to_string(size) +
                         " bytes, its fields need " + std::to_string(needs) + uvcMetaAt(base + at)};
        if (id == kD4xxCaptureTimingId) {
            out.frameCounter = d4xxField(block, kD4xxFrameCounterValid, 16);
        } else if (id == kD4xxDepthControlId) {
            out.gain = d4xxField(block, kD4xxGainValid, 16);
            out.exposureUs = d4xxField(block, kD4xxExposureValid, 20);
            out.laserPower = d4xxField(block, kD4xxLaserPowerValid, 24);
        }
        at += size;
    }
    return {};
}

} // namespace

Expected<std::vector<UvcPayloadHeader>> parseUvcMetadata(std::span<const std::uint8_t> buffer) {
    std::vector<UvcPayloadHeader> headers;
    for (std::size_t at = 0; at < buffer.size();) {
        auto block = uvcMetaBlockAt(buffer, at, false);
        if (!block)
            return block.error();
        headers.push_back(block->header);
        at += block->size;
    }
    return headers;
}

Expected<D4xxMetadata> parseD4xxMetadata(std::span<const std::uint8_t> buffer) {
    D4xxMetadata out;
    for (std::size_t at = 0; at < buffer.size();) {
        auto block = uvcMetaBlockAt(buffer, at, true);
        if (!block)
            return block.error();
        if (Status s = d4xxReadBlocks(block->vendorBytes, block->vendorAt, out); !s)
            return s.error();
        out.headers.push_back(block->header);
        at += block->size;
    }
    return out;
}

} // namespace dc::devices::v4l2
