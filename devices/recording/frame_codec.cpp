#include "devices/recording/frame_codec.h"

#include "devices/recording/byte_io.h"
#include "devices/recording/format.h"
#include "frame/camera_model.h"
#include "frame/jpeg_codec.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <zstd.h>

namespace dc::devices::recording {

namespace {

enum class Section : std::uint8_t {
    Meta = 1,
    SceneDepth = 2,
    SceneConfidence = 3,
    SmoothedDepth = 4,
    SmoothedConfidence = 5,
    Color = 6,
    Rig = 7,      // format 1.1: a two-sensor camera's calibration
    Infrared = 8, // format 1.2: the depth sensor's infrared image
    Timing = 9,   // format 1.3: what the drivers said about the capture (frame::FrameTiming); 1.4: exposure;
                  // 1.5: the depth stream's camera metadata
};
enum class Codec : std::uint8_t { Raw = 0, Zstd = 1 };
// Layouts of a section's raw bytes.
constexpr std::uint8_t kDepthFloat32Shuffled = 0; // byte k of every float in plane k: zstd finds the
                                                  // slowly varying sign/exponent bytes together
constexpr std::uint8_t kDepthUint16Scaled = 1;
constexpr std::uint8_t kConfidenceUint8 = 0;
constexpr std::uint8_t kInfraredUint16 = 0; // little-endian raw intensity
constexpr std::uint8_t kColorJpeg = 3;      // 0..2 are PixelFormat values stored as captured
constexpr std::size_t kSectionHeaderSize = 36;
constexpr std::size_t kMaxDescriptionLength = 4096;
// The timing section's per-stream flags.
constexpr std::uint8_t kTimingHasDriverSequence = 1;
constexpr std::uint8_t kTimingMonotonic = 2;
// Format 1.4: which streams' exposures follow the colour stream.
constexpr std::uint8_t kTimingDepthExposure = 1;
constexpr std::uint8_t kTimingColourExposure = 2;
// Format 1.5: which of the depth stream's frame::CameraMetadata fields follow the exposures, each in this
// order: u32 frame counter, u32 gain, u32 laser power, u32 PTS, u32 SCR, u16 SCR USB frame.
constexpr std::uint8_t kMetadataFrameCounter = 1;
constexpr std::uint8_t kMetadataGain = 2;
constexpr std::uint8_t kMetadataLaserPower = 4;
constexpr std::uint8_t kMetadataPts = 8;
constexpr std::uint8_t kMetadataScr = 16;
constexpr std::uint8_t kMetadataScrUsbFrame = 32;

// Metres per unit that importers use: millimetres (Stray, PNG16) and TUM's 1/5000 m.
constexpr double kKnownScales[] = {0.001, 0.0002};

struct SectionHeader {
    Section kind = Section::Meta;
    Codec codec = Codec::Raw;
    std::uint8_t layout = 0;
    std::int32_t width = 0;
    std::int32_t height = 0;
    double scale = 0.0;
    std::uint64_t rawSize = 0;
};

// Byte k of float i goes to plane k (the format is little-endian). Every recorded and replayed depth sample
// passes through these two loops, so this file is built with -O3 (CMakeLists.txt): -O2 leaves them scalar.
void shuffleBytes(const float* __restrict samples, std::size_t n, std::uint8_t* __restrict planes) {
    for (std::size_t i = 0; i < n; ++i) {
        const auto v = std::bit_cast<std::uint32_t>(samples[i]);
        planes[i] = static_cast<std::uint8_t>(v);
        planes[n + i] = static_cast<std::uint8_t>(v >> 8);
        planes[2 * n + i] = static_cast<std::uint8_t>(v >> 16);
        planes[3 * n + i] = static_cast<std::uint8_t>(v >> 24);
    }
}

void unshuffleBytes(const std::uint8_t* __restrict planes, std::size_t n, float* __restrict samples) {
    for (std::size_t i = 0; i < n; ++i)
        samples[i] = std::bit_cast<float>(static_cast<std::uint32_t>(planes[i]) |
                                          static_cast<std::uint32_t>(planes[n + i]) << 8 |
                                          static_cast<std::uint32_t>(planes[2 * n + i]) << 16 |
                                          static_cast<std::uint32_t>(planes[3 * n + i]) << 24);
}

std::uint8_t capabilityBits(const Capabilities& c) {
    return static_cast<std::uint8_t>(c.sceneDepth | c.smoothedSceneDepth << 1 | c.confidence << 2 |
                                     c.color << 3 | c.pose << 4);
}

Capabilities capabilitiesFromBits(std::uint8_t b) {
    return {.sceneDepth = (b & 1) != 0,
            .smoothedSceneDepth = (b & 2) != 0,
            .confidence = (b & 4) != 0,
            .color = (b & 8) != 0,
            .pose = (b & 16) != 0};
}

// The intrinsics as frame metadata and the rig's cameras both store them: fx fy cx cy, width height.
void putIntrinsics(ByteWriter& w, const frame::Intrinsics& k) {
    for (const double v : {k.fx, k.fy, k.cx, k.cy})
        w.put(v);
    w.put(static_cast<std::int32_t>(k.width));
    w.put(static_cast<std::int32_t>(k.height));
}

frame::Intrinsics getIntrinsics(ByteReader& r) {
    frame::Intrinsics k;
    k.fx = r.get<double>();
    k.fy = r.get<double>();
    k.cx = r.get<double>();
    k.cy = r.get<double>();
    k.width = r.get<std::int32_t>();
    k.height = r.get<std::int32_t>();
    return k;
}

} // namespace

const char* toString(ColorStorage storage) {
    return storage == ColorStorage::Jpeg ? "jpeg" : "as captured";
}

std::vector<std::uint8_t> encodeDescription(const DeviceInfo& info) {
    std::vector<std::uint8_t> out;
    ByteWriter w(out);
    w.putString(info.description.substr(0, kMaxDescriptionLength));
    w.put(capabilityBits(info.capabilities));
    return out;
}

std::optional<DeviceInfo> decodeDescription(std::span<const std::uint8_t> payload) {
    ByteReader r(payload, 0);
    DeviceInfo info;
    info.description = r.getString(kMaxDescriptionLength);
    info.capabilities = capabilitiesFromBits(r.get<std::uint8_t>());
    if (!r.ok())
        return std::nullopt;
    return info;
}

std::optional<double> exactUint16Scale(const frame::Plane<float>& depthMeters) {
    for (const double scale : kKnownScales) {
        bool exact = true;
        for (const float v : depthMeters.pixels) {
            if (std::bit_cast<std::uint32_t>(v) == 0)
                continue;
            const double units = std::nearbyint(v / scale);
            if (!(units >= 1.0 && units <= 65535.0) ||
                std::bit_cast<std::uint32_t>(depthFromUnits(static_cast<std::uint16_t>(units), scale)) !=
                    std::bit_cast<std::uint32_t>(v)) {
                exact = false;
                break;
            }
        }
        if (exact && !depthMeters.pixels.empty())
            return scale;
    }
    return std::nullopt;
}

// ---------------------------------------------------------------------------------------------------

struct FrameEncoder::Impl {
    EncodeOptions options;
    std::unique_ptr<ZSTD_CCtx, decltype(&ZSTD_freeCCtx)> cctx{ZSTD_createCCtx(), &ZSTD_freeCCtx};
    frame::JpegEncoder jpegEncoder;
    std::vector<std::uint8_t> scratch;

    void section(std::vector<std::uint8_t>& out, SectionHeader h, std::span<const std::uint8_t> raw,
                 bool compressible);
    void depth(std::vector<std::uint8_t>& out, Section kind, const frame::Plane<float>& plane);
    void plane8(std::vector<std::uint8_t>& out, Section kind, const frame::Plane<std::uint8_t>& plane);
    void infrared(std::vector<std::uint8_t>& out, const frame::Plane<std::uint16_t>& plane);
    Status color(std::vector<std::uint8_t>& out, const frame::CapturedImage& image);
};

void FrameEncoder::Impl::section(std::vector<std::uint8_t>& out, SectionHeader h,
                                 std::span<const std::uint8_t> raw, bool compressible) {
    const bool zstd = compressible && options.compress;
    h.codec = zstd ? Codec::Zstd : Codec::Raw;
    h.rawSize = raw.size();
    const std::size_t sectionStart = out.size();
    ByteWriter w(out);
    w.put(static_cast<std::uint8_t>(h.kind));
    w.put(static_cast<std::uint8_t>(h.codec));
    w.put(h.layout);
    w.put(std::uint8_t{0});
    w.put(h.width);
    w.put(h.height);
    w.put(h.scale);
    w.put(h.rawSize);
    const std::size_t storedSizeAt = out.size();
    w.put(std::uint64_t{0});
    std::size_t stored = raw.size();
    if (zstd) {
        const std::size_t start = out.size();
        out.resize(start + ZSTD_compressBound(raw.size()));
        ZSTD_CCtx_setParameter(cctx.get(), ZSTD_c_compressionLevel, options.zstdLevel);
        stored = ZSTD_compress2(cctx.get(), out.data() + start, out.size() - start, raw.data(), raw.size());
        // compressBound makes failure impossible short of a library bug; store raw bytes then.
        if (ZSTD_isError(stored)) {
            out.resize(start);
            out[sectionStart + 1] = static_cast<std::uint8_t>(Codec::Raw);
            w.putBytes(raw);
            stored = raw.size();
        } else {
            out.resize(start + stored);
        }
    } else {
        w.putBytes(raw);
    }
    std::memcpy(out.data() + storedSizeAt, &stored, sizeof(stored));
}

void FrameEncoder::Impl::depth(std::vector<std::uint8_t>& out, Section kind,
                               const frame::Plane<float>& plane) {
    SectionHeader h{kind, Codec::Raw, kDepthFloat32Shuffled, plane.width, plane.height, 0.0, 0};
    const std::size_t n = plane.pixels.size();
    if (const auto scale = exactUint16Scale(plane)) {
        h.layout = kDepthUint16Scaled;
        h.scale = *scale;
        scratch.resize(2 * n);
        for (std::size_t i = 0; i < n; ++i) {
            const auto units = static_cast<std::uint16_t>(std::nearbyint(plane.pixels[i] / *scale));
            std::memcpy(&scratch[2 * i], &units, 2);
        }
    } else {
        scratch.resize(4 * n);
        shuffleBytes(plane.pixels.data(), n, scratch.data());
    }
    section(out, h, scratch, true);
}

void FrameEncoder::Impl::plane8(std::vector<std::uint8_t>& out, Section kind,
                                const frame::Plane<std::uint8_t>& plane) {
    section(out, {kind, Codec::Raw, kConfidenceUint8, plane.width, plane.height, 0.0, 0}, plane.pixels, true);
}

void FrameEncoder::Impl::infrared(std::vector<std::uint8_t>& out, const frame::Plane<std::uint16_t>& plane) {
    scratch.resize(2 * plane.pixels.size());
    std::memcpy(scratch.data(), plane.pixels.data(),
                scratch.size()); // the format is little-endian, as we are
    section(out, {Section::Infrared, Codec::Raw, kInfraredUint16, plane.width, plane.height, 0.0, 0}, scratch,
            true);
}

Status FrameEncoder::Impl::color(std::vector<std::uint8_t>& out, const frame::CapturedImage& image) {
    if (!image.raw()) {
        // The camera's own JPEG (MJPEG) is stored as it came, whatever the storage asked: encoding it
        // again would cost time and quality.
        section(out, {Section::Color, Codec::Raw, kColorJpeg, image.width, image.height, 0.0, 0},
                *image.bytes, false);
        return {};
    }
    if (image.bytes->size() != frame::CapturedImage::byteSize(image.format, image.width, image.height))
        return Error{"camera image holds " + std::to_string(image.bytes->size()) + " bytes, " +
                     toString(image.format) + " " + std::to_string(image.width) + "x" +
                     std::to_string(image.height) + " needs " +
                     std::to_string(frame::CapturedImage::byteSize(image.format, image.width, image.height))};
    if (options.color == ColorStorage::AsCaptured) {
        section(out,
                {Section::Color, Codec::Raw, static_cast<std::uint8_t>(image.format), image.width,
                 image.height, 0.0, 0},
                *image.bytes, true);
        return {};
    }
    const auto jpeg = jpegEncoder.encode(image, options.jpegQuality);
    if (!jpeg)
        return jpeg.error();
    section(out, {Section::Color, Codec::Raw, kColorJpeg, image.width, image.height, 0.0, 0}, *jpeg, false);
    return {};
}

FrameEncoder::FrameEncoder(EncodeOptions options) : impl_(std::make_unique<Impl>()) {
    impl_->options = options;
}
FrameEncoder::~FrameEncoder() = default;
FrameEncoder::FrameEncoder(FrameEncoder&&) noexcept = default;
FrameEncoder& FrameEncoder::operator=(FrameEncoder&&) noexcept = default;

namespace {

void putCamera(ByteWriter& w, const frame::CameraModel& camera) {
    putIntrinsics(w, camera.intrinsics);
    w.put(static_cast<std::uint8_t>(camera.lens.model));
    for (const double c : camera.lens.coefficients)
        w.put(c);
}

std::vector<std::uint8_t> rigBytes(const frame::RigCalibration& rig) {
    std::vector<std::uint8_t> bytes;
    ByteWriter w(bytes);
    putCamera(w, rig.depth);
    putCamera(w, rig.colour);
    for (const double v : rig.depthToColour.rotation)
        w.put(v);
    for (const double v : rig.depthToColour.translationMeters)
        w.put(v);
    w.put(static_cast<std::uint8_t>(rig.approximate));
    w.putString(rig.name.substr(0, kMaxDescriptionLength));
    return bytes;
}

std::uint8_t metadataBits(const frame::CameraMetadata& m) {
    return static_cast<std::uint8_t>(
        (m.frameCounter ? kMetadataFrameCounter : 0) | (m.gain ? kMetadataGain : 0) |
        (m.laserPowerMw ? kMetadataLaserPower : 0) | (m.ptsTicks ? kMetadataPts : 0) |
        (m.scrTicks ? kMetadataScr : 0) | (m.scrUsbFrame ? kMetadataScrUsbFrame : 0));
}

// Sources that say nothing about timing (synthetic scenes, importers) get no section: their recordings
// stay as small as before and read back with the defaults.
bool hasTiming(const frame::FrameTiming& t) {
    return t.colour || t.depth.driverSequence || t.depth.sensorNs != 0 ||
           t.depth.source != frame::TimestampSource::Unknown || t.depth.monotonic || t.depth.exposureUs ||
           metadataBits(t.depthMetadata) != 0;
}

void putStreamTiming(ByteWriter& w, const frame::StreamTiming& t) {
    w.put(static_cast<std::uint8_t>((t.driverSequence ? kTimingHasDriverSequence : 0) |
                                    (t.monotonic ? kTimingMonotonic : 0)));
    w.put(t.driverSequence.value_or(0));
    w.put(t.sensorNs);
    w.put(static_cast<std::uint8_t>(t.source));
}

std::vector<std::uint8_t> timingBytes(const frame::FrameTiming& timing) {
    std::vector<std::uint8_t> bytes;
    ByteWriter w(bytes);
    putStreamTiming(w, timing.depth);
    w.put(static_cast<std::uint8_t>(timing.colour.has_value()));
    if (timing.colour)
        putStreamTiming(w, *timing.colour);
    // Format 1.4's exposures, only where a stream has one (or camera metadata follows): a 1.3 reader skips
    // them, and a frame without any is stored as 1.3 stored it.
    const std::optional<std::uint32_t> colour = timing.colour ? timing.colour->exposureUs : std::nullopt;
    const std::uint8_t metadata = metadataBits(timing.depthMetadata);
    if (timing.depth.exposureUs || colour || metadata != 0) {
        w.put(static_cast<std::uint8_t>((timing.depth.exposureUs ? kTimingDepthExposure : 0) |
                                        (colour ? kTimingColourExposure : 0)));
        for (const std::optional<std::uint32_t>& exposure : {timing.depth.exposureUs, colour})
            if (exposure)
                w.put(*exposure);
    }
    // Format 1.5's camera metadata, only where the depth stream has some: the exposures' flags byte (0 when
    // there are none) comes first, so a 1.4 reader reads what it knows and skips these.
    if (metadata != 0) {
        const frame::CameraMetadata& m = timing.depthMetadata;
        w.put(metadata);
        for (const std::optional<std::uint32_t>& field :
             {m.frameCounter, m.gain, m.laserPowerMw, m.ptsTicks, m.scrTicks})
            if (field)
                w.put(*field);
        if (m.scrUsbFrame)
            w.put(*m.scrUsbFrame);
    }
    return bytes;
}

} // namespace

Expected<std::vector<std::uint8_t>> FrameEncoder::encode(const frame::Frame& frame) {
    std::vector<std::uint8_t> out;
    std::vector<std::uint8_t> meta;
    ByteWriter m(meta);
    m.put(frame.sequence);
    putIntrinsics(m, frame.cameraIntrinsics);
    m.put(static_cast<std::uint8_t>(frame.pose.has_value()));
    if (frame.pose)
        for (const double v : frame.pose->cameraToWorld)
            m.put(v);
    impl_->section(out, {Section::Meta, Codec::Raw, 0, 0, 0, 0.0, 0}, meta, false);
    if (frame.rig)
        impl_->section(out, {Section::Rig, Codec::Raw, 0, 0, 0, 0.0, 0}, rigBytes(*frame.rig), false);
    if (hasTiming(frame.timing))
        impl_->section(out, {Section::Timing, Codec::Raw, 0, 0, 0, 0.0, 0}, timingBytes(frame.timing), false);
    if (frame.sceneDepth) {
        impl_->depth(out, Section::SceneDepth, frame.sceneDepth->depthMeters);
        if (!frame.sceneDepth->confidence.empty())
            impl_->plane8(out, Section::SceneConfidence, frame.sceneDepth->confidence);
    }
    if (frame.smoothedSceneDepth) {
        impl_->depth(out, Section::SmoothedDepth, frame.smoothedSceneDepth->depthMeters);
        if (!frame.smoothedSceneDepth->confidence.empty())
            impl_->plane8(out, Section::SmoothedConfidence, frame.smoothedSceneDepth->confidence);
    }
    if (!frame.capturedImage.empty()) {
        if (Status s = impl_->color(out, frame.capturedImage); !s)
            return s.error();
    }
    if (frame.infrared && !frame.infrared->empty())
        impl_->infrared(out, *frame.infrared);
    return out;
}

// ---------------------------------------------------------------------------------------------------

struct FrameDecoder::Impl {
    std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> dctx{ZSTD_createDCtx(), &ZSTD_freeDCtx};
    frame::JpegDecoder jpegDecoder;
    std::vector<std::uint8_t> scratch;
    std::string where; // "FILE: frame N"

    Error error(const std::string& what, std::uint64_t offset) const {
        return Error{where + ": " + what + " (byte offset " + std::to_string(offset) + ")"};
    }
    Status unpack(const SectionHeader& h, std::span<const std::uint8_t> stored, std::uint64_t offset);
    Status decodeMeta(ByteReader r, frame::Frame& frame);
    Status decodeRig(ByteReader r, frame::Frame& frame);
    Status decodeTiming(ByteReader r, frame::Frame& frame);
    Expected<frame::Plane<float>> decodeDepth(const SectionHeader& h, std::uint64_t offset);
    Expected<frame::Plane<std::uint8_t>> decodePlane8(const SectionHeader& h, std::uint64_t offset);
    Expected<frame::CapturedImage> decodeColor(const SectionHeader& h, std::uint64_t offset);
    Expected<frame::Plane<std::uint16_t>> decodeInfrared(const SectionHeader& h, std::uint64_t offset);
    Status apply(const SectionHeader& h, std::span<const std::uint8_t> stored, std::uint64_t offset,
                 frame::Frame& frame);
};

// Leaves the section's raw bytes in `scratch`.
Status FrameDecoder::Impl::unpack(const SectionHeader& h, std::span<const std::uint8_t> stored,
                                  std::uint64_t offset) {
    if (h.codec == Codec::Raw) {
        if (stored.size() != h.rawSize)
            return error("raw section of " + std::to_string(stored.size()) + " bytes, expected " +
                             std::to_string(h.rawSize),
                         offset);
        scratch.assign(stored.begin(), stored.end());
        return {};
    }
    if (h.codec != Codec::Zstd)
        return error("unknown compression " + std::to_string(static_cast<int>(h.codec)), offset);
    const unsigned long long content = ZSTD_getFrameContentSize(stored.data(), stored.size());
    if (content != h.rawSize)
        return error("compressed section does not hold the " + std::to_string(h.rawSize) +
                         " bytes it declares",
                     offset);
    scratch.resize(h.rawSize);
    const std::size_t n =
        ZSTD_decompressDCtx(dctx.get(), scratch.data(), scratch.size(), stored.data(), stored.size());
    if (ZSTD_isError(n) || n != h.rawSize)
        return error(std::string("cannot decompress section: ") +
                         (ZSTD_isError(n) ? ZSTD_getErrorName(n) : "short output"),
                     offset);
    return {};
}

Status FrameDecoder::Impl::decodeMeta(ByteReader r, frame::Frame& frame) {
    frame.sequence = r.get<std::uint64_t>();
    frame.cameraIntrinsics = getIntrinsics(r);
    if (r.get<std::uint8_t>() != 0) {
        frame::Pose pose;
        for (double& v : pose.cameraToWorld)
            v = r.get<double>();
        frame.pose = pose;
    }
    if (!r.ok())
        return error("frame metadata ends early", r.offset());
    return {};
}

namespace {

frame::CameraModel getCamera(ByteReader& r) {
    frame::CameraModel camera;
    camera.intrinsics = getIntrinsics(r);
    const auto model = r.get<std::uint8_t>();
    camera.lens.model = model <= static_cast<std::uint8_t>(frame::LensModel::InverseBrownConrady)
                            ? static_cast<frame::LensModel>(model)
                            : frame::LensModel::None;
    for (double& c : camera.lens.coefficients)
        c = r.get<double>();
    // An unknown lens model cannot be applied: the camera is refused rather than drawn undistorted.
    if (model > static_cast<std::uint8_t>(frame::LensModel::InverseBrownConrady))
        camera.intrinsics.fx = 0.0;
    return camera;
}

bool usable(const frame::CameraModel& camera) {
    return camera.intrinsics.valid() &&
           std::all_of(camera.lens.coefficients.begin(), camera.lens.coefficients.end(),
                       [](double c) { return std::isfinite(c); });
}

} // namespace

// The same checks as a calibration file gets: a recording is input too.
Status FrameDecoder::Impl::decodeRig(ByteReader r, frame::Frame& frame) {
    frame::RigCalibration rig;
    rig.depth = getCamera(r);
    rig.colour = getCamera(r);
    for (double& v : rig.depthToColour.rotation)
        v = r.get<double>();
    for (double& v : rig.depthToColour.translationMeters)
        v = r.get<double>();
    rig.approximate = r.get<std::uint8_t>() != 0;
    rig.name = r.getString(kMaxDescriptionLength);
    if (!r.ok())
        return error("rig calibration ends early", r.offset());
    const auto& t = rig.depthToColour.translationMeters;
    if (!usable(rig.depth) || !usable(rig.colour) ||
        !(frame::rotationError(rig.depthToColour.rotation) < 1e-4) || !std::isfinite(t[0] + t[1] + t[2]))
        return error("rig calibration out of range", r.offset());
    frame.rig = std::make_shared<const frame::RigCalibration>(std::move(rig));
    return {};
}

namespace {

frame::StreamTiming getStreamTiming(ByteReader& r) {
    frame::StreamTiming t;
    const auto flags = r.get<std::uint8_t>();
    const auto sequence = r.get<std::uint32_t>();
    if (flags & kTimingHasDriverSequence)
        t.driverSequence = sequence;
    t.monotonic = (flags & kTimingMonotonic) != 0;
    t.sensorNs = r.get<std::int64_t>();
    // A source a newer version defines is one this build cannot name.
    const auto source = r.get<std::uint8_t>();
    t.source = source <= static_cast<std::uint8_t>(frame::TimestampSource::Arrival)
                   ? static_cast<frame::TimestampSource>(source)
                   : frame::TimestampSource::Unknown;
    return t;
}

std::optional<std::uint32_t> getIf(ByteReader& r, std::uint8_t flags, std::uint8_t flag) {
    if (!(flags & flag))
        return std::nullopt;
    return r.get<std::uint32_t>();
}

// Bits a newer minor version defines name fields written after these: skipped with the rest.
frame::CameraMetadata getCameraMetadata(ByteReader& r) {
    frame::CameraMetadata m;
    const auto fields = r.get<std::uint8_t>();
    m.frameCounter = getIf(r, fields, kMetadataFrameCounter);
    m.gain = getIf(r, fields, kMetadataGain);
    m.laserPowerMw = getIf(r, fields, kMetadataLaserPower);
    m.ptsTicks = getIf(r, fields, kMetadataPts);
    m.scrTicks = getIf(r, fields, kMetadataScr);
    if (fields & kMetadataScrUsbFrame)
        m.scrUsbFrame = r.get<std::uint16_t>();
    return m;
}

} // namespace

// Bytes after the 1.5 camera metadata are fields a newer minor version added: skipped, as in the meta
// section.
Status FrameDecoder::Impl::decodeTiming(ByteReader r, frame::Frame& frame) {
    frame::FrameTiming timing;
    timing.depth = getStreamTiming(r);
    if (r.get<std::uint8_t>() != 0)
        timing.colour = getStreamTiming(r);
    if (r.ok() && r.remaining() > 0) {
        const auto exposures = r.get<std::uint8_t>();
        timing.depth.exposureUs = getIf(r, exposures, kTimingDepthExposure);
        // Read even without a colour stream, as the layout says, so the fields after it stay in place.
        const std::optional<std::uint32_t> colour = getIf(r, exposures, kTimingColourExposure);
        if (timing.colour)
            timing.colour->exposureUs = colour;
    }
    if (r.ok() && r.remaining() > 0)
        timing.depthMetadata = getCameraMetadata(r);
    if (!r.ok())
        return error("frame timing ends early", r.offset());
    frame.timing = timing;
    return {};
}

Expected<frame::Plane<float>> FrameDecoder::Impl::decodeDepth(const SectionHeader& h, std::uint64_t offset) {
    frame::Plane<float> plane(h.width, h.height);
    const std::size_t n = plane.pixels.size();
    if (h.layout == kDepthUint16Scaled && std::isfinite(h.scale) && h.scale > 0.0 &&
        scratch.size() == 2 * n) {
        for (std::size_t i = 0; i < n; ++i) {
            std::uint16_t units;
            std::memcpy(&units, &scratch[2 * i], 2);
            plane.pixels[i] = units == 0 ? 0.0f : depthFromUnits(units, h.scale);
        }
        return plane;
    }
    if (h.layout == kDepthFloat32Shuffled && scratch.size() == 4 * n) {
        unshuffleBytes(scratch.data(), n, plane.pixels.data());
        return plane;
    }
    return error("depth section with unknown layout " + std::to_string(h.layout) + " or wrong size", offset);
}

Expected<frame::Plane<std::uint8_t>> FrameDecoder::Impl::decodePlane8(const SectionHeader& h,
                                                                      std::uint64_t offset) {
    frame::Plane<std::uint8_t> plane(h.width, h.height);
    if (h.layout != kConfidenceUint8 || scratch.size() != plane.pixels.size())
        return error("confidence section with unknown layout or wrong size", offset);
    plane.pixels = scratch;
    return plane;
}

Expected<frame::CapturedImage> FrameDecoder::Impl::decodeColor(const SectionHeader& h, std::uint64_t offset) {
    if (h.layout == kColorJpeg) {
        auto image = jpegDecoder.decode(scratch, h.width, h.height);
        if (!image)
            return error(image.error().message, offset);
        return image;
    }
    if (h.layout > static_cast<std::uint8_t>(frame::PixelFormat::Rgb24))
        return error("camera image in unknown format " + std::to_string(h.layout), offset);
    const auto format = static_cast<frame::PixelFormat>(h.layout);
    if (scratch.size() != frame::CapturedImage::byteSize(format, h.width, h.height))
        return error("camera image of the wrong size", offset);
    return frame::CapturedImage{format, h.width, h.height,
                                std::make_shared<const std::vector<std::uint8_t>>(scratch)};
}

Expected<frame::Plane<std::uint16_t>> FrameDecoder::Impl::decodeInfrared(const SectionHeader& h,
                                                                         std::uint64_t offset) {
    frame::Plane<std::uint16_t> plane(h.width, h.height);
    if (h.layout != kInfraredUint16 || scratch.size() != 2 * plane.pixels.size())
        return error("infrared section with unknown layout or wrong size", offset);
    std::memcpy(plane.pixels.data(), scratch.data(), scratch.size());
    return plane;
}

Status FrameDecoder::Impl::apply(const SectionHeader& h, std::span<const std::uint8_t> stored,
                                 std::uint64_t offset, frame::Frame& frame) {
    if (h.kind == Section::Meta)
        return decodeMeta(ByteReader(stored, offset), frame);
    if (h.kind == Section::Rig)
        return decodeRig(ByteReader(stored, offset), frame);
    if (h.kind == Section::Timing)
        return decodeTiming(ByteReader(stored, offset), frame);
    if ((h.kind < Section::SceneDepth || h.kind > Section::Color) && h.kind != Section::Infrared)
        return {}; // a section a newer minor version added: skipped
    if (h.width <= 0 || h.height <= 0 || h.width > kMaxImageSide || h.height > kMaxImageSide ||
        static_cast<std::uint64_t>(h.width) * static_cast<std::uint64_t>(h.height) > kMaxImagePixels)
        return error("image size " + std::to_string(h.width) + "x" + std::to_string(h.height) +
                         " out of range",
                     offset);
    if (h.rawSize > 4 * kMaxImagePixels)
        return error("section too large", offset);
    if (Status s = unpack(h, stored, offset); !s)
        return s;
    const bool smoothed = h.kind == Section::SmoothedDepth || h.kind == Section::SmoothedConfidence;
    std::optional<frame::DepthData>& target = smoothed ? frame.smoothedSceneDepth : frame.sceneDepth;
    if (h.kind == Section::SceneDepth || h.kind == Section::SmoothedDepth) {
        auto plane = decodeDepth(h, offset);
        if (!plane)
            return plane.error();
        target = frame::DepthData{std::move(*plane), {}};
    } else if (h.kind == Section::SceneConfidence || h.kind == Section::SmoothedConfidence) {
        auto plane = decodePlane8(h, offset);
        if (!plane)
            return plane.error();
        if (!target || target->depthMeters.width != h.width || target->depthMeters.height != h.height)
            return error("confidence without a depth map of its size", offset);
        target->confidence = std::move(*plane);
    } else if (h.kind == Section::Infrared) {
        auto plane = decodeInfrared(h, offset);
        if (!plane)
            return plane.error();
        frame.infrared = std::move(*plane);
    } else {
        auto image = decodeColor(h, offset);
        if (!image)
            return image.error();
        frame.capturedImage = std::move(*image);
    }
    return {};
}

FrameDecoder::FrameDecoder() : impl_(std::make_unique<Impl>()) {}
FrameDecoder::~FrameDecoder() = default;
FrameDecoder::FrameDecoder(FrameDecoder&&) noexcept = default;
FrameDecoder& FrameDecoder::operator=(FrameDecoder&&) noexcept = default;

Expected<frame::Frame> FrameDecoder::decode(std::span<const std::uint8_t> payload,
                                            std::uint64_t payloadOffset, const std::string& file,
                                            std::uint64_t frameIndex) {
    impl_->where = file + ": frame " + std::to_string(frameIndex);
    frame::Frame frame;
    ByteReader r(payload, payloadOffset);
    bool sawMeta = false;
    while (r.remaining() > 0) {
        const std::uint64_t at = r.offset();
        SectionHeader h;
        h.kind = static_cast<Section>(r.get<std::uint8_t>());
        h.codec = static_cast<Codec>(r.get<std::uint8_t>());
        h.layout = r.get<std::uint8_t>();
        (void)r.get<std::uint8_t>();
        h.width = r.get<std::int32_t>();
        h.height = r.get<std::int32_t>();
        h.scale = r.get<double>();
        h.rawSize = r.get<std::uint64_t>();
        const auto storedSize = r.get<std::uint64_t>();
        if (!r.ok() || storedSize > r.remaining())
            return impl_->error("section overruns its chunk", at);
        const auto stored = r.getBytes(static_cast<std::size_t>(storedSize));
        if (Status s = impl_->apply(h, stored, at + kSectionHeaderSize, frame); !s)
            return s.error();
        sawMeta = sawMeta || h.kind == Section::Meta;
    }
    if (!sawMeta)
        return impl_->error("frame without metadata", payloadOffset);
    return frame;
}

} // namespace dc::devices::recording
