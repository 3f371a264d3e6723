// facet command line: subcommands `render` (one model to a PNG), `thumbs` (many models to
// thumbnails) and `view` (an interactive window: the executable apps/viewer builds, which this one
// becomes after checking the command line). Errors go to stderr; exit codes: 0 ok, 1 a file failed,
// 2 bad command line.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <optional>
#include <string>

#include "options.hpp"

int main(int argc, char** argv) {
    using namespace facet::cli;
    CLI::App app{k_app_description};
    app.set_version_flag("--version", std::string("facet ") + FACET_VERSION);
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

    ViewArgs view_args;
    CLI::App* view = add_view_subcommand(app, view_args);

    if (const std::optional<int> done = parse_command_line(app, argc, argv)) return *done;
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
        if (view->parsed()) return run_viewer_executable(argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "facet: %s\n", e.what());
        return k_exit_failed;
    }
    return k_exit_ok;
}
