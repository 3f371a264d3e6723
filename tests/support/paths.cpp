#include "support/paths.hpp"

namespace facet_test {

const char* const k_source_dir = FACET_SOURCE_DIR;
const char* const k_binary_dir = FACET_BINARY_DIR;

}  // namespace facet_test
