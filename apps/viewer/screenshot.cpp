// facet view: screenshot names and writing.
#include "screenshot.hpp"

#include <cstdio>
#include <filesystem>
#include <system_error>

#include "facet/io.hpp"

namespace facet::viewer {

Result<std::string> next_screenshot_path(const std::string& model_path) {
    namespace fs = std::filesystem;
    const fs::path model(model_path);
    const fs::path dir = model_path.empty() ? fs::path() : model.parent_path();
    const std::string stem = model_path.empty() ? std::string("facet") : model.stem().string();
    for (int n = 1; n <= 999; ++n) {
        char suffix[32];
        std::snprintf(suffix, sizeof suffix, ".screenshot-%03d.png", n);
        const fs::path candidate = dir / (stem + suffix);
        std::error_code ec;
        if (!fs::exists(fs::symlink_status(candidate, ec))) return candidate.string();
    }
    return Error{ErrorCode::io, (dir / (stem + ".screenshot-*.png")).string() + ": all 999 screenshot names are taken"};
}

Result<std::string> save_screenshot(const Image& image, const std::string& model_path) {
    Result<std::string> path = next_screenshot_path(model_path);
    if (!path) return path;
    if (Status s = write_png(*path, image); !s) return s.error();
    return path;
}

}  // namespace facet::viewer
