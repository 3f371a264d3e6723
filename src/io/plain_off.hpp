// facet io: a fast reader for OFF and COFF files (CGAL's and many scanned meshes), used by
// load_model instead of assimp when it can be. It gives exactly the mesh the assimp path makes of
// the same file (assimp's OFF reader, then JoinIdenticalVertices, then facet's conversion: the
// joined vertices in order of first use by the triangles), at a small fraction of the cost: it
// parses numbers with assimp's own fast_atof and joins vertices the way assimp does for the
// files it takes.
//
// It takes only files that both readers read the same way: "OFF" or "COFF" and the three counts
// ('#' lines and blank lines between them), then exactly the announced vertex lines (at least
// three numbers; for COFF four more, the colour) and face lines of 3 to 9 corners (polygons are
// triangulated as assimp's Triangulate does), blank lines allowed between them; a face line of no
// corners or more than 9 (a comment among the faces reads as one) is dropped as assimp drops it,
// with its error, reading on for the count. Anything else (a comment among the vertices, another variant header
// such as NOFF or STOFF, faces of 1 or 2 corners, an index out of range, a count that does not
// match the lines, non-finite coordinates, distinct positions that assimp's tolerance would join,
// a polygon with no ear, a NUL byte) gives nullopt, and the caller loads the file through assimp
// as before, with its messages and workarounds.
//
// The header is parsed once, from the file's first bytes (parse_off_header), and read two ways: by
// the pre-check that refuses counts the file cannot hold (check_off_header), and by the reader.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "facet/detail/thread_pool.hpp"
#include "facet/error.hpp"
#include "facet/model.hpp"
#include "io/joined_mesh.hpp"

namespace facet::io_detail {

using PlainOffMesh = JoinedMesh;

struct OffHeader {
    // The first three words, '#' comments left out: the keyword ("[ST][C][N][4]OFF") and the vertex
    // and face counts, wherever their lines put them (as assimp reads them).
    std::vector<std::string> tokens;
    // The form the reader takes: "OFF" or "COFF" (colours), the three counts, the body on a line
    // of its own ('#' lines and blank lines between them, as assimp skips them).
    struct Plain {
        std::uint32_t vertices = 0, faces = 0;
        std::size_t body = 0;  // offset of the line end before the body's first line
        bool colours = false;  // COFF
    };
    std::optional<Plain> plain;
};

// `head` is the file's first bytes, followed by a NUL character (as std::string's data is).
OffHeader parse_off_header(std::string_view head);

// Refuses vertex and face counts that the file's `size` bytes cannot hold (a vertex takes at least
// three values, "0 0 0\n", a face at least its count), and more faces than options.max_triangles.
Status check_off_header(const std::string& path, const OffHeader& header, std::uint64_t size, const LoadOptions& options);

// `text` is the whole file, whose header `header` is, and must be followed by a NUL character (as
// std::string's data is): the parser relies on it to stop. The one-argument form parses the header.
// With a pool, its threads share the lines (the mesh is the same).
std::optional<PlainOffMesh> read_plain_off_with_header(std::string_view text, const OffHeader& header,
                                                       detail::ThreadPool* pool = nullptr);
std::optional<PlainOffMesh> read_plain_off(std::string_view text);

}  // namespace facet::io_detail
