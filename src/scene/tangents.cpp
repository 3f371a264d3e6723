// facet scene: tangents for normal mapping. In: a Mesh with normals and uvs. Out: Mesh::tangents,
// one per vertex (the rule is facet/mesh.hpp's compute_tangents). Not the normals themselves, and
// no vertex splitting: a vertex shared by mirrored uv islands gets one side (files split such
// seams anyway, since their uvs differ there).
#include <cmath>
#include <cstdint>
#include <vector>

#include "facet/mesh.hpp"
#include "scene/triangle_shapes.hpp"

namespace facet {
namespace {

// The angle at corner p between the edges to a and b (as compute_smooth_normals weighs normals).
float corner_angle(Vec3 p, Vec3 a, Vec3 b) {
    const Vec3 e1 = normalize(a - p), e2 = normalize(b - p);
    return detail::corner_acos(clamp(dot(e1, e2), -1.0f, 1.0f));
}

// Any unit vector orthogonal to unit n.
Vec3 orthogonal_to(Vec3 n) {
    const Vec3 axis = std::fabs(n.x) < 0.9f ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    return normalize(cross(cross(n, axis), n));
}

}  // namespace

void compute_tangents(Mesh& mesh) {
    const std::size_t n = mesh.positions.size();
    if (mesh.normals.size() != n || mesh.uvs.size() != n) return;
    std::vector<Vec3> t_sum(n), b_sum(n);
    for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
        const std::uint32_t idx[3] = {mesh.indices[i], mesh.indices[i + 1], mesh.indices[i + 2]};
        if (idx[0] >= n || idx[1] >= n || idx[2] >= n) continue;
        const Vec3 p0 = mesh.positions[idx[0]], p1 = mesh.positions[idx[1]], p2 = mesh.positions[idx[2]];
        const Vec2 w0 = mesh.uvs[idx[0]], w1 = mesh.uvs[idx[1]], w2 = mesh.uvs[idx[2]];
        const Vec3 e1 = p1 - p0, e2 = p2 - p0;
        const float du1 = w1.x - w0.x, dv1 = w1.y - w0.y, du2 = w2.x - w0.x, dv2 = w2.y - w0.y;
        const float r = du1 * dv2 - du2 * dv1;
        if (r == 0 || !std::isfinite(r)) continue;  // the uvs give no direction
        // P - p0 = e1 (a) + e2 (b) with (du, dv) = a (du1, dv1) + b (du2, dv2): dP/du and dP/dv.
        const Vec3 dp_du = (e1 * dv2 - e2 * dv1) / r;
        const Vec3 dp_dv = (e2 * du1 - e1 * du2) / r;
        if (!is_finite(dp_du) || !is_finite(dp_dv)) continue;
        const Vec3 p[3] = {p0, p1, p2};
        for (int k = 0; k < 3; ++k) {
            const float angle = corner_angle(p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
            if (!std::isfinite(angle)) continue;
            t_sum[idx[k]] += dp_du * angle;
            b_sum[idx[k]] -= dp_dv * angle;  // v grows down the image; the bitangent points up it
        }
    }
    mesh.tangents.resize(n);
    for (std::size_t v = 0; v < n; ++v) {
        const Vec3 normal = normalize(mesh.normals[v]);
        Vec3 t = normalize(t_sum[v] - normal * dot(normal, t_sum[v]));
        if (!(dot(t, t) > 0)) t = orthogonal_to(normal);
        const float side = dot(cross(normal, t), b_sum[v]) < 0 ? -1.0f : 1.0f;
        mesh.tangents[v] = Vec4(t, side);
    }
}

}  // namespace facet
