// The STL fast path (src/io/stl.hpp): load_model must give exactly the Scene the assimp path gives,
// bit for bit, for assimp's STL test models, a CGAL mesh written as binary and ASCII STL and small
// files written here, including files the fast reader declines (it must decline them, and the
// result must still match) and damaged files (the same error). The fast path must actually be taken
// for the files it is meant for.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <sstream>
#include <iomanip>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "facet/mesh.hpp"
#include "facet/model.hpp"
#include "io/stl.hpp"
#include "support/same_scene.hpp"
#include "support/stl_files.hpp"
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;
using namespace facet;
using facet_test::ascii_stl;
using facet_test::binary_stl;
using facet_test::expect_same_as_assimp;
using facet_test::StlTriangle;
using facet_test::write_file;


fs::path temp_dir() { return facet_test::test_temp_dir("facet_stl_test"); }

void expect_taken_and_same(const std::string& path, bool taken = true) {
    facet_test::expect_read_as_told_and_same(path, io_detail::read_stl, taken);
}

TEST(Stl, AssimpTestModelsMatchAssimp) {
    FACET_REQUIRE_ASSIMP_MODELS();
    // Binary, and ASCII in the plain form: the fast path's.
    for (const char* name : {"3DSMaxExport.STL", "Spider_binary.stl", "Wuson.stl", "Spider_ascii.stl", "sphereWithHole.stl",
                             "triangle.stl"}) {
        const std::string path = (facet_test::k_assimp_models / "STL" / name).string();
        expect_taken_and_same(path);
        LoadOptions z_up_sharp;
        z_up_sharp.up_axis = UpAxis::z;
        z_up_sharp.crease_angle_degrees = 10;
        expect_same_as_assimp(path, z_up_sharp);
    }
    // Two solids, an empty solid: assimp's.
    for (const char* name : {"triangle_with_two_solids.stl", "triangle_with_empty_solid.stl"})
        expect_taken_and_same((facet_test::k_assimp_models / "STL" / name).string(), false);
}

// A large mesh, its facets shuffled so that shared corners lie far apart in the file.
TEST(Stl, CgalBunnyWrittenAsStlMatchesAssimp) {
    const std::optional<fs::path> dir = facet_test::cgal_meshes();
    if (!dir) GTEST_SKIP() << facet_test::cgal_meshes_missing();
    const Result<LoadedModel> bunny = load_model((*dir / "bunny00.off").string());
    ASSERT_TRUE(bunny.ok()) << bunny.error().message;
    std::vector<StlTriangle> facets = facet_test::triangles_of(bunny->scene.objects.at(0).mesh);
    std::shuffle(facets.begin(), facets.end(), std::mt19937(3));
    expect_taken_and_same(write_file(temp_dir() / "bunny.stl", binary_stl(facets)));
    expect_taken_and_same(write_file(temp_dir() / "bunny_ascii.stl", ascii_stl(facets)));
}

const Vec3 o{0, 0, 0}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};

// Small files in the accepted forms, each with something the join or the numbering must get right.
TEST(Stl, AcceptedBinaryFormsMatchAssimp) {
    const float tiny = 1e-30f, zero = 0.0f;
    const std::vector<std::pair<std::string, std::vector<StlTriangle>>> files = {
        {"one.stl", {{o, x, y}}},
        // Shared corners joined; -0 and +0 joined, the first in file order kept.
        {"shared.stl", {{Vec3{-zero, 0, 0}, x, y}, {x, o, z}, {z, y, o}}},
        // Equal tiny coordinates join as assimp joins them; a tiny one next to a distant position too.
        {"tiny_equal.stl", {{Vec3{tiny, 0, 0}, x, y}, {y, x, Vec3{tiny, 0, 0}}, {Vec3{0, tiny, 5}, x, z}}},
        // A degenerate facet among good ones.
        {"degenerate.stl", {{o, x, y}, {x, x, z}}},
        // Nothing but degenerate facets: load_model leaves the error to the assimp path.
        {"all_degenerate.stl", {{o, o, y}}},
    };
    for (const auto& [name, facets] : files) expect_taken_and_same(write_file(temp_dir() / name, binary_stl(facets)));
    // Attribute bits other than the colour bit mean nothing to either reader.
    expect_taken_and_same(write_file(temp_dir() / "attribute.stl", binary_stl({{o, x, y}}, "", {0x7fff})));
    // A header that begins "solid", like an ASCII file: its size makes it binary to both.
    expect_taken_and_same(write_file(temp_dir() / "solid_header.stl", binary_stl({{o, x, y}}, "solid looks like text")));
}

TEST(Stl, AcceptedAsciiFormsMatchAssimp) {
    const std::string facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
    const std::vector<std::pair<std::string, std::string>> files = {
        {"plain.stl", ascii_stl({{o, x, y}, {x, Vec3{1, 1, 0}, y}}, "part")},
        {"no_name.stl", "solid\n" + facet + "endsolid\n"},
        {"no_final_newline.stl", "solid x\n" + facet + "endsolid x"},
        // Spaces and tabs in runs, CRLF, blank lines, leading spaces, a name at "endsolid" that differs.
        {"spacing.stl", "  solid \t a\r\n\r\n facet  normal\t0 0  1\r\nouter\tloop\r\n\tvertex 0\t0 0\r\nvertex  1 0 0 \r\n"
                        "vertex 0 1 0\r\nendloop endfacet\r\nendsolid other\r\n\r\n  \n"},
        // Numbers as fast_atof reads them: exponents, signs, a leading dot, many digits, -0.
        {"numbers.stl", "solid n\nfacet normal 0 0 1\nouter loop\nvertex 1e2 -2.5E-1 +3\nvertex .25 7. -0\n"
                        "vertex 0.123456789012345678 1.0000001 1e-30\nendloop\nendfacet\nendsolid n\n"},
        // Normals are dropped, whatever they are.
        {"odd_normal.stl", "solid n\nfacet normal nan 1e39 -7\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
                           "endloop\nendfacet\nendsolid n\n"},
    };
    for (const auto& [name, text] : files) expect_taken_and_same(write_file(temp_dir() / name, text));
}

// Files the fast reader must leave to assimp, and load_model must still give assimp's answer for them.
TEST(Stl, DeclinedFormsGoThroughAssimp) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::string facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
    const std::vector<std::pair<std::string, std::string>> files = {
        // Binary. A facet colour: assimp gives vertex colours.
        {"colour.stl", binary_stl({{o, x, y}, {x, y, Vec3{1, 1, 0}}}, "", {0x8000 | 31, 0})},
        // A Materialise header colour: assimp makes it the material's.
        {"materialise.stl", binary_stl({{o, x, y}}, std::string("COLOR=") + "\x10\x20\x30\xff" + " MATERIAL=")},
        // Distinct positions only assimp's tolerance joins.
        {"tiny_distinct.stl", binary_stl({{Vec3{1e-30f, 0, 0}, x, y}, {Vec3{2e-30f, 0, 0}, y, z}})},
        {"nan.stl", binary_stl({{Vec3{nan, 0, 0}, x, y}, {o, x, y}})},
        {"zero_facets.stl", binary_stl({})},
        {"one_byte_more.stl", binary_stl({{o, x, y}}) + "x"},
        {"one_byte_less.stl", binary_stl({{o, x, y}}).substr(0, 133)},
        {"header_only.stl", std::string(80, ' ')},
        // ASCII.
        {"two_solids.stl", "solid a\n" + facet + "endsolid a\nsolid b\n" + facet + "endsolid b\n"},
        {"no_facets.stl", "solid a\nendsolid a\n"},
        {"no_endsolid.stl", "solid a\n" + facet},
        {"quad.stl", "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\n"
                     "endloop\nendfacet\nendsolid a\n"},
        {"two_vertices.stl", "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid a\n"},
        {"no_normal.stl", "solid a\nfacet\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid a\n"},
        {"vertex_split.stl", "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n0\nvertex 1 0 0\nvertex 0 1 0\n"
                             "endloop\nendfacet\nendsolid a\n"},
        {"glued.stl", "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0x\nvertex 1 0 0\nvertex 0 1 0\n"
                      "endloop\nendfacet\nendsolid a\n"},
        {"not_a_number.stl", "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 y 0\nvertex 1 0 0\nvertex 0 1 0\n"
                             "endloop\nendfacet\nendsolid a\n"},
        {"infinite.stl", "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 1e39 0\nvertex 1 0 0\nvertex 0 1 0\n"
                         "endloop\nendfacet\nendsolid a\n"},
        {"text_after.stl", "solid a\n" + facet + "endsolid a\ntrailing words\n"},
        {"words_after_name.stl", "solid a b c\n" + facet + "endsolid a\n"},
        {"newline_first.stl", "\nsolid a\n" + facet + "endsolid a\n"},
        {"bom.stl", "\xEF\xBB\xBFsolid a\n" + facet + "endsolid a\n"},
        {"nul.stl", std::string("solid a\n") + facet + "endsolid a\n" + std::string(1, '\0') + "junk"},
        {"form_feed.stl", "solid a\n" + facet + "\fendsolid a\n"},
        {"long_name.stl", "solid " + std::string(2000, 'n') + "\n" + facet + "endsolid\n"},
    };
    for (const auto& [name, bytes] : files) expect_taken_and_same(write_file(temp_dir() / name, bytes), false);
}

// Random ASCII files from STL's grammar and around it (white space of every kind, number forms,
// names, missing and extra tokens, polygons, several solids, text after the end), and random binary
// ones (attributes, headers): whatever each path makes of a file, both make the same. Many are taken
// by the fast reader (counted), the others must be declined.
TEST(Stl, GeneratedFilesMatchAssimp) {
    std::mt19937 rng(23);
    auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<std::uint32_t>(n)); };
    const char* spaces[] = {" ", "  ", "\t", " \t "};
    const char* breaks[] = {"\n", "\r\n", "\n\n", "\n  ", "\n\t"};
    auto space = [&] { return std::string(spaces[pick(4)]); };
    auto line_break = [&] { return std::string(breaks[pick(5)]); };
    auto number = [&] { return facet_test::random_number_text(rng); };
    int taken = 0;
    const int files = facet_test::sweep_size(600, 120);
    for (int i = 0; i < files; ++i) {
        std::string out;
        if (i % 4 == 3) {  // binary: random attributes and header words
            std::vector<StlTriangle> facets(1 + static_cast<std::size_t>(pick(8)));
            std::vector<std::uint16_t> attributes;
            for (auto& t : facets) {
                for (Vec3& p : t) p = {static_cast<float>(pick(3)), static_cast<float>(pick(3)), static_cast<float>(pick(3))};
                attributes.push_back(pick(4) == 0 ? static_cast<std::uint16_t>(rng()) : 0);
            }
            const char* headers[] = {"", "solid part", "COLOR=abcd", "exported by a CAD tool", "xCOLOR=1234 MATERIAL=5678"};
            out = binary_stl(facets, headers[pick(5)], attributes);
        } else {
            out = (pick(10) == 0 ? line_break() : "") + "solid" + (pick(2) ? space() + "part" + std::to_string(pick(9)) : "") +
                  (pick(10) == 0 ? space() + "extra" : "") + line_break();
            const int solids = pick(12) == 0 ? 2 : 1;
            for (int solid = 0; solid < solids; ++solid) {
                if (solid > 0) out += "solid" + space() + "second" + line_break();
                const int facets = pick(12) == 0 ? 0 : 1 + pick(6);
                for (int f = 0; f < facets; ++f) {
                    out += space() + "facet" + space() + (pick(20) == 0 ? "" : "normal" + space() + number() + space() + number() + space() + number()) + line_break();
                    if (pick(30) != 0) out += space() + "outer" + space() + "loop" + line_break();
                    const int corners = pick(15) == 0 ? 4 : 3;
                    for (int k = 0; k < corners; ++k)
                        out += space() + "vertex" + space() + number() + space() + number() + space() + number() + (pick(25) == 0 ? "x" : "") + line_break();
                    out += space() + "endloop" + line_break() + space() + "endfacet" + line_break();
                }
                out += (pick(20) == 0 ? "" : "endsolid" + (pick(2) ? space() + "part" : "")) + (pick(4) ? line_break() : "");
            }
            if (pick(15) == 0) out += "trailing text\n";
        }
        const std::string path = write_file(temp_dir() / ("generated_" + std::to_string(i) + ".stl"), out);
        taken += io_detail::read_stl(out).has_value();
        expect_same_as_assimp(path);
    }
    EXPECT_GT(taken, files / 5) << "the fast reader took too few of the generated files to test it";
}

// Cut and damaged copies of valid files: whatever each path makes of them (a scene, or an error
// naming the file), both make the same, and nothing crashes.
TEST(Stl, DamagedFilesMatchAssimp) {
    std::vector<StlTriangle> cube;
    const Vec3 c[8] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
    const int faces[6][3] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1}};
    for (const auto& f : faces) cube.push_back({c[f[0]], c[f[1]], c[f[2]]});
    const std::string good[2] = {binary_stl(cube), ascii_stl(cube)};
    const std::string alphabet = "0123456789 .-e\n\tfacetnormalvertexendloopsolid";
    std::mt19937 rng(11);
    for (int i = 0; i < facet_test::sweep_size(400, 80); ++i) {
        const std::string& from = good[i % 2];
        std::string bad = from;
        if (i % 3 == 0) {
            bad.resize(rng() % from.size());
        } else {
            for (int k = 0; k < 1 + i % 4; ++k)
                bad[rng() % bad.size()] = i % 2 ? alphabet[rng() % alphabet.size()] : static_cast<char>(rng());
        }
        expect_same_as_assimp(write_file(temp_dir() / ("damaged_" + std::to_string(i) + ".stl"), bad));
    }
}

}  // namespace
