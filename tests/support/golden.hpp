// Test support: golden images. An image rendered by a test is compared pixel for pixel with the
// image of the same file name in tests/golden/data; the renderer is deterministic, so the
// comparison is exact. With FACET_UPDATE_GOLDEN set, the rendered image replaces the stored one
// (and the test reports itself skipped, saying so). On a mismatch, a difference mask (magenta where
// pixels differ) is written next to the rendered image.
#pragma once

#include <filesystem>

namespace facet_test {

// tests/golden/data in the source tree.
std::filesystem::path golden_data_dir();
// <build>/golden_out, created on first use: where tests render the images they compare.
std::filesystem::path golden_scratch_dir();

// Compares the PNG at `actual_path` with golden_data_dir() / its file name (size and every RGBA
// pixel). Use with ASSERT_NO_FATAL_FAILURE or as the last statement of a test.
void expect_matches_golden(const std::filesystem::path& actual_path);

}  // namespace facet_test
