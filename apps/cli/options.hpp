// facet command line: the render options shared by `facet render` and `facet thumbs`, their
// parsing, and the one function that turns a loaded scene into pixels.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "facet/compare.hpp"
#include "facet/error.hpp"
#include "facet/model.hpp"
#include "facet/scene.hpp"
#include "facet/views.hpp"
#include "worker.hpp"

// CLI11 is header-only and costs seconds of compile time per file that includes it: only
// main.cpp and options.cpp do, the others see the name.
namespace CLI {
class App;
}

namespace facet::cli {

// Exit codes scripts can trust.
constexpr int k_exit_ok = 0;
constexpr int k_exit_failed = 1;     // a file could not be loaded, rendered or written
constexpr int k_exit_usage = 2;      // bad command line

// "WxH".
std::string size_text(int width, int height);

// Every default comes from facet/defaults.hpp; thumbnail_options() are thumbs' own.
struct RenderOptions {
    std::string size = size_text(defaults::k_image_width, defaults::k_image_height);
    float azimuth = defaults::k_azimuth_degrees, elevation = defaults::k_elevation_degrees;
    float fov = defaults::k_fov_degrees;
    std::string eye, target, up;
    std::optional<float> near, far;
    std::string up_axis = "y";
    bool ortho = false;
    std::string shading = "lit";
    std::string background = "";  // default: the built-in dark grey
    int ssaa = defaults::k_ssaa;
    int aa = defaults::k_aa;  // jittered frames averaged (antialias_offsets)
    float contact_shadow = defaults::k_contact_shadow;  // lit mode: its opacity, 0: none
    // The lit mode's light and display (RenderSettings): an .hdr file (empty: the built-in studio).
    std::string environment;
    float exposure = defaults::k_exposure;
    std::string tone_mapping = "neutral";
    int threads = defaults::k_threads;
    std::string isa = "best";  // instruction set of the SIMD kernels (facet/isa.hpp)
    float crease_angle = defaults::k_crease_angle_degrees;
    // Points and lines (RenderSettings::primitives), in output pixels; --point-world-size instead
    // gives points a size in model units.
    float point_size = defaults::k_point_size;
    std::optional<float> point_world_size;
    std::string point_shape = "round";
    float line_width = defaults::k_line_width;
    bool line_aa = false;  // PrimitiveStyle::line_aa
    // Resource limits for loading (LoadOptions, TextureLimits): checked before anything is allocated.
    long long max_triangles = static_cast<long long>(defaults::k_max_triangles);  // signed: -1 is an error, not 2^64 - 1
    int max_texture_size = defaults::k_max_texture_size;
    // Folders besides the model's own whose files the model may read (LoadOptions::resource_dirs).
    std::vector<std::string> resource_dirs;
    // The worker process each file is loaded and rendered in (render, thumbs; worker.hpp).
    double timeout = defaults::k_timeout_seconds;  // seconds a file may take (load, render, write); 0: no limit
    std::string max_memory;  // the worker's memory cap (parse_memory_size); empty: the default
    bool no_isolation = false;  // render: load and render in this process (debugging)
    bool print_config = false;  // print the resolved settings and exit (print_config.cpp)
    // Views and render passes (add_views_options; views_output.hpp): with either, -o is a folder.
    std::optional<std::string> passes;  // "color,depth,...": not given: colour alone
    std::optional<std::string> views;   // a camera rig (parse_views); not given: the one camera above
    std::string float_format = "npy";
    std::string normal_space = "world";
    std::optional<float> depth_scale;  // --float-format png: model units per step of depth and range
};

// `facet thumbs`' defaults: square thumbnails seen from above and to the right.
RenderOptions thumbnail_options();

// Adds the options above to a subcommand.
void add_render_options(CLI::App& command, RenderOptions& options);

// Adds --passes, --views, --float-format, --normal-space and --depth-scale (render).
void add_views_options(CLI::App& command, RenderOptions& options);

// Adds --timeout and --max-memory (render and thumbs), and with `in_process_option` --no-isolation.
void add_worker_options(CLI::App& command, RenderOptions& options, bool in_process_option);

// The worker limits by the options, for `workers` workers at a time (the default memory cap is
// shared among them); the error message names the offending option.
Result<WorkerLimits> make_worker_limits(const RenderOptions& options, unsigned workers);

// An image size "WxH" (with `square`, also "N" for NxN), each side at least 1 and, times `ssaa`,
// within the largest target; the error names `name`, the option or key it came from.
Result<std::pair<int, int>> parse_image_size(const std::string& name, const std::string& text, int ssaa, bool square);

// How floating-point passes (depth, range, normal, uv) are written: NumPy .npy files (float32),
// one OpenEXR file per view holding every pass but colour, or PNG (depth and range in 16 bits with a
// scale, normals in 8 bits, uv in 16 bits).
enum class FloatFormat { npy, exr, png };
const char* to_string(FloatFormat format);

// Many views, or render passes, of one scene into a folder (views_output.hpp).
struct ViewsPlan {
    PassSet passes = PassSet{}.add(Pass::colour);
    // Each view: a rig's orbit angles with the plan's other camera options, or an OpenCV camera read
    // from a cameras file. Empty: the plan's one camera (view, or the default scene's).
    std::vector<ViewSpec> views;
    std::string rig;  // as given, for --print-config; empty: none
    FloatFormat float_format = FloatFormat::npy;
    NormalSpace normal_space = NormalSpace::world;
    std::optional<float> depth_scale;  // png: model units per step; default: the farthest far plane / 65535
};

// The options after validation, ready to render with.
struct RenderPlan {
    int width = 0, height = 0;
    int ssaa = 1;
    int aa = 1;  // jittered frames averaged: 1, 2, 4 or 8
    float contact_shadow = 0;  // the lit mode's contact shadow's opacity (0: none)
    ViewSpec view;
    RenderSettings settings;
    std::string environment_file;  // --environment, loaded into settings.environment; empty: the studio
    std::optional<ViewsPlan> views;  // --views or --passes: a folder of views and passes
    LoadOptions load;
    bool use_default_scene_camera = false;  // no model and no camera options: the designed view
};

// Whether any option that places the camera was given to `command` (--azimuth, --elevation, --eye,
// --target, --fov, --ortho, --near, --far, --up): without one and without a model, the default
// scene is shown from its designed camera.
bool has_camera_options(const CLI::App& command);

// Parses the command line into `app`: nullopt when the command is to run, or the exit status when
// the process is done (--help and friends: 0, printed; a usage error: k_exit_usage, printed to stderr).
std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv);

// --passes, --views and the options that go with them into plan.views, after the camera options,
// which each view of a rig starts from (make_plan; `facet thumbs` for a manifest's "views" and
// "passes"). A cameras file's image size becomes the plan's unless `size_given`.
Status make_views_plan(const RenderOptions& o, bool size_given, RenderPlan& p);

// Checks and converts the options; the error message names the offending option. `size_given`:
// whether --size was given (a cameras file's views otherwise set the size). A cameras file
// (--views file:...) is read here.
Result<RenderPlan> make_plan(const RenderOptions& options, bool camera_options_given, bool size_given = true);

// The plan's camera for the scene: its automatic framing (which reads every vertex) or the explicit one.
Camera plan_camera(const Scene& scene, const RenderPlan& plan);

// The plan's request to the library's ViewRenderer: size, --ssaa, --aa, the contact shadow and the
// settings, colour alone (views_output.cpp adds the passes).
ViewRequest view_request(const RenderPlan& plan);

// Renders a scene seen by `camera` (plan_camera) into `colour` (and `depth`, window depth per pixel,
// if given) by the plan, through ViewRenderer (view_request): with --aa N, N frames jittered by
// antialias_offsets(N), each resolved (--ssaa), averaged per channel (rounded to nearest), depth the
// nearest; the stats of the first. With a contact shadow (lit mode, the camera above the ground)
// its quad is drawn too. `facet render` and `facet thumbs` draw their images with it.
DrawStats render_plan(ViewRenderer& renderer, const Scene& scene, const RenderPlan& plan, const Camera& camera,
                      Image& colour, std::vector<float>* depth);
// The same into plan.width x plan.height pixels at `colour`, which the render writes whole (its
// contents before do not matter: facet render's image is not cleared first).
DrawStats render_plan(ViewRenderer& renderer, const Scene& scene, const RenderPlan& plan, const Camera& camera,
                      Rgba8* colour, std::vector<float>* depth);

// --print-config (print_config.cpp): the settings a run resolves to, one `key = value` line each in
// a fixed order, after a `#` comment line; README, "Printing the settings", lists the keys. Values
// read as the options take them (degrees, WxH, colours in 0..1, memory in M), positions and clip
// planes exact to the float, so that a line passed back as its option gives the same image.
class ConfigText {
public:
    explicit ConfigText(const char* command);  // the comment line names the command
    void add(const std::string& key, const std::string& value);
    const std::string& str() const { return text_; }

private:
    std::string text_;
};

// Everything after the command's own lines: image, camera, lights, loading, renderer, worker.
// `camera` is plan_camera's for the loaded scene, or null where a run frames each model it loads
// (thumbs, view): the values that depend on the model then read "per model".
void describe_run(ConfigText& out, const RenderPlan& plan, const Camera* camera, const Renderer& renderer,
                  const WorkerLimits& limits, bool isolated);

// The default scene, or the model at `path`; warnings go to stderr prefixed with `command`.
Result<Scene> load_scene(const std::string& path, const RenderPlan& plan, const char* command);

// `facet view`'s arguments. The `facet` binary declares and parses them like the other subcommands
// (so `facet --help`, `facet view --help` and usage errors are its own), then replaces itself with
// the viewer executable (run_viewer_executable), which parses the same command line again. Only the
// viewer links SDL2: `facet render` and `facet thumbs` do not load its dozens of libraries.
struct ViewArgs {
    std::string model;
    bool spin = false;
    RenderOptions options;
};

// `facet view --print-config`, in the `facet` binary: the viewer's initial settings (the camera
// framed per model, as the viewer frames it once loaded). Returns the exit status.
int print_view_config(const ViewArgs& args, bool camera_options_given);

// facet's description in --help, the same in both executables.
extern const char* const k_app_description;

// Adds the `view` subcommand to `app`, with its options unless `with_options` is false (a command
// line that names another subcommand: see main.cpp).
CLI::App* add_view_subcommand(CLI::App& app, ViewArgs& args, bool with_options = true);

// Executes the viewer executable (k_viewer_executable next to the running `facet`, found through
// /proc/self/exe) with facet's own command line `argv`; returns only if that fails, after saying why,
// with k_exit_failed.
constexpr const char* k_viewer_executable = "facet-view";
int run_viewer_executable(char** argv);

// The viewer executable's parsing of that command line, `facet view [MODEL] [options]`, with the
// declarations of add_view_subcommand: fills `args` and `camera_options_given` and returns nothing,
// or returns the exit status when the process is done (--help: 0, a usage error: k_exit_usage,
// reported on stderr). Here so that the viewer's main() does not compile CLI11 again.
std::optional<int> parse_view_command_line(int argc, char** argv, ViewArgs& args, bool& camera_options_given);

// Image comparison (diff_command.cpp): `facet diff` and `facet render --reference`.
// --threshold: "diff=N,pixels=N|P%,ssim=S,psnr=DB", any of them, comma-separated; none: exact.
// diff is the per-channel difference that does not count, pixels how many (or what share) may
// differ by more; given only ssim or psnr, the pixels are not counted (images of other renderers).
Result<CompareThresholds> parse_thresholds(const std::string& spec);
std::string describe_thresholds(const CompareThresholds& thresholds);
// One line: "A vs B: WxH, N of M pixels differ by more than T (largest difference R . G . B . A .),
// PSNR . dB, SSIM .: match" or "...: MISMATCH (why)".
std::string comparison_summary(const std::string& a, const std::string& b, const ImageComparison& c, bool pass,
                               const std::string& why);
// Where a failed reference check writes its difference image: OUT.png -> OUT.diff.png.
std::string diff_image_path(const std::string& output);

struct DiffOptions {
    std::string threshold;
    std::string diff_image;  // empty: none
    bool json = false;
};
int run_diff(const std::string& a, const std::string& b, const DiffOptions& options);

// `facet render --reference REF.png [--threshold ...] [--update-reference]`.
struct ReferenceCheck {
    std::string reference;  // empty: no check
    std::string threshold;
    bool update = false;  // write REF when it is missing or differs, and say so
};
// Before rendering: false (after saying why) when the options cannot work: a bad --threshold, or
// a missing reference without --update-reference.
bool reference_usable(const ReferenceCheck& check, const char* command);
// After the output is written: compares it with the reference; returns the exit status.
int check_reference(const std::string& output, const ReferenceCheck& check);

// `benchmark_frames`: --benchmark N if given; `output_given`, `size_given`: whether -o and --size were.
int run_render(const std::string& model, const std::string& output, const std::string& depth_out,
               std::optional<int> benchmark_frames, const RenderOptions& options, bool camera_options_given,
               const ReferenceCheck& reference, bool output_given, bool size_given);
// `facet thumbs`' options for collections (README, "Collections").
struct CollectionOptions {
    std::string manifest;  // inputs from this manifest instead of the command line ("-": stdin)
    std::string shard;     // "K/N": only the objects of shard K of N
    std::string log;       // the results log to append to
    bool resume = false;   // skip what the log says is done with the same options
    std::string manifest_lines;  // "OFFSET:LINE,...": only these manifest lines (facet.distributed's tasks)
    // "folder": a worker serves objects of one folder; "batch": the next objects of the run, whatever
    // their folders; empty: batch with --manifest, folder otherwise (docs/RELIABILITY.md).
    std::string worker_sharing;
};
int run_thumbs(const std::vector<std::string>& inputs, const std::string& output_dir, const RenderOptions& options,
               const CollectionOptions& collection);

// `facet thumbnail [-s SIZE] INPUT OUTPUT` (thumbnail_command.cpp), a file manager's thumbnailer:
// INPUT a path or a file:// URI, OUTPUT a SIZE x SIZE PNG. Its defaults: thumbs' (anti-aliased,
// grounded) on a transparent background (thumbnailer_options).
RenderOptions thumbnailer_options();
int run_thumbnail(const std::string& input, const std::string& output, int size, const RenderOptions& options);

}  // namespace facet::cli
