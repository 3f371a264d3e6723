// Meshes: validation, bounds, generators (closed, outward-facing), normals, append.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <utility>

#include "facet/math/transform.hpp"
#include "facet/mesh.hpp"

namespace {

using namespace facet;

// Signed volume by the divergence theorem: positive iff the faces wind counter-clockwise seen from outside.
double signed_volume(const Mesh& m) {
    double v = 0;
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
        const Vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]], c = m.positions[m.indices[t + 2]];
        v += dot(a, cross(b, c)) / 6.0;
    }
    return v;
}

// Every edge of a closed surface is shared by exactly two triangles, in opposite directions.
// Vertices are compared by position, since seams duplicate them.
bool is_closed(const Mesh& m) {
    auto key = [](Vec3 p) { return std::tuple(std::lround(p.x * 1e4), std::lround(p.y * 1e4), std::lround(p.z * 1e4)); };
    std::map<std::pair<decltype(key(Vec3{})), decltype(key(Vec3{}))>, int> directed;
    for (std::size_t t = 0; t < m.indices.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            auto a = key(m.positions[m.indices[t + k]]), b = key(m.positions[m.indices[t + (k + 1) % 3]]);
            if (a == b) continue;  // collapsed edge at a pole
            ++directed[{a, b}];
        }
    for (const auto& [edge, count] : directed) {
        auto it = directed.find({edge.second, edge.first});
        if (count != 1 || it == directed.end() || it->second != 1) return false;
    }
    return true;
}

TEST(Mesh, ValidateFindsMismatchedArraysAndBadIndices) {
    Mesh m = make_cube(1);
    EXPECT_TRUE(m.validate().ok());
    Mesh bad = m;
    bad.indices.push_back(1000);
    bad.indices.push_back(0);
    bad.indices.push_back(1);
    const Status s = bad.validate();
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("1000"), std::string::npos);
    bad = m;
    bad.normals.pop_back();
    EXPECT_FALSE(bad.validate().ok());
    bad = m;
    bad.indices.pop_back();
    EXPECT_FALSE(bad.validate().ok());
}

TEST(Mesh, GeneratorsAreClosedAndFaceOutward) {
    const float pi = 3.14159265f;
    struct Case {
        const char* name;
        Mesh mesh;
        double volume;
        double tolerance;
    } cases[] = {
        {"cube", make_cube(1.0f), 8.0, 1e-5},
        {"uv sphere", make_uv_sphere(1.0f, 64, 32), 4.0 / 3.0 * pi, 0.02},
        {"icosphere", make_icosphere(1.0f, 3), 4.0 / 3.0 * pi, 0.02},
        {"torus", make_torus(1.0f, 0.25f, 96, 48), 2 * pi * pi * 1.0 * 0.25 * 0.25, 0.01},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        EXPECT_TRUE(c.mesh.validate().ok());
        EXPECT_TRUE(is_closed(c.mesh));
        EXPECT_NEAR(signed_volume(c.mesh), c.volume, c.volume * c.tolerance);
        // Stored normals point away from the centre (the torus: from its tube's centre circle).
        for (std::size_t i = 0; i < c.mesh.positions.size(); ++i) {
            Vec3 p = c.mesh.positions[i];
            if (std::string(c.name) == "torus") p = p - normalize(Vec3{p.x, 0, p.z});
            EXPECT_GT(dot(c.mesh.normals[i], p), 0.0f) << i;
        }
    }
}

TEST(Mesh, IcosphereTriangleCount) {
    EXPECT_EQ(make_icosphere(1, 0).triangle_count(), 20u);
    EXPECT_EQ(make_icosphere(1, 4).triangle_count(), 20u * 256u);
}

TEST(Mesh, SmoothNormalsOfASphereMatchTheRadialDirection) {
    Mesh m = make_icosphere(2.0f, 3);
    m.normals.clear();
    compute_smooth_normals(m);
    ASSERT_EQ(m.normals.size(), m.positions.size());
    for (std::size_t i = 0; i < m.positions.size(); ++i)
        EXPECT_GT(dot(m.normals[i], normalize(m.positions[i])), 0.999f) << i;
}

TEST(Mesh, SmoothNormalsIgnoreDegenerateAndOutOfRangeTriangles) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}};
    m.indices = {0, 1, 2, 0, 1, 3, 0, 1, 99};  // a zero-area triangle and a bad index
    compute_smooth_normals(m);
    EXPECT_FLOAT_EQ(m.normals[0].z, 1.0f);
    for (Vec3 n : m.normals) EXPECT_TRUE(is_finite(n));
    EXPECT_EQ(m.normals[3], (Vec3{0, 0, 0}));  // touched only by the degenerate triangle
}

TEST(Mesh, SplitFacesFlatGivesEachTriangleItsFaceNormal) {
    const Mesh flat = split_faces_flat(make_icosphere(1, 1));
    ASSERT_EQ(flat.positions.size(), flat.indices.size());
    for (std::size_t t = 0; t < flat.indices.size(); t += 3) {
        const Vec3 a = flat.positions[t], b = flat.positions[t + 1], c = flat.positions[t + 2];
        const Vec3 n = normalize(cross(b - a, c - a));
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(dot(flat.normals[t + k], n), 1.0f, 1e-6f);
    }
}

TEST(Mesh, AppendTransformsAndKeepsAttributesAligned) {
    Mesh a = make_icosphere(1, 0);  // normals, no colours
    const Mesh b = make_cube(1);     // normals and colours
    const std::size_t before = a.positions.size();
    a.append(b, translate({10, 0, 0}) * scale(2.0f));
    EXPECT_TRUE(a.validate().ok());
    EXPECT_EQ(a.colours.size(), a.positions.size());
    EXPECT_EQ(a.colours[0], (Vec4{1, 1, 1, 1}));  // filled for the first mesh
    EXPECT_EQ(a.colours[before], b.colours[0]);
    EXPECT_EQ(a.positions[before], (b.positions[0] * 2.0f + Vec3{10, 0, 0}));
    EXPECT_NEAR(length(a.normals[before]), 1.0f, 1e-6f);
    const Aabb box = a.bounds();
    EXPECT_FLOAT_EQ(box.max.x, 12.0f);
    EXPECT_FLOAT_EQ(box.min.x, make_icosphere(1, 0).bounds().min.x);
}

TEST(Mesh, BoundsSkipNonFinitePositions) {
    Mesh m;
    m.positions = {{1, 2, 3}, {NAN, 0, 0}, {-1, INFINITY, 0}, {0, 0, -3}};
    const Aabb box = m.bounds();
    EXPECT_EQ(box.min, (Vec3{0, 0, -3}));
    EXPECT_EQ(box.max, (Vec3{1, 2, 3}));
    EXPECT_TRUE(Mesh{}.bounds().empty());
}

}  // namespace
