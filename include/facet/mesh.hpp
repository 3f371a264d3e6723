// facet: triangle meshes in object space, and generators for the shapes examples and tests use.
// A Mesh is plain arrays: positions, and optionally one normal, colour and uv per position;
// indices name three positions per triangle, points one per point, lines two per segment.
// Loading files is io's job, not this header's.
#pragma once

#include <cstdint>
#include <vector>

#include "facet/api.hpp"
#include "facet/error.hpp"
#include "facet/math/mat.hpp"

FACET_API_BEGIN
namespace facet {

struct Aabb {
    Vec3 min{1e30f, 1e30f, 1e30f}, max{-1e30f, -1e30f, -1e30f};
    bool empty() const { return min.x > max.x; }
    Vec3 centre() const { return (min + max) * 0.5f; }
    void extend(Vec3 p) { min = facet::min(min, p), max = facet::max(max, p); }
};

struct Mesh {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;  // empty, or one per position
    std::vector<Vec4> colours;  // empty, or one per position (linear RGBA in [0, 1])
    std::vector<Vec2> uvs;      // empty, or one per position
    std::vector<std::uint32_t> indices;  // three per triangle
    // Empty, or one per position: xyz the unit tangent (the direction of increasing u, orthogonal to
    // the normal), w = +1 or -1, the side of the bitangent: b = w cross(n, t) points toward the top of
    // the texture image (decreasing v), as glTF's TANGENT. What normal maps are read with.
    std::vector<Vec4> tangents;
    // Points and line segments drawn besides the triangles (README, "Points and lines"), from the
    // same vertices: one index per point, two per segment (strips and loops as segments that share
    // their ends, which join without gaps).
    std::vector<std::uint32_t> points;
    std::vector<std::uint32_t> lines;

    std::size_t triangle_count() const { return indices.size() / 3; }
    // Checks that the attribute arrays match the positions and every index is in range.
    Status validate() const;
    // Bounds of the finite positions.
    Aabb bounds() const;
    // Appends another mesh (its indices, points and lines shifted), transformed by `model`. Attributes
    // missing on one side are filled with defaults (normal 0, colour white, uv 0) so the arrays stay aligned.
    void append(const Mesh& other, const Mat4& model = Mat4::identity());
};

// Smooth per-vertex normals: the angle-weighted average of the faces around each vertex (shared
// vertices only; split the vertices first for hard edges). Degenerate faces contribute nothing.
void compute_smooth_normals(Mesh& mesh);
// Tangents for normal mapping (Mesh::tangents) from the normals and uvs, for meshes whose file has
// none; the rule (README, "Materials"): per triangle, t = dP/du and b = -dP/dv from its positions and
// uvs (triangles whose uvs are degenerate add nothing), summed at each corner weighted by the corner's
// angle (as MikkTSpace weights them, without its vertex splitting), then t made orthogonal to the
// vertex normal (Gram-Schmidt) and unit, w = -1 where the summed b is on the side of -cross(n, t).
// A vertex with no usable triangle gets any unit vector orthogonal to its normal, w = 1.
// Needs normals and uvs (does nothing without either).
void compute_tangents(Mesh& mesh);
// Gives every triangle its own three vertices and its face normal: the faceted look.
Mesh split_faces_flat(const Mesh& mesh);
// Normals with hard edges where faces meet at a sharp angle: two triangles that share an edge are
// smoothed together when their face normals differ by less than `crease_angle_radians`, and split
// otherwise (pi keeps everything smooth, 0 gives flat faces). Vertices are welded by position
// first, so an unindexed mesh (STL) smooths like an indexed one; the vertex arrays are kept, and a
// vertex whose corners end up with different normals is duplicated (colour and uv copied). Each
// normal is the angle-weighted average of the faces smoothed together around the vertex.
// `threads` (0: one per core) share large meshes; the result is the same for any number.
void compute_creased_normals(Mesh& mesh, float crease_angle_radians, int threads = 1);

// Shapes, centred at the origin, counter-clockwise outward faces, with normals and uvs.
Mesh make_cube(float half_size = 1.0f);                      // 24 vertices, a colour per face
Mesh make_uv_sphere(float radius, int slices, int stacks);
Mesh make_icosphere(float radius, int subdivisions);         // 20 * 4^subdivisions triangles
Mesh make_torus(float major_radius, float minor_radius, int segments, int sides);
// A flat grid in the XZ plane facing +Y, cells x cells, of side `size`, checkered in two colours.
Mesh make_checker_plane(float size, int cells, Vec4 colour_a, Vec4 colour_b);

}  // namespace facet
FACET_API_END
