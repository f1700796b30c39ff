#pragma once

#include "devices/ros/message_store.h"

#include <memory>
#include <vector>

namespace dc::devices::ros {

// A recording split over several files (a rosbag2 folder whose recorder rolled over to a new file at a
// size or duration limit) as one MessageStore: each topic's messages are the first file's, then the
// second's, and so on, in the order given. Topics are matched by name, so files may number them apart.
// `parts` holds at least one store.
std::unique_ptr<MessageStore> concatenateStores(std::vector<std::unique_ptr<MessageStore>> parts);

} // namespace dc::devices::ros
