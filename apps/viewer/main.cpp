// The viewer executable, `facet-view`: what `facet view` becomes (apps/cli/view_command.cpp). It
// gets facet's whole command line, `facet view [MODEL] [options]`, already checked by `facet`, and
// parses it with the same declarations, so it reads it exactly as `facet` did. SDL2 is linked here
// alone, so `facet render` and `facet thumbs` start without its libraries.
#include <CLI/CLI.hpp>

#include <cstdio>

#include "options.hpp"
#include "viewer.hpp"

int main(int argc, char** argv) {
    using namespace facet::cli;
    CLI::App app{k_app_description};
    app.require_subcommand(1);
    ViewArgs args;
    CLI::App* view = add_view_subcommand(app, args);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? 0 : k_exit_usage;
    }
    try {
        return facet::viewer::run_view(args.model, args.spin, args.options, has_camera_options(*view));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "facet: %s\n", e.what());
        return k_exit_failed;
    }
}
