// facet io: the assimp module (libfacet_assimp.so, facet/detail/module.hpp): assimp and everything
// facet reads through its types (the assimp path, and the OBJ and glTF readers, whose materials are
// converted through aiMaterial), opened with dlopen by the first load that needs it, so that a
// process reading OFF, STL or PLY files does not load and relocate assimp and its libraries.
// In: a model file that passed load_model's pre-checks; out: what the functions of
// assimp_import.hpp and fast_path.hpp's load_own_scene return. Not the pre-checks, nor the list of
// extensions assimp reads (assimp_extensions.cpp, made at build time: is_supported_model_file asks
// it for every file without opening the module).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "facet/model.hpp"

namespace facet::io_detail {

// The module's table, returned by its one exported function.
struct AssimpModule {
    Result<LoadedModel> (*load_with_assimp)(const std::string& path, const std::string& ext, const LoadOptions& options);
    std::optional<Result<LoadedModel>> (*load_own_scene)(const std::string& path, const std::string& ext,
                                                         std::uint64_t size, const LoadOptions& options);
};
inline constexpr const char* k_assimp_module = "libfacet_assimp.so";
inline constexpr const char* k_assimp_module_entry = "facet_assimp_module_v1";

// Through the module (opened on first use): an error naming the file and the module when it cannot
// be opened.
Result<LoadedModel> module_load_with_assimp(const std::string& path, const std::string& ext, const LoadOptions& options);
// Through the module, for OBJ, glTF and GLB files only (nullopt for the other extensions, without
// opening the module).
std::optional<Result<LoadedModel>> module_load_own_scene(const std::string& path, const std::string& ext,
                                                         std::uint64_t size, const LoadOptions& options);

}  // namespace facet::io_detail
