#pragma once

#include "base/expected.h"
#include "devices/device.h"
#include "frame/frame.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace dc::devices::replay {

// Random access to a finished capture: our recordings and the formats other tools write. Every
// importer sits behind this interface, so the replay device, export and the benchmarks treat them alike.
// Not thread-safe: one thread decodes.
class ReplaySource {
public:
    virtual ~ReplaySource() = default;

    virtual std::string description() const = 0;
    // What the capture holds (a capture without confidence says so here).
    virtual Capabilities capabilities() const = 0;
    virtual std::size_t frameCount() const = 0;
    // Cheap: from the index or the file lists, without decoding.
    virtual std::int64_t timestampNs(std::size_t i) const = 0;
    // Decodes frame i (< frameCount()) with its recorded timestamp. Errors name file, frame and offset.
    virtual Expected<frame::Frame> frame(std::size_t i) = 0;
    // Problems found at open that did not prevent it (a recovered recording, skipped list entries).
    virtual std::vector<std::string> warnings() const { return {}; }
    // Consumers that show no color (depth export, depth-only benchmarks) skip its decoding, often the
    // most expensive part (a video).
    virtual void setDecodeColor(bool) {}

    // The frame on screen at time `ns`: the last one whose timestamp is not after it (the first frame
    // before the capture starts). Timestamps are non-decreasing in every source.
    std::size_t indexAtTime(std::int64_t ns) const;
    // The rate the capture was recorded at (frames per second of its timestamps); 0 for fewer than two
    // frames or a zero duration. Capabilities::nominalFps of the sources, at speed 1.
    double recordedFps() const;

protected:
    ReplaySource() = default;
};

// Frame i made safe to use: NaN, infinite and negative depth becomes 0 (no measurement) and confidence
// above High becomes High, with a warning that counts them.
Expected<frame::Frame> loadFrame(ReplaySource& source, std::size_t i);

// NaN, infinite and negative samples set to 0; returns how many.
std::size_t sanitizeDepth(frame::Plane<float>& depthMeters);

struct ReplayOpenOptions {
    std::string calibrationPath; // OpenCV YAML camera matrix that replaces the source's intrinsics
    // A ROS 1 or 2 recording's image topics to replay (topics=DEPTH[,COLOR]; without COLOR, no colour);
    // empty: found by their encodings.
    std::string depthTopic{};
    std::string colorTopic{};
};

// What a path holds, for the replay: a file by its first bytes where they say (a depthcloud recording's
// magic, a ROS bag's "#ROSBAG ", MCAP's), else by its extension in any case (TAKE.DCREC, x.Bag, X.MCAP); a
// folder by its entries. The file picker, a path dropped on the window and replay: all ask this one question.
enum class CaptureKind {
    DcRecording,  // a depthcloud recording
    RosBag,       // a ROS 1 bag (RealSense, ROS)
    Mcap,         // an MCAP file (ROS 2's rosbag2 since Iron, Foxglove)
    Rosbag2,      // a rosbag2 folder (metadata.yaml beside its storage files), or one of its .db3 files
    StrayCapture, // a Stray Scanner capture: depth/ beside rgb.mp4
    TumSequence,  // a TUM RGB-D sequence: rgb.txt and depth.txt
    Folder,       // any other directory
    OtherFile,    // any other file
    Missing,      // nothing there
};
CaptureKind classifyCapture(const std::filesystem::path& path);

// Opens PATH as whatever it is: a depthcloud recording (a file), a ROS bag (a .bag file), a ROS 2 recording
// (an .mcap file, a rosbag2 .db3 file, or a rosbag2 folder of either), a Stray Scanner
// directory (depth/, rgb.mp4, camera_matrix.csv, odometry.csv) or a TUM RGB-D directory (rgb.txt, depth.txt).
Expected<std::unique_ptr<ReplaySource>> openReplaySource(const std::string& path,
                                                         const ReplayOpenOptions& options = {});

// Seconds as capture files store them -> nanoseconds, rounded to the nearest.
std::int64_t secondsToNs(double seconds);

// Camera-to-world from a translation and a unit quaternion (x, y, z, w), as Stray and TUM store poses.
frame::Pose poseFromQuaternion(const double translation[3], const double quaternion[4]);

} // namespace dc::devices::replay
