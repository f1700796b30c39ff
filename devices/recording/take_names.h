#pragma once

#include "base/expected.h"

#include <string>

namespace dc::devices::recording {

inline constexpr const char* kTakePrefix = "depthcloud-recording-";

// The path of the next take in `directory`: depthcloud-recording-001.dcrec, -002, ... numbered one past
// the highest take already there, finished or interrupted (.dcrec.partial), so a deleted take's number is
// not reused out of order. At least three digits. Creating the file is still exclusive (RecordingWriter):
// two recorders that pick the same name at once get an error, never each other's file.
Expected<std::string> nextTakePath(const std::string& directory);

} // namespace dc::devices::recording
