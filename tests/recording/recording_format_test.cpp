// The recording format: lossless round trip, crash recovery and every damaged input the issue lists.

#include "devices/recording/recorder.h"
#include "devices/recording/recording_reader.h"
#include "devices/replay/importers.h"
#include "frame/camera_model.h"
#include "frame/color.h"
#include "frame/jpeg_codec.h"
#include "frame/rgb_image.h"
#include "tests/recording/recording_test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

namespace dc::devices::recording {
namespace {

using test::TempDir;

void expectSameFrame(const frame::Frame& a, const frame::Frame& b) {
    EXPECT_EQ(a.timestampNs, b.timestampNs);
    EXPECT_EQ(a.sequence, b.sequence);
    ASSERT_TRUE(a.sceneDepth && b.sceneDepth);
    EXPECT_TRUE(test::sameBits(a.sceneDepth->depthMeters, b.sceneDepth->depthMeters));
    EXPECT_EQ(a.sceneDepth->confidence.pixels, b.sceneDepth->confidence.pixels);
    ASSERT_TRUE(a.pose && b.pose);
    EXPECT_EQ(a.pose->cameraToWorld, b.pose->cameraToWorld);
    EXPECT_EQ(a.cameraIntrinsics.fx, b.cameraIntrinsics.fx);
    EXPECT_EQ(a.cameraIntrinsics.cy, b.cameraIntrinsics.cy);
    EXPECT_EQ(a.cameraIntrinsics.width, b.cameraIntrinsics.width);
    EXPECT_EQ(a.capturedImage.format, b.capturedImage.format);
    ASSERT_FALSE(b.capturedImage.empty());
    EXPECT_EQ(*a.capturedImage.bytes, *b.capturedImage.bytes);
}

TEST(RecordingFormat, RoundTripIsBitExactWithAndWithoutCompression) {
    const auto frames = test::syntheticFrames(12);
    for (const bool compress : {true, false}) {
        TempDir dir;
        WriterOptions options;
        options.encode.compress = compress;
        test::writeRecording(dir.path("r.dcrec"), frames, options);
        EXPECT_FALSE(std::filesystem::exists(dir.path("r.dcrec.partial"))) << "renamed at close";
        auto reader = RecordingReader::open(dir.path("r.dcrec"));
        ASSERT_TRUE(reader) << reader.error().message;
        EXPECT_TRUE(reader->openedThroughIndex());
        EXPECT_TRUE(reader->warnings().empty());
        ASSERT_EQ(reader->frameCount(), frames.size());
        ASSERT_TRUE(reader->device());
        EXPECT_EQ(reader->device()->description, "test camera");
        EXPECT_TRUE(reader->device()->capabilities.confidence);
        for (std::size_t i = 0; i < frames.size(); ++i) {
            EXPECT_EQ(reader->timestampNs(i), frames[i]->timestampNs);
            auto f = reader->frame(i);
            ASSERT_TRUE(f) << f.error().message;
            expectSameFrame(*frames[i], *f);
        }
    }
}

TEST(RecordingFormat, NanNegativeAndSmoothedDepthSurviveTheFileThenReplayZeroesInvalidDepth) {
    frame::Frame frame;
    frame.timestampNs = 5;
    frame.cameraIntrinsics = {100, 100, 2, 1, 4, 2};
    frame::Plane<float> depth(4, 2, 1.5f);
    depth.pixels[1] = std::numeric_limits<float>::quiet_NaN();
    depth.pixels[2] = -2.0f;
    depth.pixels[3] = std::numeric_limits<float>::infinity();
    frame.sceneDepth = frame::DepthData{depth, {}};
    frame.smoothedSceneDepth =
        frame::DepthData{frame::Plane<float>(4, 2, 0.25f), frame::Plane<std::uint8_t>(4, 2, 1)};
    TempDir dir;
    test::writeRecording(dir.path("n.dcrec"), {std::make_shared<frame::Frame>(frame)});
    auto reader = RecordingReader::open(dir.path("n.dcrec"));
    ASSERT_TRUE(reader);
    auto stored = reader->frame(0);
    ASSERT_TRUE(stored);
    EXPECT_TRUE(test::sameBits(stored->sceneDepth->depthMeters, depth)) << "the file keeps what it was given";
    EXPECT_TRUE(stored->sceneDepth->confidence.empty()) << "no confidence stays no confidence";
    ASSERT_TRUE(stored->smoothedSceneDepth);
    EXPECT_EQ(stored->smoothedSceneDepth->confidence.pixels, frame.smoothedSceneDepth->confidence.pixels);

    auto source = replay::openRecordingSource(dir.path("n.dcrec"));
    ASSERT_TRUE(source);
    auto replayed = replay::loadFrame(**source, 0);
    ASSERT_TRUE(replayed);
    const auto& px = replayed->sceneDepth->depthMeters.pixels;
    EXPECT_EQ(px[0], 1.5f);
    EXPECT_EQ(px[1], 0.0f) << "NaN becomes no measurement";
    EXPECT_EQ(px[2], 0.0f) << "negative becomes no measurement";
    EXPECT_EQ(px[3], 0.0f) << "infinity becomes no measurement";
}

TEST(RecordingFormat, IntegerDepthIsStoredAsUint16WithItsScaleAndDecodesExactly) {
    frame::Plane<float> mm(64, 48);
    for (std::size_t i = 0; i < mm.pixels.size(); ++i)
        mm.pixels[i] = i % 7 == 0 ? 0.0f : depthFromUnits(static_cast<std::uint16_t>(400 + i), 0.001);
    EXPECT_EQ(exactUint16Scale(mm), 0.001);
    frame::Plane<float> tum = mm;
    for (std::size_t i = 0; i < tum.pixels.size(); ++i)
        tum.pixels[i] = depthFromUnits(static_cast<std::uint16_t>(9000 + 3 * i), 1.0 / 5000.0);
    EXPECT_EQ(exactUint16Scale(tum), 0.0002);
    frame::Plane<float> measured = mm;
    measured.pixels[5] = 1.2345678f;
    EXPECT_FALSE(exactUint16Scale(measured)) << "one sample that is not an integer keeps float32";

    frame::Frame frame;
    frame.sceneDepth = frame::DepthData{mm, {}};
    FrameEncoder encoder;
    auto payload = encoder.encode(frame);
    ASSERT_TRUE(payload);
    EXPECT_LT(payload->size(), mm.pixels.size() * 2 + 200) << "two bytes per sample at most";
    FrameDecoder decoder;
    auto decoded = decoder.decode(*payload, 0, "mem", 0);
    ASSERT_TRUE(decoded) << decoded.error().message;
    EXPECT_TRUE(test::sameBits(decoded->sceneDepth->depthMeters, mm));
}

// Sizes around the 16-sample blocks the byte shuffle moves at once, with every byte of a sample distinct,
// so that a sample or a byte landing in the wrong place cannot go unnoticed.
TEST(RecordingFormat, FloatDepthIsStoredAsByteplanesAndDecodesBitExactForAnySize) {
    const auto byteOf = [](std::size_t i, int k) { return static_cast<std::uint8_t>(i * 4 + k * 61 + 7); };
    for (const auto& [w, h] : {std::pair{1, 1}, {15, 1}, {16, 1}, {17, 1}, {16, 2}, {33, 3}, {640, 3}}) {
        frame::Plane<float> depth(w, h);
        const std::size_t n = depth.pixels.size();
        std::vector<std::uint8_t> plane0(n);
        for (std::size_t i = 0; i < n; ++i) {
            const std::uint32_t bits = byteOf(i, 0) | byteOf(i, 1) << 8 | byteOf(i, 2) << 16 |
                                       static_cast<std::uint32_t>(byteOf(i, 3)) << 24;
            depth.pixels[i] = std::bit_cast<float>(bits);
            plane0[i] = byteOf(i, 0);
        }
        frame::Frame frame;
        frame.sceneDepth = frame::DepthData{depth, {}};
        for (const bool compress : {false, true}) {
            EncodeOptions options;
            options.compress = compress;
            auto payload = FrameEncoder(options).encode(frame);
            ASSERT_TRUE(payload);
            if (!compress) {
                EXPECT_NE(std::search(payload->begin(), payload->end(), plane0.begin(), plane0.end()),
                          payload->end())
                    << w << "x" << h << ": the low bytes of all samples are stored together";
            }
            FrameDecoder decoder;
            auto decoded = decoder.decode(*payload, 0, "mem", 0);
            ASSERT_TRUE(decoded) << decoded.error().message;
            EXPECT_TRUE(test::sameBits(decoded->sceneDepth->depthMeters, depth)) << w << "x" << h;
        }
    }
}

TEST(RecordingFormat, JpegColorDecodesToTheCapturedFormatAndSize) {
    const auto frames = test::syntheticFrames(2);
    TempDir dir;
    WriterOptions options;
    options.encode.color = ColorStorage::Jpeg;
    test::writeRecording(dir.path("j.dcrec"), frames, options);
    auto reader = RecordingReader::open(dir.path("j.dcrec"));
    ASSERT_TRUE(reader);
    auto f = reader->frame(1);
    ASSERT_TRUE(f) << f.error().message;
    EXPECT_EQ(f->capturedImage.format, frame::PixelFormat::Nv12);
    EXPECT_EQ(f->capturedImage.width, frames[1]->capturedImage.width);
    EXPECT_EQ(f->capturedImage.height, frames[1]->capturedImage.height);
    EXPECT_TRUE(test::sameBits(f->sceneDepth->depthMeters, frames[1]->sceneDepth->depthMeters));
}

// A colourful test image in `format`: Y, Cb and Cr vary independently, so swapped or converted planes
// show up as large errors.
frame::CapturedImage patternImage(frame::PixelFormat format, int w, int h) {
    std::vector<std::uint8_t> bytes(frame::CapturedImage::byteSize(format, w, h));
    for (std::size_t i = 0; i < bytes.size(); ++i)
        bytes[i] = static_cast<std::uint8_t>(64 + (i * 7 % 61) + (i / static_cast<std::size_t>(3 * w)) % 64);
    return {format, w, h, std::make_shared<const std::vector<std::uint8_t>>(std::move(bytes))};
}

double meanAbsoluteDifference(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
        sum += std::abs(static_cast<int>(a[i]) - static_cast<int>(b[i]));
    return sum / static_cast<double>(a.size());
}

TEST(JpegCodec, YcbcrPlanesRoundTripWithoutColourConversion) {
    for (const auto format : {frame::PixelFormat::Nv12, frame::PixelFormat::Yuyv}) {
        for (const auto& [w, h] : {std::pair{64, 48}, std::pair{7, 5}}) {
            SCOPED_TRACE(std::string(toString(format)) + " " + std::to_string(w) + "x" + std::to_string(h));
            const frame::CapturedImage image = patternImage(format, w, h);
            frame::JpegEncoder encoder;
            auto jpeg = encoder.encode(image, 100);
            ASSERT_TRUE(jpeg) << jpeg.error().message;
            const std::vector<std::uint8_t> stored(jpeg->begin(), jpeg->end());
            auto decoded = frame::JpegDecoder().decode(stored, w, h);
            ASSERT_TRUE(decoded) << decoded.error().message;
            EXPECT_EQ(decoded->format, format) << "the format as captured, not RGB";
            ASSERT_EQ(decoded->bytes->size(), image.bytes->size());
            // Byte for byte the same planes within JPEG's loss at quality 100: a colour conversion on the
            // way (or swapped Cb and Cr) costs several levels on this pattern.
            EXPECT_LT(meanAbsoluteDifference(*decoded->bytes, *image.bytes), 1.5);
        }
    }
}

TEST(JpegCodec, QualityReachesTheEncoderAndRgbIsStoredAsYcbcr) {
    const frame::CapturedImage image = patternImage(frame::PixelFormat::Rgb24, 64, 48);
    frame::JpegEncoder encoder;
    auto low = encoder.encode(image, 20);
    ASSERT_TRUE(low);
    const std::size_t lowSize = low->size();
    auto high = encoder.encode(image, 95);
    ASSERT_TRUE(high);
    EXPECT_LT(lowSize, high->size());
    const std::vector<std::uint8_t> stored(high->begin(), high->end());
    auto decoded = frame::JpegDecoder().decode(stored, 64, 48);
    ASSERT_TRUE(decoded);
    EXPECT_EQ(decoded->format, frame::PixelFormat::Nv12);
    EXPECT_FALSE(frame::JpegDecoder().decode(stored, 64, 47)) << "a JPEG of another size than its section";
    EXPECT_FALSE(frame::JpegDecoder().decode(std::span(stored).first(stored.size() / 2), 64, 48))
        << "truncated";
}

TEST(RecordingFormat, ACamerasOwnJpegIsStoredAsItCameWhateverTheStorage) {
    const frame::CapturedImage nv12 = patternImage(frame::PixelFormat::Nv12, 64, 48);
    frame::JpegEncoder encoder; // its result lives in the encoder
    auto jpeg = encoder.encode(nv12, 80);
    ASSERT_TRUE(jpeg);
    const std::vector<std::uint8_t> mjpeg(jpeg->begin(), jpeg->end());
    frame::Frame frame;
    frame.capturedImage = {frame::PixelFormat::Jpeg, 64, 48,
                           std::make_shared<const std::vector<std::uint8_t>>(mjpeg)};
    const auto expected = frame::JpegDecoder().decode(frame.capturedImage);
    ASSERT_TRUE(expected);
    for (const ColorStorage storage : {ColorStorage::AsCaptured, ColorStorage::Jpeg}) {
        EncodeOptions options;
        options.color = storage;
        options.compress = false;
        auto payload = FrameEncoder(options).encode(frame);
        ASSERT_TRUE(payload) << payload.error().message;
        EXPECT_NE(std::search(payload->begin(), payload->end(), mjpeg.begin(), mjpeg.end()), payload->end())
            << "the camera's bytes, not a second encoding";
        auto decoded = FrameDecoder().decode(*payload, 0, "mem", 0);
        ASSERT_TRUE(decoded) << decoded.error().message;
        EXPECT_EQ(decoded->capturedImage.format, frame::PixelFormat::Nv12);
        EXPECT_EQ(*decoded->capturedImage.bytes, *expected->bytes);
    }
}

TEST(RgbImage, WholeImageConversionMatchesPixelRgbForEveryFormat) {
    std::vector<std::uint8_t> bytes(frame::CapturedImage::byteSize(frame::PixelFormat::Nv12, 7, 5));
    for (std::size_t i = 0; i < bytes.size(); ++i)
        bytes[i] = static_cast<std::uint8_t>(i * 37 + 11);
    for (const frame::PixelFormat format :
         {frame::PixelFormat::Nv12, frame::PixelFormat::Yuyv, frame::PixelFormat::Rgb24}) {
        auto data = bytes;
        data.resize(frame::CapturedImage::byteSize(format, 7, 5), 99);
        const frame::CapturedImage image{format, 7, 5,
                                         std::make_shared<const std::vector<std::uint8_t>>(data)};
        const std::vector<std::uint8_t> rgb = frame::toRgb24(image);
        ASSERT_EQ(rgb.size(), 7u * 5u * 3u);
        for (int y = 0; y < 5; ++y) {
            for (int x = 0; x < 7; ++x) {
                const frame::Rgb c = frame::pixelRgb(image, x, y);
                const std::uint8_t* p = &rgb[(static_cast<std::size_t>(y) * 7 + x) * 3];
                EXPECT_NEAR(p[0], frame::toByte(c.r), 1) << toString(format) << " " << x << "," << y;
                EXPECT_NEAR(p[1], frame::toByte(c.g), 1) << toString(format) << " " << x << "," << y;
                EXPECT_NEAR(p[2], frame::toByte(c.b), 1) << toString(format) << " " << x << "," << y;
            }
        }
    }
}

TEST(RecordingWriter, RefusesToOverwriteUnlessAskedAndKeepsAnInterruptedRecording) {
    TempDir dir;
    const auto frames = test::syntheticFrames(2);
    test::writeRecording(dir.path("r.dcrec"), frames);
    const auto good = test::readBytes(dir.path("r.dcrec"));
    auto refused = RecordingWriter::create(dir.path("r.dcrec"), {});
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("already exists"), std::string::npos);
    WriterOptions overwrite;
    overwrite.overwrite = true;
    {
        auto writer = RecordingWriter::create(dir.path("r.dcrec"), {}, overwrite);
        ASSERT_TRUE(writer);
        ASSERT_TRUE(writer->append(*frames[0]));
        EXPECT_EQ(test::readBytes(dir.path("r.dcrec")), good)
            << "the old file stays until the new one closes";
        // Dropped without finish(): the state a crash leaves.
    }
    EXPECT_EQ(test::readBytes(dir.path("r.dcrec")), good) << "a failed recording never replaces a good one";
    auto again = RecordingWriter::create(dir.path("r.dcrec"), {}, overwrite);
    ASSERT_FALSE(again) << "the partial file of an interrupted recording is never destroyed";
    EXPECT_NE(again.error().message.find("r.dcrec.partial"), std::string::npos);
}

TEST(RecordingReader, RecoversAnUnclosedRecordingByScanningChunks) {
    TempDir dir;
    const auto frames = test::syntheticFrames(6);
    {
        auto writer = RecordingWriter::create(dir.path("k.dcrec"), {"killed", {.sceneDepth = true}});
        ASSERT_TRUE(writer);
        for (const auto& f : frames)
            ASSERT_TRUE(writer->append(*f));
    }
    auto bytes = test::readBytes(dir.path("k.dcrec.partial"));
    auto whole = RecordingReader::open(dir.path("k.dcrec.partial"));
    ASSERT_TRUE(whole) << whole.error().message;
    EXPECT_FALSE(whole->openedThroughIndex());
    ASSERT_EQ(whole->frameCount(), 6u);
    ASSERT_TRUE(whole->device());
    EXPECT_EQ(whole->device()->description, "killed");
    for (std::size_t i = 0; i < 6; ++i)
        expectSameFrame(*frames[i], *whole->frame(i));

    // Cut in the middle of the last frame's chunk, as a kill during a write leaves it.
    bytes.resize(bytes.size() - 100);
    auto cut = RecordingReader::fromBytes(bytes, "cut.dcrec");
    ASSERT_TRUE(cut);
    EXPECT_EQ(cut->frameCount(), 5u);
    ASSERT_FALSE(cut->warnings().empty());
    const std::string& w = cut->warnings().back();
    EXPECT_NE(w.find("cut.dcrec"), std::string::npos) << w;
    EXPECT_NE(w.find("frame 5"), std::string::npos) << w;
    EXPECT_NE(w.find("byte offset"), std::string::npos) << w;
    EXPECT_TRUE(cut->frame(4));
}

class DamagedRecording : public ::testing::Test {
protected:
    void SetUp() override {
        frames_ = test::syntheticFrames(5);
        test::writeRecording(dir_.path("d.dcrec"), frames_);
        bytes_ = test::readBytes(dir_.path("d.dcrec"));
        for (std::size_t i = 0; i < 5; ++i)
            offsets_.push_back(offsetOf(i));
    }
    // The chunk offset of frame i, from the index the writer put at the end.
    std::uint64_t offsetOf(std::size_t i) const {
        const auto trailer = decodeTrailer({bytes_.data() + bytes_.size() - kTrailerSize, kTrailerSize});
        const auto payload = std::span(bytes_).subspan(trailer->indexOffset + kChunkHeaderSize);
        return (*decodeIndex(payload.first(payload.size() - kTrailerSize)))[i].offset;
    }
    Expected<RecordingReader> open() { return RecordingReader::fromBytes(bytes_, "d.dcrec"); }

    TempDir dir_;
    std::vector<frame::FramePtr> frames_;
    std::vector<std::uint8_t> bytes_;
    std::vector<std::uint64_t> offsets_;
};

TEST_F(DamagedRecording, TruncatedHeaderWrongMagicAndFutureVersionAreClearErrors) {
    auto truncated = RecordingReader::fromBytes(std::span(bytes_).first(20), "t.dcrec");
    ASSERT_FALSE(truncated);
    EXPECT_NE(truncated.error().message.find("t.dcrec: truncated file"), std::string::npos)
        << truncated.error().message;
    EXPECT_NE(truncated.error().message.find("byte offset 20"), std::string::npos);

    auto magic = bytes_;
    magic[0] = 'X';
    auto wrong = RecordingReader::fromBytes(magic, "m.dcrec");
    ASSERT_FALSE(wrong);
    EXPECT_NE(wrong.error().message.find("wrong magic at byte offset 0"), std::string::npos);

    auto future = bytes_;
    future[8] = 2; // version major, little-endian u16 at offset 8
    auto newer = RecordingReader::fromBytes(future, "f.dcrec");
    ASSERT_FALSE(newer);
    EXPECT_NE(newer.error().message.find("newer depthcloud (format version 2." +
                                         std::to_string(kVersionMinor) + ")"),
              std::string::npos)
        << newer.error().message;
}

TEST_F(DamagedRecording, CorruptedChunkFailsItsChecksumAndOnlyThatFrameIsLost) {
    bytes_[offsets_[2] + kChunkHeaderSize + 50] ^= 0x40;
    auto reader = open();
    ASSERT_TRUE(reader);
    EXPECT_EQ(reader->frameCount(), 5u);
    auto bad = reader->frame(2);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("d.dcrec: frame 2"), std::string::npos) << bad.error().message;
    EXPECT_NE(bad.error().message.find("byte offset " + std::to_string(offsets_[2])), std::string::npos);
    EXPECT_NE(bad.error().message.find("checksum"), std::string::npos);
    for (const std::size_t i : {0u, 1u, 3u, 4u})
        EXPECT_TRUE(reader->frame(i)) << i;
}

TEST_F(DamagedRecording, DamagedChunkHeaderIsSkippedByResynchronising) {
    bytes_[offsets_[1] + 4] ^= 0xff; // the chunk type: the header checksum no longer matches
    auto reader = open();
    ASSERT_TRUE(reader);
    EXPECT_EQ(reader->frameCount(), 4u) << "frame 1 is lost, the others are found";
    bool named = false;
    for (const auto& w : reader->warnings())
        named = named || w.find("byte offset " + std::to_string(offsets_[1])) != std::string::npos;
    EXPECT_TRUE(named);
    auto third = reader->frame(1);
    ASSERT_TRUE(third);
    EXPECT_EQ(third->timestampNs, frames_[2]->timestampNs);
}

TEST_F(DamagedRecording, IndexThatDisagreesWithTheChunksIsReportedAndBypassed) {
    // Swap the offsets of index entries 1 and 2 and fix the index checksum: a consistent-looking index
    // that points at the wrong frames.
    const auto trailer = decodeTrailer({bytes_.data() + bytes_.size() - kTrailerSize, kTrailerSize});
    std::vector<IndexEntry> entries;
    for (std::size_t i = 0; i < 5; ++i)
        entries.push_back({offsets_[i], frames_[i]->timestampNs});
    std::swap(entries[1].offset, entries[2].offset);
    const auto payload = encodeIndex(entries);
    std::vector<std::uint8_t> head;
    appendChunkHeader(head, {ChunkType::Index, payload.size(), 0, 0, checksumOf(payload)});
    std::copy(head.begin(), head.end(), bytes_.begin() + static_cast<std::ptrdiff_t>(trailer->indexOffset));
    std::copy(payload.begin(), payload.end(),
              bytes_.begin() + static_cast<std::ptrdiff_t>(trailer->indexOffset + head.size()));
    auto reader = open();
    ASSERT_TRUE(reader);
    EXPECT_FALSE(reader->openedThroughIndex());
    ASSERT_FALSE(reader->warnings().empty());
    EXPECT_NE(reader->warnings()[0].find("disagrees with its chunks: entry 1 points at byte offset " +
                                         std::to_string(offsets_[2])),
              std::string::npos)
        << reader->warnings()[0];
    ASSERT_EQ(reader->frameCount(), 5u) << "nothing lost";
    for (std::size_t i = 0; i < 5; ++i)
        EXPECT_EQ(reader->frame(i)->timestampNs, frames_[i]->timestampNs);
}

TEST(RecordingReader, ZeroFrameRecordingOpensButIsRefusedForReplay) {
    TempDir dir;
    test::writeRecording(dir.path("z.dcrec"), {});
    auto reader = RecordingReader::open(dir.path("z.dcrec"));
    ASSERT_TRUE(reader);
    EXPECT_EQ(reader->frameCount(), 0u);
    auto source = replay::openReplaySource(dir.path("z.dcrec"));
    ASSERT_FALSE(source);
    EXPECT_NE(source.error().message.find("holds no frames"), std::string::npos);
    EXPECT_NE(source.error().message.find("z.dcrec"), std::string::npos);
}

TEST(Recorder, WritesWhatItAcceptsAndCountsWhatItDrops) {
    TempDir dir;
    const auto frames = test::syntheticFrames(4);
    RecorderOptions options;
    options.queueFrames = 2;
    auto recorder = Recorder::start(dir.path("q.dcrec"), {"queue", {}}, options);
    ASSERT_TRUE(recorder);
    int accepted = 0;
    for (int i = 0; i < 200; ++i)
        accepted += (*recorder)->push(frames[static_cast<std::size_t>(i) % frames.size()]) ? 1 : 0;
    ASSERT_TRUE((*recorder)->stop());
    const auto stats = (*recorder)->stats();
    EXPECT_EQ(stats.framesWritten, static_cast<std::uint64_t>(accepted));
    EXPECT_EQ(stats.framesWritten + stats.framesDropped, 200u);
    EXPECT_FALSE((*recorder)->push(frames[0])) << "nothing is accepted after stop";
    auto reader = RecordingReader::open(dir.path("q.dcrec"));
    ASSERT_TRUE(reader);
    EXPECT_EQ(reader->frameCount(), static_cast<std::size_t>(accepted));
}

// An encoder that throws (the seam throws on the third frame) fails the take with the exception's message,
// as a write error does: the frames before it are in the partial file, later pushes are refused, and the
// process goes on.
TEST(Recorder, AnEncoderThatThrowsFailsTheTakeWithItsMessageAndKeepsWhatWasWritten) {
    TempDir dir;
    const auto frames = test::syntheticFrames(6);
    RecorderOptions options;
    options.encoderThreads = 1; // frames are encoded in order, so the two before the fault are written
    options.encodeFault = [](std::uint64_t frame) {
        if (frame == 2)
            throw std::runtime_error("the codec ran out of memory");
    };
    auto recorder = Recorder::start(dir.path("fault.dcrec"), {"fault", {}}, options);
    ASSERT_TRUE(recorder);
    for (int i = 0; i < 3; ++i)
        ASSERT_TRUE((*recorder)->push(frames[static_cast<std::size_t>(i)]));
    for (int i = 0; i < 500 && (*recorder)->stats().error.empty(); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_FALSE((*recorder)->push(frames[3])) << "nothing is accepted after the failure";
    const Status stopped = (*recorder)->stop();
    ASSERT_FALSE(stopped);
    EXPECT_NE(stopped.error().message.find("encoding failed: the codec ran out of memory"), std::string::npos)
        << stopped.error().message;
    EXPECT_EQ((*recorder)->stats().framesWritten, 2u);
    auto partial = RecordingReader::open(dir.path("fault.dcrec.partial"));
    ASSERT_TRUE(partial) << partial.error().message;
    EXPECT_EQ(partial->frameCount(), 2u);
}

// A two-sensor frame keeps its calibration through a recording; a damaged one is refused, never applied.
TEST(RecordingFormat, ARigCalibrationRoundTripsAndABrokenOneIsRefused) {
    frame::RigCalibration rig;
    rig.depth.intrinsics = {446.25, 446.5, 423.5, 239.5, 848, 480};
    rig.colour.intrinsics = {931.5, 931.25, 639.5, 359.5, 1280, 720};
    rig.colour.lens = {frame::LensModel::InverseBrownConrady, {0.1, -0.2, 0.0008, -0.0005, 0.08}};
    rig.depthToColour = {{0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0}, {-0.015, 0.001, 0.002}};
    rig.name = "camchain.yaml (Kalibr camchain)";
    rig.approximate = true;
    frame::Frame frame;
    frame.sceneDepth = frame::DepthData{frame::Plane<float>(4, 3, 1.0f), {}};
    frame.rig = std::make_shared<const frame::RigCalibration>(rig);
    auto payload = FrameEncoder().encode(frame);
    ASSERT_TRUE(payload);
    auto decoded = FrameDecoder().decode(*payload, 0, "mem", 0);
    ASSERT_TRUE(decoded) << decoded.error().message;
    ASSERT_TRUE(decoded->rig);
    EXPECT_EQ(decoded->rig->depth, rig.depth);
    EXPECT_EQ(decoded->rig->colour, rig.colour);
    EXPECT_EQ(decoded->rig->depthToColour, rig.depthToColour);
    EXPECT_EQ(decoded->rig->name, rig.name);
    EXPECT_TRUE(decoded->rig->approximate);

    frame.rig = nullptr;
    auto single = FrameEncoder().encode(frame);
    ASSERT_TRUE(single);
    EXPECT_FALSE(FrameDecoder().decode(*single, 0, "mem", 0)->rig) << "one camera stays one camera";

    // The rotation's first entry, 0.0, made 2.0: no longer a rotation.
    std::vector<std::uint8_t> broken = *payload;
    const std::vector<std::uint8_t> needle = {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xf0, 0xbf}; // -1.0
    const auto at = std::search(broken.begin(), broken.end(), needle.begin(), needle.end());
    ASSERT_NE(at, broken.end());
    const double two = 2.0;
    std::memcpy(&*(at - 8), &two, 8);
    auto refused = FrameDecoder().decode(broken, 0, "mem", 0);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("rig calibration"), std::string::npos) << refused.error().message;
}

// The depth sensor's infrared image survives a recording exactly, 16-bit values included; a reader that
// does not know the section (as a format 1.1 reader does not) skips it and reads the rest of the frame.
TEST(RecordingFormat, AnInfraredImageRoundTripsAndAnUnknownSectionIsSkipped) {
    frame::Frame frame;
    frame.sceneDepth = frame::DepthData{frame::Plane<float>(4, 3, 1.0f), {}};
    frame::Plane<std::uint16_t> infrared(5, 2);
    for (std::size_t i = 0; i < infrared.pixels.size(); ++i)
        infrared.pixels[i] = static_cast<std::uint16_t>(i * 13001 + 7);
    frame.infrared = infrared;
    for (const bool compress : {false, true}) {
        EncodeOptions options;
        options.compress = compress;
        auto payload = FrameEncoder(options).encode(frame);
        ASSERT_TRUE(payload);
        auto decoded = FrameDecoder().decode(*payload, 0, "mem", 0);
        ASSERT_TRUE(decoded) << decoded.error().message;
        ASSERT_TRUE(decoded->infrared);
        EXPECT_EQ(decoded->infrared->width, 5);
        EXPECT_EQ(decoded->infrared->height, 2);
        EXPECT_EQ(decoded->infrared->pixels, infrared.pixels);
    }

    frame.infrared.reset();
    auto without = FrameEncoder().encode(frame);
    ASSERT_TRUE(without);
    EXPECT_FALSE(FrameDecoder().decode(*without, 0, "mem", 0)->infrared) << "no infrared stays none";

    // The infrared section is the last one; its kind byte made 200, a kind no reader knows yet.
    frame.infrared = infrared;
    EncodeOptions raw;
    raw.compress = false;
    auto payload = FrameEncoder(raw).encode(frame);
    ASSERT_TRUE(payload);
    const std::size_t sectionAt = payload->size() - 36 - 2 * infrared.pixels.size();
    ASSERT_EQ((*payload)[sectionAt], 8);
    (*payload)[sectionAt] = 200;
    auto skipped = FrameDecoder().decode(*payload, 0, "mem", 0);
    ASSERT_TRUE(skipped) << skipped.error().message;
    EXPECT_FALSE(skipped->infrared);
    ASSERT_TRUE(skipped->sceneDepth);
    EXPECT_EQ(skipped->sceneDepth->depthMeters.pixels, frame.sceneDepth->depthMeters.pixels);
}

// What the drivers said about each capture (sequence numbers, sensor stamps and their source, for depth
// and colour) comes back from a file exactly, so a replay's Timing panel shows the recording's figures.
TEST(RecordingFormat, FrameTimingRoundTripsExactlyThroughAFile) {
    const auto frames = test::withTiming(test::syntheticFrames(5));
    TempDir dir;
    test::writeRecording(dir.path("t.dcrec"), frames);
    auto reader = RecordingReader::open(dir.path("t.dcrec"));
    ASSERT_TRUE(reader) << reader.error().message;
    EXPECT_EQ(reader->header().versionMinor, kVersionMinor);
    ASSERT_EQ(reader->frameCount(), frames.size());
    for (std::size_t i = 0; i < frames.size(); ++i) {
        auto f = reader->frame(i);
        ASSERT_TRUE(f) << f.error().message;
        SCOPED_TRACE(i);
        ASSERT_TRUE(f->timing.depth.driverSequence);
        test::expectSameTiming(f->timing, frames[i]->timing);
        expectSameFrame(*frames[i], *f);
    }
}

// Format 1.4: the exposure each stream's metadata gave comes back exactly, and a frame without one is stored
// as 1.3 stored it, so a 1.3 reader finds nothing after the colour stream that it would not skip.
TEST(RecordingFormat, ExposuresRoundTripAndAFrameWithoutOneIsStoredAs13StoredIt) {
    frame::Frame f = *test::withTiming(test::syntheticFrames(1)).front();
    ASSERT_TRUE(f.timing.colour);
    const auto without = FrameEncoder().encode(f);
    ASSERT_TRUE(without);
    f.timing.depth.exposureUs = 8500;
    const auto depthOnly = FrameEncoder().encode(f);
    ASSERT_TRUE(depthOnly);
    EXPECT_EQ(depthOnly->size(), without->size() + 5) << "a flags byte and the depth exposure";
    auto decoded = FrameDecoder().decode(*depthOnly, 0, "mem", 0);
    ASSERT_TRUE(decoded) << decoded.error().message;
    test::expectSameTiming(decoded->timing, f.timing);
    ASSERT_TRUE(decoded->timing.colour);
    EXPECT_FALSE(decoded->timing.colour->exposureUs) << "none recorded for colour, none read back";

    f.timing.colour->exposureUs = 16'000;
    f.timing.depth.exposureUs.reset();
    decoded = FrameDecoder().decode(*FrameEncoder().encode(f), 0, "mem", 0);
    ASSERT_TRUE(decoded) << decoded.error().message;
    test::expectSameTiming(decoded->timing, f.timing);
    EXPECT_FALSE(decoded->timing.depth.exposureUs);
}

// The timing section's bytes in a payload of meta and timing only (synthetic frames carry no rig).
std::vector<std::uint8_t> timingSection(const std::vector<std::uint8_t>& payload) {
    std::uint64_t metaSize = 0;
    std::memcpy(&metaSize, payload.data() + 28, 8);
    const std::size_t at = 36 + metaSize;
    EXPECT_EQ(payload[at], 9) << "the timing section follows the meta section";
    std::uint64_t size = 0;
    std::memcpy(&size, payload.data() + at + 28, 8);
    return {payload.begin() + static_cast<std::ptrdiff_t>(at + 36),
            payload.begin() + static_cast<std::ptrdiff_t>(at + 36 + size)};
}

// What a 1.4 reader takes from a timing section, in 1.4's layout (docs/recording-format.md): both streams
// and the exposures; the bytes it leaves are counted in `unread`.
struct Timing14 {
    std::uint32_t depthSequence = 0;
    std::int64_t depthSensorNs = 0;
    std::optional<std::uint32_t> depthExposureUs;
    std::size_t unread = 0;
};

Timing14 readAs14(const std::vector<std::uint8_t>& t) {
    Timing14 out;
    std::size_t at = 0;
    const auto take = [&](auto& value) {
        if (at + sizeof value > t.size())
            throw std::out_of_range("the 1.4 fields run past the section");
        std::memcpy(&value, t.data() + at, sizeof value);
        at += sizeof value;
    };
    const auto stream = [&](std::uint32_t& sequence, std::int64_t& sensorNs) {
        std::uint8_t flags = 0, source = 0;
        take(flags);
        take(sequence);
        take(sensorNs);
        take(source);
    };
    std::uint32_t sequence = 0;
    std::int64_t sensorNs = 0;
    stream(out.depthSequence, out.depthSensorNs);
    std::uint8_t hasColour = 0;
    take(hasColour);
    if (hasColour)
        stream(sequence, sensorNs);
    if (at < t.size()) {
        std::uint8_t exposures = 0;
        take(exposures);
        std::uint32_t exposure = 0;
        if (exposures & 1) {
            take(exposure);
            out.depthExposureUs = exposure;
        }
        if (exposures & 2)
            take(exposure);
    }
    out.unread = t.size() - at;
    return out;
}

// Format 1.5: the depth stream's camera metadata (frame counter, gain, laser power, PTS, SCR and its USB
// frame) comes back exactly, each field only where the camera gave it; a frame without any is stored as 1.4
// stored it, and one with some but no exposure writes the exposures' flags byte (0) first.
TEST(RecordingFormat, CameraMetadataRoundTripsAndAFrameWithoutItIsStoredAs14StoredIt) {
    frame::Frame f = *test::withTiming(test::syntheticFrames(1)).front();
    ASSERT_FALSE(f.timing.depthMetadata.frameCounter || f.timing.depthMetadata.scrUsbFrame);
    f.timing.depth.exposureUs = 8500;
    const auto without = FrameEncoder().encode(f);
    ASSERT_TRUE(without);
    EXPECT_EQ(timingSection(*without).size(), 14u + 1u + 14u + 5u) << "1.4's section: streams, exposure";

    f.timing.depthMetadata = test::fullCameraMetadata(0);
    const auto with = FrameEncoder().encode(f);
    ASSERT_TRUE(with);
    const auto withTiming = timingSection(*with);
    const auto withoutTiming = timingSection(*without);
    ASSERT_EQ(withTiming.size(), withoutTiming.size() + 1 + 5 * 4 + 2) << "field bits, five u32, one u16";
    EXPECT_TRUE(std::equal(withoutTiming.begin(), withoutTiming.end(), withTiming.begin()))
        << "1.4's bytes come first, unchanged";
    EXPECT_EQ(withTiming[withoutTiming.size()], 0x3f) << "every field present";
    auto decoded = FrameDecoder().decode(*with, 0, "mem", 0);
    ASSERT_TRUE(decoded) << decoded.error().message;
    test::expectSameTiming(decoded->timing, f.timing);

    // Some fields only, and no exposure for either stream.
    f.timing.depth.exposureUs.reset();
    f.timing.depthMetadata = {};
    f.timing.depthMetadata.gain = 0; // known to be zero is not unknown
    f.timing.depthMetadata.scrUsbFrame = 0x7ff;
    const auto some = FrameEncoder().encode(f);
    ASSERT_TRUE(some);
    const auto someTiming = timingSection(*some);
    ASSERT_EQ(someTiming.size(), withoutTiming.size() - 4 + 1 + 4 + 2);
    EXPECT_EQ(someTiming[withoutTiming.size() - 4 - 1], 0) << "no exposures, their flags byte still there";
    decoded = FrameDecoder().decode(*some, 0, "mem", 0);
    ASSERT_TRUE(decoded) << decoded.error().message;
    test::expectSameTiming(decoded->timing, f.timing);
    EXPECT_EQ(decoded->timing.depthMetadata.gain, 0u);
    EXPECT_FALSE(decoded->timing.depthMetadata.frameCounter);
}

// A 1.4 reader reads a 1.5 timing section's streams and exposures where they always were and leaves the
// metadata as trailing bytes, which it skips; this reader likewise skips fields a later version appends.
// A section cut inside the metadata is an error naming it; cut before it, a frame without metadata.
TEST(RecordingFormat, OlderReadersSkipTheCameraMetadataAndACutOneIsAnError) {
    frame::Frame f = *test::withTiming(test::syntheticFrames(1)).front();
    f.timing.depth.exposureUs = 8500;
    f.timing.depthMetadata = test::fullCameraMetadata(3);
    frame::Frame bare;
    bare.timing = f.timing;
    const auto payload = FrameEncoder().encode(bare);
    ASSERT_TRUE(payload);
    const auto timing = timingSection(*payload);
    const Timing14 as14 = readAs14(timing);
    EXPECT_EQ(as14.depthSequence, *f.timing.depth.driverSequence);
    EXPECT_EQ(as14.depthSensorNs, f.timing.depth.sensorNs);
    EXPECT_EQ(as14.depthExposureUs, 8500u);
    EXPECT_EQ(as14.unread, 1u + 5 * 4 + 2) << "what a 1.4 reader skips is the metadata, all of it";

    // A later version's field after the metadata, flagged with a bit this build does not know.
    const std::size_t sizeAt = payload->size() - timing.size() - 8;
    const auto withSize = [&](std::vector<std::uint8_t> p, std::uint64_t size) {
        std::memcpy(p.data() + sizeAt, &size, 8);
        return p;
    };
    auto newer = *payload;
    newer[payload->size() - as14.unread] |= 0x40;
    newer.insert(newer.end(), {1, 2, 3, 4, 5, 6, 7});
    auto decoded = FrameDecoder().decode(withSize(newer, timing.size() + 7), 0, "mem", 0);
    ASSERT_TRUE(decoded) << decoded.error().message;
    test::expectSameTiming(decoded->timing, f.timing);

    for (std::size_t cut = 1; cut < as14.unread; ++cut) {
        auto shorter = *payload;
        shorter.resize(payload->size() - cut);
        auto cutShort = FrameDecoder().decode(withSize(shorter, timing.size() - cut), 0, "mem", 0);
        ASSERT_FALSE(cutShort) << cut;
        EXPECT_NE(cutShort.error().message.find("frame timing ends early"), std::string::npos)
            << cutShort.error().message;
    }
    auto shorter = *payload;
    shorter.resize(payload->size() - as14.unread);
    decoded = FrameDecoder().decode(withSize(shorter, timing.size() - as14.unread), 0, "mem", 0);
    ASSERT_TRUE(decoded) << decoded.error().message;
    frame::FrameTiming expected = f.timing;
    expected.depthMetadata = {};
    test::expectSameTiming(decoded->timing, expected);
}

// Format 1.2 had no timing section; such a file (what the 1.2 writer made of these frames, byte for byte)
// still opens, and its frames carry the defaults: nothing known.
TEST(RecordingFormat, AFormat12FileWithoutTimingStillReads) {
    const auto frames = test::syntheticFrames(3);
    TempDir dir;
    test::writeRecording(dir.path("old.dcrec"), frames);
    auto bytes = test::readBytes(dir.path("old.dcrec"));
    bytes[10] = 2; // version minor, little-endian u16 at offset 10
    const std::uint32_t checksum = checksumOf(std::span(bytes).first(kFileHeaderSize - 4));
    std::memcpy(&bytes[kFileHeaderSize - 4], &checksum, 4);
    auto reader = RecordingReader::fromBytes(bytes, "old.dcrec");
    ASSERT_TRUE(reader) << reader.error().message;
    EXPECT_EQ(reader->header().versionMinor, 2);
    ASSERT_EQ(reader->frameCount(), frames.size());
    for (std::size_t i = 0; i < frames.size(); ++i) {
        auto f = reader->frame(i);
        ASSERT_TRUE(f) << f.error().message;
        expectSameFrame(*frames[i], *f);
        test::expectSameTiming(f->timing, frame::FrameTiming{});
    }
}

// A reader that does not know the timing section (1.2 and older) skips it and reads the rest of the frame;
// one cut short is an error naming it, never a read past its end.
TEST(RecordingFormat, TheTimingSectionIsSkippedByOlderReadersAndACutOneIsAnError) {
    frame::Frame frame = *test::withTiming(test::syntheticFrames(1)).front();
    auto payload = FrameEncoder().encode(frame);
    ASSERT_TRUE(payload);
    // Sections: meta (its stored size is the u64 at byte 28 of its header), then timing.
    const auto timingAt = [](const std::vector<std::uint8_t>& p) {
        std::uint64_t metaSize = 0;
        std::memcpy(&metaSize, p.data() + 28, 8);
        return 36 + metaSize;
    };
    ASSERT_EQ((*payload)[timingAt(*payload)], 9);
    auto older = *payload;
    older[timingAt(*payload)] = 200;
    auto skipped = FrameDecoder().decode(older, 0, "mem", 0);
    ASSERT_TRUE(skipped) << skipped.error().message;
    test::expectSameTiming(skipped->timing, frame::FrameTiming{});
    ASSERT_TRUE(skipped->sceneDepth);
    EXPECT_TRUE(test::sameBits(skipped->sceneDepth->depthMeters, frame.sceneDepth->depthMeters));

    // Only meta and timing: the timing section is the payload's end and can be cut at every length.
    frame::Frame bare;
    bare.timing = frame.timing;
    auto full = FrameEncoder().encode(bare);
    ASSERT_TRUE(full);
    const std::size_t at = timingAt(*full);
    ASSERT_EQ((*full)[at], 9);
    std::uint64_t timingSize = 0;
    std::memcpy(&timingSize, full->data() + at + 28, 8);
    ASSERT_EQ(full->size(), at + 36 + timingSize);
    for (std::uint64_t cut = 1; cut <= timingSize; ++cut) {
        auto shorter = *full;
        shorter.resize(full->size() - cut);
        const std::uint64_t size = timingSize - cut;
        std::memcpy(shorter.data() + at + 28, &size, 8);
        auto decoded = FrameDecoder().decode(shorter, 0, "mem", 0);
        ASSERT_FALSE(decoded) << cut;
        EXPECT_NE(decoded.error().message.find("frame timing ends early"), std::string::npos)
            << decoded.error().message;
    }
}

} // namespace
} // namespace dc::devices::recording
