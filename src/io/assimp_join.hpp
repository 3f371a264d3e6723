// facet io: assimp 5.2.5's JoinIdenticalVertices for facet's own readers. assimp puts a mesh's
// vertices in a std::unordered_map reserved for the mesh's vertex count, hashed by position (-0 as
// +0) and compared with a tolerance (positions, normals, first uvs, tangents and bitangents each
// within a squared distance of 1e-10; colours not at all): a vertex joins the first one of its
// bucket that compares equal, else starts a new one. When no two differing vertices of one bucket
// compare equal, that is the join by exact equality, done here with a hash table of the readers'
// own (exact_join, checked by exact_join_is_assimps); otherwise assimp's own container is run the
// way assimp runs it (assimp_join: the same libstdc++ code, so the same buckets and the same result).
// In: the vertices' attributes as assimp compares them (uvs after FlipUVs). Out: the numbering.
#pragma once

#include <assimp/vector3.h>
#include <assimp/vector3.inl>

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

namespace facet::io_detail {

// What JoinIdenticalVertices compares of a vertex (zeros for what the mesh lacks).
struct JoinVertex {
    aiVector3D position, normal, uv, tangent, bitangent;
};

// A join as a numbering: each item's unique vertex, and each unique vertex's first item.
struct Join {
    std::vector<std::uint32_t> unique;
    std::vector<std::uint32_t> first;
};

namespace join_detail {

// libstdc++'s _Hash_bytes (hash_bytes.cc, 64-bit size_t) for a 4-byte key, inline: assimp's hash
// takes it three times per vertex. std::hash<float> passes the seed 0xc70f6907.
inline std::size_t shift_mix(std::size_t v) { return v ^ (v >> 47); }

inline std::size_t hash_four_bytes(std::uint32_t bytes) {
    constexpr std::size_t mul = (std::size_t{0xc6a4a793u} << 32) + std::size_t{0x5bd1e995u};
    std::size_t hash = std::size_t{0xc70f6907u} ^ (4 * mul);
    hash ^= std::size_t{bytes};  // load_bytes: the four bytes, little-endian
    hash *= mul;
    hash = shift_mix(hash) * mul;
    return shift_mix(hash);
}

}  // namespace join_detail

// std::hash<float> of libstdc++ (0 for both zeros, else _Hash_bytes of the four bytes), and the
// hash assimp combines from a position's three.
inline std::size_t std_float_hash(float v) { return v != 0.0f ? join_detail::hash_four_bytes(std::bit_cast<std::uint32_t>(v)) : 0; }

inline std::size_t assimp_position_hash(const aiVector3D& p) {
    // hash_combine: seed ^= hash(v) + 0x9e3779b9 + (seed << 6) + (seed >> 2), for x, y and z.
    std::size_t seed = 0;
    for (float v : {p.x, p.y, p.z}) seed ^= std_float_hash(v) + 0x9e3779b9 + (seed << 6) + (seed >> 2);
    return seed;
}
// The bucket count of a std::unordered_map reserved for `n` elements.
std::size_t reserved_buckets(std::size_t n);
// assimp's areVerticesEqual with `margin` for its squared tolerance (1e-5f * 1e-5f).
bool assimp_equal(const JoinVertex& a, const JoinVertex& b, float margin);

namespace join_detail {
inline std::uint32_t bits(float v) { return std::bit_cast<std::uint32_t>(v == 0.0f ? 0.0f : v); }
inline bool same(const aiVector3D& a, const aiVector3D& b) {
    return bits(a.x) == bits(b.x) && bits(a.y) == bits(b.y) && bits(a.z) == bits(b.z);
}
inline bool same(const JoinVertex& a, const JoinVertex& b) {
    return same(a.position, b.position) && same(a.normal, b.normal) && same(a.uv, b.uv) && same(a.tangent, b.tangent) &&
           same(a.bitangent, b.bitangent);
}
// By position only: vertices that differ elsewhere are few at one position.
inline std::uint64_t hash(const aiVector3D& p) {
    std::uint64_t h = bits(p.x) * 0x9E3779B97F4A7C15ull;
    h = (h ^ bits(p.y)) * 0xC2B2AE3D27D4EB4Full;
    h = (h ^ bits(p.z)) * 0x165667B19E3779F9ull;
    return h ^ (h >> 29);
}
}  // namespace join_detail

// Items 0..count-1 (value(i) -> JoinVertex) joined when exactly equal (-0 as +0), numbered in order
// of their first item. The table holds each unique vertex (plus one: a slot of zeros is free) with
// 32 bits of its hash, so that a probe past another vertex rarely reads that vertex's values.
template <class Value>
Join exact_join(std::size_t count, Value&& value) {
    constexpr std::uint64_t none = 0;
    // The table is far larger than the caches and each item probes a random slot: the slots are
    // fetched this many items ahead (the hashes in a ring), so that the misses overlap.
    constexpr std::size_t ahead = 16;
    Join out;
    out.unique.resize(count);
    const std::size_t slots = std::bit_ceil(std::max<std::size_t>(16, 2 * count));
    std::vector<std::uint64_t> table(slots);  // tag << 32 | unique + 1 (the heap's memory, reused from mesh to mesh)
    const std::size_t mask = slots - 1;
    std::uint64_t ring[ahead];
    for (std::size_t i = 0; i < std::min(count, ahead); ++i) {
        ring[i] = join_detail::hash(value(i).position);
        __builtin_prefetch(&table[ring[i] & mask]);
    }
    for (std::size_t i = 0; i < count; ++i) {
        const JoinVertex v = value(i);
        const std::uint64_t h = ring[i % ahead];
        if (i + ahead < count) {
            ring[i % ahead] = join_detail::hash(value(i + ahead).position);
            __builtin_prefetch(&table[ring[i % ahead] & mask]);
        }
        const std::uint64_t tag = h >> 32 << 32;
        std::size_t slot = h & mask;
        for (; table[slot] != none; slot = (slot + 1) & mask)
            if ((table[slot] & ~0xFFFFFFFFull) == tag &&
                join_detail::same(value(out.first[static_cast<std::uint32_t>(table[slot]) - 1]), v))
                break;
        if (table[slot] == none) {
            out.first.push_back(static_cast<std::uint32_t>(i));
            table[slot] = tag | out.first.size();
        }
        out.unique[i] = static_cast<std::uint32_t>(table[slot]) - 1;
    }
    return out;
}

// Whether assimp's join of a mesh of `vertex_count` vertices is the exact `join`: no two of its
// unique vertices in one of assimp's buckets compare equal, with twice the margin. unique_value(u)
// is unique vertex u's JoinVertex, position(u) its position (the callers have them gathered in
// order, as their meshes' positions). The buckets are too many to hold lists: a bit per bucket
// finds those holding two or more unique vertices, and only their vertices are compared.
template <class Value, class Position>
bool exact_join_is_assimps(const Join& join, Value&& unique_value, Position&& position, std::size_t vertex_count) {
    const std::size_t buckets = reserved_buckets(vertex_count);
    std::vector<std::uint64_t> seen((buckets + 63) / 64), shared((buckets + 63) / 64);
    std::vector<std::uint32_t> bucket_of(join.first.size());  // buckets: fewer than 2^32 (reserved for a mesh's vertices)
    for (std::size_t u = 0; u < join.first.size(); ++u) {
        const std::size_t b = assimp_position_hash(position(u)) % buckets;
        bucket_of[u] = static_cast<std::uint32_t>(b);
        const std::uint64_t bit = std::uint64_t{1} << (b % 64);
        if (seen[b / 64] & bit) shared[b / 64] |= bit;
        seen[b / 64] |= bit;
    }
    std::vector<std::uint64_t> crowded;  // bucket << 32 | unique vertex
    for (std::size_t u = 0; u < join.first.size(); ++u)
        if (shared[bucket_of[u] / 64] & (std::uint64_t{1} << (bucket_of[u] % 64)))
            crowded.push_back(std::uint64_t{bucket_of[u]} << 32 | u);
    std::sort(crowded.begin(), crowded.end());
    // Each crowded vertex's values fetched once, in bucket order (the pairs then read them in order).
    std::vector<JoinVertex> values;
    values.reserve(crowded.size());
    for (const std::uint64_t c : crowded) values.push_back(unique_value(static_cast<std::uint32_t>(c)));
    for (std::size_t a = 0; a < crowded.size(); ++a)
        for (std::size_t b = a + 1; b < crowded.size() && crowded[b] >> 32 == crowded[a] >> 32; ++b)
            if (assimp_equal(values[a], values[b], 2e-10f)) return false;
    return true;
}

// assimp's join itself over the vertices used (used(i)), in its container and order; the unused
// keep ~0.
template <class Value, class Used>
Join assimp_join(std::size_t count, Value&& value, Used&& used) {
    struct Hash {
        std::size_t operator()(const JoinVertex& v) const noexcept { return assimp_position_hash(v.position); }
    };
    struct Equal {
        bool operator()(const JoinVertex& a, const JoinVertex& b) const { return assimp_equal(a, b, 1e-5f * 1e-5f); }
    };
    // A hash that is noexcept and not one of libstdc++'s "slow" ones, as assimp's std::hash<Vertex>:
    // the same container layout (no cached hash codes) and so the same comparisons.
    std::unordered_map<JoinVertex, std::uint32_t, Hash, Equal> map;
    map.reserve(count);
    Join out;
    out.unique.assign(count, ~0u);
    for (std::size_t i = 0; i < count; ++i) {
        if (!used(i)) continue;
        const JoinVertex v = value(i);
        auto it = map.find(v);
        if (it == map.end()) {
            map[v] = static_cast<std::uint32_t>(out.first.size());
            out.unique[i] = static_cast<std::uint32_t>(out.first.size());
            out.first.push_back(static_cast<std::uint32_t>(i));
        } else {
            out.unique[i] = it->second;
        }
    }
    return out;
}

}  // namespace facet::io_detail
