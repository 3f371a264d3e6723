// facet view's parts that need no window: the bitmap font, the overlay, the wireframe pass, the
// frame renderer and screenshot names.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "facet/io.hpp"
#include "facet/scene.hpp"
#include "font.hpp"
#include "overlay.hpp"
#include "screenshot.hpp"
#include "view_renderer.hpp"

namespace {

using namespace facet;
using namespace facet::viewer;
namespace fs = std::filesystem;

Image blank(int w, int h, Rgba8 c) { return Image{w, h, std::vector<Rgba8>(static_cast<std::size_t>(w) * h, c)}; }

std::size_t count(const Image& img, Rgba8 c) {
    std::size_t n = 0;
    for (Rgba8 p : img.pixels) n += p == c;
    return n;
}

// ---- font ----

TEST(ViewerFont, EveryPrintableGlyphIsItsOwn) {
    std::set<GlyphRows> seen;
    for (char c = 33; c < 127; ++c) {
        const GlyphRows& g = glyph(c);
        int lit = 0;
        for (std::uint8_t row : g) {
            EXPECT_EQ(row & ~0x1f, 0) << c;  // five columns
            for (int b = 0; b < 5; ++b) lit += row >> b & 1;
        }
        EXPECT_GT(lit, 0) << "glyph '" << c << "' is empty";
        EXPECT_TRUE(seen.insert(g).second) << "glyph '" << c << "' looks like another one";
    }
    for (std::uint8_t row : glyph(' ')) EXPECT_EQ(row, 0);
    // Outside printable ASCII: the box, which is none of the printable glyphs.
    EXPECT_EQ(glyph('\n'), glyph('\x7f'));
    EXPECT_EQ(glyph('\n'), glyph(static_cast<char>(0xe9)));
    EXPECT_EQ(seen.count(glyph('\n')), 0u);
}

TEST(ViewerFont, OnlyDescendersUseTheRowBelowTheBaseline) {
    std::string below;
    for (char c = 32; c < 127; ++c)
        if (glyph(c)[k_glyph_height - 1]) below += c;
    EXPECT_EQ(below, ",;_gjpqy");
}

TEST(ViewerFont, DrawsTextInItsColourAndClips) {
    EXPECT_EQ(text_width("", 1), 0);
    EXPECT_EQ(text_width("a", 1), 5);
    EXPECT_EQ(text_width("abc", 1), 17);
    EXPECT_EQ(text_width("abc", 2), 34);
    const Rgba8 bg{10, 20, 30, 255}, ink{250, 240, 230, 255};
    Image img = blank(40, 12, bg);
    draw_text(img, 1, 1, "H", ink);
    // 'H': two full columns and a bar: 7 + 7 + 3 pixels.
    EXPECT_EQ(count(img, ink), 17u);
    EXPECT_EQ(img.at(1, 1), ink);
    EXPECT_EQ(img.at(2, 1), bg);
    EXPECT_EQ(img.at(5, 7), ink);
    EXPECT_EQ(img.at(3, 4), ink);  // the bar
    Image big = blank(40, 20, bg);
    draw_text(big, 0, 0, "H", ink, 2);
    EXPECT_EQ(count(big, ink), 4 * 17u);
    // Partly or wholly outside: clipped, no crash.
    Image clip = blank(8, 8, bg);
    draw_text(clip, -3, -2, "WWW", ink);
    draw_text(clip, 100, 100, "x", ink);
    draw_text(clip, 6, 6, "#", ink, 3);
    EXPECT_GT(count(clip, ink), 0u);
}

TEST(ViewerFont, BlendsWithStraightAlpha) {
    const Rgba8 dst{0, 0, 0, 255}, src{200, 100, 50, 128};
    EXPECT_EQ(blend_over(dst, Rgba8{1, 2, 3, 255}), (Rgba8{1, 2, 3, 255}));
    EXPECT_EQ(blend_over(dst, Rgba8{1, 2, 3, 0}), dst);
    const Rgba8 half = blend_over(dst, src);
    EXPECT_NEAR(half.r, 100, 1);
    EXPECT_NEAR(half.g, 50, 1);
    EXPECT_NEAR(half.b, 25, 1);
    EXPECT_EQ(half.a, 255);
    // Over a transparent pixel, the colour is the source's and the alpha too.
    EXPECT_EQ(blend_over(Rgba8{9, 9, 9, 0}, src), src);
    Image img = blank(4, 4, dst);
    blend_rect(img, 1, 1, 10, 2, src);
    EXPECT_EQ(img.at(0, 0), dst);
    EXPECT_EQ(img.at(1, 1), half);
    EXPECT_EQ(img.at(3, 2), half);
    EXPECT_EQ(img.at(3, 3), dst);
}

// ---- overlay ----

std::string joined(const std::vector<OverlayLine>& lines) {
    std::string s;
    for (const OverlayLine& l : lines) s += l.text + "\n";
    return s;
}

TEST(ViewerOverlay, ShowsRateTimeTrianglesResolutionAndKeys) {
    OverlayInfo info;
    info.model = "bunny.ply";
    info.triangles = 69451;
    info.fps = 59.94;
    info.frame_ms = 12.345;
    info.width = 800;
    info.height = 600;
    info.render_width = 800;
    info.render_height = 600;
    info.threads = 2;
    const std::string text = joined(overlay_lines(info, 80));
    for (const char* s : {"bunny.ply", "69451 triangles", "59.9 fps", "12.3 ms", "800x600", "ssaa 1", "2 threads",
                          "lit", "wire off", "cull off", "spin off", "up y", "persp", "L-drag orbit", "R-drag pan",
                          "wheel zoom", "F fit", "R reset", "1-7 views", "U up axis", "M shading", "W wire", "C cull",
                          "Space spin", "A ssaa", "S screenshot", "H hide", "Q quit"})
        EXPECT_NE(text.find(s), std::string::npos) << s << " missing from\n" << text;
    EXPECT_EQ(text.find("(800x600)"), std::string::npos);

    info.fps = 0;
    info.render_width = 400;
    info.render_height = 300;
    info.toggles.wireframe = true;
    info.toggles.shading = Shading::normals;
    info.loading = true;
    const std::string busy = joined(overlay_lines(info, 80));
    for (const char* s : {"-- fps", "800x600 (400x300)", "normals", "wire on", "loading..."})
        EXPECT_NE(busy.find(s), std::string::npos) << s << " missing from\n" << busy;

    // A point cloud is spoken of by its points, a wireframe by its segments, not as "0 triangles".
    info.loading = false;
    info.triangles = 0, info.points = 20000;
    EXPECT_NE(joined(overlay_lines(info, 80)).find("bunny.ply  20000 points\n"), std::string::npos);
    info.triangles = 12, info.segments = 30;
    EXPECT_NE(joined(overlay_lines(info, 80)).find("bunny.ply  12 triangles, 20000 points, 30 segments"), std::string::npos);
}

TEST(ViewerOverlay, WrapsMessagesAndKeepsLinesWithinTheColumns) {
    OverlayInfo info;
    info.model = "x.obj";
    info.message = "x.obj: line 3: this is a rather long error message that must wrap onto more lines";
    info.message_is_error = true;
    const auto lines = overlay_lines(info, 30);
    ASSERT_GT(lines.size(), 8u);
    for (const OverlayLine& l : lines) EXPECT_LE(l.text.size(), 30u) << l.text;
    EXPECT_EQ(lines.back().colour, k_overlay_error_text);
    EXPECT_EQ(lines.front().colour, k_overlay_text);
    std::string message;
    for (std::size_t i = 7; i < lines.size(); ++i) message += (i > 7 ? " " : "") + lines[i].text;
    EXPECT_EQ(message, info.message);
}

TEST(ViewerOverlay, RendersATranslucentBoxWithOpaqueText) {
    const std::vector<OverlayLine> lines = {{"Hello", k_overlay_text}, {"wide line of text", k_overlay_error_text}};
    const Image img = render_overlay(lines, 1);
    EXPECT_EQ(img.width, text_width("wide line of text", 1) + 2 * k_overlay_padding);
    EXPECT_EQ(img.height, 2 * k_overlay_padding + k_line_height + k_glyph_height);
    EXPECT_EQ(img.at(0, 0), k_overlay_box);
    EXPECT_EQ(img.at(img.width - 1, img.height - 1), k_overlay_box);
    EXPECT_GT(count(img, k_overlay_text), 20u);
    EXPECT_GT(count(img, k_overlay_error_text), 40u);
    EXPECT_EQ(count(img, k_overlay_text) + count(img, k_overlay_error_text) + count(img, k_overlay_box), img.pixels.size());
    const Image twice = render_overlay(lines, 2);
    EXPECT_EQ(twice.width, 2 * img.width);
    EXPECT_EQ(count(twice, k_overlay_text), 4 * count(img, k_overlay_text));
}

// ---- wireframe and frames ----

Scene quad_scene(float z, float half, Vec4 colour) {
    Mesh m;
    m.positions = {{-half, -half, z}, {half, -half, z}, {half, half, z}, {-half, half, z}};
    m.normals.assign(4, Vec3{0, 0, 1});
    m.indices = {0, 1, 2, 0, 2, 3};
    Material material;
    material.base_colour = colour;
    Scene s;
    s.objects.push_back({m, Mat4::identity(), material});
    return s;
}

ViewState looking_down_z(const Scene& scene, int w, int h) {
    ViewState s;
    s.set_viewport(w, h);
    s.set_scene_bounds(scene);
    s.set_initial(Orbit{{0, 0, 0}, 0, 0, 4});
    return s;
}

TEST(ViewerWireframe, DrawsVisibleEdgesOnly) {
    const int w = 96, h = 96;
    Scene front = quad_scene(0, 1, {0.9f, 0.9f, 0.9f, 1});
    ViewState state = looking_down_z(front, w, h);
    state.toggles().shading = Shading::vertex_color;  // flat colour: any change is the wire
    ViewRenderer r({.threads = 2});
    r.render(front, state, RenderSettings{}, w, h, 1);
    const Image plain = r.image();
    state.toggles().wireframe = true;
    r.render(front, state, RenderSettings{}, w, h, 1);
    const Image wired = r.image();
    ASSERT_EQ(wired.pixels.size(), plain.pixels.size());
    std::size_t changed = 0, darker = 0;
    for (std::size_t i = 0; i < plain.pixels.size(); ++i)
        if (!(plain.pixels[i] == wired.pixels[i])) {
            ++changed;
            darker += wired.pixels[i].r < plain.pixels[i].r;
        }
    // The quad's outline and its diagonal, about two pixels wide, and nothing else.
    EXPECT_GT(changed, 200u);
    EXPECT_LT(changed, plain.pixels.size() / 4);
    EXPECT_EQ(darker, changed);
    // The centre of the quad is on its diagonal (x = y): drawn; a point off both is not.
    EXPECT_FALSE(plain.at(w / 2, h / 2) == wired.at(w / 2, h / 2));
    EXPECT_TRUE(plain.at(w / 2 + 12, h / 2 - 2) == wired.at(w / 2 + 12, h / 2 - 2));

    // A triangle hidden behind the quad adds no edges: the picture is the same byte for byte.
    Scene both = front;
    Scene hidden = quad_scene(-1, 0.5f, {0.2f, 0.9f, 0.2f, 1});
    both.objects.push_back(hidden.objects[0]);
    r.render(both, state, RenderSettings{}, w, h, 1);
    EXPECT_TRUE(r.image().pixels == wired.pixels);
    // ... but in front, it does.
    Scene front_small = quad_scene(0.5f, 0.5f, {0.2f, 0.9f, 0.2f, 1});
    Scene over = front;
    over.objects.push_back(front_small.objects[0]);
    r.render(over, state, RenderSettings{}, w, h, 1);
    const Image with_small_wired = r.image();
    state.toggles().wireframe = false;
    r.render(over, state, RenderSettings{}, w, h, 1);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < with_small_wired.pixels.size(); ++i) differ += !(with_small_wired.pixels[i] == r.image().pixels[i]);
    EXPECT_GT(differ, changed);
}

TEST(ViewerFrame, RendersAtTheAskedSizeWithTheStateSettings) {
    const Scene scene = default_scene();
    ViewState state;
    state.set_viewport(120, 90);
    init_view(state, scene, ViewSpec{}, true);
    ViewRenderer r({.threads = 2});
    r.render(scene, state, RenderSettings{}, 120, 90, 2);
    EXPECT_EQ(r.image().width, 120);
    EXPECT_EQ(r.image().height, 90);
    // The same frame as render_scene at 240x180 resolved by 2, i.e. what `facet render --ssaa 2` does.
    Renderer reference({.threads = 1});
    Framebuffer target(240, 180);
    render_scene(reference, target, scene, state.camera(120.0f / 90.0f), RenderSettings{});
    Image expected;
    resolve_supersampled(target, 2, expected, nullptr);
    EXPECT_TRUE(r.image().pixels == expected.pixels);
    // Half size, as while dragging.
    r.render(scene, state, RenderSettings{}, 60, 45, 1);
    EXPECT_EQ(r.image().width, 60);
    // Toggles reach the settings.
    state.toggles().shading = Shading::normals;
    state.toggles().cull_back = true;
    RenderSettings base;
    base.background = {1, 0, 0, 1};
    const RenderSettings s = ViewRenderer::settings_for(state, base);
    EXPECT_EQ(s.shading, Shading::normals);
    EXPECT_EQ(s.cull, CullMode::back);
    EXPECT_EQ(s.background, (Vec4{1, 0, 0, 1}));
}

// ---- screenshots ----

TEST(ViewerScreenshot, NamesDoNotCollide) {
    const fs::path dir = fs::temp_directory_path() / "facet_viewer_screenshot_test";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string model = (dir / "bunny.ply").string();
    Result<std::string> first = next_screenshot_path(model);
    ASSERT_TRUE(first.ok());
    EXPECT_EQ(*first, (dir / "bunny.screenshot-001.png").string());
    std::ofstream(*first) << "taken";
    EXPECT_EQ(next_screenshot_path(model).value(), (dir / "bunny.screenshot-002.png").string());

    const Image img = blank(7, 5, Rgba8{1, 2, 3, 255});
    Result<std::string> saved = save_screenshot(img, model);
    ASSERT_TRUE(saved.ok()) << saved.error().message;
    EXPECT_EQ(*saved, (dir / "bunny.screenshot-002.png").string());
    Result<Image> back = read_png(*saved);
    ASSERT_TRUE(back.ok());
    EXPECT_TRUE(back->pixels == img.pixels);
    EXPECT_EQ(next_screenshot_path(model).value(), (dir / "bunny.screenshot-003.png").string());
    // The default scene: the current directory.
    EXPECT_EQ(next_screenshot_path("").value(), "facet.screenshot-001.png");
    // Unwritable: an error naming the file.
    Result<std::string> bad = save_screenshot(img, "/nonexistent-facet-dir/m.obj");
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("/nonexistent-facet-dir/m.screenshot-001.png"), std::string::npos);
    fs::remove_all(dir);
}

}  // namespace
