#include "support/stl_files.hpp"

#include <cstring>
#include <iomanip>
#include <sstream>

namespace facet_test {
namespace {

template <class T>
void put(std::string& out, T value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));  // little-endian host, as the format wants
    out.append(bytes, sizeof(T));
}

}  // namespace

std::string binary_stl(const std::vector<StlTriangle>& triangles, const std::string& header,
                       const std::vector<std::uint16_t>& attributes) {
    std::string s = header.substr(0, 80) + std::string(80 - std::min<std::size_t>(header.size(), 80), '\0');
    put(s, static_cast<std::uint32_t>(triangles.size()));
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        for (int k = 0; k < 3; ++k) put(s, 0.0f);
        for (const facet::Vec3& p : triangles[i]) put(s, p.x), put(s, p.y), put(s, p.z);
        put(s, i < attributes.size() ? attributes[i] : std::uint16_t{0});
    }
    return s;
}

std::string ascii_stl(const std::vector<StlTriangle>& triangles, const std::string& name) {
    std::ostringstream s;
    s << std::setprecision(9) << "solid " << name << "\n";
    for (const StlTriangle& t : triangles) {
        s << "  facet normal 0 0 0\n    outer loop\n";
        for (const facet::Vec3& p : t) s << "      vertex " << p.x << ' ' << p.y << ' ' << p.z << '\n';
        s << "    endloop\n  endfacet\n";
    }
    s << "endsolid " << name << "\n";
    return s.str();
}

std::vector<StlTriangle> triangles_of(const facet::Mesh& m) {
    std::vector<StlTriangle> out;
    for (std::size_t t = 0; t < m.indices.size(); t += 3)
        out.push_back({m.positions[m.indices[t]], m.positions[m.indices[t + 1]], m.positions[m.indices[t + 2]]});
    return out;
}

}  // namespace facet_test
