// facet io: the pieces of assimp's join that are not templates (assimp_join.hpp).
#include "io/assimp_join.hpp"

#include <algorithm>
#include <unordered_map>

namespace facet::io_detail {
namespace {

// libstdc++'s _Hash_bytes (hash_bytes.cc, 64-bit size_t) for a 4-byte key, inline: assimp's hash
// takes it three times per vertex. std::hash<float> passes the seed 0xc70f6907.
std::size_t shift_mix(std::size_t v) { return v ^ (v >> 47); }

std::size_t hash_four_bytes(std::uint32_t bytes) {
    constexpr std::size_t mul = (std::size_t{0xc6a4a793u} << 32) + std::size_t{0x5bd1e995u};
    std::size_t hash = std::size_t{0xc70f6907u} ^ (4 * mul);
    hash ^= std::size_t{bytes};  // load_bytes: the four bytes, little-endian
    hash *= mul;
    hash = shift_mix(hash) * mul;
    return shift_mix(hash);
}

}  // namespace

std::size_t std_float_hash(float v) { return v != 0.0f ? hash_four_bytes(std::bit_cast<std::uint32_t>(v)) : 0; }

std::size_t assimp_position_hash(const aiVector3D& p) {
    // hash_combine: seed ^= hash(v) + 0x9e3779b9 + (seed << 6) + (seed >> 2), for x, y and z.
    std::size_t seed = 0;
    for (float v : {p.x, p.y, p.z}) seed ^= std_float_hash(v) + 0x9e3779b9 + (seed << 6) + (seed >> 2);
    return seed;
}

std::size_t reserved_buckets(std::size_t n) {
    // What reserve(n) does to an empty std::unordered_map (libstdc++ 12: rehash(ceil(n / 1.0f)),
    // which takes the rehash policy's next bucket count), without allocating the buckets.
    const std::__detail::_Prime_rehash_policy policy;
    const auto wanted = static_cast<std::size_t>(__builtin_ceil(static_cast<float>(n) / 1.0f));
    return policy._M_next_bkt(std::max(policy._M_bkt_for_elements(1), wanted));
}

bool assimp_equal(const JoinVertex& a, const JoinVertex& b, float margin) {
    return !((a.position - b.position).SquareLength() > margin) && !((a.normal - b.normal).SquareLength() > margin) &&
           !((a.uv - b.uv).SquareLength() > margin) && !((a.tangent - b.tangent).SquareLength() > margin) &&
           !((a.bitangent - b.bitangent).SquareLength() > margin);
}

}  // namespace facet::io_detail
