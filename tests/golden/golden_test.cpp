// Golden images: the examples and the command line's default scene, compared pixel for pixel with
// images stored in tests/golden/data. The renderer is deterministic, so the comparison is exact.
// To accept new images after an intended change: FACET_UPDATE_GOLDEN=1 ./facet_tests --gtest_filter='Golden*'
// On a mismatch the actual image and a difference mask are written next to the build for inspection
// (tests/support/golden.hpp).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "facet/io.hpp"
#include "support/golden.hpp"
#include "support/paths.hpp"

namespace {

namespace fs = std::filesystem;

using facet_test::expect_matches_golden;
using facet_test::golden_scratch_dir;

const fs::path k_bin = fs::path(facet_test::k_binary_dir);

void run(const std::string& command) {
    ASSERT_EQ(std::system((command + " > /dev/null").c_str()), 0) << command;
}

TEST(Golden, TriangleExample) {
    const fs::path out = golden_scratch_dir() / "triangle.png";
    run((k_bin / "examples" / "example_triangle").string() + " " + out.string());
    expect_matches_golden(out);
}

TEST(Golden, SpinningTriangleExample) {
    const fs::path prefix = golden_scratch_dir() / "spin";
    run((k_bin / "examples" / "example_spinning_triangle").string() + " " + prefix.string() + " 8");
    // A quarter turn shows the front, three quarters the back; 3/8 shows the triangle edge-on-ish.
    for (const char* frame : {"spin_000.png", "spin_001.png", "spin_003.png", "spin_005.png"})
        expect_matches_golden(golden_scratch_dir() / frame);
}

TEST(Golden, LitCubeExample) {
    const fs::path prefix = golden_scratch_dir() / "cube";
    run((k_bin / "examples" / "example_lit_cube").string() + " " + prefix.string() + " 2");
    expect_matches_golden(golden_scratch_dir() / "cube_000.png");
    expect_matches_golden(golden_scratch_dir() / "cube_001.png");
}

TEST(Golden, DefaultSceneFromTheCommandLine) {
    for (const char* shading : {"lit", "flat", "normals", "lambert"}) {
        const fs::path out = golden_scratch_dir() / (std::string("default_") + shading + ".png");
        run((k_bin / "bin" / "facet").string() + " render --size 400x300 --shading " + shading + " -o " +
            out.string() + " 2> /dev/null");
        expect_matches_golden(out);
    }
}

TEST(Golden, DefaultSceneIsIdenticalForAnyThreadCount) {
    const fs::path one = golden_scratch_dir() / "threads_1.png", three = golden_scratch_dir() / "threads_3.png";
    const std::string facet = (k_bin / "bin" / "facet").string();
    run(facet + " render --size 640x480 --threads 1 -o " + one.string() + " 2> /dev/null");
    run(facet + " render --size 640x480 --threads 3 -o " + three.string() + " 2> /dev/null");
    facet::Result<facet::Image> a = facet::read_png(one.string()), b = facet::read_png(three.string());
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_TRUE(a->pixels == b->pixels);
}

}  // namespace
