#pragma once

// A metadata node's buffer (V4L2_META_FMT_UVC, V4L2_META_FMT_D4XX) built one little-endian field at a time,
// as uvcvideo lays it out, so that a test does not share the parser's idea of the layout.

#include <cstdint>
#include <vector>

namespace dc::test {

struct MetadataBytes {
    std::vector<std::uint8_t> bytes;

    MetadataBytes& u8(std::uint64_t v) { return little(v, 1); }
    MetadataBytes& u16(std::uint64_t v) { return little(v, 2); }
    MetadataBytes& u32(std::uint64_t v) { return little(v, 4); }
    MetadataBytes& u64(std::uint64_t v) { return little(v, 8); }
    MetadataBytes& append(const std::vector<std::uint8_t>& more) {
        bytes.insert(bytes.end(), more.begin(), more.end());
        return *this;
    }

private:
    MetadataBytes& little(std::uint64_t v, int count) {
        for (int i = 0; i < count; ++i)
            bytes.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
        return *this;
    }
};

} // namespace dc::test
