// facet scene internals: compute_creased_normals (facet/mesh.hpp) for facet's own readers, which
// have a pool of threads already and meshes whose positions they have joined (io/joined_mesh.hpp).
#pragma once

#include "facet/detail/thread_pool.hpp"
#include "facet/mesh.hpp"

namespace facet::detail {

// compute_creased_normals on `pool`'s threads (nullptr: this thread alone; small meshes use one
// either way). `distinct_positions`: no two vertices have equal positions (-0 as +0), as after
// join_identical_vertices: each vertex is then its own welded position and the welding is left
// out. The result is compute_creased_normals's, bit for bit.
void compute_creased_normals_on(Mesh& mesh, float crease_angle_radians, ThreadPool* pool, bool distinct_positions);
// The same with a pool of `threads` started for large meshes, as compute_creased_normals does.
void compute_creased_normals_with(Mesh& mesh, float crease_angle_radians, int threads, bool distinct_positions);

}  // namespace facet::detail
