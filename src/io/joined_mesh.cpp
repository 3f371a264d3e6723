// facet io: assimp's vertex joining and facet's renumbering, exactly (joined_mesh.hpp).
#include "io/joined_mesh.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <utility>

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

constexpr std::uint32_t k_none = ~0u;

// Runs task(i) for i in [0, n), on the pool's threads when there is one.
template <class Task>
void for_each_part(detail::ThreadPool* pool, std::size_t n, const Task& task) {
    if (pool && n > 1)
        pool->parallel_for(n, task);
    else
        for (std::size_t i = 0; i < n; ++i) task(i);
}

// [begin, end) of part p of n over `count` items.
std::pair<std::size_t, std::size_t> part_range(std::size_t count, std::size_t p, std::size_t n) {
    return {count * p / n, count * (p + 1) / n};
}

// For each used vertex, the first used vertex in file order at the same position (its group's
// representative, as in assimp's JoinIdenticalVertices); unused vertices keep k_none. Nullopt when
// two used positions share a key but are not equal. With `parts` parts, part p takes the vertices
// whose hash's top byte falls in its share, in file order, in a table of its own: equal keys have
// equal hashes, so each group is found whole by one part, and its first vertex is the same.
std::optional<std::vector<std::uint32_t>> join_used_vertices(const std::vector<Vec3>& positions,
                                                             const std::vector<std::uint32_t>& indices,
                                                             detail::ThreadPool* pool, std::size_t parts) {
    std::vector<std::uint32_t> representative(positions.size(), k_none);
    for_each_part(pool, parts, [&](std::size_t p) {  // marks the used ones (several parts may store the same 0)
        const auto [begin, end] = part_range(indices.size(), p, parts);
        for (std::size_t c = begin; c < end; ++c) std::atomic_ref(representative[indices[c]]).store(0, std::memory_order_relaxed);
    });
    const std::size_t capacity = std::bit_ceil(2 * positions.size());  // any part may hold them all
    std::vector<char> declined(parts, 0);
    for_each_part(pool, parts, [&](std::size_t p) {
        std::vector<std::uint32_t> table(capacity, k_none);  // open addressing, linear probing
        for (std::uint32_t v = 0; v < positions.size(); ++v) {
            // Another part's vertices are not read: their parts write them meanwhile.
            const std::uint64_t h = position_hash(positions[v]);
            if ((h >> 56) * parts >> 8 != p || representative[v] == k_none) continue;
            for (std::size_t slot = h & (capacity - 1);; slot = (slot + 1) & (capacity - 1)) {
                if (table[slot] == k_none) {
                    table[slot] = v;
                    representative[v] = v;
                    break;
                }
                if (same_key(positions[table[slot]], positions[v])) {
                    if (!same_position(positions[table[slot]], positions[v])) {
                        declined[p] = 1;
                        return;
                    }
                    representative[v] = table[slot];
                    break;
                }
            }
        }
    });
    if (std::find(declined.begin(), declined.end(), 1) != declined.end()) return std::nullopt;
    return representative;
}

// True when no two of `positions` share a key (most files: a join that joins nothing). The table's
// slots are fetched this many positions ahead, so that their misses overlap; each holds 32 bits of
// its position's hash beside its index, so that a probe past another position rarely reads it.
bool distinct_keys(const std::vector<Vec3>& positions) {
    constexpr std::size_t ahead = 16;
    const std::size_t n = positions.size();
    const std::size_t capacity = std::bit_ceil(2 * n + 2);
    std::vector<std::uint64_t> table(capacity, 0);  // the hash's top 32 bits << 32 | index + 1 (0: empty)
    std::uint64_t* const slots = table.data();
    const Vec3* const p = positions.data();
    std::uint64_t ring[ahead];
    for (std::size_t i = 0; i < std::min(n, ahead); ++i) {
        ring[i] = position_hash(p[i]);
        __builtin_prefetch(&slots[ring[i] & (capacity - 1)]);
    }
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint64_t h = ring[i % ahead];
        if (i + ahead < n) {
            ring[i % ahead] = position_hash(p[i + ahead]);
            __builtin_prefetch(&slots[ring[i % ahead] & (capacity - 1)]);
        }
        const std::uint64_t tag = h >> 32 << 32;
        for (std::size_t slot = h & (capacity - 1);; slot = (slot + 1) & (capacity - 1)) {
            const std::uint64_t entry = slots[slot];
            if (entry == 0) {
                slots[slot] = tag | (i + 1);
                break;
            }
            if ((entry & ~std::uint64_t{0xFFFFFFFF}) == tag && same_key(p[static_cast<std::uint32_t>(entry) - 1], p[i])) return false;
        }
    }
    return true;
}

// The mesh of positions whose keys are all distinct: each group is one vertex, its own
// representative, so the used vertices are numbered in order of first use, in one pass.
JoinedMesh number_by_first_use(const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& indices) {
    JoinedMesh out;
    out.indices.resize(indices.size());
    out.source.resize(positions.size() + 1);  // written at `used` at every corner
    std::vector<std::uint32_t> number(positions.size(), k_none);  // each used file vertex's
    const std::uint32_t* const in = indices.data();
    std::uint32_t* const to = out.indices.data();
    std::uint32_t* const numbers = number.data();
    std::uint32_t* const source = out.source.data();
    std::uint32_t used = 0;
    const auto number_of = [&](std::uint32_t v) {
        // Without a branch: a vertex's first use comes every sixth corner or so, at no pattern.
        const std::uint32_t n = numbers[v];
        const bool first = n == k_none;
        source[used] = v;
        const std::uint32_t m = first ? used : n;
        numbers[v] = m;
        used += first;
        return m;
    };
    const std::size_t triangles = indices.size() / 3;
    std::size_t degenerate = 0;
    for (std::size_t t = 0; t < triangles; ++t) {
        const std::uint32_t a = number_of(in[3 * t]), b = number_of(in[3 * t + 1]), c = number_of(in[3 * t + 2]);
        to[3 * t] = a, to[3 * t + 1] = b, to[3 * t + 2] = c;
        degenerate += a == b || b == c || c == a;
    }
    for (std::size_t c = 3 * triangles; c < indices.size(); ++c) to[c] = number_of(in[c]);
    out.source.resize(used);
    out.positions.resize(used);
    for (std::size_t i = 0; i < used; ++i) out.positions[i] = positions[source[i]];
    out.degenerate = degenerate;
    return out;
}

}  // namespace

std::optional<JoinedMesh> join_identical_vertices(const std::vector<Vec3>& file_positions,
                                                  const std::vector<std::uint32_t>& file_indices, detail::ThreadPool* pool) {
    // Threads share the work only where each has enough of it.
    const std::size_t parts = pool && file_indices.size() >= 3 * 8192 ? static_cast<std::size_t>(pool->size()) : 1;
    if (parts == 1 && distinct_keys(file_positions)) return number_by_first_use(file_positions, file_indices);
    const std::optional<std::vector<std::uint32_t>> joined = join_used_vertices(file_positions, file_indices, pool, parts);
    if (!joined) return std::nullopt;
    const std::vector<std::uint32_t>& representative = *joined;
    // Numbered in order of first use: the first part numbers its representatives as it meets them;
    // each later part numbers them among its own, and those are then renumbered in part order
    // (a representative a part before met keeps its number, the others take the next ones).
    JoinedMesh out;
    out.indices.resize(file_indices.size());
    // Per part: each representative's number there, and the representatives in that order.
    std::vector<std::vector<std::uint32_t>> number(parts), order(parts);
    for_each_part(pool, parts, [&](std::size_t p) {
        number[p].assign(file_positions.size(), k_none);
        const auto [begin, end] = part_range(file_indices.size(), p, parts);
        for (std::size_t c = begin; c < end; ++c) {
            const std::uint32_t r = representative[file_indices[c]];
            if (number[p][r] == k_none) {
                number[p][r] = static_cast<std::uint32_t>(order[p].size());
                order[p].push_back(r);
            }
            out.indices[c] = number[p][r];
        }
    });
    std::vector<std::vector<std::uint32_t>> final_number(parts);  // per part: its own number -> the final one
    std::vector<std::uint32_t>& first = number[0];                  // becomes the final numbers
    std::vector<std::uint32_t> numbered = order[0];                 // the representatives in final order
    for (std::size_t p = 1; p < parts; ++p)
        for (const std::uint32_t r : order[p]) {
            if (first[r] == k_none) {
                first[r] = static_cast<std::uint32_t>(numbered.size());
                numbered.push_back(r);
            }
            final_number[p].push_back(first[r]);
        }
    for_each_part(pool, parts, [&](std::size_t p) {
        const auto [begin, end] = part_range(file_indices.size(), p, parts);
        if (p > 0)
            for (std::size_t c = begin; c < end; ++c) out.indices[c] = final_number[p][out.indices[c]];
    });
    out.positions.resize(numbered.size());
    for (std::size_t i = 0; i < numbered.size(); ++i) out.positions[i] = file_positions[numbered[i]];
    out.source = std::move(numbered);
    const std::size_t triangles = out.indices.size() / 3;
    std::vector<std::size_t> degenerate(parts, 0);
    for_each_part(pool, parts, [&](std::size_t p) {
        const auto [begin, end] = part_range(triangles, p, parts);
        for (std::size_t t = begin; t < end; ++t) {
            const std::uint32_t a = out.indices[3 * t], b = out.indices[3 * t + 1], c = out.indices[3 * t + 2];
            degenerate[p] += a == b || b == c || c == a;
        }
    });
    for (const std::size_t d : degenerate) out.degenerate += d;
    return out;
}

}  // namespace facet::io_detail
