// facet command line: subcommands `render` (one model to a PNG) and `thumbs` (many models to
// thumbnails). Errors go to stderr; exit codes: 0 ok, 1 a file failed, 2 bad command line.
#include <CLI/CLI.hpp>

#include <cstdio>

#include "options.hpp"

int main(int argc, char** argv) {
    using namespace facet::cli;
    CLI::App app{"facet: a software 3D renderer. Renders model files to PNG on the CPU: no GPU, no display."};
    app.require_subcommand(1);

    RenderOptions render_options;
    std::string model, output = "facet.png", depth_out;
    int benchmark = 0;
    CLI::App* render = app.add_subcommand("render", "Render a model file (or, with none, the built-in default scene) to a PNG");
    render->add_option("model", model, "Model file: OBJ, STL, PLY, OFF, glTF/GLB, FBX, 3MF, DAE, 3DS, ...");
    render->add_option("-o,--output", output, "Output PNG (written atomically)")->capture_default_str();
    render->add_option("--depth-out", depth_out, "Also write window depth as a 16-bit grayscale PNG");
    render->add_option("--benchmark", benchmark, "Render N timed frames after a warm-up; print one JSON line");
    add_render_options(*render, render_options);

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

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? 0 : k_exit_usage;
    }
    try {
        if (render->parsed()) {
            const bool camera_options = render->count("--azimuth") + render->count("--elevation") + render->count("--eye") +
                                            render->count("--target") + render->count("--fov") + render->count("--ortho") +
                                            render->count("--near") + render->count("--far") + render->count("--up") > 0;
            return run_render(model, output, depth_out, benchmark, render_options, camera_options);
        }
        if (thumbs->parsed()) return run_thumbs(inputs, out_dir, thumbs_options);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "facet: %s\n", e.what());
        return k_exit_failed;
    }
    return k_exit_ok;
}
