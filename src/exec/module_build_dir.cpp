#include "exec/module_build_dir.hpp"

namespace facet::detail {

const char* const k_module_build_dir = FACET_MODULE_BUILD_DIR;

}  // namespace facet::detail
