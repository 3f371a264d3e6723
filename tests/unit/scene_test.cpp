// Scenes: shading names, the automatic framing rule, render_scene.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>

#include "facet/scene.hpp"

namespace {

using namespace facet;

// A material of one colour (GCC's -Wextra warns about designated initializers that leave members out).
Material material(Vec4 colour, AlphaMode alpha_mode = AlphaMode::opaque, bool double_sided = true) {
    Material m;
    m.base_colour = colour;
    m.alpha_mode = alpha_mode;
    m.double_sided = double_sided;
    return m;
}

TEST(Scene, ShadingNamesRoundTrip) {
    for (Shading s : {Shading::lit, Shading::lambert, Shading::flat, Shading::normals, Shading::mask,
                      Shading::vertex_color}) {
        Shading parsed;
        ASSERT_TRUE(parse_shading(to_string(s), parsed)) << to_string(s);
        EXPECT_EQ(parsed, s);
    }
    Shading unused;
    EXPECT_FALSE(parse_shading("phong", unused));
    EXPECT_FALSE(parse_shading("", unused));
}

TEST(Scene, FramingFollowsTheDocumentedRule) {
    Scene scene;
    Mesh m;
    m.positions = {{1, 2, 3}, {5, 2, 3}, {1, 4, 3}, {1, 2, 9}};
    m.indices = {0, 1, 2, 0, 2, 3};
    scene.objects.push_back({m, translate({1, 0, 0}), Material{}});
    const float fovy = radians(45), aspect = 0.5f, az = radians(30), el = radians(20);
    const Camera c = frame_scene(scene, az, el, fovy, aspect);

    const Vec3 centre{4, 3, 6};  // centre of the world-space box [2,6] x [2,4] x [3,9]
    const float r = std::sqrt(2.0f * 2 + 1 + 9);  // farthest vertex (2,2,3) or (2,2,9): |(-2,-1,-3)|
    const float fovx = 2 * std::atan(std::tan(fovy / 2) * aspect);
    const float dist = r / std::sin(std::min(fovy, fovx) / 2);
    EXPECT_NEAR(c.target.x, centre.x, 1e-5f);
    EXPECT_NEAR(c.target.y, centre.y, 1e-5f);
    EXPECT_NEAR(c.target.z, centre.z, 1e-5f);
    const Vec3 expected_eye = centre + Vec3{std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az)} * dist;
    EXPECT_NEAR(length(c.position - expected_eye), 0.0f, 1e-4f);
    EXPECT_NEAR(c.near, std::max(dist - 1.5f * r, 0.01f * r), 1e-4f);
    EXPECT_NEAR(c.far, dist + 1.5f * r, 1e-4f);
    EXPECT_FLOAT_EQ(c.fovy, fovy);
}

// The bounds and the radius that framing reads are those of transform_point(model, p), bit for bit,
// also when the model is the identity (which is not multiplied out): -0 there is +0, and a position
// that is not finite is passed over.
TEST(Scene, BoundsAndRadiusOfTheIdentityAreTransformPointsBits) {
    Mesh m;
    m.positions = {{-0.0f, 1e-30f, -3.5f}, {-2.25f, -0.0f, 1e30f}, {-1e-38f, 7.0f, -0.0f},
                   {std::nanf(""), 0, 0}, {1, INFINITY, 1}, {-0.0f, -0.0f, -0.0f}};
    m.indices = {0, 1, 2, 3, 4, 5};
    Scene scene;
    scene.objects.push_back({m, Mat4::identity(), Material{}});
    Aabb want;
    for (const Vec3& p : m.positions)
        if (is_finite(p)) want.extend(transform_point(Mat4::identity(), p));
    const Aabb got = scene.bounds();
    const Vec3 centre = want.centre();
    float want_r = 0;
    for (const Vec3& p : m.positions)
        if (is_finite(p)) want_r = std::max(want_r, length(transform_point(Mat4::identity(), p) - centre));
    for (int axis = 0; axis < 3; ++axis) {
        EXPECT_EQ(std::bit_cast<std::uint32_t>(got.min[axis]), std::bit_cast<std::uint32_t>(want.min[axis])) << axis;
        EXPECT_EQ(std::bit_cast<std::uint32_t>(got.max[axis]), std::bit_cast<std::uint32_t>(want.max[axis])) << axis;
    }
    EXPECT_FALSE(std::signbit(got.max.x));  // the largest x is a -0, +0 after the transform
    EXPECT_EQ(std::bit_cast<std::uint32_t>(scene.radius_about(centre)), std::bit_cast<std::uint32_t>(want_r));
}

// Bounds and radius take an identity object's positions four at a time: the same bits as one at a
// time, whatever the count (the last 0-3 alone), where the special values fall among the four, and
// with objects of other models between (the first one's a -0 that the identity's +0 replaces).
TEST(Scene, BoundsAndRadiusFourAtATimeAreOneAtATimesBits) {
    std::mt19937 rng(2611);
    const float special[] = {-0.0f, 0.0f, 1e30f, -1e30f, 3e38f, std::nanf(""), INFINITY, -INFINITY, 1e-40f};
    std::uniform_real_distribution<float> coordinate(-100.0f, 100.0f);
    std::uniform_int_distribution<int> pick(0, 11);
    for (std::size_t n : {0u, 1u, 3u, 4u, 5u, 7u, 8u, 9u, 13u, 1001u}) {
        Scene scene;
        // x' = -1 * 0 + 0 * -0 + 0 * -0 + -0 = -0: the running bounds hold a -0 before the identity's +0s.
        Mat4 flip = scale(Vec3{-1, 1, 1});
        flip(0, 3) = -0.0f;
        Mesh zero;
        zero.positions = {{0.0f, -0.0f, -0.0f}};
        ASSERT_TRUE(std::signbit(transform_point(flip, zero.positions[0]).x));
        scene.objects.push_back({zero, flip, Material{}});
        if (n == 5) {  // the identity's smallest x a 0, which replaces the running -0 (a +0 after it)
            Mesh ties;
            ties.positions = {{3, 1, 1}, {-0.0f, 2, 2}, {4, 3, 3}, {0.0f, 1, 1}, {2, 2, 2}};
            scene.objects.push_back({ties, Mat4::identity(), Material{}});
        }
        for (int object = 0; object < 3; ++object) {
            Mesh m;
            for (std::size_t k = 0; n != 5 && k < n + static_cast<std::size_t>(object); ++k) {
                Vec3 p;
                for (int axis = 0; axis < 3; ++axis) {
                    const int s = pick(rng);
                    p[static_cast<std::size_t>(axis)] = s < 9 && pick(rng) == 0 ? special[s] : coordinate(rng);
                }
                m.positions.push_back(p);
            }
            const Mat4 model = object == 1 ? translate({1.5f, -2, 0.25f}) : Mat4::identity();
            scene.objects.push_back({m, model, Material{}});
        }
        Aabb want;
        for (const SceneObject& o : scene.objects)
            for (const Vec3& p : o.mesh.positions)
                if (is_finite(p)) want.extend(transform_point(o.model, p));
        const Aabb got = scene.bounds();
        for (int axis = 0; axis < 3; ++axis) {
            EXPECT_EQ(std::bit_cast<std::uint32_t>(got.min[axis]), std::bit_cast<std::uint32_t>(want.min[axis])) << n;
            EXPECT_EQ(std::bit_cast<std::uint32_t>(got.max[axis]), std::bit_cast<std::uint32_t>(want.max[axis])) << n;
        }
        const Vec3 centre = want.empty() ? Vec3{} : want.centre();
        float want_r2 = 0;
        for (const SceneObject& o : scene.objects)
            for (const Vec3& p : o.mesh.positions)
                if (is_finite(p)) want_r2 = std::max(want_r2, dot(transform_point(o.model, p) - centre, transform_point(o.model, p) - centre));
        EXPECT_EQ(std::bit_cast<std::uint32_t>(scene.radius_about(centre)), std::bit_cast<std::uint32_t>(std::sqrt(want_r2))) << n;
    }
}

TEST(Scene, FramingAnEmptySceneIsFinite) {
    const Camera c = frame_scene(Scene{}, 0, 0, radians(45), 1);
    EXPECT_TRUE(is_finite(c.position));
    EXPECT_GT(c.far, c.near);
    EXPECT_GT(c.near, 0.0f);
}

TEST(Scene, FramedModelFillsTheViewWithoutTouchingTheBorder) {
    Scene scene;
    scene.objects.push_back({make_icosphere(3.0f, 3), translate({10, -4, 2}), Material{}});
    const int w = 200, h = 100;
    const Camera camera = frame_scene(scene, radians(45), radians(30), radians(45), float(w) / h);
    Renderer renderer({.threads = 1});
    Framebuffer fb(w, h);
    RenderSettings settings;
    settings.shading = Shading::mask;
    settings.background = {0, 0, 0, 1};
    render_scene(renderer, fb, scene, camera, settings);
    int min_y = h, max_y = -1, min_x = w, max_x = -1;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (fb.colour(x, y).r == 255) min_x = std::min(min_x, x), max_x = std::max(max_x, x),
                                          min_y = std::min(min_y, y), max_y = std::max(max_y, y);
    // The bounding sphere is tangent to the limiting (here: top and bottom) frustum planes, so the
    // sphere model spans the whole height, centred, and stays well inside the wider horizontal field.
    EXPECT_GT(max_y - min_y, h - 4);
    EXPECT_NEAR((min_y + max_y) / 2.0, h / 2.0, 1.0);
    EXPECT_NEAR((min_x + max_x) / 2.0, w / 2.0, 1.0);
    EXPECT_NEAR(max_x - min_x, max_y - min_y, 4);  // a sphere near the axis stays round
}

TEST(Scene, LambertModeIsTheDocumentedFormula) {
    // A quad facing the camera: n = l, so every pixel is 0.8 * (0.15 + 0.85) = 0.8 -> 204.
    Scene scene;
    Mesh quad;
    quad.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    quad.normals.assign(4, {0, 0, 1});
    quad.colours.assign(4, {1, 0, 0, 1});  // ignored by the comparison mode
    quad.indices = {0, 1, 2, 0, 2, 3};
    scene.objects.push_back({quad, Mat4::identity(), material({0, 1, 0, 1})});
    Camera camera;
    camera.position = {0, 0, 3};
    Renderer renderer;
    Framebuffer fb(64, 64);
    RenderSettings settings;
    settings.shading = Shading::lambert;
    render_scene(renderer, fb, scene, camera, settings);
    const Rgba8 c = fb.colour(32, 32);
    EXPECT_EQ(c, (Rgba8{204, 204, 204, 255}));
    // A normal at 60 degrees from l: 0.8 * (0.15 + 0.85 * 0.5) = 0.46 -> 117.
    scene.objects[0].mesh.normals.assign(4, {std::sin(radians(60)), 0, std::cos(radians(60))});
    render_scene(renderer, fb, scene, camera, settings);
    EXPECT_EQ(fb.colour(32, 32).g, 117);
}

TEST(Scene, DefaultSceneRendersSomethingInEveryMode) {
    const Scene scene = default_scene();
    EXPECT_GT(scene.triangle_count(), 1000u);
    Renderer renderer;
    Framebuffer fb(160, 120);
    for (Shading s : {Shading::lit, Shading::lambert, Shading::flat, Shading::normals, Shading::mask,
                      Shading::vertex_color}) {
        RenderSettings settings;
        settings.shading = s;
        settings.background = {0, 0, 0, 1};
        const DrawStats stats = render_scene(renderer, fb, scene, default_scene_camera(160.0f / 120), settings);
        EXPECT_EQ(stats.triangles_in, scene.triangle_count());
        EXPECT_EQ(stats.triangles_invalid, 0u);
        int covered = 0;
        for (int y = 0; y < 120; ++y)
            for (int x = 0; x < 160; ++x) covered += fb.colour(x, y) != Rgba8{0, 0, 0, 255};
        EXPECT_GT(covered, 160 * 120 / 3) << to_string(s);
    }
}

}  // namespace

namespace {

TEST(Scene, ResolveSupersampledAveragesColourAndKeepsTheNearestDepth) {
    facet::Framebuffer fb(4, 2);
    fb.clear({0, 0, 0, 1}, 1.0f);
    // Block (0,0): samples 255, 0, 0, 0 in red -> (255 + 2) / 4 = 64 with rounding; depths 0.5 and 1.
    fb.colour_data()[0] = {255, 0, 0, 255};
    fb.depth_data()[1] = 0.5f;
    // Block (1,0): all four white, depth 0.25 in one sample.
    for (int i : {2, 3, 6, 7}) fb.colour_data()[i] = {255, 255, 255, 255};
    fb.depth_data()[7] = 0.25f;
    facet::Image img;
    std::vector<float> depth;
    facet::resolve_supersampled(fb, 2, img, &depth);
    ASSERT_EQ(img.width, 2);
    ASSERT_EQ(img.height, 1);
    EXPECT_EQ(img.at(0, 0), (facet::Rgba8{64, 0, 0, 255}));
    EXPECT_EQ(img.at(1, 0), (facet::Rgba8{255, 255, 255, 255}));
    EXPECT_EQ(depth[0], 0.5f);
    EXPECT_EQ(depth[1], 0.25f);
    // Factor 1 is an exact copy.
    facet::resolve_supersampled(fb, 1, img, &depth);
    ASSERT_EQ(img.width, 4);
    EXPECT_TRUE(img.pixels == fb.to_image().pixels);
    EXPECT_EQ(depth[7], 0.25f);
}

}  // namespace

namespace {

using namespace facet;

// A quad facing +Z at depth z, covering [-s, s]^2, with uvs and normals.
Mesh quad_at(float z, float s) {
    Mesh q;
    q.positions = {{-s, -s, z}, {s, -s, z}, {s, s, z}, {-s, s, z}};
    q.normals.assign(4, {0, 0, 1});
    q.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    q.indices = {0, 1, 2, 0, 2, 3};
    return q;
}

Rgba8 centre_pixel_with(const Scene& scene, Shading shading) {
    Camera camera;
    camera.position = {0, 0, 5};
    Renderer renderer({.threads = 1});
    Framebuffer fb(32, 32);
    RenderSettings settings;
    settings.shading = shading;
    settings.background = {0, 0, 0, 1};
    render_scene(renderer, fb, scene, camera, settings);
    return fb.colour(16, 16);
}

TEST(SceneMaterials, BlendedObjectsAreDrawnFarthestFirstWhateverTheFileOrder) {
    // Unlit texture mode: colour = material colour exactly, so blending is easy to predict.
    const Material red_half = material({1, 0, 0, 0.5f}, AlphaMode::blend);
    const Material blue_half = material({0, 0, 1, 0.5f}, AlphaMode::blend);
    Scene scene;
    scene.objects.push_back({quad_at(0.5f, 1), Mat4::identity(), red_half});   // near, listed first
    scene.objects.push_back({quad_at(-0.5f, 1), Mat4::identity(), blue_half});  // far
    // Far blue over black: (0, 0, 0.5); then near red: (0.5, 0, 0.25).
    const Rgba8 c = centre_pixel_with(scene, Shading::texture);
    EXPECT_EQ(c.r, 128);
    EXPECT_EQ(c.g, 0);
    EXPECT_EQ(c.b, 64);
}

TEST(SceneMaterials, BlendedObjectsDoNotHideWhatIsBehindThem) {
    Scene scene;
    // A blended quad in front, listed before an opaque one behind it: the opaque one is drawn
    // first, and the blended one neither writes depth nor hides it.
    scene.objects.push_back({quad_at(0.5f, 1), Mat4::identity(), material({1, 1, 1, 0.25f}, AlphaMode::blend)});
    scene.objects.push_back({quad_at(-0.5f, 1), Mat4::identity(), material({0, 1, 0, 1})});
    const Rgba8 c = centre_pixel_with(scene, Shading::texture);
    EXPECT_EQ(c.r, 64);   // 0.25 * 1
    EXPECT_EQ(c.g, 255);  // 0.25 * 1 + 0.75 * 1
    EXPECT_EQ(c.b, 64);
}

TEST(SceneMaterials, MaskedTexturesCutOutBelowTheCutoff) {
    // A 2x1 texture: left texel opaque white, right texel alpha 0.2. With bilinear filtering off
    // (nearest) the quad's right half is cut out and shows the red quad behind it.
    Image texels{2, 1, {{255, 255, 255, 255}, {255, 255, 255, 51}}};
    Material masked = material({1, 1, 1, 1}, AlphaMode::mask);
    masked.base_colour_texture = std::make_shared<const Texture>(std::move(texels));
    masked.sampler = {Wrap::clamp, Wrap::clamp, Filter::nearest};
    masked.alpha_cutoff = 0.5f;
    Scene scene;
    scene.objects.push_back({quad_at(0.5f, 1), Mat4::identity(), masked});
    scene.objects.push_back({quad_at(-0.5f, 2), Mat4::identity(), material({1, 0, 0, 1})});
    Camera camera;
    camera.position = {0, 0, 5};
    Renderer renderer({.threads = 1});
    Framebuffer fb(64, 64);
    RenderSettings settings;
    settings.shading = Shading::texture;
    settings.background = {0, 0, 0, 1};
    render_scene(renderer, fb, scene, camera, settings);
    EXPECT_EQ(fb.colour(26, 32), (Rgba8{255, 255, 255, 255}));  // left half of the front quad
    EXPECT_EQ(fb.colour(38, 32), (Rgba8{255, 0, 0, 255}));      // right half: cut out, red shows
    // Opaque materials ignore alpha entirely.
    scene.objects[0].material.alpha_mode = AlphaMode::opaque;
    render_scene(renderer, fb, scene, camera, settings);
    EXPECT_EQ(fb.colour(38, 32).g, 255);
}

TEST(SceneMaterials, SingleSidedMaterialsAreCulledFromBehind) {
    Scene scene;
    Mesh back_facing = quad_at(0, 1);
    std::swap(back_facing.indices[1], back_facing.indices[2]);
    std::swap(back_facing.indices[4], back_facing.indices[5]);
    scene.objects.push_back({back_facing, Mat4::identity(), material({0, 1, 0, 1}, AlphaMode::opaque, false)});
    EXPECT_EQ(centre_pixel_with(scene, Shading::texture), (Rgba8{0, 0, 0, 255}));
    scene.objects[0].material.double_sided = true;
    EXPECT_EQ(centre_pixel_with(scene, Shading::texture), (Rgba8{0, 255, 0, 255}));
}

}  // namespace
