#include "support/golden.hpp"

#include <gtest/gtest.h>

#include <cstdlib>

#include "facet/io.hpp"
#include "support/paths.hpp"

namespace facet_test {

namespace fs = std::filesystem;

fs::path golden_data_dir() { return fs::path(k_source_dir) / "tests" / "golden" / "data"; }

fs::path golden_scratch_dir() {
    const fs::path dir = fs::path(k_binary_dir) / "golden_out";
    fs::create_directories(dir);
    return dir;
}

void expect_matches_golden(const fs::path& actual_path) {
    const fs::path golden_path = golden_data_dir() / actual_path.filename();
    facet::Result<facet::Image> actual = facet::read_png(actual_path.string());
    ASSERT_TRUE(actual.ok()) << actual.error().message;
    if (std::getenv("FACET_UPDATE_GOLDEN")) {
        fs::copy_file(actual_path, golden_path, fs::copy_options::overwrite_existing);
        GTEST_SKIP() << "updated " << golden_path;
    }
    facet::Result<facet::Image> golden = facet::read_png(golden_path.string());
    ASSERT_TRUE(golden.ok()) << golden.error().message << " (run with FACET_UPDATE_GOLDEN=1 to create it)";
    ASSERT_EQ(actual->width, golden->width) << golden_path;
    ASSERT_EQ(actual->height, golden->height) << golden_path;
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

}  // namespace facet_test
