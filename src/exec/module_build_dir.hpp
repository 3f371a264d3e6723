// facet exec: the build folder's module directory (lib/facet), where exec/module.cpp looks for
// facet's modules when a program runs from the build tree. Only module_build_dir.cpp is compiled
// with the path (src/CMakeLists.txt), so that module.cpp's command line names no build folder and
// a fresh build folder or another checkout reuses its ccache entry.
#pragma once

namespace facet::detail {

extern const char* const k_module_build_dir;

}  // namespace facet::detail
