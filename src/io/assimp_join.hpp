// facet io: assimp 5.2.5's JoinIdenticalVertices for facet's own readers. assimp puts a mesh's
// vertices in a std::unordered_map reserved for the mesh's vertex count, hashed by position (-0 as
// +0) and compared with a tolerance (positions, normals, first uvs, tangents and bitangents each
// within a squared distance of 1e-10; colours not at all): a vertex joins the first one of its
// bucket that compares equal, else starts a new one. When no two differing vertices of one bucket
// compare equal, that is the join by exact equality, done here with a hash table of the readers'
// own (join_as_assimp, which also makes that check); otherwise assimp's own container is run the
// way assimp runs it (assimp_join: the same libstdc++ code, so the same buckets and the same result).
// In: the vertices' attributes as assimp compares them (uvs after FlipUVs). Out: the numbering.
#pragma once

#include <assimp/vector3.h>
#include <assimp/vector3.inl>

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "exec/fresh_pages.hpp"

namespace facet::io_detail {

// What JoinIdenticalVertices compares of a vertex (zeros for what the mesh lacks).
struct JoinVertex {
    aiVector3D position, normal, uv, tangent, bitangent;
};

// A join as a numbering: each item's unique vertex, and each unique vertex's first item; or, when
// `identity` (join_as_assimp with the items' positions, no two items joined), neither: item i is
// unique vertex i.
struct Join {
    std::vector<std::uint32_t> unique;
    std::vector<std::uint32_t> first;
    bool identity = false;
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

// h % d for a fixed d (2 to 2^32 - 1) by multiplications (Lemire, Kaser and Kurz, "Faster
// remainder by direct computation", 2019: with a 128-bit fraction the remainder is exact for every
// 64-bit h and d): the hash table's bucket of a hash without a 64-bit division per vertex.
class Remainder {
public:
    explicit Remainder(std::uint64_t d) : d_(d), m_(~static_cast<unsigned __int128>(0) / d + 1) {}
    std::uint64_t of(std::uint64_t h) const {
        const unsigned __int128 low = m_ * h;  // the fraction h / d, modulo 1
        const unsigned __int128 top = static_cast<unsigned __int128>(static_cast<std::uint64_t>(low >> 64)) * d_;
        const unsigned __int128 bottom = static_cast<unsigned __int128>(static_cast<std::uint64_t>(low)) * d_ >> 64;
        return static_cast<std::uint64_t>((top + bottom) >> 64);
    }

private:
    std::uint64_t d_;
    unsigned __int128 m_;
};
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
}  // namespace join_detail

// Items 0..count-1 (value(i) -> JoinVertex) joined when exactly equal (-0 as +0), numbered in order
// of their first item, with each unique vertex's position in `positions`; nullopt when assimp's
// join of a mesh of `vertex_count` vertices could differ: two unique vertices in one of its buckets
// that compare equal with twice its margin. The table is keyed by assimp's bucket, so that the
// vertices of a bucket meet in one probe sequence: the exact join and the check are one pass. It
// holds each unique vertex (plus one: a slot of zeros is free) with its bucket, and a probe past
// another bucket's vertex reads nothing more.
// With `item_positions` (item i's position at item_positions[i]), nothing is written while no two
// items have joined: a join of none comes back as `identity`, with `positions` empty (the items'
// own are the unique ones), and no numbering or copy of positions is made (a file's vertices used
// in the order listed, most of them distinct).
template <class Value>
std::optional<Join> join_as_assimp(std::size_t count, Value&& value, std::size_t vertex_count, std::vector<aiVector3D>& positions,
                                   const aiVector3D* item_positions = nullptr) {
    // The table is far larger than the caches and each item probes a random slot: the slots are
    // fetched this many items ahead (the buckets in a ring), so that the misses overlap.
    constexpr std::size_t ahead = 16;
    const std::uint64_t buckets = reserved_buckets(vertex_count);  // fewer than 2^32 (reserved for a mesh's vertices)
    Join out;
    positions.clear();
    // The numbering and the positions from `items` on (at most one unique vertex per item: never
    // grown and copied); before it, item i is unique vertex i.
    const auto number = [&](std::size_t items) {
        detail::reserve_in_huge_pages(out.unique, count);
        out.unique.resize(count);
        detail::reserve_in_huge_pages(out.first, count);
        detail::reserve_in_huge_pages(positions, count);
        for (std::uint32_t i = 0; i < items; ++i) out.unique[i] = out.first.emplace_back(i);
        positions.assign(item_positions, item_positions + items);
    };
    bool identity = item_positions != nullptr;
    if (!identity) number(0);
    const aiVector3D* unique_positions = identity ? item_positions : positions.data();  // positions: reserved, never moved
    std::uint32_t uniques = 0;
    const std::size_t slots = std::bit_ceil(std::max<std::size_t>(16, 2 * count));
    const int shift = 64 - std::countr_zero(slots);
    // bucket << 32 | unique + 1. From the heap, not a mapping of its own: freed, its pages are taken
    // by the next arrays (the conversion's positions), not fresh ones ("Loading OBJ, session 15" in
    // docs/BENCHMARKS.md); in 2 MB pages where they are fresh (random probes).
    const std::unique_ptr<std::uint64_t[], void (*)(void*)> table_owner(
        static_cast<std::uint64_t*>(std::calloc(slots, sizeof(std::uint64_t))), &std::free);
    if (!table_owner) throw std::bad_alloc();
    std::uint64_t* const table = table_owner.get();
    detail::advise_huge_pages(table, slots * sizeof(std::uint64_t));
    const std::size_t mask = slots - 1;
    // A bucket's first slot: its number spread over the table.
    const auto slot_of = [&](std::uint64_t bucket) { return static_cast<std::size_t>(bucket * 0x9E3779B97F4A7C15ull >> shift); };
    const Remainder bucket_remainder(buckets);
    const auto bucket_of = [&](std::size_t i) { return bucket_remainder.of(assimp_position_hash(value(i).position)); };
    std::uint64_t ring[ahead];
    for (std::size_t i = 0; i < std::min(count, ahead); ++i) {
        ring[i] = bucket_of(i);
        __builtin_prefetch(&table[slot_of(ring[i])]);
    }
    for (std::size_t i = 0; i < count; ++i) {
        const JoinVertex v = value(i);
        const std::uint64_t bucket = ring[i % ahead];
        if (i + ahead < count) {
            ring[i % ahead] = bucket_of(i + ahead);
            __builtin_prefetch(&table[slot_of(ring[i % ahead])]);
        }
        // Half-way, the slot fetched for an item is read: a unique vertex of its bucket there is
        // compared by position, which is fetched now (a random read of its own).
        if (i + ahead / 2 < count) {
            const std::uint64_t later = ring[(i + ahead / 2) % ahead], there = table[slot_of(later)];
            if (there >> 32 == later && there != 0) __builtin_prefetch(unique_positions + static_cast<std::uint32_t>(there) - 1);
        }
        std::size_t slot = slot_of(bucket);
        for (; table[slot] != 0; slot = (slot + 1) & mask) {
            if (table[slot] >> 32 != bucket) continue;
            const std::uint32_t u = static_cast<std::uint32_t>(table[slot]) - 1;
            // Far apart positions compare unequal whatever the rest (assimp_equal): only near ones
            // read the rest of the unique vertex.
            if ((unique_positions[u] - v.position).SquareLength() > 2e-10f) continue;
            const JoinVertex w = value(identity ? u : out.first[u]);
            if (join_detail::same(w, v)) break;
            if (assimp_equal(w, v, 2e-10f)) return std::nullopt;
        }
        if (table[slot] == 0) {
            ++uniques;
            if (!identity) {
                out.first.push_back(static_cast<std::uint32_t>(i));
                positions.push_back(v.position);
            }
            table[slot] = bucket << 32 | uniques;
        } else if (identity) {
            // The first item joined to an earlier one: the numbering of the items before it made.
            number(i);
            identity = false;
            unique_positions = positions.data();
        }
        if (!identity) out.unique[i] = static_cast<std::uint32_t>(table[slot]) - 1;
    }
    out.identity = identity;
    return out;
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
