// The seeds' spinning triangle: a two-sided triangle turning about Y in front of a perspective
// camera, one PNG per frame. Its back face is drawn too, in its own colour.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "facet/camera.hpp"
#include "facet/io.hpp"
#include "facet/renderer.hpp"
#include "window.hpp"

namespace {
const char* const k_usage =
    "usage: example_spinning_triangle [OUT_PREFIX] [FRAMES]   writes FRAMES (default 8) PNGs, OUT_PREFIX_000.png, ...\n"
    "                                                         (default prefix spin)\n"
    "       example_spinning_triangle --window                  spins in a window until it is closed (Esc or Q)\n";
}

int main(int argc, char** argv) {
    using namespace facet;
    const auto [window, prefix, frames] = example::parse_frames_command_line(argc, argv, k_usage, "spin", 8);

    const Vec3 corners[3] = {{-1, -0.8f, 0}, {1, -0.8f, 0}, {0, 1, 0}};
    const Vec3 colours[3] = {{1, 0.2f, 0.2f}, {0.2f, 1, 0.2f}, {0.2f, 0.3f, 1}};

    Framebuffer target(256, 256);
    Renderer renderer;
    TransformChain chain;  // the seeds' Transformation: world changes per frame, the rest is cached
    chain.set_view(look_at_rh({0, 0, 3}, {0, 0, 0}, {0, 1, 0}));
    chain.set_projection(perspective_rh_zo(radians(50), 1.0f, 0.1f, 10.0f));

    DrawState state;
    state.cull = CullMode::none;  // two-sided
    auto render = [&](float angle) {
        chain.set_world(rotate_y(angle));
        const Mat4 clip_from_object = chain.clip_from_object();
        const auto shader = make_shader<3>(
            [&](std::uint32_t i, Varyings<3>& out) {
                out.set(0, colours[i]);
                return clip_from_object * Vec4(corners[i], 1);
            },
            [](const FragmentIn<3>& in) {
                // The back shows the same gradient, darkened and tinted, so the turn reads clearly.
                const Vec3 c = in.v.vec3(0);
                return in.front_facing ? Vec4(c, 1) : Vec4(Vec3{c.y, c.z, c.x} * 0.45f, 1);
            });
        target.clear({0.08f, 0.08f, 0.1f, 1});
        renderer.draw(target, state, DrawInput{3, {}}, shader);
        return target.to_image();
    };

    if (window) {  // one turn every four seconds, until the window is closed
        example::Window w("facet: spinning triangle", 256, 256);
        if (w.ok()) {
            while (w.show(render(2 * k_pi * static_cast<float>(SDL_GetTicks() % 4000) / 4000.0f))) {
            }
            return 0;
        }
    }
    return example::write_frames(prefix, frames, [&](int f) { return render(2 * k_pi * static_cast<float>(f) / static_cast<float>(frames)); });
}
