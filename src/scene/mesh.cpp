// facet scene: mesh validation, normals (smooth, flat, creased) and the built-in shape generators.
#include "facet/mesh.hpp"

#include "facet/detail/thread_pool.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>

namespace facet {

Status Mesh::validate() const {
    const std::size_t n = positions.size();
    auto bad = [](const std::string& what) { return Error{ErrorCode::invalid_argument, "mesh: " + what}; };
    if (!normals.empty() && normals.size() != n) return bad("normals and positions differ in count");
    if (!colours.empty() && colours.size() != n) return bad("colours and positions differ in count");
    if (!uvs.empty() && uvs.size() != n) return bad("uvs and positions differ in count");
    if (indices.size() % 3 != 0) return bad("index count is not a multiple of 3");
    for (std::size_t i = 0; i < indices.size(); ++i)
        if (indices[i] >= n)
            return bad("index " + std::to_string(indices[i]) + " at position " + std::to_string(i) +
                       " is out of range (" + std::to_string(n) + " vertices)");
    return Ok{};
}

Aabb Mesh::bounds() const {
    Aabb box;
    for (Vec3 p : positions)
        if (is_finite(p)) box.extend(p);
    return box;
}

void Mesh::append(const Mesh& other, const Mat4& model) {
    const auto base = static_cast<std::uint32_t>(positions.size());
    const std::size_t old = positions.size();
    const Mat3 nm = normal_matrix(model);
    auto keep_aligned = [&](auto& mine, const auto& theirs, auto fill) {
        if (mine.empty() && theirs.empty()) return;
        mine.resize(old, fill);
        if (theirs.empty())
            mine.resize(old + other.positions.size(), fill);
        else
            mine.insert(mine.end(), theirs.begin(), theirs.end());
    };
    for (Vec3 p : other.positions) positions.push_back(transform_point(model, p));
    keep_aligned(normals, other.normals, Vec3{});
    for (std::size_t i = old; i < normals.size() && !other.normals.empty(); ++i) normals[i] = normalize(nm * normals[i]);
    keep_aligned(colours, other.colours, Vec4{1, 1, 1, 1});
    keep_aligned(uvs, other.uvs, Vec2{});
    for (std::uint32_t i : other.indices) indices.push_back(base + i);
}

void compute_smooth_normals(Mesh& mesh) {
    mesh.normals.assign(mesh.positions.size(), Vec3{});
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t idx[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
        if (idx[0] >= mesh.positions.size() || idx[1] >= mesh.positions.size() || idx[2] >= mesh.positions.size())
            continue;
        const Vec3 face = normalize(cross(mesh.positions[idx[1]] - mesh.positions[idx[0]],
                                          mesh.positions[idx[2]] - mesh.positions[idx[0]]));
        if (!(dot(face, face) > 0)) continue;
        for (int k = 0; k < 3; ++k) {
            // Weight by the corner angle so a vertex's normal does not depend on how the fan is split.
            const Vec3 p = mesh.positions[idx[k]];
            const Vec3 e1 = normalize(mesh.positions[idx[(k + 1) % 3]] - p);
            const Vec3 e2 = normalize(mesh.positions[idx[(k + 2) % 3]] - p);
            const float angle = std::acos(clamp(dot(e1, e2), -1.0f, 1.0f));
            mesh.normals[idx[k]] += face * angle;
        }
    }
    for (Vec3& n : mesh.normals) n = normalize(n);
}

Mesh split_faces_flat(const Mesh& mesh) {
    Mesh out;
    const bool colours = !mesh.colours.empty(), uvs = !mesh.uvs.empty();
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t idx[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
        const Vec3 face = normalize(cross(mesh.positions[idx[1]] - mesh.positions[idx[0]],
                                          mesh.positions[idx[2]] - mesh.positions[idx[0]]));
        for (std::uint32_t i : idx) {
            out.indices.push_back(static_cast<std::uint32_t>(out.positions.size()));
            out.positions.push_back(mesh.positions[i]);
            out.normals.push_back(face);
            if (colours) out.colours.push_back(mesh.colours[i]);
            if (uvs) out.uvs.push_back(mesh.uvs[i]);
        }
    }
    return out;
}

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

// An id per distinct position (in order of first appearance), and each id's key.
struct Weld {
    std::vector<std::uint32_t> id;   // per vertex
    std::vector<PositionKey> key;    // per id
};

Weld weld_by_position(const std::vector<Vec3>& positions) {
    constexpr std::uint32_t empty = ~0u;
    Weld w;
    w.id.resize(positions.size());
    const std::size_t capacity = std::bit_ceil(2 * positions.size() + 2);
    std::vector<std::uint32_t> table(capacity, empty);  // open addressing: ids, linear probing
    for (std::size_t v = 0; v < positions.size(); ++v) {
        const PositionKey k = key_of(positions[v]);
        for (std::size_t slot = hash_of(k) & (capacity - 1);; slot = (slot + 1) & (capacity - 1)) {
            if (table[slot] == empty) {
                table[slot] = static_cast<std::uint32_t>(w.key.size());
                w.key.push_back(k);
            }
            if (w.key[table[slot]] == k) {
                w.id[v] = table[slot];
                break;
            }
        }
    }
    return w;
}

// Work is handed out in blocks of this many triangles or welded positions: large enough that a
// block costs far more than handing it out, small enough to share a mesh between the threads.
constexpr std::size_t k_block = 4096;

// Runs block(begin, end) over [0, count) in blocks, on the pool's threads when there is one.
// Every block writes only its own items, so the result does not depend on the threads.
template <class Block>
void for_blocks(detail::ThreadPool* pool, std::size_t count, const Block& block) {
    const std::size_t blocks = (count + k_block - 1) / k_block;
    auto run = [&](std::size_t b, int worker) { block(b * k_block, std::min(count, (b + 1) * k_block), worker); };
    if (pool)
        pool->parallel_for(blocks, run);
    else
        for (std::size_t b = 0; b < blocks; ++b) run(b, 0);
}

// What the sets around a position need of one corner, gathered in triangle order and then moved
// next to the other corners at the same position: triangles and positions are in unrelated orders
// in most files, and reading each corner's triangle from the position's side missed the cache
// for nearly every corner.
struct FanCorner {
    std::uint32_t corner;
    std::uint32_t next_position, prev_position;  // welded positions of the triangle's other corners
    Vec3 face;      // the triangle's normal, zero if degenerate
    Vec3 weighted;  // face * the corner's angle
};

// The corners of the valid triangles grouped by welded position: the corners at position w are
// corner[start[w] .. start[w + 1]), in increasing order (a counting sort).
struct CornersByPosition {
    std::vector<std::uint32_t> start;
    std::vector<FanCorner> corner;
};

// Where each corner of a valid triangle goes in CornersByPosition::corner (~0: an invalid triangle),
// with `start` filled in.
std::vector<std::uint32_t> place_corners(const Mesh& mesh, const Weld& welded, const std::vector<bool>& in_range,
                                         CornersByPosition& out) {
    const std::vector<std::uint32_t>& weld = welded.id;
    out.start.assign(welded.key.size() + 1, 0);
    const std::size_t corners = 3 * in_range.size();
    for (std::size_t c = 0; c < corners; ++c)
        if (in_range[c / 3]) ++out.start[weld[mesh.indices[c]] + 1];
    for (std::size_t w = 0; w + 1 < out.start.size(); ++w) out.start[w + 1] += out.start[w];
    std::vector<std::uint32_t> slot(corners, ~0u);
    std::vector<std::uint32_t> next(out.start.begin(), out.start.end() - 1);
    for (std::size_t c = 0; c < corners; ++c)
        if (in_range[c / 3]) slot[c] = next[weld[mesh.indices[c]]]++;
    out.corner.resize(out.start.back());
    return slot;
}

// Face normals and corner angles (zero for degenerate triangles): each valid triangle's corners
// described into their places.
void describe_corners(const Mesh& mesh, const std::vector<std::uint32_t>& weld, const std::vector<bool>& in_range,
                      const std::vector<std::uint32_t>& slot, detail::ThreadPool* pool, CornersByPosition& out) {
    for_blocks(pool, in_range.size(), [&](std::size_t first, std::size_t last, int) {
        for (std::size_t t = first; t < last; ++t) {
            if (!in_range[t]) continue;
            const std::uint32_t* idx = mesh.indices.data() + 3 * t;
            const Vec3 p[3] = {mesh.positions[idx[0]], mesh.positions[idx[1]], mesh.positions[idx[2]]};
            const Vec3 face = normalize(cross(p[1] - p[0], p[2] - p[0]));
            float angle[3] = {0, 0, 0};
            if (dot(face, face) > 0) {  // degenerate: no weight anywhere (and no NaN angles)
                // Each side normalized once: the corner at k sees sides k and k + 2 reversed, and
                // normalize(-v) is exactly -normalize(v).
                const Vec3 side[3] = {normalize(p[1] - p[0]), normalize(p[2] - p[1]), normalize(p[0] - p[2])};
                for (int k = 0; k < 3; ++k) angle[k] = std::acos(clamp(dot(side[k], -side[(k + 2) % 3]), -1.0f, 1.0f));
            }
            const std::uint32_t w[3] = {weld[idx[0]], weld[idx[1]], weld[idx[2]]};
            for (std::uint32_t k = 0; k < 3; ++k) {
                const auto c = static_cast<std::uint32_t>(3 * t + k);
                out.corner[slot[c]] = {c, w[(k + 1) % 3], w[(k + 2) % 3], face, face * angle[k]};
            }
        }
    });
}

// One triangle side that ends at the position being worked on: the position at its other end,
// the side's number (3 * triangle + k for the side from corner k to corner k + 1, the order in
// which the sides of an edge are compared) and which of the position's corners it ends at.
struct SideAt {
    std::uint32_t other, side, local_corner;
    bool operator<(const SideAt& b) const { return other != b.other ? other < b.other : side < b.side; }
};

// A position's scratch memory, kept by each thread from one position to the next.
struct FanScratch {
    std::vector<SideAt> sides;
    std::vector<std::uint32_t> parent;  // union-find over the position's corners, by local index
    std::vector<Vec3> sum;

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

// What each corner ends with: the smallest corner of its set and the set's normalized normal.
struct CornerSet {
    std::uint32_t set;
    Vec3 normal;
};

// The corners around one welded position w, split into sets: two corners are in one set when
// their triangles share an edge from w at less than the crease angle (directly or through others).
// A set's normal is the angle-weighted sum of its faces in corner order. Sets never reach beyond
// one position, so positions are independent of each other. Returns the sum of all the corners.
Vec3 split_fan(std::uint32_t w, std::span<const FanCorner> corners, float cos_crease, FanScratch& s,
               std::vector<CornerSet>& result) {
    s.sides.resize(2 * corners.size());
    std::size_t n = 0;
    for (std::uint32_t local = 0; local < corners.size(); ++local) {
        const FanCorner& c = corners[local];
        if (!(dot(c.face, c.face) > 0)) continue;  // degenerate: on no edge
        const std::uint32_t prev = c.corner / 3 * 3 + (c.corner + 2) % 3;
        if (c.next_position != w) s.sides[n++] = {c.next_position, c.corner, local};
        if (c.prev_position != w) s.sides[n++] = {c.prev_position, prev, local};
    }
    s.sides.resize(n);
    s.parent.resize(corners.size());
    std::iota(s.parent.begin(), s.parent.end(), 0u);
    auto compare = [&](const SideAt& a, const SideAt& b) {
        if (dot(corners[a.local_corner].face, corners[b.local_corner].face) > cos_crease) s.join(a.local_corner, b.local_corner);
    };
    if (all_pairs_within_reach(s.sides)) {
        // The order of the joins does not matter: every pair of sides on one edge is compared.
        for (std::size_t i = 1; i < n; ++i)
            for (std::size_t j = 0; j < i; ++j)
                if (s.sides[i].other == s.sides[j].other) compare(s.sides[i], s.sides[j]);
    } else {
        // The sides of one edge adjacent, in the order of their numbers (the keys are unique: no
        // order among equals to keep), each compared with its predecessors within reach.
        std::sort(s.sides.begin(), s.sides.end());
        for (std::size_t begin = 0, end = 0; begin < n; begin = end) {
            end = begin + 1;
            while (end < n && s.sides[end].other == s.sides[begin].other) ++end;
            for (std::size_t i = begin + 1; i < end; ++i)
                for (std::size_t j = i > begin + k_max_edge_neighbours ? i - k_max_edge_neighbours : begin; j < i; ++j)
                    compare(s.sides[i], s.sides[j]);
        }
    }
    s.sum.assign(corners.size(), Vec3{});
    Vec3 around{};
    for (std::uint32_t local = 0; local < corners.size(); ++local) {
        s.sum[s.find(local)] += corners[local].weighted;
        around += corners[local].weighted;
    }
    for (std::uint32_t local = 0; local < corners.size(); ++local) {
        const std::uint32_t root = s.find(local);
        result[corners[local].corner] = {corners[root].corner, normalize(s.sum[root])};
    }
    return around;
}

}  // namespace

void compute_creased_normals(Mesh& mesh, float crease_angle_radians, int threads) {
    const std::size_t vertex_count = mesh.positions.size();
    const std::size_t triangles = mesh.indices.size() / 3;
    // Threads only for meshes that have a block for each; they end before this returns.
    std::optional<detail::ThreadPool> pool;
    if (threads != 1 && triangles >= 2 * k_block) pool.emplace(threads <= 0 ? 0 : threads);
    detail::ThreadPool* workers = pool && pool->size() > 1 ? &*pool : nullptr;

    const Weld welded = weld_by_position(mesh.positions);
    // Decided once: the last pass below rewrites indices to vertex copies beyond vertex_count.
    std::vector<bool> in_range(triangles);
    for (std::size_t t = 0; t < triangles; ++t)
        in_range[t] = mesh.indices[3 * t] < vertex_count && mesh.indices[3 * t + 1] < vertex_count &&
                      mesh.indices[3 * t + 2] < vertex_count;

    // Each welded position's corners split into sets (split_fan); corners of invalid triangles
    // are in no set and left alone below.
    CornersByPosition by_position;
    describe_corners(mesh, welded.id, in_range, place_corners(mesh, welded, in_range, by_position), workers, by_position);
    const float cos_crease = std::cos(crease_angle_radians);
    std::vector<CornerSet> corner_set(3 * triangles);
    std::vector<Vec3> around(welded.key.size());  // for corners without area: the average around the position
    std::vector<FanScratch> scratch(workers ? workers->size() : 1);
    for_blocks(workers, welded.key.size(), [&](std::size_t first, std::size_t last, int worker) {
        for (std::size_t w = first; w < last; ++w) {
            const std::span<const FanCorner> corners(by_position.corner.data() + by_position.start[w],
                                                     by_position.start[w + 1] - by_position.start[w]);
            around[w] = split_fan(static_cast<std::uint32_t>(w), corners, cos_crease, scratch[worker], corner_set);
        }
    });

    // Each vertex takes the normal of the first set among its corners; corners from another set get
    // a copy of the vertex. Corners without area take whatever their vertex has.
    constexpr std::uint32_t none = ~0u;
    std::vector<std::uint32_t> vertex_set(vertex_count, none);
    std::unordered_map<std::uint64_t, std::uint32_t> copies;  // (vertex << 32 | set) -> new vertex
    mesh.normals.assign(vertex_count, Vec3{});
    auto copy_vertex = [&](std::uint32_t v) {
        const auto n = static_cast<std::uint32_t>(mesh.positions.size());
        mesh.positions.push_back(mesh.positions[v]);
        mesh.normals.push_back(Vec3{});
        if (!mesh.colours.empty()) mesh.colours.push_back(mesh.colours[v]);
        if (!mesh.uvs.empty()) mesh.uvs.push_back(mesh.uvs[v]);
        return n;
    };
    for (std::uint32_t c = 0; c < 3 * triangles; ++c) {
        if (!in_range[c / 3]) continue;
        const auto [set, n] = corner_set[c];
        if (!(dot(n, n) > 0)) continue;
        const std::uint32_t v = mesh.indices[c];
        if (vertex_set[v] == none) {
            vertex_set[v] = set;
            mesh.normals[v] = n;
        } else if (vertex_set[v] != set) {
            auto [it, inserted] = copies.try_emplace(std::uint64_t{v} << 32 | set, 0u);
            if (inserted) {
                it->second = copy_vertex(v);
                mesh.normals[it->second] = n;
            }
            mesh.indices[c] = it->second;
        }
    }
    for (std::uint32_t v = 0; v < vertex_count; ++v) {
        if (vertex_set[v] != none) continue;
        const Vec3 n = normalize(around[welded.id[v]]);
        mesh.normals[v] = dot(n, n) > 0 ? n : Vec3{0, 0, 1};
    }
}

Mesh make_cube(float h) {
    // Each face: outward normal n, and two axes u, v with cross(u, v) = n so corners run counter-clockwise.
    struct Face {
        Vec3 n, u, v;
        Vec4 colour;
    };
    const Face faces[6] = {
        {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}, {0.90f, 0.30f, 0.25f, 1}},
        {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}, {0.25f, 0.70f, 0.90f, 1}},
        {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}, {0.95f, 0.80f, 0.25f, 1}},
        {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}, {0.55f, 0.35f, 0.80f, 1}},
        {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {0.30f, 0.80f, 0.40f, 1}},
        {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}, {0.95f, 0.55f, 0.20f, 1}},
    };
    Mesh m;
    for (const Face& f : faces) {
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        const float corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
        for (const auto& c : corners) {
            m.positions.push_back((f.n + f.u * c[0] + f.v * c[1]) * h);
            m.normals.push_back(f.n);
            m.colours.push_back(f.colour);
            m.uvs.push_back({(c[0] + 1) / 2, (c[1] + 1) / 2});
        }
        for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(base + i);
    }
    return m;
}

Mesh make_uv_sphere(float radius, int slices, int stacks) {
    Mesh m;
    for (int j = 0; j <= stacks; ++j) {
        const float v = static_cast<float>(j) / stacks, phi = v * k_pi;  // from the north pole down
        for (int i = 0; i <= slices; ++i) {
            const float u = static_cast<float>(i) / slices, theta = u * 2 * k_pi;
            const Vec3 n{std::sin(phi) * std::sin(theta), std::cos(phi), std::sin(phi) * std::cos(theta)};
            m.positions.push_back(n * radius);
            m.normals.push_back(n);
            m.uvs.push_back({u, v});
        }
    }
    const int row = slices + 1;
    for (int j = 0; j < stacks; ++j)
        for (int i = 0; i < slices; ++i) {
            const auto a = static_cast<std::uint32_t>(j * row + i), b = a + 1, c = a + row, d = c + 1;
            if (j > 0) m.indices.insert(m.indices.end(), {a, c, b});
            if (j < stacks - 1) m.indices.insert(m.indices.end(), {b, c, d});
        }
    return m;
}

Mesh make_icosphere(float radius, int subdivisions) {
    const float t = (1.0f + std::sqrt(5.0f)) / 2;
    std::vector<Vec3> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                           {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (Vec3& v : p) v = normalize(v);
    std::vector<std::uint32_t> idx = {0, 11, 5, 0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                                      4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9,  4, 3,  4,  2, 3, 2, 6, 3,
                                      6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6, 2, 10, 8,  6, 7, 9, 8, 1};
    for (int s = 0; s < subdivisions; ++s) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            auto key = std::minmax(a, b);
            auto [it, inserted] = midpoints.try_emplace({key.first, key.second}, static_cast<std::uint32_t>(p.size()));
            if (inserted) p.push_back(normalize(p[a] + p[b]));
            return it->second;
        };
        std::vector<std::uint32_t> next;
        next.reserve(idx.size() * 4);
        for (std::size_t i = 0; i < idx.size(); i += 3) {
            const std::uint32_t a = idx[i], b = idx[i + 1], c = idx[i + 2];
            const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
            next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        idx = std::move(next);
    }
    Mesh m;
    m.normals = p;
    for (Vec3 v : p) m.positions.push_back(v * radius);
    m.indices = std::move(idx);
    return m;
}

Mesh make_torus(float major_radius, float minor_radius, int segments, int sides) {
    Mesh m;
    for (int i = 0; i <= segments; ++i) {
        const float u = static_cast<float>(i) / segments, a = u * 2 * k_pi;
        const Vec3 centre{std::cos(a) * major_radius, 0, -std::sin(a) * major_radius};
        for (int j = 0; j <= sides; ++j) {
            const float v = static_cast<float>(j) / sides, b = v * 2 * k_pi;
            const Vec3 n{std::cos(a) * std::cos(b), std::sin(b), -std::sin(a) * std::cos(b)};
            m.positions.push_back(centre + n * minor_radius);
            m.normals.push_back(n);
            m.uvs.push_back({u, v});
        }
    }
    const int row = sides + 1;
    for (int i = 0; i < segments; ++i)
        for (int j = 0; j < sides; ++j) {
            const auto a = static_cast<std::uint32_t>(i * row + j), b = a + 1, c = a + row, d = c + 1;
            m.indices.insert(m.indices.end(), {a, c, d, a, d, b});
        }
    return m;
}

Mesh make_checker_plane(float size, int cells, Vec4 colour_a, Vec4 colour_b) {
    Mesh m;
    const float step = size / cells, origin = -size / 2;
    for (int j = 0; j < cells; ++j)
        for (int i = 0; i < cells; ++i) {
            const auto base = static_cast<std::uint32_t>(m.positions.size());
            const Vec4 colour = (i + j) % 2 ? colour_a : colour_b;
            const float x0 = origin + i * step, z0 = origin + j * step;
            for (Vec2 c : {Vec2{0, 0}, Vec2{0, 1}, Vec2{1, 1}, Vec2{1, 0}}) {
                m.positions.push_back({x0 + c.x * step, 0, z0 + c.y * step});
                m.normals.push_back({0, 1, 0});
                m.colours.push_back(colour);
                m.uvs.push_back({(i + c.x) / cells, (j + c.y) / cells});
            }
            m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
        }
    return m;
}

}  // namespace facet
