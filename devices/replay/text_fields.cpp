#include "devices/replay/text_fields.h"

#include <charconv>
#include <cmath>

namespace dc::devices::replay {

void forEachLine(std::string_view text, const std::function<bool(const TextLine&)>& visit) {
    std::size_t start = 0, number = 1;
    while (start < text.size()) {
        std::size_t end = text.find('\n', start);
        const std::size_t next = end == std::string_view::npos ? text.size() : end + 1;
        if (end == std::string_view::npos)
            end = text.size();
        std::string_view line = text.substr(start, end - start);
        if (!line.empty() && line.back() == '\r')
            line.remove_suffix(1);
        if (!visit({line, number, start}))
            return;
        start = next;
        ++number;
    }
}

std::string_view trim(std::string_view text) {
    const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
    while (!text.empty() && blank(text.front()))
        text.remove_prefix(1);
    while (!text.empty() && blank(text.back()))
        text.remove_suffix(1);
    return text;
}

std::vector<std::string_view> splitFields(std::string_view line, char separator) {
    std::vector<std::string_view> fields;
    if (separator != 0) {
        std::size_t start = 0;
        for (;;) {
            const std::size_t end = line.find(separator, start);
            fields.push_back(trim(
                line.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start)));
            if (end == std::string_view::npos)
                return fields;
            start = end + 1;
        }
    }
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t'))
            ++i;
        const std::size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t')
            ++i;
        if (i > start)
            fields.push_back(line.substr(start, i - start));
    }
    return fields;
}

bool parseFiniteDouble(std::string_view field, double& out) {
    field = trim(field);
    if (!field.empty() && field.front() == '+')
        field.remove_prefix(1);
    const char* end = field.data() + field.size();
    const auto [ptr, ec] = std::from_chars(field.data(), end, out);
    return ec == std::errc() && ptr == end && !field.empty() && std::isfinite(out);
}

std::string linePrefix(const std::string& file, const TextLine& line) {
    return file + ": line " + std::to_string(line.number) + " (byte offset " + std::to_string(line.offset) +
           "): ";
}

} // namespace dc::devices::replay
