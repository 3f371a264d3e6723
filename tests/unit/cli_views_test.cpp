// `facet render --views/--passes` as a user or a script sees it: the folder of files it writes
// (one per view and pass, cameras.json, transforms.json), the same bytes whatever the thread count
// and ISA, and its errors: bad rig specs exit 2, unwritable outputs exit 1 and leave nothing. The
// geometry of the files (reprojection, the cameras read back by an independent script) is tested
// in Python: tests/python/test_views_cli.py.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <system_error>
#include <vector>

#include "math/portable_trig.hpp"
#include "support/cli.hpp"
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;
using facet_test::CliRun;
using facet_test::decode_png;
using facet_test::run_facet;
using facet_test::write_text;

fs::path temp_dir() { return facet_test::test_temp_dir("facet_cli_views"); }

const std::string k_all = "color,alpha,depth,range,normal,instance,material,primitive,uv";

// Two boxes side by side: two objects (OBJ groups) for the instance pass.
std::string two_boxes(const fs::path& dir) {
    std::string obj;
    for (int b = 0; b < 2; ++b) {
        obj += "o box" + std::to_string(b) + "\n";
        const float x = b ? 1.5f : -1.5f;
        for (int i = 0; i < 8; ++i)
            obj += "v " + std::to_string(x + ((i & 1) ? 1 : -1)) + " " + std::to_string((i & 2) ? 1 : -1) + " " +
                   std::to_string((i & 4) ? 1 : -1) + "\n";
        const int faces[12][3] = {{1, 5, 7}, {1, 7, 3}, {2, 4, 8}, {2, 8, 6}, {1, 2, 6}, {1, 6, 5},
                                  {3, 7, 8}, {3, 8, 4}, {1, 3, 4}, {1, 4, 2}, {5, 6, 8}, {5, 8, 7}};
        for (const auto& f : faces)
            obj += "f " + std::to_string(f[0] + 8 * b) + " " + std::to_string(f[1] + 8 * b) + " " + std::to_string(f[2] + 8 * b) + "\n";
    }
    return write_text(dir / "boxes.obj", obj);
}

// Every file under `dir`, relative path -> bytes.
std::map<std::string, std::string> files_of(const fs::path& dir) {
    std::map<std::string, std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file()) out[fs::relative(e.path(), dir).string()] = facet_test::read_file(e.path());
    return out;
}

// Whatever `dir` holds besides `keep` (a failed run must leave nothing: no staging folder either).
std::vector<std::string> entries_besides(const fs::path& dir, const std::vector<std::string>& keep) {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir))
        if (std::find(keep.begin(), keep.end(), e.path().filename().string()) == keep.end()) out.push_back(e.path().filename().string());
    return out;
}

CliRun render(const std::vector<std::string>& args) {
    std::vector<std::string> all{"render"};
    all.insert(all.end(), args.begin(), args.end());
    return run_facet(all);
}

TEST(CliViews, EveryPassOfEveryViewIsAFileAndTransformsJsonNamesThem) {
    const fs::path dir = temp_dir();
    const std::string model = two_boxes(dir);
    const fs::path out = dir / "out";
    const CliRun r = render({model, "--views", "orbit:3:20", "--passes", k_all, "--size", "64x48", "-o", out.string()});
    ASSERT_EQ(r.exit_code, 0) << r.all();
    const std::map<std::string, std::string> files = files_of(out);
    // Per view: colour, alpha and the ids as PNG, the float passes as .npy; and the two cameras files.
    EXPECT_EQ(files.size(), 3u * 9u + 2u);
    for (const char* name : {"0000", "0001", "0002"}) {
        for (const char* png : {"color", "alpha", "instance", "material", "primitive"})
            EXPECT_TRUE(files.count(std::string(png) + "/" + name + ".png")) << png << " " << name;
        for (const char* npy : {"depth", "range", "normal", "uv"}) {
            const auto f = files.find(std::string(npy) + "/" + name + ".npy");
            ASSERT_NE(f, files.end()) << npy << " " << name;
            EXPECT_EQ(f->second.substr(0, 6), "\x93NUMPY");
            // Header, then 4 bytes per float: (48, 64), (48, 64, 3) or (48, 64, 2).
            const std::size_t channels = std::string(npy) == "normal" ? 3 : std::string(npy) == "uv" ? 2 : 1;
            const std::size_t header = 10 + static_cast<unsigned char>(f->second[8]) + 256u * static_cast<unsigned char>(f->second[9]);
            EXPECT_EQ(header % 64, 0u);
            EXPECT_EQ(f->second.size(), header + 48u * 64u * channels * 4u) << npy;
        }
    }
    const std::string& transforms = files.at("transforms.json");
    for (const char* key : {"\"fl_x\"", "\"fl_y\"", "\"cx\"", "\"cy\"", "\"w\": 64", "\"h\": 48", "\"camera_model\"",
                            "\"file_path\": \"color/0002.png\"", "\"mask_path\": \"alpha/0000.png\"",
                            "\"depth_file_path\": \"depth/0001.npy\"", "\"normal_file_path\"", "\"instance_file_path\"",
                            "\"transform_matrix\""})
        EXPECT_NE(transforms.find(key), std::string::npos) << key << "\n" << transforms;
    // Both objects are seen: instance ids 1 and 2 (the boxes side by side), 0 on the background.
    const facet_test::DecodedPng ids = decode_png(out / "instance" / "0000.png");
    ASSERT_TRUE(ids.ok()) << ids.error;
    EXPECT_EQ(ids.bit_depth, 16);
    std::vector<int> seen(3, 0);
    for (std::uint16_t v : ids.gray16) {
        ASSERT_LE(v, 2);
        ++seen[v];
    }
    EXPECT_GT(seen[0], 0);
    EXPECT_GT(seen[1], 0);
    EXPECT_GT(seen[2], 0);
}

TEST(CliViews, SameBytesForOneAndTwoThreadsAndEveryIsaWithSupersampling) {
    const fs::path dir = temp_dir();
    const std::string model = two_boxes(dir);
    std::map<std::string, std::string> first;
    for (const auto& [threads, isa] : {std::pair{"1", "scalar"}, {"2", "best"}, {"2", "scalar"}, {"1", "best"}}) {
        const fs::path out = dir / (std::string("t") + threads + isa);
        const CliRun r = render({model, "--views", "sphere:3", "--passes", k_all, "--ssaa", "2", "--size", "40x30",
                                 "--threads", threads, "--isa", isa, "-o", out.string()});
        ASSERT_EQ(r.exit_code, 0) << r.all();
        const auto files = files_of(out);
        if (first.empty()) first = files;
        else EXPECT_TRUE(files == first) << threads << " threads, " << isa;
    }
}

// --aa and --contact-shadow with --passes: the view's colour is the same bytes as the plain render
// from the same camera (both are drawn by ViewRenderer), the shadow is in it, and the other passes
// are the surface at the pixel centres, as without either option.
TEST(CliViews, AViewsColourIsThePlainRendersWithJitteredFramesAndTheContactShadow) {
    const fs::path dir = temp_dir();
    const std::string model = two_boxes(dir);
    const std::vector<std::string> camera{"--azimuth", "30", "--elevation", "35", "--size", "48x36", "--ssaa", "2"};
    auto run = [&](std::vector<std::string> args, const fs::path& out) {
        args.insert(args.begin(), model);
        args.insert(args.end(), camera.begin(), camera.end());
        args.insert(args.end(), {"-o", out.string()});
        const CliRun r = render(args);
        EXPECT_EQ(r.exit_code, 0) << r.all();
    };
    const std::vector<std::string> aa{"--aa", "4", "--contact-shadow", "0.8"};
    run(aa, dir / "plain.png");
    run({"--aa", "4"}, dir / "unshadowed.png");
    std::vector<std::string> views = aa;
    views.insert(views.end(), {"--passes", "color,instance,depth"});
    run(views, dir / "views");
    run({"--passes", "color,instance,depth"}, dir / "bare");
    const std::string plain = facet_test::read_file(dir / "plain.png");
    EXPECT_EQ(facet_test::read_file(dir / "views" / "color" / "0000.png"), plain);
    EXPECT_NE(facet_test::read_file(dir / "unshadowed.png"), plain);
    EXPECT_NE(facet_test::read_file(dir / "bare" / "color" / "0000.png"), plain);
    for (const char* pass : {"instance/0000.png", "depth/0000.npy"})
        EXPECT_EQ(facet_test::read_file(dir / "views" / pass), facet_test::read_file(dir / "bare" / pass)) << pass;
}

TEST(CliViews, ExrHoldsEveryPassButColourAndPngScalesDepth) {
    const fs::path dir = temp_dir();
    const std::string model = two_boxes(dir);
    const CliRun exr = render({model, "--views", "random:2:7", "--passes", "color,depth,normal,instance", "--float-format",
                               "exr", "--size", "32x32", "-o", (dir / "exr").string()});
    ASSERT_EQ(exr.exit_code, 0) << exr.all();
    const auto files = files_of(dir / "exr");
    ASSERT_TRUE(files.count("exr/0001.exr"));
    EXPECT_EQ(files.at("exr/0001.exr").substr(0, 4), std::string("\x76\x2f\x31\x01", 4));  // OpenEXR's magic number
    EXPECT_TRUE(files.count("color/0001.png"));
    EXPECT_NE(files.at("transforms.json").find("\"depth_file_path\": \"exr/0000.exr\""), std::string::npos);

    // PNG depth: 16 bits, value / depth-scale rounded, 0 on the background.
    const CliRun png = render({model, "--passes", "depth", "--float-format", "png", "--depth-scale", "0.001", "--size", "32x32",
                               "-o", (dir / "png").string()});
    ASSERT_EQ(png.exit_code, 0) << png.all();
    const facet_test::DecodedPng depth = decode_png(dir / "png" / "depth" / "0000.png");
    ASSERT_TRUE(depth.ok()) << depth.error;
    EXPECT_EQ(depth.bit_depth, 16);
    EXPECT_EQ(depth.value(0, 0), 0);  // a corner: background
    // The boxes a few units away, in thousandths of model units.
    EXPECT_GT(*std::max_element(depth.gray16.begin(), depth.gray16.end()), 1000);
    EXPECT_NE(files_of(dir / "png").at("transforms.json").find("\"depth_unit_scale_factor\": 0.001"), std::string::npos);
}

TEST(CliViews, BadRigSpecsAndOptionsAreUsageErrors) {
    const fs::path dir = temp_dir();
    const std::string model = two_boxes(dir);
    write_text(dir / "not.json", "{\"frames\": [ {\"transform_matrix\": 3} ]");
    write_text(dir / "nomatrix.json", "{\"fl_x\": 100, \"w\": 10, \"h\": 10, \"frames\": [ {\"file_path\": \"a.png\"} ]}");
    write_text(dir / "mirror.json",
               "{\"views\": [{\"width\": 8, \"height\": 8, \"fx\": 8, \"fy\": 8, \"cx\": 3.5, \"cy\": 3.5, "
               "\"R\": [[-1, 0, 0], [0, 1, 0], [0, 0, 1]], \"t\": [0, 0, 5]}]}");
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"--views", "orbit:0"}, "orbit"},
        {{"--views", "orbit:many"}, "orbit"},
        {{"--views", "orbit:4:91"}, "orbit"},
        {{"--views", "sphere:"}, "sphere"},
        {{"--views", "sphere:10001"}, "10000"},
        {{"--views", "random:5"}, "random"},
        {{"--views", "random:5:-1"}, "random"},
        {{"--views", "cube:4"}, "cube"},
        {{"--views", "file:"}, "file:"},
        {{"--views", "file:" + (dir / "missing.json").string()}, "missing.json"},
        {{"--views", "file:" + (dir / "not.json").string()}, "not.json"},
        {{"--views", "file:" + (dir / "nomatrix.json").string()}, "transform_matrix"},
        {{"--views", "file:" + (dir / "mirror.json").string()}, "reflection"},
        {{"--passes", "color,depth,color"}, "color"},
        {{"--passes", "colour"}, "colour"},
        {{"--passes", ""}, "--passes"},
        {{"--views", ""}, "--views"},
        {{"--passes", "depth", "--float-format", "tiff"}, "--float-format"},
        {{"--passes", "depth", "--depth-scale", "0.1"}, "--depth-scale"},
        {{"--passes", "depth", "--ortho"}, "--ortho"},
        {{"--float-format", "exr"}, "--float-format"},
        {{"--passes", "depth", "--depth-out", (dir / "d.png").string()}, "--depth-out"},
    };
    for (const auto& [args, word] : cases) {
        std::vector<std::string> all{model, "-o", (dir / "out").string()};
        all.insert(all.end(), args.begin(), args.end());
        const CliRun r = render(all);
        EXPECT_EQ(r.exit_code, 2) << args.back() << "\n" << r.all();
        EXPECT_NE(r.err.find(word), std::string::npos) << word << "\n" << r.err;
        EXPECT_FALSE(fs::exists(dir / "out")) << args.back();
    }
    // -o is required: the folder.
    const CliRun no_output = render({model, "--views", "orbit:2"});
    EXPECT_EQ(no_output.exit_code, 2) << no_output.all();
    EXPECT_NE(no_output.err.find("-o"), std::string::npos) << no_output.err;
    EXPECT_EQ(entries_besides(dir, {"boxes.obj", "not.json", "nomatrix.json", "mirror.json"}), std::vector<std::string>{});
}

TEST(CliViews, UnwritableOutputsFailWithNothingLeft) {
    const fs::path dir = temp_dir();
    const std::string model = two_boxes(dir);
    write_text(dir / "file", "a file, not a folder");
    // The output is a file; the output is below a file.
    for (const fs::path& out : {dir / "file", dir / "file" / "views"}) {
        const CliRun r = render({model, "--views", "orbit:2", "--passes", "color,depth", "--size", "16x16", "-o", out.string()});
        EXPECT_EQ(r.exit_code, 1) << out << "\n" << r.all();
        EXPECT_NE(r.err.find("file"), std::string::npos) << r.err;
        EXPECT_EQ(facet_test::read_file(dir / "file"), "a file, not a folder");
        EXPECT_EQ(entries_besides(dir, {"boxes.obj", "file"}), std::vector<std::string>{});
    }
    // The staging folder cannot be made, even by root: sysfs refuses new folders. The reason is the
    // system's (the clean-up's error code replaced it, and the message said "exists").
    if (fs::is_directory("/sys/kernel")) {
        const CliRun sys = render({model, "--views", "orbit:2", "--size", "16x16", "-o", "/sys/facet-views-test"});
        EXPECT_EQ(sys.exit_code, 1) << sys.all();
        EXPECT_NE(sys.err.find("/sys/facet-views-test: cannot create files beside it (/sys/facet-views-test.tmp"),
                  std::string::npos) << sys.err;
        bool named = false;
        for (int e : {EPERM, EACCES, EROFS})
            named = named || sys.err.find(": " + std::generic_category().message(e) + ")") != std::string::npos;
        EXPECT_TRUE(named) << sys.err;
    }
    // A model that cannot be loaded: exit 1 and no folder, no staging folder.
    const CliRun r = render({(dir / "missing.obj").string(), "--views", "orbit:2", "--passes", "color,depth", "-o",
                             (dir / "out").string()});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_EQ(entries_besides(dir, {"boxes.obj", "file"}), std::vector<std::string>{});
}

// The folder is replaced whole, in one swap: a new folder (another inode) holding the new files and,
// as links to the same files (the same inodes), the ones the run did not write. The summary counts
// views in the singular for one.
TEST(CliViews, ASecondRunIntoTheFolderReplacesItsFilesAndKeepsOthers) {
    const fs::path dir = temp_dir();
    const std::string model = two_boxes(dir);
    const fs::path out = dir / "out";
    write_text(out / "notes.txt", "mine");
    write_text(out / "sub" / "deeper.txt", "mine too");
    ASSERT_EQ(render({model, "--views", "orbit:2", "--size", "16x16", "-o", out.string()}).exit_code, 0);
    struct stat before_folder{}, before_notes{}, before_colour{}, after_folder{}, after_notes{}, after_colour{};
    ASSERT_EQ(::stat(out.c_str(), &before_folder), 0);
    ASSERT_EQ(::stat((out / "notes.txt").c_str(), &before_notes), 0);
    ASSERT_EQ(::stat((out / "color" / "0001.png").c_str(), &before_colour), 0);
    const CliRun second = render({model, "--views", "orbit:1", "--passes", "color,depth", "--size", "16x16", "-o", out.string()});
    ASSERT_EQ(second.exit_code, 0) << second.all();
    EXPECT_NE(second.err.find(": 1 view of color,depth ("), std::string::npos) << second.err;
    const auto files = files_of(out);
    EXPECT_EQ(files.at("notes.txt"), "mine");
    EXPECT_EQ(files.at("sub/deeper.txt"), "mine too");
    EXPECT_TRUE(files.count("color/0001.png"));  // the first run's
    EXPECT_TRUE(files.count("depth/0000.npy"));  // the second's
    EXPECT_NE(files.at("transforms.json").find("depth_file_path"), std::string::npos);
    EXPECT_EQ(entries_besides(dir, {"boxes.obj", "out"}), std::vector<std::string>{});
    ASSERT_EQ(::stat(out.c_str(), &after_folder), 0);
    ASSERT_EQ(::stat((out / "notes.txt").c_str(), &after_notes), 0);
    ASSERT_EQ(::stat((out / "color" / "0001.png").c_str(), &after_colour), 0);
    EXPECT_NE(after_folder.st_ino, before_folder.st_ino) << "swapped for a new folder";
    EXPECT_EQ(after_notes.st_ino, before_notes.st_ino) << "linked, not copied";
    EXPECT_EQ(after_colour.st_ino, before_colour.st_ino);
    EXPECT_EQ(after_folder.st_mode, before_folder.st_mode);

    // Through a symbolic link to the folder: the link stays, the files go into its folder.
    const fs::path link = dir / "link";
    fs::create_directory_symlink(out, link);
    ASSERT_EQ(render({model, "--views", "orbit:1", "--passes", "instance", "--size", "16x16", "-o", link.string()}).exit_code, 0);
    EXPECT_TRUE(fs::is_symlink(link));
    EXPECT_TRUE(fs::exists(out / "instance" / "0000.png"));
    EXPECT_EQ(facet_test::read_file(out / "notes.txt"), "mine");
    EXPECT_EQ(entries_besides(dir, {"boxes.obj", "out", "link"}), std::vector<std::string>{});
}

// A NeRF file's camera_angle_x becomes fx = w / 2 / tan(angle / 2) with facet's portable tangent,
// not the C library's, whose last bit depends on the CPU (glibc picks an FMA variant at run time:
// camera_angle_x 0.098695479404196804 at w = 800 gives fx 8099.1602945243021 with FMA and
// ...012 without); fx is written to cameras.json and makes the projection. For these angles glibc
// 2.36's tan and the portable one differ in the last bit, so std::tan would fail here.
TEST(CliViews, CameraAngleXBecomesTheSameFocalLengthOnEveryMachine) {
    const fs::path dir = temp_dir();
    const std::string model = two_boxes(dir);
    const double angles[] = {1.0471975511965976, 0.4, 0.35};
    std::string frames;
    for (double a : angles) {
        char frame[200];
        std::snprintf(frame, sizeof(frame),
                      "%s{\"camera_angle_x\": %.17g, \"transform_matrix\": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 9], [0, 0, 0, 1]]}",
                      frames.empty() ? "" : ", ", a);
        frames += frame;
    }
    const std::string cameras = write_text(dir / "transforms.json", "{\"w\": 20, \"h\": 16, \"frames\": [" + frames + "]}");
    const fs::path out = dir / "out";
    const CliRun r = render({model, "--views", "file:" + cameras, "-o", out.string()});
    ASSERT_EQ(r.exit_code, 0) << r.all();
    const std::string written = facet_test::read_file(out / "cameras.json");
    std::size_t at = 0;
    for (double a : angles) {
        at = written.find("\"fx\": ", at);
        ASSERT_NE(at, std::string::npos) << written;
        at += 6;
        const double fx = std::strtod(written.c_str() + at, nullptr), portable = 0.5 * 20 / facet::portable::tan(a / 2);
        char both[80];
        std::snprintf(both, sizeof(both), "fx %.17g, portable %.17g", fx, portable);
        EXPECT_EQ(fx, portable) << "camera_angle_x " << a << ": " << both;
    }
}

}  // namespace
