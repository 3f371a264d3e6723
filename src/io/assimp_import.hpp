// facet io, the assimp path: a model file that passed load_model's pre-checks, read by assimp and
// converted into a LoadedModel (assimp_scene.hpp), or one Error naming the file. Not the pre-checks
// nor facet's own readers (model_loader.cpp, fast_path.hpp).
#pragma once

#include <string>

#include "facet/model.hpp"

namespace facet::io_detail {

// `ext` is the file's extension in lower case (model_extension).
Result<LoadedModel> load_with_assimp(const std::string& path, const std::string& ext, const LoadOptions& options);

// Whether one of assimp's importers takes files with the extension `ext` (lower case, no dot): a
// list made at build time (io/bake/assimp_extensions.cpp), in libfacet, without loading assimp.
bool assimp_reads_extension(const std::string& ext);

}  // namespace facet::io_detail
