// facet io: OBJ files (and their MTL files) and glTF 2.0 files read by facet's own readers (obj.hpp,
// gltf.hpp) and converted as the assimp path converts assimp's scenes (assimp_scene.hpp): part of
// the assimp module (assimp_module.hpp), since the conversion goes through assimp's aiMaterial. In:
// a file that passed load_model's pre-checks; out: its LoadedModel, or nullopt for the files the
// readers decline.
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

std::optional<Result<LoadedModel>> load_own_scene(const std::string& path, const std::string& ext, std::uint64_t size,
                                                  const LoadOptions& options) {
    const bool gltf = ext == "gltf" || ext == "glb";
    if (ext != "obj" && !gltf) return std::nullopt;
    const ResourceRoots roots(path, options.resource_dirs);
    ImportNotes notes;
    // A large file's pages (when read, not mapped), freed once read, taken again by the next large
    // scratch array (the creased normals' sums where they are kept for every position) rather than
    // mapped anew (fresh_pages.hpp). The OBJ join's table is the heap's: the conversion's positions
    // take its pages.
    const detail::RecycleFreshPages recycle;
    std::optional<Result<OwnScene>> scene;
    {
        std::optional<FileBytes> bytes = whole_file(path, size, options);
        if (!bytes) return std::nullopt;
        if (!gltf)
            scene = read_obj(path, *bytes, options, roots, notes, [&] { bytes.reset(); });
        else if (std::optional<OwnScene> s = read_gltf(path, *bytes, ext == "glb", options, roots, notes))
            scene = Result<OwnScene>(std::move(*s));
    }  // the file's text is freed before the conversion allocates the Scene (the OBJ's before its join)
    if (!scene) return std::nullopt;
    if (!*scene) return Result<LoadedModel>(scene->error());
    Result<LoadedModel> model = convert_scene(path, (*scene)->view(), options, roots);
    if (model) notes.add_warnings(path, roots, *model);
    return model;
}

}  // namespace facet::io_detail
