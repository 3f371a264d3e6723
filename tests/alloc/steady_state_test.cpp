// Property: drawing allocates nothing in steady state. Once a Renderer has drawn a scene (its
// scratch memory, bins and per-thread tile buffers grown to size), drawing it again calls operator
// new zero times: neither Renderer::draw nor render_scene for an opaque scene. A binary of its own,
// because it replaces the global operator new to count calls.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "facet/camera.hpp"
#include "facet/renderer.hpp"
#include "facet/scene.hpp"
#include "facet/shaders.hpp"
#include "facet/views.hpp"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

// The replacements below pair malloc with free by construction; GCC cannot see that through the
// replaced operators and would warn at every delete.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

void* operator new(std::size_t size) {
    g_allocations.fetch_add(1, std::memory_order_relaxed);
    if (void* p = std::malloc(size ? size : 1)) return p;
    throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return ::operator new(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
    g_allocations.fetch_add(1, std::memory_order_relaxed);
    return std::malloc(size ? size : 1);
}
void* operator new[](std::size_t size, const std::nothrow_t& tag) noexcept { return ::operator new(size, tag); }
void* operator new(std::size_t size, std::align_val_t align) {
    g_allocations.fetch_add(1, std::memory_order_relaxed);
    const std::size_t a = static_cast<std::size_t>(align);
    if (void* p = std::aligned_alloc(a, (size + a - 1) / a * a)) return p;
    throw std::bad_alloc();
}
void* operator new[](std::size_t size, std::align_val_t align) { return ::operator new(size, align); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

namespace {

using namespace facet;

long allocations_during(const auto& f) {
    const long before = g_allocations.load();
    f();
    return g_allocations.load() - before;
}

Scene test_scene() {
    Scene scene;
    SceneObject sphere;
    sphere.mesh = make_icosphere(1.0f, 5);  // 20,480 triangles
    scene.objects.push_back(std::move(sphere));
    SceneObject cube;
    cube.mesh = make_cube(0.6f);
    cube.model = translate(Vec3{0.8f, 0.3f, 0.9f});  // in front: crosses the near plane when close
    scene.objects.push_back(std::move(cube));
    return scene;
}

TEST(SteadyState, TheCounterSeesAllocations) {
    EXPECT_GE(allocations_during([] { const std::vector<int> v(1000); (void)v; }), 1);
}

class SteadyStateDraws : public ::testing::TestWithParam<int> {};

TEST_P(SteadyStateDraws, RenderSceneAllocatesNothingOnceWarm) {
    const Scene scene = test_scene();
    Renderer renderer(RendererConfig{.threads = GetParam()});
    Framebuffer fb(320, 240);
    for (Shading shading : {Shading::lambert, Shading::lit}) {
        RenderSettings settings;
        settings.shading = shading;
        const Camera camera = frame_scene(scene, 0.4f, 0.3f, 0.8f, 320.0f / 240.0f);
        for (int warm = 0; warm < 3; ++warm) render_scene(renderer, fb, scene, camera, settings);
        const long during = allocations_during([&] {
            for (int frame = 0; frame < 5; ++frame) render_scene(renderer, fb, scene, camera, settings);
        });
        EXPECT_EQ(during, 0) << "shading " << static_cast<int>(shading) << ", threads " << GetParam();
    }
}

TEST_P(SteadyStateDraws, DrawAllocatesNothingOnceWarm) {
    const Mesh mesh = make_icosphere(1.0f, 6);  // 81,920 triangles
    Renderer renderer(RendererConfig{.threads = GetParam(), .batch_triangles = 30000});  // several batches
    Framebuffer fb(640, 480);
    Camera camera;
    camera.position = {0.3f, 0.2f, 1.6f};  // close: triangles clipped by the near plane too
    ShadingUniforms u;
    u.clip_from_object = camera.projection(640.0f / 480.0f) * camera.view();
    const shaders::Lambert shader{MeshArrays::of(mesh), u};
    DrawState state;
    state.cull = CullMode::none;
    const DrawInput input{static_cast<std::uint32_t>(mesh.positions.size()), mesh.indices};
    for (int warm = 0; warm < 3; ++warm) {
        fb.clear(Vec4{0, 0, 0, 1});
        renderer.draw(fb, state, input, shader);
    }
    const long during = allocations_during([&] {
        for (int frame = 0; frame < 5; ++frame) {
            fb.clear(Vec4{0, 0, 0, 1});
            renderer.draw(fb, state, input, shader);
        }
    });
    EXPECT_EQ(during, 0) << "threads " << GetParam();
}

// Points and lines: the same for a scene whose mesh carries them (round and square points, a strip).
TEST_P(SteadyStateDraws, PointsAndLinesAllocateNothingOnceWarm) {
    Scene scene = test_scene();
    Mesh& m = scene.objects[0].mesh;
    for (std::uint32_t i = 0; i < m.positions.size(); ++i) m.points.push_back(i);
    for (std::uint32_t i = 0; i + 1 < m.positions.size(); ++i) m.lines.insert(m.lines.end(), {i, i + 1});
    Renderer renderer(RendererConfig{.threads = GetParam()});
    Framebuffer fb(320, 240);
    const Camera camera = frame_scene(scene, 0.4f, 0.3f, 0.8f, 320.0f / 240.0f);
    for (PointShape shape : {PointShape::round, PointShape::square}) {
        RenderSettings settings;
        settings.primitives.point_size = 5;
        settings.primitives.point_shape = shape;
        for (int warm = 0; warm < 3; ++warm) render_scene(renderer, fb, scene, camera, settings);
        const long during = allocations_during([&] {
            for (int frame = 0; frame < 5; ++frame) render_scene(renderer, fb, scene, camera, settings);
        });
        EXPECT_EQ(during, 0) << "threads " << GetParam();
    }
}

// Render passes: a warm ViewRenderer rendering every pass of views into the caller's memory, with
// and without supersampling or jittered frames, allocates nothing either.
TEST_P(SteadyStateDraws, RenderingViewsWithEveryPassAllocatesNothingOnceWarm) {
    Scene scene = test_scene();
    scene.objects[1].mesh.normals.clear();  // face normals
    ViewRenderer renderer(RendererConfig{.threads = GetParam()});
    ViewRequest request;
    request.width = 200, request.height = 150;
    request.passes = PassSet::all();
    const Camera cameras[] = {frame_scene(scene, 0.4f, 0.3f, 0.8f, 4.0f / 3), frame_scene(scene, 2.0f, -0.3f, 0.8f, 4.0f / 3)};
    ViewImages a, b;
    for (ViewImages* v : {&a, &b}) {
        const std::size_t n = 200 * 150;
        v->colour.resize(n), v->alpha.resize(n), v->depth.resize(n), v->range.resize(n), v->normal.resize(n);
        v->instance.resize(n), v->material.resize(n), v->primitive.resize(n), v->uv.resize(n);
    }
    const PassImages out[] = {a.images(), b.images()};
    for (const auto& [ssaa, aa] : {std::pair{1, 1}, {2, 1}, {1, 2}}) {
        request.ssaa = ssaa, request.aa = aa;
        for (int warm = 0; warm < 3; ++warm) renderer.render(scene, cameras, request, out);
        const long during = allocations_during([&] {
            for (int frame = 0; frame < 3; ++frame) renderer.render(scene, cameras, request, out);
        });
        EXPECT_EQ(during, 0) << "ssaa " << ssaa << ", aa " << aa << ", threads " << GetParam();
    }
}

INSTANTIATE_TEST_SUITE_P(Threads, SteadyStateDraws, ::testing::Values(1, 2, 4));

}  // namespace
