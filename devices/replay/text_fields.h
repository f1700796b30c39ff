#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace dc::devices::replay {

// One line of a text file with where it starts, for errors that point at it.
struct TextLine {
    std::string_view text;  // without the line break
    std::size_t number = 0; // 1-based
    std::size_t offset = 0; // byte offset of the line's first character
};

// Splits text into lines (LF or CR LF), calling `visit` for each; stops early when it returns false.
void forEachLine(std::string_view text, const std::function<bool(const TextLine&)>& visit);

// Fields separated by `separator` (',' for CSV) or, with separator 0, by runs of blanks, trimmed.
std::vector<std::string_view> splitFields(std::string_view line, char separator);

std::string_view trim(std::string_view text);

// A whole field as a finite double; false for anything else ("nan", "1e999", "3x").
bool parseFiniteDouble(std::string_view field, double& out);

// "FILE: line N (byte offset X): "
std::string linePrefix(const std::string& file, const TextLine& line);

} // namespace dc::devices::replay
