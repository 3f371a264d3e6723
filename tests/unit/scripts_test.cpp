// The project's scripts answer --help (and -h) with their own documentation, their leading comment,
// before doing anything: every script sources scripts/lib/help.sh first. Checked without running the
// scripts themselves (they install packages and build): the helper on a script made here, and each
// script's first command.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "support/paths.hpp"
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;

const fs::path k_source = facet_test::k_source_dir;

std::string output_of(const std::string& command, int& exit_code) {
    std::string out;
    FILE* p = popen(command.c_str(), "r");
    if (!p) return out;
    char buf[4096];
    while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) out.append(buf, n);
    const int status = pclose(p);
    exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return out;
}

TEST(Scripts, HelpPrintsTheLeadingCommentAndStops) {
    const fs::path dir = facet_test::test_temp_dir("facet_scripts_test");
    const fs::path script = dir / "tool";
    facet_test::write_file(script, "#!/usr/bin/env bash\n# Does a thing.\n#   tool --flag   does it loudly\n#\n# More.\n"
                                   "source \"" + (k_source / "scripts/lib/help.sh").string() + "\" \"$@\"\n"
                                   "echo ran \"$@\"\n");
    fs::permissions(script, fs::perms::owner_all);
    for (const char* flag : {"--help", "-h"}) {
        int code = -1;
        EXPECT_EQ(output_of(script.string() + " " + flag, code), "Does a thing.\n  tool --flag   does it loudly\n\nMore.\n") << flag;
        EXPECT_EQ(code, 0) << flag;
    }
    int code = -1;
    EXPECT_EQ(output_of(script.string() + " a --help", code), "ran a --help\n");  // only as the first argument
    EXPECT_EQ(output_of(script.string(), code), "ran\n");
}

TEST(Scripts, EveryScriptSourcesTheHelpFirst) {
    for (const char* name : {"scripts/bench", "scripts/bench-loading", "scripts/ci-extra", "scripts/demo", "scripts/fuzz", "scripts/sanitize",
                             "scripts/setup", "scripts/test", ".ci/run"}) {
        std::ifstream in(k_source / name);
        ASSERT_TRUE(in) << name;
        std::string line, first_command;
        while (std::getline(in, line))
            if (!line.empty() && line[0] != '#') {
                first_command = line;
                break;
            }
        EXPECT_EQ(first_command.rfind("source \"$(dirname \"$0\")/", 0), 0u) << name << ": " << first_command;
        EXPECT_NE(first_command.find("lib/help.sh\" \"$@\""), std::string::npos) << name << ": " << first_command;
    }
}

}  // namespace
