// Test support: the source and build trees the tests read from and write to. Only
// support/paths.cpp is compiled with their paths (tests/CMakeLists.txt), so that the other test
// objects' command lines name no directory and a fresh build folder or another checkout reuses
// their ccache entries.
#pragma once

namespace facet_test {

extern const char* const k_source_dir;  // the checkout (PROJECT_SOURCE_DIR)
extern const char* const k_binary_dir;  // the build folder (PROJECT_BINARY_DIR): bin/facet, examples/

}  // namespace facet_test
