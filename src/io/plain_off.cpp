// facet io: the plain OFF fast path (plain_off.hpp). Every step mirrors what assimp 5.2 does with
// a file of the accepted form, so that the two paths give the same mesh bit for bit:
//  - lines: assimp's OFF reader takes the text line by line, skipping empty lines (a line of
//    spaces is not empty), into a 4096-byte buffer that would cut longer lines (refused here);
//  - the header: NextToken between its words (spaces, line ends and '#' lines skipped), the
//    keyword ("OFF", or "COFF" for colours), the three counts; the body begins at the next word;
//  - vertices: SkipSpaces then fast_atoreal_move<float> three times, for COFF four more (a '#'
//    after one leaves the rest at 0, 0, 1), the rest of the line ignored;
//  - faces: SkipSpaces then strtoul10 (read_uint) for the count and each index, the rest ignored (a missing
//    index reads as 0 in both);
//  - Triangulate, for a mesh with a polygon (io/assimp_triangulate.hpp): quads split at their
//    concave corner, larger polygons cut into ears, every triangle through the NGONEncoder;
//  - JoinIdenticalVertices and facet's conversion: join_identical_vertices (io/joined_mesh.hpp),
//    which leaves files with positions only assimp's tolerance would join to assimp; colours are
//    not compared, a joined vertex keeps its first one's (clamped to [0, 1] by the conversion).
#include "io/plain_off.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>

#include "exec/fresh_pages.hpp"
#include "facet/detail/thread_pool.hpp"
#include "io/assimp_text.hpp"
#include "io/assimp_triangulate.hpp"
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

// While one thread joins the vertices, another faults in up to this much of the heap's free top,
// where the normals and the first frame then allocate (the bunny's take ~20 MB): the join ends it.
constexpr std::size_t k_populate_bytes = 32 << 20;

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
    std::array<float, 4>* colours;  // COFF: each vertex's colour as the file gives it, else null
    std::uint32_t* indices;         // three per face; a polygon's are in its OffPolygon instead
    const char* readable_end;       // the text's end: numbers are read 8 digits at a time before it
};

// A face of 4 to 9 corners, triangulated once every face is read.
struct OffPolygon {
    std::uint32_t face, corners;
    std::uint32_t index[9];
};

// Reads the lines of the piece [begin, end), the first of them line number `line` of the body, a
// line a step; where assimp's reader would read the file differently it fails. A line's reader
// stops at or before its end (numbers and spaces never take a line-end character), and the line is
// skipped from there.
// Faces assimp drops do not count: the reading goes on until it has face_count others. They are
// counted in `skipped` if `may_drop`, or (threads read pieces whose lines are numbered before) fail.
class PieceReader {
public:
    PieceReader(const char* begin, const char* end, std::size_t line, const OffTarget& to, std::vector<OffPolygon>& polygons,
                bool may_drop)
        : c_(begin), end_(end), line_(line), last_(std::size_t{to.vertex_count} + to.face_count), to_(to),
          polygons_(polygons), may_drop_(may_drop) {}

    // Reads the next line; false once the piece or the lines wanted are done, or failed.
    [[gnu::always_inline]] bool step() {
        if (stopped_) return false;
        while (c_ < end_ && is_line_end(*c_)) ++c_;
        if (line_ >= last_ + skipped_ || c_ >= end_) return stop(false);
        const char* c = c_;
        const char* const start = c;
        if (line_ < to_.vertex_count) {
            Vec3& p = to_.positions[line_];
            for (std::size_t dim = 0; dim < 3; ++dim) {
                c = skip_spaces(c);
                c = read_float(c, p[dim], to_.readable_end);  // throws where assimp's reader fails
                if (!std::isfinite(p[dim])) return stop(true);
            }
            if (to_.colours) {
                std::array<float, 4>& rgba = to_.colours[line_];
                constexpr float cut_off[4] = {0, 0, 0, 1};  // what assimp gives the channels after a '#'
                c = read_float(skip_spaces(c), rgba[0], to_.readable_end);
                for (std::size_t k = 1; k < 4; ++k) {
                    if (*c == '#')
                        rgba[k] = cut_off[k];
                    else
                        c = read_float(skip_spaces(c), rgba[k], to_.readable_end);
                }
            }
        } else {
            const std::size_t face = line_ - to_.vertex_count - skipped_;
            c = skip_spaces(c);
            const std::uint32_t corners = read_uint(c, &c, to_.readable_end);
            if (corners == 1 || corners == 2) return stop(true);  // a point or a line: SortByPType splits the mesh
            // No corners (a comment read as a face, too) or more than 9: assimp drops the face with an error.
            const bool drop = corners == 0 || corners > 9;
            if (drop && !may_drop_) return stop(true);
            skipped_ += drop;
            OffPolygon polygon{static_cast<std::uint32_t>(face), drop ? 0 : corners, {}};
            std::uint32_t* index = polygon.corners == 3 ? to_.indices + 3 * face : polygon.index;
            for (std::size_t k = 0; k < polygon.corners; ++k) {
                c = skip_spaces(c);
                index[k] = read_uint(c, &c, to_.readable_end);
                if (index[k] >= to_.vertex_count) return stop(true);  // assimp clamps it and logs an error
            }
            if (polygon.corners > 3) polygons_.push_back(polygon);
        }
        while (*c != '\0' && !is_line_end(*c)) ++c;
        if (c - start >= k_max_line) return stop(true);
        c_ = c;
        ++line_;
        return true;
    }
    bool failed() const { return failed_; }
    // The number after the last line read, and the faces dropped.
    std::size_t line() const { return line_; }
    std::size_t skipped() const { return skipped_; }

private:
    bool stop(bool failed) {
        stopped_ = true, failed_ = failed;
        return false;
    }
    const char* c_;
    const char* end_;
    std::size_t line_, last_, skipped_ = 0;
    const OffTarget& to_;
    std::vector<OffPolygon>& polygons_;
    bool may_drop_, stopped_ = false, failed_ = false;
};

// Triangulate's faces of a mesh with a polygon: `indices` (three per face, a polygon's unset; the
// polygons of faces past them not used) becomes the triangles, every one through the NGONEncoder.
// False where a polygon has no ear.
bool triangulate(const std::vector<Vec3>& positions, const std::vector<std::vector<OffPolygon>>& polygons,
                 std::vector<std::uint32_t>& indices) {
    const std::size_t faces = indices.size() / 3;
    std::vector<std::uint32_t> triangles;
    std::size_t more = 0;
    for (const std::vector<OffPolygon>& piece : polygons)
        for (const OffPolygon& p : piece) more += p.face < faces ? p.corners - 3 : 0;
    triangles.reserve(indices.size() + 3 * more);
    Triangulator triangulator;
    const auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) { triangles.insert(triangles.end(), {a, b, c}); };
    const auto at = [&](std::uint32_t v) {
        const Vec3& p = positions[v];
        return aiVector3D(p.x, p.y, p.z);
    };
    auto piece = polygons.begin();
    std::size_t next = 0;  // in *piece
    for (std::size_t face = 0; face < faces; ++face) {
        while (piece != polygons.end() && next == piece->size()) ++piece, next = 0;
        const OffPolygon* polygon = piece != polygons.end() && (*piece)[next].face == face ? &(*piece)[next++] : nullptr;
        const std::uint32_t* index = polygon ? polygon->index : &indices[3 * face];
        const auto id = [index](std::uint32_t k) { return index[k]; };
        if (!triangulator.face(polygon ? polygon->corners : 3, id, [&](std::uint32_t k) { return at(index[k]); }, emit))
            return false;
    }
    indices = std::move(triangles);
    return true;
}

// assimp's NextToken: past spaces and line ends, then past each line that begins with '#'.
const char* next_token(const char* c) {
    const auto skip_blank = [](const char* p) {
        while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n') ++p;
        return p;
    };
    for (c = skip_blank(c); *c == '#'; c = skip_blank(c))
        while (*c != '\r' && *c != '\n' && *c != '\0') ++c;
    return c;
}

// A count of the header: 1 to 9 digits, then a space or a line end; nullopt otherwise.
std::optional<std::uint32_t> header_count(const char*& c) {
    std::uint32_t v = 0;
    int digits = 0;
    for (; *c >= '0' && *c <= '9'; ++c, ++digits) v = v * 10 + static_cast<std::uint32_t>(*c - '0');
    if (digits == 0 || digits > 9 || !(is_space(*c) || *c == '\n' || *c == '\r')) return std::nullopt;
    return v;
}

// "OFF" or "COFF", then the vertex, face and edge counts, with spaces, line ends and '#' lines
// between them; the body begins on a line of its own.
std::optional<OffHeader::Plain> parse_plain_header(const char* text) {
    // A byte order mark (assimp converts such a text first) or another encoding: not taken.
    if (static_cast<unsigned char>(text[0]) >= 0x80) return std::nullopt;
    const char* c = next_token(text);
    const bool colours = *c == 'C';
    c += colours;
    if (c[0] != 'O' || c[1] != 'F' || c[2] != 'F' || !(is_space(c[3]) || c[3] == '\n' || c[3] == '\r')) return std::nullopt;
    c += 3;
    std::uint32_t counts[3];
    for (std::uint32_t& n : counts) {
        c = next_token(c);
        const std::optional<std::uint32_t> count = header_count(c);
        if (!count) return std::nullopt;
        n = *count;
    }
    if (counts[0] == 0 || counts[1] == 0) return std::nullopt;
    const char* const counts_end = c;
    c = next_token(c);
    if (*c == '\0' || *c == '\f') return std::nullopt;  // the end, or a line end NextToken does not skip
    // The reader begins at the line end before the body's first word (spaces alone between them).
    const char* line = c;
    while (line > counts_end && is_space(line[-1])) --line;
    if (line <= counts_end || (line[-1] != '\n' && line[-1] != '\r')) return std::nullopt;
    return OffHeader::Plain{counts[0], counts[1], static_cast<std::size_t>(line - 1 - text), colours};
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
    std::vector<std::array<float, 4>> colours(plain->colours ? plain->vertices : 0);
    std::vector<std::uint32_t> indices(std::size_t{3} * plain->faces);
    const OffTarget target{plain->vertices, plain->faces, positions.data(), plain->colours ? colours.data() : nullptr,
                           indices.data(), end};
    std::vector<std::size_t> stopped(piece.size() - 1, 0);
    std::vector<char> declined(piece.size() - 1, 0);
    std::vector<std::vector<OffPolygon>> polygons(piece.size() - 1);  // per piece, in face order
    std::size_t dropped = 0;
    // A thread reads two pieces at once, a line of each in turn: a line's numbers are read one
    // after another (where each ends is where the next begins), and the two pieces' chains overlap.
    auto read_pair = [&](std::size_t pair) {
        const std::size_t k = 2 * pair;
        try {
            PieceReader a(piece[k], piece[k + 1], first_line[k], target, polygons[k], !pool);
            if (k + 1 < stopped.size()) {
                PieceReader b(piece[k + 1], piece[k + 2], first_line[k + 1], target, polygons[k + 1], false);
                for (bool more = true; more;) {  // both stepped each time
                    const bool more_a = a.step(), more_b = b.step();
                    more = more_a && more_b;
                }
                while (b.step()) {
                }
                declined[k + 1] = b.failed(), stopped[k + 1] = b.line();
            }
            while (a.step()) {
            }
            declined[k] = a.failed(), stopped[k] = a.line();
            if (!pool) dropped = a.skipped();
        } catch (const NotANumber&) {
            declined[k] = 1;
        }
    };
    if (pool)
        pool->parallel_for((stopped.size() + 1) / 2, read_pair);
    else
        read_pair(0);
    if (std::find(declined.begin(), declined.end(), 1) != declined.end()) return std::nullopt;
    // Threads: the lines were counted before. One thread: assimp's mesh has face_count faces less
    // the dropped ones: the first of those read, or, where the lines ran out after a drop, all of
    // them (with an error); a face missing otherwise would fail its validation.
    bool faces_missing = false;
    if (!pool) {
        if (stopped[0] < lines + dropped) {
            faces_missing = dropped > 0 && stopped[0] == lines;
            if (!faces_missing) return std::nullopt;
        }
        indices.resize(3 * (std::size_t{plain->faces} - dropped));
    }
    const auto kept = [faces = indices.size() / 3](const std::vector<OffPolygon>& p) { return !p.empty() && p.front().face < faces; };
    if (std::any_of(polygons.begin(), polygons.end(), kept))
        if (!triangulate(positions, polygons, indices)) return std::nullopt;
    // The join stays on one thread: shared, its five short loops cost the bunny 4-6 ms more CPU
    // (the pool's spins between them) for no wall time that showed (docs/BENCHMARKS.md). The other
    // thread meanwhile faults in the memory the next stages will take; it stops when the join is
    // done (a thread that takes the task only then returns at once).
    std::optional<PlainOffMesh> mesh;
    if (pool) {
        std::atomic<bool> joined{false};
        pool->parallel_for(2, [&](std::size_t task) {
            if (task == 0) {
                mesh = join_identical_vertices(positions, indices);
                joined.store(true, std::memory_order_relaxed);
            } else {
                detail::populate_heap_top(k_populate_bytes, [&] { return !joined.load(std::memory_order_relaxed); });
            }
        });
    } else {
        mesh = join_identical_vertices(positions, indices);
    }
    if (mesh) mesh->dropped_faces = dropped, mesh->faces_missing = faces_missing;
    if (mesh && plain->colours) {
        mesh->colours.reserve(mesh->source.size());
        for (const std::uint32_t v : mesh->source) {
            const std::array<float, 4>& c = colours[v];
            mesh->colours.push_back(unit_colour(c[0], c[1], c[2], c[3]));
        }
    }
    return mesh;
}

std::optional<PlainOffMesh> read_plain_off(std::string_view text) { return read_plain_off_with_header(text, parse_off_header(text)); }

}  // namespace facet::io_detail
