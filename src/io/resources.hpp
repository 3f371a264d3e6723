// facet io: which files a model may read beside itself (textures, MTL files, glTF buffers, anything
// a reader opens). In: the model's path and LoadOptions::resource_dirs. Out: whether a path a
// reader wants lies, once every symbolic link and ".." is resolved, inside the model's folder (or a
// subfolder) or a resource folder; and the texture lookup under that rule. Every reader asks here:
// assimp through its IOSystem (assimp_import.cpp), facet's texture loading through find_texture_file.
// Not the opening itself (the worker's Landlock rules, apps/cli/worker.cpp, hold the same line in
// the kernel).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "facet/error.hpp"

namespace facet::io_detail {

class ResourceRoots {
public:
    ResourceRoots(const std::string& model_path, const std::vector<std::string>& resource_dirs);

    // Whether `path` may be read: it is the model itself, or it resolves inside one of the folders.
    // Decided by where the path leads (its existing part resolved, the rest taken as written).
    bool allows(const std::filesystem::path& path) const;

    // The reason a reference was not read, for a warning or an error after the model's name. Only
    // for references to files that exist: one that leads nowhere is reported as missing, as before,
    // so that the readers' probes for optional files (MDL's palette in the working folder, say) add
    // no warnings. (A warning thus tells that a file exists outside the folders, never its content.)
    std::string refusal(const std::string& reference) const;

private:
    std::filesystem::path model_;                // resolved
    std::vector<std::filesystem::path> folders_;  // resolved
};

// Finds a texture file named in a model: as written (relative to the model's folder; a "file://"
// URI as its path); an absolute path also as if it were relative ("\..\tex\a.png" from Windows
// tools); then its file name alone in the model's folder (absolute paths from the author's machine,
// "C:\..."). Each candidate exactly first, then in any letter case. Only candidates `roots` allows
// are looked at; when none is found and one was refused, the error says so.
Result<std::filesystem::path> find_texture_file(const ResourceRoots& roots, const std::filesystem::path& model_dir,
                                                std::string name);

}  // namespace facet::io_detail
