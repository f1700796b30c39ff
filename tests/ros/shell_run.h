#pragma once

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <sys/wait.h>

// What the ROS tests run as whole processes (depthcloud, the independent MCAP reader): a shell command in
// a folder, with its exit code and its two outputs kept.
namespace dc::test {

inline std::string readText(const std::string& path) {
    std::ifstream in(path);
    return {std::istreambuf_iterator<char>(in), {}};
}

struct RunResult {
    int exitCode = -1;
    std::string out;
    std::string err;
};

// `command` run by the shell in `dir`; its outputs pass through out.txt and err.txt there.
inline RunResult runIn(const std::string& dir, const std::string& command) {
    const std::string full = "cd '" + dir + "' && " + command + " > out.txt 2> err.txt";
    const int status = std::system(full.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, readText(dir + "/out.txt"),
            readText(dir + "/err.txt")};
}

} // namespace dc::test
