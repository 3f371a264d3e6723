// facet io: assimp 5.2.5's Triangulate step for facet's own readers (obj.cpp, plain_off.cpp), so
// that they split polygons into the triangles assimp makes of them. In: a polygon's corner
// positions (and the ids its caller gives corners); out: triangles as corner numbers, or rotated
// in place as assimp's NGONEncoder rotates them. Not the rest of Triangulate (lines, points).
#pragma once

#include <assimp/vector2.h>
#include <assimp/vector3.h>

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace facet::io_detail {

// A quad is split from the corner where the angles to its neighbours, measured against the
// diagonal, add up to more than pi (the concave corner), else from corner 0: triangles (s, s+1,
// s+2) and (s, s+2, s+3), corners mod 4.
int quad_start(const aiVector3D* const p[4]);

// A polygon of n > 4 corners at positions p: projected onto the plane of its Newell normal's
// largest component, then cut into ears. Out: triangles as corner numbers, in assimp's order;
// false when it found no ear (assimp logs an error and keeps the triangles cut so far).
bool cut_ears(const std::vector<aiVector3D>& p, std::vector<std::array<int, 3>>& out);

// NGONEncoder: a triangle whose first corner is the one the last triangle (or quad) began with
// would read as part of the same polygon, so its corners are rotated. Corners are compared by the
// id the mesh gives them (assimp: the vertex index). Every triangle of a mesh goes through it once
// the mesh has a polygon.
class NgonEncoder {
public:
    void triangle(std::uint32_t (&t)[3]) {
        if (t[0] == last_first_) std::swap(t[0], t[2]), std::swap(t[1], t[2]);
        last_first_ = t[0];
    }
    // The two triangles of a quad, sharing their first corner: both turned to fan from another.
    void quad(std::uint32_t (&t1)[3], std::uint32_t (&t2)[3]) {
        if (t1[0] == last_first_) {
            std::swap(t1[0], t1[2]), std::swap(t1[1], t1[2]);
            std::swap(t2[1], t2[2]), std::swap(t2[0], t2[2]);
        }
        last_first_ = t1[0];
    }

private:
    std::uint32_t last_first_ = ~0u;
};

// Where a mesh's faces are triangulated: the encoder and the buffers of its polygons.
struct Triangulator {
    NgonEncoder encoder;
    std::vector<aiVector3D> polygon;
    std::vector<std::array<int, 3>> ears;

    // A face of n >= 3 corners, corner k with the id id(k) at position(k) (an aiVector3D), as
    // triangles of ids through emit(a, b, c), in assimp's order; false where cut_ears found no ear
    // (the triangles cut so far emitted).
    template <class Id, class Position, class Emit>
    bool face(std::uint32_t n, const Id& id, const Position& position, const Emit& emit) {
        if (n == 3) {
            std::uint32_t t[3] = {id(0), id(1), id(2)};
            encoder.triangle(t);
            emit(t[0], t[1], t[2]);
            return true;
        }
        if (n == 4) {
            const aiVector3D q[4] = {position(0), position(1), position(2), position(3)};
            const aiVector3D* p[4] = {&q[0], &q[1], &q[2], &q[3]};
            const auto s = static_cast<std::uint32_t>(quad_start(p));
            const auto at = [&](std::uint32_t k) { return id((s + k) % 4); };
            std::uint32_t t1[3] = {at(0), at(1), at(2)}, t2[3] = {at(0), at(2), at(3)};
            encoder.quad(t1, t2);
            emit(t1[0], t1[1], t1[2]);
            emit(t2[0], t2[1], t2[2]);
            return true;
        }
        polygon.clear();
        for (std::uint32_t k = 0; k < n; ++k) polygon.push_back(position(k));
        ears.clear();
        const bool whole = cut_ears(polygon, ears);
        for (const std::array<int, 3>& e : ears) {
            std::uint32_t t[3] = {id(static_cast<std::uint32_t>(e[0])), id(static_cast<std::uint32_t>(e[1])),
                                  id(static_cast<std::uint32_t>(e[2]))};
            encoder.triangle(t);
            emit(t[0], t[1], t[2]);
        }
        return whole;
    }
};

}  // namespace facet::io_detail
