#pragma once

#include "base/expected.h"
#include "devices/uvc/v4l2/syscalls.h"
#include "devices/uvc/v4l2/v4l2_node.h"
#include "frame/frame.h"

#include <chrono>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <string>
#include <utility>

namespace dc::devices {

// What one metadata buffer says about the video frame of the same sequence.
struct FrameMetadata {
    std::optional<std::uint32_t> exposureUs;
    frame::CameraMetadata camera;
};

// One buffer of a metadata node in `dataFormat` (V4L2_META_FMT_D4XX or V4L2_META_FMT_UVC).
Expected<FrameMetadata> readFrameMetadata(std::uint32_t dataFormat, std::span<const std::uint8_t> bytes);

// Metadata waiting for the video frame of its sequence (uvcvideo gives a metadata buffer the sequence of
// the video buffer it belongs to). A frame that goes out without its metadata goes out without it: what
// arrives for a sequence already taken, or falls out of the window, is dropped. Sequences wrap at 2^32.
class MetadataWindow {
public:
    static constexpr std::size_t kSize = 8;

    void add(std::uint32_t sequence, FrameMetadata metadata);
    // The metadata of `sequence`, taken out with every entry older than it.
    std::optional<FrameMetadata> take(std::uint32_t sequence);
    void clear();
    std::size_t size() const { return entries_.size(); }

private:
    std::deque<std::pair<std::uint32_t, FrameMetadata>> entries_;
    std::optional<std::uint32_t> lastTaken_;
};

// The metadata node of a UVC camera's depth node, streamed beside it on the same capture thread. It never
// holds the video up: a node that cannot be found, opened or streamed, or that stops, leaves the frames
// without metadata, and says so once; a bad buffer is logged (rate-limited) and skipped.
class MetadataStream {
public:
    explicit MetadataStream(v4l2::Syscalls& sys) : node_(sys, v4l2::BufferKind::Metadata) {}

    // Finds the metadata node of `video` (uvcvideo registers it right after its video node, on the same
    // bus) and sets V4L2_META_FMT_D4XX where `d4xx` and the node offers it, else V4L2_META_FMT_UVC.
    // `who` names the camera in the log; a node of a USB gadget (sysfs under `sysfsRoot`) is never opened.
    void open(const v4l2::V4l2Node& video, bool d4xx, const std::string& who, const std::string& sysfsRoot);
    void start();
    void stop();
    void close();
    bool streaming() const { return node_.streaming(); }
    v4l2::V4l2Node& node() { return node_; }
    // The node and its V4L2_META_FMT_*: empty and 0 without one, or after it failed.
    std::string path() const { return node_.isOpen() ? node_.path() : std::string(); }
    std::uint32_t dataFormat() const { return node_.isOpen() ? dataFormat_ : 0; }

    // What poll() found on the node: takes every buffer ready now.
    void service(const v4l2::NodeReadiness& ready);
    // Puts the metadata of video buffer `sequence` into `timing`, taking buffers that are ready first.
    void fill(std::uint32_t sequence, frame::FrameTiming& timing);
    // The video stream restarted: its sequence starts again.
    void restart() { window_.clear(); }

private:
    unsigned drain(); // the number of buffers dequeued
    void giveUp(const std::string& message);
    void reportBad(const std::string& message);

    v4l2::V4l2Node node_;
    std::uint32_t dataFormat_ = 0;
    std::string who_;
    MetadataWindow window_;
    bool toldUnavailable_ = false; // the node's absence or failure is told once per camera
    std::chrono::steady_clock::time_point lastBadReport_{};
    std::uint64_t badSinceReport_ = 0;
    bool badReported_ = false;
};

} // namespace dc::devices
