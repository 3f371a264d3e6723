// facet bin: points and line segments as screen-space records, by the rules of README.md ("Points
// and lines"). In: projected, snapped vertices. Out: pixel rectangles, segment records and (for the
// rare segment quads that are not strictly convex) triangles to the Emitter. Every decision is
// made from the draw's input alone (never from what another chunk did), in exact integer or exactly
// rounded double arithmetic, so the pixels do not depend on threads, tiles or ISA.
#include "bin/points_lines.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace facet::detail {
namespace {

// Index k of the draw: indices[k], or k itself (out-of-range values stay out of range).
struct IndexOf {
    std::span<const std::uint32_t> indices;
    std::uint32_t operator()(std::size_t k) const {
        if (!indices.empty()) return indices[k];
        return k > 0xffffffffu ? 0xffffffffu : static_cast<std::uint32_t>(k);
    }
};

// Triangle (a, b, c) to the emitter, turned so that its signed area is positive (the winding the
// point and line params take as the front), so every fragment of a point or a line is front-facing.
template <bool Primitives>
void emit_triangle(const ScreenVertex& a, const ScreenVertex& b, const ScreenVertex& c, const std::uint32_t (&ref)[3],
                   std::uint32_t primitive, Emitter<Primitives>& emitter) {
    const std::int64_t area = std::int64_t{b.x - a.x} * (c.y - a.y) - std::int64_t{c.x - a.x} * (b.y - a.y);
    if (area >= 0) {
        const ScreenVertex v[3] = {a, b, c};
        emitter.add(v, ref, primitive);
    } else {
        const ScreenVertex v[3] = {a, c, b};
        const std::uint32_t r[3] = {ref[0], ref[2], ref[1]};
        emitter.add(v, r, primitive);
    }
}

// The quad a, b, c, d (in order around it) as triangles (a, b, c) and (a, c, d): their shared
// diagonal goes by the top-left rule, so no pixel is covered twice.
template <bool Primitives>
void emit_quad(const ScreenVertex& a, const ScreenVertex& b, const ScreenVertex& c, const ScreenVertex& d,
               std::uint32_t ref_ab, std::uint32_t ref_cd, std::uint32_t primitive, Emitter<Primitives>& emitter) {
    const std::uint32_t r0[3] = {ref_ab, ref_ab, ref_cd}, r1[3] = {ref_ab, ref_cd, ref_cd};
    emit_triangle(a, b, c, r0, primitive, emitter);
    emit_triangle(a, c, d, r1, primitive, emitter);
}

// Segment a -> b with ends e0, e1 (raster/segment.hpp's segment_record) as emit_quad's two
// triangles: the quad a + e0, a - e0, b - e1, b + e1.
template <bool Primitives>
void emit_segment_quad(const ScreenVertex& a, const ScreenVertex& b, SegmentEnd e0, SegmentEnd e1, std::uint32_t ref_a,
                       std::uint32_t ref_b, std::uint32_t primitive, Emitter<Primitives>& emitter) {
    const auto corner = [](const ScreenVertex& v, std::int32_t x, std::int32_t y) { return ScreenVertex{x, y, v.z, v.q}; };
    emit_quad(corner(a, a.x + e0.ox, a.y + e0.oy), corner(a, a.x - e0.ox, a.y - e0.oy),
              corner(b, b.x - e1.ox, b.y - e1.oy), corner(b, b.x + e1.ox, b.y + e1.oy), ref_a, ref_b, primitive, emitter);
}

// Segment a -> b as one record (segment_record), or as two triangles when it says so.
template <bool Primitives>
void emit_segment(const ScreenVertex& a, const ScreenVertex& b, SegmentEnd e0, SegmentEnd e1, std::uint32_t ref_a,
                  std::uint32_t ref_b, std::uint32_t primitive, const PixelRect& scissor, Emitter<Primitives>& emitter) {
    TriangleSetup t{};
    switch (segment_record(a, b, e0, e1, ref_a, ref_b, scissor, t)) {
        case SegmentResult::record: emitter.add_segment(t, primitive); break;
        case SegmentResult::triangles: emit_segment_quad(a, b, e0, e1, ref_a, ref_b, primitive, emitter); break;
        case SegmentResult::empty: break;
    }
}

// An anti-aliased segment (PrimitiveStyle::line_aa): which of its ends are free (not a join), and
// so fade out past it.
struct LineAaEnds {
    bool free_a, free_b;
};

// Half a pixel along the segment a -> b (a != b), in 1/256 pixel: how far an anti-aliased segment's
// free ends reach past its end points (its coverage there falls from 1/2 to 0).
SegmentEnd half_pixel_along(const ScreenVertex& a, const ScreenVertex& b) {
    const double dx = static_cast<double>(b.x - a.x), dy = static_cast<double>(b.y - a.y);
    const double scale = 0.5 * k_subpixel_one / std::sqrt(dx * dx + dy * dy);
    return {static_cast<std::int32_t>(round_half_away(dx * scale)), static_cast<std::int32_t>(round_half_away(dy * scale))};
}

// Anti-aliased segment a -> b: ends e0, e1 for the band of half-width w/2 + 1/2, its free ends moved
// out by half a pixel, as one record naming its fading edges (facet/detail/line_aa.hpp: the two
// sides, and each free end), or as two triangles (no fading: full coverage) when segment_record
// says so. One at a time, in submission order: the SIMD batches make aliased records only.
template <bool Primitives>
void emit_aa_segment(const ScreenVertex& a, const ScreenVertex& b, SegmentEnd e0, SegmentEnd e1, LineAaEnds ends,
                     std::uint32_t ref_a, std::uint32_t ref_b, std::uint32_t primitive, const PixelRect& scissor,
                     Emitter<Primitives>& emitter) {
    const SegmentEnd out = half_pixel_along(a, b);
    const SegmentEnd out_a = ends.free_a ? out : SegmentEnd{}, out_b = ends.free_b ? out : SegmentEnd{};
    const ScreenVertex a_end{a.x - out_a.ox, a.y - out_a.oy, a.z, a.q}, b_end{b.x + out_b.ox, b.y + out_b.oy, b.z, b.q};
    TriangleSetup t{};
    switch (segment_record(a, b, e0, e1, ref_a, ref_b, scissor, t, out_a, out_b)) {
        case SegmentResult::record: {
            // The record's edge k runs from corner k to k + 1 counter-clockwise from a's first corner
            // (a_end + e0), which goes to a's second corner when the quad turns left there.
            const std::int64_t to_second_x = -2 * std::int64_t{e0.ox}, to_second_y = -2 * std::int64_t{e0.oy};
            const std::int64_t to_b_x = b_end.x - e1.ox - (a_end.x - e0.ox), to_b_y = b_end.y - e1.oy - (a_end.y - e0.oy);
            const bool left = to_second_x * to_b_y - to_second_y * to_b_x > 0;
            const unsigned sides = left ? 0b1010u : 0b0101u;
            const unsigned end_a = left ? 0b0001u : 0b1000u, end_b = left ? 0b0100u : 0b0010u;
            t.line_aa = static_cast<std::uint8_t>(sides | (ends.free_a ? end_a : 0u) | (ends.free_b ? end_b : 0u));
            emitter.add_segment(t, primitive);
            break;
        }
        case SegmentResult::triangles: emit_segment_quad(a_end, b_end, e0, e1, ref_a, ref_b, primitive, emitter); break;
        case SegmentResult::empty: break;
    }
}

// Unclipped segments queued in submission order and made into records a batch at a time by the SIMD
// kernel (setup_segment_lanes: segment_record's bytes), or one by one when it declines the batch.
template <bool Primitives>
class SegmentQueue {
public:
    SegmentQueue(const PixelRect& scissor, double half_width, Emitter<Primitives>& emitter)
        : scissor_(scissor), emitter_(emitter) {
        batch_.half_width = half_width;
    }

    // Segment a -> b (a != b) with these ends.
    void add(const ScreenVertex& a, const ScreenVertex& b, SegmentEnd e0, SegmentEnd e1, std::uint32_t ref_a,
             std::uint32_t ref_b, std::uint32_t primitive) {
        const int i = batch_.count;
        batch_.ox0[i] = e0.ox, batch_.oy0[i] = e0.oy, batch_.ox1[i] = e1.ox, batch_.oy1[i] = e1.oy;
        batch_.square[i] = 0;
        push(a, b, ref_a, ref_b, primitive);
    }
    // Segment a -> b (a != b) with square ends, which the kernel computes (its offsets are left as
    // they are: a square lane never reads them).
    void add_square(const ScreenVertex& a, const ScreenVertex& b, std::uint32_t ref_a, std::uint32_t ref_b,
                    std::uint32_t primitive) {
        const int i = batch_.count;
        batch_.square[i] = 1;
        push(a, b, ref_a, ref_b, primitive);
    }

    void flush() {
        if (batch_.count == 0) return;
        const auto end = [&](int i, bool first) {
            if (batch_.square[i]) return square_end(batch_.a[i], batch_.b[i], batch_.half_width);
            return first ? SegmentEnd{batch_.ox0[i], batch_.oy0[i]} : SegmentEnd{batch_.ox1[i], batch_.oy1[i]};
        };
        if (!setup_segment_lanes(batch_, scissor_, lanes_)) {
            for (int i = 0; i < batch_.count; ++i)
                emit_segment(batch_.a[i], batch_.b[i], end(i, true), end(i, false), batch_.ref_a[i], batch_.ref_b[i],
                             primitive_[i], scissor_, emitter_);
        } else {
            // The records in order, and before each quad left as triangles (rare) the records before it.
            std::uint32_t keep = lanes_.keep;
            for (std::uint32_t quads = lanes_.culled; quads != 0; quads &= quads - 1) {
                const int i = std::countr_zero(quads);
                const std::uint32_t before = keep & ((1u << i) - 1);
                emitter_.add_segments(lanes_, before, primitive_);
                keep &= ~before;
                emit_segment_quad(batch_.a[i], batch_.b[i], end(i, true), end(i, false), batch_.ref_a[i],
                                  batch_.ref_b[i], primitive_[i], emitter_);
            }
            emitter_.add_segments(lanes_, keep, primitive_);
        }
        batch_.count = 0;
    }

private:
    void push(const ScreenVertex& a, const ScreenVertex& b, std::uint32_t ref_a, std::uint32_t ref_b,
              std::uint32_t primitive) {
        const int i = batch_.count;
        batch_.a[i] = a, batch_.b[i] = b;
        batch_.ref_a[i] = ref_a, batch_.ref_b[i] = ref_b;
        primitive_[i] = primitive;
        if (++batch_.count == SegmentBatch::k_capacity) flush();
    }

    const PixelRect& scissor_;
    Emitter<Primitives>& emitter_;
    SegmentBatch batch_{};  // zeroed once: lanes past the count then always hold coordinates in range
    std::uint32_t primitive_[SegmentBatch::k_capacity];
    SetupLanes lanes_;
};

// The aliased segments from s on that assemble_lines would queue with square ends as they are (a
// line list's, mostly): both ends valid and inside every plane, apart, and joined to neither
// neighbour, which cannot join them unless the one before ends where s starts or the one after starts
// where s ends. Returns the first segment that is not one, for assemble_lines's general path. Its own
// loop: in the general one, its state spilled to the stack cost more than the work. Each index is
// read once: the next segment's first is read with this one (whether they join), and a queued
// segment is joined to neither neighbour, so the next one is not joined before it.
template <bool Primitives, class Index>
std::size_t queue_lone_segments_by(const ClipVertices& vertices, const Index& index, std::size_t s, std::size_t end,
                                   std::size_t segment_count, SegmentQueue<Primitives>& queue) {
    const std::size_t vertex_count = vertices.pos.size();
    const std::uint8_t* outcode = vertices.outcode.data();
    const ScreenVertex* screen = vertices.screen.data();
    if (s >= end) return s;
    std::uint32_t i0 = index(2 * s), i1 = index(2 * s + 1);
    if (s > 0 && index(2 * s - 1) == i0) return s;
    for (;;) {
        const bool has_next = s + 1 < segment_count;
        const std::uint32_t next0 = has_next ? index(2 * s + 2) : 0;
        if (i0 >= vertex_count || i1 >= vertex_count || (outcode[i0] | outcode[i1]) != 0) break;
        if (has_next && next0 == i1) break;
        const ScreenVertex &a = screen[i0], &b = screen[i1];
        if (a.x == b.x && a.y == b.y) break;
        queue.add_square(a, b, i0, i1, static_cast<std::uint32_t>(s));
        if (++s == end) break;
        i0 = next0, i1 = index(2 * s + 1);
    }
    return s;
}
// With the draw's indices or without (IndexOf's two cases): the index array's pointer a local that the
// queue's stores cannot change, and no test for its absence per index.
template <bool Primitives>
[[gnu::noinline]] std::size_t queue_lone_segments(const ClipVertices& vertices, const IndexOf& index_of, std::size_t s,
                                std::size_t end, std::size_t segment_count, SegmentQueue<Primitives>& queue) {
    if (index_of.indices.empty()) return queue_lone_segments_by(vertices, IndexOf{}, s, end, segment_count, queue);
    const std::uint32_t* indices = index_of.indices.data();
    return queue_lone_segments_by(vertices, [indices](std::size_t k) { return indices[k]; }, s, end, segment_count, queue);
}

// Pixels [x0, x1) x [y0, y1) (inside the scissor) with point c's depth and varyings.
template <bool Primitives>
void emit_pixels(int x0, int y0, int x1, int y1, const ScreenVertex& c, std::uint32_t ref, std::uint32_t primitive,
                 Emitter<Primitives>& emitter) {
    emitter.add_rect(PixelRect{x0, y0, x1, y1}, c, ref, primitive);
}

// A round point: the pixels whose centre lies within r = size / 2 of c (distance <= r), decided
// exactly: in fixed point the offsets are integers below 2^24, so their squares, sums and (128 size)²
// are exact in double. Rows with the same span are merged into one rectangle.
template <bool Primitives>
void emit_round_point(const ScreenVertex& c, float size, const PixelRect& scissor, std::uint32_t ref,
                      std::uint32_t primitive, Emitter<Primitives>& emitter) {
    const double radius = static_cast<double>(size) * (k_subpixel_one / 2);  // in 1/256 pixel
    const double r2 = radius * radius;
    constexpr int half = k_subpixel_one / 2;
    const int y_lo = std::max(scissor.y0, static_cast<int>(std::floor((c.y - radius - half) / k_subpixel_one)));
    const int y_hi = std::min(scissor.y1 - 1, static_cast<int>(std::ceil((c.y + radius - half) / k_subpixel_one)));
    int run_x0 = 0, run_x1 = 0, run_y0 = 0;  // the rectangle being grown: [run_x0, run_x1) from row run_y0
    const auto flush = [&](int y_end) {
        if (run_x1 > run_x0) emit_pixels(run_x0, run_y0, run_x1, y_end, c, ref, primitive, emitter);
        run_x0 = run_x1 = 0;
    };
    for (int y = y_lo; y <= y_hi; ++y) {
        const double dy = static_cast<double>(std::int64_t{y} * k_subpixel_one + half - c.y);
        const double rest = r2 - dy * dy;
        int x0 = 0, x1 = 0;  // the row's pixels [x0, x1)
        if (rest >= 0) {
            const auto inside = [&](int x) {
                const double dx = static_cast<double>(std::int64_t{x} * k_subpixel_one + half - c.x);
                return dx * dx <= rest;
            };
            const double h = std::sqrt(rest);
            int lo = static_cast<int>(std::ceil((c.x - half - h) / k_subpixel_one));
            int hi = static_cast<int>(std::floor((c.x - half + h) / k_subpixel_one));
            // sqrt and the division round: settle the ends by the exact test.
            while (inside(lo - 1)) --lo;
            while (lo <= hi && !inside(lo)) ++lo;
            while (inside(hi + 1)) ++hi;
            while (hi >= lo && !inside(hi)) --hi;
            x0 = std::max(lo, scissor.x0);
            x1 = std::min(hi + 1, scissor.x1);
            if (x1 <= x0) x0 = x1 = 0;
        }
        if (x0 != run_x0 || x1 != run_x1) {
            flush(y);
            run_x0 = x0, run_x1 = x1, run_y0 = y;
        }
    }
    flush(y_hi + 1);
}

// A square point: the pixel centres p with c - h <= p < c + h on both axes, h = size / 2 rounded to
// 1/256 pixel (left and top edges included, as the top-left rule has it).
template <bool Primitives>
void emit_square_point(const ScreenVertex& c, float size, const PixelRect& scissor, std::uint32_t ref,
                       std::uint32_t primitive, Emitter<Primitives>& emitter) {
    const std::int64_t h = round_half_away(static_cast<double>(size) * (k_subpixel_one / 2));
    // The first centre at or after c - h, and the last one before c + h (h <= 2^15: no overflow).
    const auto first = [](std::int64_t lo) { return first_centre(static_cast<std::int32_t>(lo)); };
    const auto last = [](std::int64_t hi) { return last_centre(static_cast<std::int32_t>(hi - 1)); };
    const int x0 = std::max(first(c.x - h), scissor.x0), x1 = std::min(last(c.x + h), scissor.x1 - 1);
    const int y0 = std::max(first(c.y - h), scissor.y0), y1 = std::min(last(c.y + h), scissor.y1 - 1);
    if (x0 > x1 || y0 > y1) return;
    emit_pixels(x0, y0, x1 + 1, y1 + 1, c, ref, primitive, emitter);
}

struct Vec2d {
    double x, y;
};

// The unit normal (to the left of a -> b in screen coordinates) of a segment's snapped ends; false
// when they coincide.
bool segment_normal(const ScreenVertex& a, const ScreenVertex& b, Vec2d& n) {
    const double dx = static_cast<double>(b.x - a.x), dy = static_cast<double>(b.y - a.y);
    const double length = std::sqrt(dx * dx + dy * dy);
    if (length == 0) return false;
    n = {-dy / length, dx / length};
    return true;
}

// Miter joins that reach further than this many half-widths from the shared vertex (a turn sharper
// than about 151 degrees) are not made: both segments end square there instead.
constexpr double k_miter_limit = 4.0;

// The offset, in 1/256 pixel, of the mitred corner left of the vertex shared by segments with unit
// normals na (the first) and nb (the second), for half-width h (pixels): the bisector m = na + nb
// scaled to reach h from both segments' sides, h / cos = 2h / |m|. Both segments compute it from the
// same arguments in the same order, so the corners they share are the same bits. False past the limit.
bool join_offset(Vec2d na, Vec2d nb, double h, std::int32_t& ox, std::int32_t& oy) {
    const double mx = na.x + nb.x, my = na.y + nb.y;
    const double m2 = mx * mx + my * my;
    if (m2 * k_miter_limit * k_miter_limit < 4.0) return false;  // |m| / 2 = cos < 1 / limit
    const double s = 2.0 * h / m2 * k_subpixel_one;
    ox = static_cast<std::int32_t>(round_half_away(mx * s));
    oy = static_cast<std::int32_t>(round_half_away(my * s));
    return true;
}

}  // namespace

template <bool Primitives>
void assemble_points(const ClipVertices& vertices, const DrawInput& input, std::size_t first, std::size_t end,
                     const FrontEndParams& p, Emitter<Primitives>& emitter, FrontEndChunk& out) {
    const IndexOf index_of{input.indices};
    const PrimitiveStyle& style = input.style;
    const std::size_t vertex_count = vertices.pos.size();
    out.stats.points_in += end - first;
    for (std::size_t k = first; k < end; ++k) {
        const std::uint32_t i = index_of(k);
        if (i >= vertex_count || vertices.outcode[i] == k_outcode_invalid) {
            ++out.stats.points_invalid;
            continue;
        }
        if (vertices.outcode[i] != 0) continue;  // the centre is outside the view volume (or the guard band)
        const ScreenVertex& c = vertices.screen[i];
        const float size = style.model_scale > 0
                               ? std::min(style.point_size * style.model_scale * c.q, PrimitiveStyle::k_max_point_size)
                               : style.point_size;
        const auto primitive = static_cast<std::uint32_t>(k);
        if (style.point_shape == PointShape::square) emit_square_point(c, size, p.scissor, i, primitive, emitter);
        else emit_round_point(c, size, p.scissor, i, primitive, emitter);
    }
}

template <bool Primitives>
void assemble_lines(const ClipVertices& vertices, const DrawInput& input, std::size_t first, std::size_t end,
                    const FrontEndParams& p, Emitter<Primitives>& emitter, FrontEndChunk& out,
                    const ClipPassVaryings* passes) {
    const IndexOf index_of{input.indices};
    const std::size_t vertex_count = vertices.pos.size(), segment_count = input.primitive_count();
    const GuardBand guard = guard_band(p);
    // Anti-aliased, the quads are those of the band half a pixel wider on each side (line_aa.hpp).
    const bool aa = input.style.line_aa;
    const double h = 0.5 * static_cast<double>(input.style.line_width) + (aa ? 0.5 : 0.0);
    out.stats.segments_in += end - first;
    // Segment s's ends when both are valid and inside every plane (only such segments join), and its normal.
    const auto unclipped = [&](std::size_t s, std::uint32_t& i0, std::uint32_t& i1, Vec2d& n) {
        i0 = index_of(2 * s), i1 = index_of(2 * s + 1);
        return i0 < vertex_count && i1 < vertex_count && (vertices.outcode[i0] | vertices.outcode[i1]) == 0 &&
               segment_normal(vertices.screen[i0], vertices.screen[i1], n);
    };
    // Whether segment s's end is segment s + 1's start, both unclipped: a join of a strip.
    const auto joins_next = [&](std::size_t s) {
        if (s + 1 >= segment_count || index_of(2 * s + 1) != index_of(2 * s + 2)) return false;
        std::uint32_t j0, j1;
        Vec2d m;
        return unclipped(s, j0, j1, m) && unclipped(s + 1, j0, j1, m);
    };
    // The last and the first segment of the run of joined segments through s. A run whose last
    // segment ends where its first begins is a loop, closed by a join like the others. Each run is
    // walked by its own ends only (its first segment, its last), so the work stays linear.
    const auto run_last = [&](std::size_t s) {
        while (joins_next(s)) ++s;
        return s;
    };
    const auto run_first = [&](std::size_t s) {
        while (s > 0 && joins_next(s - 1)) --s;
        return s;
    };
    SegmentQueue<Primitives> queue(p.scissor, h, emitter);
    for (std::size_t s = first; s < end; ++s) {
        if (!aa && (s = queue_lone_segments(vertices, index_of, s, end, segment_count, queue)) == end) break;
        std::uint32_t i0 = index_of(2 * s), i1 = index_of(2 * s + 1);
        if (i0 >= vertex_count || i1 >= vertex_count || vertices.outcode[i0] == k_outcode_invalid ||
            vertices.outcode[i1] == k_outcode_invalid) {
            ++out.stats.segments_invalid;
            continue;
        }
        const std::uint32_t codes = vertices.outcode[i0] | vertices.outcode[i1];
        if (vertices.outcode[i0] & vertices.outcode[i1]) continue;  // wholly outside one plane
        ScreenVertex a, b;
        Vec2d n{};
        SegmentEnd e0{}, e1{};
        if (codes == 0) {
            a = vertices.screen[i0], b = vertices.screen[i1];
            if (a.x == b.x && a.y == b.y) continue;  // no direction (segment_normal)
            const bool joined_before = s > 0 && joins_next(s - 1), joined_after = joins_next(s);
            if (!joined_before && !joined_after) {  // a lone segment (most of a line list's)
                if (aa) {
                    e0 = square_end(a, b, h);
                    emit_aa_segment(a, b, e0, e0, {true, true}, i0, i1, static_cast<std::uint32_t>(s), p.scissor, emitter);
                } else {
                    queue.add_square(a, b, i0, i1, static_cast<std::uint32_t>(s));
                }
                continue;
            }
            segment_normal(a, b, n);
            std::uint32_t j0, j1;
            Vec2d m;
            // The join before: with the previous segment, or for the first segment of a run that
            // closes (a loop) with the run's last one.
            bool mitred = false;
            if (joined_before) mitred = unclipped(s - 1, j0, j1, m) && join_offset(m, n, h, e0.ox, e0.oy);
            else if (const std::size_t e = run_last(s); unclipped(e, j0, j1, m) && j1 == i0)
                mitred = join_offset(m, n, h, e0.ox, e0.oy);
            if (!mitred) e0 = square_end(a, b, h);
            const bool free_a = !mitred;
            mitred = false;
            if (joined_after) mitred = unclipped(s + 1, j0, j1, m) && join_offset(n, m, h, e1.ox, e1.oy);
            else if (const std::size_t f = run_first(s); unclipped(f, j0, j1, m) && j0 == i1)
                mitred = join_offset(n, m, h, e1.ox, e1.oy);
            if (!mitred) e1 = square_end(a, b, h);
            if (aa) emit_aa_segment(a, b, e0, e1, {free_a, !mitred}, i0, i1, static_cast<std::uint32_t>(s), p.scissor, emitter);
            else queue.add(a, b, e0, e1, i0, i1, static_cast<std::uint32_t>(s));
        } else {
            queue.flush();  // records keep submission order
            ++out.stats.triangles_clipped;
            ClipVertex ca{vertices.clip_position(i0), i0}, cb{vertices.clip_position(i1), i1};
            if (!clip_segment(ca, cb, codes, guard, vertices, out.extras, passes)) continue;
            if (!is_finite(ca.pos) || !is_finite(cb.pos) || !(ca.pos.w > 0) || !(cb.pos.w > 0)) {
                ++out.stats.segments_invalid;
                continue;
            }
            a = project(ca.pos, p), b = project(cb.pos, p);
            if (a.x == b.x && a.y == b.y) continue;
            e0 = e1 = square_end(a, b, h);
            if (aa) emit_aa_segment(a, b, e0, e1, {true, true}, ca.ref, cb.ref, static_cast<std::uint32_t>(s), p.scissor, emitter);
            else emit_segment(a, b, e0, e1, ca.ref, cb.ref, static_cast<std::uint32_t>(s), p.scissor, emitter);
        }
    }
    queue.flush();
}

template void assemble_points<false>(const ClipVertices&, const DrawInput&, std::size_t, std::size_t,
                                     const FrontEndParams&, Emitter<false>&, FrontEndChunk&);
template void assemble_points<true>(const ClipVertices&, const DrawInput&, std::size_t, std::size_t,
                                    const FrontEndParams&, Emitter<true>&, FrontEndChunk&);
template void assemble_lines<false>(const ClipVertices&, const DrawInput&, std::size_t, std::size_t,
                                    const FrontEndParams&, Emitter<false>&, FrontEndChunk&, const ClipPassVaryings*);
template void assemble_lines<true>(const ClipVertices&, const DrawInput&, std::size_t, std::size_t,
                                   const FrontEndParams&, Emitter<true>&, FrontEndChunk&, const ClipPassVaryings*);

}  // namespace facet::detail
