// facet io: the plain OFF fast path (plain_off.hpp). Every step mirrors what assimp 5.2 does with
// a file of the accepted form, so that the two paths give the same mesh bit for bit:
//  - lines: assimp's OFF reader takes the text line by line, skipping empty lines (a line of
//    spaces is not empty), into a 4096-byte buffer that would cut longer lines (refused here);
//  - vertices: SkipSpaces then fast_atoreal_move<float> three times, the rest of the line ignored;
//  - faces: SkipSpaces then strtoul10 for the count and each index, the rest ignored (a missing
//    index reads as 0 in both);
//  - JoinIdenticalVertices and facet's conversion: join_identical_vertices (io/joined_mesh.hpp),
//    which leaves files with positions only assimp's tolerance would join to assimp.
#include "io/plain_off.hpp"

#include <algorithm>
#include <cmath>

#include "io/assimp_text.hpp"
#include "io/joined_mesh.hpp"
#include "io/load_common.hpp"

namespace facet::io_detail {
namespace {

// assimp copies each line into a 4096-byte buffer; a longer line would be read differently.
constexpr std::ptrdiff_t k_max_line = 4000;

// The text's non-empty lines, as assimp's GetNextLine returns them. A line's reader stops at or
// before its end (numbers and spaces never take a line-end character), and the line is skipped
// from there: each character is looked at once, by the reader or here (measured: scanning each
// line again from its start was a third of the reading of a bunny).
class Lines {
public:
    explicit Lines(const char* at) : begin_(at) {}
    // The start of the first line, or nullptr when there is none or it is too long.
    const char* first() { return start_next(begin_); }
    // The start of the line after the current one, whose reader stopped at `stopped`; nullptr at
    // the end of the text or when the current line or the next is too long.
    const char* next(const char* stopped) {
        const char* end = end_of_current(stopped);
        return end ? start_next(end) : nullptr;
    }
    // Whether the current line, whose reader stopped at `stopped`, is short enough.
    bool finish(const char* stopped) const { return end_of_current(stopped) != nullptr; }

private:
    // The end of the current line, or nullptr when it is too long.
    const char* end_of_current(const char* c) const {
        while (*c != '\0' && !is_line_end(*c)) ++c;
        return c - begin_ < k_max_line ? c : nullptr;
    }
    const char* start_next(const char* c) {
        while (is_line_end(*c)) ++c;
        if (*c == '\0') return nullptr;
        begin_ = c;
        return c;
    }
    const char* begin_;  // of the current line
};

// A whole decimal count of at most 9 digits, then spaces; nullopt otherwise.
std::optional<std::uint32_t> parse_small_count(const char*& c) {
    c = skip_spaces(c);
    std::uint32_t v = 0;
    int digits = 0;
    for (; *c >= '0' && *c <= '9'; ++c, ++digits) v = v * 10 + static_cast<std::uint32_t>(*c - '0');
    if (digits == 0 || digits > 9 || !(is_space(*c) || is_line_end(*c) || *c == '\0')) return std::nullopt;
    return v;
}

// "OFF" alone on the first line, the vertex, face and edge counts alone on the second.
std::optional<OffHeader::Plain> parse_plain_header(const char* text) {
    const char* c = text;
    if (c[0] != 'O' || c[1] != 'F' || c[2] != 'F') return std::nullopt;
    c = skip_spaces(c + 3);
    if (!is_line_end(*c)) return std::nullopt;
    while (is_line_end(*c)) ++c;
    const auto vertices = parse_small_count(c), faces = parse_small_count(c), edges = parse_small_count(c);
    if (!vertices || !faces || !edges || *vertices == 0 || *faces == 0) return std::nullopt;
    c = skip_spaces(c);
    if (!is_line_end(*c)) return std::nullopt;
    return OffHeader::Plain{*vertices, *faces, static_cast<std::size_t>(c - text)};
}

// Reads `count` vertex lines, the first at `c`; returns where the reader stopped in the last one,
// or nullptr.
const char* read_vertices(Lines& lines, const char* c, std::uint32_t count, std::vector<Vec3>& out) {
    out.resize(count);
    for (std::uint32_t i = 0; i < count; ++i) {
        if (i > 0) c = lines.next(c);
        if (!c) return nullptr;
        for (std::size_t dim = 0; dim < 3; ++dim) {
            c = skip_spaces(c);
            c = read_float(c, out[i][dim]);  // throws where assimp's reader fails
            if (!std::isfinite(out[i][dim])) return nullptr;
        }
    }
    return c;
}

// Reads `count` triangle lines, the first after the line where the vertex reader stopped at `c`;
// returns where the reader stopped in the last one, or nullptr.
const char* read_triangles(Lines& lines, const char* c, std::uint32_t count, std::uint32_t vertex_count,
                           std::vector<std::uint32_t>& out) {
    out.resize(std::size_t{3} * count);
    for (std::size_t f = 0; f < count; ++f) {
        c = lines.next(c);
        if (!c) return nullptr;
        c = skip_spaces(c);
        if (Assimp::strtoul10(c, &c) != 3) return nullptr;  // polygons: assimp triangulates them
        for (std::size_t k = 0; k < 3; ++k) {
            c = skip_spaces(c);
            const unsigned index = Assimp::strtoul10(c, &c);
            if (index >= vertex_count) return nullptr;  // assimp clamps it and logs an error
            out[3 * f + k] = index;
        }
    }
    return c;
}

}  // namespace

OffHeader parse_off_header(std::string_view head) {
    OffHeader h;
    for (std::size_t at = 0; h.tokens.size() < 3 && at < head.size();) {
        const std::size_t newline = std::min(head.find('\n', at), head.size());
        const std::string_view line = head.substr(at, std::min(newline, head.find('#', at)) - at);
        at = newline + 1;
        for (std::string& word : words_of(line))
            if (h.tokens.size() < 3) h.tokens.push_back(std::move(word));
    }
    h.plain = parse_plain_header(head.data());
    return h;
}

Status check_off_header(const std::string& path, const OffHeader& header, std::uint64_t size, const LoadOptions& options) {
    const std::vector<std::string>& tokens = header.tokens;
    if (tokens.empty() || tokens[0].size() < 3 || tokens[0].substr(tokens[0].size() - 3) != "OFF" ||
        tokens[0].find('n') != std::string::npos)
        return Ok{};  // not plain OFF (or nOFF with a dimension): assimp decides
    if (tokens.size() < 3) return fail(ErrorCode::bad_format, path, "OFF header has no vertex and face counts");
    const auto vertices = parse_count(tokens[1]), faces = parse_count(tokens[2]);
    if (!vertices || !faces)
        return fail(ErrorCode::bad_format, path, "OFF header has invalid counts '" + tokens[1] + " " + tokens[2] + "'");
    if (*vertices > size / 6 || *faces > size / 2 || *vertices * 6 + *faces * 2 > size)
        return fail(ErrorCode::bad_format, path,
                    "OFF header claims " + std::to_string(*vertices) + " vertices and " + std::to_string(*faces) +
                        " faces, more than the file's " + std::to_string(size) + " bytes can hold (truncated or corrupt)");
    if (*faces > options.max_triangles) return too_many_triangles(path, *faces, options);
    return Ok{};
}

std::optional<PlainOffMesh> read_plain_off_with_header(std::string_view text, const OffHeader& header) {
    if (text.find('\0') != std::string_view::npos) return std::nullopt;  // assimp stops reading there
    const std::optional<OffHeader::Plain>& plain = header.plain;
    // A vertex line takes at least 6 bytes ("0 0 0\n"), a triangle 8: more would be a damaged
    // header, and must not allocate what it claims.
    if (!plain || plain->body > text.size() || std::uint64_t{plain->vertices} * 6 + std::uint64_t{plain->faces} * 8 > text.size())
        return std::nullopt;
    std::vector<Vec3> positions;
    std::vector<std::uint32_t> indices;
    Lines lines(text.data() + plain->body);
    const char* stopped = nullptr;
    try {
        stopped = read_vertices(lines, lines.first(), plain->vertices, positions);
    } catch (const NotANumber&) {
        return std::nullopt;
    }
    if (stopped) stopped = read_triangles(lines, stopped, plain->faces, plain->vertices, indices);
    if (!stopped || !lines.finish(stopped)) return std::nullopt;
    return join_identical_vertices(positions, indices);
}

std::optional<PlainOffMesh> read_plain_off(std::string_view text) { return read_plain_off_with_header(text, parse_off_header(text)); }

}  // namespace facet::io_detail
