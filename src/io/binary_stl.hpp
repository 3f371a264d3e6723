// facet io: a fast reader for binary STL files (the usual output of CAD and 3D-printing tools), used
// by load_model instead of assimp when it can be. It gives exactly the mesh the assimp path makes of
// the same file (assimp's STL reader with the facet normals removed, then JoinIdenticalVertices, then
// facet's conversion: joined_mesh.hpp), without assimp's per-vertex arrays and post-processing.
//
// It takes only files assimp reads as binary STL without colours: exactly 84 + 50 n bytes for the
// n > 0 facets the header announces, no "COLOR=" in the 80-byte header (a Materialise file, whose
// colour assimp makes the material's), no facet with its colour bit (bit 15 of the attribute)
// set, finite coordinates, and no two positions only assimp's tolerance would join. Anything else gives nullopt, and the caller loads the
// file through assimp as before (ASCII STL, coloured STL, damaged files and their messages).
#pragma once

#include <optional>
#include <string_view>

#include "io/joined_mesh.hpp"

namespace facet::io_detail {

std::optional<JoinedMesh> read_binary_stl(std::string_view bytes);

}  // namespace facet::io_detail
