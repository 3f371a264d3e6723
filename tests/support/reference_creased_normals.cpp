// Test support: compute_creased_normals as it was before its edges were grouped by hashing
// instead of sorting (src/scene/mesh.cpp at commit c69cde8), kept as the specification the
// faster version must match bit for bit.
#include "support/reference_creased_normals.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <numeric>
#include <unordered_map>
#include <vector>

#include "scene/triangle_shapes.hpp"

namespace facet_test {

using namespace facet;

namespace {

// Welding for crease detection: an id per distinct position (exact bits, -0 equal to +0), so
// vertices that are only duplicated by position (STL, seams in uv or colour) count as shared.
std::vector<std::uint32_t> weld_by_position(const std::vector<Vec3>& positions) {
    auto bits = [](float f) { return std::bit_cast<std::uint32_t>(f == 0.0f ? 0.0f : f); };
    auto key = [&](std::uint32_t i) {
        const Vec3 p = positions[i];
        return std::array<std::uint32_t, 3>{bits(p.x), bits(p.y), bits(p.z)};
    };
    // Sorting bit patterns is a total order even with NaN, unlike comparing floats.
    std::vector<std::uint32_t> order(positions.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
    std::vector<std::uint32_t> id(positions.size());
    std::uint32_t next = 0;
    for (std::size_t k = 0; k < order.size(); ++k) {
        if (k > 0 && key(order[k]) != key(order[k - 1])) ++next;
        id[order[k]] = next;
    }
    return id;
}

// Union-find over triangle corners (3 * triangle + k).
struct CornerSets {
    std::vector<std::uint32_t> parent;
    explicit CornerSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
    std::uint32_t find(std::uint32_t c) {
        while (parent[c] != c) c = parent[c] = parent[parent[c]];
        return c;
    }
    void join(std::uint32_t a, std::uint32_t b) {
        a = find(a), b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

// An edge between two welded positions (lo < hi) of a triangle, with the corners at each end.
struct WeldedEdge {
    std::uint32_t lo, hi, corner_lo, corner_hi;
};

// Faces on one edge are compared pairwise only with this many predecessors, so a non-manifold
// edge shared by thousands of triangles stays linear; ordinary edges have two faces.
constexpr std::size_t k_max_edge_neighbours = 8;

}  // namespace

void reference_creased_normals(Mesh& mesh, float crease_angle_radians) {
    const std::size_t vertex_count = mesh.positions.size();
    const std::size_t triangles = mesh.indices.size() / 3;
    const std::vector<std::uint32_t> weld = weld_by_position(mesh.positions);
    // Decided once: the last pass below rewrites indices to vertex copies beyond vertex_count.
    std::vector<bool> in_range(triangles);
    for (std::size_t t = 0; t < triangles; ++t)
        in_range[t] = mesh.indices[3 * t] < vertex_count && mesh.indices[3 * t + 1] < vertex_count &&
                      mesh.indices[3 * t + 2] < vertex_count;
    auto valid = [&](std::size_t t) { return in_range[t]; };

    // Face normals (zero for degenerate or invalid triangles) and the corner angles used as weights.
    std::vector<Vec3> face(triangles);
    std::vector<float> corner_angle(3 * triangles, 0.0f);
    for (std::size_t t = 0; t < triangles; ++t) {
        if (!valid(t)) continue;
        const Vec3 p[3] = {mesh.positions[mesh.indices[3 * t]], mesh.positions[mesh.indices[3 * t + 1]],
                           mesh.positions[mesh.indices[3 * t + 2]]};
        face[t] = normalize(cross(p[1] - p[0], p[2] - p[0]));
        if (!(dot(face[t], face[t]) > 0)) continue;  // degenerate: no weight anywhere (and no NaN angles)
        for (int k = 0; k < 3; ++k) {
            const Vec3 e1 = normalize(p[(k + 1) % 3] - p[k]), e2 = normalize(p[(k + 2) % 3] - p[k]);
            // fdlibm's acosf, which std::acos was with glibc 2.36 (triangle_shapes.hpp): the same
            // bits with any libm.
            corner_angle[3 * t + k] = detail::corner_acos(clamp(dot(e1, e2), -1.0f, 1.0f));
        }
    }
    auto degenerate = [&](std::size_t t) { return !(dot(face[t], face[t]) > 0); };

    // Corners of two triangles that share an edge at less than the crease angle are smoothed
    // together, at both ends of the edge; the joins spread around each vertex's fan.
    std::vector<WeldedEdge> edges;
    edges.reserve(3 * triangles);
    for (std::size_t t = 0; t < triangles; ++t) {
        if (!valid(t) || degenerate(t)) continue;
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::uint32_t ca = static_cast<std::uint32_t>(3 * t + k), cb = static_cast<std::uint32_t>(3 * t + (k + 1) % 3);
            const std::uint32_t a = weld[mesh.indices[ca]], b = weld[mesh.indices[cb]];
            if (a == b) continue;
            edges.push_back(a < b ? WeldedEdge{a, b, ca, cb} : WeldedEdge{b, a, cb, ca});
        }
    }
    std::sort(edges.begin(), edges.end(), [](const WeldedEdge& x, const WeldedEdge& y) {
        return x.lo != y.lo ? x.lo < y.lo : (x.hi != y.hi ? x.hi < y.hi : x.corner_lo < y.corner_lo);
    });
    const float cos_crease = std::cos(crease_angle_radians);
    CornerSets sets(3 * triangles);
    for (std::size_t begin = 0, end = 0; begin < edges.size(); begin = end) {
        end = begin + 1;
        while (end < edges.size() && edges[end].lo == edges[begin].lo && edges[end].hi == edges[begin].hi) ++end;
        for (std::size_t i = begin + 1; i < end; ++i)
            for (std::size_t j = i > begin + k_max_edge_neighbours ? i - k_max_edge_neighbours : begin; j < i; ++j) {
                const Vec3 ni = face[edges[i].corner_lo / 3], nj = face[edges[j].corner_lo / 3];
                if (!(dot(ni, nj) > cos_crease)) continue;  // a crease: keep the two sides apart
                sets.join(edges[i].corner_lo, edges[j].corner_lo);
                sets.join(edges[i].corner_hi, edges[j].corner_hi);
            }
    }

    // One normal per set of corners: the angle-weighted sum of their faces, in corner order so the
    // result does not depend on anything but the mesh.
    std::vector<Vec3> set_normal(3 * triangles);
    for (std::uint32_t c = 0; c < 3 * triangles; ++c) set_normal[sets.find(c)] += face[c / 3] * corner_angle[c];
    // A fallback for corners whose set has no area (degenerate triangles): the average around the position.
    std::unordered_map<std::uint32_t, Vec3> around;
    for (std::uint32_t c = 0; c < 3 * triangles; ++c)
        if (valid(c / 3)) around[weld[mesh.indices[c]]] += face[c / 3] * corner_angle[c];

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
        if (!valid(c / 3)) continue;
        const std::uint32_t set = sets.find(c);
        const Vec3 n = normalize(set_normal[set]);
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
        const Vec3 n = normalize(around[weld[v]]);
        mesh.normals[v] = dot(n, n) > 0 ? n : Vec3{0, 0, 1};
    }
}

}  // namespace facet_test
