// A rotating cube lit per pixel by a directional light (Blinn-Phong), one PNG per frame.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "facet/camera.hpp"
#include "facet/io.hpp"
#include "facet/renderer.hpp"
#include "facet/shaders.hpp"
#include "window.hpp"

namespace {
const char* const k_usage =
    "usage: example_lit_cube [OUT_PREFIX] [FRAMES]   writes FRAMES (default 4) PNGs, OUT_PREFIX_000.png, ...\n"
    "                                                (default prefix cube)\n"
    "       example_lit_cube --window                  turns in a window until it is closed (Esc or Q)\n";
}

int main(int argc, char** argv) {
    using namespace facet;
    const auto [window, prefix, frames] = example::parse_frames_command_line(argc, argv, k_usage, "cube", 4);

    const Mesh cube = make_cube(0.8f);
    Camera camera;
    camera.position = {0, 1.2f, 4};
    camera.target = {0, 0, 0};
    Framebuffer target(320, 240);
    const Mat4 clip_from_world = camera.projection(320.0f / 240.0f) * camera.view();
    Renderer renderer;

    // Frame f turns the cube by 0.5 f radians about its vertical axis.
    auto render = [&](float f) {
        shaders::BlinnPhong shader{MeshArrays::of(cube), {}};
        ShadingUniforms& u = shader.u;
        u.model = yaw_pitch_roll(0.6f + 0.5f * f, 0.4f, 0.1f);
        u.clip_from_object = clip_from_world * u.model;
        u.normal_to_world = normal_matrix(u.model);
        u.eye = camera.position;
        u.key = {normalize(Vec3{-0.5f, 1.0f, 0.8f}), {1, 1, 1}};
        u.fill = {normalize(Vec3{1.0f, 0.1f, 0.6f}), {0.3f, 0.3f, 0.36f}};
        u.specular = 0.5f;
        target.clear({0.1f, 0.1f, 0.12f, 1});
        renderer.draw(target, DrawState{}, DrawInput{static_cast<std::uint32_t>(cube.positions.size()), cube.indices},
                      shader);
        return target.to_image();
    };

    if (window) {  // two frames' turn per second, until the window is closed
        example::Window w("facet: lit cube", 320, 240);
        if (w.ok()) {
            while (w.show(render(static_cast<float>(SDL_GetTicks()) / 500.0f))) {
            }
            return 0;
        }
    }
    return example::write_frames(prefix, frames, [&](int f) { return render(static_cast<float>(f)); });
}
