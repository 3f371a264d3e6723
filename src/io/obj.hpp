// facet io: OBJ files with their MTL material libraries, read by facet's own code into the scene
// assimp 5.2.5's OBJ importer and post-processing (triangulation, FlipUVs, JoinIdenticalVertices)
// make of them, so that the Scene is the assimp path's bit for bit (assimp_scene.hpp converts
// both). In: the file's bytes and path; the MTL files it names are read where the resource rules
// allow. Out: an OwnScene and the warnings assimp would have logged (or the error of a file with
// more triangles than LoadOptions::max_triangles: past that count faces are only counted, not
// kept, and the count reported is the assimp path's), or nullopt for a file this
// reader does not read exactly as assimp does, which then goes through assimp: lines assimp reads
// in odd ways (a number with a leading zero or '+' in a face, a backslash before a line end,
// faces of more than four corners, points and lines, NUL bytes), anything assimp would refuse, and
// attributes that assimp's join tolerance could merge although they differ.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "facet/model.hpp"
#include "io/assimp_scene.hpp"

namespace facet::io_detail {

class ImportNotes;
class ResourceRoots;

// `bytes` is the whole file, followed by a NUL character (as std::string's data is).
// `bytes_read` (if any) is called once they are no longer read, before the meshes are built: their
// memory may then be freed, for the meshes' scratch arrays to take.
std::optional<Result<OwnScene>> read_obj(const std::string& path, std::string_view bytes, const LoadOptions& options,
                                         const ResourceRoots& roots, ImportNotes& notes,
                                         const std::function<void()>& bytes_read = {});

}  // namespace facet::io_detail
