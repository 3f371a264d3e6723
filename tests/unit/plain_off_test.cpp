// The OFF fast path (src/io/plain_off.hpp): load_model must give exactly the Scene the
// assimp path gives (io_detail::load_model_through_assimp), field by field and bit for bit, for
// CGAL's meshes, assimp's OFF test models and small files written here, including files the fast
// reader declines (it must decline them, and the result must still match) and damaged files
// (the same error). The fast path must actually be taken for the files it is meant for.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cmath>
#include <iomanip>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "facet/model.hpp"
#include "io/fast_path.hpp"
#include "io/joined_mesh.hpp"
#include "io/load_paths.hpp"
#include "facet/detail/thread_pool.hpp"
#include "io/plain_off.hpp"
#include "support/same_scene.hpp"
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;
using namespace facet;
using facet_test::expect_same_as_assimp;
using facet_test::read_file;
using facet_test::write_file;

bool fast_reader_takes(const std::string& path) { return io_detail::read_plain_off(read_file(path)).has_value(); }

fs::path temp_dir() { return facet_test::test_temp_dir("facet_plain_off_test"); }

TEST(PlainOff, CgalMeshesTakeTheFastPathAndMatchAssimp) {
    const std::optional<fs::path> dir = facet_test::cgal_meshes();
    if (!dir) GTEST_SKIP() << facet_test::cgal_meshes_missing();
    for (const char* name : {"bunny00.off", "armadillo.off", "elephant.off"}) {
        const std::string path = (*dir / name).string();
        EXPECT_TRUE(fast_reader_takes(path)) << path;
        expect_same_as_assimp(path);
        LoadOptions z_up_sharp;
        z_up_sharp.up_axis = UpAxis::z;
        z_up_sharp.crease_angle_degrees = 10;
        expect_same_as_assimp(path, z_up_sharp);
    }
    // COFF's colours, quads and polygons of up to 9 corners (triangulated as assimp does), faces
    // assimp drops with an error: of 10 corners (mpi.off) and a comment among the faces
    // (sphere966.off: read as a face of no corners, so the last face is never read).
    for (const char* name : {"dino.off", "cactus.off", "plane.off", "3torus.off", "corner_poly.off", "double-torus-example.off",
                             "P.off", "torus_quad.off", "mpi.off", "sphere966.off"}) {
        const std::string path = (*dir / name).string();
        EXPECT_TRUE(fast_reader_takes(path)) << path;
        expect_same_as_assimp(path);
    }
    // Read by two threads (the lines, the join and the normals shared): the same scene.
    LoadOptions two_threads;
    two_threads.threads = 2;
    expect_same_as_assimp((*dir / "bunny00.off").string(), two_threads);
}

TEST(PlainOff, AssimpTestModelsMatchAssimp) {
    FACET_REQUIRE_ASSIMP_MODELS();
    std::size_t files = 0;
    for (const auto& entry : fs::recursive_directory_iterator(facet_test::k_assimp_models)) {
        if (entry.path().extension() != ".off" && entry.path().extension() != ".OFF") continue;
        ++files;
        expect_same_as_assimp(entry.path().string());
    }
    EXPECT_GE(files, 3u);
}

// Small files in the accepted form, each with something the join or the numbering must get right.
TEST(PlainOff, AcceptedFormsMatchAssimp) {
    const fs::path dir = temp_dir();
    const std::vector<std::pair<std::string, std::string>> files = {
        // Duplicate positions joined; -0 and +0 joined, the first used one in file order kept.
        {"dup.off", "OFF\n6 2 0\n-0 0 0\n0 0 0\n1 0 0\n0 1 0\n1 0 0\n0 1 1\n3 1 2 3\n3 0 4 5\n"},
        // An unused -0 vertex first: the used +0 one represents the group.
        {"unused.off", "OFF\n5 1 0\n-0 0 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 1 2 3\n"},
        // Vertices used out of file order; blank lines, CRLF, tabs, trailing values on faces.
        {"order.off", "OFF\r\n\r\n5 2 0\r\n0 1 0\r\n\r\n0 0 1\r\n0\t1 1\r\n0 0 0\r\n1 0 0\r\n3 4 0 1 0.5 0.5 0.5\r\n3  3 4 0\r\n"},
        // Numbers as assimp's fast_atof reads them: exponents, signs, commas as decimal points,
        // a trailing dot, many digits, values between floats.
        {"numbers.off", "OFF\n4 2 0\n1e2 -2.5E-1 +3\n1,5 .25 7.\n0.123456789012345678 1.0000001 -0\n3 4 5\n3 0 1 2\n3 0 2 3\n"},
        // A degenerate triangle among good ones; a vertex line with a fourth value.
        {"degenerate.off", "OFF\n4 2 0\n0 0 0 9\n1 0 0\n0 1 0\n1 0 0\n3 0 1 2\n3 1 3 2\n"},
        // Equal tiny coordinates join as assimp joins them (distinct ones are declined below).
        {"tiny_equal.off", "OFF\n5 2 0\n1e-30 0 0\n1 0 0\n0 1 0\n1e-30 0 0\n0 0 1\n3 0 1 2\n3 3 2 4\n"},
        // Read, but nothing but degenerate triangles: load_model leaves the error to the assimp path.
        {"all_degenerate.off", "OFF\n3 1 0\n0 0 0\n0 0 0\n0 1 0\n3 0 1 2\n"},
        // The header as assimp's NextToken reads it: '#' lines (indented too), counts on the
        // keyword's line, blank lines and lines of spaces before the body, a body line indented.
        {"comment.off", "# made by hand\n#\nOFF\n# counts next\n  # indented\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
        {"counts_on_first_line.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
        {"spaces_line.off", "OFF\n3 1 0\n   \n\t0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
        // COFF: four numbers after the position (integers or not, clamped by the conversion), the
        // colours of a joined vertex its first one's; a '#' cuts the rest to 0, 0, 1.
        {"coff.off", "COFF\n4 2 0\n0 0 0 1 0 0 1\n1 0 0 0 255 0 1\n0 1 0 0 0 0.5 0.25\n1 0 0 9 9 9 9\n3 0 1 2\n3 3 2 0\n"},
        {"coff_cut.off", "COFF\n3 1 0\n0 0 0 0.5#red\n1 0 0 0.25 0.5# 1\n0 1 0 -1 2 nan 0.5\n3 0 1 2\n"},
        // Quads: convex, concave at a corner other than the first, non-planar; a triangle and a
        // quad starting at the vertex the last one began with (NGONEncoder rotates them).
        {"quad.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n"},
        {"quads.off", "OFF\n7 5 0\n0 0 0\n2 0 0\n2 2 0\n0.5 0.5 0\n0 2 1\n3 3 3\n-1 1 0.5\n"
                      "4 0 1 2 3\n4 3 0 4 6\n3 2 5 1\n3 2 4 5\n4 2 4 5 1\n"},
        // Polygons of 5 to 9 corners, convex and not, among triangles; shared first corners.
        // Faces assimp drops with an error (and reads on for the count): of no corners, of 10, a
        // comment among the faces; here the lines run out first (another error).
        {"dropped_faces.off", "OFF\n10 6 0\n0 0 0\n1 0 0\n2 0 0\n3 1 0\n3 2 0\n2 3 0\n1 3 0\n0 2 0\n0 1 0\n1 1 0\n"
                              "10 0 1 2 3 4 5 6 7 8 9\n3 0 1 9\n0\n# 2 faces\n3 1 2 3\n3 4 5 6\n"},
        {"dropped_and_quads.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n# faces\n4 0 1 2 3\n3 0 2 3\n"},
        // Lines enough after a drop: the last face read is not used (here the only quad: no
        // Triangulate, the triangles as they are).
        {"dropped_then_all_faces.off", "OFF\n4 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n12 0 1 2 3 0 1 2 3 0 1 2 3\n"
                                       "3 0 2 3\n3 3 0 2\n4 0 1 2 3\n3 1 2 3\n"},
        {"polygons.off", "OFF\n10 5 0\n0 0 0\n2 0 0\n3 1 0\n2 2 0\n1 0.5 0\n0 2 0\n-1 1 0\n0 0 1\n1 1 2\n2 0 1\n"
                         "5 0 1 2 3 5\n6 0 1 2 3 4 5\n9 0 1 2 3 4 5 6 7 8\n3 0 8 9\n7 9 8 7 6 5 4 3\n"},
    };
    for (const auto& [name, text] : files) {
        const std::string path = write_file(dir / name, text);
        EXPECT_TRUE(fast_reader_takes(path)) << name;
        expect_same_as_assimp(path);
    }
}

// Files the fast reader must leave to assimp (because assimp reads them differently or reports
// something), and load_model must still give assimp's answer for them.
TEST(PlainOff, DeclinedFormsGoThroughAssimp) {
    const fs::path dir = temp_dir();
    const std::vector<std::pair<std::string, std::string>> files = {
        {"comment_among_vertices.off", "OFF\n3 1 0\n0 0 0\n# vertices\n1 0 0\n0 1 0\n3 0 1 2\n"},
        {"colour_then_space_then_comment.off", "COFF\n3 1 0\n0 0 0 1 #\n1 0 0 0 1 0 1\n0 1 0 0 0 1 1\n3 0 1 2\n"},
        {"vertex_on_counts_line.off", "OFF\n3 1 0 0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
        {"noff.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n"},
        {"coff_three_channels.off", "COFF\n3 1 0\n0 0 0 1 0 0\n1 0 0 0 1 0\n0 1 0 0 0 1\n3 0 1 2\n"},
        {"line_face.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n2 0 1\n"},
        {"polygon_out_of_range.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 4\n"},
        {"bom.off", "\xEF\xBB\xBFOFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
        {"no_edge_count.off", "OFF\n3 1\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
        {"index_out_of_range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"},
        {"nan.off", "OFF\n4 2 0\nnan 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 1 2 3\n"},
        {"tiny.off", "OFF\n6 2 0\n0 0 0\n1e-30 0 0\n0 1 0\n0 0 1\n0 1 1\n0 2 1\n3 0 2 3\n3 1 4 5\n"},
        {"too_few_vertices.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n"},
        {"too_few_faces.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
        {"not_a_number.off", "OFF\n3 1 0\n0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n"},
        {"zero_faces.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n"},
        {"spaces_line_in_body.off", "OFF\n3 1 0\n0 0 0\n   \n1 0 0\n0 1 0\n3 0 1 2\n"},
        {"nul.off", std::string("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n\0junk", 39)},
        {"long_line.off", "OFF\n3 1 0\n0 0 0" + std::string(5000, ' ') + "\n1 0 0\n0 1 0\n3 0 1 2\n"},
        // The last line read is too long past its numbers (checked after the reading, too).
        {"long_last_line.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2" + std::string(5000, ' ') + "\n"},
        {"long_middle_line.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 " + std::string(5000, '7') + "\n3 0 2 1\n"},
    };
    for (const auto& [name, text] : files) {
        const std::string path = write_file(dir / name, text);
        EXPECT_FALSE(fast_reader_takes(path)) << name;
        expect_same_as_assimp(path);
    }
}

// Random files from OFF's grammar and around it (header forms, comments, blank lines, CRLF, tabs,
// number forms, extra values, polygons, indices out of range, short and long counts, text after the
// end): whatever each path makes of a file, both make the same. Many are taken by the fast reader
// (counted), the others must be declined.
TEST(PlainOff, GeneratedFilesMatchAssimp) {
    std::mt19937 rng(29);
    auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<std::uint32_t>(n)); };
    const char* spaces[] = {" ", "  ", "\t", " \t"};
    bool crlf = false;  // a file's line ends are alike (set per file), now and then with a blank line or one of spaces
    auto space = [&] { return std::string(spaces[pick(4)]); };
    auto line_break = [&] {
        const std::string end = crlf ? "\r\n" : "\n";
        const int r = pick(100);
        return r < 3 ? end + end : r < 4 ? end + "   " + end : end;
    };
    auto number = [&] { return facet_test::random_number_text(rng); };
    int taken = 0, taken_coff = 0, taken_polygons = 0;
    const int files = facet_test::sweep_size(600, 120);
    for (int i = 0; i < files; ++i) {
        crlf = pick(4) == 0;
        const int vertices = 3 + pick(8), faces = 1 + pick(8);
        const int said_vertices = pick(20) == 0 ? vertices + 1 : vertices, said_faces = pick(20) == 0 ? faces - 1 : faces;
        const bool coff = pick(8) == 0;
        std::string out = (pick(15) == 0 ? std::string("# made by a test") + line_break() : "") + (coff ? "COFF" : "OFF");
        out += pick(15) == 0 ? space() : line_break();
        out += std::to_string(said_vertices) + space() + std::to_string(said_faces) + (pick(10) == 0 ? "" : space() + "0") + line_break();
        for (int v = 0; v < vertices; ++v) {
            out += (pick(10) == 0 ? space() : "") + number() + space() + number() + space() + number();
            if (coff) out += space() + number() + space() + number() + space() + number();  // a colour (its alpha next)
            if (pick(10) == 0 || (coff && pick(20) != 0)) out += space() + number();       // a fourth value
            if (pick(40) == 0) out += " # note";
            out += line_break();
        }
        bool polygons = false;
        for (int f = 0; f < faces; ++f) {
            const int corners = pick(6) == 0 ? 4 + pick(7) : 3;  // up to 10: assimp drops those
            polygons |= corners > 3;
            out += std::to_string(corners);
            for (int k = 0; k < corners; ++k) out += space() + std::to_string(pick(40) == 0 ? vertices : pick(vertices));
            if (pick(10) == 0) out += space() + "0.5 0.5 0.5";  // a colour
            out += line_break();
        }
        if (pick(15) == 0) out += "trailing" + line_break();
        const std::string path = write_file(temp_dir() / ("generated_" + std::to_string(i) + ".off"), out);
        const bool took = io_detail::read_plain_off(out).has_value();
        taken += took;
        taken_coff += took && coff;
        taken_polygons += took && polygons;
        expect_same_as_assimp(path);
    }
    EXPECT_GT(taken, files / 5) << "the fast reader took too few of the generated files to test it";
    // One file in a hundred at least: the sanitizer builds draw a quarter of the files (150), where
    // the seeded generator gives 3 COFF files the fast reader takes.
    EXPECT_GT(taken_coff, files / 100);
    EXPECT_GT(taken_polygons, files / 20);
}

// Cut and damaged copies of a valid file: whatever each path makes of them (a scene, or an error
// naming the file), both make the same, and nothing crashes.
TEST(PlainOff, DamagedFilesMatchAssimp) {
    const fs::path dir = temp_dir();
    std::string good = "OFF\n8 6 0\n";
    for (int i = 0; i < 8; ++i) good += std::to_string(i & 1) + " " + std::to_string((i >> 1) & 1) + " " + std::to_string(i >> 2) + "\n";
    for (const char* f : {"3 0 1 3", "3 0 3 2", "3 4 6 7", "3 4 7 5", "3 0 4 5", "3 0 5 1"}) good += std::string(f) + "\n";
    std::mt19937 rng(7);
    const std::string alphabet = "0123456789 .-e\n#,x";
    for (int i = 0; i < facet_test::sweep_size(300, 60); ++i) {
        std::string bad = good;
        if (i % 3 == 0) {
            bad.resize(rng() % good.size());
        } else {
            for (int k = 0; k < 1 + i % 4; ++k) bad[rng() % bad.size()] = alphabet[rng() % alphabet.size()];
        }
        const std::string path = write_file(dir / ("damaged_" + std::to_string(i) + ".off"), bad);
        expect_same_as_assimp(path);
    }
}

// Files large enough to be read in several pieces and by two threads (plain_off.cpp cuts the body
// every 64 KB at a line start): the threads must give the one-thread mesh, and both assimp's, with
// what declines a file (a NUL, a long line, a bad number, an index out of range, lines missing)
// placed deep in the body, past the first pieces.
TEST(PlainOff, LargeFilesReadInPiecesByThreadsMatchAssimp) {
    std::mt19937 rng(41);
    auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<std::uint32_t>(n)); };
    const int vertices = 6000, faces = 9000;
    std::string body;
    std::vector<std::size_t> line_at;  // where each vertex and face line begins in `body`
    std::string coloured;  // the same as COFF, every 7th face a quad
    for (int v = 0; v < vertices; ++v) {
        body += pick(50) == 0 ? "\r\n\n" : "";
        line_at.push_back(body.size());
        const std::string position = facet_test::random_number_text(rng) + " " + facet_test::random_number_text(rng) + "\t" +
                                     facet_test::random_number_text(rng);
        body += position + (pick(20) == 0 ? " 0.5" : "") + "\n";
        coloured += position + " " + std::to_string(pick(256)) + " 0.5 1 255\n";
    }
    for (int f = 0; f < faces; ++f) {
        line_at.push_back(body.size());
        body += "3 " + std::to_string(pick(vertices)) + " " + std::to_string(pick(vertices)) + "  " +
                std::to_string(pick(vertices)) + (pick(30) == 0 ? std::string(300, ' ') : "") + "\n";
        const int corners = f % 7 == 0 ? 4 : 3;
        coloured += std::to_string(corners);
        for (int k = 0; k < corners; ++k) coloured += " " + std::to_string(pick(vertices));
        coloured += "\n";
    }
    const std::string header = "OFF\n" + std::to_string(vertices) + " " + std::to_string(faces) + " 0\n";
    ASSERT_GT(body.size(), 300'000u);
    auto with = [&](std::size_t line, const std::string& replacement) {
        return header + body.substr(0, line_at[line]) + replacement + body.substr(line_at[line + 1]);
    };
    const std::vector<std::pair<std::string, std::string>> files = {
        {"good", header + body},
        {"good_coff_polygons", "C" + header + coloured},
        {"nul", with(vertices + 5000, std::string("3 1 2 3\n\0\n", 10))},
        {"long_line", with(vertices + 4000, "3 1 2 3" + std::string(5000, ' ') + "\n")},
        {"not_a_number", with(5000, "1 x 2\n")},
        {"index_out_of_range", with(vertices + 8000, "3 1 2 " + std::to_string(vertices) + "\n")},
        {"lines_missing", header + body.substr(0, line_at[vertices + faces - 3])},
    };
    detail::ThreadPool two(2);
    LoadOptions threads;
    threads.threads = 2;
    for (const auto& [name, text] : files) {
        SCOPED_TRACE(name);
        const std::optional<io_detail::PlainOffMesh> alone = io_detail::read_plain_off(text);
        const std::optional<io_detail::PlainOffMesh> shared =
            io_detail::read_plain_off_with_header(text, io_detail::parse_off_header(text), &two);
        EXPECT_EQ(alone.has_value(), name.starts_with("good"));
        ASSERT_EQ(shared.has_value(), alone.has_value());
        if (alone) {
            EXPECT_EQ(facet_test::bits_of(shared->positions), facet_test::bits_of(alone->positions));
            EXPECT_EQ(shared->indices, alone->indices);
            EXPECT_EQ(facet_test::bits_of(shared->colours), facet_test::bits_of(alone->colours));
        }
        const std::string path = write_file(temp_dir() / ("large_" + name + ".off"), text);
        expect_same_as_assimp(path, threads);
    }
}

// The join shared between threads (io/joined_mesh.hpp): each thread takes the positions of its
// share of hashes and numbers the representatives in its share of the corners, and the mesh is the
// one thread's, field by field: joined duplicates (-0 as +0), unused vertices left out, the
// numbering by first use, degenerate triangles counted; and nothing for distinct tiny positions.
// Meshes 6 and 7 have no two positions alike, which one thread numbers without a join.
TEST(JoinIdenticalVertices, SharedBetweenThreadsGivesTheOneThreadMesh) {
    std::mt19937 rng(53);
    detail::ThreadPool two(2), three(3);
    for (int i = 0; i < 8; ++i) {
        SCOPED_TRACE("mesh " + std::to_string(i));
        std::vector<Vec3> positions;
        const int distinct = i % 2 ? 500 : 20000;  // many corners per position, or few
        for (int v = 0; v < distinct; ++v)
            positions.push_back(i < 6 ? Vec3{static_cast<float>(rng() % 1000) / 7, static_cast<float>(rng() % 1000) / 3, v % 5 ? 1.0f : -0.0f}
                                      : Vec3{static_cast<float>(v) / 7, static_cast<float>(rng() % 1000) / 3, v % 5 ? 1.0f : -0.0f});
        if (i == 7) positions[9] = {1e-30f, -0.0f, 0.0f};  // tiny: its key is (0, 0, 0), alone
        for (int v = 0; v < (i < 6 ? distinct / 4 : 0); ++v) {  // duplicates, some as +0 where the first is -0
            Vec3 p = positions[rng() % positions.size()];
            if (p.z == 0) p.z = 0.0f;
            positions.push_back(p);
        }
        if (i == 5) positions.push_back({1e-30f, 0, 0}), positions.push_back({0, 0, 0});  // assimp might join them
        std::vector<std::uint32_t> indices;
        for (int c = 0; c < 3 * 12000; ++c) indices.push_back(static_cast<std::uint32_t>(rng() % (positions.size() - 7)));
        if (i == 5) indices.push_back(static_cast<std::uint32_t>(positions.size() - 2)), indices.push_back(static_cast<std::uint32_t>(positions.size() - 1)), indices.push_back(0);
        const std::optional<io_detail::JoinedMesh> alone = io_detail::join_identical_vertices(positions, indices);
        EXPECT_EQ(alone.has_value(), i != 5);
        for (detail::ThreadPool* pool : {&two, &three}) {
            const std::optional<io_detail::JoinedMesh> shared = io_detail::join_identical_vertices(positions, indices, pool);
            ASSERT_EQ(shared.has_value(), alone.has_value());
            if (!alone) continue;
            EXPECT_EQ(facet_test::bits_of(shared->positions), facet_test::bits_of(alone->positions));
            EXPECT_EQ(shared->indices, alone->indices);
            EXPECT_EQ(facet_test::bits_of(shared->colours), facet_test::bits_of(alone->colours));
            EXPECT_EQ(shared->degenerate, alone->degenerate);
            EXPECT_EQ(shared->source, alone->source);
            EXPECT_LT(alone->positions.size(), positions.size());  // something was joined or left out
        }
    }
}

// The readers' input: the file's bytes exactly, a NUL after them; nothing when the file is not
// (any longer) the size its check found.
TEST(ReadWholeFile, TheBytesAndANulOrNothing) {
    const fs::path dir = temp_dir();
    std::string text;
    for (int i = 0; i < 70000; ++i) text += static_cast<char>('a' + i % 26);
    const std::string path = write_file(dir / "whole.txt", text);
    const std::optional<io_detail::FileBytes> bytes = io_detail::read_whole_file(path, text.size());
    ASSERT_TRUE(bytes.has_value());
    EXPECT_EQ(bytes->view(), text);
    EXPECT_EQ(bytes->data()[bytes->size()], '\0');
    EXPECT_FALSE(io_detail::read_whole_file(path, text.size() - 1).has_value());  // grew since
    EXPECT_FALSE(io_detail::read_whole_file(path, text.size() + 1).has_value());  // shrank since
    EXPECT_FALSE(io_detail::read_whole_file((dir / "missing.txt").string(), 1).has_value());
    const std::optional<io_detail::FileBytes> empty = io_detail::read_whole_file(write_file(dir / "empty.txt", ""), 0);
    ASSERT_TRUE(empty.has_value());
    EXPECT_EQ(empty->size(), 0u);
    EXPECT_EQ(empty->data()[0], '\0');
}

// The same of a mapped file: for a size in whole pages too (its NUL past the file's last page).
TEST(MapWholeFile, TheBytesAndANulOrNothing) {
    const fs::path dir = temp_dir();
    for (const std::size_t size : {std::size_t{70000}, std::size_t{16} * 4096}) {
        std::string text;
        for (std::size_t i = 0; i < size; ++i) text += static_cast<char>('a' + i % 26);
        const std::string path = write_file(dir / "mapped.txt", text);
        const std::optional<io_detail::FileBytes> bytes = io_detail::map_whole_file(path, text.size());
        ASSERT_TRUE(bytes.has_value()) << size;
        EXPECT_EQ(bytes->view(), text) << size;
        EXPECT_EQ(bytes->data()[bytes->size()], '\0') << size;
        EXPECT_FALSE(io_detail::map_whole_file(path, text.size() - 1).has_value()) << size;  // grew since
        EXPECT_FALSE(io_detail::map_whole_file(path, text.size() + 1).has_value()) << size;  // shrank since
    }
    EXPECT_FALSE(io_detail::map_whole_file((dir / "missing.txt").string(), 1).has_value());
}

// Whether `p` lies in a mapping of the file `path` (/proc/self/maps).
bool in_mapping_of(const char* p, const fs::path& path) {
    std::ifstream maps("/proc/self/maps");
    const auto at = reinterpret_cast<std::uintptr_t>(p);
    for (std::string line; std::getline(maps, line);) {
        std::uintptr_t start = 0, end = 0;
        char dash = 0;
        std::istringstream fields(line);
        fields >> std::hex >> start >> dash >> end;
        if (at >= start && at < end) return line.find(fs::canonical(path).string()) != std::string::npos;
    }
    return false;
}

// The readers' bytes: with map_files, a mapping of the file from FileBytes::k_fresh_from bytes (the
// copy's own fresh pages saved) and a copy below it (heap memory the process reuses); a copy always
// without map_files. The same bytes and NUL each way.
TEST(WholeFile, MappedWithMapFilesFromTheFreshPagesSize) {
    const fs::path dir = temp_dir();
    LoadOptions mapped;
    mapped.map_files = true;
    for (const std::size_t size : {std::size_t{70000}, io_detail::FileBytes::k_fresh_from}) {
        std::string text(size, 'a');
        for (std::size_t i = 0; i < size; i += 4093) text[i] = static_cast<char>('b' + i % 23);
        const fs::path path = dir / "whole_file.txt";
        write_file(path, text);
        for (const bool map : {false, true}) {
            const std::optional<io_detail::FileBytes> bytes = io_detail::whole_file(path.string(), size, map ? mapped : LoadOptions{});
            ASSERT_TRUE(bytes.has_value()) << size << map;
            EXPECT_TRUE(bytes->view() == text) << size << map;
            EXPECT_EQ(bytes->data()[size], '\0') << size << map;
            EXPECT_EQ(in_mapping_of(bytes->data(), path), map && size >= io_detail::FileBytes::k_fresh_from) << size << map;
        }
    }
    fs::remove(dir / "whole_file.txt");
}

}  // namespace
