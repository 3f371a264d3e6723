// The facet command line as scripts use it: exit codes, stderr messages, files written or not.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "facet/io.hpp"
#include "support/paths.hpp"

namespace {

namespace fs = std::filesystem;

struct CommandResult {
    int exit_code;
    std::string output;  // stdout and stderr together
};

CommandResult run_facet(const std::string& args) {
    const std::string cmd = (fs::path(facet_test::k_binary_dir) / "bin" / "facet").string() + " " + args + " 2>&1";
    CommandResult r{-1, {}};
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return r;
    char buf[4096];
    while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) r.output.append(buf, n);
    const int status = pclose(p);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

fs::path temp_dir(const char* name) {
    fs::path d = fs::temp_directory_path() / ("facet_cli_test_" + std::string(name));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

TEST(Cli, HelpListsTheOptions) {
    CommandResult r = run_facet("render --help");
    EXPECT_EQ(r.exit_code, 0);
    for (const char* option : {"--output", "--size", "--shading", "--threads", "--azimuth", "--elevation", "--fov"})
        EXPECT_NE(r.output.find(option), std::string::npos) << option;
    EXPECT_EQ(run_facet("--help").exit_code, 0);
}

TEST(Cli, VersionPrintsTheProjectVersion) {
    CommandResult r = run_facet("--version");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output, "facet " FACET_VERSION "\n");
}

TEST(Cli, RendersTheDefaultSceneAtTheRequestedSize) {
    const fs::path out = temp_dir("render") / "x.png";
    CommandResult r = run_facet("render --size 123x45 -o " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    facet::Result<facet::Image> img = facet::read_png(out.string());
    ASSERT_TRUE(img.ok());
    EXPECT_EQ(img->width, 123);
    EXPECT_EQ(img->height, 45);
}

TEST(Cli, BadArgumentsExitWithTwoAndWriteNothing) {
    const fs::path dir = temp_dir("bad_args");
    for (const char* args : {"render --size 0x10", "render --size 100", "render --size 9000x10", "render --size 10x10x",
                             "render --shading glossy", "render --threads abc", "render --no-such-option", ""}) {
        CommandResult r = run_facet(std::string(args) + " -o " + (dir / "o.png").string());
        EXPECT_NE(r.exit_code, 0) << args;
        EXPECT_FALSE(r.output.empty()) << args;
        EXPECT_FALSE(fs::exists(dir / "o.png")) << args;
    }
    EXPECT_EQ(run_facet("render --size 0x10").exit_code, 2);
    EXPECT_NE(run_facet("render --shading glossy").output.find("glossy"), std::string::npos);
}

TEST(Cli, UnwritableOutputFailsWithOneNamingTheFile) {
    CommandResult r = run_facet("render --size 16x16 -o /nonexistent-facet-dir/out.png");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.output.find("/nonexistent-facet-dir/out.png"), std::string::npos);
}

TEST(Cli, OrbitOptionsChangeTheView) {
    const fs::path dir = temp_dir("orbit");
    ASSERT_EQ(run_facet("render --size 64x48 --azimuth 0 -o " + (dir / "a.png").string()).exit_code, 0);
    ASSERT_EQ(run_facet("render --size 64x48 --azimuth 90 -o " + (dir / "b.png").string()).exit_code, 0);
    auto a = facet::read_png((dir / "a.png").string()), b = facet::read_png((dir / "b.png").string());
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_FALSE(a->pixels == b->pixels);
}

}  // namespace
