// The metadata node's buffers (V4L2_META_FMT_UVC, V4L2_META_FMT_D4XX), built byte by byte as uvcvideo
// lays them out: every field parses to its value, and a cut or inconsistent buffer is an error.

#include "devices/uvc/v4l2/uvc_metadata.h"
#include "tests/unit/metadata_bytes.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

namespace dc::devices::v4l2 {
namespace {

using dc::test::MetadataBytes;

constexpr std::uint64_t kArrivalNs = 0x0123'4567'89ab'cdefull;
constexpr std::uint8_t kEndOfHeader = 0x80;

// The driver's fields of a block: its clock and the USB frame number.
MetadataBytes blockStart() {
    MetadataBytes b;
    b.u64(kArrivalNs).u16(0x0345);
    return b;
}

TEST(UvcMetadata, PtsOnly) {
    const std::uint8_t flags = kEndOfHeader | kUvcHeaderHasPts | kUvcHeaderEndOfFrame | kUvcHeaderFrameId;
    const auto bytes = blockStart().u8(6).u8(flags).u32(0xdeadbeef).bytes;
    auto headers = parseUvcMetadata(bytes);
    ASSERT_TRUE(headers) << headers.error().message;
    ASSERT_EQ(headers->size(), 1u);
    const UvcPayloadHeader& h = headers->front();
    EXPECT_EQ(h.hostNs, kArrivalNs);
    EXPECT_EQ(h.hostSof, 0x0345);
    EXPECT_EQ(h.length, 6);
    EXPECT_EQ(h.flags, flags);
    EXPECT_TRUE(h.flags & kUvcHeaderEndOfFrame);
    EXPECT_TRUE(h.flags & kUvcHeaderFrameId);
    EXPECT_EQ(h.pts, 0xdeadbeefu);
    EXPECT_FALSE(h.scr);
}

TEST(UvcMetadata, PtsAndScrAndTheSofTokensReservedBits) {
    const std::uint8_t flags = kEndOfHeader | kUvcHeaderHasPts | kUvcHeaderHasScr;
    const auto bytes = blockStart().u8(12).u8(flags).u32(1'000'000).u32(1'002'500).u16(0xf9ab).bytes;
    auto headers = parseUvcMetadata(bytes);
    ASSERT_TRUE(headers) << headers.error().message;
    ASSERT_EQ(headers->size(), 1u);
    const UvcPayloadHeader& h = headers->front();
    EXPECT_EQ(h.pts, 1'000'000u);
    ASSERT_TRUE(h.scr);
    EXPECT_EQ(h.scr->sourceTimeClock, 1'002'500u);
    EXPECT_EQ(h.scr->sofToken, 0x01ab) << "the upper 5 bits are reserved";
    EXPECT_FALSE(h.flags & kUvcHeaderEndOfFrame);
}

// Several payloads of one frame, the first with neither PTS nor SCR, the second SCR only and cut by the
// node to its standard fields: the camera's header length stays as the camera sent it.
TEST(UvcMetadata, NoneThenScrOnlyOfALongerHeaderInOneBuffer) {
    const auto bytes =
        blockStart()
            .u8(2)
            .u8(kEndOfHeader)
            .append(blockStart().u8(0x9c).u8(kEndOfHeader | kUvcHeaderHasScr).u32(77).u16(5).bytes)
            .bytes;
    auto headers = parseUvcMetadata(bytes);
    ASSERT_TRUE(headers) << headers.error().message;
    ASSERT_EQ(headers->size(), 2u);
    EXPECT_FALSE((*headers)[0].pts);
    EXPECT_FALSE((*headers)[0].scr);
    EXPECT_EQ((*headers)[1].length, 0x9c);
    EXPECT_FALSE((*headers)[1].pts);
    ASSERT_TRUE((*headers)[1].scr);
    EXPECT_EQ((*headers)[1].scr->sourceTimeClock, 77u);
    EXPECT_EQ((*headers)[1].scr->sofToken, 5);

    auto empty = parseUvcMetadata({});
    ASSERT_TRUE(empty) << "the driver left every header out";
    EXPECT_TRUE(empty->empty());
}

TEST(UvcMetadata, AHeaderTooShortForWhatItsFlagsDeclareIsAnError) {
    const auto bytes = blockStart().u8(6).u8(kEndOfHeader | kUvcHeaderHasPts | kUvcHeaderHasScr).bytes;
    auto padded = bytes;
    padded.resize(bytes.size() + 10, 0);
    auto headers = parseUvcMetadata(padded);
    ASSERT_FALSE(headers);
    EXPECT_NE(headers.error().message.find("cannot hold the 12"), std::string::npos)
        << headers.error().message;
    EXPECT_FALSE(parseUvcMetadata(blockStart().u8(1).u8(kEndOfHeader).bytes)) << "length below 2";
}

TEST(UvcMetadata, EveryCutOfABlockIsAnError) {
    const auto bytes =
        blockStart().u8(12).u8(kEndOfHeader | kUvcHeaderHasPts | kUvcHeaderHasScr).u32(1).u32(2).u16(3).bytes;
    ASSERT_TRUE(parseUvcMetadata(bytes));
    for (std::size_t n = 1; n < bytes.size(); ++n) {
        auto cut = parseUvcMetadata(std::span(bytes).first(n));
        ASSERT_FALSE(cut) << n;
        EXPECT_NE(cut.error().message.find("cut short"), std::string::npos) << cut.error().message;
    }
}

constexpr std::uint32_t kFrameCounter = 4242;
constexpr std::uint32_t kGain = 16;
constexpr std::uint32_t kExposureUs = 8500;
constexpr std::uint32_t kLaserPower = 150;
constexpr std::uint32_t kAllValid = 0xffff'ffff;

// Intel's capture timing block: id, size, version, flags, frame counter, optical time, readout time,
// exposure time, frame interval, pipe latency.
std::vector<std::uint8_t> captureTimingBlock(std::uint32_t flags, std::uint32_t size = 40) {
    return MetadataBytes{}
        .u32(0x80000001)
        .u32(size)
        .u32(1)
        .u32(flags)
        .u32(kFrameCounter)
        .u32(4250)
        .u32(9000)
        .u32(kExposureUs)
        .u32(33333)
        .u32(2000)
        .bytes;
}

// Intel's depth control block (version 3): gain, exposure, laser power, AE mode, exposure priority, the
// AE region, preset, then emitter mode, a spare byte and LED power.
std::vector<std::uint8_t> depthControlBlock(std::uint32_t flags) {
    return MetadataBytes{}
        .u32(0x80000000)
        .u32(60)
        .u32(3)
        .u32(flags)
        .u32(kGain)
        .u32(kExposureUs)
        .u32(kLaserPower)
        .u32(1)
        .u32(0)
        .u32(0)
        .u32(847)
        .u32(0)
        .u32(479)
        .u32(0)
        .u8(1)
        .u8(0)
        .u16(0)
        .bytes;
}

// One D4xx payload header: the standard fields with PTS and SCR, then `vendor` bytes.
std::vector<std::uint8_t> d4xxBuffer(const std::vector<std::uint8_t>& vendor) {
    return blockStart()
        .u8(12 + vendor.size())
        .u8(kEndOfHeader | kUvcHeaderHasPts | kUvcHeaderHasScr | kUvcHeaderEndOfFrame)
        .u32(123456)
        .u32(123999)
        .u16(0x0123)
        .append(vendor)
        .bytes;
}

// The blocks as a D435 sends them for depth, with Microsoft's capture statistics (id 3) between them,
// which this parser skips.
std::vector<std::uint8_t> d4xxBlocks(std::uint32_t timingFlags, std::uint32_t controlFlags) {
    return MetadataBytes{}
        .append(captureTimingBlock(timingFlags))
        .u32(3)
        .u32(16)
        .u32(0)
        .u32(0)
        .append(depthControlBlock(controlFlags))
        .bytes;
}

TEST(D4xxMetadata, FrameCounterExposureGainAndLaserPower) {
    auto m = parseD4xxMetadata(d4xxBuffer(d4xxBlocks(kAllValid, kAllValid)));
    ASSERT_TRUE(m) << m.error().message;
    ASSERT_EQ(m->headers.size(), 1u);
    EXPECT_EQ(m->headers.front().length, 12 + 40 + 16 + 60);
    EXPECT_EQ(m->headers.front().pts, 123456u);
    ASSERT_TRUE(m->headers.front().scr);
    EXPECT_EQ(m->headers.front().scr->sourceTimeClock, 123999u);
    EXPECT_EQ(m->frameCounter, kFrameCounter);
    EXPECT_EQ(m->exposureUs, kExposureUs);
    EXPECT_EQ(m->gain, kGain);
    EXPECT_EQ(m->laserPower, kLaserPower);
}

TEST(D4xxMetadata, AValueMarkedInvalidIsNotReported) {
    auto none = parseD4xxMetadata(d4xxBuffer(d4xxBlocks(0, 0)));
    ASSERT_TRUE(none) << none.error().message;
    EXPECT_FALSE(none->frameCounter);
    EXPECT_FALSE(none->exposureUs);
    EXPECT_FALSE(none->gain);
    EXPECT_FALSE(none->laserPower);

    // Only laser power valid (0x04); the capture timing's own bits do not count for depth control.
    auto laser = parseD4xxMetadata(d4xxBuffer(d4xxBlocks(0xffff'fffe, 0x04)));
    ASSERT_TRUE(laser) << laser.error().message;
    EXPECT_FALSE(laser->frameCounter);
    EXPECT_FALSE(laser->exposureUs);
    EXPECT_FALSE(laser->gain);
    EXPECT_EQ(laser->laserPower, kLaserPower);

    auto plain = parseD4xxMetadata(d4xxBuffer({}));
    ASSERT_TRUE(plain) << "a header without Intel's blocks";
    EXPECT_FALSE(plain->frameCounter);
}

TEST(D4xxMetadata, EveryCutIsAnError) {
    const auto bytes = d4xxBuffer(d4xxBlocks(kAllValid, kAllValid));
    for (std::size_t n = 1; n < bytes.size(); ++n)
        ASSERT_FALSE(parseD4xxMetadata(std::span(bytes).first(n))) << n;
}

TEST(D4xxMetadata, BlocksWhoseSizesDisagreeWithTheHeaderAreErrors) {
    const auto expectError = [](const std::vector<std::uint8_t>& vendor, const std::string& what) {
        auto m = parseD4xxMetadata(d4xxBuffer(vendor));
        ASSERT_FALSE(m) << what;
        EXPECT_NE(m.error().message.find("D4XX metadata: "), std::string::npos) << m.error().message;
    };
    auto tooLong = depthControlBlock(kAllValid);
    tooLong[4] = 61; // one byte more than the header holds
    expectError(tooLong, "a block past the header's end");
    auto tooShort = depthControlBlock(kAllValid);
    tooShort[4] = 4; // smaller than its own id and size
    expectError(tooShort, "a block smaller than 8 bytes");
    expectError(captureTimingBlock(kAllValid, 16), "a capture timing block too small for its frame counter");
    expectError(MetadataBytes{}.append(depthControlBlock(kAllValid)).u32(0).bytes,
                "4 bytes after the last block");
}

// Random bytes and a buffer of 0xff never read past the end: they parse or are an error.
TEST(UvcMetadata, GarbageIsAnErrorNeverACrash) {
    const std::vector<std::uint8_t> ones(64, 0xff);
    EXPECT_FALSE(parseUvcMetadata(ones));
    EXPECT_FALSE(parseD4xxMetadata(ones));
    std::mt19937 random(30);
    std::uniform_int_distribution<int> byte(0, 255);
    for (int i = 0; i < 2000; ++i) {
        std::vector<std::uint8_t> bytes(static_cast<std::size_t>(byte(random)));
        for (auto& b : bytes)
            b = static_cast<std::uint8_t>(byte(random));
        const auto uvc = parseUvcMetadata(bytes);
        const auto d4xx = parseD4xxMetadata(bytes);
        EXPECT_TRUE(uvc || !uvc.error().message.empty());
        EXPECT_TRUE(d4xx || !d4xx.error().message.empty());
    }
}

} // namespace
} // namespace dc::devices::v4l2
