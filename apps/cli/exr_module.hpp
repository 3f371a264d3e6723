// facet command line: the OpenEXR writer as a module (libfacet_exr.so, facet/detail/module.hpp),
// so that only a process that writes --float-format exr loads OpenEXR's libraries. In: a file's
// channels; out: the file. The module's side is exr_module.cpp; pass_files.cpp opens it.
#pragma once

#include <cstddef>

namespace facet::cli {

// One channel of width * height values, the first at `first`, `pixel_bytes` apart, rows
// width * pixel_bytes apart.
struct ExrChannel {
    const char* name = "";
    bool is_uint = false;  // UINT, else FLOAT
    const void* first = nullptr;
    std::size_t pixel_bytes = 4;
};

// Writes `path` (ZIP compression); 0, or non-zero with a message in `error` (NUL-terminated).
using WriteExr = int (*)(const char* path, int width, int height, const ExrChannel* channels, int count, char* error,
                         std::size_t error_size);

inline constexpr const char* k_exr_module = "libfacet_exr.so";
inline constexpr const char* k_exr_write_symbol = "facet_exr_write_v1";

}  // namespace facet::cli
