// facet scene: creased normals for meshes without them (compute_creased_normals, facet/mesh.hpp). In:
// positions and triangles. Out: a normal per vertex, vertices copied where a crease splits them.
// Vertices are welded by position, each triangle described once (face normal, corner angles:
// triangle_shapes.hpp), each position's fan split into sets of faces that meet at less than the
// crease angle, and each set's normal given to its vertices. Positions are independent, so large
// meshes share the work between threads with the same result. The specification is the sort-based
// version in tests/support/reference_creased_normals.cpp.
#include "facet/mesh.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cmath>
#include <limits>
#include <memory>
#include <new>
#include <numeric>
#include <optional>
#include <span>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "exec/fresh_pages.hpp"
#include "facet/detail/thread_pool.hpp"
#include "math/portable_trig.hpp"
#include "scene/creased_normals.hpp"
#include "scene/triangle_shapes.hpp"

namespace facet {

namespace {

// Welding for crease detection: positions are compared by their bit patterns (-0 as +0), so
// vertices that are only duplicated by position (STL, seams in uv or colour) count as shared, and
// NaN is no trouble.
struct PositionKey {
    std::uint32_t x, y, z;
    bool operator==(const PositionKey&) const = default;
};

PositionKey key_of(Vec3 p) {
    auto bits = [](float f) { return std::bit_cast<std::uint32_t>(f == 0.0f ? 0.0f : f); };
    return {bits(p.x), bits(p.y), bits(p.z)};
}

std::uint64_t hash_of(const PositionKey& k) {
    std::uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
    h = (h ^ k.y) * 0xC2B2AE3D27D4EB4Full;
    h = (h ^ k.z) * 0x165667B19E3779F9ull;
    return h ^ (h >> 29);
}

using detail::ZeroedArray;

// An id per distinct position (in order of first appearance), and each id's key.
struct Weld {
    std::vector<std::uint32_t> id;   // per vertex
    std::vector<PositionKey> key;    // per id
};

Weld weld_by_position(const std::vector<Vec3>& positions) {
    // The table is far larger than the caches and each vertex probes a random slot: slots are
    // fetched this many vertices ahead (the hashes in a ring), so that the misses overlap, and each
    // holds 32 bits of its key's hash beside the id, so that a probe past another position rarely
    // reads that position's key.
    constexpr std::size_t ahead = 16;
    Weld w;
    w.id.resize(positions.size());
    w.key.reserve(positions.size());
    const std::size_t capacity = std::bit_ceil(2 * positions.size() + 2);
    const ZeroedArray<std::uint64_t> table(capacity);  // open addressing: tag << 32 | id + 1 (0: empty), linear probing
    std::uint64_t ring[ahead];
    for (std::size_t v = 0; v < std::min(positions.size(), ahead); ++v) {
        ring[v] = hash_of(key_of(positions[v]));
        __builtin_prefetch(&table[ring[v] & (capacity - 1)]);
    }
    for (std::size_t v = 0; v < positions.size(); ++v) {
        const PositionKey k = key_of(positions[v]);
        const std::uint64_t h = ring[v % ahead];
        if (v + ahead < positions.size()) {
            ring[v % ahead] = hash_of(key_of(positions[v + ahead]));
            __builtin_prefetch(&table[ring[v % ahead] & (capacity - 1)]);
        }
        const std::uint64_t tag = h >> 32 << 32;
        for (std::size_t slot = h & (capacity - 1);; slot = (slot + 1) & (capacity - 1)) {
            if (table[slot] == 0) {
                table[slot] = tag | (w.key.size() + 1);
                w.key.push_back(k);
            }
            const auto id = static_cast<std::uint32_t>(table[slot]) - 1;
            if ((table[slot] & ~std::uint64_t{0xFFFFFFFF}) == tag && w.key[id] == k) {
                w.id[v] = id;
                break;
            }
        }
    }
    return w;
}

// A vertex's welded position: its id in a weld, or the vertex itself where the positions are
// distinct (no array of ids to fill and fetch from).
struct WeldIds {
    const std::uint32_t* id = nullptr;  // null: each vertex its own position
    std::uint32_t operator[](std::uint32_t v) const { return id ? id[v] : v; }
};

// Which triangles have all three indices in range (the others are left out): most meshes have
// all, and then there are no bits to fetch and test per triangle.
struct InRange {
    std::vector<bool> bits;  // empty: all
    std::size_t triangles = 0;
    bool all() const { return bits.empty(); }
    bool operator[](std::size_t t) const { return bits.empty() || bits[t]; }
    std::size_t size() const { return triangles; }
};

// Work is handed out in blocks of this many triangles or welded positions: large enough that a
// block costs far more than handing it out, small enough to share a mesh between the threads.
constexpr std::size_t k_block = 4096;
// Positions for the fans' split in smaller blocks: a position costs more than a triangle, and with
// 4096 the last block handed out kept the other thread waiting (the bunny has 10 such blocks).
constexpr std::size_t k_split_block = 2048;

// Runs block(begin, end, worker) over [0, count) in blocks, on the pool's threads when there is
// one, and beside() as a task of its own, the first handed out: a serial pass that the blocks need
// not wait for. Every block writes only its own items, so the result does not depend on the threads.
template <class Block, class Beside = void (*)()>
void for_blocks(detail::ThreadPool* pool, std::size_t count, const Block& block, const Beside& beside = [] {},
                std::size_t block_size = k_block) {
    const std::size_t blocks = (count + block_size - 1) / block_size;
    auto run = [&](std::size_t task, int worker) {
        if (task == 0) return beside();
        const std::size_t b = task - 1;
        block(b * block_size, std::min(count, (b + 1) * block_size), worker);
    };
    if (pool)
        pool->parallel_for(blocks + 1, run);
    else
        for (std::size_t task = 0; task <= blocks; ++task) run(task, 0);
}

// The corners of the valid triangles grouped by welded position: the corners at position w are
// corner[start[w] .. start[w + 1]), in increasing order (a counting sort). A corner is numbered
// 4 * triangle + k here (k_corner_shift), not 3 * triangle + k as elsewhere: the split finds its
// triangle and k by a shift and a mask instead of a division and a remainder by 3 (the same order).
constexpr std::uint32_t k_corner_shift = 2;
// At most this many triangles, so that 4 * triangle + k fits in 32 bits (more: one thread).
constexpr std::size_t k_max_grouped_triangles = std::size_t{1} << 30;
std::uint32_t triangle_of(std::uint32_t grouped) { return grouped >> k_corner_shift; }
std::uint32_t k_of(std::uint32_t grouped) { return grouped & ((1u << k_corner_shift) - 1); }
// The corner's number as everything but the split has it.
std::uint32_t corner_of(std::uint32_t grouped) { return 3 * triangle_of(grouped) + k_of(grouped); }
// The record of a grouped corner's triangle: at byte (4 * triangle) * (sizeof(Facts) / 4), one mask
// from the corner's number instead of a shift down and one up.
template <class Facts>
const Facts& facts_of(const Facts* triangles, std::uint32_t grouped) {
    static_assert(sizeof(Facts) % (1u << k_corner_shift) == 0);
    const std::size_t at = std::size_t{grouped & ~((1u << k_corner_shift) - 1)} * (sizeof(Facts) >> k_corner_shift);
    return *reinterpret_cast<const Facts*>(reinterpret_cast<const char*>(triangles) + at);
}
struct CornersByPosition {
    std::vector<std::uint32_t> start;
    std::vector<std::uint32_t> corner;
};

// position_of(v): vertex v's welded position.
template <class PositionOf>
CornersByPosition group_corners(const Mesh& mesh, const PositionOf& position_of, std::size_t positions,
                                const InRange& in_range) {
    CornersByPosition out;
    // Counted two places ahead: after the sums start[w + 1] is where position w's corners begin,
    // and placing them moves it to where they end, i.e. where w + 1's begin (no second array).
    // By triangle, not by corner: one validity test per triangle and no division.
    // Where every triangle is valid (most meshes), no test per triangle: the counts' stores could
    // alias in_range's, which the compiler then read again for each triangle.
    out.start.assign(positions + 2, 0);
    const std::size_t triangles = in_range.size();
    const bool all = in_range.all();
    const std::uint32_t* index = mesh.indices.data();
    std::uint32_t* start = out.start.data();
    if (all)
        for (std::size_t c = 0; c < 3 * triangles; ++c) ++start[position_of(index[c]) + 2];
    else
        for (std::size_t t = 0; t < triangles; ++t)
            if (in_range[t])
                for (std::size_t c = 3 * t; c < 3 * t + 3; ++c) ++start[position_of(index[c]) + 2];
    for (std::size_t w = 2; w < positions + 2; ++w) start[w] += start[w - 1];
    out.corner.resize(start[positions + 1]);
    std::uint32_t* corner = out.corner.data();
    for (std::size_t t = 0; t < triangles; ++t)
        if (all || in_range[t])
            for (std::uint32_t k = 0; k < 3; ++k)
                corner[start[position_of(index[3 * t + k]) + 1]++] = static_cast<std::uint32_t>(t << k_corner_shift) + k;
    out.start.pop_back();
    return out;
}

// What the corners of one valid triangle need when their positions are worked on, written in
// triangle order and read from the positions' side, where each position's corners are of
// triangles far apart in most files (prefetched: see split_fans). A record per triangle written
// in order, rather than a record per corner scattered to its position's place: describing the
// bunny's triangles took 3.75 ms instead of 6.0 at 1 thread (both with scalar math). Also
// measured, and slower: each corner describing its triangle again from the position's side, with
// no records (+1.3 ms of 5.8), and records without the vertices and welded positions, fetched
// from the index and weld arrays instead (24 bytes a triangle instead of 48: +1.1 ms).
// Whether a face's squared length is within 4e-6 of 1 (FirstFaceTest).
bool unit_length(Vec3 face) { return std::fabs(dot(face, face) - 1.0f) <= 4e-6f; }

// Plain floats: the array is not zeroed first.
struct TriangleFacts {
    float face[3];              // the triangle's normal, zero if degenerate
    float angle[3];             // the corners' angles, zero if degenerate
    std::uint32_t position[3];  // the corners' welded positions
    std::uint32_t vertex[3];    // and vertices

    static TriangleFacts make(TriangleFacts facts, const std::uint32_t* idx, WeldIds weld) {
        for (int k = 0; k < 3; ++k) facts.position[k] = weld[idx[k]], facts.vertex[k] = idx[k];
        return facts;
    }
    std::uint32_t vertex_at(std::uint32_t k) const { return vertex[k]; }
    bool unit_face() const { return unit_length({face[0], face[1], face[2]}); }
    std::uint32_t next_at(std::uint32_t k) const { return position[(k + 1) % 3]; }
    std::uint32_t prev_at(std::uint32_t k) const { return position[(k + 2) % 3]; }
    static constexpr bool k_own_positions = false;  // vertex_at(k) need not be the position's vertex
};

// The same in 32 bytes where each vertex is its own position (no weld) and there are at most
// k_packed_vertices: the three vertices in 21 bits each, and aligned so that none spans two cache
// lines. A third less to write while describing, and to fetch back by position.
constexpr std::uint32_t k_packed_bits = 21;
constexpr std::size_t k_packed_vertices = std::size_t{1} << k_packed_bits;
struct alignas(32) PackedFacts {
    float face[3];
    float angle[3];
    std::uint64_t vertices;  // vertex k at bits 21k; bit 63: unit_length(face)

    static PackedFacts make(const TriangleFacts& facts, const std::uint32_t* idx, WeldIds) {
        PackedFacts out;
        for (int k = 0; k < 3; ++k) out.face[k] = facts.face[k], out.angle[k] = facts.angle[k];
        out.vertices = idx[0] | std::uint64_t{idx[1]} << k_packed_bits | std::uint64_t{idx[2]} << 2 * k_packed_bits |
                       std::uint64_t{facts.unit_face()} << 63;
        return out;
    }
    // Found once while describing rather than at each of the face's three corners in the split.
    bool unit_face() const { return vertices >> 63; }
    std::uint32_t vertex_at(std::uint32_t k) const {
        return static_cast<std::uint32_t>(vertices >> k_packed_bits * k) & (k_packed_vertices - 1);
    }
    // The positions at the other ends of corner k's sides (k + 1 and k + 2), by a shift from a table.
    std::uint32_t next_at(std::uint32_t k) const { return field(k_next_shift[k]); }
    std::uint32_t prev_at(std::uint32_t k) const { return field(k_prev_shift[k]); }
    static constexpr std::uint8_t k_next_shift[3] = {k_packed_bits, 2 * k_packed_bits, 0};
    static constexpr std::uint8_t k_prev_shift[3] = {2 * k_packed_bits, 0, k_packed_bits};
    std::uint32_t field(std::uint32_t shift) const {
        return static_cast<std::uint32_t>(vertices >> shift) & (k_packed_vertices - 1);
    }
    // A corner's vertex is the position it is at: known to whoever works on that position.
    static constexpr bool k_own_positions = true;
};
static_assert(sizeof(PackedFacts) == 32);

// A corner's angle from its triangle's normalized sides (side k from corner k to k + 1): the
// corner at k sees sides k and k + 2 reversed, and normalize(-v) is exactly -normalize(v).
float corner_angle(Vec3 side_out, Vec3 side_in) { return detail::corner_acos(clamp(dot(side_out, -side_in), -1.0f, 1.0f)); }

// The face normal and the corner angles of a triangle, as the specification computes them: for
// the triangles the shape kernel leaves out, and for all of them with the scalar ISA.
void describe_triangle(const Vec3 (&p)[3], TriangleFacts& out) {
    const Vec3 face = normalize(cross(p[1] - p[0], p[2] - p[0]));
    float angle[3] = {0, 0, 0};
    if (dot(face, face) > 0) {  // degenerate: no weight anywhere (and no NaN angles)
        const Vec3 side[3] = {normalize(p[1] - p[0]), normalize(p[2] - p[1]), normalize(p[0] - p[2])};
        for (int k = 0; k < 3; ++k) angle[k] = corner_angle(side[k], side[(k + 2) % 3]);
    }
    for (int k = 0; k < 3; ++k) out.face[k] = face[k], out.angle[k] = angle[k];
}

// The chunk of triangles from `first` on, as the shape kernel reads them; places without a valid
// triangle get zeros.
template <bool All>
void fill_chunk(const Mesh& mesh, const InRange& in_range, std::size_t first, std::size_t count,
                detail::TriangleChunk& chunk) {
    if constexpr (All) {  // no test per triangle: the chunk's triangles, then zeros
        const std::uint32_t* index = mesh.indices.data() + 3 * first;
        const Vec3* position = mesh.positions.data();
        for (std::size_t i = 0; i < count; ++i)
            for (int k = 0; k < 3; ++k) {
                const Vec3 p = position[index[3 * i + k]];
                chunk.corner[k][0][i] = p.x, chunk.corner[k][1][i] = p.y, chunk.corner[k][2][i] = p.z;
            }
        for (std::size_t i = count; i < detail::TriangleChunk::k_capacity; ++i)
            for (int k = 0; k < 3; ++k) chunk.corner[k][0][i] = chunk.corner[k][1][i] = chunk.corner[k][2][i] = 0.0f;
        return;
    }
    for (std::size_t i = 0; i < detail::TriangleChunk::k_capacity; ++i) {
        const bool valid = i < count && in_range[first + i];
        for (int k = 0; k < 3; ++k) {
            const Vec3 p = valid ? mesh.positions[mesh.indices[3 * (first + i) + k]] : Vec3{};
            for (int axis = 0; axis < 3; ++axis) chunk.corner[k][axis][i] = p[axis];
        }
    }
}

// described(t, facts) for each valid triangle of [first, last), in order, with its face and
// angles (the other fields not filled). The kernel does the normalizations, the cosines and their
// arc cosines in lanes.
// ahead(t) is called for the chunk's valid triangles before the kernel shapes them.
template <bool All, class Described, class Ahead>
void describe_range_of(const Mesh& mesh, const InRange& in_range, std::size_t first, std::size_t last,
                       const Described& described, const Ahead& ahead) {
    const auto valid = [&](std::size_t t) { return All || in_range[t]; };
    constexpr std::size_t chunk_size = detail::TriangleChunk::k_capacity;
    detail::TriangleChunk chunk;
    for (std::size_t begin = first; begin < last; begin += chunk_size) {
        const std::size_t count = std::min(chunk_size, last - begin);
        for (std::size_t t = begin; t < begin + count; ++t)
            if (valid(t)) ahead(t);
        fill_chunk<All>(mesh, in_range, begin, count, chunk);
        const bool shaped = detail::shape_triangles(chunk);
        for (std::size_t i = 0; i < count; ++i) {
            const std::size_t t = begin + i;
            if (!valid(t)) continue;
            TriangleFacts facts;
            if (shaped && !(chunk.unusual >> i & 1)) {
                for (int k = 0; k < 3; ++k)
                    facts.face[k] = chunk.face[k][i], facts.angle[k] = chunk.angle[k][i];
            } else {
                Vec3 p[3];
                for (int k = 0; k < 3; ++k)
                    for (int axis = 0; axis < 3; ++axis) p[k][axis] = chunk.corner[k][axis][i];
                describe_triangle(p, facts);
            }
            described(t, facts);
        }
    }
}
// Nothing fetched ahead, inlined (a function pointer was an indirect call per triangle: 4% of the
// bunny's samples at 2 threads).
struct NothingAhead {
    void operator()(std::size_t) const {}
};
template <class Described, class Ahead = NothingAhead>
void describe_range(const Mesh& mesh, const InRange& in_range, std::size_t first, std::size_t last,
                    const Described& described, const Ahead& ahead = {}) {
    if (in_range.all())
        describe_range_of<true>(mesh, in_range, first, last, described, ahead);
    else
        describe_range_of<false>(mesh, in_range, first, last, described, ahead);
}

// The facts of every valid triangle, for sharing the positions between threads. The corners are
// grouped by position beside it (it reads nothing this writes), on another thread: 0.3 ms less of
// 4.0 ms at 2 threads on the bunny.
template <class Facts>
void describe_triangles(const Mesh& mesh, WeldIds weld, std::size_t positions,
                        const InRange& in_range, detail::ThreadPool* pool, Facts* out,
                        CornersByPosition& by_position) {
    auto describe_block = [&](std::size_t first, std::size_t last, int) {
        describe_range(mesh, in_range, first, last, [&](std::size_t t, const TriangleFacts& facts) {
            out[t] = Facts::make(facts, mesh.indices.data() + 3 * t, weld);
        });
    };
    for_blocks(pool, in_range.size(), describe_block, [&] {
        if (weld.id)
            by_position = group_corners(mesh, [&](std::uint32_t v) { return weld.id[v]; }, positions, in_range);
        else
            by_position = group_corners(mesh, [](std::uint32_t v) { return v; }, positions, in_range);
    });
}

// One corner with area at the position being worked on, gathered from its triangle's facts.
struct FanCorner {
    std::uint32_t corner, vertex;
    std::uint32_t next_position, prev_position;  // welded positions of the triangle's other corners
    Vec3 face;
    Vec3 weighted;  // face * the corner's angle
};

// One triangle side that ends at the position being worked on: the position at its other end,
// the side's number (3 * triangle + k for the side from corner k to corner k + 1, the order in
// which the sides of an edge are compared) and which of the position's corners it ends at.
struct SideAt {
    std::uint32_t other, side, local_corner;
    bool operator<(const SideAt& b) const { return other != b.other ? other < b.other : side < b.side; }
};

// A corner whose vertex already has the normal of another set: it needs a copy of the vertex, and
// copies are numbered in corner order over the whole mesh, so the requests are collected here and
// granted at the end.
struct CopyRequest {
    std::uint32_t corner, vertex, set;
    Vec3 normal;
};

// Fans of up to this many corners (with area) are split with a bit per corner (split_by_all_pairs).
constexpr std::size_t k_max_mask_fan = 64;

// A thread's scratch memory, kept from one position to the next.
struct FanScratch {
    std::vector<FanCorner> corners;
    std::vector<std::uint32_t> root;  // per corner: the local index of its set's first corner
    std::vector<SideAt> sides;
    std::vector<std::uint32_t> parent;  // union-find over the position's corners, by local index
    std::array<std::uint64_t, k_max_mask_fan> smooth_neighbours;  // per corner: the corners joined with it
    std::vector<Vec3> sum;            // per set, by its root: the sum of its corners, then its normal
    std::vector<CopyRequest> copies;  // from all the thread's positions

    std::uint32_t find(std::uint32_t c) {
        while (parent[c] != c) c = parent[c] = parent[parent[c]];
        return c;
    }
    // The root of a set is its smallest local index, i.e. its smallest corner, whatever the
    // order of the joins.
    void join(std::uint32_t a, std::uint32_t b) {
        a = find(a), b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

// Faces on one edge are compared pairwise only with this many predecessors, so a non-manifold
// edge shared by thousands of triangles stays linear; ordinary edges have two faces.
constexpr std::size_t k_max_edge_neighbours = 8;

// The position's corners with area, in corner order, and the sum of their weighted faces
// (corner_of(c): the corner's FanCorner, its face zero when its triangle has no area). Corners of
// degenerate triangles are left out: they are on no edge and alone in their sets, whose normal is
// zero (which leaves their vertices to the other corners), and they add +0 to sums that start at
// +0 (and so are never -0), which changes nothing.
template <class CornerOf>
Vec3 gather_fan(std::span<const std::uint32_t> corners, const CornerOf& corner_of, std::vector<FanCorner>& out) {
    out.clear();
    Vec3 around{};
    for (const std::uint32_t c : corners) {
        const FanCorner corner = corner_of(c);
        if (!(dot(corner.face, corner.face) > 0)) continue;
        out.push_back(corner);
        around += corner.weighted;
    }
    return around;
}

// A corner as gather_fan takes it, from its triangle's facts (grouped: its number in CornersByPosition).
template <class Facts>
FanCorner corner_from_facts(std::uint32_t grouped, const Facts& t) {
    const std::uint32_t k = k_of(grouped);
    const Vec3 face{t.face[0], t.face[1], t.face[2]};
    return {corner_of(grouped), t.vertex_at(k), t.next_at(k), t.prev_at(k), face, face * t.angle[k]};
}

// Whether no edge has more sides than one is compared with (k_max_edge_neighbours), i.e. whether
// every pair of sides on an edge is compared: true for all but the few non-manifold edges.
bool all_pairs_within_reach(const std::vector<SideAt>& sides) {
    for (std::size_t i = 1; i < sides.size(); ++i) {
        std::size_t same = 0;
        for (std::size_t j = 0; j < i; ++j) same += sides[i].other == sides[j].other;
        if (same > k_max_edge_neighbours) return false;
    }
    return true;
}

// A triangle with area has three distinct welded positions (two equal ones make the cross product
// zero), so a corner's two sides end at two positions other than the corner's own.
bool share_a_side(const FanCorner& a, const FanCorner& b) {
    return (a.next_position == b.next_position) | (a.next_position == b.prev_position) |
           (a.prev_position == b.next_position) | (a.prev_position == b.prev_position);
}

// Every pair of corners compared at once (at most k_max_mask_fan of them), and the sets found as
// the connected parts of the graph of the pairs that share a side at less than the crease angle,
// the first corner of each part its root. Returns the number of sets; with one, s.root is not
// filled (no root to look up).
std::size_t split_by_all_pairs(float cos_crease, FanScratch& s) {
    const std::vector<FanCorner>& c = s.corners;
    const std::size_t n = c.size();
    std::uint64_t* smooth = s.smooth_neighbours.data();
    std::fill_n(smooth, n, 0);
    for (std::size_t i = 1; i < n; ++i) {
        // Without branches, the dot products of the pairs that share no side included: which pairs
        // do is unpredictable (0.25 ms less of 5.7 ms on the bunny at 1 thread than branching).
        std::uint64_t joined = 0;
        for (std::size_t j = 0; j < i; ++j) {
            const bool side = share_a_side(c[i], c[j]), close = dot(c[i].face, c[j].face) > cos_crease;
            const bool join = side & close;
            joined |= std::uint64_t{join} << j;
        }
        smooth[i] |= joined;
        for (std::size_t j = 0; j < i; ++j) smooth[j] |= (joined >> j & 1) << i;
    }
    std::size_t sets = 0;
    for (std::uint64_t left = n == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << n) - 1; left;) {
        const auto root = static_cast<std::uint32_t>(std::countr_zero(left));
        std::uint64_t set = std::uint64_t{1} << root;
        for (std::uint64_t frontier = set; frontier;) {
            const int k = std::countr_zero(frontier);
            const std::uint64_t reached = smooth[k] & ~set;
            set |= reached, frontier = (frontier ^ std::uint64_t{1} << k) | reached;
        }
        left &= ~set;
        if (sets == 0 && !left) return 1;
        for (; set; set &= set - 1) s.root[std::countr_zero(set)] = root;
        ++sets;
    }
    return sets;
}

// Non-manifold edges with more sides than are compared pairwise: the sides of one edge adjacent,
// in the order of their numbers (the keys are unique: no order among equals to keep), each
// compared with its predecessors within reach, and the sets joined by union-find. Returns the
// number of sets.
std::size_t split_within_reach(float cos_crease, FanScratch& s) {
    const std::vector<FanCorner>& corners = s.corners;
    s.parent.resize(corners.size());
    std::iota(s.parent.begin(), s.parent.end(), 0u);
    std::sort(s.sides.begin(), s.sides.end());
    const std::size_t sides = s.sides.size();
    for (std::size_t begin = 0, end = 0; begin < sides; begin = end) {
        end = begin + 1;
        while (end < sides && s.sides[end].other == s.sides[begin].other) ++end;
        for (std::size_t i = begin + 1; i < end; ++i)
            for (std::size_t j = i > begin + k_max_edge_neighbours ? i - k_max_edge_neighbours : begin; j < i; ++j) {
                const std::uint32_t a = s.sides[i].local_corner, b = s.sides[j].local_corner;
                if (dot(corners[a].face, corners[b].face) > cos_crease) s.join(a, b);
            }
    }
    std::size_t sets = 0;
    for (std::uint32_t local = 0; local < corners.size(); ++local) {
        s.root[local] = s.find(local);
        sets += s.root[local] == local;
    }
    return sets;
}

// The position's corners split into sets (s.root, unless there is one set): two corners are in
// one set when their triangles share an edge from the position at less than the crease angle
// (directly or through others). Returns the number of sets.
std::size_t split_into_sets(float cos_crease, FanScratch& s) {
    const std::size_t n = s.corners.size();
    s.root.resize(n);
    // An edge has at most one side per corner: with no more corners than the first side of an edge
    // and its k_max_edge_neighbours successors, every pair of sides is compared.
    if (n <= k_max_edge_neighbours + 1) return split_by_all_pairs(cos_crease, s);
    s.sides.clear();
    for (std::uint32_t local = 0; local < n; ++local) {
        const FanCorner& c = s.corners[local];
        s.sides.push_back({c.next_position, c.corner, local});
        s.sides.push_back({c.prev_position, c.corner / 3 * 3 + (c.corner + 2) % 3, local});
    }
    // When every pair of sides on an edge is compared, the order of the comparisons does not
    // matter: all pairs at once give the same sets.
    if (n <= k_max_mask_fan && all_pairs_within_reach(s.sides)) return split_by_all_pairs(cos_crease, s);
    return split_within_reach(cos_crease, s);
}

// Where the sets' normals go: each vertex takes the normal of the first set among its corners
// (vertex_set: that set's smallest corner), and corners from another set ask for a copy of the
// vertex. Corners without area take whatever their vertex has.
struct VertexNormals {
    std::uint32_t* vertex_set;  // by vertex, from vertex `first` on
    std::uint32_t first;
    std::vector<Vec3>& normals;
    std::uint32_t& set_of(std::uint32_t vertex) const { return vertex_set[vertex - first]; }
};
constexpr std::uint32_t k_no_set = ~0u;

// A set's normal is the angle-weighted sum of its faces in corner order, normalized once (one
// set: the sum of all the corners). All the corners of a vertex are at its position, so the first
// of them here is its first in the mesh.
void assign_set_normals(std::size_t sets, Vec3 around, FanScratch& s, VertexNormals out) {
    const std::vector<FanCorner>& corners = s.corners;
    if (sets == 1) {
        const Vec3 n = normalize(around);
        if (!(dot(n, n) > 0)) return;
        const std::uint32_t set = corners[0].corner;
        for (const FanCorner& c : corners)
            if (out.set_of(c.vertex) == k_no_set) out.set_of(c.vertex) = set, out.normals[c.vertex] = n;
        return;
    }
    s.sum.assign(corners.size(), Vec3{});
    for (std::uint32_t local = 0; local < corners.size(); ++local) s.sum[s.root[local]] += corners[local].weighted;
    for (std::uint32_t local = 0; local < corners.size(); ++local) {
        const std::uint32_t root = s.root[local];
        if (root == local) s.sum[local] = normalize(s.sum[local]);  // roots come first in their sets
        const Vec3 n = s.sum[root];
        if (!(dot(n, n) > 0)) continue;
        const FanCorner& c = corners[local];
        const std::uint32_t set = corners[root].corner;
        std::uint32_t& vertex_set = out.set_of(c.vertex);
        if (vertex_set == k_no_set) {
            vertex_set = set;
            out.normals[c.vertex] = n;
        } else if (vertex_set != set) {
            s.copies.push_back({c.corner, c.vertex, set, n});
        }
    }
}

// The facts of the triangles this many corners ahead are fetched while a position is worked on: far
// enough for the host's slow minutes, when memory answers later (docs/BENCHMARKS.md, session 18).
constexpr std::size_t k_prefetch_corners = 32;

// Whether a fan is one set by the test that settles positions by their sums at one thread (below).
struct FirstFaceTest;
bool one_set_by_first_face(const FirstFaceTest& test, const std::vector<FanCorner>& corners);
template <class Facts>
bool settle_one_set(std::span<const std::uint32_t> corners, const Facts* triangles, const FirstFaceTest& test,
                    std::uint32_t position, Vec3& around, VertexNormals out);

// The corners around each welded position split into sets, and the sets' normals given to the
// vertices. Sets never reach beyond one position, and each vertex is at one, so positions are
// independent of each other. Returns each position's sum of all its corners, the fallback for
// vertices without a set.
template <class Facts>
std::vector<Vec3> split_fans(const CornersByPosition& by_position, const Facts* triangles, float cos_crease,
                             const FirstFaceTest& test, detail::ThreadPool* pool, std::vector<FanScratch>& scratch,
                             VertexNormals out) {
    const std::size_t positions = by_position.start.size() - 1;
    std::vector<Vec3> around(positions);
    for_blocks(pool, positions, [&](std::size_t first, std::size_t last, int worker) {
        FanScratch& s = scratch[worker];
        const std::uint32_t* corner = by_position.corner.data();
        const std::size_t block_end = by_position.start[last];
        for (std::size_t w = first; w < last; ++w) {
            const std::size_t begin = by_position.start[w], end = by_position.start[w + 1];
            for (std::size_t i = begin + k_prefetch_corners; i < std::min(end + k_prefetch_corners, block_end); ++i) {
                // Both ends: half the 48-byte records span two cache lines.
                const auto* facts = reinterpret_cast<const char*>(&facts_of(triangles, corner[i]));
                __builtin_prefetch(facts);
                if constexpr (sizeof(Facts) > 32) __builtin_prefetch(facts + sizeof(Facts) - 1);
            }
            // Most fans are one set that the test finds in a few comparisons, where splitting them
            // compared every pair (the bunny at 2 threads: 61 of the normals' 90 M instructions).
            if (settle_one_set({corner + begin, corner + end}, triangles, test, static_cast<std::uint32_t>(w), around[w], out))
                continue;
            around[w] = gather_fan({corner + begin, corner + end},
                                   [&](std::uint32_t c) { return corner_from_facts(c, triangles[triangle_of(c)]); }, s.corners);
            assign_set_normals(one_set_by_first_face(test, s.corners) ? 1 : split_into_sets(cos_crease, s), around[w], s,
                               out);
        }
    }, [] {}, k_split_block);
    return around;
}

// Vertex copies for the requests, numbered in the order of the requests' corners (the order the
// specification makes them in), one per vertex and set; corners are pointed at them.
void copy_vertices(std::vector<FanScratch>& scratch, Mesh& mesh) {
    std::vector<CopyRequest>& requests = scratch[0].copies;
    for (std::size_t worker = 1; worker < scratch.size(); ++worker)
        requests.insert(requests.end(), scratch[worker].copies.begin(), scratch[worker].copies.end());
    std::sort(requests.begin(), requests.end(),
              [](const CopyRequest& a, const CopyRequest& b) { return a.corner < b.corner; });
    const std::size_t most = mesh.positions.size() + requests.size();
    mesh.positions.reserve(most);
    mesh.normals.reserve(most);
    if (!mesh.colours.empty()) mesh.colours.reserve(most);
    if (!mesh.uvs.empty()) mesh.uvs.reserve(most);
    std::unordered_map<std::uint64_t, std::uint32_t> copies;  // (vertex << 32 | set) -> new vertex
    for (const CopyRequest& r : requests) {
        auto [it, inserted] = copies.try_emplace(std::uint64_t{r.vertex} << 32 | r.set, 0u);
        if (inserted) {
            it->second = static_cast<std::uint32_t>(mesh.positions.size());
            mesh.positions.push_back(mesh.positions[r.vertex]);
            mesh.normals.push_back(r.normal);
            if (!mesh.colours.empty()) mesh.colours.push_back(mesh.colours[r.vertex]);
            if (!mesh.uvs.empty()) mesh.uvs.push_back(mesh.uvs[r.vertex]);
        }
        mesh.indices[r.corner] = it->second;
    }
}

// One thread goes another way, with no facts per triangle (48 MB for the 1M sphere, which cost
// more to fault in and fetch back by position than to compute): the triangles are described in
// order and each corner's weighted face added to its position's sum at once (corner order, which
// is the order the fans sum in: the same bits), and most positions are settled by that sum alone.
// Per welded position:
struct PositionSums {  // 64 bytes: a cache line
    Vec3 around;  // the sum of its corners' weighted faces (with area), in corner order
    Vec3 first;   // the face of its first corner with area
    std::uint32_t faces;  // its corners with area, and k_rough or k_far
    // The sides of its first corners with area (their other ends' welded positions, less this
    // one's: a cache line holds it all); k_far when one does not fit.
    struct Sides {
        std::int16_t next[k_max_edge_neighbours + 1], prev[k_max_edge_neighbours + 1];
    };
    union {
        Sides sides;
        std::uint32_t place;  // once listed (creased_normals_in_order): where its corners end in the list
    };
};
static_assert(sizeof(PositionSums) == 64);
constexpr std::uint32_t k_rough = 1u << 31;  // not all faces within reach of the first, or too many: split
constexpr std::uint32_t k_far = 1u << 30;    // sides too far to keep here: walked from the corners
constexpr std::uint32_t k_count = k_far - 1;

// A position is settled by its sum when its corners with area make one set, which it has when
// (a) every face there is within half the crease angle of the first, less a margin, and (b) the
// corners are joined by their sides: then each pair on a side is joined (their angle is under the
// crease angle), and the set is the whole fan. (a) holds whatever the rounding: with faces of
// squared length within 4e-6 of 1 (checked), a float dot product is within 4.5e-6 of the cosine of
// their angle, so passing cos(crease / 2 - 1e-3) puts a face within crease / 2 - 1e-3 + 2e-4 of the
// first (4.5e-6 / sin(0.024) < 2e-4), two faces within crease - 1.6e-3, and their dot product at
// least 1.6e-3 * 0.048 - 4.5e-6 above cos(crease): a margin of more than 7e-5 for crease angles in
// [0.05, pi - 0.05], the only ones taking this way (with the others every fan is split).
struct FirstFaceTest {
    float cos_half = 2;  // never passed: every fan of two faces or more is split as the threads do
    explicit FirstFaceTest(float crease) {
        if (crease >= 0.05f && crease <= k_pi - 0.05f)
            cos_half = static_cast<float>(portable::cos(double{crease} / 2 - 1e-3));
    }
    bool near(Vec3 face, Vec3 first) const { return unit_length(face) && near_unit(face, first); }
    bool near_unit(Vec3 face, Vec3 first) const { return dot(face, first) > cos_half; }
};

// Every position's sums in one array.
struct AllSums {
    PositionSums* sums;
    void before(const std::uint32_t*) const {}
    PositionSums& at(std::uint32_t w) const { return sums[w]; }
    void prefetch(std::uint32_t w) const { __builtin_prefetch(sums + w, 1); }
};

// The triangles described in order: each position's sums (sums.at(w), after sums.before(the
// triangle's indices) for each valid triangle), and a bit per triangle with area.
template <class Sums>
void sum_by_position(const Mesh& mesh, WeldIds weld, const InRange& in_range,
                     const FirstFaceTest& test, Sums& sums, std::vector<std::uint64_t>& area) {
    area.assign((in_range.size() + 63) / 64, 0);
    describe_range(mesh, in_range, 0, in_range.size(), [&](std::size_t t, const TriangleFacts& facts) {
        const std::uint32_t* idx = mesh.indices.data() + 3 * t;
        sums.before(idx);
        const Vec3 face{facts.face[0], facts.face[1], facts.face[2]};
        if (!(dot(face, face) > 0)) return;
        area[t / 64] |= std::uint64_t{1} << t % 64;
        const std::int64_t w[3] = {weld[idx[0]], weld[idx[1]], weld[idx[2]]};
        for (int k = 0; k < 3; ++k) {
            PositionSums& p = sums.at(static_cast<std::uint32_t>(w[k]));
            p.around += face * facts.angle[k];
            const std::uint32_t faces = p.faces & k_count;
            if (faces == 0) p.first = face;
            if (faces > k_max_edge_neighbours || !test.near(face, p.first)) {
                p.faces = (p.faces + 1) | k_rough;
                continue;
            }
            const std::int64_t next = w[(k + 1) % 3] - w[k], prev = w[(k + 2) % 3] - w[k];
            if (next >= -INT16_MAX && next <= INT16_MAX && prev >= -INT16_MAX && prev <= INT16_MAX)
                p.sides.next[faces] = static_cast<std::int16_t>(next), p.sides.prev[faces] = static_cast<std::int16_t>(prev);
            else
                p.faces |= k_far;
            ++p.faces;
        }
    },
    // A triangle's positions are far apart in the sums in most files (a cache miss each, which the
    // sums would otherwise wait for): they are fetched a chunk ahead, before the kernel runs.
    [&](std::size_t t) {
        const std::uint32_t* idx = mesh.indices.data() + 3 * t;
        for (int k = 0; k < 3; ++k) sums.prefetch(weld[idx[k]]);
    });
}

bool has_area(const std::vector<std::uint64_t>& area, std::uint32_t t) { return area[t / 64] >> t % 64 & 1; }

// Whether the corners (with area) of a position are all joined by sides. A closed manifold fan
// (each corner's next side the previous side of exactly one other) is one set when following
// those sides from the first corner comes back to it after all of them; otherwise the corners are
// walked from the first, forward and back, which walks an open manifold fan in full. Anything else
// (a bowtie, a non-manifold edge) is left to split_into_sets.
// The first j < n with sides[j] == side, else n.
template <class Side>
std::uint32_t first_side(const Side* sides, std::uint32_t n, Side side) {
    std::uint32_t j = 0;
    while (j < n && sides[j] != side) ++j;
    return j;
}
#if defined(__SSE2__)
// The same for a PositionSums' sides (9), without a branch per side (where a fan's next corner is
// among its corners follows no pattern a predictor learns): two overlapping compares of 8 lanes.
std::uint32_t first_side(const std::int16_t* sides, std::uint32_t n, std::int16_t side) {
    static_assert(k_max_edge_neighbours + 1 == 9);
    const __m128i wanted = _mm_set1_epi16(side);
    const auto equal_at = [&](const std::int16_t* from) {
        const __m128i lanes = _mm_loadu_si128(reinterpret_cast<const __m128i*>(from));
        return static_cast<std::uint32_t>(_mm_movemask_epi8(_mm_cmpeq_epi16(lanes, wanted)));
    };
    const std::uint32_t equal = (equal_at(sides) | equal_at(sides + 1) << 2) & ((1u << 2 * n) - 1);  // two bits a side
    return equal ? static_cast<std::uint32_t>(std::countr_zero(equal)) / 2 : n;
}
#endif

// Arrays of 32-bit sides are read whole, 4 at a time: room for this many (the values past n unused).
constexpr std::size_t k_sides_read = 12;
static_assert(k_sides_read >= k_max_edge_neighbours + 1 && k_sides_read % 4 == 0);
#if defined(__SSE2__)
// The same for the corners' sides of a fan (k_sides_read of them readable): three compares of 4 lanes,
// no branch per side (the bunny's fans spent 3% of the process's samples in the loop's branches).
std::uint32_t first_side(const std::uint32_t* sides, std::uint32_t n, std::uint32_t side) {
    static_assert(k_sides_read == 12);
    const __m128i wanted = _mm_set1_epi32(static_cast<int>(side));
    const auto equal_at = [&](std::size_t from) {
        const __m128i lanes = _mm_loadu_si128(reinterpret_cast<const __m128i*>(sides + from));
        return static_cast<std::uint32_t>(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(lanes, wanted))));
    };
    const std::uint32_t equal = (equal_at(0) | equal_at(4) << 4 | equal_at(8) << 8) & ((1u << n) - 1);  // a bit a side
    return equal ? static_cast<std::uint32_t>(std::countr_zero(equal)) : n;
}
// The sides of up to 8 corners in vector lanes: corners 0-3 in the low vectors, 4-7 in the high.
struct SidesOf8 {
    __m128i next_low, next_high, prev_low, prev_high;
};
// From arrays of 32-bit sides (8 readable in each).
SidesOf8 sides_of_8(const std::uint32_t* next, const std::uint32_t* prev) {
    const auto load = [](const std::uint32_t* from) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(from)); };
    return {load(next), load(next + 4), load(prev), load(prev + 4)};
}
// From a corner's sides in a word each (next | prev << 32; 8 readable), written one by one just
// before: loaded as they were stored, 8 bytes each (16-byte loads of the arrays, stored 4 bytes at a
// time, waited for the stores to complete: a seventh of the split's samples).
SidesOf8 sides_of_8(const std::uint64_t* pairs) {
    const auto load = [&](int i) { return _mm_loadl_epi64(reinterpret_cast<const __m128i*>(pairs + i)); };
    const __m128i low_01 = _mm_unpacklo_epi64(load(0), load(1)), low_23 = _mm_unpacklo_epi64(load(2), load(3));
    const __m128i high_45 = _mm_unpacklo_epi64(load(4), load(5)), high_67 = _mm_unpacklo_epi64(load(6), load(7));
    const auto even = [](__m128i a, __m128i b) {  // lanes 0 and 2 of each
        return _mm_castps_si128(_mm_shuffle_ps(_mm_castsi128_ps(a), _mm_castsi128_ps(b), 0x88));
    };
    const auto odd = [](__m128i a, __m128i b) {
        return _mm_castps_si128(_mm_shuffle_ps(_mm_castsi128_ps(a), _mm_castsi128_ps(b), 0xDD));
    };
    return {even(low_01, low_23), even(high_45, high_67), odd(low_01, low_23), odd(high_45, high_67)};
}

// Whether n <= 8 corners make a closed fan as joined_by_sides follows one: from corner 0 to each
// corner's successor (the first whose previous side is its next side) and back to 0 after all n.
// The 64 comparisons at once, a byte a corner (bit j: prev[j] == next[i]), then the walk from byte
// to byte: a third of the instructions of a search per corner.
[[gnu::always_inline]] inline bool closed_fan_of_8(const SidesOf8& sides, std::uint32_t n) {
    // Inlined (the compiler otherwise calls four_rows: 60 instructions a fan more).
    const auto row = [&](__m128i next_i) __attribute__((always_inline)) {  // 8 lanes of 16 bits
        return _mm_packs_epi32(_mm_cmpeq_epi32(next_i, sides.prev_low), _mm_cmpeq_epi32(next_i, sides.prev_high));
    };
    const auto rows = [&](__m128i a, __m128i b) __attribute__((always_inline)) {  // two corners' bytes
        return std::uint64_t{static_cast<std::uint16_t>(_mm_movemask_epi8(_mm_packs_epi16(row(a), row(b))))};
    };
    const auto four_rows = [&](__m128i next) __attribute__((always_inline)) {
        return rows(_mm_shuffle_epi32(next, 0x00), _mm_shuffle_epi32(next, 0x55)) |
               rows(_mm_shuffle_epi32(next, 0xAA), _mm_shuffle_epi32(next, 0xFF)) << 16;
    };
    std::uint64_t successors = four_rows(sides.next_low);
    if (n > 4) successors |= four_rows(sides.next_high) << 32;
    successors &= 0x0101010101010101ull * ((1u << n) - 1);  // no corner beyond n
    for (std::uint32_t at = 0, step = 1; step <= n; ++step) {
        const auto bits = static_cast<std::uint32_t>(successors >> 8 * at) & 0xFF;
        if (!bits) return false;
        if ((at = static_cast<std::uint32_t>(std::countr_zero(bits))) == 0) return step == n;
    }
    return false;
}
#endif

// Whether the corners make a closed fan as joined_by_sides (below) follows one, by a search for each
// corner's successor.
template <class Side>
bool closed_by_search(const Side* next, const Side* prev, std::uint32_t n) {
    std::uint32_t successor[k_max_edge_neighbours + 1];
    for (std::uint32_t i = 0; i < n; ++i) successor[i] = first_side(prev, n, next[i]);
    for (std::uint32_t at = 0, step = 1; step <= n; ++step) {
        const std::uint32_t j = successor[at];
        if (j == n) return false;
        if ((at = j) == 0) return step == n;
    }
    return false;
}

template <class Side>
bool joined_by_sides(const Side* next, const Side* prev, std::uint32_t n) {  // n <= k_max_edge_neighbours + 1
    // Closed: from each corner to the first whose previous side is its next side, back to the
    // first corner after all of them (then each was reached once). Each corner's successor is
    // found first, every search independent of the others, then followed.
    bool closed;
#if defined(__SSE2__)
    if constexpr (std::is_same_v<Side, std::uint32_t>)
        closed = n <= 8 ? closed_fan_of_8(sides_of_8(next, prev), n) : closed_by_search(next, prev, n);
    else
#endif
        closed = closed_by_search(next, prev, n);
    if (closed) return true;
    std::uint64_t reached = 1;
    for (const bool forward : {true, false})
        for (std::uint32_t at = 0;;) {
            const Side side = forward ? next[at] : prev[at];
            std::uint64_t on_side = 0;
            for (std::uint32_t j = 0; j < n; ++j) on_side |= std::uint64_t{(forward ? prev[j] : next[j]) == side} << j;
            on_side &= ~reached;
            if (!on_side) break;
            at = static_cast<std::uint32_t>(std::countr_zero(on_side));
            reached |= on_side & -on_side;
        }
    return reached == (std::uint64_t{1} << n) - 1;
}

// The fan as sum_by_position and creased_normals_in_order settle it: at most
// k_max_edge_neighbours + 1 corners (with area, in corner order), every face near the first, and
// the corners joined by their sides. Then split_into_sets finds one set (FirstFaceTest), so the
// answer is the same either way; fewer than two corners are left to it.
bool one_set_by_first_face(const FirstFaceTest& test, const std::vector<FanCorner>& corners) {
    const auto n = static_cast<std::uint32_t>(corners.size());
    if (n < 2 || n > k_max_edge_neighbours + 1) return false;
    std::uint32_t next[k_sides_read] = {}, prev[k_sides_read] = {};
    for (std::uint32_t i = 0; i < n; ++i) {
        if (!test.near(corners[i].face, corners[0].face)) return false;
        next[i] = corners[i].next_position, prev[i] = corners[i].prev_position;
    }
    return joined_by_sides(next, prev, n);
}

// A face or a sum of faces in vector lanes where there are some: x, y, z and a lane never read back.
#if defined(__SSE2__)
using Lanes3 = __m128;
// The three floats at xyz and the one after them (a face: its record's first angle).
Lanes3 load_lanes3(const float* xyz) { return _mm_loadu_ps(xyz); }
Lanes3 zero_lanes3() { return _mm_setzero_ps(); }
// dot's operations in its order: ((0 + x) + y) + z of the products.
float dot_lanes3(Lanes3 a, Lanes3 b) {
    const __m128 p = _mm_mul_ps(a, b);
    return _mm_cvtss_f32(_mm_add_ss(_mm_add_ss(_mm_add_ss(_mm_setzero_ps(), p), _mm_shuffle_ps(p, p, 1)), _mm_movehl_ps(p, p)));
}
Lanes3 add_scaled(Lanes3 sum, Lanes3 a, float s) { return _mm_add_ps(sum, _mm_mul_ps(a, _mm_set1_ps(s))); }
Lanes3 divided(Lanes3 a, float s) { return _mm_div_ps(a, _mm_set1_ps(s)); }
Vec3 vec3_of(Lanes3 a) {
    alignas(16) float lanes[4];
    _mm_store_ps(lanes, a);
    return {lanes[0], lanes[1], lanes[2]};
}
#else
using Lanes3 = Vec3;
Lanes3 load_lanes3(const float* xyz) { return {xyz[0], xyz[1], xyz[2]}; }
Lanes3 zero_lanes3() { return {}; }
float dot_lanes3(Lanes3 a, Lanes3 b) { return dot(a, b); }
Lanes3 add_scaled(Lanes3 sum, Lanes3 a, float s) { return sum + a * s; }
Lanes3 divided(Lanes3 a, float s) { return a / s; }
Vec3 vec3_of(Lanes3 a) { return a; }
#endif

// The fans one_set_by_first_face finds one set, settled in one pass over their records, as
// gather_fan, that test and assign_set_normals settle them (the same sum in corner order, the same
// test, the same writes), without a FanCorner each: at two threads most positions are settled here
// (the bunny's fans with assign_set_normals: 34.1 -> 27.0 M instructions). False, with nothing
// written, for any other fan, and for fans of more corners than the test takes, with area or not
// (the split then finds the same: one set or not, and the same sum).
template <class Facts>
bool settle_one_set(std::span<const std::uint32_t> corners, const Facts* triangles, const FirstFaceTest& test,
                    std::uint32_t position, Vec3& around, VertexNormals out) {
    constexpr std::uint32_t k_most = k_max_edge_neighbours + 1;
    if (corners.size() < 2 || corners.size() > k_most) return false;
    static_assert(offsetof(Facts, angle) == offsetof(Facts, face) + 3 * sizeof(float));  // load_lanes3 reads 4 floats
    std::uint64_t sides[k_most] = {};  // per corner with area: next | prev << 32
    std::uint32_t vertex[k_most];
    std::uint32_t n = 0;
    const std::uint32_t* c = corners.data();
    const std::uint32_t* const end = c + corners.size();
    const auto with_area = [](const Facts& t) { const Vec3 face{t.face[0], t.face[1], t.face[2]}; return dot(face, face) > 0; };
    // The first corner with area: the others' faces are tested against its face.
    for (;; ++c) {
        if (c == end) return false;
        const Facts& t = facts_of(triangles, *c);
        if (t.unit_face()) break;
        if (with_area(t)) return false;  // as test.near would find it
    }
    const Lanes3 first = load_lanes3(facts_of(triangles, *c).face);
    const std::uint32_t set = corner_of(*c);
    Lanes3 sum = zero_lanes3();
    const float cos_half = test.cos_half;
    for (; c != end; ++c) {  // numbered as in CornersByPosition
        const std::uint32_t grouped = *c;
        const Facts& t = facts_of(triangles, grouped);
        const std::uint32_t k = k_of(grouped);
        if (!t.unit_face()) [[unlikely]] {  // as test.near would find it
            if (!with_area(t)) continue;  // no area: in no set, nothing in the sum
            return false;
        }
        const Lanes3 face = load_lanes3(t.face);
        if (!(dot_lanes3(face, first) > cos_half)) return false;  // test.near_unit
        sum = add_scaled(sum, face, t.angle[k]);
        sides[n] = t.next_at(k) | std::uint64_t{t.prev_at(k)} << 32;
        if constexpr (!Facts::k_own_positions) vertex[n] = t.vertex_at(k);
        ++n;
    }
    if (n < 2) return false;
    const auto joined = [&] {  // the other fans (open, or of 9 corners): as arrays
        std::uint32_t next[k_sides_read] = {}, prev[k_sides_read] = {};
        for (std::uint32_t i = 0; i < n; ++i) next[i] = static_cast<std::uint32_t>(sides[i]), prev[i] = sides[i] >> 32;
        return joined_by_sides(next, prev, n);
    };
#if defined(__SSE2__)
    static_assert(k_most >= 8);  // sides_of_8 reads 8
    if (!(n <= 8 && closed_fan_of_8(sides_of_8(sides), n)) && !joined()) return false;
#else
    if (!joined()) return false;
#endif
    around = vec3_of(sum);
    // normalize's usual case here (it is not inlined): then the normal's squared length is near 1.
    const float length = std::sqrt(dot_lanes3(sum, sum));
    Vec3 normal;
    if (length > 0 && length < std::numeric_limits<float>::infinity())
        normal = vec3_of(divided(sum, length));
    else if (normal = normalize(around); !(dot(normal, normal) > 0))
        return true;
    if constexpr (Facts::k_own_positions) {  // every corner's vertex is the position's own, in no set yet
        out.set_of(position) = set, out.normals[position] = normal;
        return true;
    }
    for (std::uint32_t i = 0; i < n; ++i)
        if (out.set_of(vertex[i]) == k_no_set) out.set_of(vertex[i]) = set, out.normals[vertex[i]] = normal;
    return true;
}

// The corner of triangle t at k as the specification describes it (for the few positions not
// settled by their sums; the shape kernel gives the same bits for the others).
FanCorner describe_corner(const Mesh& mesh, WeldIds weld, std::uint32_t c) {
    const std::uint32_t t = c / 3, k = c % 3;
    const std::uint32_t* idx = mesh.indices.data() + 3 * t;
    const Vec3 p[3] = {mesh.positions[idx[0]], mesh.positions[idx[1]], mesh.positions[idx[2]]};
    const Vec3 face = normalize(cross(p[1] - p[0], p[2] - p[0]));
    float angle = 0;
    if (dot(face, face) > 0)
        angle = corner_angle(normalize(p[(k + 1) % 3] - p[k]), normalize(p[k] - p[(k + 2) % 3]));
    return {c, idx[k], weld[idx[(k + 1) % 3]], weld[idx[(k + 2) % 3]], face, face * angle};
}

// The normal of a vertex in no set (on degenerate triangles only, or on none): the normalized sum
// around its position, or +z.
Vec3 fallback_normal(Vec3 around) {
    const Vec3 n = normalize(around);
    return dot(n, n) > 0 ? n : Vec3{0, 0, 1};
}
// fallback_normal of each of the sums in place, 8 at a time: the same operations in the same order
// in each lane (dot from +0, sqrt, divisions; correctly rounded, no FMA), so the compiler's vector
// lanes give the same bits; the few sums without a usual length take fallback_normal itself.
void fallback_normals_in_place(Vec3* sums, std::size_t count) {
    constexpr std::size_t lanes = 8;
    std::size_t i = 0;
    for (; i + lanes <= count; i += lanes) {
        float x[lanes], y[lanes], z[lanes], l[lanes];
        for (std::size_t j = 0; j < lanes; ++j) x[j] = sums[i + j].x, y[j] = sums[i + j].y, z[j] = sums[i + j].z;
        for (std::size_t j = 0; j < lanes; ++j) l[j] = std::sqrt(((0.0f + x[j] * x[j]) + y[j] * y[j]) + z[j] * z[j]);
        bool usual = true;
        for (std::size_t j = 0; j < lanes; ++j) usual &= l[j] > 0 && l[j] < std::numeric_limits<float>::infinity();
        if (!usual) {
            for (std::size_t j = 0; j < lanes; ++j) sums[i + j] = fallback_normal(sums[i + j]);
            continue;
        }
        // With a usual length the normal's squared length is near 1, never 0: no +z.
        for (std::size_t j = 0; j < lanes; ++j) sums[i + j] = {x[j] / l[j], y[j] / l[j], z[j] / l[j]};
    }
    for (; i < count; ++i) sums[i] = fallback_normal(sums[i]);
}

// The vertices in no set given it (around(w): the sum at position w).
template <class Around>
void give_fallback_normals(const std::vector<std::uint32_t>& vertex_set, WeldIds weld,
                           const Around& around, std::vector<Vec3>& normals) {
    for (std::uint32_t v = 0; v < vertex_set.size(); ++v)
        if (vertex_set[v] == k_no_set) normals[v] = fallback_normal(around(weld[v]));
}

// One thread where each vertex is its own position: in most meshes a triangle's positions are
// numbered close to the highest number of the triangles up to it (the conversion numbers them in
// order of first use: 99% of the 1M sphere's corners are within 223 of it), so the sums are kept
// for a ring of the k_window positions up to the highest, each position settled as the ring leaves
// it, and for the few used again later than that (`far`: the 1M sphere's 6,702 on the seams of its
// subdivided faces) in an array of their own: 0.7 MB of sums instead of 32 MB of fresh pages
// (docs/BENCHMARKS.md "Loading OBJ, session 15"). The same sums in the same order: the same bits.
constexpr std::size_t k_window = 4096;  // positions; a power of two (the ring of twice as many: 512 KB)
constexpr std::size_t k_window_min_positions = 4 * k_window;

// A set of positions (a bit each) and each one's rank among them.
struct FarPositions {
    std::vector<std::uint64_t> bits;    // per position
    std::vector<std::uint32_t> before;  // per word of bits: the positions in the set before it
    std::size_t count = 0;
    bool has(std::uint32_t w) const { return bits[w / 64] >> w % 64 & 1; }
    std::uint32_t rank(std::uint32_t w) const {
        return before[w / 64] + static_cast<std::uint32_t>(std::popcount(bits[w / 64] & ((std::uint64_t{1} << w % 64) - 1)));
    }
    // `before` from the bits.
    void count_before() {
        before.resize(bits.size());
        std::uint32_t n = 0;
        for (std::size_t i = 0; i < bits.size(); ++i) before[i] = n, n += static_cast<std::uint32_t>(std::popcount(bits[i]));
    }
};

// The positions that a corner of a valid triangle uses k_window or more below the highest position
// of the valid triangles up to its own; nullopt when they are more than an eighth of all (the
// sums are then kept for every position).
std::optional<FarPositions> find_far_positions(const Mesh& mesh, const InRange& in_range, std::size_t positions) {
    FarPositions far;
    far.bits.assign((positions + 63) / 64, 0);
    const std::size_t most = positions / 8;
    constexpr auto window = static_cast<std::int64_t>(k_window);
    std::int64_t highest = -1;
    const std::uint32_t* index = mesh.indices.data();
    for (std::size_t t = 0; t < in_range.size(); ++t) {
        if (!in_range[t]) continue;
        const std::uint32_t* idx = index + 3 * t;
        highest = std::max<std::int64_t>(highest, std::max({idx[0], idx[1], idx[2]}));
        if (highest - std::min({idx[0], idx[1], idx[2]}) < window) continue;  // one test for most triangles
        for (int k = 0; k < 3; ++k) {
            if (highest - idx[k] < window) continue;
            std::uint64_t& word = far.bits[idx[k] / 64];
            const std::uint64_t bit = std::uint64_t{1} << idx[k] % 64;
            if (word & bit) continue;
            word |= bit;
            if (++far.count > most) return std::nullopt;
        }
    }
    far.count_before();
    return far;
}

// The sums as sum_by_position fills them: those of the positions from `finished_` up to the highest
// so far in a ring of 2 * k_window (the positions k_window or more below the highest, but for the
// far ones, are used no more: they are finished in batches of k_window or more, out of the
// per-triangle path), and the far positions' once they are finished. finish(w, sums) is called
// for each position in order (sums null for a far one).
template <class Finish>
class WindowSums {
public:
    WindowSums(const FarPositions& far, std::size_t positions, const Finish& finish)
        : far_(far), positions_(static_cast<std::int64_t>(positions)), ring_(k_ring), far_sums_(far.count), finish_(finish) {}
    void before(const std::uint32_t* idx) {
        const std::int64_t top = std::max({idx[0], idx[1], idx[2]});
        if (top - finished_ >= static_cast<std::int64_t>(k_ring)) finish_to(top - static_cast<std::int64_t>(k_window));
    }
    // A position finished already is a far one (find_far_positions).
    PositionSums& at(std::uint32_t w) {
        return static_cast<std::int64_t>(w) >= finished_ ? ring_[w & (k_ring - 1)] : far_sums_[far_.rank(w)];
    }
    void prefetch(std::uint32_t) const {}  // the ring stays in the caches; the far sums are few
    void finish_rest() { finish_to(positions_ - 1); }
    const std::vector<PositionSums>& far_sums() const { return far_sums_; }

private:
    static constexpr std::size_t k_ring = 2 * k_window;
    [[gnu::noinline]] void finish_to(std::int64_t last) {
        for (std::int64_t w = finished_; w <= last; ++w) {
            const auto position = static_cast<std::uint32_t>(w);
            PositionSums& sums = ring_[position & (k_ring - 1)];
            if (far_.has(position)) {
                far_sums_[far_finished_++] = sums;  // in order: its rank
                finish_(position, nullptr);
            } else {
                finish_(position, &sums);
            }
            sums = PositionSums{};  // for position w + k_ring
        }
        finished_ = std::max(finished_, last + 1);
    }
    const FarPositions& far_;
    std::int64_t positions_;
    std::int64_t finished_ = 0;  // the positions below are finished
    std::size_t far_finished_ = 0;
    std::vector<PositionSums> ring_;
    std::vector<PositionSums> far_sums_;
    const Finish& finish_;
};

// Whether a position's sums settle it (its corners with area one set, or fewer than two).
bool settled_by_sums(const PositionSums& p) {
    const std::uint32_t faces = p.faces & k_count;
    return !(p.faces & k_rough) && (faces <= 1 || (!(p.faces & k_far) && joined_by_sides(p.sides.next, p.sides.prev, faces)));
}

// A position its sums did not settle, given its corners with area: unless their sides join them
// into one set after all (k_far: the sides read from the corners), its fan is split as split_fans
// splits one, each set's normal given to its vertex.
void split_listed_fan(const Mesh& mesh, WeldIds weld, std::span<const std::uint32_t> corners, std::uint32_t flags,
                      Vec3 around, float cos_crease, FanScratch& s, VertexNormals out) {
    if (!(flags & k_rough)) {
        std::uint32_t next[k_sides_read] = {}, prev[k_sides_read] = {};
        for (std::uint32_t i = 0; i < corners.size(); ++i) {
            const std::uint32_t* idx = mesh.indices.data() + corners[i] / 3 * 3;
            const std::uint32_t k = corners[i] % 3;
            next[i] = weld[idx[(k + 1) % 3]], prev[i] = weld[idx[(k + 2) % 3]];
        }
        if (joined_by_sides(next, prev, static_cast<std::uint32_t>(corners.size()))) return;
    }
    gather_fan(corners, [&](std::uint32_t c) { return describe_corner(mesh, weld, c); }, s.corners);
    assign_set_normals(split_into_sets(cos_crease, s), around, s, out);
}

// creased_normals_in_order where each vertex is its own position, with the sums of the ring
// and of the far positions (above): the same steps, the same bits.
void creased_normals_in_window(Mesh& mesh, const FarPositions& far, std::size_t positions, const InRange& in_range,
                               float crease) {
    detail::reserve_in_huge_pages(mesh.normals, mesh.positions.size());
    mesh.normals.clear();  // appended below, position by position
    // The positions not settled by their sums, in order, with what the split needs of them.
    struct Listed {
        std::uint32_t position, faces, place;
        Vec3 around;
    };
    std::vector<Listed> listed;
    const auto finish = [&](std::uint32_t w, const PositionSums* p) {
        if (p && settled_by_sums(*p)) {
            mesh.normals.push_back(p->around);  // made its normal below
            return;
        }
        mesh.normals.emplace_back();  // given below
        if (p) listed.push_back({w, p->faces, 0, p->around});
    };
    WindowSums<decltype(finish)> sums(far, positions, finish);
    std::vector<std::uint64_t> area;
    sum_by_position(mesh, WeldIds{}, in_range, FirstFaceTest(crease), sums, area);
    sums.finish_rest();
    std::size_t far_rank = 0;
    const std::size_t from_ring = listed.size();
    for (std::size_t word = 0; word < far.bits.size(); ++word)
        for (std::uint64_t bits = far.bits[word]; bits; bits &= bits - 1) {
            const auto w = static_cast<std::uint32_t>(64 * word + static_cast<std::size_t>(std::countr_zero(bits)));
            const PositionSums& p = sums.far_sums()[far_rank++];
            if (settled_by_sums(p))
                mesh.normals[w] = p.around;
            else
                listed.push_back({w, p.faces, 0, p.around});
        }
    std::inplace_merge(listed.begin(), listed.begin() + static_cast<std::ptrdiff_t>(from_ring), listed.end(),
                       [](const Listed& a, const Listed& b) { return a.position < b.position; });
    fallback_normals_in_place(mesh.normals.data(), mesh.normals.size());
    if (listed.empty()) return;
    // Their corners with area, in corner order (place ends where each position's corners end); a
    // listed position's entry is its rank among them (as the far positions').
    FarPositions is_listed;
    is_listed.bits.assign((positions + 63) / 64, 0);
    std::uint32_t listed_count = 0;
    for (Listed& l : listed) {
        is_listed.bits[l.position / 64] |= std::uint64_t{1} << l.position % 64;
        l.place = listed_count, listed_count += l.faces & k_count;
    }
    is_listed.count_before();
    std::vector<std::uint32_t> listed_corners(listed_count);
    const auto triangles = static_cast<std::uint32_t>(in_range.size());
    for (std::uint32_t t = 0; t < triangles; ++t) {
        if (!has_area(area, t)) continue;
        for (std::uint32_t k = 0; k < 3; ++k)
            if (const std::uint32_t w = mesh.indices[3 * t + k]; is_listed.has(w))
                listed_corners[listed[is_listed.rank(w)].place++] = 3 * t + k;
    }
    const float cos_crease = static_cast<float>(portable::cos(crease));
    std::vector<FanScratch> scratch(1);
    FanScratch& s = scratch[0];
    for (const Listed& l : listed) {
        const std::uint32_t w = l.position, faces = l.faces & k_count;
        const std::span<const std::uint32_t> corners{listed_corners.data() + l.place - faces, faces};
        std::uint32_t set = k_no_set;  // the position's vertex's
        split_listed_fan(mesh, WeldIds{}, corners, l.faces, l.around, cos_crease, s, {&set, w, mesh.normals});
        if (set == k_no_set) mesh.normals[w] = fallback_normal(l.around);
    }
    copy_vertices(scratch, mesh);
}

// The normals with one thread: the fans of the positions that their sums do not settle split as
// split_fans does, and the others' vertices left to the fallback (their one set's normal is the
// normalized sum, which the fallback gives too). Where each vertex is its own position (no weld),
// a settled position's sum is written as its normal as it is settled, in order (no zeros written
// first), all normalized at once (in lanes), and only the listed ones left to the fallback.
void creased_normals_in_order(Mesh& mesh, WeldIds weld, std::size_t positions,
                              const InRange& in_range, float crease) {
    const bool own_positions = !weld.id;
    if (own_positions && positions >= k_window_min_positions)
        if (const std::optional<FarPositions> far = find_far_positions(mesh, in_range, positions)) {
            creased_normals_in_window(mesh, *far, positions, in_range, crease);
            return;
        }
    std::vector<std::uint32_t> vertex_set(mesh.positions.size(), k_no_set);
    detail::reserve_in_huge_pages(mesh.normals, mesh.positions.size());
    if (own_positions)
        mesh.normals.clear();  // appended below, position by position
    else
        mesh.normals.assign(mesh.positions.size(), Vec3{});
    std::vector<FanScratch> scratch(1);
    const ZeroedArray<PositionSums> sums(positions);
    std::vector<std::uint64_t> area;
    AllSums all{sums.data()};
    sum_by_position(mesh, weld, in_range, FirstFaceTest(crease), all, area);
    // The positions not settled here, listed: each given its place in `listed_corners` (in the
    // place of its sides, which it no longer needs) and a bit in `listed`.
    std::vector<std::uint64_t> listed((positions + 63) / 64, 0);
    std::uint32_t listed_count = 0;
    for (std::size_t w = 0; w < positions; ++w) {
        PositionSums& p = sums[w];
        if (settled_by_sums(p)) {
            if (own_positions) mesh.normals.push_back(p.around);  // made its normal below
            continue;
        }
        if (own_positions) mesh.normals.emplace_back();  // given below
        p.place = listed_count, listed_count += p.faces & k_count;
        listed[w / 64] |= std::uint64_t{1} << w % 64;
    }
    if (own_positions) fallback_normals_in_place(mesh.normals.data(), mesh.normals.size());
    if (listed_count) {
        // Their corners with area, in corner order (place ends where each position's corners end).
        std::vector<std::uint32_t> listed_corners(listed_count);
        const auto triangles = static_cast<std::uint32_t>(in_range.size());
        for (std::uint32_t t = 0; t < triangles; ++t) {
            if (!has_area(area, t)) continue;
            for (std::uint32_t k = 0; k < 3; ++k)
                if (const std::uint32_t w = weld[mesh.indices[3 * t + k]]; listed[w / 64] >> w % 64 & 1)
                    listed_corners[sums[w].place++] = 3 * t + k;
        }
        const float cos_crease = static_cast<float>(portable::cos(crease));
        FanScratch& s = scratch[0];
        for (std::size_t word = 0; word < listed.size(); ++word)
            for (std::uint64_t bits = listed[word]; bits; bits &= bits - 1) {
                const std::size_t w = 64 * word + static_cast<std::size_t>(std::countr_zero(bits));
                const PositionSums& p = sums[w];
                const std::uint32_t faces = p.faces & k_count;
                const std::span<const std::uint32_t> corners{listed_corners.data() + p.place - faces, faces};
                split_listed_fan(mesh, weld, corners, p.faces, p.around, cos_crease, s, {vertex_set.data(), 0, mesh.normals});
            }
        copy_vertices(scratch, mesh);
    }
    if (!own_positions) {
        give_fallback_normals(vertex_set, weld, [&](std::uint32_t w) { return sums[w].around; }, mesh.normals);
        return;
    }
    for (std::size_t word = 0; word < listed.size(); ++word)
        for (std::uint64_t bits = listed[word]; bits; bits &= bits - 1) {
            const std::size_t w = 64 * word + static_cast<std::size_t>(std::countr_zero(bits));
            if (vertex_set[w] == k_no_set) mesh.normals[w] = fallback_normal(sums[w].around);
        }
}

}  // namespace

void compute_creased_normals(Mesh& mesh, float crease_angle_radians, int threads) {
    detail::compute_creased_normals_with(mesh, crease_angle_radians, threads, false);
}

void detail::compute_creased_normals_with(Mesh& mesh, float crease_angle_radians, int threads, bool distinct_positions) {
    // Threads only for meshes that have a block for each; they end before this returns.
    std::optional<detail::ThreadPool> pool;
    if (threads != 1 && mesh.indices.size() / 3 >= 2 * k_block) pool.emplace(threads <= 0 ? 0 : threads);
    detail::compute_creased_normals_on(mesh, crease_angle_radians, pool ? &*pool : nullptr, distinct_positions);
}

void detail::compute_creased_normals_on(Mesh& mesh, float crease_angle_radians, ThreadPool* pool,
                                        bool distinct_positions) {
    const std::size_t vertex_count = mesh.positions.size();
    const std::size_t triangles = mesh.indices.size() / 3;
    detail::ThreadPool* workers =
        pool && pool->size() > 1 && triangles >= 2 * k_block && triangles <= k_max_grouped_triangles ? pool : nullptr;

    Weld welded;
    std::size_t positions = vertex_count;
    if (!distinct_positions) {
        welded = weld_by_position(mesh.positions);
        positions = welded.key.size();
    }
    const WeldIds weld{distinct_positions ? nullptr : welded.id.data()};  // null: each vertex its own position
    // Decided once: the copies below rewrite indices to vertices beyond vertex_count.
    // Most meshes have every index in range: one pass for their largest (vectorized), and no bits.
    std::uint32_t largest = 0;
    for (std::size_t c = 0; c < 3 * triangles; ++c) largest = std::max(largest, mesh.indices[c]);
    InRange in_range;
    in_range.triangles = triangles;
    if (largest >= vertex_count) {
        in_range.bits.resize(triangles);
        for (std::size_t t = 0; t < triangles; ++t)
            in_range.bits[t] = mesh.indices[3 * t] < vertex_count && mesh.indices[3 * t + 1] < vertex_count &&
                               mesh.indices[3 * t + 2] < vertex_count;
    }
    if (!workers) {
        creased_normals_in_order(mesh, weld, positions, in_range, crease_angle_radians);
        return;
    }

    // Each welded position's corners split into sets; corners of invalid triangles are in no set
    // and left alone.
    std::vector<std::uint32_t> vertex_set(vertex_count, k_no_set);
    detail::reserve_in_huge_pages(mesh.normals, vertex_count);
    mesh.normals.assign(vertex_count, Vec3{});
    std::vector<FanScratch> scratch(workers->size());
    CornersByPosition by_position;
    const float cos_crease = static_cast<float>(portable::cos(crease_angle_radians));
    const auto describe_and_split = [&]<class Facts>(Facts*) {
        const auto facts = std::make_unique_for_overwrite<Facts[]>(triangles);
        describe_triangles(mesh, weld, positions, in_range, workers, facts.get(), by_position);
        return split_fans(by_position, facts.get(), cos_crease, FirstFaceTest(crease_angle_radians), workers, scratch,
                          {vertex_set.data(), 0, mesh.normals});
    };
    const std::vector<Vec3> around = distinct_positions && vertex_count <= k_packed_vertices
                                         ? describe_and_split(static_cast<PackedFacts*>(nullptr))
                                         : describe_and_split(static_cast<TriangleFacts*>(nullptr));
    copy_vertices(scratch, mesh);
    give_fallback_normals(vertex_set, weld, [&](std::uint32_t w) { return around[w]; }, mesh.normals);
}

}  // namespace facet
