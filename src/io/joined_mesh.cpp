// facet io: assimp's vertex joining and facet's renumbering, exactly (joined_mesh.hpp).
#include "io/joined_mesh.hpp"

#include <bit>
#include <cmath>

namespace facet::io_detail {
namespace {

// Positions assimp might join share a key: the bit patterns, with tiny coordinates (and -0) as +0.
std::uint32_t key_bits(float v) { return std::bit_cast<std::uint32_t>(std::fabs(v) < 0x1p-49f ? 0.0f : v); }

std::uint64_t position_hash(const Vec3& p) {
    std::uint64_t h = key_bits(p.x) * 0x9E3779B97F4A7C15ull;
    h = (h ^ key_bits(p.y)) * 0xC2B2AE3D27D4EB4Full;
    h = (h ^ key_bits(p.z)) * 0x165667B19E3779F9ull;
    return h ^ (h >> 29);
}

bool same_key(const Vec3& a, const Vec3& b) {
    return key_bits(a.x) == key_bits(b.x) && key_bits(a.y) == key_bits(b.y) && key_bits(a.z) == key_bits(b.z);
}
bool same_position(const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// For each used vertex, the first used vertex in file order at the same position (its group's
// representative, as in assimp's JoinIdenticalVertices); unused vertices keep ~0. Nullopt when two
// used positions share a key but are not equal.
std::optional<std::vector<std::uint32_t>> join_used_vertices(const std::vector<Vec3>& positions,
                                                             const std::vector<std::uint32_t>& indices) {
    constexpr std::uint32_t none = ~0u;
    std::vector<std::uint32_t> representative(positions.size(), none);
    for (std::uint32_t i : indices) representative[i] = 0;  // marks the used ones
    const std::size_t capacity = std::bit_ceil(2 * positions.size());
    std::vector<std::uint32_t> table(capacity, none);  // open addressing, linear probing
    for (std::uint32_t v = 0; v < positions.size(); ++v) {
        if (representative[v] == none) continue;
        for (std::size_t slot = position_hash(positions[v]) & (capacity - 1);; slot = (slot + 1) & (capacity - 1)) {
            if (table[slot] == none) {
                table[slot] = v;
                representative[v] = v;
                break;
            }
            if (same_key(positions[table[slot]], positions[v])) {
                if (!same_position(positions[table[slot]], positions[v])) return std::nullopt;
                representative[v] = table[slot];
                break;
            }
        }
    }
    return representative;
}

}  // namespace

std::optional<JoinedMesh> join_identical_vertices(const std::vector<Vec3>& file_positions,
                                                  const std::vector<std::uint32_t>& file_indices) {
    const std::optional<std::vector<std::uint32_t>> joined = join_used_vertices(file_positions, file_indices);
    if (!joined) return std::nullopt;
    const std::vector<std::uint32_t>& representative = *joined;
    constexpr std::uint32_t none = ~0u;
    std::vector<std::uint32_t> number(file_positions.size(), none);
    JoinedMesh out;
    out.indices.resize(file_indices.size());
    for (std::size_t c = 0; c < file_indices.size(); ++c) {
        const std::uint32_t r = representative[file_indices[c]];
        if (number[r] == none) {
            number[r] = static_cast<std::uint32_t>(out.positions.size());
            out.positions.push_back(file_positions[r]);
        }
        out.indices[c] = number[r];
    }
    for (std::size_t t = 0; t < out.indices.size(); t += 3) {
        const std::uint32_t a = out.indices[t], b = out.indices[t + 1], c = out.indices[t + 2];
        out.degenerate += a == b || b == c || c == a;
    }
    return out;
}

}  // namespace facet::io_detail
