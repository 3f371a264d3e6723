// facet tile pass: the render passes of a draw (DrawPasses, facet/passes.hpp), written from the
// same visibility as the colour. In: per vertex the pass varyings (the pass vertex stage: world
// normal, uv), per set-up record the index of its triangle (the front end's primitives), per tile
// the VisibleTile its depth pass found. Per listed triangle a pass record (its primitive, face
// normal and pass varying planes, as the shading record holds the shader's), then per visible pixel
// depth, range, normal, ids and uv into the pass targets. Out: the targets' pixels of the tile.
// Does not decide visibility (depth_pass.hpp) nor touch colour.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "facet/detail/front_end.hpp"
#include "facet/detail/visible_tile.hpp"
#include "facet/passes.hpp"

namespace facet::detail {

struct TileBuffers;

// Which pass varyings a draw's vertices carry: the world normal when the normal pass is wanted and
// the mesh has normals, the uv when the uv pass is wanted and the mesh has uvs.
struct PassLayout {
    int normal_at = -1, uv_at = -1;  // first float of each, -1 when absent
    int count = 0;                   // floats per vertex
    bool face_normals = false;       // the normal pass from each triangle's face (no vertex normals)
    bool rotate_normals = false;     // DrawPasses::normal_space is not the identity
};
PassLayout pass_layout(const DrawPasses& passes);

// A triangle's pass record in a tile, floats: the head, then its pass varyings in barycentric form
// (v0[N], d1[N], d2[N], as the shading record's varyings: write_varying_planes).
enum PassHead : int { ph_primitive, ph_face_x, ph_face_y, ph_face_z, k_pass_head };
constexpr int pass_record_floats(int varyings) { return k_pass_head + 3 * varyings; }

// What the tile pass knows of a draw's passes.
struct PassDraw {
    const DrawPasses* passes = nullptr;  // null: the draw has none
    PassLayout layout;
    const ClipVertices* vertices = nullptr;    // the pass vertex stage's output
    std::span<const std::uint32_t> indices;    // the draw's (empty: consecutive triples)
    FrontFace front_face = FrontFace::ccw;
    int stride = 0;  // pixels per row of the targets
    Topology topology = Topology::triangles;  // points and lines have no face normal (0, 0, 0)
};

// A Renderer's render passes: the current draw's (valid during its draw), and the pass vertex
// stage's output, kept between draws.
struct PassState {
    PassDraw draw;
    ClipVertices vertices;
};

// The pass vertex stage for vertices [begin, end): their pass varyings into `out` (sized by the
// caller), the normal as the built-in shaders' vertex() computes it (normal_to_world * n, not
// normalized; transform_directions, the same bits).
void run_pass_vertex_stage(const DrawPasses& passes, const PassLayout& layout, std::size_t begin, std::size_t end,
                           ClipVertices& out);

// The pass records of the tile's listed triangles from `first` on, all from `bin` of `chunk`, whose
// triangle indices are `primitives` (beside the bin's records).
void write_pass_records(TileBuffers& buffers, std::size_t first, const PassDraw& draw, const FrontEndChunk& chunk,
                        const TileBin& bin, const std::vector<std::uint32_t>& primitives);

// One row of every pass, where the rows of a tile that the draw clears are assembled before they go
// to the targets, so that each of the targets' lines is written once, whole, and never read.
struct PassRow {
    alignas(64) float alpha[k_max_tile_size];
    alignas(64) float depth[k_max_tile_size];
    alignas(64) float range[k_max_tile_size];
    alignas(64) Vec3 normal[k_max_tile_size];
    alignas(64) std::uint32_t instance[k_max_tile_size];
    alignas(64) std::uint32_t material[k_max_tile_size];
    alignas(64) std::uint32_t primitive[k_max_tile_size];
    alignas(64) Vec2 uv[k_max_tile_size];
};

// Where one row's pixels of the passes go, pixel i at [i] of each (null: a pass not wanted).
struct PassOut {
    float *alpha, *depth, *range;
    Vec3* normal;
    std::uint32_t *instance, *material, *primitive;
    Vec2* uv;
};

// f(a's row, b's row, 4-byte values per pixel) for each pass, a's and b's pointers to the same pass
// (null where it is not wanted).
template <class F>
void for_each_pass(const PassOut& a, const PassOut& b, F&& f) {
    f(a.alpha, b.alpha, 1), f(a.depth, b.depth, 1), f(a.range, b.range, 1), f(a.normal, b.normal, 3);
    f(a.instance, b.instance, 1), f(a.material, b.material, 1), f(a.primitive, b.primitive, 1), f(a.uv, b.uv, 2);
}

// Pixels [begin, end) of `o` set to the background.
void fill_pass_background(const PassOut& o, int begin, int end);

// The specification of a pass pixel: pixel i of row r of the tile (visible: it has an owner) into
// [i] of `out`, every pass the targets want, as fragment_at computes the varyings.
void write_pass_pixel(const VisibleTile& tile, const float* records, int record_stride, const PassDraw& draw, int r,
                      int i, const PassOut& out);

// Row r of the tile as write_pass_pixels writes it into `out`, its visible pixels `pixels` (the
// row's covered bits), with `whole` every other pixel of the row the background too: a SIMD kernel
// for the selected ISA (passes_simd.cpp), the same bytes as write_pass_pixel per pixel. With
// `stream` (and `whole`: `out` is then a row buffer), when each of its rows is whole aligned cache
// lines the row goes straight to them with streaming stores, not fenced, and it returns true
// (`out` then holds nothing of it); otherwise it returns false.
bool write_pass_row(const VisibleTile& tile, const float* records, int record_stride, const PassDraw& draw, int r,
                    std::uint64_t pixels, const PassOut& out, bool whole, const PassOut* stream = nullptr);

// The visible pixels of the tile into the pass targets: each from the triangle that owns it, its
// set-up record (q, the barycentric planes, window depth) and its pass record. Without `rows` the
// other pixels are left as they are; with them (a tile the draw clears) every pixel of the tile is
// written, the background where no triangle is visible, row by row through `rows`, with streaming
// stores where the targets' rows allow (tile_store.hpp).
void write_pass_pixels(const VisibleTile& tile, const float* records, int record_stride, const PassDraw& draw,
                       PassRow* rows = nullptr);

// Every pixel of `rect` set to the passes' background values; with `stream`, as store_tile_rows
// streams.
void clear_pass_targets(const PassTargets& targets, PixelRect rect, int stride, bool stream = false);

}  // namespace facet::detail
