// compute_creased_normals must give exactly what the original sort-based version gives
// (tests/support/reference_creased_normals.cpp): the same vertex copies, indices and normal bits,
// for real meshes, the built-in shapes and random meshes with what breaks naive code: duplicated
// positions (-0 and +0 among them), NaN, out-of-range indices, degenerate triangles, and
// non-manifold edges shared by more triangles than are compared pairwise, in both orientations;
// on every ISA, since a SIMD kernel shapes the triangles.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "facet/isa.hpp"
#include "facet/mesh.hpp"
#include "facet/model.hpp"
#include "facet/detail/thread_pool.hpp"
#include "scene/creased_normals.hpp"
#include "scene/triangle_shapes.hpp"
#include "support/pixels.hpp"
#include "support/reference_creased_normals.hpp"
#include "support/test_data.hpp"

namespace {

using namespace facet;
using facet_test::bits_of;

void expect_same_as_reference(Mesh mesh, float crease_radians, const std::string& what, int threads = 1) {
    SCOPED_TRACE(what + ", crease " + std::to_string(crease_radians) + ", threads " + std::to_string(threads));
    Mesh want = mesh;
    facet_test::reference_creased_normals(want, crease_radians);
    compute_creased_normals(mesh, crease_radians, threads);
    EXPECT_EQ(bits_of(mesh.positions), bits_of(want.positions));
    EXPECT_EQ(bits_of(mesh.normals), bits_of(want.normals));
    EXPECT_EQ(bits_of(mesh.colours), bits_of(want.colours));
    EXPECT_EQ(bits_of(mesh.uvs), bits_of(want.uvs));
    EXPECT_EQ(mesh.indices, want.indices);
}

TEST(CreasedNormals, BuiltInShapesMatchTheReference) {
    for (float crease : {0.0f, radians(10), radians(40), radians(90), k_pi}) {
        expect_same_as_reference(make_cube(1), crease, "cube");
        expect_same_as_reference(make_uv_sphere(1, 24, 12), crease, "uv sphere");
        expect_same_as_reference(make_icosphere(1, 3), crease, "icosphere");
        expect_same_as_reference(make_torus(1, 0.3f, 32, 16), crease, "torus");
        expect_same_as_reference(make_checker_plane(2, 6, {1, 0, 0, 1}, {0, 0, 1, 1}), crease, "checker plane");
        expect_same_as_reference(split_faces_flat(make_icosphere(1, 2)), crease, "unindexed icosphere");
    }
}

TEST(CreasedNormals, CgalMeshesMatchTheReference) {
    const std::optional<std::filesystem::path> dir = facet_test::cgal_meshes();
    if (!dir) GTEST_SKIP() << facet_test::cgal_meshes_missing();
    for (const char* name : {"bunny00.off", "elephant.off"}) {
        Result<LoadedModel> model = load_model((*dir / name).string());
        ASSERT_TRUE(model.ok()) << model.error().message;
        Mesh mesh = model->scene.objects.at(0).mesh;
        mesh.normals.clear();
        for (float crease : {radians(20), radians(40)}) expect_same_as_reference(mesh, crease, name);
        expect_same_as_reference(mesh, radians(40), name, 2);
    }
}

// Random soups over a small set of positions, so that positions repeat, edges are shared by many
// triangles in both directions, and some triangles are degenerate or invalid.
Mesh random_mesh(std::mt19937& rng, int case_index) {
    const int distinct = 4 + case_index % 9;
    std::uniform_real_distribution<float> coordinate(-1, 1);
    std::vector<Vec3> pool;
    for (int i = 0; i < distinct; ++i) pool.push_back({coordinate(rng), coordinate(rng), coordinate(rng)});
    pool.push_back({0.0f, 0.5f, 0.5f});
    pool.push_back({-0.0f, 0.5f, 0.5f});  // the same position as the one before, welded
    if (case_index % 5 == 0) pool.push_back({std::numeric_limits<float>::quiet_NaN(), 0, 0});
    Mesh m;
    const int vertices = 6 + static_cast<int>(rng() % 40);
    for (int i = 0; i < vertices; ++i) m.positions.push_back(pool[rng() % pool.size()]);
    if (case_index % 3 == 0)
        for (int i = 0; i < vertices; ++i) m.uvs.push_back({coordinate(rng), coordinate(rng)});
    if (case_index % 4 == 0)
        for (int i = 0; i < vertices; ++i) m.colours.push_back({coordinate(rng), 0.5f, 0.25f, 1});
    const int triangles = 1 + static_cast<int>(rng() % 80);
    for (int t = 0; t < 3 * triangles; ++t) m.indices.push_back(static_cast<std::uint32_t>(rng() % vertices));
    if (case_index % 7 == 0) m.indices[rng() % m.indices.size()] = static_cast<std::uint32_t>(vertices + 3);  // out of range
    return m;
}

TEST(CreasedNormals, RandomMeshesMatchTheReference) {
    std::mt19937 rng(2024);
    const int cases = facet_test::sweep_size(600, 100);
    for (int i = 0; i < cases; ++i) {
        const float crease = radians(static_cast<float>(rng() % 181));
        expect_same_as_reference(random_mesh(rng, i), crease, "random mesh " + std::to_string(i));
        if (HasFailure()) return;
    }
}

// Meshes large enough to be shared between threads give what one thread gives, whatever the number
// of threads (the random soups above are too small to be shared).
TEST(CreasedNormals, SharedBetweenThreadsMatchesTheReference) {
    std::mt19937 rng(7);
    for (int i = 0; i < 3; ++i) {
        Mesh m = random_mesh(rng, i * 5);  // case 0 and 10: NaN positions; 0: uvs and colours too
        const Mesh part = m;
        while (m.indices.size() < 3 * 10'000) m.append(part);  // enough to be shared
        for (int k = 0; k < 40; ++k) m.indices[rng() % m.indices.size()] = static_cast<std::uint32_t>(rng() % m.positions.size());
        const float crease = radians(static_cast<float>(rng() % 181));
        for (int threads : {0, 2, 3}) expect_same_as_reference(m, crease, "random mesh " + std::to_string(i), threads);
        if (HasFailure()) return;
    }
    Mesh sphere = make_icosphere(1, 5);  // 20,480 triangles
    sphere.normals.clear();
    expect_same_as_reference(sphere, radians(40), "icosphere", 2);
}

// The mesh with the vertices at equal positions (by bits, -0 as +0) made one, the first of them
// kept: what facet's own readers give compute_creased_normals_on.
Mesh joined_by_position(const Mesh& m) {
    auto key = [](Vec3 p) {
        auto bits = [](float f) { return std::bit_cast<std::uint32_t>(f == 0.0f ? 0.0f : f); };
        return std::array<std::uint32_t, 3>{bits(p.x), bits(p.y), bits(p.z)};
    };
    std::map<std::array<std::uint32_t, 3>, std::uint32_t> first;
    std::vector<std::uint32_t> to(m.positions.size());
    Mesh out;
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
        const auto [at, added] = first.emplace(key(m.positions[v]), static_cast<std::uint32_t>(out.positions.size()));
        if (added) out.positions.push_back(m.positions[v]);
        to[v] = at->second;
    }
    for (std::uint32_t i : m.indices) out.indices.push_back(i < to.size() ? to[i] : i);
    return out;
}

// facet's own readers join the vertices by position and start their threads once: the normals
// leave the welding out then (compute_creased_normals_on), and must give the same bits.
void expect_distinct_positions_same_as_reference(const Mesh& mesh, float crease_radians, const std::string& what,
                                                 detail::ThreadPool* pool) {
    SCOPED_TRACE(what + ", crease " + std::to_string(crease_radians));
    Mesh want = mesh, got = mesh;
    facet_test::reference_creased_normals(want, crease_radians);
    detail::compute_creased_normals_on(got, crease_radians, pool, /*distinct_positions=*/true);
    EXPECT_EQ(bits_of(got.positions), bits_of(want.positions));
    EXPECT_EQ(bits_of(got.normals), bits_of(want.normals));
    EXPECT_EQ(got.indices, want.indices);
}

TEST(CreasedNormals, DistinctPositionsWithoutWeldingMatchTheReference) {
    std::mt19937 rng(11);
    std::vector<std::pair<std::string, Mesh>> meshes{{"icosphere", make_icosphere(1, 5)},
                                                     {"uv sphere", make_uv_sphere(1, 48, 24)},
                                                     {"torus", make_torus(1, 0.3f, 32, 16)}};
    for (int i = 0; i < 40; ++i) meshes.emplace_back("random mesh " + std::to_string(i), random_mesh(rng, i));
    Mesh large = random_mesh(rng, 3);
    const Mesh part = large;
    while (large.indices.size() < 3 * 10'000) large.append(part);
    meshes.emplace_back("large random mesh", large);
    detail::ThreadPool two(2);
    for (auto& [name, mesh] : meshes) {
        const Mesh m = joined_by_position(mesh);
        for (float crease : {radians(20), radians(40), k_pi})
            for (detail::ThreadPool* pool : {static_cast<detail::ThreadPool*>(nullptr), &two})
                expect_distinct_positions_same_as_reference(m, crease, name + (pool ? ", 2 threads" : ", 1 thread"), pool);
        if (HasFailure()) return;
    }
}

// The mesh with its positions numbered in order of first use by the triangles (as facet's conversion
// numbers them), the unused ones after them.
Mesh numbered_by_first_use(const Mesh& m) {
    std::vector<std::uint32_t> number(m.positions.size(), ~0u);
    Mesh out;
    const auto give = [&](std::uint32_t v) {
        if (number[v] != ~0u) return;
        number[v] = static_cast<std::uint32_t>(out.positions.size());
        out.positions.push_back(m.positions[v]);
    };
    for (std::uint32_t i : m.indices)
        if (i < number.size()) give(i);
    for (std::uint32_t v = 0; v < m.positions.size(); ++v) give(v);
    for (std::uint32_t i : m.indices) out.indices.push_back(i < number.size() ? number[i] : i);
    return out;
}

// A torus of rows x columns vertices, its triangles row by row but those of one row last.
Mesh torus_with_a_row_last(std::uint32_t rows, std::uint32_t columns, std::uint32_t last_row) {
    Mesh m;
    for (std::uint32_t u = 0; u < rows; ++u)
        for (std::uint32_t v = 0; v < columns; ++v) {
            const float phi = 6.2831853f * static_cast<float>(u) / static_cast<float>(rows);
            const float theta = 6.2831853f * static_cast<float>(v) / static_cast<float>(columns);
            const float ring = 1 + 0.3f * std::cos(theta);
            m.positions.push_back({ring * std::cos(phi), ring * std::sin(phi), 0.3f * std::sin(theta)});
        }
    std::vector<std::uint32_t> held;
    for (std::uint32_t u = 0; u < rows; ++u)
        for (std::uint32_t v = 0; v < columns; ++v) {
            const std::uint32_t next_u = (u + 1) % rows, next_v = (v + 1) % columns;
            const std::uint32_t a = u * columns + v, b = u * columns + next_v, c = next_u * columns + v, d = next_u * columns + next_v;
            (u == last_row ? held : m.indices).insert((u == last_row ? held : m.indices).end(), {a, c, b, b, c, d});
        }
    m.indices.insert(m.indices.end(), held.begin(), held.end());
    return m;
}

// One thread keeps the sums of the positions in a ring up to the highest one used so far, and of
// the positions used again long after it has passed them (far ones) apart, where each vertex is its
// own position and there are 16,384 positions or more. A torus numbered in order of first use,
// the triangles of its last row of quads (at its first row: far, with neighbours far in the
// numbering) and of its tenth row (at two rows with near neighbours) last, then 12,000 positions no
// triangle uses (which the ring passes at once), a ball, degenerate and out-of-range triangles,
// and a triangle at the torus's first position; and the same shuffled (too many far positions:
// every position's sums kept).
TEST(CreasedNormals, PositionsInARingMatchTheReference) {
    Mesh m = numbered_by_first_use(torus_with_a_row_last(96, 64, 10));
    for (int i = 0; i < 12000; ++i) m.positions.push_back({10.0f + static_cast<float>(i), 0, 0});
    const Mesh ball = joined_by_position(make_icosphere(0.5f, 2));
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    for (const Vec3& p : ball.positions) m.positions.push_back(p + Vec3{5, 0, 0});
    for (const std::uint32_t i : ball.indices) m.indices.push_back(base + i);
    m.indices.insert(m.indices.end(), {base, base, base + 1, base, base + 1, 1'000'000, 0, base + 2, base + 3});
    ASSERT_GE(m.positions.size(), 16384u);
    Mesh shuffled = m;
    std::mt19937 rng(7);
    std::vector<std::uint32_t> order(m.positions.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::shuffle(order.begin(), order.end(), rng);
    for (std::uint32_t i = 0; i < order.size(); ++i) shuffled.positions[order[i]] = m.positions[i];
    for (std::uint32_t& index : shuffled.indices)
        if (index < order.size()) index = order[index];
    for (const auto& [name, mesh] : {std::pair<const char*, const Mesh&>{"torus and ball", m}, {"shuffled", shuffled}})
        for (float crease : {radians(20), radians(40), k_pi})
            expect_distinct_positions_same_as_reference(mesh, crease, name, nullptr);
}

// Nothing but degenerate triangles: no triangle has an edge, so every vertex's list of edge sides is
// empty (fuzzing found pointer arithmetic past an empty list there, which UBSan reports).
TEST(CreasedNormals, MeshesWithoutAnyEdgeMatchTheReference) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 2, 2}};
    m.indices = {0, 0, 1, 2, 2, 2, 3, 3, 0};  // two corners or all three at one position
    for (float crease : {radians(0), radians(60)}) expect_same_as_reference(m, crease, "no edges");
    Mesh empty;
    empty.positions = {{0, 0, 0}};
    expect_same_as_reference(empty, radians(60), "no triangles");
}

// One edge shared by many more triangles than k_max_edge_neighbours, with both orientations and
// the apexes in varying order: which pairs are compared depends on the order of the sides.
TEST(CreasedNormals, FanAroundOneEdgeMatchesTheReference) {
    std::mt19937 rng(5);
    for (int fan : {9, 10, 17, 40}) {
        Mesh m;
        m.positions = {{0, 0, 0}, {0, 0, 1}};
        for (int i = 0; i < fan; ++i) {
            const float a = 6.2831853f * static_cast<float>(rng() % 1000) / 1000;
            m.positions.push_back({std::cos(a), std::sin(a), 0.5f});
            const auto apex = static_cast<std::uint32_t>(m.positions.size() - 1);
            if (rng() % 2)
                m.indices.insert(m.indices.end(), {0, 1, apex});
            else
                m.indices.insert(m.indices.end(), {1, 0, apex});
        }
        for (float crease : {radians(30), radians(60), radians(120)})
            expect_same_as_reference(m, crease, "fan of " + std::to_string(fan));
    }
}

// Triangles whose face normal takes normalize's rare path and still has a direction: so large
// that the cross product's squared length overflows, and so small that it underflows to zero.
// The shape kernel leaves them to the specification.
Mesh extreme_triangles() {
    Mesh m;
    for (float scale : {1e10f, 3e-13f, 1.0f}) {
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        m.positions.push_back(Vec3{0, 0, 0} * scale);
        m.positions.push_back(Vec3{1, 0, 0.25f} * scale);
        m.positions.push_back(Vec3{0.5f, 1, 0} * scale);
        m.positions.push_back(Vec3{0.75f, 0.5f, 1} * scale);
        for (std::uint32_t i : {0u, 1u, 2u, 0u, 3u, 1u, 2u, 1u, 3u}) m.indices.push_back(base + i);
    }
    return m;
}

using facet_test::IsaGuard;

// One thread sums each position's corners in triangle order and settles a fan without splitting it
// when its faces are near the first and its corners are joined by sides (kept beside the sums as
// differences of welded ids that fit 16 bits, else walked from the corners): what must still be
// split is a fan of two parts that only touch at the position (a bowtie: two closed fans or two
// open ones around one apex), whatever the crease angle, and fans whose neighbours are far apart
// in the welding order (a large sphere with its vertices shuffled).
TEST(CreasedNormals, BowtiesAndFarNeighboursMatchTheReference) {
    Mesh bowties;
    for (const float lift : {0.0f, 0.05f}) {
        const auto apex = static_cast<std::uint32_t>(bowties.positions.size());
        bowties.positions.push_back({0, 0, lift});
        for (const float radius : {1.0f, 2.0f}) {  // two closed fans of 12 around the apex
            const auto first = static_cast<std::uint32_t>(bowties.positions.size());
            for (int i = 0; i < 12; ++i) {
                const float a = 6.2831853f * static_cast<float>(i) / 12;
                bowties.positions.push_back({radius * std::cos(a), radius * std::sin(a), lift + 0.01f * radius});
                bowties.indices.insert(bowties.indices.end(), {apex, first + i, first + (i + 1) % 12});
            }
        }
        const auto open_apex = static_cast<std::uint32_t>(bowties.positions.size());
        bowties.positions.push_back({5, 0, lift});
        for (const float start : {0.0f, 3.2f}) {  // two open fans of 4 on either side of it
            const auto first = static_cast<std::uint32_t>(bowties.positions.size());
            for (int i = 0; i < 5; ++i)
                bowties.positions.push_back({5 + std::cos(start + 0.6f * i), std::sin(start + 0.6f * i), lift});
            for (std::uint32_t i = 0; i < 4; ++i) bowties.indices.insert(bowties.indices.end(), {open_apex, first + i, first + i + 1});
        }
    }
    for (float crease : {radians(10), radians(40), radians(90)}) expect_same_as_reference(bowties, crease, "bowties");

    Mesh sphere = make_icosphere(1, 6);  // 40,962 positions: ids 32,767 or more apart are not kept
    sphere.normals.clear();
    std::mt19937 rng(3);
    std::vector<std::uint32_t> order(sphere.positions.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::shuffle(order.begin(), order.end(), rng);
    Mesh shuffled = sphere;
    for (std::uint32_t i = 0; i < order.size(); ++i) shuffled.positions[order[i]] = sphere.positions[i];
    for (std::uint32_t& index : shuffled.indices) index = order[index];
    for (int k = 0; k < 200; ++k) std::swap(shuffled.indices[3 * k + 1], shuffled.indices[3 * k + 2]);  // some flipped
    expect_same_as_reference(shuffled, radians(40), "shuffled icosphere");
}

// The arc cosine of the corner angles in the kernel's lanes is corner_acos, bit for bit, on every
// ISA: every 8192nd float of [-1, 1] and the ends of its ways. With glibc up to 2.36, corner_acos is
// std::acos (fdlibm's acosf; checked there for all floats of [-1, 1]), so normals are the same as
// before it.
TEST(CreasedNormals, KernelArcCosineIsCornerAcos) {
    std::vector<float> values;
    for (std::uint32_t u = 0; u <= 0x3f800000u; u += 8192)
        for (const std::uint32_t sign : {0u, 0x80000000u}) values.push_back(std::bit_cast<float>(u | sign));
    for (const std::uint32_t u : {0x32800000u, 0x32800001u, 0x3effffffu, 0x3f000000u, 0x3f000001u, 0x3f7fffffu, 0x3f800000u})
        for (const std::uint32_t sign : {0u, 0x80000000u}) values.push_back(std::bit_cast<float>(u | sign));
    std::vector<float> want(values.size());
    for (std::size_t i = 0; i < values.size(); ++i) want[i] = detail::corner_acos(values[i]);
#if defined(__GLIBC__) && __GLIBC__ == 2 && __GLIBC_MINOR__ <= 36
    for (std::size_t i = 0; i < values.size(); ++i)
        ASSERT_EQ(std::bit_cast<std::uint32_t>(want[i]), std::bit_cast<std::uint32_t>(std::acos(values[i])))
            << "acos(" << values[i] << ")";
#endif
    const IsaGuard guard;
    for (const std::string& isa : available_isas()) {
        SCOPED_TRACE(isa);
        ASSERT_TRUE(select_isa(isa));
        std::vector<float> got = values;
        got.push_back(0.25f);  // a length that leaves a partial vector of lanes
        if (!detail::corner_acos_lanes(got.data(), got.size())) continue;  // the scalar ISA: corner_acos itself
        got.pop_back();
        EXPECT_EQ(bits_of(got), bits_of(want));
    }
}

TEST(CreasedNormals, EveryIsaMatchesTheReference) {
    const IsaGuard guard;
    const std::optional<std::filesystem::path> dir = facet_test::cgal_meshes();
    Mesh bunny;
    if (dir) {
        Result<LoadedModel> model = load_model((*dir / "bunny00.off").string());
        ASSERT_TRUE(model.ok()) << model.error().message;
        bunny = model->scene.objects.at(0).mesh;
        bunny.normals.clear();
    }
    for (const std::string& isa : available_isas()) {
        SCOPED_TRACE(isa);
        ASSERT_TRUE(select_isa(isa));
        expect_same_as_reference(extreme_triangles(), radians(40), "extreme triangles");
        expect_same_as_reference(make_icosphere(1, 3), radians(40), "icosphere");
        expect_same_as_reference(make_torus(1, 0.3f, 32, 16), radians(10), "torus");
        std::mt19937 rng(11);
        for (int i = 0; i < 60; ++i) {
            const float crease = radians(static_cast<float>(rng() % 181));
            expect_same_as_reference(random_mesh(rng, i), crease, "random mesh " + std::to_string(i));
        }
        if (dir) expect_same_as_reference(bunny, radians(40), "bunny00.off", 2);
        if (HasFailure()) return;
    }
}

}  // namespace
