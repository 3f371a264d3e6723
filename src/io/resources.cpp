// facet io: the model's resource folders and the texture lookup within them (resources.hpp).
#include "io/resources.hpp"

#include <algorithm>
#include <optional>

#include "io/load_common.hpp"

namespace facet::io_detail {
namespace {

namespace fs = std::filesystem;

// The path with its existing part resolved (symbolic links, "..") and the rest normalized as written.
std::optional<fs::path> resolved(const fs::path& path) {
    std::error_code ec;
    fs::path p = fs::weakly_canonical(path.empty() ? fs::path(".") : path, ec);
    if (ec) return std::nullopt;
    return p;
}

bool is_within(const fs::path& path, const fs::path& folder) {
    const auto [f, p] = std::mismatch(folder.begin(), folder.end(), path.begin(), path.end());
    return f == folder.end() || (std::next(f) == folder.end() && f->empty());  // "/a/b/" holds "/a/b/c"
}

// A file named `name` in `dir`, in any letter case (textures authored on Windows or macOS).
std::optional<fs::path> find_any_case(const fs::path& dir, const std::string& name) {
    std::error_code ec;
    const std::string wanted = lower(name);
    for (fs::directory_iterator it(dir.empty() ? fs::path(".") : dir, ec), end; !ec && it != end; it.increment(ec))
        if (lower(it->path().filename().string()) == wanted && it->is_regular_file(ec)) return it->path();
    return std::nullopt;
}

// A "file://" URI's path ("file:///a/b.png" and "file://localhost/a/b.png" are "/a/b.png").
std::string without_file_scheme(std::string name) {
    if (lower(name.substr(0, 7)) != "file://") return name;
    name.erase(0, 7);
    if (lower(name.substr(0, 10)) == "localhost/") name.erase(0, 9);
    return name;
}

}  // namespace

ResourceRoots::ResourceRoots(const std::string& model_path, const std::vector<std::string>& resource_dirs) {
    if (std::optional<fs::path> m = resolved(model_path)) model_ = *m;
    std::vector<fs::path> folders = {fs::path(model_path).parent_path()};
    folders.insert(folders.end(), resource_dirs.begin(), resource_dirs.end());
    for (const fs::path& f : folders)
        if (std::optional<fs::path> r = resolved(f)) folders_.push_back(*r);
}

bool ResourceRoots::allows(const fs::path& path) const {
    const std::optional<fs::path> p = resolved(path);
    if (!p) return false;
    if (*p == model_) return true;
    return std::any_of(folders_.begin(), folders_.end(), [&](const fs::path& f) { return is_within(*p, f); });
}

std::string ResourceRoots::refusal(const std::string& reference) const {
    return "refused to read '" + readable(reference) + "': it lies outside the model's folder" +
           (folders_.size() > 1 ? " and the resource folders" : "") +
           " once symbolic links are followed (--resource-dir DIR allows another folder)";
}

Result<fs::path> find_texture_file(const ResourceRoots& roots, const fs::path& model_dir, std::string name) {
    const std::string reference = name;
    name = without_file_scheme(std::move(name));
    std::replace(name.begin(), name.end(), '\\', '/');
    const fs::path as_written(name);
    const std::string file_name = name.substr(name.find_last_of('/') + 1);
    const Error not_found{ErrorCode::io, "file not found (looked for '" + reference + "' in '" +
                                             (model_dir.empty() ? std::string(".") : model_dir.string()) + "')"};
    if (file_name.empty()) return not_found;
    std::vector<fs::path> candidates = {as_written.is_absolute() ? as_written : model_dir / as_written};
    if (as_written.is_absolute()) candidates.push_back(model_dir / as_written.relative_path());
    candidates.push_back(model_dir / file_name);
    bool refused = false;
    std::error_code ec;
    for (const fs::path& c : candidates) {
        if (!roots.allows(c)) {
            refused = refused || fs::exists(c, ec);
        } else if (fs::is_regular_file(c, ec)) {
            return c;
        }
    }
    for (const fs::path& c : candidates) {
        if (!roots.allows(c.parent_path())) continue;  // not even listed
        if (std::optional<fs::path> found = find_any_case(c.parent_path(), file_name)) {
            if (roots.allows(*found)) return *found;
            refused = true;
        }
    }
    if (refused) return Error{ErrorCode::io, roots.refusal(reference)};
    return not_found;
}

}  // namespace facet::io_detail
