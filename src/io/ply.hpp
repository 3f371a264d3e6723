// facet io: a fast reader for PLY meshes that carry positions only (most scans, such as Stanford's),
// used by load_model instead of assimp when it can be. It gives exactly the mesh the assimp path
// makes of the same file (assimp's PLY reader, then JoinIdenticalVertices, then facet's conversion:
// joined_mesh.hpp).
//
// It takes only this form, ASCII or binary (either byte order):
//   ply / format ... 1.0 / element vertex N / property lines / element face M /
//   property list <integer> <integer> vertex_indices (or vertex_index) / end_header
// with "comment" and "obj_info" lines before the first element and after the face list (assimp
// misreads a property list with one inside); the vertex properties are x, y and z,
// each float or double, and any of "confidence" and "intensity" (which assimp ignores); every face
// is a triangle of vertices in range, every coordinate finite, and the file holds exactly the
// announced data (ASCII: one element per line, values separated by spaces, nothing else but white
// space at the end; binary: no carriage return in the header, no byte after the last face). Anything
// else (normals, colours, texture coordinates, other elements or properties, polygons) gives
// nullopt, and the caller loads the file through assimp as before.
#pragma once

#include <optional>
#include <string_view>

#include "io/joined_mesh.hpp"

namespace facet::io_detail {

// `bytes` is the whole file, followed by a NUL character (as std::string's data is).
std::optional<JoinedMesh> read_plain_ply(std::string_view bytes);

}  // namespace facet::io_detail
