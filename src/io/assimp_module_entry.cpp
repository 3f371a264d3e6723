// facet io: the assimp module's exported entry (assimp_module.hpp), built into libfacet_assimp.so
// with the assimp path, the OBJ and glTF readers and the parts of libfacet they use (kept inside
// the module). Not loaded by libfacet's own code directly: assimp_module.cpp opens it.
#include <exception>
#include <new>

#include "io/assimp_import.hpp"
#include "io/assimp_module.hpp"
#include "io/fast_path.hpp"
#include "io/load_common.hpp"

namespace facet::io_detail {
namespace {

// No exception leaves the module: the caller's catch clauses name facet's types, whose type
// information this module holds a copy of. As load_model_from words them.
Error exception_error(const std::string& path) {
    try {
        throw;
    } catch (const std::bad_alloc&) {
        return out_of_memory(path);
    } catch (const FacetError& e) {
        return fail(e.error().code, path, e.error().message);
    } catch (const std::exception& e) {
        return fail(ErrorCode::bad_format, path, std::string("cannot be converted (") + e.what() + ")");
    } catch (...) {
        return fail(ErrorCode::bad_format, path, "cannot be converted");
    }
}

Result<LoadedModel> with_assimp(const std::string& path, const std::string& ext, const LoadOptions& options) {
    try {
        return load_with_assimp(path, ext, options);
    } catch (...) {
        return exception_error(path);
    }
}

std::optional<Result<LoadedModel>> own_scene(const std::string& path, const std::string& ext, std::uint64_t size,
                                             const LoadOptions& options) {
    try {
        return load_own_scene(path, ext, size, options);
    } catch (...) {
        return Result<LoadedModel>(exception_error(path));
    }
}

constexpr AssimpModule k_table{&with_assimp, &own_scene};

}  // namespace
}  // namespace facet::io_detail

extern "C" __attribute__((visibility("default"))) const facet::io_detail::AssimpModule* facet_assimp_module_v1() {
    return &facet::io_detail::k_table;
}
