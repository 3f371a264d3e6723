// facet_bench_stages: Google Benchmark micro-benchmarks of the pipeline stages, through the library's
// internal entry points (include/facet/detail, and the clip and setup headers in src/):
//   vertex stage  Renderer::draw of many vertices and one degenerate triangle (shader + projection)
//   clip          detail::clip_triangle on triangles crossing the near plane
//   setup         detail::setup_triangle on projected, snapped vertices; setup_triangles 16 at a time
//   front end     detail::run_front_end: assemble + reject + setup + bin (bin = front end - setup)
//   coverage      detail::rasterize_tile per (tile, triangle) pair
//   depth pass    detail::resolve_triangle per (tile, triangle) pair (visible-only order, pass one)
//   shading       detail::shade_tile with the Lambert shader over a fully covered tile, and the
//                 visible-pixel pass (scalar specification and compiled SIMD kernel)
//   clear         Framebuffer::clear
//   texture       Texture::sample, bilinear and trilinear
//   draw          Renderer::draw end to end: Lambert (visible-only order), Lambert blended and
//                 Textured (one-pass order), and a trivial (Mask) shader
// The workload is a geodesic sphere of 81,920 triangles framed at 512x512 (triangles of a few
// pixels, like a scanned model), single-threaded. Run: build/release/bench/facet_bench_stages.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "bench_scenes.hpp"
#include "facet/detail/front_end.hpp"
#include "facet/renderer.hpp"
#include "facet/scene.hpp"
#include "facet/shaders.hpp"
#include "facet/texture.hpp"
#include "geometry/clip.hpp"
#include "geometry/project.hpp"
#include "setup/setup.hpp"
#include "tile/depth_pass.hpp"
#include "tile/tile_buffers.hpp"

namespace {

using namespace facet;
namespace d = facet::detail;

detail::FrontEndParams params_for(int w, int h, CullMode cull = CullMode::none) {
    d::FrontEndParams p{};
    p.state.cull = cull;
    p.scissor = {0, 0, w, h};
    p.vp_x = 0, p.vp_y = 0, p.vp_w = static_cast<float>(w), p.vp_h = static_cast<float>(h);
    p.tile_size = 64;
    p.tiles_x = (w + 63) / 64;
    p.tiles_y = (h + 63) / 64;
    return p;
}

// The vertex stage's output for a mesh seen by the framing camera, with the Lambert shader's
// 7 varyings, projected and outcoded as the renderer does it.
struct Workload {
    Mesh mesh;
    int width = 512, height = 512;
    d::FrontEndParams params;
    shaders::Lambert shader;
    d::ClipVertices vertices;
};

const Workload& sphere_workload() {
    static const Workload w = [] {
        Workload wl;
        wl.mesh = bench::make_geodesic_sphere(1.0f, 64);  // 81,920 triangles
        Scene scene;
        scene.objects.push_back({wl.mesh, Mat4::identity(), {}});
        const Camera camera = frame_scene(scene, 0, 0, radians(45.0f), 1.0f);
        wl.params = params_for(wl.width, wl.height);
        wl.shader.mesh = MeshArrays::of(wl.mesh);
        wl.shader.u.clip_from_object = camera.projection(1.0f) * camera.view();
        wl.shader.u.key.direction = normalize(camera.position - camera.target);
        const std::size_t n = wl.mesh.positions.size();
        wl.vertices.resize(n, 7);
        Varyings<7> out;
        for (std::size_t i = 0; i < n; ++i) {
            wl.vertices.pos[i] = wl.shader.vertex(static_cast<std::uint32_t>(i), out);
            for (int k = 0; k < 7; ++k) wl.vertices.varyings[i * 7 + k] = out[k];
        }
        d::project_vertices(wl.vertices, 0, n, wl.params);
        return wl;
    }();
    return w;
}

void BM_Clear(benchmark::State& state) {
    const int w = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
    Framebuffer fb(w, h);
    for (auto _ : state) {
        fb.clear({0.1f, 0.2f, 0.3f, 1});
        benchmark::DoNotOptimize(fb.colour_data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * w * h);
    state.SetBytesProcessed(state.iterations() * w * h * static_cast<std::int64_t>(sizeof(Rgba8) + sizeof(float)));
}
BENCHMARK(BM_Clear)->Args({512, 512})->Args({1920, 1080});

// Every vertex goes through the Lambert vertex shader and the projection pass; the one triangle
// drawn is degenerate, so the front end and the tiles cost next to nothing.
void BM_VertexStage(benchmark::State& state) {
    const Workload& wl = sphere_workload();
    Renderer renderer(RendererConfig{.threads = 1});
    Framebuffer fb(64, 64);
    const std::uint32_t one_triangle[3] = {0, 0, 0};
    const DrawInput input{static_cast<std::uint32_t>(wl.mesh.positions.size()), one_triangle};
    DrawState ds;
    ds.cull = CullMode::none;
    for (auto _ : state) benchmark::DoNotOptimize(renderer.draw(fb, ds, input, wl.shader));
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(wl.mesh.positions.size()));
    state.SetLabel("vertices");
}
BENCHMARK(BM_VertexStage);

// Triangles with one or two vertices behind the near plane (z < 0): cut by one plane.
void BM_Clip(benchmark::State& state) {
    const int count = 4096;
    d::ClipVertices vertices;
    vertices.resize(count * 3, 7);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1, 1);
    for (int i = 0; i < count * 3; ++i) {
        const float w = 1.0f + 0.5f * (u(rng) + 1);
        const bool behind = (i % 3 == 0) || (i % 6 == 1);
        vertices.pos[static_cast<std::size_t>(i)] = {u(rng) * w, u(rng) * w, behind ? -0.5f * w : 0.5f * w, w};
    }
    const d::GuardBand guard{8192.0f / 256, 8192.0f / 256};
    d::ClipVertices extras;
    extras.stride = 7;
    d::ClipVertex out[d::k_max_clip_polygon];
    std::int64_t produced = 0;
    for (auto _ : state) {
        extras.pos.clear();
        extras.varyings.clear();
        for (int t = 0; t < count; ++t) {
            d::ClipVertex tri[3];
            std::uint32_t planes = 0;
            for (int k = 0; k < 3; ++k) {
                const auto i = static_cast<std::uint32_t>(t * 3 + k);
                tri[k] = {vertices.pos[i], i};
                planes |= d::outcode(tri[k].pos, guard);
            }
            produced += d::clip_triangle(tri, planes, guard, vertices, extras, out);
        }
        benchmark::DoNotOptimize(out);
    }
    benchmark::DoNotOptimize(produced);
    state.SetItemsProcessed(state.iterations() * count);
    state.SetLabel("triangles");
}
BENCHMARK(BM_Clip);

void BM_Setup(benchmark::State& state) {
    const Workload& wl = sphere_workload();
    const auto& idx = wl.mesh.indices;
    const std::size_t count = idx.size() / 3;
    d::TriangleSetup t;
    std::int64_t ok = 0;
    for (auto _ : state) {
        for (std::size_t i = 0; i < count; ++i) {
            const std::uint32_t ref[3] = {idx[i * 3], idx[i * 3 + 1], idx[i * 3 + 2]};
            const d::ScreenVertex v[3] = {wl.vertices.screen[ref[0]], wl.vertices.screen[ref[1]], wl.vertices.screen[ref[2]]};
            ok += d::setup_triangle(v, ref, wl.params, t) == d::SetupResult::ok;
        }
        benchmark::DoNotOptimize(t);
    }
    benchmark::DoNotOptimize(ok);
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(count));
    state.SetLabel("triangles");
}
BENCHMARK(BM_Setup);

// The same triangles through setup_triangles, 16 at a time (the SIMD kernel of the active ISA).
void BM_SetupBatch(benchmark::State& state) {
    const Workload& wl = sphere_workload();
    const auto& idx = wl.mesh.indices;
    const std::size_t count = idx.size() / 3;
    d::SetupBatch batch{};
    std::vector<d::TriangleSetup> out(d::SetupBatch::k_capacity);
    std::int64_t ok = 0;
    for (auto _ : state) {
        for (std::size_t i = 0; i < count; i += d::SetupBatch::k_capacity) {
            batch.count = static_cast<int>(std::min<std::size_t>(d::SetupBatch::k_capacity, count - i));
            for (int j = 0; j < batch.count; ++j)
                for (int k = 0; k < 3; ++k) {
                    batch.ref[k][j] = idx[(i + j) * 3 + k];
                    batch.v[k][j] = wl.vertices.screen[batch.ref[k][j]];
                }
            ok += d::setup_triangles(batch, wl.params, out.data()).written;
        }
        benchmark::DoNotOptimize(out.data());
    }
    benchmark::DoNotOptimize(ok);
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(count));
    state.SetLabel("triangles");
}
BENCHMARK(BM_SetupBatch);

void BM_FrontEnd_SmallTriangles(benchmark::State& state) {
    const Workload& wl = sphere_workload();
    const DrawInput input{static_cast<std::uint32_t>(wl.mesh.positions.size()), wl.mesh.indices};
    const std::size_t count = wl.mesh.indices.size() / 3;
    d::FrontEndChunk chunk;
    const std::size_t tiles = static_cast<std::size_t>(wl.params.tiles_x) * wl.params.tiles_y;
    for (auto _ : state) {
        chunk.reset(tiles, 7);
        d::run_front_end(wl.vertices, input, 0, count, wl.params, chunk);
        benchmark::DoNotOptimize(chunk.bins.data());
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(count));
    state.SetLabel("triangles (assemble + setup + bin)");
}
BENCHMARK(BM_FrontEnd_SmallTriangles);

// 128 screen-sized triangles at 1920x1080: binning into ~500 tiles each dominates.
void BM_FrontEnd_LargeTriangles(benchmark::State& state) {
    const int w = 1920, h = 1080;
    const Scene scene = bench::make_quad_stack(64, static_cast<float>(w) / h);
    const Mesh& mesh = scene.objects[0].mesh;
    const Camera camera = bench::quad_stack_camera();
    const Mat4 clip = camera.projection(static_cast<float>(w) / h) * camera.view();
    const d::FrontEndParams params = params_for(w, h);
    d::ClipVertices vertices;
    vertices.resize(mesh.positions.size(), 0);
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) vertices.pos[i] = clip * Vec4(mesh.positions[i], 1);
    d::project_vertices(vertices, 0, mesh.positions.size(), params);
    const DrawInput input{static_cast<std::uint32_t>(mesh.positions.size()), mesh.indices};
    const std::size_t count = mesh.indices.size() / 3;
    d::FrontEndChunk chunk;
    for (auto _ : state) {
        chunk.reset(static_cast<std::size_t>(params.tiles_x) * params.tiles_y, 0);
        d::run_front_end(vertices, input, 0, count, params, chunk);
        benchmark::DoNotOptimize(chunk.bins.data());
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(count));
    state.SetLabel("triangles (assemble + setup + bin)");
}
BENCHMARK(BM_FrontEnd_LargeTriangles);

d::PixelRect tile_rect(const d::FrontEndParams& p, std::size_t tile_index) {
    const int tx = static_cast<int>(tile_index % static_cast<std::size_t>(p.tiles_x));
    const int ty = static_cast<int>(tile_index / static_cast<std::size_t>(p.tiles_x));
    return {tx * p.tile_size, ty * p.tile_size, std::min((tx + 1) * p.tile_size, p.scissor.x1),
            std::min((ty + 1) * p.tile_size, p.scissor.y1)};
}

// Coverage of every binned (tile, triangle) pair of the sphere: small triangles.
void BM_Coverage_SmallTriangles(benchmark::State& state) {
    const Workload& wl = sphere_workload();
    const DrawInput input{static_cast<std::uint32_t>(wl.mesh.positions.size()), wl.mesh.indices};
    d::FrontEndChunk chunk;
    chunk.reset(static_cast<std::size_t>(wl.params.tiles_x) * wl.params.tiles_y, 7);
    d::run_front_end(wl.vertices, input, 0, wl.mesh.indices.size() / 3, wl.params, chunk);
    std::int64_t pairs = 0, covered = 0;
    d::TileCoverage cov;
    for (auto _ : state) {
        for (std::size_t tile = 0; tile < chunk.bins.size(); ++tile) {
            const d::PixelRect r = tile_rect(wl.params, tile);
            for (const d::TriangleSetup& t : chunk.bins[tile]) {
                covered += d::rasterize_tile(t, r, cov);
                ++pairs;
            }
        }
        benchmark::DoNotOptimize(cov);
    }
    benchmark::DoNotOptimize(covered);
    state.SetItemsProcessed(pairs);
    state.SetLabel("tile-triangle pairs");
}
BENCHMARK(BM_Coverage_SmallTriangles);

// Pass one of the visible-only order (coverage, depth test and write, owners) for every binned
// (tile, triangle) pair of the sphere, front faces only as a renderer with culling would draw them.
// lequal, so every frame after the first passes where it passed before.
void BM_DepthPass_SmallTriangles(benchmark::State& state) {
    const Workload& wl = sphere_workload();
    const DrawInput input{static_cast<std::uint32_t>(wl.mesh.positions.size()), wl.mesh.indices};
    d::FrontEndParams params = wl.params;
    params.state.cull = CullMode::back;
    d::FrontEndChunk chunk;
    chunk.reset(static_cast<std::size_t>(params.tiles_x) * params.tiles_y, 7);
    d::run_front_end(wl.vertices, input, 0, wl.mesh.indices.size() / 3, params, chunk);
    Framebuffer fb(wl.width, wl.height);
    fb.clear({0, 0, 0, 1});
    const d::TargetView view{fb.colour_data(), fb.depth_data(), fb.width()};
    static d::TileBuffers buffers;  // 49 KB: not on the stack
    std::int64_t pairs = 0, owning = 0;
    for (auto _ : state) {
        for (std::size_t tile = 0; tile < chunk.bins.size(); ++tile) {
            const d::PixelRect r = tile_rect(params, tile);
            buffers.begin(r, 7, view);
            for (const d::TriangleSetup& t : chunk.bins[tile]) {
                owning += d::resolve_triangle({&t, r, &buffers, 0, DepthTest::lequal, true});
                ++pairs;
            }
            buffers.end(r, view, true);
        }
        benchmark::ClobberMemory();
    }
    benchmark::DoNotOptimize(owning);
    state.SetItemsProcessed(pairs);
    state.SetLabel("tile-triangle pairs");
}
BENCHMARK(BM_DepthPass_SmallTriangles);

// A triangle that covers a whole 64x64 tile, and the tile.
struct FullTile {
    d::FrontEndParams params = params_for(64, 64);
    d::TriangleSetup setup{};
    d::PixelRect rect{0, 0, 64, 64};
    d::ClipVertices vertices;
    FullTile() {
        vertices.resize(3, 7);
        vertices.pos = {{-3, -3, 0.5f, 1}, {3, -3, 0.5f, 1}, {-3, 3, 0.2f, 1}};  // well past the tile
        for (int i = 0; i < 3; ++i) {
            float* v = vertices.varyings.data() + i * 7;
            const float n[7] = {0.2f * static_cast<float>(i), 0.3f, 0.9f, 1, 1, 1, 1};
            std::copy(n, n + 7, v);
        }
        d::project_vertices(vertices, 0, 3, params);
        const d::ScreenVertex v[3] = {vertices.screen[0], vertices.screen[1], vertices.screen[2]};
        const std::uint32_t ref[3] = {0, 1, 2};
        d::setup_triangle(v, ref, params, setup);
    }
};

void BM_Coverage_FullTile(benchmark::State& state) {
    const FullTile ft;
    d::TileCoverage cov;
    for (auto _ : state) {
        benchmark::DoNotOptimize(d::rasterize_tile(ft.setup, ft.rect, cov));
        benchmark::DoNotOptimize(cov);
    }
    state.SetItemsProcessed(state.iterations() * 64 * 64);
    state.SetLabel("pixels");
}
BENCHMARK(BM_Coverage_FullTile);

// The fragment stage alone: depth test (lequal, so every pass re-shades), perspective-correct
// varyings, the Lambert shader, depth write and colour store, over 4096 covered pixels.
void BM_Shading_Lambert(benchmark::State& state) {
    FullTile ft;
    d::TileCoverage cov;
    d::rasterize_tile(ft.setup, ft.rect, cov);
    Framebuffer fb(64, 64);
    fb.clear({0, 0, 0, 1});
    shaders::Lambert shader;
    shader.u.key.direction = {0, 0, 1};
    const d::TargetView view{fb.colour_data(), fb.depth_data(), fb.width()};
    const float* var[3];
    for (int k = 0; k < 3; ++k) var[k] = ft.vertices.varyings_of(ft.setup.vertex[k]);
    for (auto _ : state) {
        d::shade_tile<shaders::Lambert, true, Blend::none>(shader, DepthTest::lequal, ft.setup, cov, ft.rect, var,
                                                            view);
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * 64 * 64);
    state.SetLabel("pixels");
}
BENCHMARK(BM_Shading_Lambert);

// The visible-pixel pass alone (pass two of the visible-only order) over a 64x64 tile owned by 16
// triangles in 4x4-pixel cells, as small triangles leave it: Arg 0 runs the scalar specification
// (shade_visible, fragment() per pixel), Arg 1 the compiled SIMD kernel of the built-in Lambert,
// Arg 2 the kernel over 2x2-pixel cells (four triangles in every 4x4 block, as in the CGAL meshes
// at 1920x1080: 3.6 to 4.6 on average, 7.1 on the 1M sphere).
void BM_ShadeVisible_Lambert(benchmark::State& state) {
    FullTile ft;
    Framebuffer fb(64, 64);
    fb.clear({0, 0, 0, 1});
    const d::TargetView view{fb.colour_data(), fb.depth_data(), fb.width()};
    static d::TileBuffers buffers;  // 49 KB: not on the stack
    buffers.begin(ft.rect, 7, view);
    const float* var[3];
    for (int k = 0; k < 3; ++k) var[k] = ft.vertices.varyings_of(ft.setup.vertex[k]);
    constexpr int k_owners = 16;
    for (int id = 0; id < k_owners; ++id) {
        buffers.triangles.push_back(&ft.setup);
        buffers.records.resize(buffers.records.size() + static_cast<std::size_t>(buffers.stride));
        d::write_shading_record(ft.setup, var, 7, buffers.records.data() + buffers.records.size() - buffers.stride);
    }
    for (int y = 0; y < 64; ++y) {
        buffers.covered[y] = ~0ull;
        for (int x = 0; x < 64; ++x) {
            const int cell = state.range(0) == 2 ? 2 : 4;
            buffers.owner[y * d::k_max_tile_size + x] = static_cast<std::uint32_t>((x / cell + y / cell * 3) % k_owners);
        }
    }
    shaders::Lambert shader;
    shader.u.key.direction = {0, 0, 1};
    for (auto _ : state) {
        if (state.range(0))
            d::CompiledVisiblePass<shaders::Lambert>::run(shader, buffers.visible(ft.rect), view);
        else
            d::shade_visible(shader, buffers.visible(ft.rect), view);
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * 64 * 64);
    state.SetLabel(state.range(0) == 2   ? "pixels, compiled SIMD pass, 4 triangles per block"
                   : state.range(0) ? "pixels, compiled SIMD pass"
                                    : "pixels, scalar specification");
}
BENCHMARK(BM_ShadeVisible_Lambert)->Arg(0)->Arg(1)->Arg(2);

void BM_TextureSample(benchmark::State& state) {
    Image img{256, 256, std::vector<Rgba8>(256 * 256)};
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x)
            img.at(x, y) = {static_cast<std::uint8_t>(x), static_cast<std::uint8_t>(y), static_cast<std::uint8_t>(x ^ y), 255};
    const Texture tex(std::move(img));
    Sampler sampler;
    sampler.filter = state.range(0) ? Filter::trilinear : Filter::bilinear;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0, 4);
    std::vector<Vec2> uvs(4096);
    for (Vec2& p : uvs) p = {u(rng), u(rng)};
    const Vec2 dx{1.5f / 256, 0}, dy{0, 1.5f / 256};
    Vec4 sum{};
    for (auto _ : state) {
        for (Vec2 p : uvs) sum = sum + tex.sample(p, dx, dy, sampler);
        benchmark::DoNotOptimize(sum);
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(uvs.size()));
    state.SetLabel(state.range(0) ? "trilinear samples" : "bilinear samples");
}
BENCHMARK(BM_TextureSample)->Arg(0)->Arg(1);

// Renderer::draw end to end (clear not included), one thread.
template <class S>
void draw_benchmark(benchmark::State& state, const S& shader, Blend blend = Blend::none) {
    const Workload& wl = sphere_workload();
    Renderer renderer(RendererConfig{.threads = static_cast<int>(state.range(0))});
    Framebuffer fb(wl.width, wl.height);
    DrawState ds;
    ds.cull = CullMode::none;
    ds.blend = blend;
    const DrawInput input{static_cast<std::uint32_t>(wl.mesh.positions.size()), wl.mesh.indices};
    for (auto _ : state) {
        state.PauseTiming();
        fb.clear({0, 0, 0, 1});
        state.ResumeTiming();
        benchmark::DoNotOptimize(renderer.draw(fb, ds, input, shader));
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(wl.mesh.indices.size() / 3));
    state.SetLabel("triangles");
}

void BM_Draw_Lambert(benchmark::State& state) { draw_benchmark(state, sphere_workload().shader); }
BENCHMARK(BM_Draw_Lambert)->Arg(1)->Arg(2)->UseRealTime();

// The one-pass order (detail::shade_tile) end to end: blending, or a shader that can discard.
void BM_Draw_LambertBlended(benchmark::State& state) { draw_benchmark(state, sphere_workload().shader, Blend::alpha); }
BENCHMARK(BM_Draw_LambertBlended)->Arg(1)->UseRealTime();

// shaders::Textured (Blinn-Phong, a 256x256 mipmapped texture, trilinear; it may discard, so
// it is drawn in one pass), uv from the sphere's positions.
void BM_Draw_Textured(benchmark::State& state) {
    const Workload& wl = sphere_workload();
    static const Texture tex = [] {
        Image img{256, 256, std::vector<Rgba8>(256 * 256)};
        for (int y = 0; y < 256; ++y)
            for (int x = 0; x < 256; ++x)
                img.at(x, y) = {static_cast<std::uint8_t>(x), static_cast<std::uint8_t>(y), static_cast<std::uint8_t>(x ^ y), 255};
        return Texture(std::move(img));
    }();
    static const std::vector<Vec2> uvs = [&] {
        std::vector<Vec2> out;
        for (const Vec3& p : wl.mesh.positions) out.push_back({p.x * 2 + 2, p.y * 2 + 2});
        return out;
    }();
    shaders::Textured shader;
    shader.mesh = wl.shader.mesh;
    shader.mesh.uvs = uvs.data();
    shader.u = wl.shader.u;
    shader.u.specular = 0.5f;
    shader.tex.texture = &tex;
    shader.tex.sampler.filter = Filter::trilinear;
    draw_benchmark(state, shader);
}
BENCHMARK(BM_Draw_Textured)->Arg(1)->UseRealTime();

void BM_Draw_Trivial(benchmark::State& state) {
    shaders::Mask mask;
    mask.mesh = sphere_workload().shader.mesh;
    mask.u = sphere_workload().shader.u;
    draw_benchmark(state, mask);
}
BENCHMARK(BM_Draw_Trivial)->Arg(1)->Arg(2)->UseRealTime();

// The fixed cost of a frame (issue 21): a clearing draw at 1920x1080 whose one triangle lies
// outside the view, so that no pixel is covered: the clear of every tile (colour alone, as
// facet_bench_scenes and facet render draw it, DrawState::keep_depth = false; arg 1: 1 with the
// depth too), the tile walk and the draw's set-up, nothing else.
void BM_Frame_NothingCovered(benchmark::State& state) {
    static const Mesh mesh = [] {
        Mesh m;
        m.positions = {{-1, -1, 5}, {1, -1, 5}, {0, 1, 5}};  // behind the camera below
        m.indices = {0, 1, 2};
        return m;
    }();
    Renderer renderer(RendererConfig{.threads = static_cast<int>(state.range(0))});
    Framebuffer fb(1920, 1080);
    Camera camera;
    camera.position = {0, 0, 3};
    camera.target = {0, 0, 0};
    shaders::LambertBaseColour shader;
    shader.mesh = MeshArrays::of(mesh);
    shader.u.clip_from_object = camera.projection(1920.0f / 1080.0f) * camera.view();
    DrawState ds;
    ds.clear = ClearValues{};
    ds.keep_depth = state.range(1) != 0;
    const DrawInput input{3, mesh.indices};
    for (auto _ : state) benchmark::DoNotOptimize(renderer.draw(fb, ds, input, shader));
    state.SetLabel(ds.keep_depth ? "colour and depth" : "colour");
}
BENCHMARK(BM_Frame_NothingCovered)->Args({1, 0})->Args({1, 1})->Args({2, 0})->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
