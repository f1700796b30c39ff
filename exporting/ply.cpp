#include "exporting/ply.h"

#include <cstring>

namespace dc::exporting {

std::vector<std::uint8_t> encodePly(const std::vector<processing::CloudPoint>& points,
                                    const std::vector<std::string>& comments) {
    std::string header = "ply\nformat binary_little_endian 1.0\n";
    for (const std::string& c : comments)
        header += "comment " + c + "\n";
    header += "element vertex " + std::to_string(points.size()) +
              "\nproperty float x\nproperty float y\nproperty float z\n"
              "property uchar red\nproperty uchar green\nproperty uchar blue\n"
              "property uchar confidence\nend_header\n";
    constexpr std::size_t kVertexBytes = 3 * sizeof(float) + 4;
    std::vector<std::uint8_t> out(header.size() + points.size() * kVertexBytes);
    std::memcpy(out.data(), header.data(), header.size());
    std::uint8_t* p = out.data() + header.size();
    for (const processing::CloudPoint& v : points) {
        const float xyz[3] = {v.x, v.y, v.z};
        std::memcpy(p, xyz, sizeof(xyz));
        p[12] = v.r;
        p[13] = v.g;
        p[14] = v.b;
        p[15] = v.confidence;
        p += kVertexBytes;
    }
    return out;
}

} // namespace dc::exporting
