// OpenCV's camera convention (OpenCvCamera, Camera::from_opencv, to_opencv, camera_to_world_gl),
// the scene functions over ObjectViews, ViewSpec's OpenCV camera and orbit distance, and drawing
// into caller memory (Framebuffer::use_colour_memory): what the Python package is built on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "facet/camera.hpp"
#include "facet/scene.hpp"
#include "support/glm_compare.hpp"

namespace {

using namespace facet;
using facet_test::Rng;

// A random rotation (from a random unit quaternion), row-major, in double.
std::array<double, 9> random_rotation(Rng& rng) {
    double q[4];
    double n = 0;
    do {
        n = 0;
        for (double& v : q) v = rng.uniform(-1, 1), n += v * v;
    } while (n < 0.01 || n > 1);
    n = std::sqrt(n);
    for (double& v : q) v /= n;
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    return {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
            2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
            2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
}

OpenCvCamera random_opencv(Rng& rng) {
    OpenCvCamera c;
    c.width = 32 + static_cast<int>(rng.uniform(0, 2000));
    c.height = 32 + static_cast<int>(rng.uniform(0, 2000));
    c.fx = rng.uniform(0.3f, 3) * c.width;
    c.fy = c.fx * rng.uniform(0.8f, 1.25f);
    c.cx = c.width * rng.uniform(0.3f, 0.7f);
    c.cy = c.height * rng.uniform(0.3f, 0.7f);
    c.skew = rng.uniform(-0.01f, 0.01f) * c.fx;
    c.rotation = random_rotation(rng);
    for (double& t : c.translation) t = rng.uniform(-5, 5);
    return c;
}

struct Pixel {
    double x, y;  // facet's screen: pixel centres at +0.5
};

// Where facet's pipeline puts a world point: clip = P V p, then the viewport's mapping.
Pixel facet_pixel(const Camera& c, int width, int height, Vec3 p) {
    const Mat4 clip_from_world = c.projection(static_cast<float>(width) / height) * c.view();
    const Vec4 q = clip_from_world * Vec4(p, 1);
    return {(q.x / q.w + 1.0) * width / 2, (1.0 - q.y / q.w) * height / 2};
}

// OpenCV's projection, in double: x = R p + t, u = fx x/z + skew y/z + cx, v = fy y/z + cy.
Pixel opencv_pixel(const OpenCvCamera& c, Vec3 p, double* depth = nullptr) {
    double x[3];
    for (int i = 0; i < 3; ++i)
        x[i] = c.rotation[i * 3] * p.x + c.rotation[i * 3 + 1] * p.y + c.rotation[i * 3 + 2] * p.z + c.translation[i];
    if (depth) *depth = x[2];
    return {c.fx * x[0] / x[2] + c.skew * x[1] / x[2] + c.cx, c.fy * x[1] / x[2] + c.cy};
}

// Within one image size of the image on every side.
bool near_image(const OpenCvCamera& c, Pixel p) {
    return std::fabs(p.x - c.width / 2.0) < 1.5 * c.width && std::fabs(p.y - c.height / 2.0) < 1.5 * c.height;
}

bool same_bits(const Mat4& a, const Mat4& b) { return std::memcmp(&a, &b, sizeof(Mat4)) == 0; }

// facet's pixel is OpenCV's plus one half: every point in front of a random camera (skew, off-centre
// principal point, non-square pixels) that lands near the image lands within 1/100 px of where
// OpenCV's formula puts it (float arithmetic on images up to 2000 px wide).
TEST(OpenCvCamera, FromOpenCvProjectsPointsWhereOpenCvDoes) {
    Rng rng(2301);
    int checked = 0;
    for (int it = 0; it < 300; ++it) {
        const OpenCvCamera cv = random_opencv(rng);
        ASSERT_TRUE(validate(cv).ok()) << validate(cv).error().message;
        const Camera c = Camera::from_opencv(cv, 0.05f, 500.0f);
        for (int k = 0; k < 20; ++k) {
            const Vec3 p{rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-3, 3)};
            double z = 0;
            const Pixel expected = opencv_pixel(cv, p, &z);
            if (z < 1 || !near_image(cv, expected)) continue;
            const Pixel got = facet_pixel(c, cv.width, cv.height, p);
            EXPECT_NEAR(got.x, expected.x + 0.5, 1e-2) << it;
            EXPECT_NEAR(got.y, expected.y + 0.5, 1e-2) << it;
            ++checked;
        }
    }
    EXPECT_GT(checked, 500);
}

// A camera made by look-at (any field of view, size, roll) goes to OpenCV and back with the same
// view and projection matrices, bit for bit, and converting again gives the same numbers.
TEST(OpenCvCamera, LookAtCamerasRoundTripBitForBit) {
    Rng rng(2302);
    for (int it = 0; it < 500; ++it) {
        Camera c;
        c.position = {rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-20, 20)};
        c.target = {rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2)};
        c.fovy = radians(rng.uniform(5, 150));
        c.roll = it % 3 == 0 ? rng.uniform(-3, 3) : 0;
        c.near = rng.uniform(0.01f, 1), c.far = c.near + rng.uniform(1, 100);
        const int w = 1 + static_cast<int>(rng.uniform(0, 4000)), h = 1 + static_cast<int>(rng.uniform(0, 4000));
        const std::optional<OpenCvCamera> cv = to_opencv(c, w, h);
        ASSERT_TRUE(cv);
        ASSERT_TRUE(validate(*cv).ok()) << validate(*cv).error().message;
        EXPECT_NEAR(cv->fx, cv->fy, 1e-6 * cv->fy);  // the same up to the float division by the aspect
        EXPECT_EQ(cv->cx, w / 2.0 - 0.5);
        EXPECT_EQ(cv->cy, h / 2.0 - 0.5);
        EXPECT_EQ(cv->skew, 0);
        const Camera back = Camera::from_opencv(*cv, c.near, c.far);
        const float aspect = static_cast<float>(w) / h;
        EXPECT_TRUE(same_bits(back.view(), c.view())) << it;
        EXPECT_TRUE(same_bits(back.projection(aspect), c.projection(aspect))) << it;
        EXPECT_LT(length(back.position - c.position), 1e-4f * (1 + length(c.position)));
        const std::optional<OpenCvCamera> again = to_opencv(back, w, h);
        ASSERT_TRUE(again);
        EXPECT_EQ(std::memcmp(&*again, &*cv, sizeof(OpenCvCamera)), 0) << it;
    }
}

// Orthographic cameras have no intrinsics; left-handed ones see the world mirrored, which no
// OpenCV camera does.
TEST(OpenCvCamera, OrthographicAndLeftHandedCamerasHaveNone) {
    Camera c;
    c.projection_kind = ProjectionKind::orthographic;
    EXPECT_FALSE(to_opencv(c, 100, 100));
    Camera lh;
    lh.handedness = Handedness::left;
    EXPECT_FALSE(to_opencv(lh, 100, 100));
    EXPECT_TRUE(to_opencv(Camera{}, 100, 100));
}

// Rendered at another size, an OpenCV camera keeps its view: to_opencv scales K so that every
// point's pixel scales with the image (screen coordinates, centres at +0.5, times the factor).
TEST(OpenCvCamera, IntrinsicsScaleWithTheImage) {
    Rng rng(2304);
    for (int it = 0; it < 50; ++it) {
        const OpenCvCamera cv = random_opencv(rng);
        const Camera c = Camera::from_opencv(cv, 0.1f, 100);
        const int w2 = cv.width * 3, h2 = cv.height * 2;
        const std::optional<OpenCvCamera> scaled = to_opencv(c, w2, h2);
        ASSERT_TRUE(scaled);
        EXPECT_EQ(scaled->width, w2);
        EXPECT_EQ(scaled->height, h2);
        for (int k = 0; k < 10; ++k) {
            const Vec3 p{rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-3, 3)};
            double z = 0;
            const Pixel a = opencv_pixel(cv, p, &z), b = opencv_pixel(*scaled, p);
            if (z < 1 || !near_image(cv, a)) continue;
            EXPECT_NEAR(b.x + 0.5, (a.x + 0.5) * 3, 1e-6 * std::max(1.0, std::fabs(a.x)));
            EXPECT_NEAR(b.y + 0.5, (a.y + 0.5) * 2, 1e-6 * std::max(1.0, std::fabs(a.y)));
            const Pixel f = facet_pixel(c, w2, h2, p);  // and facet's render at that size agrees
            EXPECT_NEAR(f.x, b.x + 0.5, 3e-2);
            EXPECT_NEAR(f.y, b.y + 0.5, 3e-2);
        }
    }
}

// Camera-to-world in the OpenGL convention: the eye at the origin, looking down -Z, +Y up.
TEST(OpenCvCamera, CameraToWorldIsTheOpenGlPose) {
    Rng rng(2305);
    for (int it = 0; it < 200; ++it) {
        Camera c;
        c.position = {rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-20, 20)};
        c.target = {rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2)};
        const Mat4 m = camera_to_world_gl(c);
        const CameraBasis b = camera_basis(c.target - c.position, c.up, Handedness::right);
        EXPECT_LT(length(transform_point(m, {0, 0, 0}) - c.position), 1e-4f * (1 + length(c.position)));
        EXPECT_LT(length(transform_direction(m, {0, 0, -1}) - b.forward), 1e-5f);
        EXPECT_LT(length(transform_direction(m, {0, 1, 0}) - b.up), 1e-5f);
        EXPECT_LT(length(transform_direction(m, {1, 0, 0}) - b.right), 1e-5f);
        // The same pose from the camera's OpenCV form.
        const Mat4 m2 = camera_to_world_gl(Camera::from_opencv(*to_opencv(c, 64, 64), 0.1f, 10));
        for (int i = 0; i < 16; ++i) EXPECT_NEAR(m.col[i / 4][i % 4], m2.col[i / 4][i % 4], 1e-6f * (1 + length(c.position)));
    }
}

TEST(OpenCvCamera, ValidateNamesWhatIsWrong) {
    OpenCvCamera good;
    good.fx = good.fy = 500, good.cx = 319.5, good.cy = 239.5, good.width = 640, good.height = 480;
    ASSERT_TRUE(validate(good).ok());
    auto message = [](const OpenCvCamera& c) { return validate(c).ok() ? std::string("ok") : validate(c).error().message; };
    OpenCvCamera c = good;
    c.fx = 0;
    EXPECT_NE(message(c).find("focal"), std::string::npos) << message(c);
    c = good, c.fy = std::nan("");
    EXPECT_NE(message(c).find("focal"), std::string::npos) << message(c);
    c = good, c.cx = INFINITY;
    EXPECT_NE(message(c).find("principal point"), std::string::npos) << message(c);
    c = good, c.width = 0;
    EXPECT_NE(message(c).find("image size"), std::string::npos) << message(c);
    c = good, c.height = k_max_target_size + 1;
    EXPECT_NE(message(c).find("image size"), std::string::npos) << message(c);
    c = good, c.rotation = {1, 0, 0, 0, 1, 0, 0, 0, -1};
    EXPECT_NE(message(c).find("reflection"), std::string::npos) << message(c);
    c = good, c.rotation = {2, 0, 0, 0, 1, 0, 0, 0, 1};
    EXPECT_NE(message(c).find("not a rotation"), std::string::npos) << message(c);
    c = good, c.translation[1] = std::nan("");
    EXPECT_NE(message(c).find("translation"), std::string::npos) << message(c);
    c = good, c.rotation[4] = INFINITY;
    EXPECT_NE(message(c).find("rotation"), std::string::npos) << message(c);
}

// ---- end to end: the rendered pixels ---------------------------------------------------------

Material plain() { return Material{}; }

// A small triangle centred on a world point, seen by an OpenCV camera through make_camera and
// render_scene: the centroid of the pixels it covers is OpenCV's (u, v) of that point (the pixel
// centres of OpenCV's convention), within a tenth of a pixel.
TEST(OpenCvCamera, RenderedPixelsSitWhereKAndRtPutThem) {
    Rng rng(2306);
    Renderer renderer({.threads = 1});
    for (int it = 0; it < 20; ++it) {
        OpenCvCamera cv = random_opencv(rng);
        cv.width = 96 + it, cv.height = 80;
        cv.fx = 90, cv.fy = 95, cv.cx = 40.25 + it, cv.cy = 35.75, cv.skew = it % 2 ? 3 : 0;
        // A point 5 units in front of the camera, and a triangle about it facing the camera.
        const double z = 5, u = 30 + it, v = 40;
        double x_cam[3] = {(u - cv.cx - cv.skew * ((v - cv.cy) / cv.fy)) / cv.fx * z, (v - cv.cy) / cv.fy * z, z};
        Vec3 p_world;
        for (int i = 0; i < 3; ++i) {  // R^T (x - t)
            double s = 0;
            for (int k = 0; k < 3; ++k) s += cv.rotation[k * 3 + i] * (x_cam[k] - cv.translation[k]);
            p_world[static_cast<std::size_t>(i)] = static_cast<float>(s);
        }
        const Vec3 right{static_cast<float>(cv.rotation[0]), static_cast<float>(cv.rotation[1]), static_cast<float>(cv.rotation[2])};
        const Vec3 down{static_cast<float>(cv.rotation[3]), static_cast<float>(cv.rotation[4]), static_cast<float>(cv.rotation[5])};
        const float s = 0.4f;  // about 7 px
        Mesh m;
        // An equilateral triangle's centroid is the point.
        m.positions = {p_world + down * (-s), p_world + right * (s * 0.866f) + down * (s * 0.5f),
                       p_world + right * (-s * 0.866f) + down * (s * 0.5f)};
        m.indices = {0, 1, 2};
        Scene scene;
        scene.objects.push_back({m, Mat4::identity(), plain()});
        ViewSpec spec;
        spec.opencv = cv;
        const Camera camera = make_camera(scene, spec, static_cast<float>(cv.width) / cv.height);
        Framebuffer fb(cv.width, cv.height);
        RenderSettings settings;
        settings.shading = Shading::mask;
        settings.background = {0, 0, 0, 1};
        render_scene(renderer, fb, scene, camera, settings);
        double sx = 0, sy = 0, n = 0;
        for (int y = 0; y < fb.height(); ++y)
            for (int x = 0; x < fb.width(); ++x)
                if (fb.colour(x, y).r == 255) sx += x, sy += y, n += 1;
        ASSERT_GT(n, 10) << it;
        // Pixel (i, j) is OpenCV's (u, v) = (i, j): the covered centres average to the centroid.
        EXPECT_NEAR(sx / n, u, 0.35) << it;
        EXPECT_NEAR(sy / n, v, 0.35) << it;
    }
}

// make_camera with an OpenCV camera: its pose exactly, the clip planes from the bounding sphere
// unless given, as for an explicit eye.
TEST(OpenCvCamera, ViewSpecTakesTheClipPlanesFromTheScene) {
    Scene scene;
    scene.objects.push_back({make_icosphere(1.0f, 2), translate({0, 0, -10}), plain()});
    OpenCvCamera cv;
    cv.fx = cv.fy = 100, cv.cx = 49.5, cv.cy = 49.5, cv.width = cv.height = 100;
    cv.rotation = {-1, 0, 0, 0, 1, 0, 0, 0, -1};  // at the origin, camera +Z along world -Z
    ViewSpec spec;
    spec.opencv = cv;
    const Camera c = make_camera(scene, spec, 1);
    ASSERT_TRUE(c.opencv);
    EXPECT_NEAR(c.near, 10 - 1.5f, 1e-3f);
    EXPECT_NEAR(c.far, 10 + 1.5f, 1e-3f);
    spec.near = 2, spec.far = 20;
    const Camera c2 = make_camera(scene, spec, 1);
    EXPECT_EQ(c2.near, 2);
    EXPECT_EQ(c2.far, 20);
}

// An orbit at a given distance: the eye that distance from the centre of the bounds.
TEST(OpenCvCamera, ViewSpecOrbitsAtAGivenDistance) {
    Scene scene;
    scene.objects.push_back({make_icosphere(1.0f, 2), translate({3, 1, 2}), plain()});
    ViewSpec spec;
    spec.azimuth = radians(30), spec.elevation = radians(20), spec.distance = 7;
    const Camera c = make_camera(scene, spec, 1);
    const Vec3 centre = scene.bounds().centre();
    EXPECT_NEAR(length(c.position - centre), 7, 1e-4f);
    EXPECT_LT(length(c.target - centre), 1e-5f);
    ViewSpec framing;
    framing.azimuth = spec.azimuth, framing.elevation = spec.elevation;
    const Camera framed = make_camera(scene, framing, 1);
    EXPECT_LT(length(normalize(c.position - centre) - normalize(framed.position - centre)), 1e-5f);
    EXPECT_NEAR(c.near, std::max(7 - 1.5f * scene.radius_about(centre), 0.01f * scene.radius_about(centre)), 1e-4f);
}

// ---- scenes as views, and drawing into caller memory ------------------------------------------

Scene mixed_scene() {
    Scene scene = default_scene();
    Material blended;
    blended.base_colour = {0.2f, 0.5f, 0.9f, 0.5f};
    blended.alpha_mode = AlphaMode::blend;
    scene.objects.push_back({make_torus(1.0f, 0.3f, 32, 16), translate({0, 1, 0}), blended});
    return scene;
}

std::vector<ObjectView> views_of(const Scene& scene) {
    std::vector<ObjectView> views;
    for (const SceneObject& o : scene.objects) views.push_back(view_of(o));
    return views;
}

// The same scene as ObjectViews: the same camera from make_camera and the same bytes from
// render_scene, for every shading mode, with a blended object among them.
TEST(SceneViews, RenderTheSameBytesAsTheScene) {
    const Scene scene = mixed_scene();
    const std::vector<ObjectView> views = views_of(scene);
    ViewSpec spec;
    spec.azimuth = radians(40), spec.elevation = radians(25);
    const Camera a = make_camera(scene, spec, 1.5f), b = make_camera(views, spec, 1.5f);
    EXPECT_TRUE(same_bits(a.view(), b.view()));
    EXPECT_EQ(a.near, b.near);
    EXPECT_EQ(a.far, b.far);
    Renderer renderer({.threads = 2});
    for (Shading s : {Shading::lit, Shading::lambert, Shading::flat, Shading::normals, Shading::mask,
                      Shading::vertex_color, Shading::texture}) {
        RenderSettings settings;
        settings.shading = s;
        Framebuffer fa(120, 80), fb(120, 80);
        const DrawStats sa = render_scene(renderer, fa, scene, a, settings);
        const DrawStats sb = render_scene(renderer, fb, views, a, settings);
        EXPECT_EQ(std::memcmp(fa.colour_data(), fb.colour_data(), 120 * 80 * 4), 0) << to_string(s);
        EXPECT_EQ(std::memcmp(fa.depth_data(), fb.depth_data(), 120 * 80 * 4), 0) << to_string(s);
        EXPECT_EQ(sa.triangles_in, sb.triangles_in);
        EXPECT_EQ(sa.triangles_rasterized, sb.triangles_rasterized);
    }
}

// A framebuffer drawing into caller memory draws the bytes it draws into its own, at any
// alignment of that memory (rows that are not whole cache lines take the plain stores), and goes
// back to memory of its own on nullptr; and one made on caller memory draws the same.
TEST(SceneViews, FramebufferDrawsIntoCallerMemory) {
    const Scene scene = mixed_scene();
    Renderer renderer({.threads = 2});
    for (int w : {128, 97}) {
        const int h = 64;
        const Camera camera = make_camera(scene, ViewSpec{}, static_cast<float>(w) / h);
        Framebuffer own(w, h);
        render_scene(renderer, own, scene, camera, RenderSettings{});
        for (std::size_t offset : {0, 4, 36}) {
            std::vector<unsigned char> memory(static_cast<std::size_t>(w) * h * 4 + 128, 0xab);
            // 64-byte aligned, then `offset` bytes past it
            auto base = reinterpret_cast<std::uintptr_t>(memory.data());
            auto* pixels = reinterpret_cast<Rgba8*>(((base + 63) & ~std::uintptr_t{63}) + offset);
            Framebuffer fb(w, h);
            fb.use_colour_memory(pixels);
            EXPECT_EQ(fb.colour_data(), pixels);
            render_scene(renderer, fb, scene, camera, RenderSettings{});
            EXPECT_EQ(std::memcmp(pixels, own.colour_data(), static_cast<std::size_t>(w) * h * 4), 0) << w << " " << offset;
            EXPECT_EQ(std::memcmp(fb.depth_data(), own.depth_data(), static_cast<std::size_t>(w) * h * 4), 0);
            fb.use_colour_memory(nullptr);
            EXPECT_NE(fb.colour_data(), pixels);
            render_scene(renderer, fb, scene, camera, RenderSettings{});
            EXPECT_EQ(std::memcmp(fb.colour_data(), own.colour_data(), static_cast<std::size_t>(w) * h * 4), 0);
            // Made on the caller's memory: nothing cleared before the draw, which clears both arrays.
            std::fill_n(pixels, static_cast<std::size_t>(w) * h, Rgba8{0xab, 0xab, 0xab, 0xab});
            Framebuffer made(w, h, pixels);
            EXPECT_EQ(made.colour_data(), pixels);
            EXPECT_EQ(made.colour(0, 0), (Rgba8{0xab, 0xab, 0xab, 0xab}));
            render_scene(renderer, made, scene, camera, RenderSettings{});
            EXPECT_EQ(std::memcmp(pixels, own.colour_data(), static_cast<std::size_t>(w) * h * 4), 0) << w << " " << offset;
            EXPECT_EQ(std::memcmp(made.depth_data(), own.depth_data(), static_cast<std::size_t>(w) * h * 4), 0);
        }
    }
}

// resolve_supersampled into caller memory equals the Image form.
TEST(SceneViews, ResolveIntoCallerMemoryEqualsTheImageForm) {
    const Scene scene = mixed_scene();
    Renderer renderer({.threads = 1});
    Framebuffer fb(150, 90);
    render_scene(renderer, fb, scene, make_camera(scene, ViewSpec{}, 150.0f / 90), RenderSettings{});
    for (int factor : {1, 3}) {
        Image image;
        std::vector<float> depth;
        resolve_supersampled(fb, factor, image, &depth);
        std::vector<Rgba8> colour(depth.size());
        std::vector<float> depth2(depth.size());
        resolve_supersampled(fb, factor, colour.data(), depth2.data());
        EXPECT_EQ(std::memcmp(colour.data(), image.pixels.data(), colour.size() * 4), 0);
        EXPECT_EQ(std::memcmp(depth2.data(), depth.data(), depth.size() * 4), 0);
    }
}

}  // namespace
