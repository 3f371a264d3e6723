// facet scene internals: face normals and the cosines of the corner angles of many triangles at
// once (triangle_shapes_simd.cpp), for compute_creased_normals (mesh.cpp), whose describe_triangle
// is the specification.
#pragma once

#include <cstddef>
#include <cstdint>

namespace facet::detail {

// k_capacity triangles as structures of arrays: their corners' positions in, their shapes out.
struct TriangleChunk {
    static constexpr std::size_t k_capacity = 64;  // a bit of `unusual` each
    alignas(64) float corner[3][3][k_capacity];    // [corner][axis][triangle]
    alignas(64) float face[3][k_capacity];         // the normal, [axis][triangle]
    alignas(64) float cosine[3][k_capacity];       // each corner's, clamped to [-1, 1]
    // A bit per triangle left to the specification: one of its four normalizations (the face's and
    // its sides') is not of a vector of finite, non-zero length, so it takes normalize's rare path.
    // Degenerate triangles are among them. The other triangles' face and cosines are the
    // specification's, bit for bit.
    std::uint64_t unusual;
};

// The shapes of all the chunk's triangles (fill the places not used, e.g. with zeros). Returns
// false, computing nothing, when the scalar ISA is selected (facet/isa.hpp).
bool shape_triangles(TriangleChunk& chunk);

}  // namespace facet::detail
