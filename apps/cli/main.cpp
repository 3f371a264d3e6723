// facet command line: `facet render` draws a scene to a PNG with no display and no GPU.
// Model-file loading arrives with the render issue; today the built-in default scene is rendered.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <string>

#include "facet/io.hpp"
#include "facet/scene.hpp"

namespace {

struct RenderOptions {
    std::string output = "facet.png";
    std::string size = "800x600";
    std::string shading = "lit";
    int threads = 0;
    bool use_default_camera = true;
    float azimuth = 35, elevation = 28, fov = 45;
};

bool parse_size(const std::string& s, int& w, int& h) {
    int n = 0;
    if (std::sscanf(s.c_str(), "%dx%d%n", &w, &h, &n) != 2 || n != static_cast<int>(s.size())) return false;
    return w >= 1 && h >= 1 && w <= facet::k_max_target_size && h <= facet::k_max_target_size;
}

int run_render(const RenderOptions& o) {
    int width = 0, height = 0;
    if (!parse_size(o.size, width, height)) {
        std::fprintf(stderr, "facet render: --size must be WxH with 1..%d pixels per side, got '%s'\n",
                     facet::k_max_target_size, o.size.c_str());
        return 2;
    }
    facet::Shading shading;
    if (!facet::parse_shading(o.shading, shading)) {
        std::fprintf(stderr, "facet render: unknown --shading '%s'\n", o.shading.c_str());
        return 2;
    }
    const facet::Scene scene = facet::default_scene();
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    facet::Camera camera = o.use_default_camera
                               ? facet::default_scene_camera(aspect)
                               : facet::frame_scene(scene, facet::radians(o.azimuth), facet::radians(o.elevation),
                                                    facet::radians(o.fov), aspect);
    facet::Renderer renderer({.threads = o.threads});
    facet::Framebuffer target(width, height);
    facet::RenderSettings settings;
    settings.shading = shading;
    const auto start = std::chrono::steady_clock::now();
    const facet::DrawStats stats = facet::render_scene(renderer, target, scene, camera, settings);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (facet::Status s = facet::write_png(o.output, target.to_image()); !s) {
        std::fprintf(stderr, "facet render: %s\n", s.error().message.c_str());
        return 1;
    }
    std::fprintf(stderr, "facet render: %s (%dx%d, %llu triangles, %.1f ms, %d threads)\n", o.output.c_str(), width,
                 height, static_cast<unsigned long long>(stats.triangles_in), ms, renderer.threads());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"facet: a software 3D renderer. Turns triangles into pixels on the CPU, no GPU needed."};
    app.require_subcommand(1);
    RenderOptions o;
    CLI::App* render = app.add_subcommand("render", "Render the built-in default scene to a PNG");
    render->add_option("-o,--output", o.output, "Output PNG file")->capture_default_str();
    render->add_option("--size", o.size, "Image size WxH")->capture_default_str();
    render->add_option("--shading", o.shading, "lit|lambert|flat|normals|mask|vertex-color")->capture_default_str();
    render->add_option("--threads", o.threads, "Worker threads (0: all cores)")->capture_default_str();
    auto* az = render->add_option("--azimuth", o.azimuth, "Orbit azimuth in degrees (automatic framing)");
    auto* el = render->add_option("--elevation", o.elevation, "Orbit elevation in degrees (automatic framing)");
    render->add_option("--fov", o.fov, "Vertical field of view in degrees")->capture_default_str();
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    o.use_default_camera = az->count() == 0 && el->count() == 0;
    try {
        if (render->parsed()) return run_render(o);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "facet: %s\n", e.what());
        return 1;
    }
    return 0;
}
