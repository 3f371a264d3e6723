// facet internals: the hook by which a shader type brings a compiled vertex stage, and the SIMD
// transforms it is made of. Renderer::draw calls vertex() once per vertex; a shader type for which
// CompiledVertexStage is specialized with available = true computes a block of vertices with its
// run(shader, begin, end, clip, varyings) instead, and gives one vertex's clip position again, the
// same bits, with position(shader, i) (clipping's; the stage keeps no array of them). The built-in
// shaders whose vertex() is a matrix times the position and the normal (shaders.hpp) have one: the
// same bytes as vertex(), several vertices at a time.
#pragma once

#include <cstddef>

#include "facet/api.hpp"
#include "facet/math/mat.hpp"

FACET_API_BEGIN
namespace facet::detail {

template <class S>
struct CompiledVertexStage {
    static constexpr bool available = false;
};

// out[i] = m * Vec4(points[i], 1) for i in [0, n), bit for bit as Mat4's operator* computes it
// (src/vertex/transform_simd.cpp: SIMD on every ISA but "scalar").
void transform_points(const Mat4& m, const Vec3* points, std::size_t n, Vec4* out);

// out[i * stride + k] = (m * directions[i])[k] for k < 3 and i in [0, n), bit for bit as Mat3's
// operator*; or 0 when directions is null (no normals: world_normal's Vec3{}).
void transform_directions(const Mat3& m, const Vec3* directions, std::size_t n, float* out, std::size_t stride);

}  // namespace facet::detail
FACET_API_END
