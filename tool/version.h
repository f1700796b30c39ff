#pragma once

namespace dc::tool {

// "depthcloud 0.1.0 (git 0123456789ab)": the project's version and the commit the binary was built from
// (tool/CMakeLists.txt reads it when CMake configures, and configures again when the commit changes).
const char* versionLine();

} // namespace dc::tool
