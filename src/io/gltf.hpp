// facet io: glTF 2.0 files (.gltf, .glb) read by facet's own code into the scene assimp 5.2.5's glTF2
// importer and post-processing (FlipUVs, JoinIdenticalVertices) make of them, so that the Scene is the
// assimp path's bit for bit (assimp_scene.hpp converts both). In: the file's bytes and path; the
// buffers it names are read where the resource rules allow (images are found by the conversion).
// Out: an OwnScene, or nullopt for a file this reader does not read exactly as assimp does, which
// then goes through assimp and its errors: points and lines, sparse accessors,
// morph targets, skins, animations, cameras, extensions other than KHR_texture_transform and
// KHR_materials_unlit, attributes other than POSITION, NORMAL, TANGENT, TEXCOORD_0 and COLOR_0, a
// value of an unexpected type, a reference, index or range out of bounds.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "facet/model.hpp"
#include "io/assimp_scene.hpp"

namespace facet::io_detail {

class ImportNotes;
class ResourceRoots;

// `bytes` is the whole file; `binary` for GLB.
std::optional<OwnScene> read_gltf(const std::string& path, std::string_view bytes, bool binary, const LoadOptions& options,
                                  const ResourceRoots& roots, ImportNotes& notes);

}  // namespace facet::io_detail
