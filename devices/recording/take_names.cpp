#include "devices/recording/take_names.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <string_view>

namespace dc::devices::recording {

namespace {

// The number of a take's file name, or 0 for any other name.
unsigned long takeNumber(std::string_view name) {
    if (!name.starts_with(kTakePrefix))
        return 0;
    name.remove_prefix(std::string_view(kTakePrefix).size());
    unsigned long number = 0;
    const auto [end, ec] = std::from_chars(name.data(), name.data() + name.size(), number);
    const std::string_view rest(end, static_cast<std::size_t>(name.data() + name.size() - end));
    if (ec != std::errc() || end == name.data() || (rest != ".dcrec" && rest != ".dcrec.partial"))
        return 0;
    return number;
}

} // namespace

Expected<std::string> nextTakePath(const std::string& directory) {
    namespace fs = std::filesystem;
    std::error_code ec;
    unsigned long highest = 0;
    for (fs::directory_iterator it(directory, ec), end; !ec && it != end; it.increment(ec))
        highest = std::max(highest, takeNumber(it->path().filename().string()));
    if (ec)
        return Error{"cannot list " + directory + " for the next take: " + ec.message()};
    char name[64];
    std::snprintf(name, sizeof name, "%s%03lu.dcrec", kTakePrefix, highest + 1);
    return (fs::path(directory) / name).string();
}

} // namespace dc::devices::recording
