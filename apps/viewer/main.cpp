// The viewer executable, `facet-view`: what `facet view` becomes (apps/cli/options.cpp). It
// gets facet's whole command line, `facet view [MODEL] [options]`, already checked by `facet`, and
// parses it with the same declarations, so it reads it exactly as `facet` did. SDL2 is linked here
// alone, so `facet render` and `facet thumbs` start without its libraries.
#include <cstdio>
#include <optional>

#include "options.hpp"
#include "viewer.hpp"

int main(int argc, char** argv) {
    using namespace facet::cli;
    ViewArgs args;
    bool camera_options_given = false;
    if (const std::optional<int> exit_code = parse_view_command_line(argc, argv, args, camera_options_given))
        return *exit_code;
    try {
        return facet::viewer::run_view(args.model, args.spin, args.options, camera_options_given);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "facet: %s\n", e.what());
        return k_exit_failed;
    }
}
