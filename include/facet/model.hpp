// facet io: loading model files into a Scene. Formats: everything assimp reads (OBJ + MTL, STL,
// PLY, OFF, glTF 2.0 / GLB, FBX, 3MF, COLLADA, 3DS, ...). Node transforms are applied, every mesh of
// the file becomes a SceneObject, materials carry base colour, vertex colours and base-colour
// textures (external files or embedded). Bad files give one Error naming the file and the problem;
// recoverable trouble (a missing texture, some invalid triangles) gives warnings and a fallback.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "facet/api.hpp"
#include "facet/defaults.hpp"
#include "facet/error.hpp"
#include "facet/scene.hpp"
#include "facet/texture.hpp"

FACET_API_BEGIN
namespace facet {

enum class UpAxis { y, z };

struct LoadOptions {
    // Files without normals get smooth normals, split where faces meet at more than this angle
    // (degrees); 180 keeps everything smooth, small values give CAD/STL files crisp edges.
    float crease_angle_degrees = defaults::k_crease_angle_degrees;
    UpAxis up_axis = UpAxis::y;  // z: the file's +Z becomes +Y (CAD, STL, 3MF are often Z-up)
    TextureLimits texture_limits;
    std::size_t max_triangles = defaults::k_max_triangles;  // refuse larger models before allocating them
    std::size_t max_file_bytes = defaults::k_max_file_bytes;
    // The memory the converted Scene would take (positions, normals, colours, uvs and indices of
    // every instance: a mesh placed by many nodes is copied for each), estimated from assimp's
    // counts before converting. Stops a small file that instances a large mesh thousands of times.
    std::size_t max_scene_bytes = defaults::k_max_scene_bytes;
    // Threads for the work after reading (normals) of large meshes, 0: one per core. The default
    // keeps loading on the calling thread, for callers that load several files at once.
    int threads = defaults::k_load_threads;
    // Where a model may read the files it names (textures, MTL files, glTF buffers and images, the
    // scenes and meshes some formats pull in): its own folder and subfolders, and these folders.
    // A reference that leads elsewhere once symbolic links and ".." are resolved (an absolute path,
    // a "file://" URI, "../..", a link pointing out) is not read: a warning names the model and the
    // reference, and the material falls back as for a missing texture. Embedded data is unaffected.
    std::vector<std::string> resource_dirs;
    // OBJ, glTF, OFF, STL, PLY, XYZ and PTS files of 32 MiB or more read through a read-only mapping
    // of the file (mmap) instead of a copy: faster, and the file's text takes none of the process's
    // own memory (a smaller file's copy is heap memory the process reuses next, which pays more).
    // But a file cut short by another program while it is read then ends the process with SIGBUS:
    // only for a process whose end is reported, as facet's worker processes and
    // load_model_isolated's child (which set it).
    bool map_files = false;
};

struct LoadedModel {
    Scene scene;
    std::vector<std::string> warnings;  // each names the file
};

// Loads in the calling process: assimp runs here. A few damaged files crash, hang or exhaust memory
// inside assimp 5.2.5 itself (MDL, COB, OGEX, FBX, LWS, ASE, PLY, X, HMP and COLLADA inputs found
// by fuzzing, docs/RELIABILITY.md), which no Result can report. A program that loads files it does
// not trust should use load_model_isolated below, or run the whole job in a process of its own as
// `facet render` and `facet thumbs` do (apps/cli/worker.hpp).
Result<LoadedModel> load_model(const std::string& path, const LoadOptions& options = {});

struct IsolationLimits {
    double timeout_seconds = defaults::k_timeout_seconds;  // the child is killed after this; 0: no limit
    std::uint64_t max_memory_bytes = 0;  // the child's RLIMIT_DATA; 0: no limit (not for sanitizer builds)
};

// load_model in a child process (Linux: fork, an anonymous memory file for the result): a file
// that crashes, hangs or exhausts memory inside the reader gives an Error naming the file and what
// happened ("the importer crashed (SIGSEGV: Segmentation fault)", "gave up after 60 s", "needs more
// memory than is available") and the calling program goes on. The child is sandboxed as facet's
// worker processes are (facet/sandbox.hpp: it reads only the model's folder and the resource
// folders, and opens no socket, runs no program, starts no process). Costs a fork and a copy of the
// scene (about a millisecond per megabyte). Call it while the program has one thread, or at least while no
// other thread holds a lock the reader needs (a forked child gets only the calling thread).
Result<LoadedModel> load_model_isolated(const std::string& path, const LoadOptions& options = {},
                                        const IsolationLimits& limits = {});

// "SIGSEGV: Segmentation fault" for SIGSEGV, and so on: how facet names a signal in its errors.
std::string describe_signal(int signal);

// True when the file name has an extension of a format load_model reads (case-insensitive).
bool is_supported_model_file(const std::string& path);

// The file name's extension in lower case, without its dot ("" for none): what load_model picks
// a format by.
std::string model_extension(const std::string& path);

// What a SIGBUS of a process loading `path` with LoadOptions::map_files adds to its report: "; was
// the file changed while it was read?" for the formats that may be mapped (a file cut short by
// another program meanwhile is the likely cause), else "".
std::string mapped_file_crash_hint(const std::string& path);

// How many files load_model has needed assimp's importer for in this process (not facet's own
// readers), given to it or refused (below). facet thumbs' workers, which serve several objects,
// use it to read such files only in a fresh process: what a damaged file does inside assimp (reads
// past its buffers) depends on the state of the heap, and the objects before it would change that.
std::size_t assimp_import_count();
// With false, load_model fails a file that needs assimp's importer (ErrorCode::unsupported, "is
// left to a fresh process") instead of giving it to assimp, until allowed again; true by default.
void allow_assimp_imports(bool allowed);

// True when load_model reads the file with facet's own parser first rather than assimp's (OFF, STL
// and PLY, by the extension, case-insensitive; a file the parser declines still goes to assimp).
bool has_own_parser(const std::string& path);

// Opens the module that reads OBJ, glTF and assimp's formats now, rather than at the first load
// that needs it: for a parent that forks worker processes, which then share it instead of each
// opening and relocating it again. False when it cannot be opened (the loads that need it say why).
bool open_model_reader_module();

}  // namespace facet
FACET_API_END
