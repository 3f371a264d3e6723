// `facet thumbs` as a script sees it: which files appear in the output directory under which
// names, at which size, showing which model; what stderr says (progress, summary, failures); the
// exit code. The facet binary is run with tests/support/cli.hpp, images decoded with libspng.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli.hpp"
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;
using facet_test::k_box_obj;
using facet_test::CliRun;
using facet_test::decode_png;
using facet_test::DecodedPng;
using facet_test::run_facet;
using facet_test::write_text;

fs::path temp_dir() { return facet_test::test_temp_dir("facet_cli_thumbs"); }

const char* k_triangle_obj = "v -1 -1 0\nv 1 -1 0\nv 0 2 0\nf 1 2 3\n";
const char* k_tetra_stl =
    "solid t\n"
    "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
    "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\n"
    "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 1 0 0\nendloop\nendfacet\n"
    "facet normal 0 0 0\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\n"
    "endsolid t\n";

std::string garbage() {
    std::string g(2000, '\0');
    for (std::size_t i = 0; i < g.size(); ++i) g[i] = static_cast<char>((i * 104729 + 7) % 253);
    return g;
}

// Every file under `dir`, as paths relative to it.
std::set<std::string> files_in(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(dir)) names.insert(fs::relative(e.path(), dir).string());
    return names;
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

bool has_foreground(const DecodedPng& img) {
    return std::any_of(img.rgba.begin(), img.rgba.end(), [&](facet::Rgba8 p) { return p != img.at(0, 0); });
}

// A folder with two good models and one broken file at the top, a second a.obj (a different
// model) in a subfolder, and a file that is not a model.
struct Batch {
    fs::path in, out;
};
Batch make_batch() {
    const fs::path dir = temp_dir();
    Batch b{dir / "models", dir / "thumbs"};
    write_text(b.in / "a.obj", k_box_obj);
    write_text(b.in / "b.stl", k_tetra_stl);
    write_text(b.in / "broken.obj", garbage());
    write_text(b.in / "sub" / "a.obj", k_triangle_obj);
    write_text(b.in / "notes.txt", "not a model\n");
    return b;
}

TEST(CliThumbs, OneThumbnailPerGoodModelAndASummaryOfFailures) {
    const Batch b = make_batch();
    const std::string missing = (b.in.parent_path() / "no-such-model.obj").string();
    const CliRun r = run_facet({"thumbs", b.in.string(), missing, "-o", b.out.string(), "--size", "48"});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_TRUE(r.out.empty()) << r.out;
    // The documented names; nothing for the broken, missing or non-model files; no temporary files.
    EXPECT_EQ(files_in(b.out), (std::set<std::string>{"a.obj.png", "b.stl.png", "sub__a.obj.png"}));
    for (const char* name : {"a.obj.png", "b.stl.png", "sub__a.obj.png"}) {
        SCOPED_TRACE(name);
        const DecodedPng img = decode_png(b.out / name);
        ASSERT_TRUE(img.ok()) << img.error;
        EXPECT_EQ(img.width, 48u);
        EXPECT_EQ(img.height, 48u);
        EXPECT_TRUE(has_foreground(img));
    }

    // Each thumbnail shows its own model: the same pixels as `facet render` of that file with the
    // thumbnail defaults (azimuth 35, elevation 25, two jittered frames, a contact shadow).
    for (const auto& [model, thumb] : {std::pair{"a.obj", "a.obj.png"}, std::pair{"sub/a.obj", "sub__a.obj.png"}}) {
        SCOPED_TRACE(model);
        const fs::path single = b.in.parent_path() / "single.png";
        const CliRun s = run_facet({"render", (b.in / model).string(), "--size", "48x48", "--azimuth", "35",
                                    "--elevation", "25", "--aa", "2", "--contact-shadow", "0.6", "-o", single.string()});
        ASSERT_EQ(s.exit_code, 0) << s.all();
        EXPECT_TRUE(decode_png(single).rgba == decode_png(b.out / thumb).rgba);
    }
    EXPECT_FALSE(decode_png(b.out / "a.obj.png").rgba == decode_png(b.out / "sub__a.obj.png").rgba);

    // stderr is not a terminal: one plain progress line per model file found, no progress bar.
    const std::vector<std::string> lines = lines_of(r.err);
    EXPECT_EQ(r.err.find('\r'), std::string::npos);
    const std::regex progress(R"(.*\[([0-9]+)/4\].*)");
    std::set<std::string> counters;
    std::size_t last_progress = 0;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        std::smatch m;
        if (std::regex_match(lines[i], m, progress)) counters.insert(m[1].str()), last_progress = i;
    }
    EXPECT_EQ(counters, (std::set<std::string>{"1", "2", "3", "4"})) << r.err;
    EXPECT_EQ(std::count_if(lines.begin(), lines.end(), [&](const std::string& l) { return std::regex_match(l, progress); }), 4)
        << r.err;
    for (const char* model : {"a.obj", "b.stl", "broken.obj", "sub/a.obj"}) {
        const std::string path = (b.in / model).string();
        EXPECT_EQ(std::count_if(lines.begin(), lines.end(),
                                [&](const std::string& l) { return std::regex_match(l, progress) && l.find(path) != std::string::npos; }),
                  1)
            << path << "\n" << r.err;
    }
    // Then the summary: the counts, and each failure with its file name and a reason.
    std::string summary;
    for (std::size_t i = last_progress + 1; i < lines.size(); ++i) summary += lines[i] + "\n";
    EXPECT_NE(summary.find("3 rendered"), std::string::npos) << summary;
    EXPECT_NE(summary.find("2 failed"), std::string::npos) << summary;
    const std::vector<std::string> summary_lines = lines_of(summary);
    for (const std::string& failed : {(b.in / "broken.obj").string(), missing}) {
        const auto line = std::find_if(summary_lines.begin(), summary_lines.end(),
                                       [&](const std::string& l) { return l.find(failed) != std::string::npos; });
        ASSERT_NE(line, summary_lines.end()) << failed << " not in the summary:\n" << summary;
        EXPECT_GT(line->size(), line->find(failed) + failed.size() + 3) << "no reason given: " << *line;
    }
    for (const char* good : {"b.stl", "notes.txt"}) EXPECT_EQ(summary.find(good), std::string::npos) << summary;
}

TEST(CliThumbs, AllGoodExitsZeroAtTheRequestedSize) {
    const Batch b = make_batch();
    fs::remove(b.in / "broken.obj");
    const CliRun square = run_facet({"thumbs", b.in.string(), "-o", b.out.string(), "--size", "40"});
    EXPECT_EQ(square.exit_code, 0) << square.all();
    EXPECT_EQ(files_in(b.out), (std::set<std::string>{"a.obj.png", "b.stl.png", "sub__a.obj.png"}));
    EXPECT_EQ(decode_png(b.out / "b.stl.png").width, 40u);
    EXPECT_EQ(decode_png(b.out / "b.stl.png").height, 40u);

    // Files as inputs (named after the file), WxH, and an output directory that does not exist yet.
    const fs::path out2 = b.out.parent_path() / "new" / "dir";
    const CliRun rect = run_facet({"thumbs", (b.in / "b.stl").string(), (b.in / "sub" / "a.obj").string(), "-o",
                                   out2.string(), "--size", "36x20", "--threads", "2"});
    EXPECT_EQ(rect.exit_code, 0) << rect.all();
    EXPECT_EQ(files_in(out2), (std::set<std::string>{"b.stl.png", "a.obj.png"}));
    for (const char* name : {"b.stl.png", "a.obj.png"}) {
        const DecodedPng img = decode_png(out2 / name);
        ASSERT_TRUE(img.ok()) << img.error;
        EXPECT_EQ(img.width, 36u);
        EXPECT_EQ(img.height, 20u);
        EXPECT_TRUE(has_foreground(img));
    }
    // Default size 256.
    const fs::path out3 = b.out.parent_path() / "default";
    ASSERT_EQ(run_facet({"thumbs", (b.in / "b.stl").string(), "-o", out3.string()}).exit_code, 0);
    EXPECT_EQ(decode_png(out3 / "b.stl.png").width, 256u);
    EXPECT_EQ(decode_png(out3 / "b.stl.png").height, 256u);
}

TEST(CliThumbs, ProgressBarOnATerminal) {
    const Batch b = make_batch();
    fs::remove(b.in / "broken.obj");
    const CliRun r = run_facet({"thumbs", b.in.string(), "-o", b.out.string(), "--size", "24"}, /*stderr_tty=*/true);
    EXPECT_EQ(r.exit_code, 0) << r.all();
    EXPECT_NE(r.err.find('\r'), std::string::npos) << r.err;  // redrawn in place
    EXPECT_NE(r.err.find("3/3"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("[1/3]"), std::string::npos) << r.err;  // not the plain lines
    EXPECT_EQ(files_in(b.out).size(), 3u);
}

TEST(CliThumbs, MissingInputsAndBadOptions) {
    const Batch b = make_batch();
    const std::string missing = (b.in / "nothing-here.stl").string();
    const CliRun r = run_facet({"thumbs", missing, "-o", b.out.string(), "--size", "32"});
    EXPECT_EQ(r.exit_code, 1) << r.all();
    EXPECT_NE(r.err.find(missing), std::string::npos) << r.err;
    EXPECT_TRUE(!fs::exists(b.out) || fs::is_empty(b.out));

    // One broken file alone: exit 1, nothing written.
    const CliRun broken = run_facet({"thumbs", (b.in / "broken.obj").string(), "-o", b.out.string(), "--size", "32"});
    EXPECT_EQ(broken.exit_code, 1) << broken.all();
    EXPECT_NE(broken.err.find((b.in / "broken.obj").string()), std::string::npos) << broken.err;
    EXPECT_TRUE(!fs::exists(b.out) || fs::is_empty(b.out));

    for (std::vector<std::string> bad : {std::vector<std::string>{"--size", "0"}, {"--size", "9000"}, {"--size", "32x"},
                                         {"--shading", "glossy"}, {"--depth-out", "d.png"}, {"--benchmark", "2"}}) {
        std::vector<std::string> args{"thumbs", b.in.string(), "-o", b.out.string()};
        args.insert(args.end(), bad.begin(), bad.end());
        const CliRun u = run_facet(args);
        EXPECT_EQ(u.exit_code, 2) << bad[0] << " " << bad[1] << ": " << u.all();
        EXPECT_TRUE(!fs::exists(b.out) || fs::is_empty(b.out));
    }
    EXPECT_EQ(run_facet({"thumbs", b.in.string()}).exit_code, 2);  // -o is required
    // Quoted as given (it said "--size must be WxH, got '0x0'" for --size 0).
    const CliRun zero = run_facet({"thumbs", b.in.string(), "-o", b.out.string(), "--size", "0"});
    EXPECT_NE(zero.err.find("--size must be N or WxH, each at least 1, got '0'\n"), std::string::npos) << zero.err;
}

}  // namespace
