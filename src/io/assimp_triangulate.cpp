// facet io: assimp 5.2.5's Triangulate for facet's own readers (assimp_triangulate.hpp), in the
// same float and double arithmetic as assimp's TriangulateProcess and PolyTools.
#include "io/assimp_triangulate.hpp"

#include <cmath>

#include <assimp/defs.h>
#include <assimp/vector2.inl>
#include <assimp/vector3.inl>

#include "scene/triangle_shapes.hpp"

namespace facet::io_detail {
namespace {

// PolyTools' GetArea2D and PointInTriangle2D, in their arithmetic (float differences and dot
// products, double sums).
double area_2d(const aiVector2D& v1, const aiVector2D& v2, const aiVector2D& v3) {
    return 0.5 * (v1.x * (static_cast<double>(v3.y) - v2.y) + v2.x * (static_cast<double>(v1.y) - v3.y) +
                  v3.x * (static_cast<double>(v2.y) - v1.y));
}

bool point_in_triangle_2d(const aiVector2D& p0, const aiVector2D& p1, const aiVector2D& p2, const aiVector2D& pp) {
    const aiVector2D v0 = p1 - p0, v1 = p2 - p0, v2 = pp - p0;
    double dot00 = v0 * v0, dot11 = v1 * v1;
    const double dot01 = v0 * v1, dot02 = v0 * v2, dot12 = v1 * v2;
    const double denom = dot00 * dot11 - dot01 * dot01;
    if (denom == 0.0) return false;
    const double inv = 1.0 / denom;
    dot11 = (dot11 * dot02 - dot01 * dot12) * inv;
    dot00 = (dot00 * dot12 - dot01 * dot02) * inv;
    return dot11 > 0 && dot00 > 0 && dot11 + dot00 < 1;
}

}  // namespace

int quad_start(const aiVector3D* const p[4]) {
    for (int i = 0; i < 4; ++i) {
        const aiVector3D &v0 = *p[(i + 3) % 4], &v1 = *p[(i + 2) % 4], &v2 = *p[(i + 1) % 4], &v = *p[i];
        aiVector3D left = v0 - v, diag = v1 - v, right = v2 - v;
        left.Normalize();
        diag.Normalize();
        right.Normalize();
        // corner_acos: std::acos(float) of glibc 2.36 (assimp's), with the same bits on every machine.
        const float angle = detail::corner_acos(left * diag) + detail::corner_acos(right * diag);
        if (angle > AI_MATH_PI_F) return i;
    }
    return 0;
}


bool cut_ears(const std::vector<aiVector3D>& p, std::vector<std::array<int, 3>>& out) {
    const int n = static_cast<int>(p.size());
    std::vector<aiVector3D> v(p);
    v.push_back(p[0]);
    v.push_back(p[1]);
    float sum_xy = 0, sum_yz = 0, sum_zx = 0;
    for (int k = 0; k < n; ++k) {
        sum_xy += v[k + 1].x * (v[k + 2].y - v[k].y);
        sum_yz += v[k + 1].y * (v[k + 2].z - v[k].z);
        sum_zx += v[k + 1].z * (v[k + 2].x - v[k].x);
    }
    const aiVector3D normal(sum_yz, sum_zx, sum_xy);
    const float ax = normal.x > 0 ? normal.x : -normal.x, ay = normal.y > 0 ? normal.y : -normal.y,
                az = normal.z > 0 ? normal.z : -normal.z;
    unsigned ac = 0, bc = 1;
    float inv = normal.z;
    if (ax > ay) {
        if (ax > az) ac = 1, bc = 2, inv = normal.x;
    } else if (ay > az) {
        ac = 2, bc = 0, inv = normal.y;
    }
    if (inv < 0.f) std::swap(ac, bc);
    std::vector<aiVector2D> t(static_cast<std::size_t>(n));
    std::vector<char> done(static_cast<std::size_t>(n), 0);
    for (int k = 0; k < n; ++k) t[k] = aiVector2D(p[k][ac], p[k][bc]);
    int num = n, ear = 0, prev = n - 1, next = 0;
    while (num > 3) {
        int found = 0;
        for (ear = next;; prev = ear, ear = next) {
            for (next = ear + 1; done[next >= n ? (next = 0) : next]; ++next) {
            }
            if (next < ear && ++found == 2) break;
            const aiVector2D &p1 = t[ear], &p0 = t[prev], &p2 = t[next];
            if (area_2d(p0, p1, p2) > 0) continue;  // not convex (OnLeftSideOfLine2D)
            int k = 0;
            for (; k < n; ++k)
                if (t[k] != p1 && t[k] != p2 && t[k] != p0 && point_in_triangle_2d(p0, p1, p2, t[k])) break;
            if (k != n) continue;
            break;
        }
        if (found == 2) return false;
        out.push_back({prev, ear, next});
        done[ear] = 1;
        --num;
    }
    std::array<int, 3> last{};
    int k = 0;
    for (int& c : last) {
        while (done[k]) ++k;
        c = k++;
    }
    out.push_back(last);
    return true;
}

}  // namespace facet::io_detail
