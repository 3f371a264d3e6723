// Golden images: the examples and the command line's default scene, compared pixel for pixel with
// images stored in tests/golden/data. The renderer is deterministic, so the comparison is exact.
// To accept new images after an intended change: FACET_UPDATE_GOLDEN=1 ./facet_tests --gtest_filter='Golden*'
// On a mismatch the actual image and a difference mask are written next to the build for inspection.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "facet/io.hpp"

namespace {

namespace fs = std::filesystem;

const fs::path k_data = fs::path(FACET_SOURCE_DIR) / "tests" / "golden" / "data";
const fs::path k_bin = fs::path(FACET_BINARY_DIR);

fs::path scratch_dir() {
    fs::path dir = k_bin / "golden_out";
    fs::create_directories(dir);
    return dir;
}

void run(const std::string& command) {
    ASSERT_EQ(std::system((command + " > /dev/null").c_str()), 0) << command;
}

// Compares `actual` with the stored golden image of the same file name.
void expect_matches_golden(const fs::path& actual_path) {
    const fs::path golden_path = k_data / actual_path.filename();
    facet::Result<facet::Image> actual = facet::read_png(actual_path.string());
    ASSERT_TRUE(actual.ok()) << actual.error().message;
    if (std::getenv("FACET_UPDATE_GOLDEN")) {
        fs::copy_file(actual_path, golden_path, fs::copy_options::overwrite_existing);
        GTEST_SKIP() << "updated " << golden_path;
    }
    facet::Result<facet::Image> golden = facet::read_png(golden_path.string());
    ASSERT_TRUE(golden.ok()) << golden.error().message << " (run with FACET_UPDATE_GOLDEN=1 to create it)";
    ASSERT_EQ(actual->width, golden->width);
    ASSERT_EQ(actual->height, golden->height);
    std::size_t differing = 0;
    facet::Image diff = *golden;
    for (std::size_t i = 0; i < golden->pixels.size(); ++i) {
        const bool same = actual->pixels[i] == golden->pixels[i];
        differing += same ? 0 : 1;
        diff.pixels[i] = same ? facet::Rgba8{0, 0, 0, 255} : facet::Rgba8{255, 0, 255, 255};
    }
    if (differing) {
        const fs::path diff_path = actual_path.parent_path() / ("diff_" + actual_path.filename().string());
        (void)facet::write_png(diff_path.string(), diff);
        ADD_FAILURE() << differing << " pixels differ from " << golden_path << "; actual: " << actual_path
                      << ", difference mask: " << diff_path;
    }
}

TEST(Golden, TriangleExample) {
    const fs::path out = scratch_dir() / "triangle.png";
    run((k_bin / "examples" / "example_triangle").string() + " " + out.string());
    expect_matches_golden(out);
}

TEST(Golden, SpinningTriangleExample) {
    const fs::path prefix = scratch_dir() / "spin";
    run((k_bin / "examples" / "example_spinning_triangle").string() + " " + prefix.string() + " 8");
    // A quarter turn shows the front, three quarters the back; 3/8 shows the triangle edge-on-ish.
    for (const char* frame : {"spin_000.png", "spin_001.png", "spin_003.png", "spin_005.png"})
        expect_matches_golden(scratch_dir() / frame);
}

TEST(Golden, LitCubeExample) {
    const fs::path prefix = scratch_dir() / "cube";
    run((k_bin / "examples" / "example_lit_cube").string() + " " + prefix.string() + " 2");
    expect_matches_golden(scratch_dir() / "cube_000.png");
    expect_matches_golden(scratch_dir() / "cube_001.png");
}

TEST(Golden, DefaultSceneFromTheCommandLine) {
    for (const char* shading : {"lit", "flat", "normals", "lambert"}) {
        const fs::path out = scratch_dir() / (std::string("default_") + shading + ".png");
        run((k_bin / "bin" / "facet").string() + " render --size 400x300 --shading " + shading + " -o " +
            out.string() + " 2> /dev/null");
        expect_matches_golden(out);
    }
}

TEST(Golden, DefaultSceneIsIdenticalForAnyThreadCount) {
    const fs::path one = scratch_dir() / "threads_1.png", three = scratch_dir() / "threads_3.png";
    const std::string facet = (k_bin / "bin" / "facet").string();
    run(facet + " render --size 640x480 --threads 1 -o " + one.string() + " 2> /dev/null");
    run(facet + " render --size 640x480 --threads 3 -o " + three.string() + " 2> /dev/null");
    facet::Result<facet::Image> a = facet::read_png(one.string()), b = facet::read_png(three.string());
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_TRUE(a->pixels == b->pixels);
}

}  // namespace
