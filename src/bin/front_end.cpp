// facet bin: the front end of a draw for one range of triangles (points and lines: points_lines.cpp),
// and binning into screen tiles. In: ClipVertices + indices. Out: FrontEndChunk (set-up triangles, clip-made vertices, per-tile bins).
#include "facet/detail/front_end.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include "bin/emitter.hpp"
#include "bin/points_lines.hpp"
#include "geometry/clip.hpp"
#include "geometry/project.hpp"
#include "setup/setup.hpp"

namespace facet::detail {
namespace {

// A triangle that is not wholly inside the clip volume with valid vertices: rejected, or clipped
// and its pieces emitted. Out of line: most triangles of a mesh never get here.
template <bool Primitives>
[[gnu::noinline]] void assemble_other(const ClipVertices& vertices, const std::uint32_t (&idx)[3], std::uint32_t triangle,
                                      GuardBand guard, const FrontEndParams& p, Emitter<Primitives>& emitter,
                                      FrontEndChunk& out, const ClipPassVaryings* passes) {
    const std::size_t vertex_count = vertices.pos.size();
    std::uint32_t codes[3];
    for (int k = 0; k < 3; ++k) {
        if (idx[k] >= vertex_count || vertices.outcode[idx[k]] == k_outcode_invalid) {
            ++out.stats.triangles_invalid;
            return;
        }
        codes[k] = vertices.outcode[idx[k]];
    }
    if (codes[0] & codes[1] & codes[2]) return;  // wholly outside one plane
    ++out.stats.triangles_clipped;
    const ClipVertex tri[3] = {{vertices.clip_position(idx[0]), idx[0]}, {vertices.clip_position(idx[1]), idx[1]},
                               {vertices.clip_position(idx[2]), idx[2]}};
    ClipVertex poly[k_max_clip_polygon];
    const int n = clip_triangle(tri, codes[0] | codes[1] | codes[2], guard, vertices, out.extras, poly, passes);
    bool poly_finite = true;
    for (int i = 0; i < n; ++i) poly_finite = poly_finite && is_finite(poly[i].pos) && poly[i].pos.w > 0;
    if (!poly_finite) {  // coordinates so large that the intersections overflowed
        ++out.stats.triangles_invalid;
        return;
    }
    ScreenVertex projected[k_max_clip_polygon];
    for (int i = 0; i < n; ++i) projected[i] = project(poly[i].pos, p);
    for (int i = 1; i + 1 < n; ++i) {
        const ScreenVertex v[3] = {projected[0], projected[i], projected[i + 1]};
        const std::uint32_t ref[3] = {poly[0].ref, poly[i].ref, poly[i + 1].ref};
        emitter.emit(v, ref, triangle);
    }
}

// Triangles [first, end) in order, their vertex indices from `index_of`. A triangle whose three
// vertices are in range and inside every clip plane (outcode 0; an invalid vertex's is not) joins
// the set-up batch after one test; the others go to assemble_other.
template <bool Primitives, class IndexOf>
void assemble(const ClipVertices& vertices, std::size_t first, std::size_t end, const IndexOf& index_of,
              GuardBand guard, const FrontEndParams& p, Emitter<Primitives>& emitter, FrontEndChunk& out,
              const ClipPassVaryings* passes) {
    const std::size_t vertex_count = vertices.pos.size();
    const std::uint8_t* outcode = vertices.outcode.data();
    const ScreenVertex* screen = vertices.screen.data();
    for (std::size_t t = first; t < end; ++t) {
        // Scalars, and the array only on the rare path: an array passed by reference was stored
        // to the stack for every triangle (and `screen` a local: through `vertices` its address was
        // loaded again after each of the batch's stores).
        const std::uint32_t i0 = index_of(t, 0), i1 = index_of(t, 1), i2 = index_of(t, 2);
        if (std::max({i0, i1, i2}) < vertex_count && (outcode[i0] | outcode[i1] | outcode[i2]) == 0) {
            emitter.add_unclipped(screen, i0, i1, i2, static_cast<std::uint32_t>(t));
            continue;
        }
        const std::uint32_t idx[3] = {i0, i1, i2};
        assemble_other(vertices, idx, static_cast<std::uint32_t>(t), guard, p, emitter, out, passes);
    }
}

// The chunk's first draw, its bins without memory yet: each bin's first allocation is the number
// of the chunk's triangles (every `stride`-th, counted `stride` times) inside the clip volume whose
// pixel bounds reach its tile, after the set-up's area, culling and bounds tests, with room to
// spare. The bins then rarely grow, where growth from an even share of the records doubled them:
// the records copied, and twice their memory met for the first time (the first frame's front end:
// docs/BENCHMARKS.md). Bins that get nothing keep no memory; the others grow by doubling as before.
template <bool Primitives, class IndexOf>
void size_first_bins(const ClipVertices& vertices, std::size_t first, std::size_t end, const IndexOf& index_of,
                     const FrontEndParams& p, FrontEndChunk& out) {
    const std::size_t tiles = static_cast<std::size_t>(p.tiles_x) * static_cast<std::size_t>(p.tiles_y);
    for (std::size_t t = 0; t < tiles; ++t)
        if (out.bins[t].capacity() != 0) return;
    constexpr std::size_t stride = 4;
    std::vector<std::uint32_t> count(tiles, 0);
    const int shift = std::countr_zero(static_cast<unsigned>(p.tile_size));
    const std::size_t vertex_count = vertices.pos.size();
    const std::uint8_t* outcode = vertices.outcode.data();
    const ScreenVertex* screen = vertices.screen.data();
    for (std::size_t t = first; t < end; t += stride) {
        const std::uint32_t idx[3] = {index_of(t, 0), index_of(t, 1), index_of(t, 2)};
        if (std::max({idx[0], idx[1], idx[2]}) >= vertex_count || (outcode[idx[0]] | outcode[idx[1]] | outcode[idx[2]]) != 0)
            continue;
        const ScreenVertex &a = screen[idx[0]], &b = screen[idx[1]], &c = screen[idx[2]];
        bool front = false;
        if (!kept_by_culling(twice_signed_area(a, b, c), p.state, front)) continue;
        const CentreBounds r = centre_bounds(a, b, c, p.scissor);
        if (r.x0 > r.x1 || r.y0 > r.y1) continue;
        for (int ty = r.y0 >> shift; ty <= r.y1 >> shift; ++ty)
            for (int tx = r.x0 >> shift; tx <= r.x1 >> shift; ++tx) ++count[static_cast<std::size_t>(ty) * static_cast<std::size_t>(p.tiles_x) + static_cast<std::size_t>(tx)];
    }
    for (std::size_t t = 0; t < tiles; ++t) {
        if (count[t] == 0) continue;
        // A sample's count varies by about its square root: an eighth more, and 64 records, cover that.
        const std::size_t records = std::size_t{count[t]} * stride + std::size_t{count[t]} * stride / 8 + 64;
        out.bins[t].reserve(records);
        if constexpr (Primitives) out.primitives[t].reserve(records);
    }
}

}  // namespace

void FrontEndChunk::reset(std::size_t tile_count, int stride, int pass_stride) {
    extras.pos.clear();
    extras.varyings.clear();
    extras.stride = stride;
    // Bins only grow: a renderer that draws targets of two sizes in turn (a view's supersampled
    // colour and its passes at 1x) keeps the memory of both. The tiles read only the first tile_count.
    if (bins.size() < tile_count) bins.resize(tile_count);
    for (std::size_t t = 0; t < tile_count; ++t) bins[t].clear();
    if (depth_floors.size() < tile_count) depth_floors.resize(tile_count);
    for (std::size_t t = 0; t < tile_count; ++t) depth_floors[t].clear();
    pass_extras.varyings.clear();
    pass_extras.stride = pass_stride < 0 ? 0 : pass_stride;
    if (pass_stride >= 0) {
        if (primitives.size() < tile_count) primitives.resize(tile_count);
        for (std::size_t t = 0; t < tile_count; ++t) primitives[t].clear();
    }
    stats = {};
}

namespace {

template <bool Primitives>
void run_front_end_of(const ClipVertices& vertices, const DrawInput& input, std::size_t first, std::size_t end,
                      const FrontEndParams& p, FrontEndChunk& out, const ClipPassVaryings* passes) {
    if (input.topology != Topology::triangles) {
        // Points' and lines' triangles are never culled and always front-facing (emit_triangle).
        FrontEndParams params = p;
        params.state.cull = CullMode::none;
        params.state.front_face = FrontFace::cw;
        Emitter<Primitives> emitter(params, out, end - first);
        if (input.topology == Topology::points) assemble_points(vertices, input, first, end, params, emitter, out);
        else assemble_lines(vertices, input, first, end, params, emitter, out, passes);
        emitter.finish();
        return;
    }
    const GuardBand guard = guard_band(p);
    Emitter<Primitives> emitter(p, out, end - first);
    out.stats.triangles_in += end - first;
    if (input.indices.empty()) {
        // Indices past 2^32 - 1 cannot name a vertex (vertex counts are 32-bit): they stay out of range.
        const auto index_of = [](std::size_t t, int k) {
            const std::size_t i = t * 3 + static_cast<std::size_t>(k);
            return i > 0xffffffffu ? 0xffffffffu : static_cast<std::uint32_t>(i);
        };
        size_first_bins<Primitives>(vertices, first, end, index_of, p, out);
        assemble(vertices, first, end, index_of, guard, p, emitter, out, passes);
    } else {
        const std::uint32_t* indices = input.indices.data();
        const auto index_of = [indices](std::size_t t, int k) { return indices[t * 3 + static_cast<std::size_t>(k)]; };
        size_first_bins<Primitives>(vertices, first, end, index_of, p, out);
        assemble(vertices, first, end, index_of, guard, p, emitter, out, passes);
    }
    emitter.finish();
}

}  // namespace

void run_front_end(const ClipVertices& vertices, const DrawInput& input, std::size_t first, std::size_t end,
                   const FrontEndParams& p, FrontEndChunk& out, const ClipVertices* pass_vertices) {
    if (!pass_vertices) return run_front_end_of<false>(vertices, input, first, end, p, out, nullptr);
    const ClipPassVaryings passes{*pass_vertices, out.pass_extras};
    run_front_end_of<true>(vertices, input, first, end, p, out, &passes);
}

}  // namespace facet::detail
