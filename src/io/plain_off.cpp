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
#include <bit>
#include <cmath>
#include <cstring>

#include "facet/detail/thread_pool.hpp"
#include "io/assimp_text.hpp"
#include "io/joined_mesh.hpp"
#include "io/load_common.hpp"

namespace facet::io_detail {
namespace {

// assimp copies each line into a 4096-byte buffer; a longer line would be read differently.
constexpr std::ptrdiff_t k_max_line = 4000;

// Threads share the body in pieces of about this many bytes, each beginning where a line does:
// first the lines of every piece are counted (2 instructions a byte), then every piece's lines are
// read knowing their numbers. The mesh does not depend on where the pieces are cut, nor on the
// threads; one thread reads the body as one piece.
constexpr std::size_t k_piece_bytes = 64 * 1024;

// Where the next line after `c` begins (or `end`): past the rest of the line and the line ends.
const char* next_line_start(const char* c, const char* end) {
    while (c < end && !is_line_end(*c)) ++c;
    while (c < end && is_line_end(*c)) ++c;
    return c;
}

// Sixteen bytes at a time (GCC's and Clang's generic vectors: SSE2, NEON, or plain code): a
// comparison gives 0xFF in the bytes where it holds.
using Bytes16 = unsigned char __attribute__((vector_size(16)));
Bytes16 load16(const char* c) {
    Bytes16 v;
    std::memcpy(&v, c, sizeof v);
    return v;
}
Bytes16 line_ends(Bytes16 v) { return reinterpret_cast<Bytes16>((v == '\n') | (v == '\r') | (v == '\f')); }

// The lines beginning in [begin, end), as assimp's GetNextLine returns them: empty lines do not
// count (a line of spaces is not empty), and a line begins at a byte that is not a line end after
// one that is. The byte before `begin` is in the text: a line end (the previous piece's), or the
// header's last (where `begin` is the header's line end, no line's start). `nul` is set if the
// piece has a NUL byte (assimp stops reading there).
std::size_t count_lines(const char* begin, const char* end, bool& nul) {
    std::size_t lines = 0;
    const char* c = begin;
    Bytes16 zeros{}, counts{};
    for (int in_counts = 0; end - c >= 16; c += 16) {
        const Bytes16 v = load16(c);
        counts -= line_ends(load16(c - 1)) & ~line_ends(v);  // + 1 where a line begins
        zeros |= reinterpret_cast<Bytes16>(v == 0);
        if (++in_counts == 255 || end - c < 32) {  // before a byte of `counts` could overflow
            for (int i = 0; i < 16; ++i) lines += counts[i];
            counts = Bytes16{}, in_counts = 0;
        }
    }
    bool zero = false;
    for (int i = 0; i < 16; ++i) zero |= zeros[i] != 0;
    for (; c < end; ++c) {
        lines += is_line_end(c[-1]) && !is_line_end(*c);
        zero |= *c == '\0';
    }
    nul = zero;
    return lines;
}

// Where the readers of the lines write: the vertex lines come first, then the triangle lines; the
// lines after them are not read.
struct OffTarget {
    std::uint32_t vertex_count, face_count;
    Vec3* positions;
    std::uint32_t* indices;
};

// Reads the lines of the piece [begin, end), the first of them line number `line` of the body;
// returns the number after the last line read, or nullopt where assimp's reader would read the
// file differently. A line's reader stops at or before its end (numbers and spaces never take a
// line-end character), and the line is skipped from there.
std::optional<std::size_t> read_piece(const char* begin, const char* end, std::size_t line, const OffTarget& to) {
    const std::size_t last = std::size_t{to.vertex_count} + to.face_count;
    for (const char* c = begin; line < last; ++line) {
        while (c < end && is_line_end(*c)) ++c;
        if (c >= end) break;
        const char* const start = c;
        if (line < to.vertex_count) {
            Vec3& p = to.positions[line];
            for (std::size_t dim = 0; dim < 3; ++dim) {
                c = skip_spaces(c);
                c = read_float(c, p[dim]);  // throws where assimp's reader fails
                if (!std::isfinite(p[dim])) return std::nullopt;
            }
        } else {
            std::uint32_t* index = to.indices + 3 * (line - to.vertex_count);
            c = skip_spaces(c);
            if (Assimp::strtoul10(c, &c) != 3) return std::nullopt;  // polygons: assimp triangulates them
            for (std::size_t k = 0; k < 3; ++k) {
                c = skip_spaces(c);
                index[k] = Assimp::strtoul10(c, &c);
                if (index[k] >= to.vertex_count) return std::nullopt;  // assimp clamps it and logs an error
            }
        }
        while (*c != '\0' && !is_line_end(*c)) ++c;
        if (c - start >= k_max_line) return std::nullopt;
    }
    return line;
}

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

std::optional<PlainOffMesh> read_plain_off_with_header(std::string_view text, const OffHeader& header,
                                                       detail::ThreadPool* pool) {
    const std::optional<OffHeader::Plain>& plain = header.plain;
    // A vertex line takes at least 6 bytes ("0 0 0\n"), a triangle 8: more would be a damaged
    // header, and must not allocate what it claims.
    if (!plain || plain->body > text.size() || std::uint64_t{plain->vertices} * 6 + std::uint64_t{plain->faces} * 8 > text.size())
        return std::nullopt;
    if (text.substr(0, plain->body).find('\0') != std::string_view::npos) return std::nullopt;
    const char* const body = text.data() + plain->body;
    const char* const end = text.data() + text.size();
    const std::size_t lines = std::size_t{plain->vertices} + plain->faces;
    // One thread reads the body as one piece, numbering the lines as it goes; threads share it in
    // pieces whose lines they count first.
    std::vector<const char*> piece{body};
    std::vector<std::size_t> first_line{0};
    if (pool) {
        for (const char* c = body; c < end;) {
            c = next_line_start(std::min(c + k_piece_bytes, end), end);
            piece.push_back(c);
        }
        first_line.assign(piece.size(), 0);  // each piece's count first, then their running sums
        std::vector<char> has_nul(piece.size() - 1, 0);
        pool->parallel_for(piece.size() - 1, [&](std::size_t k) {
            bool nul = false;
            first_line[k + 1] = count_lines(piece[k], piece[k + 1], nul);
            has_nul[k] = nul;
        });
        for (std::size_t k = 1; k < first_line.size(); ++k) first_line[k] += first_line[k - 1];
        if (std::find(has_nul.begin(), has_nul.end(), 1) != has_nul.end() || first_line.back() < lines) return std::nullopt;
    } else {
        piece.push_back(end);
        if (std::memchr(body, 0, static_cast<std::size_t>(end - body))) return std::nullopt;
    }

    std::vector<Vec3> positions(plain->vertices);
    std::vector<std::uint32_t> indices(std::size_t{3} * plain->faces);
    const OffTarget target{plain->vertices, plain->faces, positions.data(), indices.data()};
    std::vector<std::size_t> stopped(piece.size() - 1, 0);
    std::vector<char> declined(piece.size() - 1, 0);
    auto read = [&](std::size_t k) {
        try {
            const std::optional<std::size_t> read_to = read_piece(piece[k], piece[k + 1], first_line[k], target);
            declined[k] = !read_to;
            stopped[k] = read_to.value_or(0);
        } catch (const NotANumber&) {
            declined[k] = 1;
        }
    };
    if (pool)
        pool->parallel_for(stopped.size(), read);
    else
        read(0);
    if (std::find(declined.begin(), declined.end(), 1) != declined.end()) return std::nullopt;
    if (!pool && stopped[0] < lines) return std::nullopt;  // threads: the lines were counted before
    // The join stays on this thread: shared, its five short loops cost the bunny 4-6 ms more CPU
    // (the pool's spins between them) for no wall time that showed (docs/BENCHMARKS.md).
    return join_identical_vertices(positions, indices);
}

std::optional<PlainOffMesh> read_plain_off(std::string_view text) { return read_plain_off_with_header(text, parse_off_header(text)); }

}  // namespace facet::io_detail
