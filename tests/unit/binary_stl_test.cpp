// The binary STL fast path (src/io/binary_stl.hpp): load_model must give exactly the Scene the
// assimp path gives, bit for bit, for assimp's binary STL test models, a CGAL mesh written as STL and
// small files written here, including files the fast reader declines (it must decline them, and the
// result must still match) and damaged files (the same error). The fast path must actually be taken
// for the files it is meant for.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "facet/mesh.hpp"
#include "facet/model.hpp"
#include "io/binary_stl.hpp"
#include "support/same_scene.hpp"
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;
using namespace facet;
using facet_test::expect_same_as_assimp;
using facet_test::read_file;
using facet_test::write_file;

bool fast_reader_takes(const std::string& path) { return io_detail::read_binary_stl(read_file(path)).has_value(); }

fs::path temp_dir() { return facet_test::test_temp_dir("facet_binary_stl_test"); }

struct Facet {
    Vec3 v[3];
    std::uint16_t attribute = 0;
};

void append(std::string& out, const void* p, std::size_t n) { out.append(static_cast<const char*>(p), n); }

// A binary STL file: the header (padded to 80 bytes), the count, each facet with a zero normal.
std::string binary_stl(const std::vector<Facet>& facets, const std::string& header = "binary STL written by facet's tests") {
    std::string out = header;
    out.resize(80, '\0');
    const auto count = static_cast<std::uint32_t>(facets.size());
    append(out, &count, 4);
    for (const Facet& f : facets) {
        const float normal[3] = {0, 0, 0};
        append(out, normal, sizeof(normal));
        for (const Vec3& v : f.v) {
            const float xyz[3] = {v.x, v.y, v.z};
            append(out, xyz, sizeof(xyz));
        }
        append(out, &f.attribute, 2);
    }
    return out;
}

// The triangles of a mesh as STL facets, each corner repeated as STL stores it.
std::vector<Facet> facets_of(const Mesh& mesh) {
    std::vector<Facet> out(mesh.triangle_count());
    for (std::size_t t = 0; t < out.size(); ++t)
        for (int k = 0; k < 3; ++k) out[t].v[k] = mesh.positions[mesh.indices[3 * t + static_cast<std::size_t>(k)]];
    return out;
}

TEST(BinaryStl, AssimpTestModelsTakeTheFastPathAndMatchAssimp) {
    FACET_REQUIRE_ASSIMP_MODELS();
    for (const char* name : {"3DSMaxExport.STL", "Spider_binary.stl", "Wuson.stl"}) {
        const std::string path = (facet_test::k_assimp_models / "STL" / name).string();
        EXPECT_TRUE(fast_reader_takes(path)) << path;
        expect_same_as_assimp(path);
        LoadOptions z_up_sharp;
        z_up_sharp.up_axis = UpAxis::z;
        z_up_sharp.crease_angle_degrees = 10;
        expect_same_as_assimp(path, z_up_sharp);
    }
    // ASCII files are assimp's: the reader declines them, and the results are its.
    for (const char* name : {"Spider_ascii.stl", "sphereWithHole.stl", "triangle_with_two_solids.stl"}) {
        const std::string path = (facet_test::k_assimp_models / "STL" / name).string();
        EXPECT_FALSE(fast_reader_takes(path)) << path;
        expect_same_as_assimp(path);
    }
}

// A large mesh, its facets shuffled so that shared corners lie far apart in the file.
TEST(BinaryStl, CgalBunnyWrittenAsStlMatchesAssimp) {
    const std::optional<fs::path> dir = facet_test::cgal_meshes();
    if (!dir) GTEST_SKIP() << facet_test::cgal_meshes_missing();
    const Result<LoadedModel> bunny = load_model((*dir / "bunny00.off").string());
    ASSERT_TRUE(bunny.ok()) << bunny.error().message;
    std::vector<Facet> facets = facets_of(bunny->scene.objects.at(0).mesh);
    std::shuffle(facets.begin(), facets.end(), std::mt19937(3));
    const std::string path = write_file(temp_dir() / "bunny.stl", binary_stl(facets));
    EXPECT_TRUE(fast_reader_takes(path));
    expect_same_as_assimp(path);
}

// Small files in the accepted form, each with something the join or the numbering must get right.
TEST(BinaryStl, AcceptedFormsMatchAssimp) {
    const Vec3 o{0, 0, 0}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
    const float tiny = 1e-30f, zero = 0.0f;
    const std::vector<std::pair<std::string, std::vector<Facet>>> files = {
        {"one.stl", {{{o, x, y}}}},
        // Shared corners joined; -0 and +0 joined, the first in file order kept.
        {"shared.stl", {{{Vec3{-zero, 0, 0}, x, y}}, {{x, o, z}}, {{z, y, o}}}},
        // Equal tiny coordinates join as assimp joins them; a tiny one next to a distant position too.
        {"tiny_equal.stl", {{{Vec3{tiny, 0, 0}, x, y}}, {{y, x, Vec3{tiny, 0, 0}}}, {{Vec3{0, tiny, 5}, x, z}}}},
        // A degenerate facet among good ones.
        {"degenerate.stl", {{{o, x, y}}, {{x, x, z}}}},
        // Nothing but degenerate facets: load_model leaves the error to the assimp path.
        {"all_degenerate.stl", {{{o, o, y}}}},
        // Attribute bits other than the colour bit mean nothing to either reader.
        {"attribute.stl", {{{o, x, y}, 0x7fff}}},
    };
    for (const auto& [name, facets] : files) {
        const std::string path = write_file(temp_dir() / name, binary_stl(facets));
        EXPECT_TRUE(fast_reader_takes(path)) << name;
        expect_same_as_assimp(path);
    }
    // A binary file whose header begins "solid", like an ASCII file: its size makes it binary to both.
    const std::string solid = write_file(temp_dir() / "solid_header.stl", binary_stl({{{o, x, y}}}, "solid looks like text"));
    EXPECT_TRUE(fast_reader_takes(solid));
    expect_same_as_assimp(solid);
}

// Files the fast reader must leave to assimp, and load_model must still give assimp's answer for them.
TEST(BinaryStl, DeclinedFormsGoThroughAssimp) {
    const Vec3 o{0, 0, 0}, x{1, 0, 0}, y{0, 1, 0};
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<std::pair<std::string, std::string>> files = {
        // A facet colour: assimp gives vertex colours.
        {"colour.stl", binary_stl({{{o, x, y}, 0x8000 | 31}, {{x, y, Vec3{1, 1, 0}}}})},
        // A Materialise header colour: assimp makes it the material's.
        {"materialise.stl", binary_stl({{{o, x, y}}}, std::string("COLOR=") + "\x10\x20\x30\xff" + " MATERIAL=")},
        // Distinct positions only assimp's tolerance joins.
        {"tiny_distinct.stl", binary_stl({{{Vec3{1e-30f, 0, 0}, x, y}}, {{Vec3{2e-30f, 0, 0}, y, Vec3{0, 0, 1}}}})},
        {"nan.stl", binary_stl({{{Vec3{nan, 0, 0}, x, y}}, {{o, x, y}}})},
        {"zero_facets.stl", binary_stl({})},
        {"one_byte_more.stl", binary_stl({{{o, x, y}}}) + "x"},
        {"one_byte_less.stl", binary_stl({{{o, x, y}}}).substr(0, 133)},
        {"header_only.stl", std::string(80, ' ')},
    };
    for (const auto& [name, bytes] : files) {
        const std::string path = write_file(temp_dir() / name, bytes);
        EXPECT_FALSE(fast_reader_takes(path)) << name;
        expect_same_as_assimp(path);
    }
}

// Cut and damaged copies of a valid file: whatever each path makes of them (a scene, or an error
// naming the file), both make the same, and nothing crashes.
TEST(BinaryStl, DamagedFilesMatchAssimp) {
    std::vector<Facet> cube;
    const Vec3 c[8] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
    const int faces[6][3] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1}};
    for (const auto& f : faces) cube.push_back({{c[f[0]], c[f[1]], c[f[2]]}});
    const std::string good = binary_stl(cube);
    std::mt19937 rng(11);
    for (int i = 0; i < facet_test::sweep_size(300, 60); ++i) {
        std::string bad = good;
        if (i % 3 == 0) {
            bad.resize(rng() % good.size());
        } else {
            for (int k = 0; k < 1 + i % 4; ++k) bad[rng() % bad.size()] = static_cast<char>(rng());
        }
        const std::string path = write_file(temp_dir() / ("damaged_" + std::to_string(i) + ".stl"), bad);
        expect_same_as_assimp(path);
    }
}

}  // namespace
