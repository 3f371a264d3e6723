// The OBJ reader (src/io/obj.hpp): load_model must give exactly the Scene the assimp path gives,
// bit for bit (materials, textures and warnings included), for every OBJ file of assimp's test
// models and for files written here: the forms it takes (it must take them), the forms it declines
// (it must decline them, and the result must still match), generated files mixing every statement
// with MTL libraries and textures, and damaged ones (the same error).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <functional>
#include <cstdint>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "facet/io.hpp"
#include "facet/model.hpp"
#include "io/assimp_join.hpp"
#include "io/import_notes.hpp"
#include "io/obj.hpp"
#include "io/resources.hpp"
#include "support/same_scene.hpp"
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;
using namespace facet;
using facet_test::expect_same_as_assimp;
using facet_test::write_file;

fs::path temp_dir() { return facet_test::test_temp_dir("facet_obj_test"); }

// Whether facet's OBJ reader takes the file (rather than leaving it to assimp).
bool taken(const std::string& path, const LoadOptions& options = {}) {
    const std::string bytes = facet_test::read_file(path);
    const io_detail::ResourceRoots roots(path, options.resource_dirs);
    io_detail::ImportNotes notes;
    return io_detail::read_obj(path, bytes, options, roots, notes).has_value();
}

void expect_taken_and_same(const std::string& path, bool expected = true) {
    EXPECT_EQ(taken(path), expected) << path;
    expect_same_as_assimp(path);
}

// A small RGBA PNG, opaque or with one transparent texel.
std::string write_png_texture(const fs::path& path, int seed, bool transparent) {
    Image image{4, 3, {}};
    for (int i = 0; i < 12; ++i)
        image.pixels.push_back({static_cast<std::uint8_t>(40 * i + seed), static_cast<std::uint8_t>(7 * seed), 200,
                                static_cast<std::uint8_t>(transparent && i == 5 ? 10 : 255)});
    EXPECT_TRUE(write_png(path.string(), image));
    return path.string();
}

TEST(Obj, AssimpTestModelsMatchAssimp) {
    FACET_REQUIRE_ASSIMP_MODELS();
    std::vector<std::string> all, declined;
    for (const auto& entry : fs::recursive_directory_iterator(facet_test::k_assimp_models))
        if (entry.is_regular_file() && model_extension(entry.path().string()) == "obj") all.push_back(entry.path().string());
    std::sort(all.begin(), all.end());
    ASSERT_GE(all.size(), 20u);
    for (const std::string& path : all) {
        expect_same_as_assimp(path);
        LoadOptions z_up_sharp;
        z_up_sharp.up_axis = UpAxis::z;
        z_up_sharp.crease_angle_degrees = 10;
        expect_same_as_assimp(path, z_up_sharp);
        if (!taken(path)) declined.push_back(fs::path(path).filename().string());
    }
    // The files meant for the reader: textured (spider), with groups, materials and normals, and the
    // test files of OBJ's odd corners that assimp reads as it reads plain ones.
    for (const char* name : {"spider.obj", "WusonOBJ.obj", "box.obj", "box_longline.obj", "box_mat_with_spaces.obj",
                             "box_without_lineending.obj", "cube_mtllib_after_g.obj", "cube_usemtl.obj", "cube_with_vertexcolors.obj",
                             "cube_with_vertexcolors_uni.obj", "empty_mat.obj", "multiple_spaces.obj", "number_formats.obj",
                             "regr01.obj", "regr_3429812.obj", "space_in_material_name.obj", "concave_polygon.obj"})
        EXPECT_EQ(std::count(declined.begin(), declined.end(), name), 0) << name << " was left to assimp";
    std::string list;
    for (const std::string& d : declined) list += " " + d;
    std::cout << "[ obj ] left to assimp:" << list << "\n";
}

TEST(Obj, AcceptedFormsMatchAssimp) {
    const fs::path dir = temp_dir();
    write_png_texture(dir / "tex.png", 1, false);
    write_png_texture(dir / "alpha.png", 2, true);
    write_file(dir / "m.mtl",
               "# materials\nnewmtl red\nKd 1 0 0\nd 0.5\nillum 2\n"
               "newmtl textured\nKa 0.1 0.1 0.1\nKd 0.8 0.8 0.8\nmap_Kd -clamp on -s 1 1 1 tex.png\n"
               "newmtl see_through\n  Kd 0.2 0.4 0.6\n  illum 4\n  map_Kd alpha.png\n"
               "newmtl missing\nmap_Kd nowhere.png\nTr 0.25\n");
    const std::string quads = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                              "vn 0 0 1\nvn 0 0 -1\nvn 0 1 0\n";
    const std::vector<std::pair<std::string, std::string>> files = {
        {"triangles.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 1 4 2\n"},
        {"crlf.obj", "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n"},
        {"quads.obj", quads + "f 1/1/1 2/2/1 3/3/1 4/4/1\nf 1/1 2/2 5/3\nf -5/-4/-3 -4/-3/-3 -1/-1/-1\n"},
        {"concave_quad.obj", "v 0 0 0\nv 2 0 0\nv 0.4 0.4 0\nv 0 2 0\nf 1 2 3 4\nf 2 3 4 1\nf 3 4 1 2\nf 4 1 2 3\n"},
        {"normals_only.obj", quads + "f 1//1 2//1 3//1\nf 1//2 3//2 4//2\nf 2//3 5//3 3//3\n"},
        {"no_vt_slash.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1/1 2/1 3/1\n"},
        {"materials.obj", "mtllib m.mtl\n" + quads + "g a\nusemtl red\nf 1 2 3\nusemtl textured\nf 1/1 2/2 3/3\n"
                              "g b\nusemtl see_through\nf 1/1 3/3 4/4\nusemtl missing\nf 2/2 3/3 5/4\nusemtl undefined\nf 1 2 5\n"
                              "o thing\nusemtl red\nf 3 4 5\no thing\nf 1 4 5\n"},
        {"groups.obj", quads + "g\nf 1 2 3\ng one\ng two\nf 1 3 4\ng one\nf 2 3 5\ns 1\nf 3 4 5\ng  spaced name  \nf 1 4 5\n"},
        {"colours.obj", "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nv 0 0 1\nf 1 2 3\nf 1 3 4\n"},
        {"homogeneous.obj", "v 0 0 0 2\nv 2 0 0 2\nv 0 2 0 0.5\nf 1 2 3\n"},
        {"odd_lines.obj", "# comment\n   v 9 9 9\nv 0 0 0\nvp 1 2\nv 1 0 0 # trailing\nv 0 1 0\nmg 1\ncstype bspline\nv 5 5 5\nend\n"
                          "vt 0.5 0.5 0.5\nvt -.5 1\nf 1 2 3\n\n\nf 3 2 1\nusemtl\nx y z\n"},
        {"forward.obj", "f 1 2 3\nf 2 3 4\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\n"},
        {"repeated.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 0\nv -0 0 0\nvt 0 0\nvt 0 0\nf 1/1 2/1 3/1\nf 4/2 2/2 3/2\nf 5 2 3\n"},
        {"numbers.obj", "v 1e2 -2.5E-1 3,5\nv +1 -0 -.25\nv 123456789012345678901234567890 1.00000000000000000001 -7.\n"
                        "v nan 0 0 1 0 0 0\nf 1 2 3\n"},
        {"mtl_after.obj", quads + "f 1 2 3\nmtllib m.mtl\nf 1 3 4\n"},
        {"no_final_newline.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3"},
        // Normals within assimp's join tolerance: joined as its hash table joins them.
        {"near_normals.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0 0.000001 1\nf 1//1 2//1 3//1\nf 1//2 3//2 2//2\n"},
        // Meshes whose faces give texture coordinates or normals from some face on (the corners'
        // arrays are the model's, in ranges per mesh), tabs, and faces of more than 8 corners.
        {"mixed_meshes.obj", quads + "g a\nf 1 2 3\nf 1/1 2/2 3/3\ng b\nf 2 3 4\ng c\nf 3 4 5\nf 1//1 2//1 3//1\nf 3 4 5\n"
                             "f\t1\t2  3 \ng d\nf 1 2 3 4 5 1 2 3 4\nusemtl x\nf 5 4 3\n"},
        // Vertices used in the order they are listed (grouped without stamps), some at one position
        // (joined), and a quad (triangulated).
        {"in_order_joined.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 0\nv 1 1 0\nv 2 2 0\nf 1 2 3\nf 4 3 5\nf 1 5 6\n"},
        {"in_order_quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 0 0\nf 1 2 3 4\nf 2 5 3\n"},
        {"pentagon.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 0.2 0\nv 0 1 0\nf 1 2 3 4 5\nf 5 4 3 2 1\nf 1 2 3 4 5 1 2 3 4 5\n"},
    };
    for (const auto& [name, bytes] : files) expect_taken_and_same(write_file(dir / name, bytes));
    // The same with the up axis, crease angle and threads of other runs.
    LoadOptions other;
    other.up_axis = UpAxis::z;
    other.crease_angle_degrees = 5;
    other.threads = 2;
    for (const auto& [name, bytes] : files) expect_same_as_assimp((dir / name).string(), other);
}

TEST(Obj, DeclinedFormsGoThroughAssimp) {
    const fs::path dir = temp_dir();
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 2 2 0\n";
    const std::vector<std::pair<std::string, std::string>> files = {
        {"leading_zero.obj", tri + "f 01 2 3\n"},   // atoi's step reads "01" as two ones
        {"plus.obj", tri + "f +1 2 3\n"},
        {"zero.obj", tri + "f 0 1 2\n"},           // assimp: "Invalid face index"
        {"continued.obj", tri + "f 1 2 \\\n3\n"},  // a continued line
        {"line.obj", tri + "f 1 2 3\nl 1 2\n"},
        {"points.obj", tri + "p 1\nf 1 2 3\n"},
        {"nul.obj", tri + std::string("f 1 2 3\n\0\n", 10)},
        {"short.obj", "f 1 2 3\n"},
        {"out_of_range.obj", tri + "f 1 2 9\n"},
        {"empty_face.obj", tri + "f\nf 1 2 3\n"},
        {"two_corners.obj", tri + "f 1 2\nf 1 2 3\n"},
        {"bad_number.obj", tri + "v 1 x 2 3\nf 1 2 3\n"},
        {"vt_one.obj", tri + "vt 0.5\nf 1 2 3\n"},
        {"too_many_slashes.obj", tri + "vn 0 0 1\nf 1/1/1/1 2/1/1 3/1/1\n"},
        // A missing MTL file whose name's tail names one in the model's folder, which assimp finds.
        {"mtl_elsewhere.obj", "mtllib sub/found.mtl\n" + tri + "usemtl m\nf 1 2 3\n"},
    };
    write_file(dir / "found.mtl", "newmtl m\nKd 1 0 0\n");
    for (const auto& [name, bytes] : files) expect_taken_and_same(write_file(dir / name, bytes), false);
}

TEST(Obj, TriangleLimitIsTheAssimpPaths) {
    const fs::path dir = temp_dir();
    std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\no a\n";
    for (int i = 0; i < 40; ++i) text += i % 2 ? "f 1 2 3\n" : "f 1 2 4 3\n";
    text += "o b\n";
    for (int i = 0; i < 40; ++i) text += "f 2 3 4\n";
    const std::string path = write_file(dir / "many.obj", text);
    for (std::size_t limit : {10u, 59u, 60u, 61u, 100u, 1000u}) {
        LoadOptions options;
        options.max_triangles = limit;
        SCOPED_TRACE(limit);
        expect_same_as_assimp(path, options);
        EXPECT_EQ(load_model(path, options).ok(), limit >= 100);
    }
}

// What the resource rules refuse is refused by the reader as by assimp's IOSystem, with the same
// warnings: an MTL file outside the model's folder (by "..", or a symbolic link pointing out), a
// texture outside it (by "..", an absolute path, a ".." through a subfolder, a link pointing out).
TEST(Obj, ResourceRulesAsTheAssimpPaths) {
    const fs::path dir = temp_dir(), model_dir = dir / "model", other = dir / "other";
    fs::create_directories(model_dir);
    fs::create_directories(other);
    write_png_texture(other / "private.png", 9, false);
    write_file(other / "outside.mtl", "newmtl m\nKd 1 0 0\n");
    write_file(model_dir / "inside.mtl", "newmtl m\nKd 0 1 0\nmap_Kd ../other/private.png\n");
    const std::string base = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n";
    write_file(model_dir / "absolute.mtl", "newmtl m\nKd 0 1 0\nmap_Kd " + (other / "private.png").string() + "\n");
    fs::create_directories(model_dir / "sub");
    write_file(model_dir / "dotted.mtl", "newmtl m\nKd 0 1 0\nmap_Kd sub/../../other/private.png\n");
    fs::create_symlink(other / "private.png", model_dir / "link.png");
    write_file(model_dir / "linked.mtl", "newmtl m\nKd 0 1 0\nmap_Kd link.png\n");
    fs::create_symlink(other / "outside.mtl", model_dir / "link.mtl");
    std::vector<std::string> models;
    for (const char* mtllib : {"../other/outside.mtl", "inside.mtl", "absolute.mtl", "dotted.mtl", "linked.mtl", "link.mtl"})
        models.push_back(write_file(model_dir / ("m" + std::to_string(models.size()) + ".obj"),
                                    std::string("mtllib ") + mtllib + "\n" + base + "usemtl m\nf 1/1 2/2 3/3\n"));
    for (const std::string& path : models) {
        // An MTL file refused is left to assimp, which looks for it under other names too.
        const bool mtl_refused = path == models[0] || path == models[5];
        EXPECT_EQ(taken(path), !mtl_refused) << path;
        expect_same_as_assimp(path);
        const Result<LoadedModel> model = load_model(path);
        ASSERT_TRUE(model.ok());
        ASSERT_FALSE(model->warnings.empty());
        EXPECT_NE(model->warnings[0].find(path), std::string::npos);
        EXPECT_EQ(model->scene.objects[0].material.base_colour_texture, nullptr);
        LoadOptions allowed;
        allowed.resource_dirs = {other.string()};
        expect_same_as_assimp(path, allowed);
        const Result<LoadedModel> through = load_model(path, allowed);
        ASSERT_TRUE(through.ok());
        for (const std::string& w : through->warnings) EXPECT_EQ(w.find("refused"), std::string::npos) << w;
    }
}

// Random files from OBJ's statements, with MTL libraries and textures: whatever each path makes of
// a file, both make the same. Many are taken by the reader (counted), the others declined.
TEST(Obj, GeneratedFilesMatchAssimp) {
    const fs::path dir = temp_dir();
    std::mt19937 rng(23);
    auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<std::uint32_t>(n)); };
    write_png_texture(dir / "t0.png", 3, false);
    write_png_texture(dir / "t1.png", 4, true);
    const char* material_names[] = {"a", "b", "c d", "DefaultMaterial", "undefined"};
    int accepted = 0;
    const int files = facet_test::sweep_size(400, 80);
    for (int i = 0; i < files; ++i) {
        // The MTL library.
        std::string mtl;
        for (int m = 0; m < 4; ++m) {
            // (An indented first line is skipped: a texture before any material crashes assimp.)
            mtl += std::string(m == 0 || pick(6) ? "newmtl " : "  newmtl ") + material_names[m] + (pick(8) ? "" : " ") + "\n";
            if (pick(2)) mtl += "Kd " + facet_test::random_number_text(rng) + (pick(5) ? " 0.5 0.25" : "") + "\n";
            if (pick(3) == 0) mtl += std::string(pick(2) ? "d " : "Tr ") + std::to_string(pick(5) / 4.0) + "\n";
            if (pick(3) == 0) mtl += "illum " + std::to_string(pick(6)) + "\n";
            if (pick(2)) {
                const char* options[] = {"", "-clamp on ", "-clamp off ", "-s 2 2 1 ", "-bm 0.5 ", "-type sphere "};
                const char* textures[] = {"t0.png", "t1.png", "T0.PNG", "missing.png", "sub\\t0.png", "t0.png  "};
                mtl += std::string(pick(4) ? "map_Kd " : "map_kd ") + options[pick(6)] + textures[pick(6)] + "\n";
            }
            if (pick(6) == 0) mtl += "map_Bump bump.png\nrandom line\nNs 10\nKs 1 1 1\n";
        }
        if (pick(10) == 0) mtl += "map_Kd t0.png\n";  // a texture for the material before
        write_file(dir / ("lib" + std::to_string(i) + ".mtl"), mtl);

        std::ostringstream o;
        const int positions = 3 + pick(8);
        int texcoords = 0, normals = 0;
        if (pick(4)) o << "mtllib " << (pick(10) ? "lib" + std::to_string(i) + ".mtl" : std::string("absent.mtl")) << "\n";
        auto number = [&]() { return pick(3) ? std::to_string(pick(3)) : facet_test::random_number_text(rng); };
        const bool colours = pick(6) == 0;
        for (int v = 0; v < positions; ++v) {
            o << "v " << number() << ' ' << number() << ' ' << number();
            if (colours && pick(4)) o << ' ' << pick(2) << ' ' << pick(3) * 0.5 << " 1";
            o << (pick(10) ? "\n" : "\r\n");
            if (pick(3) == 0) o << "vt " << pick(3) * 0.5 << ' ' << pick(3) * 0.5 << (pick(5) ? "" : " 0") << "\n", ++texcoords;
            if (pick(3) == 0) o << "vn " << pick(3) - 1 << ' ' << pick(2) << ' ' << (pick(2) ? "1" : "0.5") << "\n", ++normals;
        }
        const int faces = 1 + pick(12);
        for (int f = 0; f < faces; ++f) {
            switch (pick(12)) {
                case 0: o << "g " << (pick(2) ? "one" : "two") << "\n"; break;
                case 1: o << "o " << (pick(2) ? "x" : "y") << "\n"; break;
                case 2: o << "usemtl " << material_names[pick(5)] << "\n"; break;
                case 3: o << "s " << pick(2) << "\n"; break;
                case 4: o << "# a comment\n"; break;
                default: break;
            }
            const int corners = pick(6) == 0 ? 4 : 3;
            const int form = pick(4);  // v, v/vt, v//vn, v/vt/vn
            o << "f";
            for (int k = 0; k < corners; ++k) {
                auto index = [&](int count) {
                    const int at = pick(count > 0 ? count : 1);
                    return pick(5) == 0 ? std::to_string(at - count) : std::to_string(at + 1);  // relative now and then
                };
                o << ' ' << index(positions);
                if (form == 1 && texcoords) o << '/' << index(texcoords);
                if (form == 2 && normals) o << "//" << index(normals);
                if (form == 3 && texcoords && normals) o << '/' << index(texcoords) << '/' << index(normals);
            }
            o << "\n";
        }
        const std::string path = write_file(dir / ("generated_" + std::to_string(i) + ".obj"), o.str());
        accepted += taken(path);
        expect_same_as_assimp(path);
    }
    EXPECT_GT(accepted, files / 2) << "the reader took too few of the generated files to test it";
}

// Runs of "v x y z" and "f a b c" lines, which the reader reads in loops of their own (from bit
// masks of a line's first 48 bytes where it fits them, else number by number): numbers of 1 to 8
// digits each side of the point (8 is not the plain form), signs, one or two blanks (spaces, tabs)
// between and after them, both line ends, lines across the masks' 48 bytes and near the file's
// end, indices of 1 to 4 digits, corners "a/b/c". The same scene as assimp's, and taken.
TEST(Obj, PlainRunsOfEveryLayoutMatchAssimp) {
    const fs::path dir = temp_dir();
    std::mt19937 rng(31);
    auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<std::uint32_t>(n)); };
    auto digits = [&](int n) {
        std::string d;
        for (int i = 0; i < n; ++i) d += static_cast<char>('0' + pick(10));
        return d;
    };
    auto blanks = [&]() { return std::string(pick(4) ? " " : "\t") + (pick(6) ? "" : " "); };
    for (int file = 0; file < 3; ++file) {
        std::string text;
        const int vertices = 1000;
        for (int v = 0; v < vertices; ++v) {
            text += "v";
            for (int k = 0; k < 3; ++k) {
                const int whole = pick(4) ? 1 + pick(2) : 1 + pick(8), fraction = pick(3) ? 6 : 1 + pick(8);
                text += blanks() + (pick(2) ? "-" : "") + digits(whole) + "." + digits(fraction);
            }
            text += std::string(pick(8) ? "" : blanks()) + (pick(5) ? "\n" : "\r\n");
        }
        // The third file's faces give texture coordinates and normals ("a/b/c", their own loop).
        const bool attributed = file == 2;
        for (int t = 0; attributed && t < 300; ++t)
            text += "vt 0." + digits(6) + " 0." + digits(6) + "\nvn " + digits(1) + ".5 -0." + digits(3) + " 1.0\n";
        auto index = [&](int count) { return std::to_string(1 + pick(pick(3) ? count : 9)); };
        for (int f = 0; f < 1500; ++f) {
            text += "f";
            for (int k = 0; k < 3; ++k) {
                text += blanks() + index(vertices);
                if (attributed) text += "/" + index(300) + "/" + index(300);
            }
            text += std::string(pick(8) ? "" : blanks()) + (pick(5) ? "\n" : "\r\n");
        }
        const std::string path = write_file(dir / ("runs_" + std::to_string(file) + ".obj"), text);
        expect_taken_and_same(path);
    }
}

// Cut and damaged copies of a valid file: whatever each path makes of them (a scene, or an error
// naming the file), both make the same, and nothing crashes.
TEST(Obj, DamagedFilesMatchAssimp) {
    const fs::path dir = temp_dir();
    const std::string good = "o box\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 1\nvn 0 0 1\n"
                             "usemtl m\nf 1/1/1 2/2/1 3/1/1 4/2/1\nf 1/1/1 2/2/1 5/1/1\nf -1 -2 -3\n";
    const std::string alphabet = "0123456789 ./-e\n\rfvgo";
    std::mt19937 rng(29);
    for (int i = 0; i < facet_test::sweep_size(300, 60); ++i) {
        std::string bad = good;
        if (i % 3 == 0) {
            bad.resize(16 + rng() % (good.size() - 16));
        } else {
            for (int k = 0; k < 1 + i % 4; ++k) bad[rng() % bad.size()] = alphabet[rng() % alphabet.size()];
        }
        expect_same_as_assimp(write_file(dir / ("damaged_" + std::to_string(i) + ".obj"), bad));
    }
}

}  // namespace

namespace {

// The join check reproduces libstdc++'s hash of a float, which assimp's hash table uses.
TEST(AssimpJoin, FloatHashIsLibstdcxxs) {
    std::mt19937 rng(5);
    for (int i = 0; i < 100000; ++i) {
        const float v = std::bit_cast<float>(static_cast<std::uint32_t>(rng()));
        EXPECT_EQ(io_detail::std_float_hash(v), std::hash<float>{}(v)) << v;
    }
    for (float v : {0.0f, -0.0f, 1.0f, -1.0f, 1e-30f}) EXPECT_EQ(io_detail::std_float_hash(v), std::hash<float>{}(v));
}

// The check uses the bucket count assimp's std::unordered_map has after reserve(n), computed
// without allocating the buckets.
TEST(AssimpJoin, ReservedBucketsAreUnorderedMaps) {
    std::vector<std::size_t> counts;
    for (std::size_t n = 0; n < 300; ++n) counts.push_back(n);
    for (std::size_t n : {1000u, 4093u, 65536u, 100003u, 3010560u}) counts.push_back(n);
    for (std::size_t n : counts) {
        std::unordered_map<int, int> map;
        map.reserve(n);
        EXPECT_EQ(io_detail::reserved_buckets(n), map.bucket_count()) << n;
    }
}

// The join's remainder by multiplications is the division's, for the bucket counts of meshes of
// every size up to 2^32 vertices and hashes of every size.
TEST(AssimpJoin, RemainderIsTheDivisions) {
    std::mt19937_64 rng(31);
    std::vector<std::uint64_t> divisors = {2, 3, 5, 7, 0xFFFFFFFFull, 0xFFFFFFFBull};
    for (std::size_t n = 1; n < (std::size_t{1} << 32); n = n * 3 / 2 + 1) divisors.push_back(io_detail::reserved_buckets(n));
    for (int i = 0; i < 100; ++i) divisors.push_back(2 + rng() % 0xFFFFFFFEull);
    for (const std::uint64_t d : divisors) {
        const io_detail::Remainder remainder(d);
        std::vector<std::uint64_t> hashes = {0, 1, d - 1, d, d + 1, 2 * d - 1, ~0ull, ~0ull - 1, ~0ull / d * d, ~0ull / d * d - 1};
        for (int i = 0; i < 2000; ++i) hashes.push_back(rng() >> (rng() % 64));
        for (const std::uint64_t h : hashes) ASSERT_EQ(remainder.of(h), h % d) << h << " % " << d;
    }
}

}  // namespace

namespace {

// The readers' join (exact equality keyed by assimp's bucket, checked in the same pass) against
// assimp's own container on small meshes with few buckets: exact duplicates, -0 and +0, and
// vertices a unit in the last place apart (which assimp's tolerance joins) in positions and
// normals. Where join_as_assimp gives a join it is assimp's; where it declines, assimp's join is
// not the exact one.
TEST(AssimpJoin, JoinAsAssimpIsAssimpsWhereItJoins) {
    std::mt19937 rng(21);
    const float pool[] = {0.0f, -0.0f, 1.0f, std::nextafter(1.0f, 2.0f), 0.5f, -0.25f, 3.0f, std::nextafter(3.0f, 0.0f)};
    auto pick = [&] { return pool[rng() % std::size(pool)]; };
    int joined = 0, declined = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const std::size_t n = 1 + rng() % 40;
        std::vector<io_detail::JoinVertex> v(n);
        const bool with_normals = trial % 2 == 1;
        for (io_detail::JoinVertex& x : v) {
            x.position = {pick(), pick(), trial % 3 == 0 ? pick() : 0.0f};
            if (with_normals) x.normal = {trial % 5 == 0 ? pick() : 0.0f, pick() > 0.0f ? 1.0f : 0.0f, 0.0f};
        }
        const auto value = [&](std::size_t i) { return v[i]; };
        std::vector<aiVector3D> positions;
        const std::optional<io_detail::Join> ours = io_detail::join_as_assimp(n, value, n, positions);
        const io_detail::Join theirs = io_detail::assimp_join(n, value, [](std::size_t) { return true; });
        if (!ours) {
            ++declined;
            continue;
        }
        ++joined;
        EXPECT_EQ(ours->unique, theirs.unique) << trial;
        EXPECT_EQ(ours->first, theirs.first) << trial;
        ASSERT_EQ(positions.size(), ours->first.size());
        for (std::size_t u = 0; u < positions.size(); ++u) EXPECT_EQ(positions[u], v[ours->first[u]].position) << trial;
        // An exact join differs from assimp's only where two of its vertices compare equal.
        for (std::size_t a = 0; a < ours->first.size(); ++a)
            for (std::size_t b = a + 1; b < ours->first.size(); ++b)
                if (io_detail::assimp_equal(v[ours->first[a]], v[ours->first[b]], 1e-10f) &&
                    io_detail::assimp_position_hash(v[ours->first[a]].position) % io_detail::reserved_buckets(n) ==
                        io_detail::assimp_position_hash(v[ours->first[b]].position) % io_detail::reserved_buckets(n))
                    ADD_FAILURE() << "trial " << trial << ": " << a << " and " << b;
    }
    EXPECT_GT(joined, 1000);  // both ways taken often
    EXPECT_GT(declined, 100);
}

}  // namespace
