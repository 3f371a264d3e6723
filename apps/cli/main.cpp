// facet command line: subcommands `render` (one model to a PNG), `thumbs` (many models to
// thumbnails) and `view` (an interactive window, apps/viewer). Errors go to stderr; exit codes:
// 0 ok, 1 a file failed, 2 bad command line.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <optional>

#include "options.hpp"
#include "viewer.hpp"

int main(int argc, char** argv) {
    using namespace facet::cli;
    CLI::App app{"facet: a software 3D renderer. Renders model files to PNG on the CPU (no GPU, no display), or shows them in a window."};
    app.require_subcommand(1);

    RenderOptions render_options;
    std::string model, output = "facet.png", depth_out;
    std::optional<int> benchmark;
    CLI::App* render = app.add_subcommand("render", "Render a model file (or, with none, the built-in default scene) to a PNG");
    render->add_option("model", model, "Model file: OBJ, STL, PLY, OFF, glTF/GLB, FBX, 3MF, DAE, 3DS, ...");
    render->add_option("-o,--output", output, "Output PNG (written atomically)")->capture_default_str();
    render->add_option("--depth-out", depth_out, "Also write window depth as a 16-bit grayscale PNG");
    render->add_option("--benchmark", benchmark, "Render N timed frames after a warm-up; print one JSON line");
    add_render_options(*render, render_options);
    add_worker_options(*render, render_options, /*in_process_option=*/true);

    RenderOptions thumbs_options;
    thumbs_options.size = "256";
    thumbs_options.azimuth = 35;
    thumbs_options.elevation = 25;
    std::vector<std::string> inputs;
    std::string out_dir;
    CLI::App* thumbs = app.add_subcommand("thumbs", "Render a thumbnail PNG of every model in files and directories");
    thumbs->add_option("inputs", inputs, "Model files and directories (searched recursively)")->required();
    thumbs->add_option("-o,--output", out_dir, "Output directory")->required();
    add_render_options(*thumbs, thumbs_options);
    thumbs->get_option("--size")->description("Thumbnail size N (square) or WxH");
    add_worker_options(*thumbs, thumbs_options, /*in_process_option=*/false);

    RenderOptions view_options;
    std::string view_model;
    bool spin = false;
    CLI::App* view = app.add_subcommand("view", "Open a model (or, with none, the default scene) in an interactive window");
    view->add_option("model", view_model, "Model file (or drop one onto the window)");
    view->add_flag("--spin", spin, "Start with the turntable spinning (Space toggles it)");
    add_render_options(*view, view_options);
    view->get_option("--size")->description("Initial window size WxH");
    view->get_option("--ssaa")->description("Initial supersampling NxN (A toggles 1 and 2)");
    view->footer(
        "Mouse: left drag orbit, right or middle drag pan, wheel zoom. Keys: F fit, R reset, 1-7 front/right/top/iso/"
        "back/left/bottom, U up axis y/z, P perspective/ortho, M shading, W wireframe, C back-face culling, Space spin, "
        "A supersampling 1/2, S screenshot, H overlay, Q or Esc quit. Drop a model file onto the window to open it.");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? 0 : k_exit_usage;
    }
    try {
        if (render->parsed()) {
            if (render_options.no_isolation && (render->count("--timeout") > 0 || render->count("--max-memory") > 0)) {
                std::fprintf(stderr, "facet render: --timeout and --max-memory apply to the worker process, which "
                                     "--no-isolation does without\n");
                return k_exit_usage;
            }
            return run_render(model, output, depth_out, benchmark, render_options, has_camera_options(*render));
        }
        if (thumbs->parsed()) return run_thumbs(inputs, out_dir, thumbs_options);
        if (view->parsed()) return facet::viewer::run_view(view_model, spin, view_options, has_camera_options(*view));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "facet: %s\n", e.what());
        return k_exit_failed;
    }
    return k_exit_ok;
}
