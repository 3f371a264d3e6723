// facet bin: the front end of a draw for one range of triangles, and binning into screen tiles.
// In: ClipVertices + indices. Out: FrontEndChunk (set-up triangles, clip-made vertices, per-tile bins).
#include "facet/detail/front_end.hpp"

#include <algorithm>
#include <cmath>

#include "geometry/clip.hpp"
#include "setup/setup.hpp"

namespace facet::detail {
namespace {

// True when the edge function is negative over the whole rectangle (no pixel of it is inside).
bool edge_rejects(const TriangleSetup& t, int e, const PixelRect& r) {
    // The largest value of a*x + b*y + c over the rectangle is at the corner its gradient points to.
    const std::int64_t x = t.a[e] > 0 ? r.x1 - 1 : r.x0;
    const std::int64_t y = t.b[e] > 0 ? r.y1 - 1 : r.y0;
    return t.a[e] * x + t.b[e] * y + t.c[e] < 0;
}

void bin_triangle(const TriangleSetup& t, std::uint32_t index, const FrontEndParams& p, FrontEndChunk& out) {
    const int s = p.tile_size;
    const int tx0 = t.min_x / s, tx1 = t.max_x / s, ty0 = t.min_y / s, ty1 = t.max_y / s;
    const bool single = tx0 == tx1 && ty0 == ty1;
    for (int ty = ty0; ty <= ty1; ++ty)
        for (int tx = tx0; tx <= tx1; ++tx) {
            if (!single) {
                const PixelRect r{tx * s, ty * s, tx * s + s, ty * s + s};
                if (edge_rejects(t, 0, r) || edge_rejects(t, 1, r) || edge_rejects(t, 2, r)) continue;
            }
            out.bins[static_cast<std::size_t>(ty) * p.tiles_x + tx].push_back(index);
        }
}

void emit(const ClipVertex (&tri)[3], const FrontEndParams& p, FrontEndChunk& out) {
    TriangleSetup t;
    switch (setup_triangle(tri, p, t)) {
        case SetupResult::culled: ++out.stats.triangles_culled; return;
        case SetupResult::empty: return;
        case SetupResult::ok: break;
    }
    const auto index = static_cast<std::uint32_t>(out.triangles.size());
    out.triangles.push_back(t);
    ++out.stats.triangles_rasterized;
    bin_triangle(t, index, p, out);
}

bool finite(Vec4 p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(p.w); }

}  // namespace

void FrontEndChunk::reset(std::size_t tile_count, int stride) {
    triangles.clear();
    extras.pos.clear();
    extras.varyings.clear();
    extras.stride = stride;
    if (bins.size() != tile_count) bins.resize(tile_count);
    for (auto& bin : bins) bin.clear();
    stats = {};
}

void run_front_end(const ClipVertices& vertices, const DrawInput& input, std::size_t first, std::size_t end,
                   const FrontEndParams& p, FrontEndChunk& out) {
    const GuardBand guard{k_guard_band_pixels / (p.vp_w * 0.5f), k_guard_band_pixels / (p.vp_h * 0.5f)};
    const bool indexed = !input.indices.empty();
    const std::size_t vertex_count = vertices.pos.size();
    for (std::size_t t = first; t < end; ++t) {
        ++out.stats.triangles_in;
        ClipVertex tri[3];
        bool valid = true;
        for (int k = 0; k < 3; ++k) {
            const std::size_t i = indexed ? input.indices[t * 3 + k] : t * 3 + k;
            if (i >= vertex_count || !finite(vertices.pos[i])) {
                valid = false;
                break;
            }
            tri[k] = {vertices.pos[i], static_cast<std::uint32_t>(i)};
        }
        if (!valid) {
            ++out.stats.triangles_invalid;
            continue;
        }
        const std::uint32_t c0 = outcode(tri[0].pos, guard), c1 = outcode(tri[1].pos, guard),
                            c2 = outcode(tri[2].pos, guard);
        if (c0 & c1 & c2) continue;  // wholly outside one plane
        if ((c0 | c1 | c2) == 0) {
            emit(tri, p, out);
            continue;
        }
        ++out.stats.triangles_clipped;
        ClipVertex poly[k_max_clip_polygon];
        const int n = clip_triangle(tri, c0 | c1 | c2, guard, vertices, out.extras, poly);
        bool poly_finite = true;
        for (int i = 0; i < n; ++i) poly_finite = poly_finite && finite(poly[i].pos) && poly[i].pos.w > 0;
        if (!poly_finite) {  // coordinates so large that the intersections overflowed
            ++out.stats.triangles_invalid;
            continue;
        }
        for (int i = 1; i + 1 < n; ++i) {
            const ClipVertex fan[3] = {poly[0], poly[i], poly[i + 1]};
            emit(fan, p, out);
        }
    }
}

}  // namespace facet::detail
