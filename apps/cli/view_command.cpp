// `facet view` in the `facet` binary: its options, and the hand-over to the viewer executable
// (apps/viewer), which alone links SDL2.
#include <CLI/CLI.hpp>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "options.hpp"

namespace facet::cli {

const char* const k_app_description =
    "facet: a software 3D renderer. Renders model files to PNG on the CPU (no GPU, no display), or shows them in a "
    "window.";

CLI::App* add_view_subcommand(CLI::App& app, ViewArgs& args) {
    CLI::App* view = app.add_subcommand("view", "Open a model (or, with none, the default scene) in an interactive window");
    view->add_option("model", args.model, "Model file (or drop one onto the window)");
    view->add_flag("--spin", args.spin, "Start with the turntable spinning (Space toggles it)");
    add_render_options(*view, args.options);
    view->get_option("--size")->description("Initial window size WxH");
    view->get_option("--ssaa")->description("Initial supersampling NxN (A toggles 1 and 2)");
    view->footer(
        "Mouse: left drag orbit, right or middle drag pan, wheel zoom. Keys: F fit, R reset, 1-7 front/right/top/iso/"
        "back/left/bottom, U up axis y/z, P perspective/ortho, M shading, W wireframe, C back-face culling, Space spin, "
        "A supersampling 1/2, S screenshot, H overlay, Q or Esc quit. Drop a model file onto the window to open it.");
    return view;
}

int run_viewer_executable(char** argv) {
    // /proc/self/exe rather than argv[0]: facet may have been found through PATH or a symbolic link.
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) {
        std::fprintf(stderr, "facet view: cannot find the facet executable: %s\n", ec.message().c_str());
        return k_exit_failed;
    }
    const std::string viewer = (self.parent_path() / k_viewer_executable).string();
    std::fflush(nullptr);
    ::execv(viewer.c_str(), argv);
    std::fprintf(stderr, "facet view: cannot run the viewer %s: %s\n", viewer.c_str(), std::strerror(errno));
    return k_exit_failed;
}

}  // namespace facet::cli
