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
#include "io/resources.hpp"

// assimp's internal consistency checks (ai_assert) are compiled into Debian's libassimp and call
// std::abort() when they fail; malformed input reaches some of them (a truncated ASCII PLY trips
// one in the triangulation step). libassimp calls this function through its PLT and it is exported,
// so the definition in the executable takes precedence. Throwing instead of aborting lets assimp's
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
// logger hands each error to the thread whose import logged it; they become one warning, except
// an out-of-range index, which means a corrupt file (as it is for OBJ and PLY): an error.
struct LoggedErrors {
    std::vector<std::string> distinct;  // the first few, in order
    std::size_t total = 0;
    std::optional<std::string> bad_index;
};
thread_local LoggedErrors* t_assimp_errors = nullptr;
constexpr std::size_t k_max_logged_errors = 3;

// Logged "errors" about things facet does not use, or about files that are fine.
bool ignorable(std::string_view message) {
    for (std::string_view noise : {"No object detected to attach a new mesh instance",  // OBJ: usemtl before o/g
                                   "nimation", "Bone", "binormal", "tangent"})
        if (message.find(noise) != std::string_view::npos) return true;
    return false;
}

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
        LoggedErrors* e = t_assimp_errors;
        const std::string_view m = message;
        if (!e || ignorable(m)) return;
        if (m.find("out of range") != std::string_view::npos && m.find("ndex") != std::string_view::npos && !e->bad_index)
            e->bad_index = message;
        if (std::find(e->distinct.begin(), e->distinct.end(), message) != e->distinct.end()) return;
        ++e->total;
        if (e->distinct.size() < k_max_logged_errors) e->distinct.push_back(message);
    }
};

// Collects assimp's logged errors on this thread while it lives.
class AssimpErrors {
public:
    AssimpErrors() {
        static std::once_flag installed;
        std::call_once(installed, [] { Assimp::DefaultLogger::set(new ErrorCollector); });
        t_assimp_errors = &errors_;
    }
    ~AssimpErrors() { t_assimp_errors = nullptr; }
    AssimpErrors(const AssimpErrors&) = delete;
    AssimpErrors& operator=(const AssimpErrors&) = delete;

    const std::optional<std::string>& bad_index() const { return errors_.bad_index; }

    // One warning naming the file, or nothing if assimp logged no error.
    std::optional<std::string> warning(const std::string& path) const {
        if (errors_.total == 0) return std::nullopt;
        std::string w = path + ": assimp reported problems and worked around them: ";
        for (std::size_t i = 0; i < errors_.distinct.size(); ++i) w += (i ? "; " : "") + errors_.distinct[i];
        if (errors_.total > errors_.distinct.size())
            w += " (and " + std::to_string(errors_.total - errors_.distinct.size()) + " more)";
        return w;
    }

private:
    LoggedErrors errors_;
};

// assimp opens every file through its IOSystem: the model, and whatever the model names (OBJ's MTL
// files, glTF's buffers, the scenes and meshes LWS, IRR or X3D pull in, ...). This one opens for
// reading only what the model's resource folders allow; a refused file reads as missing to the
// importer, which then works around it or fails, and is named in a warning or the error.
class ConfinedIOSystem final : public Assimp::DefaultIOSystem {
public:
    explicit ConfinedIOSystem(const ResourceRoots& roots) : roots_(roots) {}

    bool Exists(const char* file) const override { return allowed(file) && DefaultIOSystem::Exists(file); }

    Assimp::IOStream* Open(const char* file, const char* mode) override {
        const std::string_view m = mode ? mode : "rb";
        if (m.find_first_of("wa+") != std::string_view::npos || !allowed(file)) return nullptr;
        return DefaultIOSystem::Open(file, mode);
    }

    // The files refused that exist (resources.hpp), in order, each once.
    const std::vector<std::string>& refused() const { return refused_; }

private:
    bool allowed(const char* file) const {
        if (file && roots_.allows(file)) return true;
        const std::string name = file ? file : "";
        std::error_code ec;
        if (std::filesystem::exists(name, ec) && std::find(refused_.begin(), refused_.end(), name) == refused_.end())
            refused_.push_back(name);
        return false;
    }

    const ResourceRoots& roots_;
    mutable std::vector<std::string> refused_;  // Exists is const
};

}  // namespace

bool assimp_reads_extension(const std::string& ext) {
    static const Assimp::Importer importer;  // IsExtensionSupported only reads the importer list
    return importer.IsExtensionSupported("." + ext);
}

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
    auto* io = new ConfinedIOSystem(roots);
    importer.SetIOHandler(io);  // the importer owns it
    AssimpErrors logged;
    const aiScene* scene = importer.ReadFile(path, flags);
    std::vector<std::string> refusals;
    for (const std::string& file : io->refused()) refusals.push_back(roots.refusal(file));
    if (!scene) {
        const std::string why = importer.GetErrorString();
        // assimp catches the std::bad_alloc of a reader that asked for more than there is
        // (a damaged count in a header, or a process memory cap) and keeps only its name.
        if (why == "std::bad_alloc") return out_of_memory(path);
        std::string refused;  // what the model wanted to read and may not: maybe why it failed
        for (const std::string& r : refusals) refused += "; " + r;
        if (means_no_triangles(why)) return fail(ErrorCode::bad_format, path, "contains no triangles (" + why + ")" + refused);
        return fail(ErrorCode::bad_format, path, "cannot be read as a model (" + readable(why) + ")" + refused);
    }
    if (logged.bad_index()) return fail(ErrorCode::bad_format, path, "has out-of-range indices (" + *logged.bad_index() + ")");
    Result<LoadedModel> model = convert_scene(path, *scene, options, roots);
    if (model) {
        if (std::optional<std::string> w = logged.warning(path)) model->warnings.insert(model->warnings.begin(), *w);
        for (std::size_t i = 0; i < refusals.size(); ++i)
            model->warnings.insert(model->warnings.begin() + static_cast<std::ptrdiff_t>(i), path + ": " + refusals[i]);
    }
    return model;
}

}  // namespace facet::io_detail
