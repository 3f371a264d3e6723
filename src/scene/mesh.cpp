// facet scene: Mesh basics (validation, bounds, appending), smooth and flat normals, and the built-in
// shape generators. Creased normals are in creased_normals.cpp.
#include "facet/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "math/portable_trig.hpp"
#include "scene/triangle_shapes.hpp"

namespace facet {

Status Mesh::validate() const {
    const std::size_t n = positions.size();
    auto bad = [](const std::string& what) { return Error{ErrorCode::invalid_argument, "mesh: " + what}; };
    if (!normals.empty() && normals.size() != n) return bad("normals and positions differ in count");
    if (!colours.empty() && colours.size() != n) return bad("colours and positions differ in count");
    if (!uvs.empty() && uvs.size() != n) return bad("uvs and positions differ in count");
    if (!tangents.empty() && tangents.size() != n) return bad("tangents and positions differ in count");
    if (indices.size() % 3 != 0) return bad("index count is not a multiple of 3");
    if (lines.size() % 2 != 0) return bad("line index count is not a multiple of 2");
    for (const auto* list : {&indices, &points, &lines}) {
        const char* name = list == &indices ? "index " : list == &points ? "point index " : "line index ";
        for (std::size_t i = 0; i < list->size(); ++i)
            if ((*list)[i] >= n)
                return bad(name + std::to_string((*list)[i]) + " at position " + std::to_string(i) +
                           " is out of range (" + std::to_string(n) + " vertices)");
    }
    return Ok{};
}

Aabb Mesh::bounds() const {
    Aabb box;
    for (Vec3 p : positions)
        if (is_finite(p)) box.extend(p);
    return box;
}

void Mesh::append(const Mesh& other, const Mat4& model) {
    const auto base = static_cast<std::uint32_t>(positions.size());
    const std::size_t old = positions.size();
    const Mat3 nm = normal_matrix(model);
    auto keep_aligned = [&](auto& mine, const auto& theirs, auto fill) {
        if (mine.empty() && theirs.empty()) return;
        mine.resize(old, fill);
        if (theirs.empty())
            mine.resize(old + other.positions.size(), fill);
        else
            mine.insert(mine.end(), theirs.begin(), theirs.end());
    };
    for (Vec3 p : other.positions) positions.push_back(transform_point(model, p));
    keep_aligned(normals, other.normals, Vec3{});
    for (std::size_t i = old; i < normals.size() && !other.normals.empty(); ++i) normals[i] = normalize(nm * normals[i]);
    keep_aligned(colours, other.colours, Vec4{1, 1, 1, 1});
    keep_aligned(uvs, other.uvs, Vec2{});
    keep_aligned(tangents, other.tangents, Vec4{0, 0, 0, 1});
    // A mirroring transform turns the bitangent's side over.
    const float side = determinant(model.upper3x3()) < 0 ? -1.0f : 1.0f;
    for (std::size_t i = old; i < tangents.size() && !other.tangents.empty(); ++i)
        tangents[i] = Vec4(normalize(model.upper3x3() * tangents[i].xyz()), tangents[i].w * side);
    for (std::uint32_t i : other.indices) indices.push_back(base + i);
    for (std::uint32_t i : other.points) points.push_back(base + i);
    for (std::uint32_t i : other.lines) lines.push_back(base + i);
}

void compute_smooth_normals(Mesh& mesh) {
    mesh.normals.assign(mesh.positions.size(), Vec3{});
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t idx[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
        if (idx[0] >= mesh.positions.size() || idx[1] >= mesh.positions.size() || idx[2] >= mesh.positions.size())
            continue;
        const Vec3 face = normalize(cross(mesh.positions[idx[1]] - mesh.positions[idx[0]],
                                          mesh.positions[idx[2]] - mesh.positions[idx[0]]));
        if (!(dot(face, face) > 0)) continue;
        for (int k = 0; k < 3; ++k) {
            // Weight by the corner angle so a vertex's normal does not depend on how the fan is split.
            const Vec3 p = mesh.positions[idx[k]];
            const Vec3 e1 = normalize(mesh.positions[idx[(k + 1) % 3]] - p);
            const Vec3 e2 = normalize(mesh.positions[idx[(k + 2) % 3]] - p);
            const float angle = detail::corner_acos(clamp(dot(e1, e2), -1.0f, 1.0f));
            mesh.normals[idx[k]] += face * angle;
        }
    }
    for (Vec3& n : mesh.normals) n = normalize(n);
}

Mesh split_faces_flat(const Mesh& mesh) {
    Mesh out;
    const bool colours = !mesh.colours.empty(), uvs = !mesh.uvs.empty();
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t idx[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
        const Vec3 face = normalize(cross(mesh.positions[idx[1]] - mesh.positions[idx[0]],
                                          mesh.positions[idx[2]] - mesh.positions[idx[0]]));
        for (std::uint32_t i : idx) {
            out.indices.push_back(static_cast<std::uint32_t>(out.positions.size()));
            out.positions.push_back(mesh.positions[i]);
            out.normals.push_back(face);
            if (colours) out.colours.push_back(mesh.colours[i]);
            if (uvs) out.uvs.push_back(mesh.uvs[i]);
        }
    }
    return out;
}

Mesh make_cube(float h) {
    // Each face: outward normal n, and two axes u, v with cross(u, v) = n so corners run counter-clockwise.
    struct Face {
        Vec3 n, u, v;
        Vec4 colour;
    };
    const Face faces[6] = {
        {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}, {0.90f, 0.30f, 0.25f, 1}},
        {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}, {0.25f, 0.70f, 0.90f, 1}},
        {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}, {0.95f, 0.80f, 0.25f, 1}},
        {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}, {0.55f, 0.35f, 0.80f, 1}},
        {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {0.30f, 0.80f, 0.40f, 1}},
        {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}, {0.95f, 0.55f, 0.20f, 1}},
    };
    Mesh m;
    for (const Face& f : faces) {
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        const float corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
        for (const auto& c : corners) {
            m.positions.push_back((f.n + f.u * c[0] + f.v * c[1]) * h);
            m.normals.push_back(f.n);
            m.colours.push_back(f.colour);
            m.uvs.push_back({(c[0] + 1) / 2, (c[1] + 1) / 2});
        }
        for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(base + i);
    }
    return m;
}

Mesh make_uv_sphere(float radius, int slices, int stacks) {
    Mesh m;
    for (int j = 0; j <= stacks; ++j) {
        const float v = static_cast<float>(j) / stacks, phi = v * k_pi;  // from the north pole down
        for (int i = 0; i <= slices; ++i) {
            const float u = static_cast<float>(i) / slices, theta = u * 2 * k_pi;
            float sp, cp, st, ct;
            portable::sincos(phi, sp, cp);
            portable::sincos(theta, st, ct);
            const Vec3 n{sp * st, cp, sp * ct};
            m.positions.push_back(n * radius);
            m.normals.push_back(n);
            m.uvs.push_back({u, v});
        }
    }
    const int row = slices + 1;
    for (int j = 0; j < stacks; ++j)
        for (int i = 0; i < slices; ++i) {
            const auto a = static_cast<std::uint32_t>(j * row + i), b = a + 1, c = a + row, d = c + 1;
            if (j > 0) m.indices.insert(m.indices.end(), {a, c, b});
            if (j < stacks - 1) m.indices.insert(m.indices.end(), {b, c, d});
        }
    return m;
}

Mesh make_icosphere(float radius, int subdivisions) {
    const float t = (1.0f + std::sqrt(5.0f)) / 2;
    std::vector<Vec3> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                           {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (Vec3& v : p) v = normalize(v);
    std::vector<std::uint32_t> idx = {0, 11, 5, 0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                                      4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9,  4, 3,  4,  2, 3, 2, 6, 3,
                                      6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6, 2, 10, 8,  6, 7, 9, 8, 1};
    for (int s = 0; s < subdivisions; ++s) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            auto key = std::minmax(a, b);
            auto [it, inserted] = midpoints.try_emplace({key.first, key.second}, static_cast<std::uint32_t>(p.size()));
            if (inserted) p.push_back(normalize(p[a] + p[b]));
            return it->second;
        };
        std::vector<std::uint32_t> next;
        next.reserve(idx.size() * 4);
        for (std::size_t i = 0; i < idx.size(); i += 3) {
            const std::uint32_t a = idx[i], b = idx[i + 1], c = idx[i + 2];
            const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
            next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        idx = std::move(next);
    }
    Mesh m;
    m.normals = p;
    for (Vec3 v : p) m.positions.push_back(v * radius);
    m.indices = std::move(idx);
    return m;
}

Mesh make_torus(float major_radius, float minor_radius, int segments, int sides) {
    Mesh m;
    for (int i = 0; i <= segments; ++i) {
        const float u = static_cast<float>(i) / segments, a = u * 2 * k_pi;
        float sa, ca;
        portable::sincos(a, sa, ca);
        const Vec3 centre{ca * major_radius, 0, -sa * major_radius};
        for (int j = 0; j <= sides; ++j) {
            const float v = static_cast<float>(j) / sides, b = v * 2 * k_pi;
            float sb, cb;
            portable::sincos(b, sb, cb);
            const Vec3 n{ca * cb, sb, -sa * cb};
            m.positions.push_back(centre + n * minor_radius);
            m.normals.push_back(n);
            m.uvs.push_back({u, v});
        }
    }
    const int row = sides + 1;
    for (int i = 0; i < segments; ++i)
        for (int j = 0; j < sides; ++j) {
            const auto a = static_cast<std::uint32_t>(i * row + j), b = a + 1, c = a + row, d = c + 1;
            m.indices.insert(m.indices.end(), {a, c, d, a, d, b});
        }
    return m;
}

Mesh make_checker_plane(float size, int cells, Vec4 colour_a, Vec4 colour_b) {
    Mesh m;
    const float step = size / cells, origin = -size / 2;
    for (int j = 0; j < cells; ++j)
        for (int i = 0; i < cells; ++i) {
            const auto base = static_cast<std::uint32_t>(m.positions.size());
            const Vec4 colour = (i + j) % 2 ? colour_a : colour_b;
            const float x0 = origin + i * step, z0 = origin + j * step;
            for (Vec2 c : {Vec2{0, 0}, Vec2{0, 1}, Vec2{1, 1}, Vec2{1, 0}}) {
                m.positions.push_back({x0 + c.x * step, 0, z0 + c.y * step});
                m.normals.push_back({0, 1, 0});
                m.colours.push_back(colour);
                m.uvs.push_back({(i + c.x) / cells, (j + c.y) / cells});
            }
            m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
        }
    return m;
}

}  // namespace facet
