// facet io: the binary STL fast path (binary_stl.hpp).
#include "io/binary_stl.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

namespace facet::io_detail {
namespace {

constexpr std::size_t k_header_bytes = 80;
constexpr std::size_t k_facet_bytes = 50;  // normal, three vertices (12 floats), 16-bit attribute
constexpr std::uint16_t k_colour_bit = 0x8000;

std::uint32_t read_u32(const char* p) {
    std::uint32_t v;
    std::memcpy(&v, p, sizeof(v));
    return v;  // little-endian in the file, as on every platform facet builds for
}

}  // namespace

std::optional<JoinedMesh> read_binary_stl(std::string_view bytes) {
    if (bytes.size() < k_header_bytes + 4) return std::nullopt;
    const std::uint64_t facets = read_u32(bytes.data() + k_header_bytes);
    if (facets == 0 || facets > 0xFFFFFFFFu / 3 || k_header_bytes + 4 + facets * k_facet_bytes != bytes.size()) return std::nullopt;
    if (bytes.substr(0, k_header_bytes).find("COLOR=") != std::string_view::npos) return std::nullopt;
    std::vector<Vec3> positions(3 * facets);
    std::vector<std::uint32_t> indices(3 * facets);
    const char* facet = bytes.data() + k_header_bytes + 4;
    for (std::size_t f = 0; f < facets; ++f, facet += k_facet_bytes) {
        float v[9];
        std::memcpy(v, facet + 12, sizeof(v));  // after the facet normal, which the assimp path drops
        std::uint16_t attribute;
        std::memcpy(&attribute, facet + 48, sizeof(attribute));
        if (attribute & k_colour_bit) return std::nullopt;
        for (float c : v)
            if (!std::isfinite(c)) return std::nullopt;
        for (std::size_t k = 0; k < 3; ++k) {
            positions[3 * f + k] = {v[3 * k], v[3 * k + 1], v[3 * k + 2]};
            indices[3 * f + k] = static_cast<std::uint32_t>(3 * f + k);
        }
    }
    return join_identical_vertices(positions, indices);
}

}  // namespace facet::io_detail
