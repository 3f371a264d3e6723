// facet setup: culling, edge functions and attribute planes of projected, snapped triangles.
#include "setup/setup.hpp"

#include <algorithm>
#include <cmath>

namespace facet::detail {
namespace {

// Needs t's bounds.
void set_edge(TriangleSetup& t, int e, const ScreenVertex& a, const ScreenVertex& b) {
    const PixelEdge edge = pixel_edge(a.x, a.y, b.x, b.y, t.min_x, t.min_y);
    t.a[e] = edge.a;
    t.b[e] = edge.b;
    t.e0[e] = edge.at;
}

// The four attribute planes f(x, y) = f0 + dfdx (x - x0) + dfdy (y - y0) through the vertex values of
// depth, q, b1·q and b2·q. The specification, in double with coordinates in pixels (fixed point / 256):
//   dfdx = (d1 (y2 - y0) - d2 (y1 - y0)) * inv_area,  dfdy = (d2 (x1 - x0) - d1 (x2 - x0)) * inv_area,
//   d1 = f1 - f0, d2 = f2 - f0, inv_area = 1 / (area / 256²).
// Here the offsets stay in fixed-point units and inv_area is 256 / area instead: every quantity is then
// the specification's times an exact power of two (doubles of these magnitudes never reach the
// subnormal or overflow range), and rounding commutes with such scaling, so each product, difference
// and quotient rounds to the specification's value scaled, and the results are bit-identical with two
// fewer multiplications per offset and none before the division. The four planes are independent
// lanes of the same operations, which the compiler may run two at a time.
void set_planes(TriangleSetup& t, const ScreenVertex& v0, const ScreenVertex& v1, const ScreenVertex& v2,
                std::int64_t area) {
    const double x1 = v1.x - v0.x, x2 = v2.x - v0.x;
    const double y1 = v1.y - v0.y, y2 = v2.y - v0.y;
    const double inv_area = static_cast<double>(k_subpixel_one) / static_cast<double>(area);
    const double z0 = v0.z, z1 = v1.z, z2 = v2.z, q0 = v0.q, q1 = v1.q, q2 = v2.q;
    // Per plane: the values at vertices 0, 1 and 2 (b1·q is q1 at vertex 1 and 0 elsewhere, b2·q likewise).
    const double f0[4] = {z0, q0, 0.0, 0.0};
    const double f1[4] = {z1, q1, q1, 0.0};
    const double f2[4] = {z2, q2, 0.0, q2};
    float dfdx[4], dfdy[4];
    for (int k = 0; k < 4; ++k) {
        const double d1 = f1[k] - f0[k], d2 = f2[k] - f0[k];
        dfdx[k] = static_cast<float>((d1 * y2 - d2 * y1) * inv_area);
        dfdy[k] = static_cast<float>((d2 * x1 - d1 * x2) * inv_area);
    }
    constexpr double scale = 1.0 / k_subpixel_one;
    t.x0 = static_cast<float>(v0.x * scale);
    t.y0 = static_cast<float>(v0.y * scale);
    t.z0 = v0.z, t.dzdx = dfdx[0], t.dzdy = dfdy[0];
    t.q0 = v0.q, t.dqdx = dfdx[1], t.dqdy = dfdy[1];
    t.dl1dx = dfdx[2], t.dl1dy = dfdy[2];
    t.dl2dx = dfdx[3], t.dl2dy = dfdy[3];
}

}  // namespace

bool covers_no_centre_of_small_bounds(const TriangleSetup& t) {
    const int w = t.max_x - t.min_x, h = t.max_y - t.min_y;
    if (w >= k_small_bounds || h >= k_small_bounds) return false;
    for (int y = t.min_y; y <= t.max_y; ++y)
        for (int x = t.min_x; x <= t.max_x; ++x)
            if (edge_at(t, 0, x, y) >= 0 && edge_at(t, 1, x, y) >= 0 && edge_at(t, 2, x, y) >= 0) return false;
    return true;
}

SetupResult setup_triangle(const ScreenVertex (&sv)[3], const std::uint32_t (&vertex_ref)[3],
                           const FrontEndParams& params, TriangleSetup& t) {
    const std::int64_t signed_area = twice_signed_area(sv[0], sv[1], sv[2]);
    bool front = false;
    if (!kept_by_culling(signed_area, params.state, front)) return SetupResult::culled;

    // Orient so that the inside of every edge is where its function is positive. Left to a branch on
    // purpose: the windings that survive culling are almost always alike (all of them with back-face
    // culling), and indexing the vertices by the sign instead made the loads wait for the area
    // (measured slower on the sphere benchmark).
    const bool flip = signed_area < 0;
    const ScreenVertex& v0 = sv[0];
    const ScreenVertex& v1 = flip ? sv[2] : sv[1];
    const ScreenVertex& v2 = flip ? sv[1] : sv[2];
    const std::int64_t area = flip ? -signed_area : signed_area;

    const CentreBounds bounds = centre_bounds(v0, v1, v2, params.scissor);
    t.min_x = bounds.x0, t.max_x = bounds.x1, t.min_y = bounds.y0, t.max_y = bounds.y1;
    if (t.min_x > t.max_x || t.min_y > t.max_y) return SetupResult::empty;

    set_edge(t, 0, v0, v1);
    set_edge(t, 1, v1, v2);
    set_edge(t, 2, v2, v0);
    if (covers_no_centre_of_small_bounds(t)) return SetupResult::empty;
    t.small_edges = edges_fit_32_bits(t);
    set_planes(t, v0, v1, v2, area);
    t.vertex[0] = vertex_ref[0];
    t.vertex[1] = vertex_ref[flip ? 2 : 1];
    t.vertex[2] = vertex_ref[flip ? 1 : 2];
    t.front_facing = front;
    t.segment = false;
    t.line_aa = 0;
    return SetupResult::ok;
}

}  // namespace facet::detail
