// facet command line: subcommands `render` (one model to a PNG), `thumbs` (many models to
// thumbnails), `thumbnail` (one, for a file manager), `view` (an interactive window: the
// executable apps/viewer builds, which this one becomes after checking the command line) and `diff` (two images compared). Errors go to stderr;
// exit codes: 0 ok, 1 a file failed (diff: the images differ), 2 bad command line (diff: or a file
// that cannot be read).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>

#include "add_option.hpp"
#include "facet/sandbox.hpp"
#include "options.hpp"

namespace {
const char* const k_threshold_help =
    "Comparison thresholds, any of diff=N (per-channel difference that does not count), pixels=N or P% (how many "
    "may differ by more), ssim=S, psnr=DB, comma-separated; default exact (diff=0,pixels=0); only ssim and/or psnr: "
    "pixels are not counted";

// The subcommands. A command line that names one first (`facet render ...`, nearly all) gets the
// options of that one only: making every subcommand's options was most of what facet did before
// the job began (CLI11 compares each new option's names with all the others: 2.6 M of the parent's
// 6.6 M instructions for `facet render`). Any other command line (--help, --version, a mistake)
// gets them all, as before.
constexpr std::string_view k_subcommands[] = {"render", "thumbs", "thumbnail", "view", "diff"};

bool options_wanted(std::string_view subcommand, int argc, char** argv) {
    const std::string_view first = argc > 1 ? argv[1] : "";
    return first == subcommand || std::find(std::begin(k_subcommands), std::end(k_subcommands), first) == std::end(k_subcommands);
}

// `facet render`'s end, its files complete and its messages written: stdio flushed, the process
// ends without destroying the options (CLI11's App: ~0.1 ms of frees) or running static
// destructors, which release nothing the exit does not. Sanitizer builds return from main as
// usual: LeakSanitizer checks at exit.
int end_render(int status) {
    if (facet::sanitizer_build()) return status;
    std::fflush(nullptr);
    std::_Exit(status);
}
}  // namespace

int main(int argc, char** argv) {
    using namespace facet::cli;
    CLI::App app{k_app_description};
    app.set_version_flag("--version", std::string("facet ") + FACET_VERSION);
    app.require_subcommand(1);

    RenderOptions render_options;
    std::string model, output = "facet.png", depth_out;
    std::optional<int> benchmark;
    ReferenceCheck reference;
    CLI::App* render = app.add_subcommand("render", "Render a model file (or, with none, the built-in default scene) to a PNG");
    if (options_wanted("render", argc, argv)) {
        add_option(*render, "model", model, "Model file: OBJ, STL, PLY, OFF, glTF/GLB, FBX, 3MF, DAE, 3DS, ...");
        add_option(*render, "-o,--output", output,
                   "Output PNG (written atomically); with --views or --passes, the folder to write into")
            ->capture_default_str();
        add_option(*render, "--depth-out", depth_out, "Also write window depth as a 16-bit grayscale PNG");
        add_option(*render, "--benchmark", benchmark, "Render N timed frames after a warm-up; print one JSON line");
        add_render_options(*render, render_options);
        add_views_options(*render, render_options);
        add_worker_options(*render, render_options, /*in_process_option=*/true);
        add_option(*render, "--reference", reference.reference,
                   "Compare the output with this PNG: exit 1 and write OUTPUT.diff.png when they differ");
        add_option(*render, "--threshold", reference.threshold, k_threshold_help);
        add_flag(*render, "--update-reference", reference.update,
                 "Write the --reference PNG when it is missing or differs (and say so) instead of failing");
    }

    RenderOptions thumbs_options = thumbnail_options();
    std::vector<std::string> inputs;
    std::string out_dir;
    CollectionOptions collection;
    CLI::App* thumbs = app.add_subcommand("thumbs", "Render a thumbnail PNG of every model in files and directories");
    if (options_wanted("thumbs", argc, argv)) {
        add_option(*thumbs, "inputs", inputs, "Model files and directories (searched recursively); or give --manifest");
        add_option(*thumbs, "-o,--output", out_dir, "Output directory")->required();
        add_option(*thumbs, "--manifest", collection.manifest,
                   "Objects from this file ('-': stdin): a path per line, or JSON Lines with \"path\", \"id\" and "
                   "per-object \"size\", \"up_axis\", \"views\", \"passes\"; outputs are named by the id");
        add_option(*thumbs, "--shard", collection.shard,
                   "K/N: only the objects whose id hashes into shard K of N (0 <= K < N), the same on every machine");
        add_option(*thumbs, "--log", collection.log,
                   "Append one JSON line per finished object to this file (id, status, error, times, outputs, "
                   "options hash)");
        add_option(*thumbs, "--manifest-lines", collection.manifest_lines,
                   "Only these lines of the --manifest file, as OFFSET:LINE pairs (byte offset of the line's start, "
                   "line number), comma-separated: a task of a few objects that need not read the whole manifest "
                   "(facet.distributed's tasks; temporaries of killed runs are then left to the caller)");
        add_flag(*thumbs, "--resume", collection.resume,
                 "Skip the objects the --log has done with the same options whose outputs exist; redo the rest");
        add_option(*thumbs, "--worker-sharing", collection.worker_sharing,
                   "folder: a worker process serves files of one folder only; batch: the next objects of the run "
                   "whatever their folders, its sandbox opened to those folders (default: batch with --manifest, "
                   "folder otherwise)")
            ->check(CLI::IsMember({"folder", "batch"}));
        add_render_options(*thumbs, thumbs_options);
        thumbs->get_option("--size")->description("Thumbnail size N (square) or WxH");
        add_worker_options(*thumbs, thumbs_options, /*in_process_option=*/false);
    }

    RenderOptions thumbnail_options = thumbnailer_options();
    std::string thumbnail_input, thumbnail_output;
    int thumbnail_size = facet::defaults::k_thumbnail_size;
    CLI::App* thumbnail = app.add_subcommand(
        "thumbnail", "One thumbnail for a file manager (the freedesktop thumbnailer entry runs it): a PNG of SIZE x SIZE "
                     "on a transparent background; exit 0 only when it is written");
    if (options_wanted("thumbnail", argc, argv)) {
        add_option(*thumbnail, "input", thumbnail_input, "Model file: a path or a file:// URI")->required();
        add_option(*thumbnail, "output", thumbnail_output, "Output PNG (written atomically; none when the model fails)")->required();
        add_render_options(*thumbnail, thumbnail_options);
        thumbnail->remove_option(thumbnail->get_option("--size"));
        thumbnail->remove_option(thumbnail->get_option("--threads"));  // one file: one worker, one thread
        add_option(*thumbnail, "-s,--size", thumbnail_size, "Thumbnail size N for N x N (the file manager's %s)")
            ->capture_default_str();
        add_worker_options(*thumbnail, thumbnail_options, /*in_process_option=*/false);
    }

    ViewArgs view_args;
    CLI::App* view = add_view_subcommand(app, view_args, options_wanted("view", argc, argv));

    std::string diff_a, diff_b;
    DiffOptions diff_options;
    CLI::App* diff = app.add_subcommand("diff", "Compare two PNG images: exit 0 when within the thresholds, 1 when not, 2 on an error");
    if (options_wanted("diff", argc, argv)) {
        add_option(*diff, "a", diff_a, "First image (the diff image dims a copy of it)")->required();
        add_option(*diff, "b", diff_b, "Second image")->required();
        add_option(*diff, "--threshold", diff_options.threshold, k_threshold_help);
        add_option(*diff, "--diff-image", diff_options.diff_image, "Write where they differ (red) over a dimmed copy of A to this PNG");
        add_flag(*diff, "--json", diff_options.json, "Print the comparison as one JSON object instead of the summary line");
    }

    if (const std::optional<int> done = parse_command_line(app, argc, argv)) return *done;
    try {
        if (render->parsed()) {
            if (render_options.no_isolation && (render->count("--timeout") > 0 || render->count("--max-memory") > 0)) {
                std::fprintf(stderr, "facet render: --timeout and --max-memory apply to the worker process, which "
                                     "--no-isolation does without\n");
                return k_exit_usage;
            }
            return end_render(run_render(model, output, depth_out, benchmark, render_options, has_camera_options(*render),
                                         reference, render->count("--output") > 0, render->count("--size") > 0));
        }
        if (thumbs->parsed()) return run_thumbs(inputs, out_dir, thumbs_options, collection);
        if (thumbnail->parsed()) return run_thumbnail(thumbnail_input, thumbnail_output, thumbnail_size, thumbnail_options);
        if (diff->parsed()) return run_diff(diff_a, diff_b, diff_options);
        if (view->parsed() && view_args.options.print_config)
            return print_view_config(view_args, has_camera_options(*view));
        if (view->parsed()) return run_viewer_executable(argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "facet: %s\n", e.what());
        return k_exit_failed;
    }
    return k_exit_ok;
}
