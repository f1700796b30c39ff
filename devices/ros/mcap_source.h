#pragma once

#include "base/expected.h"
#include "devices/replay/replay_source.h"
#include "devices/ros/bag_source.h"

#include <memory>
#include <string>

namespace dc::devices::ros {

// A ROS 2 recording as a replay source: an MCAP file, or a rosbag2 folder (metadata.yaml beside it) whose
// storage is MCAP or sqlite3 (a .db3, read through devices/ros/db3_store.h). sensor_msgs/msg/Image and
// CameraInfo in CDR replay as a ROS 1 bag's do: the same topic choice (the ROS 2 wrappers' /camera/camera/...
// names, or BagOptions' topics), pairing, calibration and infrared. Messages are found through the file's
// indexes, or indexed on open where it has none.
Expected<std::unique_ptr<replay::ReplaySource>> openMcapSource(const std::string& path,
                                                               const BagOptions& options = {});

// The file a rosbag2 folder records into, from its metadata.yaml: its .mcap, or its .db3 for sqlite3 storage.
Expected<std::string> rosbag2File(const std::string& directory);

} // namespace dc::devices::ros
