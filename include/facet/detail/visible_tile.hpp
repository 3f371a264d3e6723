// facet internals: VisibleTile, the hand-off from the depth pass to the shading pass, one tile at a
// time. The tile pass (src/tile/) first runs the depth test and write of every triangle binned to a
// tile, in submission order, remembering which triangle last passed at each pixel; it then hands
// the shading pass (fragment() once per visible pixel, detail/fragment.hpp, or a built-in shader's
// compiled kernel, CompiledVisiblePass) what it found: which triangle owns each pixel, which pixels
// have an owner, and per triangle its set-up record and its shading record. The shading pass reads
// this and writes colours; it neither tests depth nor sees a hidden triangle.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "facet/api.hpp"
#include "facet/detail/frame.hpp"

FACET_API_BEGIN
namespace facet::detail {

// The shading record: what the shading pass needs of one triangle in one tile, as one record of
// floats, contiguous so that SIMD kernels fetch a field of any triangle by its id
// (src/shade/visible_simd-inl.h). First the head, the set-up values fragment_at reads (a copy of
// TriangleSetup's, front-facing as 1 or 0; the barycentric planes are 0 at (x0, y0), as there: no
// field holds that 0), then the varying planes of its N varyings: v0[N], d1[N], d2[N], with
// v = v0 + b1 d1 + b2 d2 for the perspective-correct barycentrics b1 and b2.
enum ShadingHead : int { sh_x0, sh_y0, sh_q0, sh_dqdx, sh_dqdy, sh_dl1dx, sh_dl1dy, sh_dl2dx, sh_dl2dy, sh_front,
                         k_shading_head };

// Floats per shading record of a shader with `varyings` varyings.
constexpr int shading_record_floats(int varyings) { return k_shading_head + 3 * varyings; }

// Varyings in barycentric form, v = v0 + b1 d1 + b2 d2: out[0, n) = v0, out[n, 2n) = d1, out[2n, 3n) = d2.
[[gnu::always_inline]] inline void write_varying_planes(const float* const (&var)[3], int n, float* out) {
    for (int k = 0; k < n; ++k) {
        out[k] = var[0][k];
        out[n + k] = var[1][k] - var[0][k];
        out[2 * n + k] = var[2][k] - var[0][k];
    }
}

// The shading record of triangle t, whose vertices' varyings are var, into out.
// The head's two runs copied straight from the record (a few vector moves, not a load and a store
// per field); a head assembled on the stack and copied was read back before its pieces were
// stored, a store-forwarding stall.
inline void write_shading_record(const TriangleSetup& t, const float* const (&var)[3], int n, float* out) {
    static_assert(offsetof(TriangleSetup, y0) == offsetof(TriangleSetup, x0) + 4 && sh_y0 == sh_x0 + 1);
    static_assert(offsetof(TriangleSetup, dl2dy) == offsetof(TriangleSetup, q0) + 24 && sh_dl2dy == sh_q0 + 6);
    std::memcpy(out + sh_x0, &t.x0, 2 * sizeof(float));
    std::memcpy(out + sh_q0, &t.q0, 7 * sizeof(float));
    out[sh_front] = t.front_facing ? 1.0f : 0.0f;
    write_varying_planes(var, n, out + k_shading_head);
}

// Rows of the worker's empty tiles still to be cleared (src/tile/deferred_fills.hpp): the idle work.
struct DeferredFills;

// One tile after its depth pass. Triangles are named by their id: their index in the tile's list of
// the triangles that passed the depth test somewhere in it, in submission order (one that passed
// nowhere can own no pixel and is not listed). Everything here stays valid, and unchanged, until
// the shading pass of the tile returns.
struct VisibleTile {
    static constexpr std::uint32_t k_no_owner = ~0u;
    static constexpr int k_row = k_max_tile_size;  // owner entries from one row to the next

    PixelRect rect;  // the tile's pixels in the target, 1 to k_max_tile_size on each side
    // owner[r * k_row + i]: the id of the triangle visible at pixel (rect.x0 + i, rect.y0 + r), the
    // last to pass the depth test there, or k_no_owner. Entries past the tile's width hold anything:
    // read only where `covered` has a bit. Rows start on a cache line (whole aligned vectors).
    const std::uint32_t* owner;
    // covered[r] bit i: pixel (rect.x0 + i, rect.y0 + r) has an owner (0 past the width): the
    // shading pass's map of work, found once per tile from the owners.
    const std::uint64_t* covered;
    std::uint32_t count;  // triangles listed: every owner is below it
    // triangles[id]: the triangle's set-up record (its depth plane; fragment_at's inputs).
    const TriangleSetup* const* triangles;
    // records + id * record_stride: the shading record (ShadingHead) of a triangle that owns a pixel,
    // copied from its vertices so the shading pass reads one contiguous record per triangle. (Listed
    // triangles that later ones hid everywhere may have none: only owners' records are read.)
    const float* records;
    int record_stride;  // shading_record_floats(varyings)
    // The idle work of this worker: rows of empty tiles that the draw clears, written with streaming
    // stores. A compiled shading kernel, whose long chains of arithmetic leave the core's stores
    // idle, writes a few before each block it shades (stream_fill_rows, src/tile/stream_fill-inl.h);
    // the tile pass writes the rest after the tiles. Shading code that does not know it leaves it
    // alone: the image does not depend on when the rows are written. Never null.
    DeferredFills* idle;

    const float* record(std::uint32_t id) const { return records + static_cast<std::size_t>(id) * record_stride; }
};

static_assert(k_max_tile_size <= 64, "covered: a row of the tile is one 64-bit word");
static_assert(VisibleTile::k_row * sizeof(std::uint32_t) % 64 == 0,
              "owner rows whole cache lines, so aligned vectors of every ISA tile a row");

}  // namespace facet::detail
FACET_API_END
