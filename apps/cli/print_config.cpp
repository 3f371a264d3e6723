// facet command line: --print-config, the settings a run resolves to as `key = value` lines. It
// reads the objects the run itself renders with (the plan, the camera, the Renderer, the worker
// limits), so what it prints is what the run uses; it does not resolve anything itself.
#include <cinttypes>
#include <cstdio>
#include <optional>

#include "facet/isa.hpp"
#include "options.hpp"

namespace facet::cli {
namespace {

std::string number(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

// Angles, colours and factors as a user types them; positions exact (9 digits round-trip a float).
std::string short_number(double v) { return number("%g", v); }
std::string exact(float v) { return number("%.9g", v); }
std::string exact(Vec3 v) { return exact(v.x) + "," + exact(v.y) + "," + exact(v.z); }
std::string short_vec(Vec3 v) { return short_number(v.x) + "," + short_number(v.y) + "," + short_number(v.z); }
std::string count(std::uint64_t n) { return std::to_string(n); }

// --max-memory's syntax: MiB with an M, or KiB with a K when not a whole number of MiB.
std::string memory_size(std::uint64_t bytes) {
    if (bytes == 0) return "0";
    if (bytes % (1 << 20) == 0) return std::to_string(bytes >> 20) + "M";
    return std::to_string((bytes + 1023) >> 10) + "K";
}

const char* cull_name(CullMode c) {
    switch (c) {
    case CullMode::none: return "none";
    case CullMode::back: return "back";
    case CullMode::front: return "front";
    }
    return "?";
}

void describe_camera(ConfigText& out, const RenderPlan& plan, const Camera* camera) {
    const ViewSpec& v = plan.view;
    const char* per_model = "per model";
    // The default scene's designed view needs no scene: known before anything is loaded.
    std::optional<Camera> designed;
    if (!camera && plan.use_default_scene_camera) camera = &designed.emplace(plan_camera(Scene{}, plan));
    if (plan.use_default_scene_camera) {
        out.add("camera", "default-scene");  // the default scene's designed view
    } else {
        out.add("camera", v.eye ? "eye" : "orbit");
        if (!v.eye) {
            out.add("azimuth", short_number(degrees(v.azimuth)));
            out.add("elevation", short_number(degrees(v.elevation)));
        }
    }
    const bool ortho = camera ? camera->projection_kind == ProjectionKind::orthographic : v.orthographic;
    out.add("projection", ortho ? "orthographic" : "perspective");
    out.add("fov", short_number(degrees(camera ? camera->fovy : v.fovy)));
    if (ortho) out.add("ortho-height", camera ? exact(camera->ortho_height) : per_model);
    out.add("eye", camera ? exact(camera->position) : v.eye ? exact(*v.eye) : per_model);
    out.add("target", camera ? exact(camera->target) : v.target ? exact(*v.target) : per_model);
    out.add("up", camera ? exact(camera->up) : exact(v.up));
    out.add("near", camera ? exact(camera->near) : v.near ? exact(*v.near) : per_model);
    out.add("far", camera ? exact(camera->far) : v.far ? exact(*v.far) : per_model);
}

void describe_lighting(ConfigText& out, const RenderPlan& plan) {
    const RenderSettings& s = plan.settings;
    switch (s.shading) {
    case Shading::lit:
        out.add("environment", plan.environment_file.empty() ? "studio" : plan.environment_file);
        out.add("exposure", short_number(s.exposure));
        out.add("tone-mapping", to_string(s.tone_mapping));
        out.add("contact-shadow", short_number(plan.contact_shadow));
        return;
    case Shading::flat: {
        const Lighting& l = s.lighting;
        out.add("light.key.direction", short_vec(l.key.direction));
        out.add("light.key.colour", short_vec(l.key.colour));
        out.add("light.fill.direction", short_vec(l.fill.direction));
        out.add("light.fill.colour", short_vec(l.fill.colour));
        out.add("light.ambient", short_number(l.ambient));
        out.add("light.diffuse", short_number(l.diffuse));
        return;
    }
    case Shading::lambert:
        out.add("light.key.direction", "0,0,1");  // at the eye
        out.add("light.key.colour", "1,1,1");
        out.add("light.ambient", short_number(defaults::k_lambert_ambient));
        out.add("light.diffuse", short_number(defaults::k_lambert_diffuse));
        out.add("albedo", short_number(defaults::k_lambert_albedo));
        return;
    case Shading::normals:
    case Shading::mask:
    case Shading::vertex_color:
    case Shading::texture:
        break;
    }
    out.add("light", "none");  // unlit
}

}  // namespace

ConfigText::ConfigText(const char* command) {
    text_ = std::string("# facet ") + FACET_VERSION + " " + command +
            ": the settings of this run, every default resolved (README: Printing the settings)\n";
}

void ConfigText::add(const std::string& key, const std::string& value) { text_ += key + " = " + value + "\n"; }

void describe_run(ConfigText& out, const RenderPlan& plan, const Camera* camera, const Renderer& renderer,
                  const WorkerLimits& limits, bool isolated) {
    out.add("size", size_text(plan.width, plan.height));
    out.add("ssaa", std::to_string(plan.ssaa));
    out.add("aa", std::to_string(plan.aa));
    out.add("shading", to_string(plan.settings.shading));
    const Vec4 bg = plan.settings.background;
    out.add("background", short_vec(bg.xyz()) + "," + short_number(bg.w));
    // none: only single-sided materials are culled (back faces); lambert never culls.
    const CullMode cull = plan.settings.shading == Shading::lambert ? CullMode::none : plan.settings.cull;
    out.add("cull", cull == CullMode::none && plan.settings.shading != Shading::lambert ? "single-sided"
                                                                                       : cull_name(cull));
    const PrimitiveStyle& style = plan.settings.primitives;
    const float ssaa = static_cast<float>(plan.ssaa);
    out.add("point-size", plan.settings.point_size_in_model_units ? short_number(style.point_size) + " model units"
                                                                  : short_number(style.point_size / ssaa));
    out.add("point-shape", style.point_shape == PointShape::square ? "square" : "round");
    out.add("line-width", short_number(style.line_width / ssaa));
    out.add("line-aa", style.line_aa ? "on" : "off");
    describe_camera(out, plan, camera);
    describe_lighting(out, plan);
    if (plan.views) {  // --views, --passes
        const ViewsPlan& v = *plan.views;
        out.add("passes", to_string(v.passes));
        out.add("views", v.rig.empty() ? "1 (the camera above)" : v.rig + " (" + std::to_string(v.views.size()) + " views)");
        out.add("float-format", to_string(v.float_format));
        out.add("normal-space", v.normal_space == NormalSpace::camera ? "camera" : "world");
        if (v.float_format == FloatFormat::png)
            out.add("depth-scale", v.depth_scale ? exact(*v.depth_scale) : "(the farthest far plane / 65535)");
    }

    const LoadOptions& load = plan.load;
    out.add("up-axis", load.up_axis == UpAxis::z ? "z" : "y");
    out.add("crease-angle", short_number(load.crease_angle_degrees));
    out.add("max-triangles", count(load.max_triangles));
    out.add("max-texture-size", std::to_string(load.texture_limits.max_size));
    out.add("max-texture-pixels", count(load.texture_limits.max_pixels));
    out.add("max-file-bytes", count(load.max_file_bytes));
    out.add("max-scene-bytes", count(load.max_scene_bytes));
    out.add("load-threads", std::to_string(resolve_threads(load.threads)));
    std::string dirs;
    for (const std::string& d : load.resource_dirs) dirs += (dirs.empty() ? "" : ", ") + d;
    out.add("resource-dirs", dirs.empty() ? "(only the model's folder)" : dirs);

    out.add("threads", std::to_string(renderer.threads()));
    out.add("isa", active_isa());
    out.add("tile-size", std::to_string(renderer.tile_size()));
    out.add("batch-triangles", count(renderer.batch_triangles()));

    out.add("isolation", isolated ? "worker-process" : "none");
    out.add("sandbox", describe_sandbox(isolated));
    out.add("timeout", isolated ? short_number(limits.timeout_seconds) : "0");
    out.add("max-memory", isolated ? memory_size(limits.max_memory_bytes) : "0");
}

int print_view_config(const ViewArgs& args, bool camera_options_given) {
    Result<RenderPlan> plan = make_plan(args.options, camera_options_given || !args.model.empty());
    if (!plan) {
        std::fprintf(stderr, "facet view: %s\n", plan.error().message.c_str());
        return k_exit_usage;
    }
    ConfigText out("view");
    out.add("model", args.model.empty() ? "(the built-in default scene)" : args.model);
    out.add("spin", args.spin ? "on" : "off");
    const Renderer renderer({.threads = args.options.threads});  // as the viewer's
    describe_run(out, *plan, nullptr, renderer, WorkerLimits{}, false);
    std::fputs(out.str().c_str(), stdout);
    return k_exit_ok;
}

}  // namespace facet::cli
