// facet internals: facet's loadable modules (libfacet_*.so, built and installed with facet), the
// parts that link large libraries only some jobs need, opened with dlopen when first needed: a
// process that never needs them does not load and relocate those libraries at start. Not a plugin
// interface: a module and the program opening it come from the same build.
#pragma once

#include <string>
#include <vector>

#include "facet/api.hpp"

FACET_API_BEGIN
namespace facet::detail {

// The address of `symbol` in the module file `file` (e.g. "libfacet_exr.so"), opened once per
// process from the first place that has it: $FACET_MODULE_DIR; beside the program (or the shared
// library) holding facet's code, or its facet/ or ../<libdir>/facet/ folder; the build tree's
// lib/facet; the installed <libdir>/facet. nullptr when it cannot be opened, with `why` saying
// where it was looked for and what went wrong.
void* module_symbol(const char* file, const char* symbol, std::string& why);

// The folders module_symbol looks in, existing ones only (for a sandbox's read rules).
std::vector<std::string> module_dirs();

}  // namespace facet::detail
FACET_API_END
