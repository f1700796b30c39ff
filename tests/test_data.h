#pragma once

#include <string>

namespace dc::test {

// A real capture of the workspace's shared data (tests/CMakeLists.txt says how the directory is found).
inline std::string dataPath(const std::string& name) {
    return std::string(DC_TEST_DATA_DIR) + "/" + name;
}

} // namespace dc::test
