// Render passes (facet/passes.hpp, facet/views.hpp) against what they claim, each checked by an
// independent computation: depth back-projected through the exported OpenCV camera lands on the
// analytic surfaces (a finely tessellated sphere, a plane), range is depth through the ray's angle,
// normals are the analytic ones (interpolated) or the face normals (flat), instance ids are the
// nearest of the objects rendered alone, primitive ids are the reference rasterizer's triangle per
// pixel, and every pass is the same bytes for any thread count, tile size, ISA and supersampling.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "facet/isa.hpp"
#include "facet/shaders.hpp"
#include "facet/views.hpp"
#include "support/reference_raster.hpp"

namespace {

using namespace facet;

constexpr Vec3 k_sphere_centre{0.3f, 0.2f, -0.1f};
constexpr float k_sphere_radius = 1.0f;
constexpr float k_plane_y = -1.25f;

SceneObject sphere_object(int slices, int stacks) {
    SceneObject o;
    o.mesh = make_uv_sphere(k_sphere_radius, slices, stacks);
    o.model = translate(k_sphere_centre);
    o.material.base_colour = {0.9f, 0.4f, 0.3f, 1};
    return o;
}

// A 12 x 12 square in the plane y = k_plane_y, facing +Y.
SceneObject plane_object() {
    SceneObject o;
    o.mesh = make_checker_plane(12.0f, 4, {1, 1, 1, 1}, {0.5f, 0.5f, 0.5f, 1});
    o.model = translate({0, k_plane_y, 0});
    return o;
}

Scene sphere_and_plane() {
    Scene s;
    s.objects.push_back(sphere_object(256, 128));
    s.objects.push_back(plane_object());
    return s;
}

// Perspective cameras around the scene, among them OpenCV ones with an off-centre principal point,
// non-square pixels and skew.
std::vector<Camera> test_cameras(int width, int height) {
    std::vector<Camera> cameras;
    Camera a = Camera::orbit({0.2f, 0.0f, 0.0f}, 0.6f, 0.45f, 4.2f);
    a.near = 0.5f, a.far = 20.0f;
    cameras.push_back(a);
    Camera b = Camera::orbit({0.0f, -0.5f, 0.0f}, -2.2f, 0.2f, 3.4f);
    b.fovy = radians(60), b.near = 0.3f, b.far = 30.0f;
    cameras.push_back(b);
    OpenCvCamera cv = *to_opencv(a, width, height);
    cv.cx += 0.17 * width, cv.cy -= 0.09 * height, cv.fy *= 1.1, cv.skew = 0.004 * cv.fx;
    cameras.push_back(Camera::from_opencv(cv, 0.5f, 20.0f));
    return cameras;
}

ViewRequest all_passes(int width, int height) {
    ViewRequest r;
    r.width = width, r.height = height;
    r.passes = PassSet::all();
    return r;
}

std::size_t pixels(const ViewRequest& r) { return static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height); }

// The OpenCV ray of pixel (i, j) per unit depth, (x/z, y/z, 1), by inverting K in double.
struct Ray {
    double x, y;
};
Ray opencv_ray(const OpenCvCamera& c, int i, int j) {
    const double yn = (j - c.cy) / c.fy;
    return {(i - c.cx - c.skew * yn) / c.fx, yn};
}

// The world point at depth d along pixel (i, j)'s ray: R^T (d (x, y, 1) - t).
std::array<double, 3> back_project(const OpenCvCamera& c, int i, int j, double d) {
    const Ray r = opencv_ray(c, i, j);
    const double p[3] = {d * r.x - c.translation[0], d * r.y - c.translation[1], d - c.translation[2]};
    std::array<double, 3> w{};
    for (int k = 0; k < 3; ++k) w[static_cast<std::size_t>(k)] = c.rotation[k] * p[0] + c.rotation[3 + k] * p[1] + c.rotation[6 + k] * p[2];
    return w;
}

// Depth back-projected with the camera's own K and [R|t] lies on the sphere (within its
// tessellation: 256 x 128 facets sit at most r (1 - cos(pi / 128)) = 3e-4 inside it) or on the
// plane, within what snapping the vertices to 1/256 pixel moves a surface at that depth (1/362 of a
// pixel diagonally, d / (362 f) in model units); range is depth times the length of (x/z, y/z, 1);
// and every visible pixel has a depth.
TEST(Passes, DepthBackProjectsOntoTheSurfacesThroughTheExportedCamera) {
    const Scene scene = sphere_and_plane();
    const ViewRequest request = all_passes(320, 240);
    ViewRenderer renderer;
    const std::vector<Camera> cameras = test_cameras(request.width, request.height);
    const std::vector<ViewImages> views = renderer.render(scene, cameras, request);
    for (std::size_t v = 0; v < views.size(); ++v) {
        const ViewImages& img = views[v];
        const OpenCvCamera cv = *to_opencv(cameras[v], request.width, request.height);
        int on_sphere = 0, on_plane = 0;
        double worst_sphere = 0, worst_plane = 0, worst_range = 0;
        for (int j = 0; j < img.height; ++j)
            for (int i = 0; i < img.width; ++i) {
                const std::size_t at = static_cast<std::size_t>(j) * img.width + i;
                const double d = img.depth[at];
                if (img.instance[at] == 0) {
                    ASSERT_TRUE(std::isinf(img.depth[at]) && std::isinf(img.range[at])) << i << "," << j;
                    continue;
                }
                ASSERT_TRUE(std::isfinite(d) && d > 0) << i << "," << j;
                const std::array<double, 3> p = back_project(cv, i, j, d);
                const double snap = d / (362 * std::min(cv.fx, cv.fy)) + 2e-6 * d;  // and float rounding
                if (img.instance[at] == 1) {
                    const double dx = p[0] - k_sphere_centre.x, dy = p[1] - k_sphere_centre.y, dz = p[2] - k_sphere_centre.z;
                    const double off = std::sqrt(dx * dx + dy * dy + dz * dz) - k_sphere_radius;
                    EXPECT_TRUE(off > -3e-4 - snap && off < snap) << "view " << v << " pixel " << i << "," << j << ": " << off;
                    worst_sphere = std::max(worst_sphere, std::fabs(off));
                    ++on_sphere;
                } else {
                    const double off = p[1] - k_plane_y;
                    EXPECT_LT(std::fabs(off), snap) << "view " << v << " pixel " << i << "," << j;
                    worst_plane = std::max(worst_plane, std::fabs(off) / d);
                    ++on_plane;
                }
                const Ray r = opencv_ray(cv, i, j);
                const double range = d * std::sqrt(r.x * r.x + r.y * r.y + 1);
                worst_range = std::max(worst_range, std::fabs(img.range[at] - range) / range);
            }
        EXPECT_GT(on_sphere, 2000) << "view " << v;
        EXPECT_GT(on_plane, 2000) << "view " << v;
        EXPECT_LT(worst_range, 2e-6) << "view " << v;
        RecordProperty("worst_sphere_" + std::to_string(v), std::to_string(worst_sphere));
    }
}

// Interpolated normals of a sphere are its analytic normals at the back-projected point (the
// vertex normals are the vertices' directions from the centre, and interpolation is linear in the
// same barycentrics as the point), within 1e-3; the plane's are +Y; camera space is the view's
// rotation of world space (OpenGL axes: a surface facing the camera has z > 0).
TEST(Passes, NormalsAreTheAnalyticNormalsInWorldAndCameraSpace) {
    const Scene scene = sphere_and_plane();
    ViewRequest request = all_passes(256, 192);
    ViewRenderer renderer;
    const std::vector<Camera> cameras = test_cameras(request.width, request.height);
    const std::vector<ViewImages> world = renderer.render(scene, cameras, request);
    request.normal_space = NormalSpace::camera;
    const std::vector<ViewImages> camera = renderer.render(scene, cameras, request);
    for (std::size_t v = 0; v < world.size(); ++v) {
        const OpenCvCamera cv = *to_opencv(cameras[v], request.width, request.height);
        const Mat4 view = cameras[v].view();
        for (int j = 0; j < request.height; ++j)
            for (int i = 0; i < request.width; ++i) {
                const std::size_t at = static_cast<std::size_t>(j) * request.width + i;
                const std::uint32_t id = world[v].instance[at];
                const Vec3 n = world[v].normal[at];
                if (id == 0) {
                    EXPECT_TRUE(n == Vec3{} && camera[v].normal[at] == Vec3{});
                    continue;
                }
                double expected[3] = {0, 1, 0};
                if (id == 1) {
                    const std::array<double, 3> p = back_project(cv, i, j, world[v].depth[at]);
                    double len = 0;
                    for (int k = 0; k < 3; ++k) {
                        expected[k] = p[static_cast<std::size_t>(k)] - k_sphere_centre[static_cast<std::size_t>(k)];
                        len += expected[k] * expected[k];
                    }
                    for (double& e : expected) e /= std::sqrt(len);
                }
                for (int k = 0; k < 3; ++k)
                    ASSERT_NEAR(n[static_cast<std::size_t>(k)], expected[k], 1e-3) << "view " << v << " pixel " << i << "," << j;
                EXPECT_NEAR(length(n), 1.0f, 1e-6f);
                // Camera space: the view matrix's rotation, in double.
                const Vec3 c = camera[v].normal[at];
                for (int r = 0; r < 3; ++r) {
                    const double e = double{view(r, 0)} * n.x + double{view(r, 1)} * n.y + double{view(r, 2)} * n.z;
                    ASSERT_NEAR(c[static_cast<std::size_t>(r)], e, 1e-6);
                }
            }
    }
}

// Face normals: a mesh without normals gets each triangle's normal, pointing out of its front
// (counter-clockwise) face, and a flat-shaded mesh (split faces, each vertex carrying its face's
// normal) the same; both within 1e-5 of the face normal computed in double from the triangle the
// primitive pass names.
TEST(Passes, FlatScenesGiveTheFaceNormalOfThePrimitive) {
    SceneObject smooth;
    smooth.mesh = make_icosphere(1.0f, 2);
    smooth.model = rotate_y(0.3f) * translate({0.1f, 0, 0});
    SceneObject flat = smooth;
    flat.mesh = split_faces_flat(smooth.mesh);
    SceneObject bare = flat;
    bare.mesh.normals.clear();
    ViewRenderer renderer;
    const ViewRequest request = all_passes(200, 160);
    for (const SceneObject* object : {&flat, &bare}) {
        Scene scene;
        scene.objects.push_back(*object);
        const std::vector<Camera> cameras = test_cameras(request.width, request.height);
        const std::vector<ViewImages> views = renderer.render(scene, cameras, request);
        int seen = 0;
        for (const ViewImages& img : views)
            for (std::size_t at = 0; at < pixels(request); ++at) {
                if (img.primitive[at] == 0) continue;
                const std::uint32_t t = img.primitive[at] - 1;
                const Mesh& m = object->mesh;
                double p[3][3];
                for (int k = 0; k < 3; ++k) {
                    const Vec3 q = transform_point(object->model, m.positions[m.indices[t * 3 + static_cast<std::uint32_t>(k)]]);
                    p[k][0] = q.x, p[k][1] = q.y, p[k][2] = q.z;
                }
                const double e1[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
                const double e2[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
                double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
                const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                for (int k = 0; k < 3; ++k) ASSERT_NEAR(img.normal[at][static_cast<std::size_t>(k)], n[k] / len, 1e-5);
                ++seen;
            }
        EXPECT_GT(seen, 5000);
    }
}

// Each pixel's instance is the object that, rendered alone, covers it and is nearest (where one is
// nearer than the others by a margin: coplanar ties are the depth test's to break), 0 where none
// covers it; the material id is that object's material's.
TEST(Passes, InstanceIsTheNearestObjectThatCoversThePixelAlone) {
    Scene scene;
    scene.objects.push_back(sphere_object(64, 32));
    SceneObject cube;
    cube.mesh = make_cube(0.6f);
    cube.model = translate({0.9f, 0.4f, 0.8f}) * rotate_y(0.5f);
    scene.objects.push_back(cube);
    SceneObject torus;
    torus.mesh = make_torus(0.9f, 0.25f, 48, 16);
    torus.model = translate({-0.3f, 0.1f, 0.3f}) * rotate_x(1.1f);
    torus.material.base_colour = {0.9f, 0.4f, 0.3f, 1};  // the sphere's: the same material id
    scene.objects.push_back(torus);
    scene.objects.push_back(plane_object());
    const ViewRequest request = all_passes(240, 180);
    ViewRenderer renderer;
    const std::vector<Camera> cameras = test_cameras(request.width, request.height);
    const std::vector<ViewImages> together = renderer.render(scene, cameras, request);
    std::vector<std::vector<ViewImages>> alone;
    for (const SceneObject& o : scene.objects) {
        Scene one;
        one.objects.push_back(o);
        alone.push_back(renderer.render(one, cameras, request));
    }
    const std::uint32_t expected_material[] = {1, 2, 1, 2};  // the cube and the plane: the default material
    for (std::size_t v = 0; v < cameras.size(); ++v) {
        int decided = 0;
        for (std::size_t at = 0; at < pixels(request); ++at) {
            float nearest = k_background_depth, second = k_background_depth;
            std::uint32_t which = 0;
            for (std::size_t k = 0; k < alone.size(); ++k) {
                const float d = alone[k][v].depth[at];
                EXPECT_EQ(alone[k][v].instance[at], std::isinf(d) ? 0u : 1u);
                if (d < nearest) second = nearest, nearest = d, which = static_cast<std::uint32_t>(k + 1);
                else if (d < second) second = d;
            }
            if (std::isinf(nearest)) {
                ASSERT_EQ(together[v].instance[at], 0u);
                ++decided;
                continue;
            }
            if (!(second - nearest > 1e-4f * nearest)) continue;  // a tie within depth precision
            ++decided;
            ASSERT_EQ(together[v].instance[at], which) << "view " << v << " pixel " << at;
            ASSERT_EQ(together[v].material[at], which ? expected_material[which - 1] : 0u);
            if (which) {
                ASSERT_EQ(together[v].depth[at], nearest) << "the same surface, the same depth";
            }
        }
        EXPECT_GT(decided, static_cast<int>(pixels(request) * 9 / 10));
    }
}

// Random triangles, each at its own depth, snapped exactly to chosen fixed-point positions: the
// primitive pass at every pixel is the reference rasterizer's nearest covering triangle (+1), or 0.
TEST(Passes, PrimitiveIdsAreTheReferenceRasterizersNearestTriangle) {
    namespace ref = facet_test::raster;
    constexpr int W = 128, H = 96;
    const Rect vp{0, 0, W, H};
    std::mt19937 rng(22);
    std::uniform_int_distribution<std::int64_t> x(-20 * ref::k_sub, (W + 20) * ref::k_sub), y(-20 * ref::k_sub, (H + 20) * ref::k_sub);
    for (int round = 0; round < 6; ++round) {
        const int count = 40 + 30 * round;
        std::vector<ref::Fixed> fixed;
        std::vector<Vec4> clip;
        std::vector<float> depth;
        std::vector<float> depths(static_cast<std::size_t>(count));
        for (int t = 0; t < count; ++t) depths[static_cast<std::size_t>(t)] = (static_cast<float>(t) + 0.5f) / static_cast<float>(count);
        std::shuffle(depths.begin(), depths.end(), rng);
        while (static_cast<int>(fixed.size()) < 3 * count) {
            const ref::Fixed p{x(rng), y(rng)};
            const float z = depths[fixed.size() / 3];
            if (!ref::snaps_exactly(p, vp, z)) continue;
            fixed.push_back(p);
            clip.push_back(ref::clip_from_fixed(p, vp, z));
        }
        const auto shader = make_shader<0>([&](std::uint32_t i, Varyings<0>&) { return clip[i]; },
                                           [](const FragmentIn<0>&) { return Vec4{1, 1, 1, 1}; });
        std::vector<std::uint32_t> primitive(W * H, 7), instance(W * H, 7);
        std::vector<float> pass_depth(W * H);
        DrawPasses passes;
        passes.targets.primitive = primitive.data();
        passes.targets.instance = instance.data();
        passes.targets.depth = pass_depth.data();
        passes.instance = 5;
        Renderer renderer;
        Framebuffer fb(W, H);
        DrawState state;
        state.cull = CullMode::none;
        state.clear = ClearValues{};
        renderer.draw(fb, state, DrawInput{static_cast<std::uint32_t>(clip.size()), {}}, shader, &passes);
        for (int j = 0; j < H; ++j)
            for (int i = 0; i < W; ++i) {
                std::uint32_t expected = 0;
                float nearest = 2;
                for (int t = 0; t < count; ++t) {
                    const ref::Fixed v[3] = {fixed[3 * t], fixed[3 * t + 1], fixed[3 * t + 2]};
                    if (depths[static_cast<std::size_t>(t)] < nearest && ref::covers(v, ref::pixel_centre(i, j)))
                        nearest = depths[static_cast<std::size_t>(t)], expected = static_cast<std::uint32_t>(t + 1);
                }
                const std::size_t at = static_cast<std::size_t>(j) * W + i;
                ASSERT_EQ(primitive[at], expected) << "round " << round << " pixel " << i << "," << j;
                ASSERT_EQ(instance[at], expected ? 5u : 0u);
                if (expected) {
                    ASSERT_EQ(pass_depth[at], 1.0f) << "clip w";
                }
            }
    }
}

// The normal pass is the normal the `normals` shading colours (0.5 + 0.5 n), bit for bit, clipped
// triangles included (the camera is inside the scene's bounds).
TEST(Passes, TheNormalPassIsWhatTheNormalsShadingShows) {
    Scene scene = sphere_and_plane();
    scene.objects[0].mesh = make_uv_sphere(k_sphere_radius, 48, 24);
    ViewRequest request = all_passes(200, 150);
    request.settings.shading = Shading::normals;
    std::vector<Camera> cameras = test_cameras(request.width, request.height);
    Camera close = Camera::orbit(k_sphere_centre, 0.3f, 0.2f, 1.3f);  // the near plane cuts the sphere
    close.near = 0.5f, close.far = 10;
    cameras.push_back(close);
    ViewRenderer renderer;
    const std::vector<ViewImages> views = renderer.render(scene, cameras, request);
    for (std::size_t v = 0; v < views.size(); ++v) {
        int compared = 0;
        for (std::size_t at = 0; at < pixels(request); ++at) {
            if (views[v].instance[at] == 0) continue;
            const Vec3 n = views[v].normal[at];
            const Rgba8 expected = to_rgba8({0.5f + 0.5f * n.x, 0.5f + 0.5f * n.y, 0.5f + 0.5f * n.z, 1});
            ASSERT_EQ(views[v].colour[at], expected) << "view " << v << " pixel " << at;
            ++compared;
        }
        EXPECT_GT(compared, 3000);
    }
}

// A scene with every kind of draw: alpha-masked (the one-pass order), alpha-blended (no depth
// writes: in colour only), without normals (face normals), textured (uvs), clipped by the near plane.
Scene every_kind_of_draw() {
    Scene scene = sphere_and_plane();
    scene.objects[0].mesh = make_uv_sphere(k_sphere_radius, 64, 32);
    Image cut{16, 16, std::vector<Rgba8>(256)};
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 16; ++i) cut.at(i, j) = {200, 120, 40, static_cast<std::uint8_t>((i / 4 + j / 4) % 2 ? 255 : 0)};
    SceneObject masked;
    masked.mesh = make_cube(0.5f);
    masked.model = translate({-1.0f, 0.2f, 0.9f});
    masked.material.base_colour_texture = std::make_shared<const Texture>(std::move(cut));
    masked.material.alpha_mode = AlphaMode::mask;
    scene.objects.push_back(masked);
    SceneObject glass;
    glass.mesh = make_icosphere(0.4f, 2);
    glass.model = translate({1.1f, 0.5f, 1.0f});
    glass.material.base_colour = {0.5f, 0.8f, 1.0f, 0.4f};
    glass.material.alpha_mode = AlphaMode::blend;
    scene.objects.push_back(glass);
    SceneObject bare;
    bare.mesh = make_torus(0.5f, 0.15f, 32, 12);
    bare.mesh.normals.clear();
    bare.model = translate({0.2f, -0.9f, 1.2f});
    scene.objects.push_back(bare);
    return scene;
}

struct AllPasses {
    std::vector<ViewImages> views;
    bool operator==(const AllPasses& o) const {
        if (views.size() != o.views.size()) return false;
        auto same = [](const auto& a, const auto& b) {
            return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0);
        };
        for (std::size_t v = 0; v < views.size(); ++v) {
            const ViewImages &a = views[v], &b = o.views[v];
            if (!same(a.colour, b.colour) || !same(a.alpha, b.alpha) || !same(a.depth, b.depth) || !same(a.range, b.range) ||
                !same(a.normal, b.normal) || !same(a.instance, b.instance) || !same(a.material, b.material) ||
                !same(a.primitive, b.primitive) || !same(a.uv, b.uv))
                return false;
        }
        return true;
    }
};

AllPasses render_all(RendererConfig config, int ssaa = 1) {
    const Scene scene = every_kind_of_draw();
    ViewRequest request = all_passes(190, 130);
    request.ssaa = ssaa;
    std::vector<Camera> cameras = test_cameras(request.width, request.height);
    Camera close = Camera::orbit(k_sphere_centre, 2.6f, 0.1f, 1.25f);
    close.near = 0.4f, close.far = 12;
    cameras.push_back(close);
    ViewRenderer renderer(config);
    AllPasses all{renderer.render(scene, cameras, request)};
    // Normals rotated into camera space, and an orthographic camera (depth from the window depth).
    Camera ortho = cameras[0];
    ortho.projection_kind = ProjectionKind::orthographic;
    ortho.ortho_height = 5;
    cameras.push_back(ortho);
    request.normal_space = NormalSpace::camera;
    for (ViewImages& v : renderer.render(scene, cameras, request)) all.views.push_back(std::move(v));
    return all;
}

TEST(Passes, EveryPassIsTheSameBytesForEveryThreadCountTileSizeAndIsa) {
    const AllPasses reference = render_all({.threads = 1});
    // The scene draws what it claims to: the masked cube's cut-outs, the blended sphere, the torus.
    int masked = 0, torus = 0;
    for (std::size_t at = 0; at < reference.views[0].instance.size(); ++at)
        masked += reference.views[0].instance[at] == 3, torus += reference.views[0].instance[at] == 5;
    EXPECT_GT(masked, 50);
    EXPECT_GT(torus, 50);
    for (int threads : {2, 3})
        for (int tile : {16, 64}) {
            EXPECT_TRUE(render_all({.threads = threads, .tile_size = tile}) == reference) << threads << " threads, tile " << tile;
        }
    std::vector<std::string> isas = available_isas();
    for (const std::string& isa : isas) {
        ASSERT_TRUE(select_isa(isa));
        EXPECT_TRUE(render_all({.threads = 2}) == reference) << isa;
    }
    select_isa("best");
}

// Each pass asked for alone (with colour, or without) is the same bytes as in the set of all.
TEST(Passes, EachPassAloneIsWhatItIsAmongAll) {
    const AllPasses all = render_all({.threads = 2});
    const Scene scene = every_kind_of_draw();
    ViewRequest request = all_passes(190, 130);
    std::vector<Camera> cameras = test_cameras(request.width, request.height);
    ViewRenderer renderer({.threads = 2});
    for (Pass pass : k_all_passes)
        for (bool with_colour : {false, true}) {
            request.passes = PassSet{}.add(pass);
            if (with_colour) request.passes.add(Pass::colour);
            const std::vector<ViewImages> alone = renderer.render(scene, cameras, request);
            AllPasses expected = all;
            expected.views.resize(cameras.size());
            for (std::size_t v = 0; v < cameras.size(); ++v) {
                ViewImages& e = expected.views[v];
                const PassSet p = request.passes;
                if (!p.has(Pass::colour)) e.colour.clear();
                if (!p.has(Pass::alpha)) e.alpha.clear();
                if (!p.has(Pass::depth)) e.depth.clear();
                if (!p.has(Pass::range)) e.range.clear();
                if (!p.has(Pass::normal)) e.normal.clear();
                if (!p.has(Pass::instance)) e.instance.clear();
                if (!p.has(Pass::material)) e.material.clear();
                if (!p.has(Pass::primitive)) e.primitive.clear();
                if (!p.has(Pass::uv)) e.uv.clear();
            }
            EXPECT_TRUE(AllPasses{alone} == expected) << pass_name(pass) << (with_colour ? " with colour" : "");
        }
}

// With supersampling, colour and alpha average the samples; every other pass is the surface at the
// pixel centre, the same bytes as without; alpha is the share of covered samples.
TEST(Passes, SupersamplingLeavesTheSurfacePassesAsTheyAre) {
    const AllPasses one = render_all({.threads = 2}, 1);
    for (int ssaa : {2, 3}) {
        AllPasses many = render_all({.threads = 2}, ssaa);
        bool partial = false;
        for (std::size_t v = 0; v < many.views.size(); ++v) {
            ViewImages& a = many.views[v];
            const ViewImages& b = one.views[v];
            for (std::size_t at = 0; at < a.alpha.size(); ++at) {
                const float covered = a.alpha[at] * static_cast<float>(ssaa * ssaa);
                ASSERT_EQ(covered, std::round(covered));
                partial |= a.alpha[at] > 0 && a.alpha[at] < 1;
                EXPECT_EQ(b.alpha[at], b.instance[at] ? 1.0f : 0.0f);
            }
            // The rest equal once colour and alpha are set aside.
            a.colour = b.colour, a.alpha = b.alpha;
        }
        EXPECT_TRUE(partial) << "edges have partly covered pixels";
        EXPECT_TRUE(many == one) << "ssaa " << ssaa;
    }
}

// With jittered frames (and supersampling), colour is the frames' colours averaged per channel
// (rounded to nearest), each frame a plain render moved by its antialias_offsets offset; alpha is
// the share of covered samples of every frame; every other pass is the surface at the pixel
// centre, the same bytes as with neither.
TEST(Passes, JitteredFramesAverageColourAndAlphaAndLeaveTheSurfacePasses) {
    const Scene scene = every_kind_of_draw();
    const ViewRequest plain = all_passes(64, 48);
    const std::vector<Camera> cameras = test_cameras(plain.width, plain.height);
    ViewRenderer renderer({.threads = 2});
    const std::vector<ViewImages> one = renderer.render(scene, cameras, plain);
    for (const auto& [aa, ssaa] : {std::pair{4, 1}, {2, 2}}) {
        ViewRequest request = plain;
        request.aa = aa, request.ssaa = ssaa;
        std::vector<ViewImages> many = renderer.render(scene, cameras, request);
        ViewRequest frame = plain;
        frame.ssaa = ssaa;
        frame.passes = PassSet{}.add(Pass::colour);
        std::vector<std::vector<int>> sums(cameras.size(), std::vector<int>(pixels(plain) * 4, 0));
        for (Vec2 offset : antialias_offsets(aa)) {
            frame.settings.pixel_offset = {offset.x * static_cast<float>(ssaa), offset.y * static_cast<float>(ssaa)};
            const std::vector<ViewImages> f = renderer.render(scene, cameras, frame);
            for (std::size_t v = 0; v < cameras.size(); ++v)
                for (std::size_t at = 0; at < pixels(plain); ++at) {
                    const Rgba8 c = f[v].colour[at];
                    sums[v][at * 4] += c.r, sums[v][at * 4 + 1] += c.g, sums[v][at * 4 + 2] += c.b, sums[v][at * 4 + 3] += c.a;
                }
        }
        bool partial = false;
        for (std::size_t v = 0; v < cameras.size(); ++v) {
            ViewImages& a = many[v];
            for (std::size_t at = 0; at < pixels(plain); ++at) {
                const Rgba8 c = a.colour[at];
                const int* sum = &sums[v][at * 4];
                auto average = [&](int k) { return (sum[k] + aa / 2) / aa; };
                ASSERT_TRUE(c.r == average(0) && c.g == average(1) && c.b == average(2) && c.a == average(3))
                    << "aa " << aa << ", ssaa " << ssaa << ", view " << v << ", pixel " << at;
                const float covered = a.alpha[at] * static_cast<float>(ssaa * ssaa * aa);
                ASSERT_EQ(covered, std::round(covered));
                partial |= a.alpha[at] > 0 && a.alpha[at] < 1;
            }
            a.colour = one[v].colour, a.alpha = one[v].alpha;
        }
        EXPECT_TRUE(partial) << "edges have partly covered pixels";
        EXPECT_TRUE(AllPasses{many} == AllPasses{one}) << "aa " << aa << ", ssaa " << ssaa;
    }
}

// The contact shadow darkens the ground around the objects seen from above and is in the colour
// only: every other pass is the objects' alone; seen from below it is not drawn.
TEST(Passes, TheContactShadowIsInTheColourOnly) {
    Scene scene;
    scene.objects.push_back(sphere_object(48, 24));
    ViewRequest request = all_passes(64, 48);
    Camera above = Camera::orbit(k_sphere_centre, 0.5f, 0.7f, 5.0f), below = Camera::orbit(k_sphere_centre, 0.5f, -0.7f, 5.0f);
    above.near = below.near = 0.5f, above.far = below.far = 20;
    const Camera cameras[] = {above, below};
    ViewRenderer renderer({.threads = 2});
    for (const auto& [aa, ssaa] : {std::pair{1, 1}, {2, 2}}) {
        request.aa = aa, request.ssaa = ssaa, request.contact_shadow = 0;
        const std::vector<ViewImages> bare = renderer.render(scene, cameras, request);
        request.contact_shadow = 0.8f;
        std::vector<ViewImages> shadowed = renderer.render(scene, cameras, request);
        int darker = 0;
        for (std::size_t at = 0; at < pixels(request); ++at) {
            const Rgba8 a = shadowed[0].colour[at], b = bare[0].colour[at];
            if (a == b) continue;
            EXPECT_LT(bare[0].alpha[at], 1.0f) << "only where the sphere leaves room";
            darker += a.r < b.r && a.g < b.g && a.b < b.b;
        }
        EXPECT_GT(darker, 50) << "aa " << aa;
        EXPECT_TRUE(shadowed[1].colour == bare[1].colour) << "from below";
        shadowed[0].colour = bare[0].colour;
        EXPECT_TRUE(AllPasses{shadowed} == AllPasses{bare}) << "aa " << aa;
    }
    request.settings.shading = Shading::normals;  // the lit mode's alone
    const std::vector<ViewImages> unlit = renderer.render(scene, cameras, request);
    request.contact_shadow = 0;
    EXPECT_TRUE(AllPasses{renderer.render(scene, cameras, request)} == AllPasses{unlit});
}

// The one-pass order (a shader that may discard, here never) lists its pixels' owners as the
// visible-only order does: the same passes.
TEST(Passes, TheOnePassOrderGivesTheSamePassesAsTheVisibleOnlyOrder) {
    const Mesh mesh = make_torus(0.8f, 0.3f, 40, 16);
    Camera camera = Camera::orbit({}, 0.4f, 0.7f, 2.2f);
    camera.near = 0.5f, camera.far = 5;
    constexpr int W = 160, H = 120;
    ShadingUniforms u;
    u.clip_from_object = camera.projection(float{W} / H) * camera.view();
    const MeshArrays arrays = MeshArrays::of(mesh);
    const shaders::Normals visible_only{arrays, u};
    const auto one_pass = make_shader<3>([&](std::uint32_t i, Varyings<3>& out) { return visible_only.vertex(i, out); },
                                         [&](const FragmentIn<3>& in) { return std::optional<Vec4>{visible_only.fragment(in)}; });
    auto passes_of = [&](const auto& shader) {
        std::vector<float> depth(W * H);
        std::vector<Vec3> normal(W * H);
        std::vector<std::uint32_t> primitive(W * H);
        std::vector<Vec2> uv(W * H);
        DrawPasses p;
        p.targets = {.depth = depth.data(), .normal = normal.data(), .primitive = primitive.data(), .uv = uv.data()};
        p.positions = mesh.positions.data(), p.normals = mesh.normals.data(), p.uvs = mesh.uvs.data();
        Renderer renderer({.threads = 2});
        Framebuffer fb(W, H);
        DrawState state;
        state.clear = ClearValues{};
        renderer.draw(fb, state, DrawInput{static_cast<std::uint32_t>(mesh.positions.size()), mesh.indices}, shader, &p);
        return std::make_tuple(depth, normal, primitive, uv, fb.to_image().pixels);
    };
    const auto a = passes_of(visible_only), b = passes_of(one_pass);
    EXPECT_TRUE(std::get<4>(a) == std::get<4>(b)) << "the same colours";
    EXPECT_EQ(std::memcmp(std::get<0>(a).data(), std::get<0>(b).data(), W * H * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(std::get<1>(a).data(), std::get<1>(b).data(), W * H * sizeof(Vec3)), 0);
    EXPECT_TRUE(std::get<2>(a) == std::get<2>(b));
    EXPECT_EQ(std::memcmp(std::get<3>(a).data(), std::get<3>(b).data(), W * H * sizeof(Vec2)), 0);
    int covered = 0;
    for (std::uint32_t p : std::get<2>(a)) covered += p != 0;
    EXPECT_GT(covered, 2000);
}

// Orthographic cameras: depth is the distance from the eye's plane along the axis (from window
// depth), and range equals it (the rays are parallel to the axis).
TEST(Passes, OrthographicDepthIsTheDistanceAlongTheAxis) {
    Scene scene;
    scene.objects.push_back(plane_object());
    scene.objects.push_back(sphere_object(128, 64));
    Camera c = Camera::orbit({0, 0, 0}, 0.3f, 0.6f, 6.0f);
    c.projection_kind = ProjectionKind::orthographic;
    c.ortho_height = 5;
    c.near = 1, c.far = 12;
    const ViewRequest request = all_passes(160, 120);
    ViewRenderer renderer;
    const Camera cameras[] = {c};
    const ViewImages img = renderer.render(scene, cameras, request)[0];
    const Mat4 view = c.view();
    const float half_h = c.ortho_height / 2, half_w = half_h * 160.0f / 120.0f;
    int checked = 0;
    for (int j = 0; j < 120; ++j)
        for (int i = 0; i < 160; ++i) {
            const std::size_t at = static_cast<std::size_t>(j) * 160 + i;
            if (img.instance[at] == 0) continue;
            ASSERT_EQ(img.range[at], img.depth[at]);
            // The view-space point (x, y, -depth), back in world space (the view is a rotation and a translation).
            const double vx = (2.0 * (i + 0.5) / 160 - 1) * half_w, vy = (1 - 2.0 * (j + 0.5) / 120) * half_h, vz = -img.depth[at];
            double p[3];
            for (int k = 0; k < 3; ++k)
                p[k] = view(0, k) * (vx - view(0, 3)) + view(1, k) * (vy - view(1, 3)) + view(2, k) * (vz - view(2, 3));
            if (img.instance[at] == 1) {
                EXPECT_NEAR(p[1], k_plane_y, 2e-4);
            } else {
                const double dx = p[0] - k_sphere_centre.x, dy = p[1] - k_sphere_centre.y, dz = p[2] - k_sphere_centre.z;
                EXPECT_NEAR(std::sqrt(dx * dx + dy * dy + dz * dz), k_sphere_radius, 2e-3);
            }
            ++checked;
        }
    EXPECT_GT(checked, 5000);
}

// Background values, and a scene with nothing in it.
TEST(Passes, TheBackgroundHasTheDocumentedValues) {
    const Scene empty;
    const ViewRequest request = all_passes(40, 30);
    const Camera cameras[] = {Camera::orbit({}, 0, 0, 3)};
    ViewRenderer renderer;
    for (const ViewImages& img : renderer.render(empty, cameras, request))
        for (std::size_t at = 0; at < pixels(request); ++at) {
            EXPECT_EQ(img.alpha[at], 0.0f);
            EXPECT_TRUE(std::isinf(img.depth[at]) && img.depth[at] > 0);
            EXPECT_TRUE(std::isinf(img.range[at]));
            EXPECT_TRUE(img.normal[at] == Vec3{});
            EXPECT_EQ(img.instance[at] + img.material[at] + img.primitive[at], 0u);
            EXPECT_TRUE(img.uv[at] == Vec2{});
        }
}

// Images whose rows are whole cache lines have the empty tiles of their passes cleared between the
// kernels' work, with the colour (DeferredFills): into images full of other bytes, every pixel no
// surface covers still gets the background, and the rest is what any tile size and thread count give.
TEST(Passes, EmptyTilesOfAlignedImagesGetTheBackground) {
    Scene scene;
    scene.objects.push_back(sphere_object(32, 16));
    ViewRequest request = all_passes(256, 128);
    const Camera cameras[] = {Camera::orbit(k_sphere_centre, 0.4f, 0.3f, 6.0f)};
    auto render = [&](RendererConfig config) {
        ViewImages img = make_view_images(request);
        auto garble = [](auto& v) { std::memset(static_cast<void*>(v.data()), 0xab, v.size() * sizeof(v[0])); };
        garble(img.colour), garble(img.alpha), garble(img.depth), garble(img.range), garble(img.normal);
        garble(img.instance), garble(img.material), garble(img.primitive), garble(img.uv);
        const PassImages out[] = {img.images()};
        ViewRenderer renderer(config);
        renderer.render(scene, cameras, request, out);
        return img;
    };
    const ViewImages img = render({.threads = 2, .tile_size = 16});
    int background = 0, surface = 0;
    for (std::size_t at = 0; at < pixels(request); ++at) {
        if (img.instance[at] != 0) {
            ASSERT_EQ(img.alpha[at], 1.0f);
            ++surface;
            continue;
        }
        ASSERT_EQ(img.alpha[at], 0.0f) << at;
        ASSERT_TRUE(std::isinf(img.depth[at]) && std::isinf(img.range[at])) << at;
        ASSERT_TRUE(img.normal[at] == Vec3{} && img.uv[at] == Vec2{}) << at;
        ASSERT_EQ(img.material[at] + img.primitive[at], 0u) << at;
        ++background;
    }
    EXPECT_GT(background, 20000);
    EXPECT_GT(surface, 2000);
    for (RendererConfig config : {RendererConfig{.threads = 1, .tile_size = 64}, RendererConfig{.threads = 3}})
        EXPECT_TRUE(AllPasses{{render(config)}} == AllPasses{{img}});
}

// What a render is asked for is checked, with messages that say what is wrong.
TEST(Passes, BadRequestsAreRefusedWithAReason) {
    const Scene scene = sphere_and_plane();
    const Camera cameras[] = {Camera::orbit({}, 0, 0, 4)};
    ViewRenderer renderer;
    auto message = [&](ViewRequest r, PassImages out) {
        try {
            const PassImages outs[] = {out};
            renderer.render(scene, cameras, r, outs);
        } catch (const FacetError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    std::vector<Rgba8> colour(64 * 64);
    ViewRequest r;
    r.width = r.height = 64;
    const PassImages only_colour{colour.data(), {}};
    EXPECT_EQ(message(r, only_colour), "no error");
    r.passes = PassSet{}.add(Pass::colour).add(Pass::depth);
    EXPECT_NE(message(r, only_colour).find("the depth pass is asked for but has no image"), std::string::npos);
    r.passes = {};
    EXPECT_NE(message(r, only_colour).find("no pass"), std::string::npos);
    r.passes = PassSet{}.add(Pass::colour);
    r.ssaa = 9;
    EXPECT_NE(message(r, only_colour).find("ssaa must be 1..8"), std::string::npos);
    r.ssaa = 1, r.width = 0;
    EXPECT_NE(message(r, only_colour).find("the size must be"), std::string::npos);
}

TEST(Passes, PassListsParseAndPrint) {
    const Result<PassSet> all = parse_passes("color,alpha,depth,range,normal,instance,material,primitive,uv");
    ASSERT_TRUE(all);
    EXPECT_TRUE(*all == PassSet::all());
    EXPECT_EQ(to_string(*all), "color,alpha,depth,range,normal,instance,material,primitive,uv");
    const Result<PassSet> some = parse_passes("normal,color");
    ASSERT_TRUE(some);
    EXPECT_EQ(to_string(*some), "color,normal");
    EXPECT_TRUE(some->needs_surface());
    EXPECT_FALSE(parse_passes("color,alpha")->needs_surface());
    for (const char* bad : {"", "color,", "colour", "depth,depth", "color,,depth"}) {
        const Result<PassSet> r = parse_passes(bad);
        EXPECT_FALSE(r) << bad;
    }
    EXPECT_NE(parse_passes("colour").error().message.find("unknown pass 'colour' (known: color, alpha"), std::string::npos);
    EXPECT_NE(parse_passes("depth,depth").error().message.find("named twice"), std::string::npos);
}

TEST(Passes, MaterialsAreNumberedInTheOrderObjectsFirstUseThem) {
    Material red, blue, red_again;
    red.base_colour = red_again.base_colour = {1, 0, 0, 1};
    blue.base_colour = {0, 0, 1, 1};
    Material red_one_sided = red;
    red_one_sided.double_sided = false;
    std::vector<ObjectView> v(5);
    const Material* materials[] = {&blue, &red, &red_again, &red_one_sided, &blue};
    for (std::size_t k = 0; k < 5; ++k) v[k].material = materials[k];
    std::vector<std::uint32_t> ids;
    std::vector<const Material*> scratch;
    material_ids(v, ids, scratch);
    EXPECT_EQ(ids, (std::vector<std::uint32_t>{1, 2, 2, 3, 1}));
}

// Rigs: the counts asked for, unit directions where the spec says, the same views for the same
// seed, and specs that cannot be read refused with a reason.
TEST(Passes, CameraRigsGiveTheViewsTheirSpecsDescribe) {
    ViewSpec base;
    base.fovy = radians(30);
    const Result<std::vector<ViewSpec>> orbit = parse_rig("orbit:8:30", base);
    ASSERT_TRUE(orbit);
    ASSERT_EQ(orbit->size(), 8u);
    for (std::size_t k = 0; k < 8; ++k) {
        EXPECT_NEAR((*orbit)[k].azimuth, 2 * 3.14159265f * static_cast<float>(k) / 8, 1e-5f);
        EXPECT_FLOAT_EQ((*orbit)[k].elevation, radians(30));
        EXPECT_EQ((*orbit)[k].fovy, base.fovy);
    }
    base.elevation = 0.25f;
    EXPECT_FLOAT_EQ((*parse_rig("orbit:3", base))[2].elevation, 0.25f);
    const Result<std::vector<ViewSpec>> sphere = parse_rig("sphere:200", base);
    ASSERT_TRUE(sphere);
    double mean[3] = {0, 0, 0};
    for (const ViewSpec& v : *sphere) {
        const double d[3] = {std::cos(v.elevation) * std::sin(v.azimuth), std::sin(v.elevation), std::cos(v.elevation) * std::cos(v.azimuth)};
        for (int k = 0; k < 3; ++k) mean[k] += d[k] / 200;
    }
    for (double m : mean) EXPECT_LT(std::fabs(m), 0.02) << "evenly spread";
    const auto a = *parse_rig("random:50:7", base), b = *parse_rig("random:50:7", base), c = *parse_rig("random:50:8", base);
    ASSERT_EQ(a.size(), 50u);
    bool differ = false;
    for (std::size_t k = 0; k < 50; ++k) {
        EXPECT_EQ(a[k].azimuth, b[k].azimuth);
        EXPECT_EQ(a[k].elevation, b[k].elevation);
        differ |= a[k].azimuth != c[k].azimuth;
    }
    EXPECT_TRUE(differ);
    for (const char* bad : {"orbit", "orbit:0", "orbit:x", "orbit:4:95", "orbit:4:10:1", "sphere:-3", "sphere:3:1", "random:5",
                            "random:5:x", "spiral:4", "", "orbit:10001"}) {
        const Result<std::vector<ViewSpec>> r = parse_rig(bad, base);
        ASSERT_FALSE(r) << bad;
        EXPECT_NE(r.error().message.find("bad view rig"), std::string::npos);
    }
}

}  // namespace
