#pragma once

// The real depthcloud binary run as a new user runs it: from a fresh working directory under the temp dir,
// far from the checkout (so no ../shared), with its exit status, standard output and standard error kept.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace dc::test {

struct RunResult {
    int exitCode = -1;
    std::string out;
    std::string err;
};

inline std::string readFile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

inline std::size_t lines(const std::string& text) {
    return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

class ToolInTempDir : public ::testing::Test {
protected:
    void SetUp() override {
        std::string pattern = (std::filesystem::temp_directory_path() / "depthcloud-app-XXXXXX").string();
        ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
        dir_ = pattern;
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }

    // `depthcloud ARGUMENTS` in dir_.
    RunResult runTool(const std::string& arguments) const {
        const std::string command =
            "cd '" + dir_.string() + "' && " + DEPTHCLOUD_BINARY + " " + arguments + " > out.txt 2> err.txt";
        const int status = std::system(command.c_str());
        RunResult r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, readFile(dir_ / "out.txt"),
                    readFile(dir_ / "err.txt")};
        std::filesystem::remove(dir_ / "out.txt");
        std::filesystem::remove(dir_ / "err.txt");
        return r;
    }

    std::filesystem::path dir_;
};

} // namespace dc::test
