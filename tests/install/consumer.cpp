// A program that embeds facet from an installed tree (tests/install/check-installed-tree builds it
// twice: through find_package and through pkg-config). It renders the default scene as `facet
// render --size 400x300` does, so its image must equal tests/golden/data/default_lit.png.
#include <facet/io.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>

#include <cstdio>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUT.png\n", argv[0]);
        return 2;
    }
    constexpr int width = 400, height = 300;
    facet::Renderer renderer;
    facet::Framebuffer target(width, height);
    const facet::Scene scene = facet::default_scene();
    const facet::Camera camera = facet::default_scene_camera(static_cast<float>(width) / height);
    facet::render_scene(renderer, target, scene, camera, facet::RenderSettings{});
    if (const facet::Status s = facet::write_png(argv[1], target.to_image()); !s) {
        std::fprintf(stderr, "%s\n", s.error().message.c_str());
        return 1;
    }
    return 0;
}
