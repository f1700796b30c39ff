#include "exporting/export.h"

#include "base/files.h"

#include "base/log.h"
#include "exporting/mcap_export.h"
#include "exporting/ply.h"
#include "exporting/stray_writer.h"
#include "frame/image_io.h"
#include "processing/point_cloud.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <filesystem>

namespace dc::exporting {

namespace {

std::string numberedName(std::size_t i, const char* extension) {
    char name[32];
    std::snprintf(name, sizeof(name), "%06zu.%s", i, extension);
    return name;
}

bool parseIndex(const std::string& text, std::size_t& out) {
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
    return ec == std::errc() && ptr == text.data() + text.size() && !text.empty();
}

// The points of a frame, through its pose when world coordinates are asked for.
std::vector<processing::CloudPoint> framePoints(const frame::Frame& frame, bool world) {
    auto points = processing::buildPointCloud(frame, frame::Confidence::Low, 0.0f);
    if (!world || !frame.pose)
        return points;
    const auto& m = frame.pose->cameraToWorld;
    for (processing::CloudPoint& p : points) {
        const double x = p.x, y = p.y, z = p.z;
        p.x = static_cast<float>(m[0] * x + m[4] * y + m[8] * z + m[12]);
        p.y = static_cast<float>(m[1] * x + m[5] * y + m[9] * z + m[13]);
        p.z = static_cast<float>(m[2] * x + m[6] * y + m[10] * z + m[14]);
    }
    return points;
}

Status writePlyFrame(const frame::Frame& frame, std::size_t index, const ExportOptions& options) {
    const bool world = options.worldCoordinates && frame.pose;
    const std::vector<std::string> comments = {
        "depthcloud export: frame " + std::to_string(index) + ", timestamp " +
            std::to_string(frame.timestampNs) + " ns",
        world ? "world coordinates (camera-to-world pose applied), meters"
              : "camera coordinates, OpenCV axes (x right, y down, z forward), meters",
        "confidence: 0 low, 1 medium, 2 high"};
    const auto bytes = encodePly(framePoints(frame, world), comments);
    return base::writeFileAtomically(options.outDirectory + "/" + numberedName(index, "ply"), bytes);
}

std::vector<processing::CloudPoint> worldPoints(const frame::Frame& frame,
                                                const frame::RigidTransform& cameraToWorld) {
    auto points = processing::buildPointCloud(frame, frame::Confidence::Low, 0.0f);
    for (processing::CloudPoint& p : points) {
        const auto w = cameraToWorld.apply({p.x, p.y, p.z});
        p.x = static_cast<float>(w[0]);
        p.y = static_cast<float>(w[1]);
        p.z = static_cast<float>(w[2]);
    }
    return points;
}

// The mean frame rate over the range, for the Stray video (30 when it cannot be told).
double meanFps(const devices::replay::ReplaySource& source, const FrameRange& range) {
    if (range.end - range.first < 2)
        return 30.0;
    const double seconds =
        static_cast<double>(source.timestampNs(range.end - 1) - source.timestampNs(range.first)) * 1e-9;
    const double fps = seconds > 0.0 ? static_cast<double>(range.end - range.first - 1) / seconds : 30.0;
    return std::clamp(fps, 1.0, 240.0);
}

// Where the directory formats write, made when missing; for MCAP the file's directory.
Status createDestination(const ExportOptions& options) {
    const std::string directory = options.format == ExportFormat::Mcap
                                      ? std::filesystem::path(options.outDirectory).parent_path().string()
                                  : options.format == ExportFormat::Png16 ? options.outDirectory + "/depth"
                                                                          : options.outDirectory;
    std::error_code ec;
    if (!directory.empty())
        std::filesystem::create_directories(directory, ec);
    if (ec)
        return Error{"cannot create " + directory + ": " + ec.message()};
    return {};
}

// The writers of the formats that gather frames into one output.
struct Writers {
    StrayWriter stray;
    std::unique_ptr<McapFrameWriter> mcap;
};

Status writeFrame(const frame::Frame& frame, std::size_t index, const ExportOptions& options,
                  Writers& writers) {
    switch (options.format) {
    case ExportFormat::Ply:
        return writePlyFrame(frame, index, options);
    case ExportFormat::Stray:
        return writers.stray.add(frame);
    case ExportFormat::Png16:
        return writeDepthPng16(options.outDirectory + "/depth/" + numberedName(index, "png"),
                               frame.sceneDepth->depthMeters);
    case ExportFormat::Mcap:
        return writers.mcap->add(frame);
    }
    return Error{"unknown export format"};
}

} // namespace

const char* toString(ExportFormat format) {
    switch (format) {
    case ExportFormat::Ply:
        return "ply";
    case ExportFormat::Stray:
        return "stray";
    case ExportFormat::Png16:
        return "png16";
    case ExportFormat::Mcap:
        return "mcap";
    }
    return "unknown";
}

Expected<FrameRange> parseFrameRange(const std::string& text, std::size_t count) {
    const auto colon = text.find(':');
    const Error bad{"frame range '" + text + "' is not A:B, A: or :B (B excluded)"};
    if (colon == std::string::npos)
        return bad;
    FrameRange range{0, count};
    const std::string a = text.substr(0, colon), b = text.substr(colon + 1);
    if ((!a.empty() && !parseIndex(a, range.first)) || (!b.empty() && !parseIndex(b, range.end)))
        return bad;
    if (range.end > count)
        return Error{"frame range '" + text + "' ends after the last frame (the source has " +
                     std::to_string(count) + " frames)"};
    if (range.first >= range.end)
        return Error{"frame range '" + text + "' is empty"};
    return range;
}

Expected<FrameRange> framesWithin(const FrameRange& requested, std::size_t count) {
    FrameRange range = requested;
    if (range.end == 0)
        range.end = count;
    if (range.first >= range.end || range.end > count)
        return Error{"frames " + std::to_string(range.first) + ":" + std::to_string(range.end) +
                     " are not within the source's " + std::to_string(count) + " frames"};
    return range;
}

Status writeFusedPly(const std::vector<PlacedFrame>& parts, const std::string& directory) {
    if (parts.empty())
        return Error{"a fused PLY needs at least one source"};
    const PlacedFrame& first = parts.front();
    std::vector<std::string> comments{
        "depthcloud export: frame " + std::to_string(first.index) + ", timestamp " +
            std::to_string(first.frame->timestampNs) + " ns",
        "depthcloud: several sources fused in the world frame, source after source",
        "world coordinates (each source's camera-to-world placement applied), meters",
        "confidence: 0 low, 1 medium, 2 high"};
    std::vector<processing::CloudPoint> points;
    for (const PlacedFrame& part : parts) {
        auto own = worldPoints(*part.frame, part.cameraToWorld);
        comments.push_back(std::to_string(own.size()) + " points of " + part.name);
        comments.push_back("frame " + std::to_string(part.index) + " of " + part.name + ", timestamp " +
                           std::to_string(part.frame->timestampNs) + " ns");
        points.insert(points.end(), own.begin(), own.end());
    }
    return base::writeFileAtomically(directory + "/" + numberedName(first.index, "ply"),
                                     encodePly(points, comments));
}

Expected<ExportResult> exportFrames(devices::replay::ReplaySource& source, const ExportOptions& options,
                                    const ExportProgress& progress) {
    const auto within = framesWithin(options.frames, source.frameCount());
    if (!within)
        return within.error();
    const FrameRange range = *within;
    if (Status s = createDestination(options); !s)
        return s.error();
    // Processing may need the colour even for depth-only output (upsampling is guided by it).
    source.setDecodeColor(options.format != ExportFormat::Png16 || options.transform);
    Writers writers{StrayWriter(options.outDirectory, meanFps(source, range)), nullptr};
    if (options.format == ExportFormat::Mcap) {
        auto mcap = McapFrameWriter::create(options.outDirectory, options.overwrite);
        if (!mcap)
            return mcap.error();
        writers.mcap = std::move(*mcap);
    }
    ExportResult result;
    const std::size_t total = range.end - range.first;
    for (std::size_t i = range.first; i < range.end; ++i) {
        auto frame = devices::replay::loadFrame(source, i);
        if (frame && options.transform)
            *frame = options.transform(std::move(*frame));
        if (!frame || !frame->sceneDepth) {
            logWarning("export: skipping frame " + std::to_string(i) + ": " +
                       (frame ? std::string("it has no depth") : frame.error().message));
            ++result.framesSkipped;
        } else {
            const std::size_t out = options.format == ExportFormat::Stray ? result.framesWritten : i;
            if (Status s = writeFrame(*frame, out, options, writers); !s)
                return s.error();
            ++result.framesWritten;
        }
        if (progress && !progress(i - range.first + 1, total))
            return Error{"export cancelled after " + std::to_string(result.framesWritten) + " frames"};
    }
    Status finished = options.format == ExportFormat::Stray ? writers.stray.finish()
                      : writers.mcap                        ? writers.mcap->finish()
                                                            : Status{};
    if (!finished)
        return finished.error();
    return result;
}

} // namespace dc::exporting
