// facet command line: parsing and validating render options, and rendering by them; the `view`
// subcommand and the hand-over to the viewer executable.
#include "options.hpp"

#include <CLI/CLI.hpp>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <span>
#include <sstream>
#include <system_error>
#include <tuple>

#include "add_option.hpp"
#include "facet/isa.hpp"
#include "views_output.hpp"

namespace facet::cli {
namespace {

Error usage(const std::string& message) { return Error{ErrorCode::invalid_argument, message}; }

// The ISAs this CPU runs, best first: "avx512, avx2, sse4, scalar".
std::string isa_list() {
    std::string out;
    for (const std::string& name : available_isas()) out += (out.empty() ? "" : ", ") + name;
    return out;
}

bool parse_size(const std::string& s, int& w, int& h) {
    int n = 0;
    if (std::sscanf(s.c_str(), "%dx%d%n", &w, &h, &n) != 2 || n != static_cast<int>(s.size())) return false;
    return w >= 1 && h >= 1;
}

// "x,y,z" (or with `count` = 4 an optional fourth value) into floats; all must be finite.
bool parse_floats(const std::string& s, int min_count, int max_count, float* out, int& count) {
    std::stringstream in(s);
    std::string item;
    count = 0;
    while (std::getline(in, item, ',')) {
        if (count == max_count) return false;
        char* end = nullptr;
        const float v = std::strtof(item.c_str(), &end);
        if (item.empty() || *end != '\0' || !std::isfinite(v)) return false;
        out[count++] = v;
    }
    return count >= min_count;
}

Result<Vec3> parse_vec3(const std::string& option, const std::string& value) {
    float v[3];
    int n = 0;
    if (!parse_floats(value, 3, 3, v, n)) return usage(option + " must be X,Y,Z with finite numbers, got '" + value + "'");
    return Vec3{v[0], v[1], v[2]};
}

Result<Vec4> parse_background(const std::string& value) {
    if (value == "transparent") return Vec4{0, 0, 0, 0};
    float v[4] = {0, 0, 0, 1};
    int n = 0;
    if (!parse_floats(value, 3, 4, v, n))
        return usage("--background must be R,G,B[,A] (0..1 or 0..255) or 'transparent', got '" + value + "'");
    // The colour channels share a scale: 0..255 when any of them is above 1 ("255,128,0"), else
    // 0..1. Alpha has its own, so that "255,0,0,1" is opaque red rather than alpha 1/255, and
    // "255,0,0,128" half-transparent.
    const bool colour_bytes = v[0] > 1 || v[1] > 1 || v[2] > 1;
    const bool alpha_bytes = n == 4 && v[3] > 1;
    for (int i = 0; i < n; ++i) {
        if (i < 3 ? colour_bytes : alpha_bytes) v[i] /= 255.0f;
        if (v[i] < 0 || v[i] > 1) return usage("--background values must lie in 0..1 or 0..255, got '" + value + "'");
    }
    return Vec4{v[0], v[1], v[2], v[3]};
}

}  // namespace

std::string size_text(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

RenderOptions thumbnail_options() {
    RenderOptions o;
    o.size = std::to_string(defaults::k_thumbnail_size);
    o.azimuth = defaults::k_thumbnail_azimuth_degrees;
    o.elevation = defaults::k_thumbnail_elevation_degrees;
    o.aa = defaults::k_thumbnail_aa;
    o.contact_shadow = defaults::k_thumbnail_contact_shadow;
    return o;
}

void add_render_options(CLI::App& c, RenderOptions& o) {
    // An empty value would read as "not given" below; a script passing --eye "$EYE" with EYE unset
    // should hear about it instead of getting the automatic camera.
    const CLI::Validator non_empty([](std::string& v) { return v.empty() ? std::string("must not be empty") : std::string(); },
                                   "");
    add_option(c, "--size", o.size, "Image size WxH")->capture_default_str();
    add_option(c, "--azimuth", o.azimuth, "Orbit azimuth in degrees, about +Y from +Z toward +X")->capture_default_str();
    add_option(c, "--elevation", o.elevation, "Orbit elevation in degrees above the XZ plane")->capture_default_str();
    add_option(c, "--fov", o.fov, "Vertical field of view in degrees")->capture_default_str();
    add_option(c, "--eye", o.eye, "Explicit camera position X,Y,Z (replaces automatic framing)")->check(non_empty);
    add_option(c, "--target", o.target, "Point the explicit camera looks at X,Y,Z (default: model centre)")->check(non_empty);
    add_option(c, "--up", o.up, "Camera up vector X,Y,Z (default 0,1,0)")->check(non_empty);
    add_option(c, "--near", o.near, "Near clip plane distance");
    add_option(c, "--far", o.far, "Far clip plane distance");
    add_option(c, "--up-axis", o.up_axis, "Which model axis is up: y or z (CAD and STL files are often Z-up)")
        ->check(CLI::IsMember({"y", "z"}))
        ->capture_default_str();
    add_flag(c, "--ortho", o.ortho, "Orthographic projection");
    add_option(c, "--shading", o.shading, "lit | lambert | flat | normals | mask | vertex-color | texture")
        ->capture_default_str();
    add_option(c, "--background", o.background, "R,G,B[,A]: R,G,B in 0..1, or 0..255 if any is above 1; A in 0..1, or 0..255 if above 1; or 'transparent'")->check(non_empty);
    add_option(c, "--ssaa", o.ssaa, "Anti-aliasing by NxN supersampling (1..8)")->capture_default_str();
    add_option(c, "--aa", o.aa,
               "Anti-aliasing by N jittered frames averaged (1, 2, 4 or 8; MSAA's sample positions), N times a frame's cost")
        ->capture_default_str();
    add_option(c, "--contact-shadow", o.contact_shadow,
               "Lit mode: opacity (0..1) of a soft shadow on the ground under the model; 0: none")
        ->capture_default_str();
    add_option(c, "--environment", o.environment,
               "Lit mode: the environment light, a Radiance .hdr image (equirectangular, +Y up; default: the built-in "
               "neutral studio)")
        ->check(non_empty);
    add_option(c, "--exposure", o.exposure, "Lit mode: linear exposure factor applied before tone mapping")
        ->capture_default_str();
    add_option(c, "--tone-mapping", o.tone_mapping, "Lit mode: neutral (Khronos PBR Neutral) | aces | linear (clamp)")
        ->capture_default_str();
    add_option(c, "--threads", o.threads, "Worker threads (0: all cores)")->capture_default_str();
    add_option(c, "--isa", o.isa, "SIMD instruction set: best, or one of " + isa_list() +
               " (same image on every one; lower ones for comparison)")
        ->capture_default_str();
    add_option(c, "--crease-angle", o.crease_angle, "Degrees; computed normals split at sharper edges")
        ->capture_default_str();
    add_option(c, "--point-size", o.point_size, "Points' diameter in pixels of the output image (0 < PX <= 256 / ssaa)")
        ->capture_default_str();
    add_option(c, "--point-world-size", o.point_world_size,
               "Points' diameter in model units instead, perspective-scaled (at most 256 pixels / ssaa)");
    add_option(c, "--point-shape", o.point_shape, "round | square")->check(CLI::IsMember({"round", "square"}))->capture_default_str();
    add_option(c, "--line-width", o.line_width, "Lines' width in pixels of the output image (0 < PX <= 256 / ssaa)")
        ->capture_default_str();
    add_flag(c, "--line-aa", o.line_aa, "Anti-aliased lines: blended by their coverage of each pixel, writing no depth");
    add_option(c, "--max-triangles", o.max_triangles, "Refuse models with more triangles (points and segments count too), before loading them")
        ->capture_default_str();
    add_option(c, "--max-texture-size", o.max_texture_size,
               "Largest texture side in pixels (and at most N*N, 64 Mpixels by default); larger ones are not used")
        ->capture_default_str();
    add_option(c, "--resource-dir", o.resource_dirs,
               "A folder whose files models may read besides their own folder (textures, MTL files, glTF buffers); "
               "repeatable. References elsewhere are refused with a warning")
        ->expected(1)
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    add_flag(c, "--print-config", o.print_config,
             "Print the settings this run would use, every default resolved, as 'key = value' lines, and exit "
             "without rendering");
}

void add_views_options(CLI::App& c, RenderOptions& o) {
    add_option(c, "--passes", o.passes,
               "Render passes to write, comma-separated: color, alpha, depth, range, normal, instance, material, "
               "primitive, uv (-o is then a folder)");
    add_option(c, "--views", o.views,
               "Camera rig: orbit:N[:ELEVATION], sphere:N, random:N:SEED or file:CAMERAS.json (-o is then a folder)");
    add_option(c, "--float-format", o.float_format,
               "How depth, range, normal and uv are written: npy (float32 .npy files), exr (one OpenEXR file per "
               "view with every pass but color) or png (16-bit depth and range, 8-bit normals, 16-bit uv)")
        ->check(CLI::IsMember({"npy", "exr", "png"}))
        ->capture_default_str();
    add_option(c, "--normal-space", o.normal_space, "Space of the normal pass: world, or camera (x right, y up, z toward the viewer)")
        ->check(CLI::IsMember({"world", "camera"}))
        ->capture_default_str();
    add_option(c, "--depth-scale", o.depth_scale,
               "--float-format png: model units per step of the 16-bit depth and range (default: the farthest far "
               "plane / 65535)");
}

const char* to_string(FloatFormat f) {
    switch (f) {
        case FloatFormat::npy: return "npy";
        case FloatFormat::exr: return "exr";
        case FloatFormat::png: return "png";
    }
    return "?";
}

void add_worker_options(CLI::App& c, RenderOptions& o, bool in_process_option) {
    add_option(c, "--timeout", o.timeout,
               "Seconds one file may take (load, render, write) before it is abandoned; 0: no limit")
        ->capture_default_str();
    add_option(c, "--max-memory", o.max_memory,
               "Memory cap of the worker process loading and rendering a file: MiB, or N followed by K, M or G; "
               "0: no limit (default: 3/4 of the physical memory, shared among thumbs' workers)");
    if (in_process_option)
        add_flag(c, "--no-isolation", o.no_isolation,
                 "Load and render in this process instead of a worker process (for debuggers; a file that crashes "
                 "the model reader then crashes facet, and --timeout and --max-memory do not apply)");
}

Result<WorkerLimits> make_worker_limits(const RenderOptions& o, unsigned workers) {
    constexpr std::uint64_t k_min_memory = defaults::k_min_memory_bytes;
    WorkerLimits limits;
    if (!(o.timeout >= 0 && std::isfinite(o.timeout))) return usage("--timeout must be 0 (no limit) or a number of seconds");
    limits.timeout_seconds = o.timeout;
    if (o.max_memory.empty()) {
        const std::uint64_t all = default_max_memory_bytes();  // 0: unknown, no cap
        limits.max_memory_bytes = all == 0 ? 0 : std::max(all / std::max(workers, 1u), k_min_memory);
    } else {
        const std::optional<std::uint64_t> bytes = parse_memory_size(o.max_memory);
        if (!bytes || (*bytes != 0 && *bytes < k_min_memory))
            return usage("--max-memory must be 0 (no limit) or at least 64 MiB, as MiB or with K, M or G, got '" +
                         o.max_memory + "'");
        limits.max_memory_bytes = *bytes;
    }
    if (!memory_cap_supported()) limits.max_memory_bytes = 0;
    return limits;
}

bool has_camera_options(const CLI::App& c) {
    for (const char* name : {"--azimuth", "--elevation", "--eye", "--target", "--fov", "--ortho", "--near", "--far", "--up"})
        if (c.count(name) > 0) return true;
    return false;
}

Result<std::pair<int, int>> parse_image_size(const std::string& name, const std::string& text, int ssaa, bool square) {
    int w = 0, h = 0;
    const std::string wxh = square && text.find('x') == std::string::npos ? text + "x" + text : text;
    if (!parse_size(wxh, w, h))
        return usage(name + (square ? " must be N or WxH, each at least 1, got '" : " must be WxH, each at least 1, got '") +
                     text + "'");
    if (static_cast<long>(w) * ssaa > k_max_target_size || static_cast<long>(h) * ssaa > k_max_target_size)
        return usage(name + " times --ssaa must stay within " + std::to_string(k_max_target_size) + " pixels per side");
    return std::pair{w, h};
}

Status make_views_plan(const RenderOptions& o, bool size_given, RenderPlan& p) {
    const bool wanted = o.passes || o.views;
    if (!wanted) {
        if (o.float_format != "npy" || o.normal_space != "world" || o.depth_scale)
            return usage("--float-format, --normal-space and --depth-scale go with --passes or --views");
        return Ok{};
    }
    ViewsPlan v;
    if (o.passes) {
        Result<PassSet> passes = parse_passes(*o.passes);
        if (!passes) return usage("--passes: " + passes.error().message);
        v.passes = *passes;
    }
    v.float_format = o.float_format == "exr" ? FloatFormat::exr : o.float_format == "png" ? FloatFormat::png : FloatFormat::npy;
    v.normal_space = o.normal_space == "camera" ? NormalSpace::camera : NormalSpace::world;
    if (o.depth_scale && !(*o.depth_scale > 0 && std::isfinite(*o.depth_scale)))
        return usage("--depth-scale must be a positive number of model units");
    if (o.depth_scale && v.float_format != FloatFormat::png) return usage("--depth-scale goes with --float-format png");
    v.depth_scale = o.depth_scale;
    if (o.ortho)
        return usage("--views and --passes need a perspective camera (their cameras are written in OpenCV's pinhole "
                     "model): leave out --ortho");
    if (o.views) {
        Result<RigViews> rig = parse_views(*o.views, p.view);
        if (!rig) return usage("--views: " + rig.error().message);
        v.views = std::move(rig->views);
        v.rig = *o.views;
        if (rig->width > 0 && !size_given) {
            Result<std::pair<int, int>> size = parse_image_size("the cameras file's size",
                                                                 size_text(rig->width, rig->height), o.ssaa, false);
            if (!size) return size.error();
            std::tie(p.width, p.height) = *size;
        }
    }
    p.views = std::move(v);
    return Ok{};
}

namespace {

std::string general_number(float v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", static_cast<double>(v));
    return text;
}

}  // namespace

Result<RenderPlan> make_plan(const RenderOptions& o, bool camera_options_given, bool size_given) {
    RenderPlan p;
    if (o.ssaa < 1 || o.ssaa > 8) return usage("--ssaa must be 1..8, got " + std::to_string(o.ssaa));
    p.ssaa = o.ssaa;
    if (antialias_offsets(o.aa).empty()) return usage("--aa must be 1, 2, 4 or 8, got " + std::to_string(o.aa));
    p.aa = o.aa;
    Result<std::pair<int, int>> size = parse_image_size("--size", o.size, o.ssaa, false);
    if (!size) return size.error();
    std::tie(p.width, p.height) = *size;
    if (o.threads < 0) return usage("--threads must be 0 (all cores) or more");
    // Process-wide, and inherited by worker processes.
    if (!select_isa(o.isa)) return usage("--isa must be best or one of " + isa_list() + " on this CPU, got '" + o.isa + "'");
    if (!(o.fov > 0 && o.fov < 180)) return usage("--fov must be between 0 and 180 degrees");
    if (!parse_shading(o.shading, p.settings.shading)) return usage("unknown --shading '" + o.shading + "'");
    if (!(o.contact_shadow >= 0 && o.contact_shadow <= 1)) return usage("--contact-shadow must be 0..1");
    p.contact_shadow = p.settings.shading == Shading::lit ? o.contact_shadow : 0.0f;  // the other modes draw none
    if (!(o.exposure > 0 && std::isfinite(o.exposure))) return usage("--exposure must be a positive number");
    p.settings.exposure = o.exposure;
    if (!parse_tone_mapping(o.tone_mapping, p.settings.tone_mapping))
        return usage("--tone-mapping must be neutral, aces or linear, got '" + o.tone_mapping + "'");
    if (!o.environment.empty()) {
        // Loaded (and prefiltered) once here, before any worker process is forked: thumbs' workers share it.
        Result<std::shared_ptr<const Environment>> e = Environment::load_hdr(o.environment);
        if (!e) return usage("--environment: " + e.error().message);
        p.settings.environment = *e;
        p.environment_file = o.environment;
    }
    if (p.settings.shading == Shading::lit) {
        // Made here, in the process that forks the workers, so that each worker inherits them
        // (the built-in ones are the library's constants; README, "The lit mode").
        if (!p.settings.environment) p.settings.environment = Environment::studio();
        split_sum_table();
    }
    if (!o.background.empty()) {
        Result<Vec4> bg = parse_background(o.background);
        if (!bg) return bg.error();
        p.settings.background = *bg;
    }
    // Sizes are in output pixels: the supersampled target draws them ssaa times larger.
    const float most = PrimitiveStyle::k_max_point_size / static_cast<float>(o.ssaa);
    if (!(o.point_size > 0 && o.point_size <= most))
        return usage("--point-size must be more than 0 and at most 256 / --ssaa pixels, got " + general_number(o.point_size));
    if (!(o.line_width > 0 && o.line_width <= most))
        return usage("--line-width must be more than 0 and at most 256 / --ssaa pixels, got " + general_number(o.line_width));
    if (o.point_world_size && !(*o.point_world_size > 0 && *o.point_world_size < PrimitiveStyle::k_model_point_size_bound))
        return usage("--point-world-size must be more than 0 and less than 1e30 model units, got " +
                     general_number(*o.point_world_size));
    PrimitiveStyle& style = p.settings.primitives;
    style.point_size = (o.point_world_size ? *o.point_world_size : o.point_size) * (o.point_world_size ? 1.0f : static_cast<float>(o.ssaa));
    style.point_shape = o.point_shape == "square" ? PointShape::square : PointShape::round;
    style.line_width = o.line_width * static_cast<float>(o.ssaa);
    style.line_aa = o.line_aa;
    p.settings.point_size_in_model_units = o.point_world_size.has_value();
    p.view.azimuth = radians(o.azimuth);
    p.view.elevation = radians(o.elevation);
    p.view.fovy = radians(o.fov);
    p.view.orthographic = o.ortho;
    if (!o.eye.empty()) {
        Result<Vec3> v = parse_vec3("--eye", o.eye);
        if (!v) return v.error();
        p.view.eye = *v;
    }
    if (!o.target.empty()) {
        Result<Vec3> v = parse_vec3("--target", o.target);
        if (!v) return v.error();
        p.view.target = *v;
    }
    if (!o.up.empty()) {
        Result<Vec3> v = parse_vec3("--up", o.up);
        if (!v) return v.error();
        if (!(length(*v) > 0)) return usage("--up must not be the zero vector");
        p.view.up = *v;
    }
    if (o.near && !(*o.near > 0)) return usage("--near must be positive");
    if (o.far && !(*o.far > (o.near ? *o.near : 0))) return usage("--far must be positive and beyond --near");
    p.view.near = o.near;
    p.view.far = o.far;
    p.load.up_axis = o.up_axis == "z" ? UpAxis::z : UpAxis::y;
    if (!(o.crease_angle >= 0 && o.crease_angle <= 180)) return usage("--crease-angle must be 0..180 degrees");
    p.load.crease_angle_degrees = o.crease_angle;
    if (o.max_triangles < 1) return usage("--max-triangles must be 1 or more");
    if (o.max_texture_size < 1) return usage("--max-texture-size must be 1 or more");
    p.load.max_triangles = static_cast<std::size_t>(o.max_triangles);
    p.load.texture_limits.max_size = o.max_texture_size;
    for (const std::string& dir : o.resource_dirs) {
        std::error_code ec;
        if (!std::filesystem::is_directory(dir, ec)) return usage("--resource-dir '" + dir + "' is not a directory");
    }
    p.load.resource_dirs = o.resource_dirs;
    const auto side = static_cast<std::size_t>(o.max_texture_size);
    p.load.texture_limits.max_pixels = std::min(p.load.texture_limits.max_pixels, side * side);
    p.use_default_scene_camera = !camera_options_given;
    if (Status s = make_views_plan(o, size_given, p); !s) return s.error();
    return p;
}

Camera plan_camera(const Scene& scene, const RenderPlan& plan) {
    const float aspect = static_cast<float>(plan.width) / static_cast<float>(plan.height);
    return plan.use_default_scene_camera ? default_scene_camera(aspect) : make_camera(scene, plan.view, aspect);
}

ViewRequest view_request(const RenderPlan& plan) {
    ViewRequest r;
    r.width = plan.width, r.height = plan.height;
    r.ssaa = plan.ssaa, r.aa = plan.aa;
    r.contact_shadow = plan.contact_shadow;
    r.settings = plan.settings;
    return r;
}

DrawStats render_plan(ViewRenderer& renderer, const Scene& scene, const RenderPlan& plan, const Camera& camera,
                      Image& colour, std::vector<float>* depth) {
    colour.width = plan.width, colour.height = plan.height;
    colour.pixels.resize(static_cast<std::size_t>(plan.width) * static_cast<std::size_t>(plan.height));
    return render_plan(renderer, scene, plan, camera, colour.pixels.data(), depth);
}

DrawStats render_plan(ViewRenderer& renderer, const Scene& scene, const RenderPlan& plan, const Camera& camera,
                      Rgba8* colour, std::vector<float>* depth) {
    if (depth) depth->resize(static_cast<std::size_t>(plan.width) * static_cast<std::size_t>(plan.height));
    PassImages out;
    out.colour = colour;
    out.window_depth = depth ? depth->data() : nullptr;
    ViewRequest request = view_request(plan);
    request.settings.keep_depth = depth != nullptr;  // otherwise only the colour is read
    return renderer.render(scene, {&camera, 1}, request, {&out, 1});
}

Result<Scene> load_scene(const std::string& path, const RenderPlan& plan, const char* command) {
    if (path.empty()) return default_scene();
    Result<LoadedModel> model = load_model(path, plan.load);
    if (!model) return model.error();
    for (const std::string& w : model->warnings) std::fprintf(stderr, "%s: warning: %s\n", command, w.c_str());
    return std::move(model->scene);
}

// `facet view` in the `facet` binary: its options, and the hand-over to the viewer executable
// (apps/viewer), which alone links SDL2. (Here rather than in a file of its own: each file that
// includes CLI11 costs seconds of compile time.)
const char* const k_app_description =
    "facet: a software 3D renderer. Renders model files to PNG on the CPU (no GPU, no display), or shows them in a "
    "window.";

CLI::App* add_view_subcommand(CLI::App& app, ViewArgs& args, bool with_options) {
    CLI::App* view = app.add_subcommand("view", "Open a model (or, with none, the default scene) in an interactive window");
    if (!with_options) return view;
    add_option(*view, "model", args.model, "Model file (or drop one onto the window)");
    add_flag(*view, "--spin", args.spin, "Start with the turntable spinning (Space toggles it)");
    add_render_options(*view, args.options);
    view->get_option("--size")->description("Initial window size WxH");
    view->get_option("--ssaa")->description("Initial supersampling NxN (A toggles 1 and 2)");
    view->remove_option(view->get_option("--aa"));
    view->remove_option(view->get_option("--contact-shadow"));  // the viewer supersamples (A); jittered frames are for still images
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

std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? 0 : k_exit_usage;
    }
    return std::nullopt;
}

std::optional<int> parse_view_command_line(int argc, char** argv, ViewArgs& args, bool& camera_options_given) {
    CLI::App app{k_app_description};
    app.require_subcommand(1);
    CLI::App* view = add_view_subcommand(app, args);
    if (const std::optional<int> done = parse_command_line(app, argc, argv)) return done;
    camera_options_given = has_camera_options(*view);
    return std::nullopt;
}

}  // namespace facet::cli
