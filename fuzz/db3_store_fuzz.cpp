// libFuzzer: the rosbag2 sqlite3 reader on arbitrary bytes (written to a file first, since SQLite opens
// databases by name): its topics and messages tables however they came out, then the first messages of
// every topic through the CDR decoders.

#include "devices/ros/db3_store.h"

#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

// Never destroyed, so that the exit handler that removes the file can still read its name.
const std::string& databasePath() {
    static const std::string& path = *new std::string(
        (std::filesystem::temp_directory_path() / ("db3_store_fuzz_" + std::to_string(::getpid()) + ".db3"))
            .string());
    static const bool removedAtExit = std::atexit([] { std::filesystem::remove(databasePath()); }) == 0;
    (void)removedAtExit;
    return path;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace dc::devices::ros;
    std::ofstream(databasePath(), std::ios::binary | std::ios::trunc)
        .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    auto store = openDb3Store(databasePath());
    if (!store)
        return 0;
    for (const MessageStore::Topic& topic : (*store)->topics()) {
        (void)(*store)->firstCameraInfo(topic.name);
        auto handle = (*store)->indexTopic(topic.name);
        if (!handle)
            continue;
        const std::size_t messages = std::min<std::size_t>((*store)->messageCount(*handle), 8);
        for (std::size_t i = 0; i < messages; ++i) {
            (void)(*store)->recordedNs(*handle, i);
            (void)(*store)->image(*handle, i);
            (void)(*store)->transforms(*handle, i);
        }
    }
    return 0;
}
