// facet io: the plain OFF fast path (plain_off.hpp). Every step mirrors what assimp 5.2 does with
// a file of the accepted form, so that the two paths give the same mesh bit for bit:
//  - lines: assimp's OFF reader takes the text line by line, skipping empty lines (a line of
//    spaces is not empty), into a 4096-byte buffer that would cut longer lines (refused here);
//  - vertices: SkipSpaces then fast_atoreal_move<float> three times, the rest of the line ignored;
//  - faces: SkipSpaces then strtoul10 for the count and each index, the rest ignored (a missing
//    index reads as 0 in both);
//  - JoinIdenticalVertices: only vertices the faces use, joined when their positions are equal
//    (-0 equal to +0), each group keeping the first of them in file order. assimp finds equal
//    positions with a tolerance of a few units in the last place of tiny squared distances,
//    which differs from exact equality only for coordinates within about 1e-22 of each other:
//    files with nonzero coordinates below 2^-49 go to assimp, as do non-finite ones;
//  - facet's conversion: vertices renumbered in order of first use by the triangles.
#include "io/plain_off.hpp"

#include <assimp/fast_atof.h>

#include <bit>
#include <cmath>
#include <exception>

namespace facet::io_detail {
namespace {

// What fast_atof throws where assimp's reader would fail (assimp's own DeadlyImportError is not
// exported by libassimp); the caller then leaves the file to assimp, which reports it.
struct NotANumber : std::exception {
    template <class... Parts>
    explicit NotANumber(Parts&&...) {}
};

bool is_line_end(char c) { return c == '\n' || c == '\r' || c == '\f'; }  // and '\0', the end
bool is_space(char c) { return c == ' ' || c == '\t'; }

const char* skip_spaces(const char* c) {
    while (is_space(*c)) ++c;
    return c;
}

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

struct Header {
    std::uint32_t vertices = 0, faces = 0;
    const char* body = nullptr;  // the first line after the counts
};

// "OFF" alone on the first line, the vertex, face and edge counts alone on the second.
std::optional<Header> parse_header(const char* c) {
    if (c[0] != 'O' || c[1] != 'F' || c[2] != 'F') return std::nullopt;
    c = skip_spaces(c + 3);
    if (!is_line_end(*c)) return std::nullopt;
    while (is_line_end(*c)) ++c;
    Header h;
    const auto vertices = parse_small_count(c), faces = parse_small_count(c), edges = parse_small_count(c);
    if (!vertices || !faces || !edges || *vertices == 0 || *faces == 0) return std::nullopt;
    c = skip_spaces(c);
    if (!is_line_end(*c)) return std::nullopt;
    h.vertices = *vertices;
    h.faces = *faces;
    h.body = c;
    return h;
}

// Coordinates the exact join below treats as assimp does (see the file comment).
bool joins_exactly(float v) {
    constexpr float k_tiny = 0x1p-49f;
    return std::isfinite(v) && (v == 0.0f || std::fabs(v) >= k_tiny);
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
            c = Assimp::fast_atoreal_move<float, NotANumber>(c, out[i][dim]);  // throws where assimp's reader fails
            if (!joins_exactly(out[i][dim])) return nullptr;
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

// Equal positions share a key: the bit patterns, with -0 as +0.
std::uint32_t key_bits(float v) { return std::bit_cast<std::uint32_t>(v == 0.0f ? 0.0f : v); }

std::uint64_t position_hash(const Vec3& p) {
    std::uint64_t h = key_bits(p.x) * 0x9E3779B97F4A7C15ull;
    h = (h ^ key_bits(p.y)) * 0xC2B2AE3D27D4EB4Full;
    h = (h ^ key_bits(p.z)) * 0x165667B19E3779F9ull;
    return h ^ (h >> 29);
}

bool same_position(const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// For each used vertex, the first used vertex in file order at the same position (its group's
// representative, as in assimp's JoinIdenticalVertices); unused vertices keep ~0.
std::vector<std::uint32_t> join_used_vertices(const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& indices) {
    constexpr std::uint32_t none = ~0u;
    std::vector<std::uint32_t> representative(positions.size(), none);
    for (std::uint32_t i : indices) representative[i] = 0;  // marks the used ones
    const std::size_t capacity = std::bit_ceil(2 * positions.size());
    std::vector<std::uint32_t> table(capacity, none);  // open addressing, linear probing
    for (std::uint32_t v = 0; v < positions.size(); ++v) {
        if (representative[v] == none) continue;
        for (std::size_t slot = position_hash(positions[v]) & (capacity - 1);; slot = (slot + 1) & (capacity - 1)) {
            if (table[slot] == none) {
                table[slot] = v;
                representative[v] = v;
                break;
            }
            if (same_position(positions[table[slot]], positions[v])) {
                representative[v] = table[slot];
                break;
            }
        }
    }
    return representative;
}

// The representatives renumbered in order of first use by the triangles, as facet's conversion
// of assimp's mesh does.
PlainOffMesh number_by_first_use(const std::vector<Vec3>& file_positions, const std::vector<std::uint32_t>& file_indices) {
    const std::vector<std::uint32_t> representative = join_used_vertices(file_positions, file_indices);
    constexpr std::uint32_t none = ~0u;
    std::vector<std::uint32_t> number(file_positions.size(), none);
    PlainOffMesh out;
    out.indices.resize(file_indices.size());
    for (std::size_t c = 0; c < file_indices.size(); ++c) {
        const std::uint32_t r = representative[file_indices[c]];
        if (number[r] == none) {
            number[r] = static_cast<std::uint32_t>(out.positions.size());
            out.positions.push_back(file_positions[r]);
        }
        out.indices[c] = number[r];
    }
    for (std::size_t t = 0; t < out.indices.size(); t += 3) {
        const std::uint32_t a = out.indices[t], b = out.indices[t + 1], c = out.indices[t + 2];
        out.degenerate += a == b || b == c || c == a;
    }
    return out;
}

}  // namespace

std::optional<PlainOffMesh> read_plain_off(std::string_view text) {
    if (text.find('\0') != std::string_view::npos) return std::nullopt;  // assimp stops reading there
    const std::optional<Header> header = parse_header(text.data());
    // A vertex line takes at least 6 bytes ("0 0 0\n"), a triangle 8: more would be a damaged
    // header, and must not allocate what it claims.
    if (!header || std::uint64_t{header->vertices} * 6 + std::uint64_t{header->faces} * 8 > text.size()) return std::nullopt;
    std::vector<Vec3> positions;
    std::vector<std::uint32_t> indices;
    Lines lines(header->body);
    const char* stopped = nullptr;
    try {
        stopped = read_vertices(lines, lines.first(), header->vertices, positions);
    } catch (const NotANumber&) {
        return std::nullopt;
    }
    if (stopped) stopped = read_triangles(lines, stopped, header->faces, header->vertices, indices);
    if (!stopped || !lines.finish(stopped)) return std::nullopt;
    return number_by_first_use(positions, indices);
}

}  // namespace facet::io_detail
