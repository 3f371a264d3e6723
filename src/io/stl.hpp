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
//
// The header (binary or ASCII, and a binary file's facet count) is read once, from the file's first
// bytes and its size (parse_stl_header), by the pre-check (check_stl_header) and the reader.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "facet/error.hpp"
#include "facet/model.hpp"
#include "io/joined_mesh.hpp"

namespace facet::io_detail {

struct StlHeader {
    // assimp's test: binary when the file is exactly 84 + 50 n bytes for the n facets the header announces.
    bool binary = false;
    std::uint64_t facets = 0;  // n, from bytes 80 to 83 (files of at least 84 bytes)
    // Text (no NUL in the bytes read) whose first word, after white space, is "solid" in any case.
    bool ascii = false;
};

// `head` is the file's first bytes (at least 84 of them when the file has that many), `size` the file's.
StlHeader parse_stl_header(std::string_view head, std::uint64_t size);

// Refuses a binary file with more facets than options.max_triangles, and a file that is neither
// binary (its size does not match its count: cut short, damaged or not STL) nor ASCII.
Status check_stl_header(const std::string& path, const StlHeader& header, std::uint64_t size, const LoadOptions& options);

// `bytes` is the whole file; read_ascii_stl needs it followed by a NUL character (as std::string's
// data is), which stops its parser.
std::optional<JoinedMesh> read_binary_stl(std::string_view bytes);
std::optional<JoinedMesh> read_ascii_stl(std::string_view bytes);
// The one of the two assimp would use: binary when the header says so, else ASCII.
std::optional<JoinedMesh> read_stl_with_header(std::string_view bytes, const StlHeader& header);
std::optional<JoinedMesh> read_stl(std::string_view bytes);

}  // namespace facet::io_detail
