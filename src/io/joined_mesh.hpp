// facet io: what assimp's JoinIdenticalVertices and facet's conversion of its mesh make of a list
// of triangles, for the readers that load a format without assimp (plain_off.hpp, stl.hpp)
// and must give exactly the Scene the assimp path gives:
//  - JoinIdenticalVertices: only vertices the triangles use, joined when their positions are equal
//    (-0 equal to +0), each group keeping the first of them in file order. assimp finds equal
//    positions with a tolerance of a few units in the last place of tiny squared distances (about
//    1e-44), which differs from exact equality only for distinct positions whose every coordinate
//    is equal or tiny in both (below 2^-49: the nearest distinct float to any other value is more
//    than 2^-72 away). A file with two such positions, or a non-finite coordinate, is left to assimp;
//  - facet's conversion: vertices renumbered in order of first use by the triangles.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "facet/detail/thread_pool.hpp"
#include "facet/math/vec.hpp"

namespace facet::io_detail {

struct JoinedMesh {
    std::vector<Vec3> positions;          // joined by position, in order of first use by the triangles
    std::vector<std::uint32_t> indices;   // three per triangle, in file order
    std::size_t degenerate = 0;           // triangles with two corners at the same position
    std::vector<std::uint32_t> source;    // each vertex's file vertex (the first of its group)
    std::vector<Vec4> colours;            // empty, or one per vertex (the reader fills them from `source`)
    std::size_t dropped_faces = 0;        // faces the reader left out as assimp's reader does (with an error)
    bool faces_missing = false;           // fewer face lines than the header's count (assimp logs an error)
};

// The mesh of triangles `file_indices` (three per triangle, each < file_positions.size()) over
// `file_positions` (finite), joined and renumbered as above; nullopt when assimp's tolerance could
// join two used positions that are not equal.
// With a pool, its threads share the work (the same mesh).
std::optional<JoinedMesh> join_identical_vertices(const std::vector<Vec3>& file_positions,
                                                  const std::vector<std::uint32_t>& file_indices,
                                                  detail::ThreadPool* pool = nullptr);

}  // namespace facet::io_detail
