// facet setup: projection, snapping, culling, edge functions and attribute planes.
#include "setup/setup.hpp"

#include <algorithm>
#include <cmath>

namespace facet::detail {
namespace {

// A projected vertex widened to 64 bits for the products of setup.
struct Vertex64 {
    std::int64_t x, y;
    float z, q;
};

std::int64_t floor_div(std::int64_t n, std::int64_t d) {  // d > 0
    std::int64_t q = n / d;
    return (n % d != 0 && n < 0) ? q - 1 : q;
}

// Pixel index range whose centres (i + 0.5) lie in [lo, hi] (fixed point).
int first_centre(std::int64_t lo) { return static_cast<int>(-floor_div(-(lo - k_subpixel_one / 2), k_subpixel_one)); }
int last_centre(std::int64_t hi) { return static_cast<int>(floor_div(hi - k_subpixel_one / 2, k_subpixel_one)); }

// A plane f(x, y) = f0 + dfdx (x - x0) + dfdy (y - y0) through three vertex values.
void plane(const double (&x)[3], const double (&y)[3], double inv_area, const double (&f)[3], float& f0,
           float& dfdx, float& dfdy) {
    const double d1 = f[1] - f[0], d2 = f[2] - f[0];
    f0 = static_cast<float>(f[0]);
    dfdx = static_cast<float>((d1 * (y[2] - y[0]) - d2 * (y[1] - y[0])) * inv_area);
    dfdy = static_cast<float>((d2 * (x[1] - x[0]) - d1 * (x[2] - x[0])) * inv_area);
}

}  // namespace

ScreenVertex project(Vec4 p, const FrontEndParams& v) {
    const float q = 1.0f / p.w;
    const float sx = v.vp_x + (p.x * q + 1.0f) * (v.vp_w * 0.5f);
    const float sy = v.vp_y + (1.0f - p.y * q) * (v.vp_h * 0.5f);
    const float z = std::clamp(p.z * q, 0.0f, 1.0f);
    return {static_cast<std::int32_t>(std::lrint(sx * k_subpixel_one)),
            static_cast<std::int32_t>(std::lrint(sy * k_subpixel_one)), z, q};
}

SetupResult setup_triangle(const ScreenVertex (&sv)[3], const std::uint32_t (&vertex_ref)[3],
                           const FrontEndParams& params, TriangleSetup& t) {
    Vertex64 v[3];
    for (int i = 0; i < 3; ++i) v[i] = {sv[i].x, sv[i].y, sv[i].z, sv[i].q};
    std::uint32_t ref[3] = {vertex_ref[0], vertex_ref[1], vertex_ref[2]};

    // Twice the signed area in fixed point. Screen y grows downward, so a positive area is a
    // clockwise triangle to the viewer.
    std::int64_t area = (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[2].x - v[0].x) * (v[1].y - v[0].y);
    if (area == 0) return SetupResult::culled;
    const bool viewer_ccw = area < 0;
    const bool front = (params.state.front_face == FrontFace::ccw) == viewer_ccw;
    if ((params.state.cull == CullMode::back && !front) || (params.state.cull == CullMode::front && front))
        return SetupResult::culled;
    if (area < 0) {  // orient so that the inside of every edge is where its function is positive
        std::swap(v[1], v[2]);
        std::swap(ref[1], ref[2]);
        area = -area;
    }

    const std::int64_t min_x = std::min({v[0].x, v[1].x, v[2].x}), max_x = std::max({v[0].x, v[1].x, v[2].x});
    const std::int64_t min_y = std::min({v[0].y, v[1].y, v[2].y}), max_y = std::max({v[0].y, v[1].y, v[2].y});
    t.min_x = std::max(first_centre(min_x), params.scissor.x0);
    t.max_x = std::min(last_centre(max_x), params.scissor.x1 - 1);
    t.min_y = std::max(first_centre(min_y), params.scissor.y0);
    t.max_y = std::min(last_centre(max_y), params.scissor.y1 - 1);
    if (t.min_x > t.max_x || t.min_y > t.max_y) return SetupResult::empty;

    // Edge a->b: E(p) = A px + B py + C, positive inside. A pixel centre exactly on an edge belongs to
    // the triangle only for a top edge (horizontal, inside below) or a left edge (inside to the right).
    // With p = 256 i + 128 per axis, E = 256 (A ix + B iy) + 128 (A + B) + C, and for integers
    // 256 k + c >= 0  <=>  k + floor(c / 256) >= 0, which turns E into pixel units exactly.
    for (int e = 0; e < 3; ++e) {
        const Vertex64& a = v[e];
        const Vertex64& b = v[(e + 1) % 3];
        const std::int64_t A = a.y - b.y, B = b.x - a.x;
        const std::int64_t C = -(A * a.x + B * a.y);
        const bool top_left = A > 0 || (A == 0 && B > 0);
        const std::int64_t c = C + (top_left ? 0 : -1) + (k_subpixel_one / 2) * (A + B);
        t.a[e] = static_cast<std::int32_t>(A);
        t.b[e] = static_cast<std::int32_t>(B);
        t.c[e] = c >> k_subpixel_bits;  // arithmetic shift: floor division by 256
    }

    const double scale = 1.0 / k_subpixel_one;
    const double x[3] = {v[0].x * scale, v[1].x * scale, v[2].x * scale};
    const double y[3] = {v[0].y * scale, v[1].y * scale, v[2].y * scale};
    const double inv_area = 1.0 / (static_cast<double>(area) * scale * scale);
    t.x0 = static_cast<float>(x[0]);
    t.y0 = static_cast<float>(y[0]);
    plane(x, y, inv_area, {v[0].z, v[1].z, v[2].z}, t.z0, t.dzdx, t.dzdy);
    plane(x, y, inv_area, {v[0].q, v[1].q, v[2].q}, t.q0, t.dqdx, t.dqdy);
    plane(x, y, inv_area, {0.0, v[1].q, 0.0}, t.l1_0, t.dl1dx, t.dl1dy);
    plane(x, y, inv_area, {0.0, 0.0, v[2].q}, t.l2_0, t.dl2dx, t.dl2dy);
    for (int i = 0; i < 3; ++i) t.vertex[i] = ref[i];
    t.front_facing = front;
    return SetupResult::ok;
}

}  // namespace facet::detail
