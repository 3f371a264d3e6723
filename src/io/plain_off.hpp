// facet io: a fast reader for plain triangle OFF files (CGAL's and many scanned meshes), used by
// load_model instead of assimp when it can be. It gives exactly the mesh the assimp path makes of
// the same file (assimp's OFF reader, then JoinIdenticalVertices, then facet's conversion: the
// joined vertices in order of first use by the triangles), at a small fraction of the cost: it
// parses numbers with assimp's own fast_atof and joins vertices the way assimp does for the
// files it takes.
//
// It takes only files that both readers read the same way: "OFF" alone on the first line, the
// three counts alone on the next, then exactly the announced vertex lines (at least three
// numbers) and triangle lines ("3 a b c"), blank lines allowed between them. Anything else
// (comments, a variant header such as COFF or STOFF, polygons other than triangles, an index out
// of range, a count that does not match the lines, non-finite coordinates, distinct positions
// that assimp's tolerance would join, a NUL byte) gives nullopt, and the caller loads the file through assimp as before, with its
// messages and workarounds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "io/joined_mesh.hpp"

namespace facet::io_detail {

using PlainOffMesh = JoinedMesh;

// `text` is the whole file and must be followed by a NUL character (as std::string's data is):
// the parser relies on it to stop.
std::optional<PlainOffMesh> read_plain_off(std::string_view text);

}  // namespace facet::io_detail
