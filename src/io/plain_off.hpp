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
// of range, a count that does not match the lines, non-finite or extremely small coordinates,
// a NUL byte) gives nullopt, and the caller loads the file through assimp as before, with its
// messages and workarounds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "facet/math/vec.hpp"

namespace facet::io_detail {

struct PlainOffMesh {
    std::vector<Vec3> positions;          // joined by position, in order of first use by the triangles
    std::vector<std::uint32_t> indices;   // three per triangle, in file order
    std::size_t degenerate = 0;           // triangles with two corners at the same position
};

// `text` is the whole file and must be followed by a NUL character (as std::string's data is):
// the parser relies on it to stop.
std::optional<PlainOffMesh> read_plain_off(std::string_view text);

}  // namespace facet::io_detail
