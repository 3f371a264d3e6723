// The seeds' "hello triangle": one triangle, a colour per vertex, interpolated across it.
#include <cstdio>

#include "facet/io.hpp"
#include "facet/renderer.hpp"
#include "window.hpp"

namespace {
const char* const k_usage =
    "usage: example_triangle [OUT.png]   writes the triangle to OUT.png (default triangle.png)\n"
    "       example_triangle --window    shows it in a window until it is closed (Esc or Q)\n";
}

int main(int argc, char** argv) {
    using namespace facet;
    const example::CommandLine line = example::parse_command_line(argc, argv, k_usage, 1);
    const bool window = line.window;
    const std::string out = line.arg(0, "triangle.png");

    // Clip-space corners (w = 1, so clip space is NDC) and their colours.
    const Vec4 corners[3] = {{-0.8f, -0.75f, 0.5f, 1}, {0.8f, -0.75f, 0.5f, 1}, {0.0f, 0.85f, 0.5f, 1}};
    const Vec3 colours[3] = {{1, 0.1f, 0.1f}, {0.1f, 1, 0.1f}, {0.1f, 0.2f, 1}};

    const auto shader = make_shader<3>(
        [&](std::uint32_t i, Varyings<3>& out_v) {
            out_v.set(0, colours[i]);
            return corners[i];
        },
        [](const FragmentIn<3>& in) { return Vec4(in.v.vec3(0), 1); });

    Framebuffer target(320, 240);
    target.clear({0.08f, 0.08f, 0.1f, 1});
    Renderer renderer;
    renderer.draw(target, DrawState{}, DrawInput{3, {}}, shader);

    if (window) {
        example::Window w("facet: triangle", 320, 240);
        if (w.ok()) {
            w.show_until_closed(target.to_image());
            return 0;
        }
    }
    if (Status s = write_png(out, target.to_image()); !s) {
        std::fprintf(stderr, "%s\n", s.error().message.c_str());
        return 1;
    }
    std::printf("wrote %s\n", out.c_str());
    return 0;
}
