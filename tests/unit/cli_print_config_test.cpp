// `--print-config` as a user sees it: `facet render`, `facet thumbs` and `facet view` print the
// settings a run resolves to and render nothing. The printed values are checked against what a run
// does (the thread count its summary reports, the image an explicit camera with the printed values
// gives, the thumbnail `facet render` gives with the printed size and orbit), against the README's
// rules evaluated here (the framing rule, the batch size, the memory cap), and against the README's
// documentation of the defaults and of every key.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "facet/isa.hpp"
#include "support/cli.hpp"
#include "support/paths.hpp"
#include "worker.hpp"  // apps/cli: whether this build caps the worker's memory
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;
using facet_test::CliRun;
using facet_test::run_facet;

fs::path temp_dir() { return facet_test::test_temp_dir("facet_print_config"); }

using Config = std::map<std::string, std::string>;

// The `key = value` lines of a run's stdout; every other line must be a `#` comment.
Config parse_config(const std::string& out) {
    Config c;
    std::istringstream in(out);
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        const std::size_t eq = line.find(" = ");
        EXPECT_NE(eq, std::string::npos) << "not a key = value line: '" << line << "'";
        if (eq == std::string::npos) continue;
        EXPECT_EQ(c.count(line.substr(0, eq)), 0u) << "key printed twice: " << line;
        c[line.substr(0, eq)] = line.substr(eq + 3);
    }
    return c;
}

Config print_config(const std::vector<std::string>& args) {
    std::vector<std::string> all = args;
    all.push_back("--print-config");
    const CliRun r = run_facet(all);
    EXPECT_EQ(r.exit_code, 0) << r.all();
    return parse_config(r.out);
}

std::vector<double> numbers(const std::string& csv) {
    std::vector<double> v;
    std::stringstream in(csv);
    std::string item;
    while (std::getline(in, item, ',')) v.push_back(std::stod(item));
    return v;
}

void expect_entries(const Config& c, const std::vector<std::pair<std::string, std::string>>& entries) {
    for (const auto& [key, value] : entries) {
        const auto it = c.find(key);
        EXPECT_TRUE(it != c.end() && it->second == value)
            << key << " = " << (it == c.end() ? "(not printed)" : it->second) << ", want " << value;
    }
}

unsigned cores() { return std::max(1u, std::thread::hardware_concurrency()); }

// A box from (-1, -2, -0.5) to (3, 1, 0.5), off centre, as OBJ.
std::string box_obj() {
    const double lo[3] = {-1, -2, -0.5}, hi[3] = {3, 1, 0.5};
    std::ostringstream s;
    for (int i = 0; i < 8; ++i) s << "v " << (i & 1 ? hi[0] : lo[0]) << ' ' << (i & 2 ? hi[1] : lo[1]) << ' ' << (i & 4 ? hi[2] : lo[2]) << '\n';
    const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& f : faces)
        s << "f " << f[0] + 1 << ' ' << f[1] + 1 << ' ' << f[2] + 1 << "\nf " << f[0] + 1 << ' ' << f[2] + 1 << ' ' << f[3] + 1 << '\n';
    return s.str();
}

facet_test::DecodedPng png(const fs::path& path) {
    facet_test::DecodedPng p = facet_test::decode_png(path);
    EXPECT_TRUE(p.ok()) << path << ": " << p.error;
    return p;
}

TEST(PrintConfig, RenderPrintsTheResolvedDefaultsAndRendersNothing) {
    const fs::path dir = temp_dir();
    const fs::path out = dir / "never.png";
    const Config c = print_config({"render", "-o", out.string()});
    EXPECT_FALSE(fs::exists(out)) << "--print-config must not render";
    // camera: no model and no camera option give the default scene's designed view.
    expect_entries(c, {{"size", "800x600"}, {"ssaa", "1"}, {"shading", "lit"}, {"camera", "default-scene"},
                       {"crease-angle", "40"}, {"up-axis", "y"}, {"max-triangles", "50000000"},
                       {"max-texture-size", "16384"}, {"timeout", "60"}, {"isolation", "worker-process"},
                       {"output", out.string()}, {"line-aa", "off"}});
    // "--threads N: default all cores"; --isa best is the best ISA this CPU runs.
    EXPECT_EQ(c.at("threads"), std::to_string(cores()));
    EXPECT_EQ(c.at("isa"), facet::available_isas().front());
    // README: 131,072 triangles per thread, at least 1,048,576 per batch.
    EXPECT_EQ(c.at("batch-triangles"), std::to_string(std::max<std::size_t>(131072u * cores(), 1u << 20)));
    EXPECT_EQ(c.at("tile-size"), "64");
    // README: "default three quarters of the physical memory", in --max-memory's own syntax; none
    // in sanitizer builds, whose shadow memory the cap would count (worker.hpp).
    const std::uint64_t physical = static_cast<std::uint64_t>(sysconf(_SC_PHYS_PAGES)) * sysconf(_SC_PAGESIZE);
    const std::uint64_t cap = physical / 4 * 3;
    EXPECT_EQ(c.at("max-memory"), !facet::cli::memory_cap_supported() ? "0"
                                  : cap % (1 << 20) == 0             ? std::to_string(cap >> 20) + "M"
                                                                     : std::to_string((cap + 1023) >> 10) + "K");
    // The lit mode's environment and display transform are printed, the flat mode's lights, and
    // an unlit mode says it has none.
    expect_entries(c, {{"environment", "studio"}, {"exposure", "1"}, {"tone-mapping", "neutral"}});
    EXPECT_EQ(c.count("light.key.direction"), 0u);
    EXPECT_EQ(print_config({"render", "--shading", "flat"}).at("light.key.direction"), "-0.5,0.8,1");
    EXPECT_EQ(print_config({"render", "--shading", "normals"}).at("light"), "none");
    expect_entries(print_config({"render", "--exposure", "1.5", "--tone-mapping", "aces"}),
                   {{"exposure", "1.5"}, {"tone-mapping", "aces"}});
}

TEST(PrintConfig, GivenOptionsArePrintedAsResolved) {
    const Config c = print_config({"render", "--isa", "scalar", "--ssaa", "2", "--shading", "lambert", "--background",
                                   "transparent", "--threads", "3", "--max-memory", "1G", "--timeout", "7",
                                   "--up-axis", "z", "--size", "64x32", "--line-aa"});
    // load-threads: render loads one file, whose normals use the render's threads; lambert never culls.
    expect_entries(c, {{"isa", "scalar"}, {"ssaa", "2"}, {"size", "64x32"}, {"shading", "lambert"},
                       {"background", "0,0,0,0"}, {"threads", "3"}, {"load-threads", "3"},
                       {"max-memory", facet::cli::memory_cap_supported() ? "1024M" : "0"},
                       {"timeout", "7"}, {"up-axis", "z"}, {"cull", "none"}, {"line-aa", "on"}});
    // The comparison mode's contract: 0.8 * (0.15 + 0.85 * max(dot(n, l), 0)).
    EXPECT_EQ(c.at("albedo"), "0.8");
    EXPECT_EQ(c.at("light.ambient"), "0.15");
    EXPECT_EQ(c.at("light.diffuse"), "0.85");
    EXPECT_EQ(c.count("light.specular"), 0u);
    // Without a worker process there is no timeout or memory cap.
    const Config in_process = print_config({"render", "--no-isolation"});
    EXPECT_EQ(in_process.at("isolation"), "none");
    EXPECT_EQ(in_process.at("timeout"), "0");
    EXPECT_EQ(in_process.at("max-memory"), "0");
    // A bad option is still a usage error, with nothing printed to stdout.
    const CliRun bad = run_facet({"render", "--size", "0x5", "--print-config"});
    EXPECT_EQ(bad.exit_code, 2) << bad.all();
    EXPECT_EQ(bad.out, "");
}

TEST(PrintConfig, ThreadsAreTheOnesTheRenderUses) {
    const fs::path dir = temp_dir();
    for (const std::vector<std::string>& extra : {std::vector<std::string>{}, std::vector<std::string>{"--threads", "3"}}) {
        std::vector<std::string> args = {"render", "--size", "32x24", "-o", (dir / "t.png").string()};
        args.insert(args.end(), extra.begin(), extra.end());
        const Config c = print_config(args);
        const CliRun r = run_facet(args);
        ASSERT_EQ(r.exit_code, 0) << r.all();
        std::smatch m;
        ASSERT_TRUE(std::regex_search(r.err, m, std::regex(", ([0-9]+) threads\\)"))) << r.err;
        EXPECT_EQ(c.at("threads"), m[1].str()) << r.err;
    }
}

// The README's framing rule, evaluated here for the box: centre of the bounds, r the farthest
// vertex, dist = r / sin(min(fovy, fovx) / 2), near = max(dist - 1.5 r, 0.01 r), far = dist + 1.5 r.
TEST(PrintConfig, FramedCameraIsTheReadmesRuleAndPastesBackToTheSameImage) {
    const fs::path dir = temp_dir();
    const std::string model = facet_test::write_file(dir / "box.obj", box_obj());
    const int width = 120, height = 80;
    const double az = 30 * M_PI / 180, el = 20 * M_PI / 180, fovy = 45 * M_PI / 180;
    const std::vector<std::string> framed = {"render", model, "--size", "120x80", "--azimuth", "30", "--elevation", "20"};
    const Config c = print_config(framed);
    EXPECT_EQ(c.at("camera"), "orbit");
    EXPECT_EQ(c.at("azimuth"), "30");
    EXPECT_EQ(c.at("elevation"), "20");
    EXPECT_EQ(c.at("fov"), "45");

    const double centre[3] = {1, -0.5, 0};
    const double r = std::sqrt(2.0 * 2.0 + 1.5 * 1.5 + 0.5 * 0.5);
    const double fovx = 2 * std::atan(std::tan(fovy / 2) * width / height);
    const double dist = r / std::sin(std::min(fovy, fovx) / 2);
    const double eye[3] = {centre[0] + dist * std::cos(el) * std::sin(az), centre[1] + dist * std::sin(el),
                           centre[2] + dist * std::cos(el) * std::cos(az)};
    const double tol = 1e-5 * dist;
    EXPECT_NEAR(std::stod(c.at("near")), std::max(dist - 1.5 * r, 0.01 * r), tol);
    EXPECT_NEAR(std::stod(c.at("far")), dist + 1.5 * r, tol);
    const std::vector<double> e = numbers(c.at("eye")), t = numbers(c.at("target"));
    ASSERT_EQ(e.size(), 3u);
    ASSERT_EQ(t.size(), 3u);
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(e[i], eye[i], tol) << i;
        EXPECT_NEAR(t[i], centre[i], tol) << i;
    }

    // The printed camera, given back as explicit options, is the camera the framed render used.
    std::vector<std::string> a = framed, b = {"render", model, "--size", "120x80"};
    a.insert(a.end(), {"-o", (dir / "framed.png").string()});
    for (const char* key : {"eye", "target", "up", "near", "far", "fov"}) b.insert(b.end(), {std::string("--") + key, c.at(key)});
    b.insert(b.end(), {"-o", (dir / "explicit.png").string()});
    ASSERT_EQ(run_facet(a).exit_code, 0);
    const CliRun rb = run_facet(b);
    ASSERT_EQ(rb.exit_code, 0) << rb.all();
    const facet_test::DecodedPng pa = png(dir / "framed.png"), pb = png(dir / "explicit.png");
    EXPECT_TRUE(pa.rgba == pb.rgba) << "the explicit camera from --print-config draws a different image";
    const std::size_t background = static_cast<std::size_t>(std::count(pa.rgba.begin(), pa.rgba.end(), pa.rgba[0]));
    EXPECT_LT(background, pa.rgba.size() * 9 / 10) << "the box should fill a good part of the image";
}

TEST(PrintConfig, ThumbsDefaultsAreTheOnesItRendersWith) {
    const fs::path dir = temp_dir();
    const std::string model = facet_test::write_file(dir / "box.obj", box_obj());
    const fs::path thumbs = dir / "thumbs";
    const Config c = print_config({"thumbs", model, "-o", thumbs.string()});
    EXPECT_FALSE(fs::exists(thumbs)) << "--print-config must not create the output directory";
    EXPECT_EQ(c.at("size"), "256x256");
    EXPECT_EQ(c.at("azimuth"), "35");
    EXPECT_EQ(c.at("elevation"), "25");
    EXPECT_EQ(c.at("camera"), "orbit");
    EXPECT_EQ(c.at("near"), "per model");
    EXPECT_EQ(c.at("threads"), "1");  // each worker draws with one thread
    EXPECT_EQ(c.at("workers"), "1");  // one file
    EXPECT_EQ(c.at("worker-sharing"), "folder");  // files on the command line (a manifest's: batch)
    EXPECT_EQ(c.at("load-threads"), "1");
    EXPECT_EQ(c.at("aa"), "2");  // anti-aliased by two jittered frames
    EXPECT_EQ(c.at("contact-shadow"), "0.6");
    // The thumbnail is `facet render` at the printed size, orbit, anti-aliasing and shadow, byte for byte.
    ASSERT_EQ(run_facet({"thumbs", model, "-o", thumbs.string()}).exit_code, 0);
    const fs::path rendered = dir / "render.png";
    const CliRun r = run_facet({"render", model, "--size", c.at("size"), "--azimuth", c.at("azimuth"), "--elevation",
                                c.at("elevation"), "--aa", c.at("aa"), "--contact-shadow", c.at("contact-shadow"), "-o",
                                rendered.string()});
    ASSERT_EQ(r.exit_code, 0) << r.all();
    const facet_test::DecodedPng a = png(thumbs / "box.obj.png"), b = png(rendered);
    EXPECT_EQ(a.width, 256u);
    EXPECT_TRUE(a.rgba == b.rgba);
}

TEST(PrintConfig, ViewPrintsWithoutAWindow) {
    const CliRun r = facet_test::run_program(facet_test::facet_binary(), {"view", "--print-config", "--size", "640x400"});
    ASSERT_EQ(r.exit_code, 0) << r.all();
    const Config c = parse_config(r.out);
    EXPECT_EQ(c.at("size"), "640x400");
    EXPECT_EQ(c.at("camera"), "default-scene");
    EXPECT_EQ(c.at("spin"), "off");
    EXPECT_EQ(c.at("threads"), std::to_string(cores()));
}

// The README's option table states the defaults that --print-config prints, and its "Printing the
// settings" section names every key.
TEST(PrintConfig, ReadmeDocumentsTheDefaultsAndEveryKey) {
    const std::string readme = facet_test::read_file(fs::path(facet_test::k_source_dir) / "README.md");
    ASSERT_FALSE(readme.empty());
    auto row = [&](const std::string& option) {
        const std::size_t at = readme.find("\n| `" + option);
        EXPECT_NE(at, std::string::npos) << option;
        return at == std::string::npos ? std::string() : readme.substr(at, readme.find('\n', at + 1) - at);
    };
    const fs::path dir = temp_dir();
    const std::string model = facet_test::write_file(dir / "box.obj", box_obj());
    const Config render = print_config({"render", model});
    const Config thumbs = print_config({"thumbs", model, "-o", (dir / "thumbs").string()});
    auto with_commas = [](std::string n) {
        for (int i = static_cast<int>(n.size()) - 3; i > 0; i -= 3) n.insert(static_cast<std::size_t>(i), ",");
        return n;
    };
    EXPECT_NE(row("--size").find("default " + render.at("size")), std::string::npos) << row("--size");
    EXPECT_NE(row("--size").find("default " + std::to_string(std::stoi(thumbs.at("size"))) + ")"), std::string::npos)
        << row("--size");
    EXPECT_NE(row("--azimuth").find("render: " + render.at("azimuth") + ", " + render.at("elevation") + "; thumbs: " +
                                    thumbs.at("azimuth") + ", " + thumbs.at("elevation")),
              std::string::npos)
        << row("--azimuth");
    EXPECT_NE(row("--fov").find("default " + render.at("fov")), std::string::npos) << row("--fov");
    EXPECT_NE(row("--shading").find("`" + render.at("shading") + "` (default)"), std::string::npos);
    EXPECT_NE(row("--crease-angle").find("default " + render.at("crease-angle")), std::string::npos);
    EXPECT_NE(row("--max-triangles").find("default " + with_commas(render.at("max-triangles"))), std::string::npos);
    EXPECT_NE(row("--max-texture-size").find("default " + render.at("max-texture-size")), std::string::npos);
    EXPECT_NE(row("--timeout").find("default " + render.at("timeout")), std::string::npos);

    const std::size_t section = readme.find("**Printing the settings**");
    ASSERT_NE(section, std::string::npos);
    const std::string text = readme.substr(section, readme.find("\n\n**", section + 1) - section);
    const Config view = parse_config(run_facet({"view", "--print-config"}).out);
    for (const Config* c : {&render, &thumbs, &view})
        for (const auto& [key, value] : *c)
            EXPECT_NE(text.find("`" + key + "`"), std::string::npos) << "README does not explain the key " << key;
}

}  // namespace
