// facet io: the STL fast path (stl.hpp). Each step mirrors what assimp 5.2 does with a file of the
// accepted form: the binary layout as its LoadBinaryFile reads it; for ASCII, its LoadASCIIFile,
// which skips spaces and line ends between tokens, reads "facet normal" and "vertex" numbers with
// SkipSpaces and fast_atoreal_move on the keyword's line, and skips any other token whole.
#include "io/stl.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "io/assimp_text.hpp"
#include "io/load_common.hpp"

namespace facet::io_detail {
namespace {

constexpr std::size_t k_header_bytes = 80;
constexpr std::size_t k_facet_bytes = 50;  // normal, three vertices (12 floats), 16-bit attribute
constexpr std::uint16_t k_colour_bit = 0x8000;

// The facet count in a binary header (bytes 80 to 83), if `head` has it.
std::optional<std::uint64_t> announced_facets(std::string_view head) {
    if (head.size() < k_header_bytes + 4) return std::nullopt;
    std::uint32_t count;
    std::memcpy(&count, head.data() + k_header_bytes, sizeof(count));  // little-endian, as facet's platforms
    return count;
}

// assimp's IsBinarySTL: the size is exactly what the facet count in the header needs.
bool is_binary(std::optional<std::uint64_t> facets, std::uint64_t size) {
    return facets && k_header_bytes + 4 + *facets * k_facet_bytes == size;
}

bool is_binary_size(std::string_view bytes, std::uint64_t& facets) {
    const std::optional<std::uint64_t> n = announced_facets(bytes);
    facets = n.value_or(0);
    return is_binary(n, bytes.size());
}

// The facets' corners as triangles 0, 1, 2, ... over them, then joined.
std::optional<JoinedMesh> join_facets(const std::vector<Vec3>& corners) {
    std::vector<std::uint32_t> indices(corners.size());
    for (std::size_t i = 0; i < indices.size(); ++i) indices[i] = static_cast<std::uint32_t>(i);
    return join_identical_vertices(corners, indices);
}

// ASCII: the separators between tokens (a form feed, which assimp treats as a line end in some places
// and not in others, is declined).
bool is_separator(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

const char* skip_separators(const char* c) {
    while (is_separator(*c)) ++c;
    return c;
}

// The keyword at c, followed by a separator: where it ends, or nullptr.
const char* expect(const char* c, std::string_view keyword) {
    if (std::strncmp(c, keyword.data(), keyword.size()) != 0 || !is_separator(c[keyword.size()])) return nullptr;
    return c + keyword.size();
}

// "keyword x y z" on one line, as assimp reads a normal or a vertex: one separator after the keyword
// (a space or tab here, since the numbers share the line), spaces, and three numbers separated by
// spaces, each ending at a separator. Returns where the last number ends, or nullptr.
const char* read_triple(const char* c, std::string_view keyword, float (&out)[3]) {
    c = expect(c, keyword);
    if (!c || !is_space(*c)) return nullptr;
    c = skip_spaces(c + 1);
    for (int k = 0; k < 3; ++k) {
        if (k > 0) {
            if (!is_space(*c)) return nullptr;
            c = skip_spaces(c);
        }
        const char* start = c;
        c = read_float(c, out[k]);
        if (c == start || !is_separator(*c)) return nullptr;
    }
    return c;
}

// One facet from "facet" on: its three corners appended to `corners`. Returns where it ends, or nullptr.
const char* read_facet(const char* c, std::vector<Vec3>& corners) {
    float v[3];
    c = expect(c, "facet");
    if (!c) return nullptr;
    c = skip_spaces(c);  // "facet normal" on one line, as assimp looks for "normal" after SkipSpaces
    if (!(c = read_triple(c, "normal", v))) return nullptr;
    for (const char* word : {"outer", "loop"})
        if (!(c = expect(skip_separators(c), word))) return nullptr;
    for (int k = 0; k < 3; ++k) {
        if (!(c = read_triple(skip_separators(c), "vertex", v))) return nullptr;
        for (float x : v)
            if (!std::isfinite(x)) return nullptr;
        corners.push_back({v[0], v[1], v[2]});
    }
    for (const char* word : {"endloop", "endfacet"})
        if (!(c = expect(skip_separators(c), word))) return nullptr;
    return c;
}

}  // namespace

std::optional<JoinedMesh> read_binary_stl(std::string_view bytes) {
    std::uint64_t facets = 0;
    if (!is_binary_size(bytes, facets) || facets == 0 || facets > 0xFFFFFFFFu / 3) return std::nullopt;
    if (bytes.substr(0, k_header_bytes).find("COLOR=") != std::string_view::npos) return std::nullopt;
    std::vector<Vec3> corners(3 * facets);
    const char* facet = bytes.data() + k_header_bytes + 4;
    for (std::size_t f = 0; f < facets; ++f, facet += k_facet_bytes) {
        float v[9];
        std::memcpy(v, facet + 12, sizeof(v));  // after the facet normal, which the assimp path drops
        std::uint16_t attribute;
        std::memcpy(&attribute, facet + 48, sizeof(attribute));
        if (attribute & k_colour_bit) return std::nullopt;
        for (float c : v)
            if (!std::isfinite(c)) return std::nullopt;
        for (std::size_t k = 0; k < 3; ++k) corners[3 * f + k] = {v[3 * k], v[3 * k + 1], v[3 * k + 2]};
    }
    return join_facets(corners);
}

std::optional<JoinedMesh> read_ascii_stl(std::string_view bytes) {
    std::uint64_t facets = 0;
    if (is_binary_size(bytes, facets)) return std::nullopt;  // assimp reads it as binary
    if (bytes.find('\0') != std::string_view::npos || bytes.find('\f') != std::string_view::npos) return std::nullopt;
    const char* c = expect(skip_spaces(bytes.data()), "solid");  // assimp skips no line ends before it
    if (!c) return std::nullopt;
    // The name: assimp takes the first word after "solid" (up to 1024 characters) and skips the
    // rest of the line word by word, as unknown tokens.
    c = skip_spaces(c);
    const char* name = c;
    while (!is_separator(*c) && *c != '\0') ++c;
    if (c - name >= 1000) return std::nullopt;
    c = skip_spaces(c);
    if (*c != '\r' && *c != '\n') return std::nullopt;  // nothing else on the solid's line
    std::vector<Vec3> corners;
    corners.reserve(bytes.size() / 64);  // about 250 bytes per facet in the usual layout: at most one reallocation
    try {
        for (c = skip_separators(c); std::strncmp(c, "endsolid", 8) != 0; c = skip_separators(c))
            if (!(c = read_facet(c, corners))) return std::nullopt;
    } catch (const NotANumber&) {
        return std::nullopt;
    }
    // "endsolid", the rest of its line, then nothing but separators.
    c += 8;
    while (*c != '\0' && !is_line_end(*c)) ++c;
    if (*skip_separators(c) != '\0' || corners.empty()) return std::nullopt;
    return join_facets(corners);
}

std::optional<JoinedMesh> read_stl_with_header(std::string_view bytes, const StlHeader& header) {
    return header.binary ? read_binary_stl(bytes) : read_ascii_stl(bytes);
}

std::optional<JoinedMesh> read_stl(std::string_view bytes) { return read_stl_with_header(bytes, parse_stl_header(bytes, bytes.size())); }

StlHeader parse_stl_header(std::string_view head, std::uint64_t size) {
    StlHeader h;
    const std::optional<std::uint64_t> facets = announced_facets(head);
    h.facets = facets.value_or(0);
    h.binary = is_binary(facets, size);
    // Binary files often start with "solid" too, so a cut binary file is recognised by its zero bytes.
    const std::size_t first = head.find_first_not_of(" \t\r\n");
    h.ascii = !h.binary && head.find('\0') == std::string_view::npos && first != std::string_view::npos &&
              lower(std::string(head.substr(first, 5))) == "solid";
    return h;
}

Status check_stl_header(const std::string& path, const StlHeader& header, std::uint64_t size, const LoadOptions& options) {
    if (header.binary)
        return header.facets > options.max_triangles ? Status{too_many_triangles(path, header.facets, options)} : Status{Ok{}};
    if (header.ascii) return Ok{};  // parsed incrementally
    if (size < k_header_bytes + 4) return fail(ErrorCode::bad_format, path, "is too short for a binary STL file and is not ASCII STL");
    return fail(ErrorCode::bad_format, path,
                "binary STL header claims " + std::to_string(header.facets) + " triangles (" +
                    std::to_string(k_header_bytes + 4 + k_facet_bytes * header.facets) + " bytes), which does not match the file's " +
                    std::to_string(size) + " bytes (cut short, damaged or not STL)");
}

}  // namespace facet::io_detail
