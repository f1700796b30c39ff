#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

namespace dc::devices::recording {

// Appends little-endian fields to a byte vector. The format is defined byte by byte (docs/
// recording-format.md), so nothing is written by copying a struct.
class ByteWriter {
public:
    explicit ByteWriter(std::vector<std::uint8_t>& out) : out_(out) {}

    template <class T> void put(T value) {
        static_assert(std::is_arithmetic_v<T>);
        static_assert(std::endian::native == std::endian::little, "the format is little-endian");
        append(&value, sizeof(T));
    }
    void putBytes(std::span<const std::uint8_t> bytes) { append(bytes.data(), bytes.size()); }
    void putString(const std::string& text) {
        put(static_cast<std::uint32_t>(text.size()));
        putBytes({reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
    }
    std::size_t size() const { return out_.size(); }

private:
    // resize + memcpy rather than insert(): GCC 12 reports a false stringop-overflow for small inserts.
    void append(const void* data, std::size_t count) {
        if (count == 0)
            return;
        const std::size_t at = out_.size();
        out_.resize(at + count);
        std::memcpy(out_.data() + at, data, count);
    }

    std::vector<std::uint8_t>& out_;
};

// Reads little-endian fields from a span that sits at `baseOffset` in its file. Reading past the end
// sets a sticky failure and returns zeros, so a parser checks ok() once after a group of fields and
// reports the file offset where the data ran out.
class ByteReader {
public:
    ByteReader(std::span<const std::uint8_t> bytes, std::uint64_t baseOffset)
        : bytes_(bytes), base_(baseOffset) {}

    template <class T> T get() {
        static_assert(std::is_arithmetic_v<T>);
        T value{};
        if (!require(sizeof(T)))
            return value;
        std::memcpy(&value, bytes_.data() + pos_, sizeof(T));
        pos_ += sizeof(T);
        return value;
    }
    std::span<const std::uint8_t> getBytes(std::size_t count) {
        if (!require(count))
            return {};
        const auto view = bytes_.subspan(pos_, count);
        pos_ += count;
        return view;
    }
    std::string getString(std::size_t maxLength) {
        const auto length = get<std::uint32_t>();
        if (length > maxLength) {
            failed_ = true;
            return {};
        }
        const auto view = getBytes(length);
        return {reinterpret_cast<const char*>(view.data()), view.size()};
    }

    bool ok() const { return !failed_; }
    std::size_t remaining() const { return bytes_.size() - pos_; }
    // File offset of the next byte to read (where a failure happened, once ok() is false).
    std::uint64_t offset() const { return base_ + pos_; }

private:
    bool require(std::size_t count) {
        if (failed_ || count > bytes_.size() - pos_) {
            failed_ = true;
            return false;
        }
        return true;
    }

    std::span<const std::uint8_t> bytes_;
    std::uint64_t base_ = 0;
    std::size_t pos_ = 0;
    bool failed_ = false;
};

} // namespace dc::devices::recording
