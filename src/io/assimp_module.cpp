// facet io: libfacet's side of the assimp module (assimp_module.hpp): opens it on first use and
// calls through its table. Not the module's code (assimp_module_entry.cpp and what it links).
#include "io/assimp_module.hpp"

#include "facet/detail/module.hpp"
#include "io/load_common.hpp"

namespace facet::io_detail {
namespace {

const AssimpModule* assimp_module(std::string& why) {
    using Entry = const AssimpModule* (*)();
    const auto entry = reinterpret_cast<Entry>(detail::module_symbol(k_assimp_module, k_assimp_module_entry, why));
    return entry ? entry() : nullptr;
}

}  // namespace

Result<LoadedModel> module_load_with_assimp(const std::string& path, const std::string& ext, const LoadOptions& options) {
    std::string why;
    const AssimpModule* m = assimp_module(why);
    if (!m) return fail(ErrorCode::unsupported, path, "cannot be read: " + why);
    return m->load_with_assimp(path, ext, options);
}

std::optional<Result<LoadedModel>> module_load_own_scene(const std::string& path, const std::string& ext,
                                                         std::uint64_t size, const LoadOptions& options) {
    if (ext != "obj" && ext != "gltf" && ext != "glb") return std::nullopt;
    std::string why;
    const AssimpModule* m = assimp_module(why);
    if (!m) return Result<LoadedModel>(fail(ErrorCode::unsupported, path, "cannot be read: " + why));
    return m->load_own_scene(path, ext, size, options);
}

}  // namespace facet::io_detail

namespace facet {

bool open_model_reader_module() {
    std::string why;
    return io_detail::assimp_module(why) != nullptr;
}

}  // namespace facet
