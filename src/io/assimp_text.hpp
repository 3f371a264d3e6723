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

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
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

namespace text_detail {

inline bool digit(char d) { return static_cast<unsigned>(static_cast<unsigned char>(d) - '0') <= 9u; }

// Of 8 bytes (a little-endian word), how many before the first that is not a decimal digit. Less
// '0', a digit is 0..9: its top bit clear, and clear too with 0x76 added; any other byte sets one
// of them. A borrow or carry out of a byte reaches only the bytes after it, which come after a
// flagged one.
inline unsigned leading_digits(std::uint64_t word) {
    const std::uint64_t less = word - 0x3030303030303030ull;
    const std::uint64_t flagged = (less | (less + 0x7676767676767676ull)) & 0x8080808080808080ull;
    return flagged ? static_cast<unsigned>(std::countr_zero(flagged)) / 8 : 8;
}

// The value of the first n (1 to 8) digits of a word: shifted up so that they are the last of
// eight, zeros before them, then added in pairs, fours and eights (as fast_float does).
inline std::uint64_t digits_value(std::uint64_t word, unsigned n) {
    std::uint64_t v = (word - 0x3030303030303030ull) << (8 * (8 - n));  // the bytes past the digits shifted out
    v = v * 10 + (v >> 8);
    return (((v & 0x000000FF000000FFull) * 0x000F424000000064ull) + (((v >> 16) & 0x000000FF000000FFull) * 0x0000271000000001ull)) >> 32;
}

// The run of decimal digits at p as an integer (modulo 2^64, as the digit-by-digit sum), and its
// end. 8 bytes at a time while 8 bytes before `readable_end` remain, then one at a time.
[[gnu::always_inline]] inline const char* read_digits(const char* p, const char* readable_end, std::uint64_t& value) {
    static constexpr std::uint64_t scale[9] = {1, 10, 100, 1000, 10000, 100000, 1000000, 10000000, 100000000};
    std::uint64_t v = 0;
    while (readable_end - p >= 8) {
        std::uint64_t word;
        std::memcpy(&word, p, sizeof word);
        const unsigned n = leading_digits(word);
        if (n == 0) break;
        v = v * scale[n] + digits_value(word, n);
        p += n;
        if (n < 8) {
            value = v;
            return p;
        }
    }
    while (digit(*p)) v = v * 10 + static_cast<unsigned>(*p++ - '0');
    value = v;
    return p;
}

}  // namespace text_detail

// assimp's strtoul10 (the value of the run of digits at c, modulo 2^32, and its end in *out), 8 digits
// at a time while 8 bytes before `readable_end` remain: an OFF face's count and indices, where the
// byte-by-byte loop's exit, at no pattern in the digits' counts, was a third of the reader's time.
[[gnu::always_inline]] inline std::uint32_t read_uint(const char* c, const char** out, const char* readable_end) {
    std::uint64_t value;
    *out = text_detail::read_digits(c, readable_end, value);
    return static_cast<std::uint32_t>(value);
}

// The form OBJ, PLY and OFF exporters write ("%f": "[-]D.F", 1-7 digits each side) as
// fast_atoreal_move reads it, by read_float's arithmetic below, when 16 bytes from c (past the sign)
// may be read: each side's digits are one 8-byte word's. The number's end, or null for any other
// form (read_float's to read).
[[gnu::always_inline]] inline const char* read_plain_float(const char* c, float& out, const char* readable_end) {
    const bool negative = *c == '-';
    const char* const p = c + negative;
    if (readable_end - p < 16) return nullptr;
    std::uint64_t whole, fraction;
    std::memcpy(&whole, p, sizeof whole);
    const unsigned n = text_detail::leading_digits(whole);
    if (n - 1 >= 7 || ((whole >> (8 * n)) & 0xFF) != '.') return nullptr;
    std::memcpy(&fraction, p + n + 1, sizeof fraction);
    const unsigned m = text_detail::leading_digits(fraction);
    if (m - 1 >= 7) return nullptr;  // before the shift below: 8 digits would shift by 64
    const unsigned after = static_cast<unsigned>(fraction >> (8 * m)) & 0xFF;
    if (after == 'e' || after == 'E' || after == ',' || after == '.') return nullptr;
    // Below 2^63: as signed integers, the same values without the unsigned conversion's branch.
    float f = static_cast<float>(static_cast<std::int64_t>(text_detail::digits_value(whole, n)));
    f += static_cast<float>(static_cast<double>(static_cast<std::int64_t>(text_detail::digits_value(fraction, m))) *
                            Assimp::fast_atof_table[m]);
    out = std::bit_cast<float>(std::bit_cast<std::uint32_t>(f) ^ static_cast<std::uint32_t>(negative) << 31);  // -f, without a branch
    return p + n + 1 + m;
}

// A float as fast_atoreal_move reads it; throws NotANumber where assimp's reader would fail. The
// common "[-]D[.F]" (1-18 integer digits, 1-15 fraction digits, no exponent, comma or trailing dot)
// is read here with fast_atoreal_move's own arithmetic in its own order (the integer part as an
// integer converted to float; the fraction as an integer converted to double, times
// fast_atof_table[its digits], converted to float and added; then the sign), so the same bits
// without its checks; every other form goes to fast_atoreal_move itself. With `readable_end` (the
// end of the bytes that may be read, past the text's NUL), digits are read 8 at a time.
[[gnu::noinline]] inline const char* read_any_float(const char* c, float& out, const char* readable_end) {
    const char* p = c;
    const bool negative = *p == '-';
    p += negative;
    const char* const whole_start = p;
    std::uint64_t whole = 0;
    p = text_detail::read_digits(p, readable_end, whole);
    if (static_cast<std::size_t>(p - whole_start) - 1 < 18) {  // 1 to 18 digits: no overflow
        float f = static_cast<float>(whole);
        bool plain = true;
        if (*p == '.') {
            const char* const fraction_start = ++p;
            std::uint64_t fraction = 0;
            p = text_detail::read_digits(p, readable_end, fraction);
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
inline const char* read_float(const char* c, float& out, const char* readable_end) {
    if (const char* end = read_plain_float(c, out, readable_end)) return end;
    return read_any_float(c, out, readable_end);
}
inline const char* read_float(const char* c, float& out) { return read_any_float(c, out, c); }

}  // namespace facet::io_detail
