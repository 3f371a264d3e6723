// assimp_text.hpp's read_float (and read_plain_float, its first way): its own reading of the common
// "[-]D[.F]" form must give fast_atoreal_move's bits and stop where it stops, for every string,
// digit by digit and 8 digits at a time, and leave every other form to fast_atoreal_move (the same
// result, or NotANumber where that throws).
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <random>
#include <string>

#include "io/assimp_text.hpp"

namespace {

using facet::io_detail::NotANumber;

// Both readings of `text`: the same bits and the same end, or both throwing.
void expect_as_fast_atof(const std::string& text) {
    float ours = 0, theirs = 0;
    const char* our_end = nullptr;
    const char* their_end = nullptr;
    bool our_throw = false, their_throw = false;
    try {
        our_end = facet::io_detail::read_float(text.c_str(), ours);
    } catch (const NotANumber&) {
        our_throw = true;
    }
    // Digits 8 at a time: the text followed by its NUL and more that may be read (any bytes).
    const std::string padded = text + std::string(1, '\0') + "9876543210 \xff\xfa.e";
    float wide = 0;
    const char* wide_end = nullptr;
    bool wide_throw = false;
    try {
        wide_end = facet::io_detail::read_float(padded.c_str(), wide, padded.c_str() + padded.size());
    } catch (const NotANumber&) {
        wide_throw = true;
    }
    try {
        their_end = Assimp::fast_atoreal_move<float, NotANumber>(text.c_str(), theirs);
    } catch (const NotANumber&) {
        their_throw = true;
    }
    ASSERT_EQ(our_throw, their_throw) << text;
    ASSERT_EQ(wide_throw, their_throw) << text;
    if (our_throw) return;
    ASSERT_EQ(std::bit_cast<std::uint32_t>(ours), std::bit_cast<std::uint32_t>(theirs)) << text;
    ASSERT_EQ(std::bit_cast<std::uint32_t>(wide), std::bit_cast<std::uint32_t>(theirs)) << text;
    ASSERT_EQ(our_end, their_end) << text;
    ASSERT_EQ(wide_end - padded.c_str(), their_end - text.c_str()) << text;
}

TEST(AssimpText, ReadFloatIsFastAtofOnRandomStrings) {
    std::mt19937_64 rng(21);
    const char* const suffixes[] = {"", " ", "\n", "\r\n", "e5", "E-3", ",5", ".", "..", "x", "/", "\t1"};
    std::string s;
    // Half a million strings: integer parts of 0-20 digits, fractions of 0-17, leading zeros, the
    // forms OBJ exporters write ("%.6f") and whatever follows a number.
    for (int i = 0; i < 500000; ++i) {
        s.clear();
        const std::uint64_t r = rng();
        if (r % 3 == 0) s += '-';
        if (r % 97 == 0) s += '+';
        const int whole = (r >> 8) % 4 == 0 ? static_cast<int>((r >> 10) % 21) : 1 + static_cast<int>((r >> 10) % 3);
        for (int k = 0; k < whole; ++k) s += static_cast<char>('0' + rng() % 10);
        if ((r >> 16) % 8 != 0) {
            s += (r >> 20) % 50 == 0 ? ',' : '.';
            const int fraction = (r >> 24) % 4 == 0 ? static_cast<int>((r >> 26) % 18) : 6;
            for (int k = 0; k < fraction; ++k) s += static_cast<char>('0' + rng() % 10);
        }
        s += suffixes[(r >> 32) % std::size(suffixes)];
        expect_as_fast_atof(s);
        if (HasFatalFailure()) return;
    }
}

// read_plain_float takes the "%f" forms (1-7 digits each side) itself, with fast_atof's bits and
// end, and no other form.
TEST(AssimpText, PlainFloatsAreReadByTheirOwnPath) {
    std::mt19937_64 rng(22);
    const char* const suffixes[] = {" ", "\n", "\r", "\t", "", "x", "/"};
    std::string s;
    for (int i = 0; i < 200000; ++i) {
        s.clear();
        const std::uint64_t r = rng();
        if (r % 2) s += '-';
        for (int k = 0, n = 1 + static_cast<int>((r >> 1) % 7); k < n; ++k) s += static_cast<char>('0' + rng() % 10);
        s += '.';
        for (int k = 0, n = 1 + static_cast<int>((r >> 4) % 7); k < n; ++k) s += static_cast<char>('0' + rng() % 10);
        s += suffixes[(r >> 8) % std::size(suffixes)];
        const std::string padded = s + std::string(1, '\0') + "9876543210 9.e";
        float ours = 0, theirs = 0;
        const char* end = facet::io_detail::read_plain_float(padded.c_str(), ours, padded.c_str() + padded.size());
        const char* their_end = Assimp::fast_atoreal_move<float, NotANumber>(s.c_str(), theirs);
        ASSERT_NE(end, nullptr) << s;
        ASSERT_EQ(end - padded.c_str(), their_end - s.c_str()) << s;
        ASSERT_EQ(std::bit_cast<std::uint32_t>(ours), std::bit_cast<std::uint32_t>(theirs)) << s;
    }
    for (const char* other : {"1", "-1", "1.", "1.5e3", "1.5E3", "1.5,2", "1.5.5", "12345678.5", "1.12345678", ".5", "+1.5", "nan"}) {
        const std::string padded = other + std::string(1, '\0') + "9876543210 9.e";
        float value = 0;
        EXPECT_EQ(facet::io_detail::read_plain_float(padded.c_str(), value, padded.c_str() + padded.size()), nullptr) << other;
    }
    // Fewer than 16 readable bytes past the sign: left to read_float's other ways.
    float value = 0;
    const std::string short_text = "-0.5 0.25";
    EXPECT_EQ(facet::io_detail::read_plain_float(short_text.c_str(), value, short_text.c_str() + short_text.size() + 1), nullptr);
}

TEST(AssimpText, ReadFloatEdgeForms) {
    for (const char* s : {"0", "-0", "0.0", "-0.000000", "1.", "-1.", ".5", "-.5", "1,5", "1e3", "1.5e-3", "nan", "-inf", "+1.5",
                          "999999999999999999", "9999999999999999999", "18446744073709551616", "1.123456789012345",
                          "1.1234567890123456", "0.000000000000001", "16777217", "16777217.5", "-", "", "x", "1.5.5",
                          "0.1000000000000000000001"})
        expect_as_fast_atof(s);
}

// read_uint is strtoul10 (the value modulo 2^32 and the end), digit by digit near `readable_end` and
// 8 digits at a time before it, whatever follows the digits.
TEST(AssimpText, ReadUintIsStrtoul10OnRandomStrings) {
    std::mt19937_64 rng(17);
    const char* const suffixes[] = {"", " ", "\n", "\r\n", "/", ":", "x", "\xff", ".5", "\t7"};
    std::string s;
    for (int i = 0; i < 200000; ++i) {
        s.clear();
        const std::size_t digits = rng() % 24;  // 0 to 23: past 8, 16 and the 32 bits' 10
        for (std::size_t d = 0; d < digits; ++d) s += static_cast<char>('0' + rng() % 10);
        s += suffixes[rng() % std::size(suffixes)];
        const char* their_end = nullptr;
        const unsigned theirs = Assimp::strtoul10(s.c_str(), &their_end);
        const char* our_end = nullptr;
        ASSERT_EQ(facet::io_detail::read_uint(s.c_str(), &our_end, s.c_str()), theirs) << s;
        ASSERT_EQ(our_end, their_end) << s;
        const std::string padded = s + std::string(1, '\0') + "9876543210 \xff";
        ASSERT_EQ(facet::io_detail::read_uint(padded.c_str(), &our_end, padded.c_str() + padded.size()), theirs) << s;
        ASSERT_EQ(our_end - padded.c_str(), their_end - s.c_str()) << s;
    }
}

}  // namespace
