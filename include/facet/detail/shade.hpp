// facet internals: the fragment stage, templated on the shader so fragment() inlines into the loop.
// In: a TriangleSetup, its TileCoverage and the three vertices' varyings. Per covered pixel: depth
// (linear in screen space) tested before the shader runs, perspective-correct varyings through
// q = 1/w, optional exact derivatives, the shader, then depth write and blending into the target.
// Out: pixels of the framebuffer inside this tile (the only thread that touches them).
//
// Two orders, one result. shade_tile draws a triangle's pixels as they come (needed for blending and
// discard). When neither is used, a pixel's final colour is that of the last triangle to pass the
// depth test there, so a tile is drawn in two passes instead (TileVisibility): every triangle's
// depth first, remembering which triangle last passed at each pixel, then the shader once per
// visible pixel. Depth tests and writes happen in the same order with the same values, and each
// visible pixel is shaded by the same code (fragment_at) from the same inputs, so the bytes are those
// of the one-pass order; hidden pixels are simply never shaded.
#pragma once

#include <algorithm>
#include <bit>
#include <concepts>
#include <cstdint>
#include <cstring>
#include <optional>
#include <vector>

#include "facet/api.hpp"
#include "facet/detail/frame.hpp"
#include "facet/image.hpp"

FACET_API_BEGIN
namespace facet::detail {

template <DepthTest D>
inline bool depth_passes(float z, float stored) {
    if constexpr (D == DepthTest::less) return z < stored;
    if constexpr (D == DepthTest::lequal) return z <= stored;
    if constexpr (D == DepthTest::equal) return z == stored;
    if constexpr (D == DepthTest::greater) return z > stored;
    if constexpr (D == DepthTest::always) return true;
    return false;
}

// Calls f.template operator()<D>() with the depth test `test` as a template argument (nothing for
// never): where a run-time choice becomes a compile-time one.
template <class F>
void with_depth_test(DepthTest test, F&& f) {
    switch (test) {
        case DepthTest::never: break;
        case DepthTest::less: f.template operator()<DepthTest::less>(); break;
        case DepthTest::lequal: f.template operator()<DepthTest::lequal>(); break;
        case DepthTest::equal: f.template operator()<DepthTest::equal>(); break;
        case DepthTest::greater: f.template operator()<DepthTest::greater>(); break;
        case DepthTest::always: f.template operator()<DepthTest::always>(); break;
    }
}

// The same as a run-time choice, for the compiled kernels.
inline bool depth_passes(DepthTest test, float z, float stored) {
    switch (test) {
        case DepthTest::less: return depth_passes<DepthTest::less>(z, stored);
        case DepthTest::lequal: return depth_passes<DepthTest::lequal>(z, stored);
        case DepthTest::equal: return depth_passes<DepthTest::equal>(z, stored);
        case DepthTest::greater: return depth_passes<DepthTest::greater>(z, stored);
        case DepthTest::always: return true;
        case DepthTest::never: break;
    }
    return false;
}

// Where a stage writes pixels: the framebuffer (origin 0, 0), or a tile's own buffer whose first
// pixel is (x0, y0) of the target.
struct TargetView {
    Rgba8* colour;
    float* depth;
    int stride;  // pixels per row
    int x0 = 0, y0 = 0;
    // Index of pixel (x, y), x >= x0 and y >= y0, in colour and depth.
    std::size_t at(int x, int y) const {
        return static_cast<std::size_t>(y - y0) * static_cast<std::size_t>(stride) + static_cast<std::size_t>(x - x0);
    }
};

template <class S>
constexpr bool shader_discards() {
    return std::same_as<decltype(std::declval<const S&>().fragment(std::declval<const FragmentIn<S::k_varyings>&>())),
                        std::optional<Vec4>>;
}

// Shaders may set k_shade_hidden = true to be called for every fragment that passes the depth test,
// hidden later or not (e.g. to count them); otherwise only visible pixels are shaded when possible.
template <class S>
constexpr bool shades_visible_only() {
    if constexpr (requires { S::k_shade_hidden; }) return !S::k_shade_hidden;
    return true;
}

template <class S, Blend B>
constexpr bool draws_visible_only() {
    return B == Blend::none && !shader_discards<S>() && shades_visible_only<S>();
}

// Window depth of the pixel (x, y) on triangle t, clamped to [0, 1].
inline float depth_at(const TriangleSetup& t, int x, int y) {
    const float dx = (static_cast<float>(x) + 0.5f) - t.x0, dy = (static_cast<float>(y) + 0.5f) - t.y0;
    const float z = t.z0 + t.dzdx * dx + t.dzdy * dy;
    return z < 0 ? 0 : (z > 1 ? 1 : z);
}

// Varyings in barycentric form, v = v0 + b1 d1 + b2 d2, with b1 and b2 perspective-correct:
// out[0, n) = v0, out[n, 2n) = d1, out[2n, 3n) = d2.
[[gnu::always_inline]] inline void write_varying_planes(const float* const (&var)[3], int n, float* out) {
    for (int k = 0; k < n; ++k) {
        out[k] = var[0][k];
        out[n + k] = var[1][k] - var[0][k];
        out[2 * n + k] = var[2][k] - var[0][k];
    }
}

// What the shading pass needs of one triangle in one tile, as one record of floats: the set-up
// values fragment_at reads (k_shading_head of them), then the varying planes. Contiguous floats, so
// that SIMD kernels can gather them by triangle index (src/shade/visible_simd-inl.h).
// (The barycentric planes are 0 at (x0, y0), as in TriangleSetup: no field holds that 0.)
enum ShadingHead : int { sh_x0, sh_y0, sh_q0, sh_dqdx, sh_dqdy, sh_dl1dx, sh_dl1dy, sh_dl2dx, sh_dl2dy, sh_front,
                         k_shading_head };

// Field by field: a head assembled on the stack and copied was read back before its pieces were
// stored, a store-forwarding stall (measured: 20% of the tile loop).
inline void write_shading_record(const TriangleSetup& t, const float* const (&var)[3], int n, float* out) {
    out[sh_x0] = t.x0, out[sh_y0] = t.y0;
    out[sh_q0] = t.q0, out[sh_dqdx] = t.dqdx, out[sh_dqdy] = t.dqdy;
    out[sh_dl1dx] = t.dl1dx, out[sh_dl1dy] = t.dl1dy;
    out[sh_dl2dx] = t.dl2dx, out[sh_dl2dy] = t.dl2dy;
    out[sh_front] = t.front_facing ? 1.0f : 0.0f;
    write_varying_planes(var, n, out + k_shading_head);
}

template <int N>
struct VaryingPlanes {
    float p[N > 0 ? 3 * N : 1];
    explicit VaryingPlanes(const float* const (&var)[3]) { write_varying_planes(var, N, p); }
};

// The shader's result at pixel (x, y) of triangle t, whose depth there is z: fills `in` and calls
// fragment(). Both drawing orders go through here.
template <class S>
inline auto fragment_at(const S& shader, const TriangleSetup& t, const float* planes, int x, int y, float z,
                        FragmentIn<S::k_varyings>& in) {
    constexpr int N = S::k_varyings;
    constexpr int derivative_varyings = derivative_count<S>();
    const float dx = (static_cast<float>(x) + 0.5f) - t.x0, dy = (static_cast<float>(y) + 0.5f) - t.y0;
    const float q = t.q0 + t.dqdx * dx + t.dqdy * dy;
    const float w = 1.0f / q;
    // The planes' value at (x0, y0) is 0; it is still added, so a -0 product sums to +0 as it always has.
    const float b1 = (0.0f + t.dl1dx * dx + t.dl1dy * dy) * w;
    const float b2 = (0.0f + t.dl2dx * dx + t.dl2dy * dy) * w;
    const float *v0 = planes, *d1 = planes + N, *d2 = planes + 2 * N;
    for (int k = 0; k < N; ++k) in.v[k] = v0[k] + b1 * d1[k] + b2 * d2[k];
    if constexpr (derivative_varyings > 0) {
        // d(l/q)/dx = (dl/dx - (l/q) dq/dx) / q for each perspective-correct barycentric.
        const float b1x = (t.dl1dx - b1 * t.dqdx) * w, b1y = (t.dl1dy - b1 * t.dqdy) * w;
        const float b2x = (t.dl2dx - b2 * t.dqdx) * w, b2y = (t.dl2dy - b2 * t.dqdy) * w;
        for (int k = 0; k < derivative_varyings; ++k) {
            in.ddx[k] = b1x * d1[k] + b2x * d2[k];
            in.ddy[k] = b1y * d1[k] + b2y * d2[k];
        }
    }
    in.pos_screen = {static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f};
    in.depth = z;
    in.front_facing = t.front_facing;
    return shader.fragment(in);
}

// A depth test as the set of comparison outcomes it passes (bit 1: z < stored, bit 2: equal, bit 4:
// greater, bit 0: unordered, i.e. a NaN), for depth_passes_in below.
inline std::uint32_t depth_pass_set(DepthTest test) {
    switch (test) {
        case DepthTest::less: return 1u << 1;
        case DepthTest::lequal: return 1u << 1 | 1u << 2;
        case DepthTest::equal: return 1u << 2;
        case DepthTest::greater: return 1u << 4;
        case DepthTest::always: return 1u << 0 | 1u << 1 | 1u << 2 | 1u << 4;
        case DepthTest::never: break;
    }
    return 0;
}

// depth_passes<D>(z, stored) for the D whose depth_pass_set is `pass_set`, without a branch: the
// one-pass order takes the depth test as a run-time argument, so it is not instantiated once per
// depth test (that multiplied every shader's fragment stage by five).
[[gnu::always_inline]] inline bool depth_passes_in(std::uint32_t pass_set, float z, float stored) {
    const unsigned outcome = unsigned{z < stored} | unsigned{z == stored} << 1 | unsigned{z > stored} << 2;
    return (pass_set >> outcome) & 1u;
}

// One pass: test, shade, write each covered pixel of one triangle in turn.
template <class S, bool DepthWrite, Blend B>
void shade_tile(const S& shader, DepthTest test, const TriangleSetup& t, const TileCoverage& cov, PixelRect tile,
                const float* const (&var)[3], TargetView target) {
    const VaryingPlanes<S::k_varyings> planes(var);
    FragmentIn<S::k_varyings> in;
    const std::uint32_t pass_set = depth_pass_set(test);
    for (int row = cov.first_row; row <= cov.last_row; ++row) {
        std::uint64_t mask = cov.rows[row];
        const int y = tile.y0 + row;
        Rgba8* colour_row = target.colour + static_cast<std::size_t>(y) * target.stride;
        float* depth_row = target.depth + static_cast<std::size_t>(y) * target.stride;
        while (mask) {
            const int x = tile.x0 + std::countr_zero(mask);
            mask &= mask - 1;
            const float z = depth_at(t, x, y);
            if (!depth_passes_in(pass_set, z, depth_row[x])) continue;
            Vec4 c;
            if constexpr (shader_discards<S>()) {
                const std::optional<Vec4> r = fragment_at(shader, t, planes.p, x, y, z, in);
                if (!r) continue;
                c = *r;
            } else {
                c = fragment_at(shader, t, planes.p, x, y, z, in);
            }
            if constexpr (DepthWrite) depth_row[x] = z;
            if constexpr (B == Blend::alpha) {
                const Vec4 dst = to_vec4(colour_row[x]);
                const float a = c.w > 0 ? (c.w < 1 ? c.w : 1) : 0;
                c = Vec4{c.x * a + dst.x * (1 - a), c.y * a + dst.y * (1 - a), c.z * a + dst.z * (1 - a),
                         a + dst.w * (1 - a)};
            }
            colour_row[x] = to_rgba8(c);
        }
    }
}

// Fills a row of pixels with one colour. std::fill of the 4-byte Rgba8 struct is not vectorized
// (measured: 2.5x slower than Framebuffer::clear per pixel); a fill of 32-bit words is.
inline void fill_row(Rgba8* row, int width, Rgba8 colour) {
    std::uint32_t word;
    std::memcpy(&word, &colour, sizeof(word));
    std::uint32_t words[k_max_tile_size];
    std::fill_n(words, width, word);
    std::memcpy(row, words, static_cast<std::size_t>(width) * sizeof(word));
}

// Writes the rows of `tile` in the target (4-byte values: colour or depth) from rows `rows_stride`
// values apart starting at `rows` (0: the same row every time, for a fill), to `target_origin`, rows
// `target_stride` values apart. With `stream`, rows that are whole cache lines at aligned addresses
// are written with streaming stores (SIMD, in src/raster/depth_simd.cpp): the target's lines are not
// read first, nor kept in the caches; for tiles the draw cleared, which nothing reads again in this
// draw. The others are copied. With `covered` (one 64-bit row mask per row, bit i for pixel
// tile.x0 + i), a pixel whose bit is clear is written `fill` instead of its value in `rows`.
void store_tile_rows(const void* rows, int rows_stride, void* target_origin, PixelRect tile, int target_stride,
                     bool stream, const std::uint64_t* covered = nullptr, std::uint32_t fill = 0);
template <class T>
void store_tile_rows(const T* rows, int rows_stride, T* target_origin, PixelRect tile, int target_stride, bool stream) {
    static_assert(sizeof(T) == 4);
    store_tile_rows(static_cast<const void*>(rows), rows_stride, static_cast<void*>(target_origin), tile, target_stride,
                    stream);
}
// One row of store_tile_rows, as it is specified: the values, or `fill` where `covered` (if given)
// has a clear bit.
inline void store_tile_row_reference(const std::uint32_t* from, const std::uint64_t* covered, std::uint32_t fill,
                                     std::uint32_t* to, int width) {
    if (!covered) {
        std::memcpy(to, from, static_cast<std::size_t>(width) * sizeof(std::uint32_t));
        return;
    }
    for (int i = 0; i < width; ++i) to[i] = (*covered >> i) & 1 ? from[i] : fill;
}

// Tiles of the target that the draw clears and no triangle reaches, to be filled with the clear
// colour and depth by streaming stores a row at a time, between the tile kernels' own work, instead
// of all at once. A core writes memory past its caches at a limited rate (about 40 GB/s, measured),
// and a run of such fills leaves it waiting for every line: at 1920x1080 the empty tiles around a
// model are 13 MB a frame, 0.45 ms or 11% of a mesh's frame at one thread. Written a few rows at a
// time between the blocks of the compiled shading pass (take(), then stream_fill_rows in
// src/raster/stream_fill-inl.h), they cost a fraction of that. One queue per pool worker (in
// TileVisibility): the empty tiles a worker is handed join its queue, and what is left when the
// tiles are done is written by drain_fills (all of it for shaders without a compiled pass). Only
// tiles whose every row is whole aligned cache lines are queued; the image does not depend on when
// they are written.
struct DeferredFills {
    struct Tile {
        std::uint32_t* colour;  // the tile's first colour and depth pixels in the target
        std::uint32_t* depth;
        int width, height;
    };
    // One row to write: `width` words of value `word` from `to`, 64-byte aligned, width a multiple of 16.
    struct Row {
        std::uint32_t* to;
        int width;
        std::uint32_t word;
    };
    std::vector<Tile> tiles;
    std::size_t next = 0;  // tiles[next] is being written, row `row` of colour then of depth
    int row = 0;
    int stride = 0;        // the target's row, in pixels
    std::uint32_t colour = 0, depth = 0;  // the clear values' bits
    bool streamed = false;  // rows were taken since the last fence

    // Empties the queue (it must have been drained) for a draw that clears to `c` and `z`, with room
    // for all `tile_count` tiles of the target: queueing them allocates nothing.
    void start(TargetView target, Rgba8 c, float z, std::size_t tile_count) {
        tiles.clear();
        tiles.reserve(tile_count);
        next = 0, row = 0;
        stride = target.stride;
        std::memcpy(&colour, &c, sizeof(colour));
        std::memcpy(&depth, &z, sizeof(depth));
    }
    // Whether `tile` of the target can be queued: every row whole aligned cache lines.
    static bool fits(TargetView target, PixelRect tile) {
        constexpr int k_line = 64 / sizeof(std::uint32_t);
        return (tile.x1 - tile.x0) % k_line == 0 && target.stride % k_line == 0 &&
               reinterpret_cast<std::uintptr_t>(target.colour + target.at(tile.x0, tile.y0)) % 64 == 0 &&
               reinterpret_cast<std::uintptr_t>(target.depth + target.at(tile.x0, tile.y0)) % 64 == 0;
    }
    void add(TargetView target, PixelRect tile) {
        tiles.push_back({reinterpret_cast<std::uint32_t*>(target.colour + target.at(tile.x0, tile.y0)),
                         reinterpret_cast<std::uint32_t*>(target.depth + target.at(tile.x0, tile.y0)),
                         tile.x1 - tile.x0, tile.y1 - tile.y0});
    }
    bool pending() const { return next < tiles.size(); }
    // The next row of the queue (a tile's colour rows, then its depth rows), if any, for the caller
    // to write with streaming stores (stream_fill_row).
    [[gnu::always_inline]] bool take(Row& out) {
        if (!pending()) return false;
        const Tile& t = tiles[next];
        const bool is_colour = row < t.height;
        const int r = is_colour ? row : row - t.height;
        out = {(is_colour ? t.colour : t.depth) + static_cast<std::size_t>(r) * static_cast<std::size_t>(stride),
               t.width, is_colour ? colour : depth};
        streamed = true;
        if (++row == 2 * t.height) row = 0, ++next;
        return true;
    }
};
// drain_fills writes all that is left of a queue; both end with a fence when the queue's rows were
// streamed since the last one: streaming stores are weakly ordered, so they are made visible before
// the work that wrote them is reported done (fence_fills, at the end of each tile).
void drain_fills(DeferredFills& fills);
void fence_fills(DeferredFills& fills);

struct TileVisibility;
// Sets TileVisibility::covered from the owners, with the ISA selected in facet/isa.hpp (a SIMD kernel
// in src/raster/depth_simd.cpp, or find_owned_pixels_reference).
void find_owned_pixels(TileVisibility& vis, PixelRect tile);

// A tile's triangles that are visible somewhere, in submission order, and which of them is visible
// at each pixel.
struct TileVisibility {
    static constexpr std::uint32_t k_none = ~0u;
    // The triangles that passed the depth test at some pixel of the tile when they were drawn; the
    // others cannot own a pixel, so they are not listed and their varyings are never copied.
    std::vector<const TriangleSetup*> triangles;
    // Each triangle's shading record (write_shading_record), `stride` floats apart: copied while the
    // vertices are in the cache, so the shading pass reads them from here, not from scattered vertices.
    std::vector<float> planes;
    int stride = 0;
    // Rows of owner and depth: three more than the largest tile, never inside a triangle, so that the
    // depth pass, which draws rows in groups of two (four for narrow rectangles), can load and store
    // back unchanged the rows of a group that lie past the tile (their values are never read
    // otherwise) instead of testing for them.
    static constexpr int k_rows = k_max_tile_size + 3;
    // triangles index per pixel, row-major, or k_none where no triangle passed the depth test (set
    // for the whole tile by begin(), so the depth pass need not track which pixels it touched first).
    alignas(64) std::uint32_t owner[k_rows * k_max_tile_size];
    // The tile's depth buffer during the depth pass, laid out like owner: loaded by begin(), stored
    // back by end(). Rows that start on a cache line and are 64 wide whatever the tile let the SIMD
    // kernel load and store aligned whole vectors: no split cache lines, no tile-edge special case,
    // and a load of a vector the previous triangle stored is forwarded from the store whole
    // (unaligned vectors overlapping it partly wait for the store; measured: ~10% of the pass).
    alignas(64) float depth[k_rows * k_max_tile_size];
    // The tile's colour while it is drawn, when the draw clears it (DrawState::clear): the shading
    // pass writes its covered pixels (colour_view), and store_colour() writes the finished tile to
    // the target in whole cache lines, streamed past the caches, with the clear colour where no
    // triangle is visible: the tile is never filled first, the target's old bytes are never read,
    // and each of its lines is written once. (The other pixels hold whatever the last tile left.)
    alignas(64) Rgba8 colour[k_max_tile_size * k_max_tile_size];
    Rgba8 clear_colour{};
    bool depth_cleared = false;  // begin() set depth to a clear value: end() must store it
    bool colour_cleared = false;  // begin() set colour to a clear value: store_colour() must store it
    // Per row, the pixels some triangle owns: set by end() from `owner`, once per tile, rather than
    // by the depth pass for every row of every triangle.
    std::uint64_t covered[k_max_tile_size];
    // Empty tiles this worker was handed, written between the blocks of the shading pass; mutable,
    // as that pass only reads the tile's visibility.
    mutable DeferredFills fills;

    // Room for `count` triangles with `varyings` each, so that drawing a tile of that many allocates
    // nothing.
    void reserve(std::size_t count, int varyings) {
        triangles.reserve(count);
        planes.reserve(count * static_cast<std::size_t>(k_shading_head + 3 * varyings));
    }
    struct Clear {
        Rgba8 colour;
        float depth;
    };
    // Starts a tile: its depth copied from the target, or, when the draw clears it, its depth and
    // colour set to the clear values (then the target's tile is neither read nor cleared first).
    void begin(PixelRect tile, int varyings, TargetView target, const Clear* clear = nullptr) {
        triangles.clear();
        planes.clear();
        stride = k_shading_head + 3 * varyings;
        const int width = tile.x1 - tile.x0, height = tile.y1 - tile.y0;
        depth_cleared = colour_cleared = clear != nullptr;
        if (clear) clear_colour = clear->colour;
        for (int r = 0; r < height; ++r) {
            std::fill_n(owner + r * k_max_tile_size, width, k_none);
            if (clear) {
                std::fill_n(depth + r * k_max_tile_size, width, clear->depth);
            } else {
                std::copy_n(target.depth + target.at(tile.x0, tile.y0 + r), width, depth + r * k_max_tile_size);
            }
        }
    }
    // Ends the depth pass: finds the covered pixels, and writes the tile's depth back to the target
    // when it changed (cleared by begin() or written by the depth pass, depth_write).
    void end(PixelRect tile, TargetView target, bool depth_write) {
        find_owned_pixels(*this, tile);
        if (depth_write || depth_cleared)
            store_tile_rows(depth, k_max_tile_size, target.depth + target.at(tile.x0, tile.y0), tile, target.stride,
                            depth_cleared);
    }
    // Where the shading pass writes: the tile's own colour when begin() cleared it, else the target.
    TargetView colour_view(PixelRect tile, TargetView target) {
        return colour_cleared ? TargetView{colour, nullptr, k_max_tile_size, tile.x0, tile.y0} : target;
    }
    // After the shading pass: the tile's own colour, if it has one, to the target, the clear colour
    // where no pixel was covered.
    void store_colour(PixelRect tile, TargetView target) const {
        if (!colour_cleared) return;
        std::uint32_t fill;
        std::memcpy(&fill, &clear_colour, sizeof(fill));
        store_tile_rows(colour, k_max_tile_size, target.colour + target.at(tile.x0, tile.y0), tile, target.stride, true,
                        covered, fill);
    }
    // The shading records of the triangles listed from `first` on (resolve_bin lists them), with
    // each triangle's varyings from varyings_of(t, var); those of a later triangle are fetched a few
    // triangles ahead, since a tile's triangles share vertices with triangles anywhere in the mesh.
    template <int N, class VaryingsOf>
    void write_shading_records(std::size_t first, const VaryingsOf& varyings_of) {
        constexpr std::size_t k_distance = 16;
        const std::size_t count = triangles.size();
        planes.resize(count * static_cast<std::size_t>(stride));
        for (std::size_t i = first; i < count; ++i) {
            const float* var[3];
            if (i + k_distance < count) {
                varyings_of(*triangles[i + k_distance], var);
                for (const float* v : var) prefetch(v);
            }
            varyings_of(*triangles[i], var);
            write_shading_record(*triangles[i], var, N, planes.data() + i * static_cast<std::size_t>(stride));
        }
    }
};



// Pass one, for one triangle: coverage within the tile, then the depth test (and write) at every
// covered pixel; the triangle becomes the owner (id) of each pixel where it passes.
struct DepthJob {
    const TriangleSetup* setup;
    PixelRect tile;
    TileVisibility* vis;  // depth and owner are updated; the triangle list is the caller's
    std::uint32_t id;
    DepthTest test;
    bool write;
};

// The depth test of the covered pixels, one pixel at a time. Returns true when some pixel passed.
template <DepthTest D, bool DepthWrite>
bool resolve_depth_reference(const DepthJob& job, const TileCoverage& cov) {
    const TriangleSetup& t = *job.setup;
    bool any = false;
    for (int row = cov.first_row; row <= cov.last_row; ++row) {
        std::uint64_t mask = cov.rows[row];
        const int y = job.tile.y0 + row;
        float* depth_row = job.vis->depth + row * k_max_tile_size;
        std::uint32_t* owner_row = job.vis->owner + row * k_max_tile_size;
        while (mask) {
            const int i = std::countr_zero(mask);
            mask &= mask - 1;
            const int x = job.tile.x0 + i;
            const float z = depth_at(t, x, y);
            if (!depth_passes<D>(z, depth_row[i])) continue;
            if constexpr (DepthWrite) depth_row[i] = z;
            owner_row[i] = job.id;
            any = true;
        }
    }
    return any;
}

// The scalar specification of pass one: the reference coverage, then resolve_depth_reference.
template <DepthTest D, bool DepthWrite>
bool resolve_triangle_reference(const DepthJob& job) {
    TileCoverage cov;
    if (!rasterize_tile_reference(*job.setup, job.tile, cov)) return false;
    return resolve_depth_reference<D, DepthWrite>(job, cov);
}

// The scalar specification of find_owned_pixels.
inline void find_owned_pixels_reference(TileVisibility& vis, PixelRect tile) {
    for (int row = 0; row < tile.y1 - tile.y0; ++row) {
        std::uint64_t bits = 0;
        for (int i = 0; i < tile.x1 - tile.x0; ++i)
            bits |= std::uint64_t{vis.owner[row * k_max_tile_size + i] != TileVisibility::k_none} << i;
        vis.covered[row] = bits;
    }
}

// Pass one for the ISA selected in facet/isa.hpp: a SIMD kernel that computes coverage and depth in
// one sweep (src/raster/depth_simd.cpp), or resolve_triangle_reference when "scalar" is selected.
// Same bytes either way. Returns true when the triangle passed the depth test at some pixel, i.e.
// owns pixels now; one that does not can never own any in this tile. Compiled once, not per shader.
bool resolve_triangle(const DepthJob& job);
// The function resolve_triangle calls for this depth test and write flag with the ISA selected now:
// chosen once per draw, it saves the dispatch per triangle.
using ResolveTriangleKernel = bool (*)(const DepthJob&);
ResolveTriangleKernel resolve_triangle_kernel(DepthTest test, bool write);
// Pass one over a tile's bin, `count` records in submission order: each triangle is resolved as by
// resolve_triangle with the id vis.triangles.size(), and appended to vis.triangles when it passed
// somewhere. One call per bin, not per triangle: the kernel keeps the tile's constants in registers
// and fetches the records ahead itself.
using ResolveBinKernel = void (*)(const TriangleSetup* records, std::size_t count, PixelRect tile, TileVisibility& vis);
ResolveBinKernel resolve_bin_kernel(DepthTest test, bool write);

// Pass two: the shader once per visible pixel, with the triangle that owns it. This is the scalar
// specification; built-in shaders also have SIMD kernels with the same results (CompiledVisiblePass).
// Shades the pixels of row y whose bits are set in `mask` (bit i: pixel tile.x0 + i).
template <class S>
[[gnu::always_inline]] inline void shade_visible_pixels(const S& shader, const TileVisibility& vis, PixelRect tile,
                                                        TargetView target, int y, std::uint64_t mask) {
    FragmentIn<S::k_varyings> in;
    const std::uint32_t* owner_row = vis.owner + (y - tile.y0) * k_max_tile_size;
    Rgba8* colour_row = target.colour + target.at(tile.x0, y);
    for (; mask; mask &= mask - 1) {
        const int i = std::countr_zero(mask), x = tile.x0 + i;
        const std::uint32_t owner = owner_row[i];
        if (owner == TileVisibility::k_none) continue;
        const TriangleSetup& t = *vis.triangles[owner];
        const float* planes = vis.planes.data() + static_cast<std::size_t>(owner) * vis.stride + k_shading_head;
        colour_row[i] = to_rgba8(fragment_at(shader, t, planes, x, y, depth_at(t, x, y), in));
    }
}

// Flattened: GCC otherwise keeps fragment() and to_rgba8 as calls here (measured: 10% of a bunny frame).
template <class S>
[[gnu::flatten]] void shade_visible(const S& shader, const TileVisibility& vis, PixelRect tile, TargetView target) {
    for (int y = tile.y0; y < tile.y1; ++y) shade_visible_pixels(shader, vis, tile, target, y, vis.covered[y - tile.y0]);
}

}  // namespace facet::detail
FACET_API_END
