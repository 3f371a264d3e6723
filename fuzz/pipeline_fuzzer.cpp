// Fuzz target: the rasterization pipeline (vertex stage, clipping, setup, binning, coverage,
// fragment stage) fed hostile triangles. The bytes choose a small framebuffer, a thread count and
// tile size, up to three draws with random DrawState (culling, winding, depth test and write,
// blending, viewport), random matrices and clip-space positions that include NaN, +-inf, +-1e38,
// denormals, zero and negative w, random varyings, and indices including out-of-range ones.
// A finding is a crash, a sanitizer report, or a broken promise of the API, each checked here:
//   - the depth buffer holds only finite values in [0, 1];
//   - the image and depth are the same bytes as the same draws with 1 thread and 64-pixel tiles;
//   - draw throws FacetError exactly for an invalid viewport; the stats add up (within what
//     clipping can add: a triangle cut by the seven planes fans into at most eight).
#include <fuzzer/FuzzedDataProvider.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "facet/math/mat.hpp"
#include "facet/renderer.hpp"

namespace {

using namespace facet;

void check(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "pipeline_fuzzer: %s\n", what);
        std::abort();
    }
}

// Mostly ordinary values, often the hostile ones.
float any_float(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegralInRange<int>(0, 15)) {
        case 0: return std::numeric_limits<float>::quiet_NaN();
        case 1: return std::numeric_limits<float>::infinity();
        case 2: return -std::numeric_limits<float>::infinity();
        case 3: return 1e38f;
        case 4: return -1e38f;
        case 5: return std::numeric_limits<float>::denorm_min();
        case 6: return -std::numeric_limits<float>::denorm_min() * 3;
        case 7: return 0.0f;
        case 8: return -0.0f;
        case 9: return std::bit_cast<float>(in.ConsumeIntegral<std::uint32_t>());
        case 10: return in.ConsumeFloatingPointInRange<float>(-1e6f, 1e6f);
        default: return in.ConsumeFloatingPointInRange<float>(-2.0f, 2.0f);
    }
}

Mat4 any_matrix(FuzzedDataProvider& in) {
    if (in.ConsumeBool()) return Mat4::identity();
    Mat4 m;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m(r, c) = in.ConsumeBool() ? any_float(in) : (r == c ? 1.0f : 0.0f);
    return m;
}

struct Geometry {
    std::vector<Vec4> positions;
    std::vector<std::array<float, 4>> varyings;
    std::vector<std::uint32_t> indices;
};

template <bool Derivatives>
struct FuzzShader {
    static constexpr int k_varyings = 4;
    static constexpr bool k_derivatives = Derivatives;
    const Geometry* g;
    Mat4 m;
    bool discard_negative;
    Vec4 vertex(std::uint32_t i, Varyings<4>& out) const {
        for (int k = 0; k < 4; ++k) out[k] = g->varyings[i][static_cast<std::size_t>(k)];
        return m * g->positions[i];
    }
    std::optional<Vec4> fragment(const FragmentIn<4>& in) const {
        if (discard_negative && in.v[3] < 0) return std::nullopt;
        Vec4 c = in.v.vec4(0);
        if constexpr (Derivatives) c.x += in.ddx[0] + in.ddy[1];
        c.y += in.depth;
        if (!in.front_facing) c.z = 1 - c.z;
        return c;
    }
};

struct Draw {
    DrawState state;
    Mat4 m;
    bool derivatives = false, discard_negative = false;
    bool viewport_valid = true;
};

Renderer& renderer_for(int threads, int tile_size) {
    static std::map<std::pair<int, int>, std::unique_ptr<Renderer>> cache;
    auto& r = cache[{threads, tile_size}];
    if (!r) r = std::make_unique<Renderer>(RendererConfig{.threads = threads, .tile_size = tile_size});
    return *r;
}

// Runs the draws; returns the stats of each (nullopt where draw threw FacetError).
std::vector<std::optional<DrawStats>> run(Renderer& r, Framebuffer& fb, const Geometry& g, const std::vector<Draw>& draws,
                                          std::uint32_t vertex_count) {
    std::vector<std::optional<DrawStats>> stats;
    for (const Draw& d : draws) {
        const DrawInput input{vertex_count, g.indices};
        try {
            if (d.derivatives)
                stats.push_back(r.draw(fb, d.state, input, FuzzShader<true>{&g, d.m, d.discard_negative}));
            else
                stats.push_back(r.draw(fb, d.state, input, FuzzShader<false>{&g, d.m, d.discard_negative}));
        } catch (const FacetError& e) {
            check(e.error().code == ErrorCode::invalid_argument, "draw threw an error that is not invalid_argument");
            stats.push_back(std::nullopt);
        }
    }
    return stats;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    FuzzedDataProvider in(data, size);
    const int width = in.ConsumeIntegralInRange(1, 80), height = in.ConsumeIntegralInRange(1, 80);
    const int threads = in.ConsumeIntegralInRange(1, 4);
    const int tile_size = 8 << in.ConsumeIntegralInRange(0, 3);
    const float clear_depth = in.PickValueInArray({1.0f, 0.5f, 0.0f});

    std::vector<Draw> draws(in.ConsumeIntegralInRange(1, 3));
    for (Draw& d : draws) {
        d.state.cull = static_cast<CullMode>(in.ConsumeIntegralInRange(0, 2));
        d.state.front_face = static_cast<FrontFace>(in.ConsumeIntegralInRange(0, 1));
        d.state.depth_test = static_cast<DepthTest>(in.ConsumeIntegralInRange(0, 5));
        d.state.depth_write = in.ConsumeBool();
        d.state.blend = static_cast<Blend>(in.ConsumeIntegralInRange(0, 1));
        if (in.ConsumeIntegralInRange(0, 3) == 0) {
            Rect& v = d.state.viewport;
            v.x = in.ConsumeIntegralInRange(-2, width + 8);
            v.y = in.ConsumeIntegralInRange(-2, height + 8);
            v.width = in.ConsumeBool() ? k_max_target_size - v.x + in.ConsumeIntegralInRange(-1, 1)
                                       : in.ConsumeIntegralInRange(-1, width + 8);
            v.height = in.ConsumeIntegralInRange(-1, height + 8);
            d.viewport_valid = (v.width == 0 && v.height == 0) ||
                               (v.width > 0 && v.height > 0 && v.x >= 0 && v.y >= 0 && v.x + v.width <= k_max_target_size &&
                                v.y + v.height <= k_max_target_size);
        }
        d.m = any_matrix(in);
        d.derivatives = in.ConsumeBool();
        d.discard_negative = in.ConsumeBool();
    }

    Geometry g;
    const auto vertex_count = in.ConsumeIntegralInRange<std::uint32_t>(0, 48);
    for (std::uint32_t i = 0; i < vertex_count; ++i) {
        g.positions.push_back({any_float(in), any_float(in), any_float(in), in.ConsumeBool() ? 1.0f : any_float(in)});
        g.varyings.push_back({any_float(in), any_float(in), any_float(in), any_float(in)});
    }
    if (in.ConsumeBool()) {
        const std::size_t n = in.ConsumeIntegralInRange<std::size_t>(0, 96);
        for (std::size_t i = 0; i < n && in.remaining_bytes() > 0; ++i)
            g.indices.push_back(in.ConsumeBool() ? in.ConsumeIntegral<std::uint32_t>()
                                                 : in.ConsumeIntegralInRange<std::uint32_t>(0, vertex_count + 2));
    }
    // With no indices, the vertices are read as consecutive triples.
    const std::uint64_t expected_triangles = g.indices.empty() ? vertex_count / 3 : g.indices.size() / 3;

    Framebuffer fb(width, height), reference(width, height);
    fb.clear({0.2f, 0.3f, 0.4f, 1.0f}, clear_depth);
    reference.clear({0.2f, 0.3f, 0.4f, 1.0f}, clear_depth);
    const auto stats = run(renderer_for(threads, tile_size), fb, g, draws, vertex_count);
    const auto ref_stats = run(renderer_for(1, 64), reference, g, draws, vertex_count);

    for (std::size_t i = 0; i < draws.size(); ++i) {
        check(stats[i].has_value() == draws[i].viewport_valid, "draw threw for a valid viewport, or not for an invalid one");
        if (!stats[i]) continue;
        const DrawStats& s = *stats[i];
        check(s.triangles_in == expected_triangles, "triangles_in is not the number of triangles given");
        check(s.triangles_invalid <= s.triangles_in, "more triangles invalid than given");
        // Culled and rasterized count after clipping, which fans one triangle into at most 7 + 1.
        check(s.triangles_culled + s.triangles_rasterized <= 8 * (s.triangles_in - s.triangles_invalid),
              "more triangles culled and rasterized than clipping can make");
        check(s.triangles_clipped <= s.triangles_in, "more triangles clipped than given");
        const DrawStats& r = *ref_stats[i];
        check(s.triangles_in == r.triangles_in && s.triangles_invalid == r.triangles_invalid &&
                  s.triangles_culled == r.triangles_culled && s.triangles_clipped == r.triangles_clipped &&
                  s.triangles_rasterized == r.triangles_rasterized,
              "stats depend on the thread count or tile size");
    }
    const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    for (std::size_t i = 0; i < pixels; ++i) {
        const float d = fb.depth_data()[i];
        check(std::isfinite(d) && d >= 0.0f && d <= 1.0f, "depth buffer value not finite or outside [0, 1]");
    }
    check(std::memcmp(fb.colour_data(), reference.colour_data(), pixels * sizeof(Rgba8)) == 0,
          "colour differs from the 1-thread, 64-pixel-tile render");
    check(std::memcmp(fb.depth_data(), reference.depth_data(), pixels * sizeof(float)) == 0,
          "depth differs from the 1-thread, 64-pixel-tile render");
    return 0;
}
