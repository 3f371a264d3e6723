// facet io, the fast path (fast_path.hpp): the header of an OFF, STL or PLY file, its pre-check, and
// its Scene as facet's own readers make it, equal to the assimp path's bit for bit. (OBJ and glTF:
// own_scene.cpp, in the assimp module.)
#include "io/fast_path.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <string_view>
#include <utility>

#include "facet/detail/thread_pool.hpp"
#include "facet/mesh.hpp"
#include "io/import_notes.hpp"
#include "io/load_common.hpp"
#include "io/resources.hpp"
#include "scene/creased_normals.hpp"

namespace facet::io_detail {
namespace {

template <class... F>
struct Overloaded : F... {
    using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

constexpr std::uint64_t k_file_bytes_for_threads = 256 * 1024;

// At most this much of the heap is faulted in while the file is read (the bunny's 2.6 MB: ~0.5 ms,
// four or five 2 MiB pages of the ~20 MB its render takes).
constexpr std::size_t k_populate_bytes_while_read = std::size_t{32} << 20;

// The material assimp's reader gives such a file, as the assimp path converts it: grey for OFF
// (COFF's colours are its vertices'), white for STL and PLY (the files the readers take have no
// colours); two-sided.
Material own_format_material(bool off) {
    Material m;
    if (off) m.base_colour = {0.6f, 0.6f, 0.6f, 1.0f};
    return m;
}

}  // namespace

std::optional<FileBytes> read_whole_file(const std::string& path, std::uint64_t size) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return std::nullopt;
    std::optional<FileBytes> bytes(std::in_place, static_cast<std::size_t>(size));
    // The bytes, then one more: a file that still has one has grown since its size was taken.
    char extra;
    std::size_t done = 0;
    bool whole = false;
    for (;;) {
        const bool body = done < bytes->size();
        const ssize_t n = ::read(fd, body ? bytes->data() + done : &extra, body ? bytes->size() - done : 1);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0 || !body) {
            whole = n == 0 && !body;
            break;
        }
        done += static_cast<std::size_t>(n);
    }
    ::close(fd);
    if (!whole) return std::nullopt;  // changed while being read: assimp reads it again and decides
    return bytes;
}

std::optional<FileBytes> map_whole_file(const std::string& path, std::uint64_t size) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return std::nullopt;
    struct stat st {};
    if (fstat(fd, &st) != 0 || static_cast<std::uint64_t>(st.st_size) != size) {
        ::close(fd);
        return std::nullopt;  // changed since its size was taken: assimp reads it again and decides
    }
    // Room for the bytes and a NUL: zero pages of an anonymous mapping, the file mapped over its
    // start. The zero after the bytes is the last file page's (cleared past the end by the kernel)
    // or, for a size in whole pages, the read-only zero page after them.
    const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
    const std::size_t span = (static_cast<std::size_t>(size) + page) & ~(page - 1);
    void* room = mmap(nullptr, span, PROT_READ, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    void* file = room == MAP_FAILED ? MAP_FAILED
                                    : mmap(room, static_cast<std::size_t>(size), PROT_READ,
                                           MAP_PRIVATE | MAP_FIXED | MAP_POPULATE, fd, 0);
    ::close(fd);  // the mapping holds the file
    if (file == MAP_FAILED) {
        if (room != MAP_FAILED) munmap(room, span);
        return read_whole_file(path, size);
    }
    return std::optional<FileBytes>(std::in_place, FileBytes::Mapped{}, static_cast<char*>(room), span,
                                    static_cast<std::size_t>(size));
}

std::optional<FileBytes> whole_file(const std::string& path, std::uint64_t size, const LoadOptions& options) {
    // From this size read_whole_file's copy takes fresh pages itself, so a mapping saves it; a smaller
    // file's copy is heap memory that the rest of the process reuses once it is freed.
    constexpr std::uint64_t k_map_from = FileBytes::k_fresh_from;
    return options.map_files && size >= k_map_from ? map_whole_file(path, size) : read_whole_file(path, size);
}

std::optional<OwnFormatHeader> OwnFormatHeader::parse(const std::string& ext, std::string_view head, std::uint64_t size) {
    if (ext == "off") return OwnFormatHeader(parse_off_header(head));
    if (ext == "stl") return OwnFormatHeader(parse_stl_header(head, size));
    if (ext == "ply") return OwnFormatHeader(parse_ply_header(head));
    return std::nullopt;
}

Status OwnFormatHeader::check(const std::string& path, std::uint64_t size, const LoadOptions& options) const {
    return std::visit(Overloaded{[&](const OffHeader& h) { return check_off_header(path, h, size, options); },
                                 [&](const StlHeader& h) { return check_stl_header(path, h, size, options); },
                                 [&](const PlyHeader& h) { return check_ply_header(path, h, size, options); }},
                      header_);
}

std::optional<Result<LoadedModel>> OwnFormatHeader::load_point_cloud(const std::string& path, std::string_view head,
                                                                     std::uint64_t size, const LoadOptions& options) const {
    const PlyHeader* ply = std::get_if<PlyHeader>(&header_);
    if (!ply || !is_ply_point_cloud(*ply)) return std::nullopt;
    const std::optional<FileBytes> bytes = whole_file(path, size, options);
    if (!bytes || bytes->view().substr(0, head.size()) != head)
        return fail(ErrorCode::io, path, "changed while it was being read");
    return read_ply_point_cloud(path, *bytes, *ply, options);
}

std::optional<LoadedModel> OwnFormatHeader::load(const std::string& path, std::string_view head, std::uint64_t size,
                                                 const LoadOptions& options) const {
    // One pool for the file's read, the reading and the normals, for files large enough to share
    // (a thread costs about 0.1 ms to start): the threads are started once.
    std::optional<detail::ThreadPool> pool;
    if (options.threads != 1 && size >= k_file_bytes_for_threads) pool.emplace(options.threads <= 0 ? 0 : options.threads);
    detail::ThreadPool* workers = pool && pool->size() > 1 ? &*pool : nullptr;
    std::optional<FileBytes> bytes;
    if (workers) {
        // While one thread reads the file, another faults in the heap's free top, where the reader's
        // arrays, the normals and the first frame then allocate (as during the OFF reader's join):
        // the read ends it.
        std::atomic<bool> read{false};
        workers->parallel_for(2, [&](std::size_t task) {
            if (task == 0) {
                bytes = whole_file(path, size, options);
                read.store(true, std::memory_order_relaxed);
            } else {
                detail::populate_heap_top(k_populate_bytes_while_read, [&] { return !read.load(std::memory_order_relaxed); });
            }
        });
    } else {
        bytes = whole_file(path, size, options);
    }
    // A file changed since its header was read goes to assimp, which reads it again.
    if (!bytes || bytes->view().substr(0, head.size()) != head) return std::nullopt;
    std::optional<JoinedMesh> mesh =
        std::visit(Overloaded{[&](const OffHeader& h) { return read_plain_off_with_header(*bytes, h, workers); },
                              [&](const StlHeader& h) { return read_stl_with_header(*bytes, h); },
                              [&](const PlyHeader& h) { return read_plain_ply_with_header(*bytes, h); }},
                   header_);
    if (!mesh) return std::nullopt;
    const std::size_t triangles = mesh->indices.size() / 3;
    // Whatever the assimp path would refuse, it refuses with its own words.
    if (triangles > options.max_triangles || mesh->degenerate == triangles ||
        estimated_scene_bytes(mesh->positions.size(), triangles, !mesh->colours.empty(), false) > options.max_scene_bytes)
        return std::nullopt;
    SceneObject object;
    object.mesh.positions = std::move(mesh->positions);
    object.mesh.indices = std::move(mesh->indices);
    object.mesh.colours = std::move(mesh->colours);  // COFF's
    // The readers joined the vertices by position: nothing to weld.
    detail::compute_creased_normals_on(object.mesh, radians(options.crease_angle_degrees), workers,
                                       /*distinct_positions=*/true);
    // The root node's identity transform under the up-axis root, composed as the assimp path's node walk does.
    object.model = up_axis_root(options.up_axis) * Mat4::identity();
    object.material = own_format_material(std::holds_alternative<OffHeader>(header_));
    LoadedModel out;
    out.scene.objects.push_back(std::move(object));
    if (mesh->dropped_faces > 0) {  // the errors assimp's OFF reader logs, as the assimp path reports them
        ImportNotes notes;
        notes.error("OFF: Faces with zero indices aren't allowed");
        if (mesh->faces_missing) notes.error("OFF: The number of faces in the header is incorrect");
        notes.add_warnings(path, ResourceRoots(path, options.resource_dirs), out);
    }
    return out;
}

}  // namespace facet::io_detail
