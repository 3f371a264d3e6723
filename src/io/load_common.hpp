// facet io: what every path of load_model shares (the pre-checks, facet's own readers, the assimp
// path): the wording of its errors, the up-axis root transform and the estimate of a Scene's size.
// No reading here.
#pragma once

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "facet/error.hpp"
#include "facet/math/mat.hpp"
#include "facet/math/vec.hpp"
#include "facet/model.hpp"

namespace facet::io_detail {

// Every message names the file first.
inline Error fail(ErrorCode code, const std::string& path, const std::string& problem) {
    return Error{code, path + ": " + problem};
}

inline Error too_many_triangles(const std::string& path, std::uint64_t n, const LoadOptions& options) {
    return fail(ErrorCode::limit_exceeded, path,
                "has " + std::to_string(n) + " triangles, more than the limit of " + std::to_string(options.max_triangles));
}

// Text from a file or a library quoted in a message: the start of it, control characters replaced,
// so that one bad file cannot flood or garble a terminal or a log.
inline std::string readable(const std::string& text, std::size_t max = 200) {
    std::string out;
    for (char c : text.substr(0, max)) out += (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) ? ' ' : c;
    if (text.size() > max) out += "...";
    return out;
}

// A reader asked for more memory than there is (a damaged count in a header, or a process memory cap).
inline Error out_of_memory(const std::string& path) {
    return fail(ErrorCode::limit_exceeded, path, "needs more memory than is available");
}

inline std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// A whole non-negative decimal count as a header states it; nullopt if it is not one (or beyond 2^63).
inline std::optional<std::uint64_t> parse_count(std::string_view token) {
    if (token.empty() || token.size() > 18 || !std::all_of(token.begin(), token.end(), [](char c) { return c >= '0' && c <= '9'; }))
        return std::nullopt;
    std::uint64_t n = 0;
    for (char c : token) n = n * 10 + static_cast<std::uint64_t>(c - '0');
    return n;
}

// The words of a header line, split at white space as the C locale's isspace does (how the
// pre-checks have always split them).
inline std::vector<std::string> words_of(std::string_view line) {
    const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; };
    std::vector<std::string> words;
    for (std::size_t i = 0; i < line.size();) {
        while (i < line.size() && space(line[i])) ++i;
        const std::size_t start = i;
        while (i < line.size() && !space(line[i])) ++i;
        if (i > start) words.emplace_back(line.substr(start, i - start));
    }
    return words;
}

// The transform above the file's root node: +Z up to +Y up is a rotation of -90 degrees about X,
// (x, y, z) -> (x, z, -y), with exact zeros.
inline Mat4 up_axis_root(UpAxis up) {
    if (up == UpAxis::y) return Mat4::identity();
    return Mat4::from_rows({1, 0, 0, 0,  //
                            0, 0, 1, 0,  //
                            0, -1, 0, 0,  //
                            0, 0, 0, 1});
}

// A colour read from a file (a vertex's or a material's) as the Scene holds it: each channel
// clamped to [0, 1], a non-finite one taken as 1.
inline Vec4 unit_colour(float r, float g, float b, float a) {
    auto unit = [](float v) { return std::isfinite(v) ? clamp(v, 0.0f, 1.0f) : 1.0f; };
    return {unit(r), unit(g), unit(b), unit(a)};
}

// What one instance of a mesh costs once converted: the vertices its triangles can use (each with
// position, normal and, when the file has them, colour and uv) and three indices per triangle.
// Checked against LoadOptions::max_scene_bytes before converting.
inline std::uint64_t estimated_scene_bytes(std::uint64_t vertices, std::uint64_t triangles, bool colours, bool uvs) {
    const std::uint64_t used = std::min<std::uint64_t>(vertices, 3 * triangles);
    const std::uint64_t per_vertex = sizeof(Vec3) * 2 + (colours ? sizeof(Vec4) : 0) + (uvs ? sizeof(Vec2) : 0);
    return used * per_vertex + triangles * 3 * sizeof(std::uint32_t);
}

}  // namespace facet::io_detail
