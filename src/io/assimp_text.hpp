// facet io: the pieces of assimp's text parsing (assimp/ParsingUtils.h, fast_atof.h) that facet's own
// readers (plain_off.cpp, stl.cpp) use to read text exactly as assimp's readers do.
#pragma once

// The readers of OFF, STL and PLY need nothing of libassimp, which is then loaded only for the
// files that need it (assimp_module.hpp): fast_atof's two calls into it go. It logs a warning
// through assimp's logger when a number overflows (facet keeps none of assimp's warnings:
// assimp_import.cpp's ErrorCollector keeps errors only), and builds without NDEBUG (the sanitizer
// presets) check ASSIMP_strincmp's arguments against null with ai_assert (they are string
// literals and a pointer into the text here).
#include <assimp/DefaultLogger.hpp>
#include <assimp/ai_assert.h>
#undef ASSIMP_LOG_WARN
#define ASSIMP_LOG_WARN(...) ((void)0)
#undef ai_assert
#define ai_assert(expression) ((void)0)
#include <assimp/fast_atof.h>

#include <exception>

namespace facet::io_detail {

// What fast_atof throws where assimp's reader would fail (assimp's own DeadlyImportError is not
// exported by libassimp); the reader then leaves the file to assimp, which reports it.
struct NotANumber : std::exception {
    template <class... Parts>
    explicit NotANumber(Parts&&...) {}
};

// assimp's IsSpace and IsLineEnd ('\0' ends the text too).
inline bool is_space(char c) { return c == ' ' || c == '\t'; }
inline bool is_line_end(char c) { return c == '\n' || c == '\r' || c == '\f'; }

// assimp's SkipSpaces: spaces and tabs, not line ends.
inline const char* skip_spaces(const char* c) {
    while (is_space(*c)) ++c;
    return c;
}

// A float as fast_atoreal_move reads it; throws NotANumber where assimp's reader would fail.
inline const char* read_float(const char* c, float& out) { return Assimp::fast_atoreal_move<float, NotANumber>(c, out); }

}  // namespace facet::io_detail
