// The plain PLY fast path (src/io/ply.hpp): load_model must give exactly the Scene the assimp path
// gives, bit for bit, for assimp's PLY test models, a CGAL mesh written as PLY in every encoding and
// small files written here, including files the fast reader declines (it must decline them, and the
// result must still match) and damaged files (the same error). The fast path must actually be taken
// for the files it is meant for.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "facet/mesh.hpp"
#include "facet/model.hpp"
#include "io/ply.hpp"
#include "support/same_scene.hpp"
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;
using namespace facet;
using facet_test::expect_same_as_assimp;
using facet_test::write_file;


fs::path temp_dir() { return facet_test::test_temp_dir("facet_ply_test"); }

void expect_taken_and_same(const std::string& path, bool taken = true) {
    facet_test::expect_read_as_told_and_same(path, io_detail::read_plain_ply, taken);
}

enum class Encoding { ascii, little_endian, big_endian };

// How a test PLY is written: its encoding, the coordinates' type, extra vertex properties assimp
// ignores, and the face list's types and name.
struct Layout {
    Encoding encoding = Encoding::ascii;
    bool doubles = false;
    bool extras = false;  // "confidence" (float) before x, "intensity" (uchar) after z
    std::string count_type = "uchar", index_type = "int", list_name = "vertex_indices";
    std::string comment = {};  // a header comment line, if any
};

template <class T>
void put(std::string& out, T value, bool big_endian) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &value, sizeof(T));
    if (big_endian) std::reverse(b, b + sizeof(T));
    out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

// An integer of the named PLY type.
void put_integer(std::string& out, const std::string& type, std::int64_t v, bool big_endian) {
    if (type == "uchar" || type == "uint8") put(out, static_cast<std::uint8_t>(v), big_endian);
    else if (type == "ushort" || type == "uint16") put(out, static_cast<std::uint16_t>(v), big_endian);
    else if (type == "short" || type == "int16") put(out, static_cast<std::int16_t>(v), big_endian);
    else if (type == "uint" || type == "uint32") put(out, static_cast<std::uint32_t>(v), big_endian);
    else put(out, static_cast<std::int32_t>(v), big_endian);
}

std::string ply(const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& indices, const Layout& l = {}) {
    std::ostringstream h;
    h << "ply\nformat "
      << (l.encoding == Encoding::ascii ? "ascii" : l.encoding == Encoding::little_endian ? "binary_little_endian" : "binary_big_endian")
      << " 1.0\n";
    if (!l.comment.empty()) h << "comment " << l.comment << "\n";
    h << "element vertex " << positions.size() << "\n";
    if (l.extras) h << "property float confidence\n";
    for (const char* axis : {"x", "y", "z"}) h << "property " << (l.doubles ? "double " : "float ") << axis << "\n";
    if (l.extras) h << "property uchar intensity\n";
    h << "element face " << indices.size() / 3 << "\nproperty list " << l.count_type << " " << l.index_type << " " << l.list_name
      << "\nend_header\n";
    std::string out = h.str();
    const bool big = l.encoding == Encoding::big_endian;
    if (l.encoding == Encoding::ascii) {
        std::ostringstream b;
        b << std::setprecision(17);
        for (const Vec3& p : positions) {
            if (l.extras) b << "0.5 ";
            b << p.x << ' ' << p.y << ' ' << p.z;
            if (l.extras) b << " 200";
            b << "\n";
        }
        for (std::size_t t = 0; t < indices.size(); t += 3) b << "3 " << indices[t] << ' ' << indices[t + 1] << ' ' << indices[t + 2] << "\n";
        return out + b.str();
    }
    for (const Vec3& p : positions) {
        if (l.extras) put(out, 0.5f, big);
        for (float c : {p.x, p.y, p.z}) {
            if (l.doubles) put(out, static_cast<double>(c), big);
            else put(out, c, big);
        }
        if (l.extras) put(out, std::uint8_t{200}, big);
    }
    for (std::size_t t = 0; t < indices.size(); t += 3) {
        put_integer(out, l.count_type, 3, big);
        for (std::size_t k = 0; k < 3; ++k) put_integer(out, l.index_type, indices[t + k], big);
    }
    return out;
}

// The data after a file's header.
std::string binary_body(const std::string& file) { return file.substr(file.find("end_header\n") + 11); }

TEST(PlainPly, AssimpTestModelsMatchAssimp) {
    FACET_REQUIRE_ASSIMP_MODELS();
    const fs::path dir = facet_test::k_assimp_models / "PLY";
    expect_taken_and_same((dir / "cube_binary.ply").string());
    // Quads, normals, colours, texture coordinates, points: assimp's.
    for (const char* name : {"cube.ply", "Wuson.ply", "cube_uv.ply", "float-color.ply", "issue623.ply", "points.ply", "pond.0.ply"})
        expect_taken_and_same((dir / name).string(), false);
}

// A large mesh in every encoding, its faces shuffled so that shared vertices lie far apart in the file.
TEST(PlainPly, CgalBunnyInEveryEncodingMatchesAssimp) {
    const std::optional<fs::path> dir = facet_test::cgal_meshes();
    if (!dir) GTEST_SKIP() << facet_test::cgal_meshes_missing();
    const Result<LoadedModel> bunny = load_model((*dir / "bunny00.off").string());
    ASSERT_TRUE(bunny.ok()) << bunny.error().message;
    const Mesh& mesh = bunny->scene.objects.at(0).mesh;
    std::vector<std::uint32_t> indices = mesh.indices;
    std::vector<std::size_t> order(indices.size() / 3);
    for (std::size_t t = 0; t < order.size(); ++t) order[t] = t;
    std::shuffle(order.begin(), order.end(), std::mt19937(5));
    for (std::size_t t = 0; t < order.size(); ++t)
        for (std::size_t k = 0; k < 3; ++k) indices[3 * t + k] = mesh.indices[3 * order[t] + k];
    for (Encoding e : {Encoding::ascii, Encoding::little_endian, Encoding::big_endian}) {
        const std::string path =
            write_file(temp_dir() / ("bunny_" + std::to_string(static_cast<int>(e)) + ".ply"), ply(mesh.positions, indices, {.encoding = e}));
        expect_taken_and_same(path);
        LoadOptions z_up_sharp;
        z_up_sharp.up_axis = UpAxis::z;
        z_up_sharp.crease_angle_degrees = 10;
        expect_same_as_assimp(path, z_up_sharp);
    }
}

const std::vector<Vec3> k_square = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-0.0f, 0, 0}, {5, 5, 5}};
const std::vector<std::uint32_t> k_square_faces = {0, 1, 2, 4, 2, 3};  // vertex 5 unused; 4 is 0 again, as -0

// Small files in the accepted forms, each with something the reading, the join or the numbering must
// get right.
TEST(PlainPly, AcceptedFormsMatchAssimp) {
    std::vector<std::pair<std::string, Layout>> layouts;
    for (Encoding e : {Encoding::ascii, Encoding::little_endian, Encoding::big_endian}) {
        const std::string n = std::to_string(static_cast<int>(e));
        layouts.push_back({"plain_" + n, {.encoding = e}});
        layouts.push_back({"doubles_" + n, {.encoding = e, .doubles = true}});
        layouts.push_back({"extras_" + n, {.encoding = e, .extras = true}});
        layouts.push_back({"types_" + n, {.encoding = e, .count_type = "uint8", .index_type = "uint16", .list_name = "vertex_index"}});
        layouts.push_back({"comment_" + n, {.encoding = e, .index_type = "uint", .comment = "made by facet's tests"}});
    }
    for (const auto& [name, layout] : layouts)
        expect_taken_and_same(write_file(temp_dir() / (name + ".ply"), ply(k_square, k_square_faces, layout)));
    // Coordinates as fast_atof reads them: exponents, signs, a leading dot, many digits (double and float).
    const std::string numbers = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty double y\nproperty float z\n"
                                "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                "1e2 -2.5E-1 +3\n.25 0.12345678901234567890123 -0\n0.123456789012345678 1e-30 7.\n3 0 1 2\n";
    expect_taken_and_same(write_file(temp_dir() / "numbers.ply", numbers));
    // CRLF line ends, runs of spaces and tabs, trailing white space.
    const std::string spacing = "ply\r\nformat ascii 1.0\r\nobj_info x\r\nelement vertex 3\r\nproperty float x\r\nproperty float y\r\n"
                                "property float z\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
                                "0  0\t0 \r\n1 0 0\r\n0 1 0\r\n3 0  1 2 \r\n\r\n  \n";
    expect_taken_and_same(write_file(temp_dir() / "spacing.ply", spacing));
    // Properties in another order, an ignored one between the coordinates; comments before the first
    // element and after the face list.
    const std::string order = "ply\nformat ascii 1.0\ncomment first\nelement vertex 4\nproperty float y\nproperty uchar intensity\n"
                              "property double z\nproperty float x\nelement face 2\nproperty list uint8 uint32 vertex_index\n"
                              "obj_info last\nend_header\n1 7 2 3\n0 255 0 1\n0 0 4 0\n1 1 1 1\n3 0 1 2\n3 3 2 1\n";
    expect_taken_and_same(write_file(temp_dir() / "order.ply", order));
}

// Files the fast reader must leave to assimp, and load_model must still give assimp's answer for them.
TEST(PlainPly, DeclinedFormsGoThroughAssimp) {
    const std::string tri = "3 0 1 2\n";
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string faces = "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const std::string body = "0 0 0\n1 0 0\n0 1 0\n" + tri;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<std::pair<std::string, std::string>> files = {
        {"normals.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                        "property float nx\nproperty float ny\nproperty float nz\n" + faces +
                        "0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n" + tri},
        {"colours.ply", head + "property uchar red\nproperty uchar green\nproperty uchar blue\n" + faces +
                        "0 0 0 1 2 3\n1 0 0 1 2 3\n0 1 0 1 2 3\n" + tri},
        {"int_coordinates.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty int x\nproperty int y\nproperty int z\n" + faces + body},
        {"no_z.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n" + faces + "0 0\n1 0\n0 1\n" + tri},
        {"quad.ply", head + faces + "0 0 0\n1 0 0\n0 1 0\n4 0 1 2 0\n"},
        {"index_out_of_range.ply", head + faces + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"},
        {"negative_index.ply", head + faces + "0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n"},
        {"nan.ply", head + faces + "nan 0 0\n1 0 0\n0 1 0\n" + tri},
        {"too_few_vertices.ply", head + faces + "0 0 0\n1 0 0\n" + tri},
        {"extra_data.ply", head + faces + body + "junk\n"},
        {"blank_line.ply", head + faces + "0 0 0\n\n1 0 0\n0 1 0\n" + tri},
        {"two_vertices_on_a_line.ply", head + faces + "0 0 0 1 0 0\n0 1 0\n" + tri},
        {"value_on_next_line.ply", head + faces + "0 0\n0\n1 0 0\n0 1 0\n" + tri},
        {"glued.ply", head + faces + "0 0 0x\n1 0 0\n0 1 0\n" + tri},
        {"edges.ply", head + faces.substr(0, faces.size() - 11) + "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n" +
                      body + "0 1\n"},
        {"uppercase.ply", "PLY\n" + head.substr(4) + faces + body},
        {"version.ply", "ply\nformat ascii 2.0\n" + head.substr(21) + faces + body},
        {"no_faces.ply", head + "end_header\n0 0 0\n1 0 0\n0 1 0\n"},
        {"comment_before_format.ply", "ply\ncomment first\n" + head.substr(4) + faces + body},
        // Comments inside a property list: assimp ends the list there, or misreads it.
        {"comment_among_properties.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\ncomment m\nproperty float y\n"
                                         "property float z\n" + faces + body},
        {"comment_before_properties.ply", "ply\nformat ascii 1.0\nelement vertex 3\ncomment m\nproperty float x\nproperty float y\n"
                                          "property float z\n" + faces + body},
        {"comment_after_properties.ply", head + "comment m\n" + faces + body},
        {"binary_crlf.ply", "ply\r\nformat binary_little_endian 1.0\r\nelement vertex 3\r\nproperty float x\r\nproperty float y\r\n"
                            "property float z\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n" +
                            binary_body(ply({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2}, {.encoding = Encoding::little_endian}))},
        {"binary_nan.ply", ply({{nan, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2}, {.encoding = Encoding::little_endian})},
        {"binary_short.ply", ply(k_square, k_square_faces, {.encoding = Encoding::little_endian}).substr(0, 200)},
        {"binary_long.ply", ply(k_square, k_square_faces, {.encoding = Encoding::little_endian}) + "x"},
        {"tiny_distinct.ply", ply({{1e-30f, 0, 0}, {2e-30f, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 2, 3, 1, 3, 2})},
    };
    for (const auto& [name, bytes] : files) expect_taken_and_same(write_file(temp_dir() / name, bytes), false);
}

// Random headers from PLY's grammar (formats, property orders and types, ignored and unknown
// properties, comments anywhere, list types) with data that fits them: whatever each path makes of a
// file, both make the same. Many are taken by the fast reader (counted), the others must be declined.
TEST(PlainPly, GeneratedFilesMatchAssimp) {
    std::mt19937 rng(17);
    auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<std::uint32_t>(n)); };
    const char* formats[] = {"ascii", "binary_little_endian", "binary_big_endian"};
    const char* list_counts[] = {"uchar", "uint8", "int", "ushort"};
    const char* list_indices[] = {"int", "uint", "int32", "uint32", "short", "ushort"};
    int taken = 0;
    const int files = facet_test::sweep_size(600, 120);
    for (int i = 0; i < files; ++i) {
        const int format = pick(3);
        const bool big = format == 2;
        struct Prop {
            std::string name, type;
        };
        std::vector<Prop> props = {{"x", pick(2) ? "float" : "double"}, {"y", pick(2) ? "float" : "double"},
                                   {"z", pick(2) ? "float" : "double"}};
        if (pick(3) == 0) props.push_back({"confidence", "float"});
        if (pick(3) == 0) props.push_back({"intensity", pick(2) ? "uchar" : "float"});
        if (pick(8) == 0) props.push_back({"nx", "float"});
        std::shuffle(props.begin(), props.end(), rng);
        const int vertices = 3 + pick(10), faces = 1 + pick(10);
        const std::string count_type = list_counts[pick(4)], index_type = list_indices[pick(6)];
        auto comment = [&]() { return std::string(pick(2) ? "comment c " : "obj_info o ") + std::to_string(pick(100)) + "\n"; };
        std::string out = std::string("ply\n") + (pick(20) == 0 ? comment() : "") + "format " + formats[format] + " 1.0\n";
        if (pick(3) == 0) out += comment();
        out += "element vertex " + std::to_string(vertices) + "\n";
        const int comment_at = pick(6) == 0 ? pick(static_cast<int>(props.size()) + 1) : -1;
        for (std::size_t k = 0; k < props.size(); ++k) {
            if (static_cast<int>(k) == comment_at) out += comment();
            out += "property " + props[k].type + " " + props[k].name + "\n";
        }
        if (comment_at == static_cast<int>(props.size())) out += comment();
        out += "element face " + std::to_string(faces) + "\nproperty list " + count_type + " " + index_type + " " +
               (pick(2) ? "vertex_indices" : "vertex_index") + "\n";
        if (pick(3) == 0) out += comment();
        out += "end_header\n";
        std::ostringstream text;
        text << std::setprecision(9);
        for (int v = 0; v < vertices; ++v) {
            for (std::size_t k = 0; k < props.size(); ++k) {
                // Small integers make repeated positions; the rest any value, some tiny.
                float value = pick(2) ? static_cast<float>(pick(3)) : std::ldexp(static_cast<float>(pick(2000)) - 1000.0f, -pick(40));
                if (props[k].type == "uchar") value = static_cast<float>(pick(256));
                if (format == 0) {
                    text << (k ? " " : "") << value;
                } else if (props[k].type == "double") {
                    put(out, static_cast<double>(value), big);
                } else if (props[k].type == "uchar") {
                    put(out, static_cast<std::uint8_t>(value), big);
                } else {
                    put(out, value, big);
                }
            }
            if (format == 0) text << "\n";
        }
        for (int f = 0; f < faces; ++f) {
            const int corners = pick(12) == 0 ? 4 : 3;
            if (format == 0) text << corners;
            else put_integer(out, count_type, corners, big);
            for (int k = 0; k < corners; ++k) {
                const int index = pick(40) == 0 ? vertices : pick(vertices);  // now and then out of range
                if (format == 0) text << ' ' << index;
                else put_integer(out, index_type, index, big);
            }
            if (format == 0) text << "\n";
        }
        if (format == 0) out += text.str();
        const std::string path = write_file(temp_dir() / ("generated_" + std::to_string(i) + ".ply"), out);
        taken += io_detail::read_plain_ply(out).has_value();
        expect_same_as_assimp(path);
    }
    EXPECT_GT(taken, files / 5) << "the fast reader took too few of the generated files to test it";
}

// Cut and damaged copies of valid files: whatever each path makes of them (a scene, or an error
// naming the file), both make the same, and nothing crashes.
TEST(PlainPly, DamagedFilesMatchAssimp) {
    const std::vector<Vec3> c = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
    const std::vector<std::uint32_t> cube = {0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1};
    const std::string good[2] = {ply(c, cube), ply(c, cube, {.encoding = Encoding::little_endian})};
    const std::string alphabet = "0123456789 .-e\n\r";
    std::mt19937 rng(13);
    for (int i = 0; i < facet_test::sweep_size(400, 80); ++i) {
        const std::string& from = good[i % 2];
        std::string bad = from;
        const std::size_t body = from.find("end_header\n") + 11;
        if (i % 3 == 0) {
            bad.resize(body + rng() % (from.size() - body));  // cut in the data: a cut header is check_ply's business
        } else {
            for (int k = 0; k < 1 + i % 4; ++k) {
                const std::size_t at = body + rng() % (bad.size() - body);
                bad[at] = i % 2 ? static_cast<char>(rng()) : alphabet[rng() % alphabet.size()];
            }
        }
        expect_same_as_assimp(write_file(temp_dir() / ("damaged_" + std::to_string(i) + ".ply"), bad));
    }
    // Damaged headers: characters replaced, words swapped for other PLY words, lines doubled or
    // dropped. Cut headers are left out: check_ply refuses those before either reader sees them.
    const std::vector<std::string> words = {"ply", "format", "ascii", "binary_little_endian", "binary_big_endian", "1.0",
                                            "comment", "obj_info", "element", "vertex", "face", "property", "list",
                                            "float", "double", "uchar", "int", "x", "y", "z", "nx", "red", "confidence",
                                            "vertex_indices", "vertex_index", "end_header", "0", "3", "8", "12", " ", "\t"};
    for (int i = 0; i < facet_test::sweep_size(400, 80); ++i) {
        const std::string& from = good[i % 2];
        const std::size_t header_end = from.find("end_header\n");
        std::string header = from.substr(0, header_end), rest = from.substr(header_end);
        switch (i % 4) {
            case 0: header[rng() % header.size()] = alphabet[rng() % alphabet.size()]; break;
            case 1: {  // a word replaced by another
                const std::size_t at = rng() % header.size();
                const std::size_t before = header.find_last_of(" \n", at);
                const std::size_t start = before == std::string::npos ? 0 : before + 1;
                const std::size_t end = std::min(header.find_first_of(" \n", start), header.size());
                header.replace(start, end - start, words[rng() % words.size()]);
                break;
            }
            case 2: {  // a line doubled
                const std::size_t line = header.find('\n', rng() % header.size());
                if (line == std::string::npos) break;
                const std::size_t start = header.rfind('\n', line - 1) == std::string::npos ? 0 : header.rfind('\n', line - 1) + 1;
                header.insert(start, header.substr(start, line - start + 1));
                break;
            }
            default: {  // a line dropped (not the magic)
                const std::size_t start = header.find('\n', rng() % header.size());
                if (start == std::string::npos) break;
                const std::size_t end = header.find('\n', start + 1);
                header.erase(start, (end == std::string::npos ? header.size() : end) - start);
                break;
            }
        }
        expect_same_as_assimp(write_file(temp_dir() / ("header_" + std::to_string(i) + ".ply"), header + rest));
    }
}

}  // namespace
