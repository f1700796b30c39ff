#pragma once

#include "base/expected.h"

#include <chrono>
#include <string>

// Where a ROS 1 master is and whether it answers, without roscpp: roscpp's own calls can block for as long
// as the kernel's TCP connect timeout when the master's host is gone, so every first contact goes through a
// bounded probe here. This header must stay valid C++17 (the roscpp glue includes it).
namespace dc::devices::ros {

struct MasterUri {
    std::string uri; // as given: http://host:port[/]
    std::string host;
    int port = 0;
};

// The master's URI from `explicitUri` (a spec's master=), else from ROS_MASTER_URI. Fails, naming what was
// wrong, when neither is set or the URI is not http://HOST:PORT.
Expected<MasterUri> resolveMasterUri(const std::string& explicitUri);
Expected<MasterUri> parseMasterUri(const std::string& uri);

// Asks the master for its pid over XML-RPC, waiting at most `timeout` in all: success means a master
// answers there. The error says why not (refused, timed out, no answer, unknown host) in one line.
Status probeMaster(const MasterUri& master, std::chrono::milliseconds timeout);
// A master that does not answer a probe in this long is taken to be away.
inline constexpr std::chrono::milliseconds kMasterProbeTimeout{1000};

} // namespace dc::devices::ros
