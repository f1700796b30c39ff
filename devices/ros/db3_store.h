#pragma once

#include "base/expected.h"
#include "devices/ros/message_store.h"

#include <memory>
#include <string>

namespace dc::devices::ros {

// A rosbag2 sqlite3 file (.db3, the storage before Iron made MCAP the default) as a MessageStore: its
// `topics` table (name, type, serialization format) and `messages` table (topic, receive time, CDR bytes),
// read-only. Messages of a topic in receive-time order, read one by one by their row ids.
Expected<std::unique_ptr<MessageStore>> openDb3Store(const std::string& path);

} // namespace dc::devices::ros
