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

#include <cstddef>
#include <cstdint>
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

// A float as fast_atoreal_move reads it; throws NotANumber where assimp's reader would fail. The
// common "[-]D[.F]" (1-18 integer digits, 1-15 fraction digits, no exponent, comma or trailing dot)
// is read here with fast_atoreal_move's own arithmetic in its own order (the integer part as an
// integer converted to float; the fraction as an integer converted to double, times
// fast_atof_table[its digits], converted to float and added; then the sign), so the same bits
// without its checks; every other form goes to fast_atoreal_move itself.
inline const char* read_float(const char* c, float& out) {
    const auto digit = [](char d) { return static_cast<unsigned>(static_cast<unsigned char>(d) - '0') <= 9u; };
    const char* p = c;
    const bool negative = *p == '-';
    p += negative;
    const char* const whole_start = p;
    std::uint64_t whole = 0;
    while (digit(*p)) whole = whole * 10 + static_cast<unsigned>(*p++ - '0');
    if (static_cast<std::size_t>(p - whole_start) - 1 < 18) {  // 1 to 18 digits: no overflow
        float f = static_cast<float>(whole);
        bool plain = true;
        if (*p == '.') {
            const char* const fraction_start = ++p;
            std::uint64_t fraction = 0;
            while (digit(*p)) fraction = fraction * 10 + static_cast<unsigned>(*p++ - '0');
            const std::size_t n = static_cast<std::size_t>(p - fraction_start);
            plain = n - 1 < 15;  // 1 to 15 digits
            if (plain) {
                double pl = static_cast<double>(fraction);
                pl *= Assimp::fast_atof_table[n];
                f += static_cast<float>(pl);
            }
        }
        if (plain && *p != 'e' && *p != 'E' && *p != ',' && *p != '.') {
            out = negative ? -f : f;
            return p;
        }
    }
    return Assimp::fast_atoreal_move<float, NotANumber>(c, out);
}

}  // namespace facet::io_detail
