// facet io: OBJ files (and their MTL files) and glTF 2.0 files read by facet's own readers (obj.hpp,
// gltf.hpp) and converted as the assimp path converts assimp's scenes (assimp_scene.hpp): part of
// the assimp module (assimp_module.hpp), since the conversion goes through assimp's aiMaterial. In:
// a file that passed load_model's pre-checks; out: its LoadedModel, or nullopt for the files the
// readers decline.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <string_view>
#include <utility>

#include "exec/fresh_pages.hpp"
#include "io/assimp_scene.hpp"
#include "io/fast_path.hpp"
#include "io/gltf.hpp"
#include "io/import_notes.hpp"
#include "io/obj.hpp"
#include "io/resources.hpp"

namespace facet::io_detail {
namespace {

// A file's bytes followed by a NUL, as the OBJ reader takes them, read straight into fresh pages
// (zero already, not cleared again; of 2 MB where the system grants them, so that tens of
// megabytes are faulted in a few dozen times rather than thousands). Not mapped: a file cut short
// while mapped would crash the reader (SIGBUS) instead of failing. Nullopt when the file's size is
// no longer `size`.
class FileText {
public:
    static std::optional<FileText> open(const std::string& path, std::uint64_t size) {
        FileText t(static_cast<std::size_t>(size));
        const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) return std::nullopt;
        std::size_t got = 0;
        char extra = 0;
        for (;;) {
            const bool tail = got == t.size_;  // one byte more must find the end of the file
            const ssize_t n = ::read(fd, tail ? &extra : t.bytes_.data() + got, tail ? 1 : t.size_ - got);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0 || tail) {
                ::close(fd);
                if (n != 0 || !tail) return std::nullopt;  // changed while being read: assimp reads it again and decides
                break;
            }
            got += static_cast<std::size_t>(n);
        }
        return t;
    }
    std::string_view text() const { return {bytes_.data(), size_}; }

private:
    explicit FileText(std::size_t size) : bytes_(size + 1), size_(size) {}  // the NUL: zero already
    detail::ZeroedArray<char> bytes_;
    std::size_t size_;
};

}  // namespace

std::optional<Result<LoadedModel>> load_own_scene(const std::string& path, const std::string& ext, std::uint64_t size,
                                                  const LoadOptions& options) {
    const bool gltf = ext == "gltf" || ext == "glb";
    if (ext != "obj" && !gltf) return std::nullopt;
    const ResourceRoots roots(path, options.resource_dirs);
    ImportNotes notes;
    std::optional<Result<OwnScene>> scene;
    {
        std::optional<FileText> bytes = FileText::open(path, size);
        if (!bytes) return std::nullopt;
        if (!gltf)
            scene = read_obj(path, bytes->text(), options, roots, notes);
        else if (std::optional<OwnScene> s = read_gltf(path, bytes->text(), ext == "glb", options, roots, notes))
            scene = Result<OwnScene>(std::move(*s));
    }  // the file's text is freed before the conversion allocates the Scene
    if (!scene) return std::nullopt;
    if (!*scene) return Result<LoadedModel>(scene->error());
    Result<LoadedModel> model = convert_scene(path, (*scene)->view(), options, roots);
    if (model) notes.add_warnings(path, roots, *model);
    return model;
}

}  // namespace facet::io_detail
