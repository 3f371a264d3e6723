// facet io, the assimp path's first half: a model file read by assimp into an aiScene, then handed
// to the conversion (assimp_scene.hpp). assimp reads and post-processes (triangulate, split by
// primitive type, join identical vertices, validate); its failures become one bad_format Error,
// errors it only logs while working around bad data become a warning (an out-of-range index: an
// Error), and its internal assertions throw instead of aborting the process (aiAssertViolation
// below). Not the checks made before assimp sees a file (model_loader.cpp), nor facet's own readers.
#include "io/assimp_import.hpp"

#include <assimp/DefaultIOSystem.h>
#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/Logger.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <filesystem>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "io/assimp_scene.hpp"
#include "io/load_common.hpp"
#include "io/import_notes.hpp"
#include "io/resources.hpp"

// assimp's internal consistency checks (ai_assert) are compiled into Debian's libassimp and call
// std::abort() when they fail; malformed input reaches some of them (a truncated ASCII PLY trips
// one in the triangulation step). libassimp calls this function through its PLT and it is exported
// (by the executable that links this file, or by the assimp module, io/assimp_module.map, which
// comes before libassimp in the search order of what dlopen loads), so this definition takes
// precedence. Throwing instead of aborting lets assimp's
// own exception handling (around every importer and post-processing step) turn it into a failed
// import with this message.
namespace Assimp {
void aiAssertViolation(const char* expression, const char* file, int line) {
    throw std::runtime_error(std::string("assimp internal check failed: ") + expression + " (" + file + ":" +
                             std::to_string(line) + ")");
}
}  // namespace Assimp

namespace facet::io_detail {
namespace {

// Not used: GenNormals/GenSmoothNormals (facet computes creased normals itself), FindInvalidData
// (it deletes a whole mesh for one non-finite position; facet drops just those triangles) and
// FlipWindingOrder (files are counter-clockwise, as facet). FlipUVs turns assimp's bottom-left
// UV origin into facet's top-left one (for glTF it undoes assimp's own flip).
constexpr unsigned k_import_flags = aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_JoinIdenticalVertices |
                                    aiProcess_ValidateDataStructure | aiProcess_FlipUVs;

// assimp's messages for "nothing left that has faces", from validation or SortByPType.
bool means_no_triangles(const std::string& message) {
    return message.find("no faces") != std::string::npos || message.find("No meshes remaining") != std::string::npos ||
           message.find("mNumMeshes is 0") != std::string::npos;
}

// Some readers work around bad data and only log an error: the OBJ reader replaces a missing
// material, the OFF reader clamps out-of-range vertex indices to the last vertex. A global assimp
// logger hands each error to the thread whose import logged it (ImportNotes, import_notes.hpp).
thread_local ImportNotes* t_assimp_notes = nullptr;

class ErrorCollector final : public Assimp::Logger {
public:
    ErrorCollector() : Logger(Logger::NORMAL) {}
    bool attachStream(Assimp::LogStream*, unsigned) override { return false; }
    bool detachStream(Assimp::LogStream*, unsigned) override { return false; }
    void OnDebug(const char*) override {}
    void OnVerboseDebug(const char*) override {}
    void OnInfo(const char*) override {}
    void OnWarn(const char*) override {}
    void OnError(const char* message) override {
        if (t_assimp_notes) t_assimp_notes->error_reached_logger(message);
    }
};

// Collects assimp's logged errors on this thread while it lives.
class AssimpErrors {
public:
    explicit AssimpErrors(ImportNotes& notes) {
        static std::once_flag installed;
        std::call_once(installed, [] { Assimp::DefaultLogger::set(new ErrorCollector); });
        t_assimp_notes = &notes;
    }
    ~AssimpErrors() { t_assimp_notes = nullptr; }
    AssimpErrors(const AssimpErrors&) = delete;
    AssimpErrors& operator=(const AssimpErrors&) = delete;
};

// assimp opens every file through its IOSystem: the model, and whatever the model names (OBJ's MTL
// files, glTF's buffers, the scenes and meshes LWS, IRR or X3D pull in, ...). This one opens for
// reading only what the model's resource folders allow; a refused file reads as missing to the
// importer, which then works around it or fails, and is named in a warning or the error.
class ConfinedIOSystem final : public Assimp::DefaultIOSystem {
public:
    ConfinedIOSystem(const ResourceRoots& roots, ImportNotes& notes) : roots_(roots), notes_(notes) {}

    bool Exists(const char* file) const override { return allowed(file) && DefaultIOSystem::Exists(file); }

    Assimp::IOStream* Open(const char* file, const char* mode) override {
        const std::string_view m = mode ? mode : "rb";
        if (m.find_first_of("wa+") != std::string_view::npos || !allowed(file)) return nullptr;
        return DefaultIOSystem::Open(file, mode);
    }

private:
    bool allowed(const char* file) const { return file && notes_.may_open(roots_, file); }

    const ResourceRoots& roots_;
    ImportNotes& notes_;  // Exists is const; the refusals are noted there
};

}  // namespace

Result<LoadedModel> load_with_assimp(const std::string& path, const std::string& ext, const LoadOptions& options) {
    Assimp::Importer importer;
    unsigned flags = k_import_flags;
    if (ext == "stl") {
        // STL repeats every vertex per facet with the facet's normal; without the normals,
        // JoinIdenticalVertices welds the mesh, and facet computes creased normals instead.
        importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS, aiComponent_NORMALS);
        flags |= aiProcess_RemoveComponent;
    }
    const ResourceRoots roots(path, options.resource_dirs);
    ImportNotes notes;
    importer.SetIOHandler(new ConfinedIOSystem(roots, notes));  // the importer owns it
    AssimpErrors logged(notes);
    const aiScene* scene = importer.ReadFile(path, flags);
    if (!scene) {
        const std::string why = importer.GetErrorString();
        // assimp catches the std::bad_alloc of a reader that asked for more than there is
        // (a damaged count in a header, or a process memory cap) and keeps only its name.
        if (why == "std::bad_alloc") return out_of_memory(path);
        const std::string refused = notes.refusals_text(roots);  // what the model wanted to read and may not: maybe why it failed
        if (means_no_triangles(why)) return fail(ErrorCode::bad_format, path, "contains no triangles (" + why + ")" + refused);
        return fail(ErrorCode::bad_format, path, "cannot be read as a model (" + readable(why) + ")" + refused);
    }
    if (notes.bad_index()) return fail(ErrorCode::bad_format, path, "has out-of-range indices (" + *notes.bad_index() + ")");
    Result<LoadedModel> model = convert_scene(path, source_of(*scene, ext == "gltf" || ext == "glb"), options, roots);
    if (model) notes.add_warnings(path, roots, *model);
    return model;
}

}  // namespace facet::io_detail
