// facet io: a fast reader for STL files (the usual output of CAD and 3D-printing tools), used by
// load_model instead of assimp when it can be. It gives exactly the mesh the assimp path makes of the
// same file (assimp's STL reader with the facet normals removed, then JoinIdenticalVertices, then
// facet's conversion: joined_mesh.hpp), without assimp's per-vertex arrays and post-processing.
//
// It takes the files assimp reads the same way and without remarks:
//  - binary (as assimp decides: exactly 84 + 50 n bytes for the n facets the header announces),
//    n > 0, no "COLOR=" in the 80-byte header (a Materialise file, whose colour assimp makes the
//    material's), no facet with its colour bit (bit 15 of the attribute) set;
//  - ASCII, one solid in the plain form: "solid" and an optional name, then facets that are each
//    "facet normal" with three numbers, "outer loop", three "vertex" lines of three numbers,
//    "endloop", "endfacet", then "endsolid" and its line, and nothing but white space after it.
//    Tokens are separated by spaces, tabs and line ends; a vertex's or normal's numbers share its
//    line; every number ends at a separator.
// In both, every coordinate is finite and no two positions are ones only assimp's tolerance would
// join. Anything else (several solids, other tokens, a NUL byte, a byte-order mark, colours) gives
// nullopt, and the caller loads the file through assimp as before, with its messages and
// workarounds.
#pragma once

#include <optional>
#include <string_view>

#include "io/joined_mesh.hpp"

namespace facet::io_detail {

// `bytes` is the whole file; read_ascii_stl needs it followed by a NUL character (as std::string's
// data is), which stops its parser.
std::optional<JoinedMesh> read_binary_stl(std::string_view bytes);
std::optional<JoinedMesh> read_ascii_stl(std::string_view bytes);
// The one of the two assimp would use: binary when the size says so, else ASCII.
std::optional<JoinedMesh> read_stl(std::string_view bytes);

}  // namespace facet::io_detail
