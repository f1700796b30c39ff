#pragma once

#include "base/expected.h"

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

// Parsers for the buffers of a UVC camera's metadata node (uvcvideo's second /dev/video node per
// streaming interface): V4L2_META_FMT_UVC, and V4L2_META_FMT_D4XX, which RealSense D4xx cameras extend
// with Intel's blocks. The node's bytes come from the camera, so every length in them is checked against
// the buffer before it is used; a bad buffer is an error, never a read past its end.
namespace dc::devices::v4l2 {

// The UVC payload header's flags (UVC 1.5, 2.4.3.3).
inline constexpr std::uint8_t kUvcHeaderFrameId = 0x01;
inline constexpr std::uint8_t kUvcHeaderEndOfFrame = 0x02;
inline constexpr std::uint8_t kUvcHeaderHasPts = 0x04;
inline constexpr std::uint8_t kUvcHeaderHasScr = 0x08;

// The source clock reference: the camera's clock sampled with the USB bus's frame number, which is what
// relates the camera's clock (PTS) to this machine's.
struct UvcScr {
    std::uint32_t sourceTimeClock = 0;
    std::uint16_t sofToken = 0; // the USB frame number's low 11 bits; the upper 5 are reserved
};

// One block of a metadata buffer (struct uvc_meta_buf): the driver's clock at the payload's arrival
// and a copy of the camera's payload header.
struct UvcPayloadHeader {
    std::uint64_t hostNs = 0;  // CLOCK_MONOTONIC (uvcvideo's default clock) when the payload arrived
    std::uint16_t hostSof = 0; // the USB frame number the driver read at that time
    // The camera's header length. For V4L2_META_FMT_UVC the node copies only the standard fields, so
    // this may be larger than what the buffer holds.
    std::uint8_t length = 0;
    std::uint8_t flags = 0;
    std::optional<std::uint32_t> pts; // the camera's clock at the start of exposure
    std::optional<UvcScr> scr;
};

// All blocks of one V4L2_META_FMT_UVC buffer (its bytesused), in order. An empty buffer is no blocks:
// the driver leaves out headers that add nothing (no SCR, or the same SCR as before).
Expected<std::vector<UvcPayloadHeader>> parseUvcMetadata(std::span<const std::uint8_t> buffer);

// What a D4xx camera adds to its payload header, each value only where the camera marks it valid.
struct D4xxMetadata {
    std::vector<UvcPayloadHeader> headers;     // one per payload; D4xx cameras send one per frame
    std::optional<std::uint32_t> frameCounter; // capture timing: the camera's own frame count
    std::optional<std::uint32_t> exposureUs;   // depth control: the exposure the frame was taken with
    std::optional<std::uint32_t> gain;         // depth control: in V4L2_CID_GAIN's units
    std::optional<std::uint32_t> laserPower;   // depth control: the projector's power, 0-360
};

// One V4L2_META_FMT_D4XX buffer: blocks as for V4L2_META_FMT_UVC, each with the whole header, whose
// bytes after the standard fields are Intel's and Microsoft's blocks (u32 id, u32 size including these
// 8 bytes, then the fields). Blocks of other kinds are skipped.
Expected<D4xxMetadata> parseD4xxMetadata(std::span<const std::uint8_t> buffer);

} // namespace dc::devices::v4l2
