// facet exec: opening facet's modules (facet/detail/module.hpp) with dlopen. In: a module's file
// and symbol names; out: the symbol's address or why not. Does not decide which job needs a module.
#include "facet/detail/module.hpp"

#include <dlfcn.h>
#include <link.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>

#include "exec/module_build_dir.hpp"

namespace facet::detail {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> candidate_dirs() {
    std::vector<std::string> dirs;
    if (const char* env = std::getenv("FACET_MODULE_DIR"); env && *env) dirs.push_back(env);
    // The file holding this code: a shared library's path, or for the program itself (whose name
    // in the loader's list is empty) /proc/self/exe, not argv[0], which may be a bare name on PATH.
    Dl_info info{};
    link_map* object = nullptr;
    if (dladdr1(reinterpret_cast<void*>(&candidate_dirs), &info, reinterpret_cast<void**>(&object), RTLD_DL_LINKMAP) != 0) {
        const bool program = !object || !object->l_name || object->l_name[0] == '\0';
        std::error_code ec;
        const fs::path self = fs::canonical(program ? "/proc/self/exe" : object->l_name, ec);
        if (!ec) {
            const fs::path here = self.parent_path();
            dirs.push_back(here.string());
            dirs.push_back((here / "facet").string());
            dirs.push_back((here / FACET_MODULE_RELATIVE_DIR).lexically_normal().string());
        }
    }
    dirs.push_back(k_module_build_dir);
    dirs.push_back(FACET_MODULE_INSTALL_DIR);
    return dirs;
}

}  // namespace

std::vector<std::string> module_dirs() {
    std::vector<std::string> found;
    for (const std::string& d : candidate_dirs()) {
        std::error_code ec;
        if (fs::is_directory(d, ec)) found.push_back(d);
    }
    return found;
}

void* module_symbol(const char* file, const char* symbol, std::string& why) {
    static std::mutex lock;
    static std::map<std::string, void*> opened;  // file -> handle, kept for the process's life
    const std::lock_guard<std::mutex> guard(lock);
    void*& handle = opened[file];
    if (!handle) {
        std::string tried;
        for (const std::string& dir : candidate_dirs()) {
            const fs::path path = fs::path(dir) / file;
            std::error_code ec;
            if (!fs::exists(path, ec)) continue;
            handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
            if (handle) break;
            const char* error = dlerror();
            tried += (tried.empty() ? "" : "; ") + std::string(error ? error : path.string() + ": cannot be opened");
        }
        if (!handle) {
            why = std::string("facet's module ") + file + " cannot be loaded (" +
                  (tried.empty() ? "not found beside the program, in $FACET_MODULE_DIR or in " FACET_MODULE_INSTALL_DIR : tried) + ")";
            return nullptr;
        }
    }
    void* address = dlsym(handle, symbol);
    if (!address) why = std::string("facet's module ") + file + " has no " + symbol + " (a module of another build?)";
    return address;
}

}  // namespace facet::detail
