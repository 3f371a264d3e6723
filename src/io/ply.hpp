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
//
// The header is parsed once, from the file's first bytes (parse_ply_header), and read two ways: by
// the pre-check that refuses what assimp must not see (check_ply_header), and by the reader, which
// takes only the form above.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "facet/error.hpp"
#include "facet/model.hpp"
#include "io/joined_mesh.hpp"

namespace facet::io_detail {

struct PlyHeader {
    struct Line {
        std::string text;                // without its '\n' (a '\r' before it kept)
        std::vector<std::string> words;  // split at white space (' ', '\t', '\r', '\f', '\v')
    };
    bool magic = false;               // the bytes start with "ply" or "PLY"; otherwise assimp says what the file is
    std::optional<std::size_t> end;   // where the first line starting with "end_header" starts
    std::string after_end;            // the (at most two) bytes read after that "end_header"
    std::size_t bytes_read = 0;       // how many of the file's bytes the header was parsed from
    std::vector<Line> lines;          // the lines before `end`
};

// `head` is the file's first bytes (the whole header for any file facet reads).
PlyHeader parse_ply_header(std::string_view head);

// Refuses what assimp 5.2.5 must not read: a header without a proper end_header line, unknown
// property types, a comment among an element's properties, element counts that the file's `size`
// bytes cannot hold, or more faces than options.max_triangles.
Status check_ply_header(const std::string& path, const PlyHeader& header, std::uint64_t size, const LoadOptions& options);

// `bytes` is the whole file, followed by a NUL character (as std::string's data is), whose header
// `header` is; the one-argument form parses it.
std::optional<JoinedMesh> read_plain_ply_with_header(std::string_view bytes, const PlyHeader& header);
std::optional<JoinedMesh> read_plain_ply(std::string_view bytes);

// A point cloud: a PLY header whose first element is `vertex`, with scalar properties among which
// x, y and z, and whose other elements (faces, edges) have none. Such files are read by
// read_ply_point_cloud (assimp 5.2.5 refuses them: "contains no faces"): x, y, z; nx, ny, nz when all
// three are there; red, green, blue and alpha (integers scaled by their type's maximum, floats as
// they are); other properties skipped. `bytes` is the whole file followed by a NUL character. A body
// shorter than the header says, or a value that does not parse, is an error naming the vertex.
bool is_ply_point_cloud(const PlyHeader& header);
Result<LoadedModel> read_ply_point_cloud(const std::string& path, std::string_view bytes, const PlyHeader& header,
                                         const LoadOptions& options);

}  // namespace facet::io_detail
