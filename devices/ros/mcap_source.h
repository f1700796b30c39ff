#pragma once

#include "base/expected.h"
#include "devices/replay/replay_source.h"
#include "devices/ros/bag_source.h"

#include <memory>
#include <string>
#include <vector>

namespace dc::devices::ros {

// A ROS 2 recording as a replay source: an MCAP file, a rosbag2 .db3 file (read through
// devices/ros/db3_store.h), or a rosbag2 folder (metadata.yaml beside them) of either, split over several
// files or not. sensor_msgs/msg/Image and
// CameraInfo in CDR replay as a ROS 1 bag's do: the same topic choice (the ROS 2 wrappers' /camera/camera/...
// names, or BagOptions' topics), pairing, calibration and infrared. Messages are found through the file's
// indexes, or indexed on open where it has none.
Expected<std::unique_ptr<replay::ReplaySource>> openMcapSource(const std::string& path,
                                                               const BagOptions& options = {});

// The files a rosbag2 folder records into, in order, from its metadata.yaml: its .mcap files, or its .db3
// files for sqlite3 storage (a recorder that splits by size or duration writes several).
Expected<std::vector<std::string>> rosbag2Files(const std::string& directory);

} // namespace dc::devices::ros
