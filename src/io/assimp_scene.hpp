// facet io, the assimp path's second half: the aiScene assimp read (assimp_import.hpp) into facet's
// Scene, with the limits of LoadOptions checked on assimp's counts before converting.
#pragma once

#include <string>

#include "facet/model.hpp"

struct aiScene;

namespace facet::io_detail {

class ResourceRoots;

// Texture files are looked for where `roots` allows.
Result<LoadedModel> convert_scene(const std::string& path, const aiScene& scene, const LoadOptions& options,
                                  const ResourceRoots& roots);

}  // namespace facet::io_detail
