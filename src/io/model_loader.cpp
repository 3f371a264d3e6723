// facet io: load_model, the entry of model files into a Scene. The path of a file:
//   1. checks facet makes itself before any reader sees the file: it exists, is a regular readable
//      file, is within max_file_bytes and not empty, has an extension assimp knows, and (STL, PLY,
//      OFF, GLB) its header does not claim more elements than the file's size can hold or more
//      triangles than max_triangles. assimp trusts such counts and reserves memory for them: an
//      OFF header claiming 3.5e11 vertices costs it 40 s and 16 GB of address space.
//   2. plain OFF, STL and PLY files are read by facet's own readers (fast_path.hpp), several times
//      faster, into the same Scene;
//   3. everything else, and whatever those readers decline, is read by assimp and converted
//      (assimp_import.hpp, assimp_scene.hpp); OBJ and glTF by facet's readers converted the same
//      way; both in the assimp module, opened when a file needs it (assimp_module.hpp);
//   point clouds, which assimp does not read (PLY of vertices alone, XYZ, PTS, OBJ of `v` lines
//   alone), are read by point_cloud.hpp's readers.
#include "facet/model.hpp"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <optional>
#include <string>
#include <string_view>

#include "io/assimp_import.hpp"
#include "io/assimp_module.hpp"
#include "io/fast_path.hpp"
#include "io/load_common.hpp"
#include "io/load_paths.hpp"
#include "io/point_cloud.hpp"

namespace facet {
namespace {

namespace fs = std::filesystem;
using io_detail::fail;

constexpr std::size_t k_header_bytes = 64 * 1024;  // enough for any sane PLY/OFF/STL/GLB header

// The file is a regular, readable, non-empty file within the size limit. Returns its size and
// its first bytes (for the header checks).
Status check_file(const std::string& path, const LoadOptions& options, std::uintmax_t& size, std::string& head) {
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (ec || !fs::exists(st)) return fail(ErrorCode::io, path, "no such file");
    if (fs::is_directory(st)) return fail(ErrorCode::io, path, "is a directory, not a model file");
    if (!fs::is_regular_file(st)) return fail(ErrorCode::io, path, "is not a regular file");
    size = fs::file_size(path, ec);
    if (ec) return fail(ErrorCode::io, path, "cannot read the file size (" + ec.message() + ")");
    if (size > options.max_file_bytes)
        return fail(ErrorCode::limit_exceeded, path,
                    "is " + std::to_string(size) + " bytes, more than the limit of " +
                        std::to_string(options.max_file_bytes) + " bytes");
    if (size == 0) return fail(ErrorCode::bad_format, path, "is empty");
    std::ifstream in(path, std::ios::binary);
    if (!in) return fail(ErrorCode::io, path, std::string("cannot be opened for reading (") + std::strerror(errno) + ")");
    head.resize(static_cast<std::size_t>(std::min<std::uintmax_t>(size, k_header_bytes)));
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    if (in.gcount() != static_cast<std::streamsize>(head.size()))
        return fail(ErrorCode::io, path, "cannot be read (" + std::string(std::strerror(errno)) + ")");
    return Ok{};
}

std::atomic<std::size_t> assimp_imports{0};  // assimp_import_count
std::atomic<bool> assimp_allowed{true};      // allow_assimp_imports

// GLB: "glTF" magic, version, total length; the length must not exceed the file.
Status check_glb(const std::string& path, const std::string& head, std::uint64_t size) {
    if (size < 12 || head.compare(0, 4, "glTF") != 0) return fail(ErrorCode::bad_format, path, "is not a GLB file (no glTF header)");
    std::uint32_t length = 0;
    for (int i = 3; i >= 0; --i) length = length << 8 | static_cast<unsigned char>(head[8 + static_cast<std::size_t>(i)]);
    if (length > size)
        return fail(ErrorCode::bad_format, path,
                    "GLB header claims " + std::to_string(length) + " bytes but the file has " + std::to_string(size) +
                        " (truncated)");
    return Ok{};
}

Result<LoadedModel> load_model_from(const std::string& path, const LoadOptions& options, bool fast_paths) {
    std::uintmax_t size = 0;
    std::string head;
    if (Status s = check_file(path, options, size, head); !s) return s.error();
    const std::string ext = model_extension(path);
    if (!is_supported_model_file(path))
        return fail(ErrorCode::unsupported, path,
                    ext.empty() ? "has no file extension to tell its format" : "'." + ext + "' is not a model format facet reads");
    const std::optional<io_detail::OwnFormatHeader> own = io_detail::OwnFormatHeader::parse(ext, head, size);
    if (own) {
        if (Status s = own->check(path, size, options); !s) return s.error();
    } else if (ext == "glb") {
        if (Status s = check_glb(path, head, size); !s) return s.error();
    }

    try {
        if (ext == "xyz" || ext == "pts") {
            const std::optional<io_detail::FileBytes> bytes = io_detail::whole_file(path, size, options);
            if (!bytes) return fail(ErrorCode::io, path, "changed while it was being read");
            return io_detail::read_text_points(path, *bytes, ext == "pts", options);
        }
        if (own)
            if (std::optional<Result<LoadedModel>> cloud = own->load_point_cloud(path, head, size, options)) return std::move(*cloud);
        if (fast_paths && own)
            if (std::optional<LoadedModel> model = own->load(path, head, size, options)) return std::move(*model);
        if (fast_paths)
            if (std::optional<Result<LoadedModel>> model = io_detail::module_load_own_scene(path, ext, size, options)) return std::move(*model);
        assimp_imports.fetch_add(1, std::memory_order_relaxed);
        if (!assimp_allowed.load(std::memory_order_relaxed))
            return fail(ErrorCode::unsupported, path, "is left to a fresh process (it needs assimp's importer)");
        Result<LoadedModel> model = io_detail::module_load_with_assimp(path, ext, options);
        // assimp refuses OBJ files of vertices alone ("no faces"): those are point clouds.
        if (!model && ext == "obj" && model.error().code == ErrorCode::bad_format)
            if (const std::optional<io_detail::FileBytes> bytes = io_detail::whole_file(path, size, options))
                if (std::optional<Result<LoadedModel>> cloud = io_detail::read_obj_points(path, *bytes, options))
                    return std::move(*cloud);
        return model;
    } catch (const std::bad_alloc&) {
        return io_detail::out_of_memory(path);
    } catch (const FacetError& e) {
        return fail(e.error().code, path, e.error().message);
    } catch (const std::exception& e) {
        return fail(ErrorCode::bad_format, path, std::string("cannot be converted (") + e.what() + ")");
    }
}

}  // namespace

std::string model_extension(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    return io_detail::lower(ext.empty() ? ext : ext.substr(1));
}

std::string mapped_file_crash_hint(const std::string& path) {
    const std::string ext = model_extension(path);
    for (const char* mapped : {"obj", "gltf", "glb", "off", "stl", "ply", "xyz", "pts"})  // io_detail::whole_file's readers
        if (ext == mapped) return "; was the file changed while it was read?";
    return "";
}

std::size_t assimp_import_count() { return assimp_imports.load(std::memory_order_relaxed); }
void allow_assimp_imports(bool allowed) { assimp_allowed.store(allowed, std::memory_order_relaxed); }

bool has_own_parser(const std::string& path) {
    const std::string ext = model_extension(path);
    return ext == "off" || ext == "stl" || ext == "ply";
}

bool is_supported_model_file(const std::string& path) {
    const std::string ext = model_extension(path);
    return !ext.empty() && (ext == "xyz" || ext == "pts" || io_detail::assimp_reads_extension(ext));
}

Result<LoadedModel> load_model(const std::string& path, const LoadOptions& options) {
    // FACET_READER=assimp: every file through assimp, for comparisons (docs/BENCHMARKS.md).
    static const bool assimp_only = [] {
        const char* reader = std::getenv("FACET_READER");
        return reader && std::string_view(reader) == "assimp";
    }();
    return load_model_from(path, options, /*fast_paths=*/!assimp_only);
}

Result<LoadedModel> io_detail::load_model_through_assimp(const std::string& path, const LoadOptions& options) {
    return load_model_from(path, options, /*fast_paths=*/false);
}

}  // namespace facet
