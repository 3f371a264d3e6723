// facet io: the plain PLY fast path (ply.hpp). Each step mirrors what assimp 5.2 does with a file of
// the accepted form: binary values copied (byte-swapped for big-endian files) and converted to float
// by a cast; ASCII float values read by fast_atoreal_move<float>, double ones by
// fast_atoreal_move<double> and then cast, each element from its own line.
#include "io/ply.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <system_error>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "io/assimp_text.hpp"
#include "io/load_common.hpp"
#include "io/point_cloud.hpp"

namespace facet::io_detail {
namespace {

enum class Format { ascii, little_endian, big_endian };
enum class Type { i8, u8, i16, u16, i32, u32, f32, f64 };

std::optional<Type> type_named(std::string_view name) {
    struct Named {
        const char* name;
        Type type;
    };
    static constexpr Named k_types[] = {{"char", Type::i8},    {"int8", Type::i8},     {"uchar", Type::u8},   {"uint8", Type::u8},
                                        {"short", Type::i16},  {"int16", Type::i16},   {"ushort", Type::u16}, {"uint16", Type::u16},
                                        {"int", Type::i32},    {"int32", Type::i32},   {"uint", Type::u32},   {"uint32", Type::u32},
                                        {"float", Type::f32},  {"float32", Type::f32}, {"double", Type::f64}, {"float64", Type::f64}};
    for (const Named& t : k_types)
        if (name == t.name) return t.type;
    return std::nullopt;
}

std::size_t size_of(Type t) {
    switch (t) {
        case Type::i8: case Type::u8: return 1;
        case Type::i16: case Type::u16: return 2;
        case Type::i32: case Type::u32: case Type::f32: return 4;
        case Type::f64: return 8;
    }
    return 0;
}
bool is_float(Type t) { return t == Type::f32 || t == Type::f64; }
bool is_signed(Type t) { return t == Type::i8 || t == Type::i16 || t == Type::i32; }

constexpr int k_ignored = -1;  // a vertex property assimp does not use; otherwise 0, 1, 2 for x, y, z

struct Property {
    Type type;
    int axis;
};

struct Header {
    Format format = Format::ascii;
    std::uint64_t vertices = 0, faces = 0;
    std::vector<Property> vertex;
    Type count_type = Type::u8, index_type = Type::i32;
    std::size_t body = 0;  // offset of the first byte after end_header's line
};

std::optional<std::uint64_t> count_of(std::string_view word) {
    if (word.empty() || word.size() > 10) return std::nullopt;
    std::uint64_t n = 0;
    for (char c : word) {
        if (c < '0' || c > '9') return std::nullopt;
        n = n * 10 + static_cast<std::uint64_t>(c - '0');
    }
    return n;
}

// The plain form of the header (ply.hpp), as the reader takes it; nullopt for any other header.
std::optional<Header> plain_form(const PlyHeader& header) {
    // end_header's line end: "\n" or "\r\n"
    const std::string& after = header.after_end;
    const std::size_t line_end = !header.end || after.empty() ? 0 : after[0] == '\n' ? 1 : after == "\r\n" ? 2 : 0;
    if (line_end == 0) return std::nullopt;
    Header h;
    enum class Expect { magic, format, vertex_element, vertex_property, face_property, end } expect = Expect::magic;
    bool carriage_return = line_end == 2;
    for (const PlyHeader::Line& l : header.lines) {
        std::string_view line = l.text;
        if (!line.empty() && line.back() == '\r') {
            line.remove_suffix(1);
            carriage_return = true;
        }
        // Without these inside, the words are what splitting at spaces and tabs gives.
        if (line.find_first_of("\r\f\v") != std::string_view::npos) return std::nullopt;
        const std::vector<std::string>& w = l.words;
        // Comments only where assimp reads past them: between the format line and the first element,
        // and after the face list. (It takes the second line as the format, and one inside an
        // element's properties ends or garbles its property list.)
        const bool between = expect == Expect::vertex_element || expect == Expect::end;
        if (between && !w.empty() && (w[0] == "comment" || w[0] == "obj_info")) continue;
        switch (expect) {
            case Expect::magic:
                if (line != "ply") return std::nullopt;
                expect = Expect::format;
                break;
            case Expect::format:
                if (w.size() != 3 || w[0] != "format" || w[2] != "1.0") return std::nullopt;
                if (w[1] == "ascii") h.format = Format::ascii;
                else if (w[1] == "binary_little_endian") h.format = Format::little_endian;
                else if (w[1] == "binary_big_endian") h.format = Format::big_endian;
                else return std::nullopt;
                expect = Expect::vertex_element;
                break;
            case Expect::vertex_element: {
                const std::optional<std::uint64_t> n = w.size() == 3 ? count_of(w[2]) : std::nullopt;
                if (!n || w[0] != "element" || w[1] != "vertex" || *n == 0) return std::nullopt;
                h.vertices = *n;
                expect = Expect::vertex_property;
                break;
            }
            case Expect::vertex_property: {
                if (w.size() == 3 && w[0] == "element" && w[1] == "face") {
                    const std::optional<std::uint64_t> n = count_of(w[2]);
                    if (!n || *n == 0) return std::nullopt;
                    h.faces = *n;
                    expect = Expect::face_property;
                    break;
                }
                const std::optional<Type> type = w.size() == 3 && w[0] == "property" ? type_named(w[1]) : std::nullopt;
                if (!type) return std::nullopt;
                int axis = k_ignored;
                if (w[2] == "x" || w[2] == "y" || w[2] == "z") axis = w[2][0] - 'x';
                else if (w[2] != "confidence" && w[2] != "intensity") return std::nullopt;
                if (axis != k_ignored && !is_float(*type)) return std::nullopt;
                h.vertex.push_back({*type, axis});
                break;
            }
            case Expect::face_property: {
                if (w.size() != 5 || w[0] != "property" || w[1] != "list" || (w[4] != "vertex_indices" && w[4] != "vertex_index"))
                    return std::nullopt;
                const std::optional<Type> count = type_named(w[2]), index = type_named(w[3]);
                if (!count || !index || is_float(*count) || is_float(*index)) return std::nullopt;
                h.count_type = *count;
                h.index_type = *index;
                expect = Expect::end;
                break;
            }
            case Expect::end:
                return std::nullopt;  // anything but a comment between the face list and end_header
        }
    }
    if (expect != Expect::end) return std::nullopt;
    if (h.format != Format::ascii && carriage_return) return std::nullopt;  // assimp's binary body would start at the '\n'
    h.body = *header.end + 10 + line_end;
    for (int axis = 0; axis < 3; ++axis) {
        int seen = 0;
        for (const Property& p : h.vertex) seen += p.axis == axis;
        if (seen != 1) return std::nullopt;
    }
    return h;
}

// ---- binary ----

// The value of type t at p, in the file's byte order, as a double (exact for every type).
double binary_value(const char* p, Type t, bool swap) {
    unsigned char b[8];
    const std::size_t n = size_of(t);
    std::memcpy(b, p, n);
    if (swap)
        for (std::size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
    switch (t) {
        case Type::i8: return static_cast<std::int8_t>(b[0]);
        case Type::u8: return b[0];
        case Type::i16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
        case Type::u16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
        case Type::i32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
        case Type::u32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
        case Type::f32: { float v; std::memcpy(&v, b, 4); return v; }
        case Type::f64: { double v; std::memcpy(&v, b, 8); return v; }
    }
    return 0;
}

bool read_binary(std::string_view bytes, const Header& h, std::vector<Vec3>& positions, std::vector<std::uint32_t>& indices) {
    const bool swap = (h.format == Format::big_endian) == (std::endian::native == std::endian::little);
    std::size_t vertex_size = 0;
    for (const Property& p : h.vertex) vertex_size += size_of(p.type);
    const std::size_t face_size = size_of(h.count_type) + 3 * size_of(h.index_type);
    if (h.body + h.vertices * vertex_size + h.faces * face_size != bytes.size()) return false;
    positions.resize(h.vertices);
    const char* p = bytes.data() + h.body;
    for (Vec3& v : positions) {
        for (const Property& prop : h.vertex) {
            if (prop.axis != k_ignored) {
                // float as stored; double cast to float, as assimp converts it
                const double value = binary_value(p, prop.type, swap);
                v[static_cast<std::size_t>(prop.axis)] = static_cast<float>(value);
                if (!std::isfinite(v[static_cast<std::size_t>(prop.axis)])) return false;
            }
            p += size_of(prop.type);
        }
    }
    indices.resize(3 * h.faces);
    for (std::size_t f = 0; f < h.faces; ++f) {
        if (binary_value(p, h.count_type, swap) != 3) return false;  // polygons: assimp triangulates them
        p += size_of(h.count_type);
        for (std::size_t k = 0; k < 3; ++k, p += size_of(h.index_type)) {
            const double index = binary_value(p, h.index_type, swap);
            if (index < 0 || index >= static_cast<double>(h.vertices)) return false;
            indices[3 * f + k] = static_cast<std::uint32_t>(index);
        }
    }
    return true;
}

// ---- ASCII ----

// An integer of type t at c, as assimp's strtol10/strtoul10 reads it: an optional '-' (signed types),
// then digits; nullptr when there is no digit.
const char* read_integer(const char* c, Type t, std::int64_t& out) {
    bool negative = false;
    if (is_signed(t) && *c == '-') negative = true, ++c;
    if (*c < '0' || *c > '9') return nullptr;
    std::int64_t v = 0;
    for (; *c >= '0' && *c <= '9'; ++c)
        if ((v = v * 10 + (*c - '0')) > (std::int64_t{1} << 32)) return nullptr;  // beyond every type: leave it to assimp
    out = negative ? -v : v;
    return c;
}

// One value of type t at c (after spaces): as a float for x, y and z. Returns where it ends, which
// must be a space or the line's end, or nullptr.
const char* read_ascii_value(const char* c, Type t, float& value) {
    c = skip_spaces(c);
    if (is_line_end(*c) || *c == '\0') return nullptr;  // assimp would take the value from the next line
    if (t == Type::f32) {
        c = read_float(c, value);
    } else if (t == Type::f64) {
        double d;
        c = Assimp::fast_atoreal_move<double, NotANumber>(c, d);
        value = static_cast<float>(d);
    } else {
        std::int64_t ignored;
        if (!(c = read_integer(c, t, ignored))) return nullptr;
    }
    return is_space(*c) || *c == '\r' || *c == '\n' ? c : nullptr;
}

// The end of the line at c, which holds nothing more but spaces: where the next line starts, or nullptr.
const char* next_line(const char* c) {
    c = skip_spaces(c);
    if (*c == '\r') ++c;
    return *c == '\n' ? c + 1 : nullptr;
}

bool read_ascii(std::string_view bytes, const Header& h, std::vector<Vec3>& positions, std::vector<std::uint32_t>& indices) {
    // A vertex line takes at least 6 bytes ("0 0 0\n"), a face line 8: more would be a damaged header.
    if (h.vertices * 2 * h.vertex.size() + h.faces * 8 > bytes.size()) return false;
    positions.resize(h.vertices);
    indices.resize(3 * h.faces);
    const char* c = bytes.data() + h.body;
    try {
        for (Vec3& v : positions) {
            for (const Property& prop : h.vertex) {
                float value = 0;
                if (!(c = read_ascii_value(c, prop.type, value))) return false;
                if (prop.axis != k_ignored) {
                    if (!std::isfinite(value)) return false;
                    v[static_cast<std::size_t>(prop.axis)] = value;
                }
            }
            if (!(c = next_line(c))) return false;
        }
    } catch (const NotANumber&) {
        return false;
    }
    for (std::size_t f = 0; f < h.faces; ++f) {
        std::int64_t count = 0;
        if (!(c = read_integer(skip_spaces(c), h.count_type, count)) || count != 3) return false;
        for (std::size_t k = 0; k < 3; ++k) {
            std::int64_t index = 0;
            if (!is_space(*c) || !(c = read_integer(skip_spaces(c), h.index_type, index))) return false;
            if (index < 0 || static_cast<std::uint64_t>(index) >= h.vertices) return false;
            indices[3 * f + k] = static_cast<std::uint32_t>(index);
        }
        if (!(c = next_line(c))) return false;
    }
    while (is_space(*c) || *c == '\r' || *c == '\n') ++c;
    return *c == '\0' && c == bytes.data() + bytes.size();
}

}  // namespace

std::optional<JoinedMesh> read_plain_ply_with_header(std::string_view bytes, const PlyHeader& header) {
    const std::optional<Header> h = plain_form(header);
    if (!h || h->body > bytes.size() || h->vertices > 0xFFFFFFFFu || h->faces > 0xFFFFFFFFu / 3) return std::nullopt;
    std::vector<Vec3> positions;
    std::vector<std::uint32_t> indices;
    const bool read = h->format == Format::ascii ? read_ascii(bytes, *h, positions, indices)
                                                 : read_binary(bytes, *h, positions, indices);
    if (!read) return std::nullopt;
    return join_identical_vertices(positions, indices);
}

namespace {

// A point cloud's header (is_ply_point_cloud): the vertex properties, and which is which.
struct CloudForm {
    Format format = Format::ascii;
    std::uint64_t vertices = 0;
    std::vector<Type> types;
    int position[3] = {-1, -1, -1}, normal[3] = {-1, -1, -1}, colour[4] = {-1, -1, -1, -1};
    std::size_t body = 0;  // where the vertices start
};

std::optional<CloudForm> cloud_form(const PlyHeader& header) {
    if (!header.magic || !header.end || header.lines.empty() || header.after_end.empty()) return std::nullopt;
    CloudForm f;
    int element = -1;  // 0: vertex, 1: an empty other element
    static constexpr const char* k_names[] = {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue", "alpha"};
    for (const PlyHeader::Line& line : header.lines) {
        const std::vector<std::string>& w = line.words;
        if (w.empty() || w[0] == "comment" || w[0] == "obj_info" || w[0] == "ply" || w[0] == "PLY") continue;
        if (w[0] == "format" && w.size() == 3) {
            f.format = w[1] == "ascii" ? Format::ascii : w[1] == "binary_little_endian" ? Format::little_endian
                                                                                         : Format::big_endian;
            if (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian") return std::nullopt;
        } else if (w[0] == "element" && w.size() == 3) {
            const std::optional<std::uint64_t> n = parse_count(w[2]);
            if (!n) return std::nullopt;
            if (element < 0 && w[1] == "vertex") f.vertices = *n, element = 0;
            else if (element >= 0 && *n == 0) element = 1;
            else return std::nullopt;
        } else if (w[0] == "property" && element == 1) {
            continue;  // of an empty element
        } else if (w[0] == "property" && element == 0 && w.size() == 3) {
            const std::optional<Type> t = type_named(w[1]);
            if (!t) return std::nullopt;
            const int index = static_cast<int>(f.types.size());
            f.types.push_back(*t);
            for (int k = 0; k < 10; ++k)
                if (w[2] == k_names[k]) (k < 3 ? f.position[k] : k < 6 ? f.normal[k - 3] : f.colour[k - 6]) = index;
        } else {
            return std::nullopt;
        }
    }
    if (element < 0 || f.position[0] < 0 || f.position[1] < 0 || f.position[2] < 0) return std::nullopt;
    f.body = *header.end + 10 + (header.after_end[0] == '\r' ? 2 : 1);
    return f;
}

// A colour channel's value in [0, 1]: an integer over its type's largest value, a float as it is.
float channel(double v, Type t) {
    double scale = 1;
    switch (t) {
        case Type::u8: case Type::i8: scale = 255; break;
        case Type::u16: case Type::i16: scale = 65535; break;
        case Type::u32: case Type::i32: scale = 4294967295.0; break;
        default: break;
    }
    const double c = v / scale;
    return std::isfinite(c) ? static_cast<float>(std::clamp(c, 0.0, 1.0)) : 1.0f;
}

}  // namespace

bool is_ply_point_cloud(const PlyHeader& header) { return cloud_form(header).has_value(); }

Result<LoadedModel> read_ply_point_cloud(const std::string& path, std::string_view bytes, const PlyHeader& header,
                                         const LoadOptions& options) {
    const std::optional<CloudForm> f = cloud_form(header);
    if (!f) return fail(ErrorCode::bad_format, path, "is not a PLY point cloud");
    if (f->vertices > options.max_triangles)
        return fail(ErrorCode::limit_exceeded, path,
                    "has " + std::to_string(f->vertices) + " points, more than the limit of " +
                        std::to_string(options.max_triangles) + " (--max-triangles counts points too)");
    const std::size_t n = static_cast<std::size_t>(f->vertices), props = f->types.size();
    std::size_t stride = 0;
    for (Type t : f->types) stride += size_of(t);
    // Checked before anything is allocated: binary vertices take their size, ASCII ones two bytes a value.
    const std::size_t available = bytes.size() > f->body ? bytes.size() - f->body : 0;
    const std::size_t least = f->format == Format::ascii ? 2 * props : stride;
    if (n > available / least)
        return fail(ErrorCode::bad_format, path,
                    "PLY header claims " + std::to_string(n) + " vertices, more than the " + std::to_string(available) +
                        " bytes of data can hold (truncated or corrupt)");
    const bool normals = f->normal[0] >= 0 && f->normal[1] >= 0 && f->normal[2] >= 0;
    const bool colours = f->colour[0] >= 0 && f->colour[1] >= 0 && f->colour[2] >= 0;
    PointCloud cloud;
    cloud.positions.resize(n);
    if (normals) cloud.normals.resize(n);
    if (colours) cloud.colours.assign(n, Vec4{1, 1, 1, 1});
    std::vector<double> value(props);
    const bool swap = (f->format == Format::big_endian) == (std::endian::native == std::endian::little);
    const char* c = bytes.data() + f->body;
    const char* const end = bytes.data() + bytes.size();
    for (std::size_t i = 0; i < n; ++i) {
        if (f->format == Format::ascii) {
            for (std::size_t k = 0; k < props; ++k) {
                while (c < end && (is_space(*c) || is_line_end(*c))) ++c;
                const auto [next, ec] = std::from_chars(c + (c < end && *c == '+'), end, value[k]);
                if (ec != std::errc())
                    return fail(ErrorCode::bad_format, path, "PLY vertex " + std::to_string(i) + " has a value that is not a number");
                c = next;
            }
        } else {
            for (std::size_t k = 0; k < props; ++k) {
                value[k] = binary_value(c, f->types[k], swap);
                c += size_of(f->types[k]);
            }
        }
        for (int a = 0; a < 3; ++a) {
            cloud.positions[i][static_cast<std::size_t>(a)] = static_cast<float>(value[static_cast<std::size_t>(f->position[a])]);
            if (normals) cloud.normals[i][static_cast<std::size_t>(a)] = static_cast<float>(value[static_cast<std::size_t>(f->normal[a])]);
        }
        for (int a = 0; colours && a < 4; ++a)
            if (f->colour[a] >= 0) {
                const auto k = static_cast<std::size_t>(f->colour[a]);
                cloud.colours[i][static_cast<std::size_t>(a)] = channel(value[k], f->types[k]);
            }
    }
    return point_cloud_model(path, std::move(cloud), options);
}

std::optional<JoinedMesh> read_plain_ply(std::string_view bytes) { return read_plain_ply_with_header(bytes, parse_ply_header(bytes)); }

PlyHeader parse_ply_header(std::string_view head) {
    PlyHeader h;
    h.bytes_read = head.size();
    h.magic = head.substr(0, 3) == "ply" || head.substr(0, 3) == "PLY";
    // end_header must start a line: assimp 5.2.5 loops forever or reads past its buffer when the
    // only "end_header" is in the middle of one (load_model_fuzzer findings).
    const std::size_t end = head.find("\nend_header");
    if (!h.magic || end == std::string_view::npos) return h;
    h.end = end + 1;
    h.after_end = std::string(head.substr(*h.end + 10, 2));
    for (std::size_t at = 0; at < *h.end;) {
        const std::size_t newline = head.find('\n', at);
        PlyHeader::Line line{std::string(head.substr(at, newline - at)), {}};
        at = newline + 1;
        line.words = words_of(line.text);
        h.lines.push_back(std::move(line));
    }
    return h;
}

Status check_ply_header(const std::string& path, const PlyHeader& header, std::uint64_t size, const LoadOptions& options) {
    if (!header.magic) return Ok{};  // not PLY: assimp says what it is
    if (!header.end)
        return fail(ErrorCode::bad_format, path,
                    "PLY header has no end_header line in its first " + std::to_string(header.bytes_read) + " bytes");
    // assimp's reader runs past the end of the buffer when end_header is not followed by a line end
    // ("end_header0", "end_header\v": a load_model_fuzzer finding, a crash in assimp 5.2.5).
    const std::string& after = header.after_end;
    const bool cut = header.bytes_read < size && after.size() < 2;  // the rest is past the bytes read
    if (!cut && (after.empty() || (after[0] != '\n' && after != "\r\n")))
        return fail(ErrorCode::bad_format, path, "PLY header's end_header is not followed by a line end (corrupt header)");
    bool ascii = true;
    struct Element {
        std::string name;
        std::uint64_t count = 0, min_bytes = 0;  // the fewest bytes one element can take
    };
    std::vector<Element> elements;
    bool comment_in_element = false;  // a comment since the last element line
    for (const PlyHeader::Line& line : header.lines) {
        const std::vector<std::string>& w = line.words;
        auto word = [&](std::size_t i) { return i < w.size() ? w[i] : std::string(); };
        if ((word(0) == "comment" || word(0) == "obj_info") && !elements.empty()) comment_in_element = true;
        // assimp 5.2.5 ends an element's property list at a comment and reads the rest wrongly: an
        // error, garbled positions, or, in a binary file, a minute of work on a 300-byte header
        // (found comparing facet's PLY reader with assimp on generated headers).
        if (word(0) == "property" && comment_in_element)
            return fail(ErrorCode::bad_format, path,
                        "PLY header has a comment among the properties of element '" + elements.back().name +
                            "', which assimp cannot read");
        if (word(0) == "format") {
            ascii = word(1) == "ascii";
        } else if (word(0) == "element") {
            Element e;
            e.name = word(1);
            const auto n = parse_count(word(2));
            if (!n) return fail(ErrorCode::bad_format, path, "PLY element '" + e.name + "' has an invalid count '" + word(2) + "'");
            e.count = *n;
            elements.push_back(e);
            comment_in_element = false;
        } else if (word(0) == "property" && !elements.empty()) {
            // assimp 5.2.5 loops forever on a property of a type it does not know ("uint4": a
            // load_model_fuzzer finding), so every type must be one of PLY's. ASCII needs a
            // character and a separator per value (a list at least its count), binary the sizes of
            // its scalars (a list at least its count).
            std::string type = word(1);
            if (type == "list") {
                type = word(2);  // the count's type (a list may be empty); then the items' type
                if (!type_named(word(3)))
                    return fail(ErrorCode::bad_format, path, "PLY property list has an unknown item type '" + word(3) + "'");
            }
            const std::optional<Type> t = type_named(type);
            if (!t) return fail(ErrorCode::bad_format, path, "PLY property has an unknown type '" + type + "'");
            elements.back().min_bytes += ascii ? 2 : size_of(*t);
        }
    }
    const std::uint64_t data = size - std::min<std::uint64_t>(size, *header.end + 10);
    std::uint64_t needed = 0;
    for (const Element& e : elements) {
        if (e.min_bytes == 0) continue;
        if (e.count > data / e.min_bytes || needed + e.count * e.min_bytes > data)
            return fail(ErrorCode::bad_format, path,
                        "PLY header claims " + std::to_string(e.count) + " '" + e.name + "' elements, more than the " +
                            std::to_string(data) + " bytes of data can hold (truncated or corrupt)");
        needed += e.count * e.min_bytes;
        if (e.name == "face" && e.count > options.max_triangles) return too_many_triangles(path, e.count, options);
    }
    return Ok{};
}

}  // namespace facet::io_detail
