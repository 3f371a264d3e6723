// `facet thumbnail [-s SIZE] INPUT OUTPUT` as a file manager calls it: paths and file:// URIs,
// other schemes refused with exit 2, a SIZE x SIZE RGBA PNG on a transparent background, the same
// pixels as `facet thumbs` with the same settings, and on any failure exit 1 and no file at all.
// (tests/install/check-thumbnailer runs the installed entry inside bubblewrap.)
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "support/cli.hpp"
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;
using facet_test::CliRun;
using facet_test::decode_png;
using facet_test::DecodedPng;
using facet_test::k_box_obj;
using facet_test::run_facet;
using facet_test::write_text;

fs::path temp_dir() { return facet_test::test_temp_dir("facet_cli_thumbnail"); }

std::set<std::string> files_in(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
    return names;
}

// Percent-encodes every byte but unreserved ones and '/', as file managers write %u.
std::string file_uri(const fs::path& path) {
    std::string uri = "file://";
    for (unsigned char c : path.string()) {
        if (std::isalnum(c) || c == '/' || c == '-' || c == '.' || c == '_' || c == '~') {
            uri += static_cast<char>(c);
        } else {
            char hex[4];
            std::snprintf(hex, sizeof hex, "%%%02X", c);
            uri += hex;
        }
    }
    return uri;
}

TEST(CliThumbnail, TransparentSquarePngOfTheModel) {
    const fs::path dir = temp_dir();
    const std::string model = write_text(dir / "box.obj", k_box_obj);
    const fs::path out = dir / "box.png";
    const CliRun r = run_facet({"thumbnail", "-s", "96", model, out.string()});
    ASSERT_EQ(r.exit_code, 0) << r.all();
    EXPECT_TRUE(r.out.empty()) << r.out;
    const DecodedPng img = decode_png(out);
    ASSERT_TRUE(img.ok()) << img.error;
    EXPECT_EQ(img.width, 96u);
    EXPECT_EQ(img.height, 96u);
    EXPECT_EQ(img.colour_type, 6);  // RGBA
    EXPECT_EQ(img.at(0, 0).a, 0);   // the background
    EXPECT_EQ(img.at(48, 48).a, 255);  // the box, framed in the middle
    // Anti-aliased by default: the box's outline has partly covered pixels.
    EXPECT_TRUE(std::any_of(img.rgba.begin(), img.rgba.end(), [](facet::Rgba8 p) { return p.a > 0 && p.a < 255; }));
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"box.obj", "box.png"}));
}

TEST(CliThumbnail, DefaultSizeIs256) {
    const fs::path dir = temp_dir();
    const std::string model = write_text(dir / "box.obj", k_box_obj);
    const CliRun r = run_facet({"thumbnail", model, (dir / "t.png").string()});
    ASSERT_EQ(r.exit_code, 0) << r.all();
    const DecodedPng img = decode_png(dir / "t.png");
    EXPECT_EQ(img.width, 256u);
    EXPECT_EQ(img.height, 256u);
}

// One rendering path: with the same settings, `facet thumbs` draws the same pixels.
TEST(CliThumbnail, SamePixelsAsThumbs) {
    const fs::path dir = temp_dir();
    const std::string model = write_text(dir / "in" / "box.obj", k_box_obj);
    ASSERT_EQ(run_facet({"thumbnail", "-s", "64", model, (dir / "one.png").string()}).exit_code, 0);
    const CliRun t = run_facet({"thumbs", model, "-o", (dir / "many").string(), "--size", "64",
                                "--background", "transparent"});
    ASSERT_EQ(t.exit_code, 0) << t.all();
    const DecodedPng one = decode_png(dir / "one.png"), many = decode_png(dir / "many" / "box.obj.png");
    ASSERT_TRUE(one.ok() && many.ok());
    EXPECT_TRUE(one.rgba == many.rgba);
}

TEST(CliThumbnail, FileUrisArePercentDecoded) {
    const fs::path dir = temp_dir();
    const std::string model = write_text(dir / "a box #1 %41 ü.obj", k_box_obj);
    ASSERT_EQ(run_facet({"thumbnail", "-s", "32", model, (dir / "path.png").string()}).exit_code, 0);
    const DecodedPng expected = decode_png(dir / "path.png");
    const std::string uri = file_uri(model);
    std::string localhost = uri;
    localhost.insert(7, "localhost");
    std::string file_colon = uri;
    file_colon.replace(0, 7, "FILE:");  // file:/path, the scheme in capitals
    for (const std::string& input : {uri, localhost, file_colon}) {
        SCOPED_TRACE(input);
        const fs::path out = dir / "uri.png";
        const CliRun r = run_facet({"thumbnail", "-s", "32", input, out.string()});
        ASSERT_EQ(r.exit_code, 0) << r.all();
        EXPECT_TRUE(decode_png(out).rgba == expected.rgba);
        fs::remove(out);
    }
}

TEST(CliThumbnail, OtherSchemesAndBadUrisAreUsageErrors) {
    const fs::path dir = temp_dir();
    write_text(dir / "box.obj", k_box_obj);
    const std::string box = (dir / "box.obj").string();
    for (const std::string& input : std::vector<std::string>{"http://example.org/box.obj", "smb://server/share/box.obj", "sftp:///box.obj",
                                     "file://elsewhere" + box, "file:///no%2Fslash.obj", "file:///nul%00.obj",
                                     "file:///bad%4.obj", "file:///bad%zz.obj", "file://" + box + "?x=1",
                                     "file://" + box + "#part", "file:box.obj"}) {
        SCOPED_TRACE(input);
        const CliRun r = run_facet({"thumbnail", input, (dir / "out.png").string()});
        EXPECT_EQ(r.exit_code, 2) << r.all();
        EXPECT_NE(r.err.find(input), std::string::npos) << r.err;
    }
    // A colon without "//" is part of a file name.
    const std::string colon = write_text(dir / "part:2.obj", k_box_obj);
    fs::current_path(dir);
    EXPECT_EQ(run_facet({"thumbnail", "-s", "16", "part:2.obj", (dir / "out.png").string()}).exit_code, 0);
    EXPECT_TRUE(fs::exists(dir / "out.png"));
    fs::remove(dir / "out.png");
    for (const char* size : {"0", "-5", "x", "9000"}) {
        const CliRun r = run_facet({"thumbnail", "-s", size, box, (dir / "out.png").string()});
        EXPECT_EQ(r.exit_code, 2) << size << ": " << r.all();
    }
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"box.obj", "part:2.obj"}));
}

TEST(CliThumbnail, FailuresLeaveNoFile) {
    const fs::path dir = temp_dir();
    std::string garbage(3000, '\0');
    for (std::size_t i = 0; i < garbage.size(); ++i) garbage[i] = static_cast<char>((i * 7919 + 3) % 251);
    const std::string broken = write_text(dir / "broken.glb", garbage);
    const std::string empty = write_text(dir / "empty.stl", "");
    const std::string degenerate = write_text(dir / "flat.obj", "v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n");
    const std::string box = write_text(dir / "box.obj", k_box_obj);
    const std::set<std::string> inputs{"broken.glb", "empty.stl", "flat.obj", "box.obj"};
    for (const std::string& input : {broken, empty, degenerate, (dir / "missing.obj").string()}) {
        SCOPED_TRACE(input);
        const CliRun r = run_facet({"thumbnail", input, (dir / "out.png").string()});
        EXPECT_EQ(r.exit_code, 1) << r.all();
        EXPECT_NE(r.err.find(input), std::string::npos) << r.err;
        EXPECT_EQ(files_in(dir), inputs);
    }
    // An output folder that does not exist; one a killed worker leaves nothing in (--timeout).
    EXPECT_EQ(run_facet({"thumbnail", box, (dir / "no" / "out.png").string()}).exit_code, 1);
    facet_test::ScopedEnv sleep("FACET_TEST_SLEEP_ON", "box.obj");
    const CliRun r = run_facet({"thumbnail", "--timeout", "0.5", box, (dir / "out.png").string()});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_NE(r.err.find("gave up after"), std::string::npos) << r.err;
    EXPECT_EQ(files_in(dir), inputs);
}

TEST(CliThumbnail, PrintConfigNamesTheThumbnailerDefaults) {
    const fs::path dir = temp_dir();
    const CliRun r = run_facet({"thumbnail", "--print-config", "-s", "128", "file:///models/a%20b.stl", "out.png"});
    ASSERT_EQ(r.exit_code, 0) << r.all();
    for (const char* line : {"model = /models/a b.stl\n", "output = out.png\n", "size = 128x128\n", "aa = 2\n",
                             "background = 0,0,0,0\n"})
        EXPECT_NE(r.out.find(line), std::string::npos) << line << "\n" << r.out;
}

}  // namespace
