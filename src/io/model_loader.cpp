// facet io: model files into a Scene, through assimp. The path of a file:
//   1. checks facet makes itself before assimp sees the file: it exists, is a regular readable file,
//      is within max_file_bytes and not empty, has an extension assimp knows, and (STL, PLY, OFF,
//      GLB) its header does not claim more elements than the file's size can hold or more
//      triangles than max_triangles. assimp trusts such counts and reserves memory for them: an
//      OFF header claiming 3.5e11 vertices costs it 40 s and 16 GB of address space.
//   2. assimp reads and post-processes (triangulate, split by primitive type, join identical
//      vertices, validate); its failures become one bad_format Error, errors it only logs while
//      working around bad data become a warning (an out-of-range index: an Error), and its
//      internal assertions throw instead of aborting the process (see aiAssertViolation below).
//   3. the aiScene is converted: the node hierarchy is walked, each mesh reference becomes a
//      SceneObject (mesh in its own space, the accumulated node transform as `model`); triangles
//      with non-finite or out-of-range vertices are dropped with a warning; missing normals are
//      computed with the crease angle; materials give base colour, opacity, alpha mode, sidedness
//      and the base-colour texture (embedded or a file next to the model, found leniently).
// Plain triangle OFF files (io/plain_off.hpp), plain STL files (io/stl.hpp) and PLY files with
// positions only (io/ply.hpp) skip steps 2 and 3: a dedicated reader gives the same Scene several times faster; whatever it does not take
// goes through assimp as above.
#include "facet/model.hpp"

#include <assimp/DefaultLogger.hpp>
#include <assimp/GltfMaterial.h>
#include <assimp/Importer.hpp>
#include <assimp/Logger.hpp>
#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <new>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_set>
#include <utility>
#include <vector>

#include "facet/mesh.hpp"
#include "io/load_paths.hpp"
#include "io/plain_off.hpp"
#include "io/ply.hpp"
#include "io/stl.hpp"

// assimp's internal consistency checks (ai_assert) are compiled into Debian's libassimp and call
// std::abort() when they fail; malformed input reaches some of them (a truncated ASCII PLY trips
// one in the triangulation step). libassimp calls this function through its PLT and it is exported,
// so the definition in the executable takes precedence. Throwing instead of aborting lets assimp's
// own exception handling (around every importer and post-processing step) turn it into a failed
// import with this message.
namespace Assimp {
void aiAssertViolation(const char* expression, const char* file, int line) {
    throw std::runtime_error(std::string("assimp internal check failed: ") + expression + " (" + file + ":" +
                             std::to_string(line) + ")");
}
}  // namespace Assimp

namespace facet {
namespace {

// assimp's messages sometimes quote the text they failed on, up to the whole file; keep the start
// and replace control characters so that one bad file cannot flood or garble a terminal or a log.
std::string readable_reason(const std::string& why) {
    constexpr std::size_t k_max = 200;
    std::string out;
    for (char c : why.substr(0, k_max)) out += (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) ? ' ' : c;
    if (why.size() > k_max) out += "...";
    return out;
}


namespace fs = std::filesystem;

Error fail(ErrorCode code, const std::string& path, const std::string& problem) {
    return Error{code, path + ": " + problem};
}

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}


// ---------------------------------------------------------------------------------------------
// 1. Checks before assimp

constexpr std::size_t k_header_bytes = 64 * 1024;  // enough for any sane PLY/OFF/STL/GLB header

// The file is a regular, readable, non-empty file within the size limit. Returns its size and
// its first bytes (for the header checks).
Status check_file(const std::string& path, const LoadOptions& options, std::uintmax_t& size, std::string& head) {
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (ec || !fs::exists(st)) return fail(ErrorCode::io, path, "no such file");
    if (fs::is_directory(st)) return fail(ErrorCode::io, path, "is a directory, not a model file");
    if (!fs::is_regular_file(st)) return fail(ErrorCode::io, path, "is not a regular file");
    size = fs::file_size(path, ec);
    if (ec) return fail(ErrorCode::io, path, "cannot read the file size (" + ec.message() + ")");
    if (size > options.max_file_bytes)
        return fail(ErrorCode::limit_exceeded, path,
                    "is " + std::to_string(size) + " bytes, more than the limit of " +
                        std::to_string(options.max_file_bytes) + " bytes");
    if (size == 0) return fail(ErrorCode::bad_format, path, "is empty");
    std::ifstream in(path, std::ios::binary);
    if (!in) return fail(ErrorCode::io, path, std::string("cannot be opened for reading (") + std::strerror(errno) + ")");
    head.resize(static_cast<std::size_t>(std::min<std::uintmax_t>(size, k_header_bytes)));
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    if (in.gcount() != static_cast<std::streamsize>(head.size()))
        return fail(ErrorCode::io, path, "cannot be read (" + std::string(std::strerror(errno)) + ")");
    return Ok{};
}

std::uint32_t read_le32(const std::string& bytes, std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = v << 8 | static_cast<unsigned char>(bytes[at + static_cast<std::size_t>(i)]);
    return v;
}

// Parses a whole non-negative decimal count; nullopt if it is not one (or beyond 2^63).
std::optional<std::uint64_t> parse_count(const std::string& token) {
    if (token.empty() || token.size() > 18 || !std::all_of(token.begin(), token.end(), [](char c) { return c >= '0' && c <= '9'; }))
        return std::nullopt;
    return std::stoull(token);
}

Status too_many_triangles(const std::string& path, std::uint64_t n, const LoadOptions& options) {
    return fail(ErrorCode::limit_exceeded, path,
                "has " + std::to_string(n) + " triangles, more than the limit of " + std::to_string(options.max_triangles));
}

// Binary STL is 80 bytes of header, a 32-bit triangle count n and 50 bytes per triangle, so the
// size must be exactly 84 + 50 n. ASCII STL starts with "solid" and is text (binary files often
// start with "solid" too, so a cut binary file is recognised by its zero bytes).
Status check_stl(const std::string& path, const std::string& head, std::uint64_t size, const LoadOptions& options) {
    if (size >= 84) {
        const std::uint64_t n = read_le32(head, 80);
        if (84 + 50 * n == size) return n > options.max_triangles ? too_many_triangles(path, n, options) : Status{Ok{}};
    }
    const std::size_t first = head.find_first_not_of(" \t\r\n");
    const bool text = head.find('\0') == std::string::npos;
    if (text && first != std::string::npos && lower(head.substr(first, 5)) == "solid") return Ok{};  // parsed incrementally
    if (size < 84) return fail(ErrorCode::bad_format, path, "is too short for a binary STL file and is not ASCII STL");
    const std::uint64_t n = read_le32(head, 80);
    return fail(ErrorCode::bad_format, path,
                "binary STL header claims " + std::to_string(n) + " triangles (" + std::to_string(84 + 50 * n) +
                    " bytes), which does not match the file's " + std::to_string(size) + " bytes (cut short, damaged or not STL)");
}

// The fewest bytes one element can take: ASCII needs a character and a separator per value (a
// list at least its count), binary the sizes of its scalars (a list at least its count).
// nullopt: not one of PLY's scalar types.
std::optional<std::uint64_t> ply_type_size(const std::string& type) {
    static const std::map<std::string, std::uint64_t> sizes = {
        {"char", 1},  {"uchar", 1},  {"int8", 1},   {"uint8", 1},   {"short", 2},   {"ushort", 2}, {"int16", 2},
        {"uint16", 2}, {"int", 4},   {"uint", 4},   {"int32", 4},   {"uint32", 4},  {"float", 4},  {"float32", 4},
        {"double", 8}, {"float64", 8}};
    auto it = sizes.find(type);
    if (it == sizes.end()) return std::nullopt;
    return it->second;
}

// PLY: the header ends with an end_header line (at the start of a line, followed by a line end);
// properties have PLY's types; every element count in the header times the element's minimal size
// must fit in the bytes after the header; the face count must be within max_triangles.
Status check_ply(const std::string& path, const std::string& head, std::uint64_t size, const LoadOptions& options) {
    // end_header must start a line: assimp 5.2.5 loops forever or reads past its buffer when the
    // only "end_header" is in the middle of one (load_model_fuzzer findings).
    std::size_t end = head.find("\nend_header");
    if (head.rfind("ply", 0) != 0 && head.rfind("PLY", 0) != 0) return Ok{};  // not PLY: assimp says what it is
    if (end == std::string::npos)
        return fail(ErrorCode::bad_format, path,
                    "PLY header has no end_header line in its first " + std::to_string(head.size()) + " bytes");
    ++end;
    // assimp's reader runs past the end of the buffer when end_header is not followed by a line end
    // ("end_header0", "end_header\v": a load_model_fuzzer finding, a crash in assimp 5.2.5).
    const std::string after = head.substr(end + 10, 2);
    const bool cut = head.size() < size && after.size() < 2;  // the rest is past the bytes read
    if (!cut && (after.empty() || (after[0] != '\n' && after != "\r\n")))
        return fail(ErrorCode::bad_format, path, "PLY header's end_header is not followed by a line end (corrupt header)");
    std::istringstream lines(head.substr(0, end));
    std::string line;
    bool ascii = true;
    struct Element {
        std::string name;
        std::uint64_t count = 0, min_bytes = 0;
    };
    std::vector<Element> elements;
    bool comment_in_element = false;  // a comment since the last element line
    while (std::getline(lines, line)) {
        std::istringstream words(line);
        std::string word;
        words >> word;
        if ((word == "comment" || word == "obj_info") && !elements.empty()) comment_in_element = true;
        // assimp 5.2.5 ends an element's property list at a comment and reads the rest wrongly: an
        // error, garbled positions, or, in a binary file, a minute of work on a 300-byte header
        // (found comparing facet's PLY reader with assimp on generated headers).
        if (word == "property" && comment_in_element)
            return fail(ErrorCode::bad_format, path,
                        "PLY header has a comment among the properties of element '" + elements.back().name +
                            "', which assimp cannot read");
        if (word == "format") {
            std::string kind;
            words >> kind;
            ascii = kind == "ascii";
        } else if (word == "element") {
            Element e;
            std::string count;
            words >> e.name >> count;
            const auto n = parse_count(count);
            if (!n) return fail(ErrorCode::bad_format, path, "PLY element '" + e.name + "' has an invalid count '" + count + "'");
            e.count = *n;
            elements.push_back(e);
            comment_in_element = false;
        } else if (word == "property" && !elements.empty()) {
            // assimp 5.2.5 loops forever on a property of a type it does not know ("uint4": a
            // load_model_fuzzer finding), so every type must be one of PLY's.
            std::string type, item_type;
            words >> type;
            if (type == "list") {
                words >> type >> item_type;  // the count's type (a list may be empty), the items' type
                if (!ply_type_size(item_type))
                    return fail(ErrorCode::bad_format, path, "PLY property list has an unknown item type '" + item_type + "'");
            }
            const std::optional<std::uint64_t> bytes = ply_type_size(type);
            if (!bytes) return fail(ErrorCode::bad_format, path, "PLY property has an unknown type '" + type + "'");
            elements.back().min_bytes += ascii ? 2 : *bytes;
        }
    }
    const std::uint64_t data = size - std::min<std::uint64_t>(size, end + 10);
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

// OFF: "[ST][C][N][4]OFF", then vertex, face and edge counts. A vertex takes at least three
// values ("0 0 0\n", 6 bytes), a face at least its count (2 bytes).
Status check_off(const std::string& path, const std::string& head, std::uint64_t size, const LoadOptions& options) {
    std::istringstream in(head);
    std::vector<std::string> tokens;
    std::string line;
    while (tokens.size() < 3 && std::getline(in, line)) {
        line = line.substr(0, line.find('#'));
        std::istringstream words(line);
        for (std::string w; tokens.size() < 3 && words >> w;) tokens.push_back(w);
    }
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

// GLB: "glTF" magic, version, total length; the length must not exceed the file.
Status check_glb(const std::string& path, const std::string& head, std::uint64_t size) {
    if (size < 12 || head.compare(0, 4, "glTF") != 0) return fail(ErrorCode::bad_format, path, "is not a GLB file (no glTF header)");
    const std::uint64_t length = read_le32(head, 8);
    if (length > size)
        return fail(ErrorCode::bad_format, path,
                    "GLB header claims " + std::to_string(length) + " bytes but the file has " + std::to_string(size) +
                        " (truncated)");
    return Ok{};
}

Status check_header(const std::string& path, const std::string& ext, const std::string& head, std::uint64_t size,
                    const LoadOptions& options) {
    if (ext == "stl") return check_stl(path, head, size, options);
    if (ext == "ply") return check_ply(path, head, size, options);
    if (ext == "off") return check_off(path, head, size, options);
    if (ext == "glb") return check_glb(path, head, size);
    return Ok{};
}

// ---------------------------------------------------------------------------------------------
// 2. assimp

// Not used: GenNormals/GenSmoothNormals (facet computes creased normals itself), FindInvalidData
// (it deletes a whole mesh for one non-finite position; facet drops just those triangles) and
// FlipWindingOrder (files are counter-clockwise, as facet). FlipUVs turns assimp's bottom-left
// UV origin into facet's top-left one (for glTF it undoes assimp's own flip).
constexpr unsigned k_import_flags = aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_JoinIdenticalVertices |
                                    aiProcess_ValidateDataStructure | aiProcess_FlipUVs;

// assimp's messages for "nothing left that has faces", from validation or SortByPType.
bool means_no_triangles(const std::string& message) {
    return message.find("no faces") != std::string::npos || message.find("No meshes remaining") != std::string::npos ||
           message.find("mNumMeshes is 0") != std::string::npos;
}

// Some readers work around bad data and only log an error: the OBJ reader replaces a missing
// material, the OFF reader clamps out-of-range vertex indices to the last vertex. A global assimp
// logger hands each error to the thread whose import logged it; they become one warning, except
// an out-of-range index, which means a corrupt file (as it is for OBJ and PLY): an error.
struct LoggedErrors {
    std::vector<std::string> distinct;  // the first few, in order
    std::size_t total = 0;
    std::optional<std::string> bad_index;
};
thread_local LoggedErrors* t_assimp_errors = nullptr;
constexpr std::size_t k_max_logged_errors = 3;

// Logged "errors" about things facet does not use, or about files that are fine.
bool ignorable(std::string_view message) {
    for (std::string_view noise : {"No object detected to attach a new mesh instance",  // OBJ: usemtl before o/g
                                   "nimation", "Bone", "binormal", "tangent"})
        if (message.find(noise) != std::string_view::npos) return true;
    return false;
}

class ErrorCollector final : public Assimp::Logger {
public:
    ErrorCollector() : Logger(Logger::NORMAL) {}
    bool attachStream(Assimp::LogStream*, unsigned) override { return false; }
    bool detachStream(Assimp::LogStream*, unsigned) override { return false; }
    void OnDebug(const char*) override {}
    void OnVerboseDebug(const char*) override {}
    void OnInfo(const char*) override {}
    void OnWarn(const char*) override {}
    void OnError(const char* message) override {
        LoggedErrors* e = t_assimp_errors;
        const std::string_view m = message;
        if (!e || ignorable(m)) return;
        if (m.find("out of range") != std::string_view::npos && m.find("ndex") != std::string_view::npos && !e->bad_index)
            e->bad_index = message;
        if (std::find(e->distinct.begin(), e->distinct.end(), message) != e->distinct.end()) return;
        ++e->total;
        if (e->distinct.size() < k_max_logged_errors) e->distinct.push_back(message);
    }
};

// Collects assimp's logged errors on this thread while it lives.
class AssimpErrors {
public:
    AssimpErrors() {
        static std::once_flag installed;
        std::call_once(installed, [] { Assimp::DefaultLogger::set(new ErrorCollector); });
        t_assimp_errors = &errors_;
    }
    ~AssimpErrors() { t_assimp_errors = nullptr; }
    AssimpErrors(const AssimpErrors&) = delete;
    AssimpErrors& operator=(const AssimpErrors&) = delete;

    const std::optional<std::string>& bad_index() const { return errors_.bad_index; }

    // One warning naming the file, or nothing if assimp logged no error.
    std::optional<std::string> warning(const std::string& path) const {
        if (errors_.total == 0) return std::nullopt;
        std::string w = path + ": assimp reported problems and worked around them: ";
        for (std::size_t i = 0; i < errors_.distinct.size(); ++i) w += (i ? "; " : "") + errors_.distinct[i];
        if (errors_.total > errors_.distinct.size())
            w += " (and " + std::to_string(errors_.total - errors_.distinct.size()) + " more)";
        return w;
    }

private:
    LoggedErrors errors_;
};

// ---------------------------------------------------------------------------------------------
// 3. aiScene -> Scene

Mat4 to_mat4(const aiMatrix4x4& m) {
    // aiMatrix4x4 is row-major with the translation in a4, b4, c4 (it also transforms column
    // vectors), so its rows are our rows.
    return Mat4::from_rows({m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4});
}

// +Z up to +Y up: a rotation of -90 degrees about X, (x, y, z) -> (x, z, -y), with exact zeros.
Mat4 z_up_to_y_up() {
    return Mat4::from_rows({1, 0, 0, 0,  //
                            0, 0, 1, 0,  //
                            0, -1, 0, 0,  //
                            0, 0, 0, 1});
}

bool is_triangle_mesh(const aiMesh& m) { return (m.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) != 0 && m.mNumFaces > 0; }

std::size_t triangle_count(const aiMesh& m) {
    if (!is_triangle_mesh(m)) return 0;
    std::size_t n = 0;
    for (unsigned f = 0; f < m.mNumFaces; ++f) n += m.mFaces[f].mNumIndices == 3;
    return n;
}

// What one instance of the mesh costs once converted: the vertices its triangles can use (each
// with position, normal and, when the file has them, colour and uv) and three indices per triangle.
std::uint64_t estimated_bytes(const aiMesh& m) {
    const std::uint64_t triangles = triangle_count(m);
    const std::uint64_t vertices = std::min<std::uint64_t>(m.mNumVertices, 3 * triangles);
    const std::uint64_t per_vertex = sizeof(Vec3) * 2 + (m.HasVertexColors(0) ? sizeof(Vec4) : 0) +
                                     (m.HasTextureCoords(0) ? sizeof(Vec2) : 0);
    return vertices * per_vertex + triangles * 3 * sizeof(std::uint32_t);
}

// Node transforms are composed parent-first. The walk is iterative (deep hierarchies cannot
// overflow the stack) and refuses cycles, which a corrupt file could build.
struct NodeVisit {
    const aiNode* node;
    Mat4 world;
};

template <class F>
Status walk_nodes(const std::string& path, const aiScene& scene, const Mat4& root, F&& visit_mesh) {
    std::vector<NodeVisit> stack;
    std::unordered_set<const aiNode*> seen;
    if (scene.mRootNode) stack.push_back({scene.mRootNode, root});
    while (!stack.empty()) {
        const NodeVisit v = stack.back();
        stack.pop_back();
        if (!seen.insert(v.node).second) return fail(ErrorCode::bad_format, path, "node hierarchy has a cycle");
        const Mat4 world = v.world * to_mat4(v.node->mTransformation);
        for (unsigned i = 0; i < v.node->mNumMeshes; ++i) {
            const unsigned mesh = v.node->mMeshes[i];
            if (mesh >= scene.mNumMeshes) return fail(ErrorCode::bad_format, path, "a node refers to a missing mesh");
            if (Status s = visit_mesh(mesh, world); !s) return s;
        }
        // Children pushed in reverse so they are visited in file order.
        for (unsigned c = v.node->mNumChildren; c-- > 0;)
            if (v.node->mChildren[c]) stack.push_back({v.node->mChildren[c], world});
    }
    return Ok{};
}

// One aiMesh converted, shared by every node that refers to it.
struct ConvertedMesh {
    Mesh mesh;
    std::size_t dropped = 0;     // triangles with a non-finite or out-of-range vertex
    std::size_t degenerate = 0;  // kept triangles with two corners at the same position
};

bool finite_and_nonzero(const aiVector3D& n) {
    return std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z) && (n.x != 0 || n.y != 0 || n.z != 0);
}

Vec4 clamp_colour(const aiColor4D& c) {
    auto unit = [](float v) { return std::isfinite(v) ? clamp(v, 0.0f, 1.0f) : 1.0f; };
    return {unit(c.r), unit(c.g), unit(c.b), unit(c.a)};
}

// Keeps the triangles whose three vertices exist and are finite, then only the vertices they use.
ConvertedMesh convert_mesh(const aiMesh& in, bool use_file_normals, float crease_angle_radians, int threads) {
    ConvertedMesh out;
    std::vector<std::uint32_t> used;  // file vertex of each kept vertex
    std::vector<std::uint32_t> remap(in.mNumVertices, ~0u);
    auto finite = [&](unsigned i) {
        const aiVector3D& p = in.mVertices[i];
        return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
    };
    for (unsigned f = 0; is_triangle_mesh(in) && f < in.mNumFaces; ++f) {
        const aiFace& face = in.mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines left in a mixed mesh
        bool ok = true;
        for (unsigned k = 0; k < 3; ++k) ok = ok && face.mIndices[k] < in.mNumVertices && finite(face.mIndices[k]);
        if (!ok) {
            ++out.dropped;
            continue;
        }
        const aiVector3D &a = in.mVertices[face.mIndices[0]], &b = in.mVertices[face.mIndices[1]],
                         &c = in.mVertices[face.mIndices[2]];
        out.degenerate += a == b || b == c || c == a;
        for (unsigned k = 0; k < 3; ++k) {
            std::uint32_t& r = remap[face.mIndices[k]];
            if (r == ~0u) {
                r = static_cast<std::uint32_t>(used.size());
                used.push_back(face.mIndices[k]);
            }
            out.mesh.indices.push_back(r);
        }
    }
    Mesh& m = out.mesh;
    for (std::uint32_t i : used) m.positions.push_back({in.mVertices[i].x, in.mVertices[i].y, in.mVertices[i].z});
    if (in.HasVertexColors(0))
        for (std::uint32_t i : used) m.colours.push_back(clamp_colour(in.mColors[0][i]));
    if (in.HasTextureCoords(0)) {
        for (std::uint32_t i : used) {
            const aiVector3D& t = in.mTextureCoords[0][i];
            m.uvs.push_back({std::isfinite(t.x) ? t.x : 0.0f, std::isfinite(t.y) ? t.y : 0.0f});
        }
    }
    // The file's normals are used only when every one is usable; otherwise all are recomputed, so
    // a mesh never mixes the two.
    bool normals_ok = use_file_normals && in.HasNormals();
    for (std::size_t k = 0; normals_ok && k < used.size(); ++k) normals_ok = finite_and_nonzero(in.mNormals[used[k]]);
    if (normals_ok) {
        for (std::uint32_t i : used) m.normals.push_back(normalize(Vec3{in.mNormals[i].x, in.mNormals[i].y, in.mNormals[i].z}));
    } else if (!m.indices.empty()) {
        compute_creased_normals(m, crease_angle_radians, threads);
    }
    return out;
}

// ---- materials and textures

// A file named `name` in `dir`, in any letter case (textures authored on Windows or macOS).
std::optional<fs::path> find_any_case(const fs::path& dir, const std::string& name) {
    std::error_code ec;
    const std::string wanted = lower(name);
    for (fs::directory_iterator it(dir.empty() ? fs::path(".") : dir, ec), end; !ec && it != end; it.increment(ec))
        if (lower(it->path().filename().string()) == wanted && it->is_regular_file(ec)) return it->path();
    return std::nullopt;
}

// Finds a texture file named in a model: as written (relative to the model's directory); an
// absolute path also as if it were relative ("\..\tex\a.png" from Windows tools); then its file
// name alone in the model's directory (absolute paths from the author's machine, "C:\...").
// Each candidate exactly first, then in any letter case.
std::optional<fs::path> find_texture_file(const fs::path& model_dir, std::string name) {
    std::replace(name.begin(), name.end(), '\\', '/');
    const fs::path as_written(name);
    const std::string file_name = name.substr(name.find_last_of('/') + 1);
    if (file_name.empty()) return std::nullopt;
    std::vector<fs::path> candidates = {as_written.is_absolute() ? as_written : model_dir / as_written};
    if (as_written.is_absolute()) candidates.push_back(model_dir / as_written.relative_path());
    candidates.push_back(model_dir / file_name);
    std::error_code ec;
    for (const fs::path& c : candidates)
        if (fs::is_regular_file(c, ec)) return c;
    for (const fs::path& c : candidates)
        if (auto found = find_any_case(c.parent_path(), file_name)) return found;
    return std::nullopt;
}

Wrap to_wrap(int mode) {
    switch (mode) {
        case aiTextureMapMode_Clamp:
        case aiTextureMapMode_Decal: return Wrap::clamp;
        case aiTextureMapMode_Mirror: return Wrap::mirror;
        default: return Wrap::repeat;
    }
}

// Everything about one file's conversion that outlives a single mesh.
class Converter {
public:
    Converter(const std::string& path, const aiScene& scene, const LoadOptions& options)
        : path_(path), dir_(fs::path(path).parent_path()), scene_(scene), options_(options) {
        const std::string ext = model_extension(path);
        gltf_ = ext == "gltf" || ext == "glb";
        // STL's normals are per facet (often zero or stale): they are removed on import (see
        // load_model) and creased ones computed; this is a second guard.
        use_file_normals_ = ext != "stl";
    }

    std::vector<std::string>& warnings() { return warnings_; }

    // The converted mesh `index` (converted once, on first use).
    ConvertedMesh& mesh(unsigned index) {
        auto it = meshes_.find(index);
        if (it == meshes_.end())
            it = meshes_.emplace(index, convert_mesh(*scene_.mMeshes[index], use_file_normals_,
                                                     radians(options_.crease_angle_degrees), options_.threads)).first;
        return it->second;
    }

    // The material of mesh `index`, with its texture only when the mesh has uvs to sample it with.
    Material material(unsigned mesh_index, bool has_uvs) {
        const unsigned index = scene_.mMeshes[mesh_index]->mMaterialIndex;
        if (index >= scene_.mNumMaterials) return Material{};
        auto it = materials_.find(index);
        if (it == materials_.end()) it = materials_.emplace(index, convert_material(*scene_.mMaterials[index])).first;
        Material m = it->second.material;
        if (has_uvs && it->second.has_texture) {
            m.base_colour_texture = texture(*scene_.mMaterials[index], it->second.texture_type);
            if (!gltf_ && m.base_colour_texture && m.base_colour_texture->has_transparency()) m.alpha_mode = AlphaMode::blend;
        }
        return m;
    }

private:
    struct ConvertedMaterial {
        Material material;
        bool has_texture = false;
        aiTextureType texture_type = aiTextureType_DIFFUSE;
    };

    // Base colour: glTF's base colour (its alpha is the opacity) or the diffuse colour times
    // AI_MATKEY_OPACITY. Alpha mode: glTF's alphaMode and alphaCutoff; other formats blend when
    // the material or its texture is not fully opaque (the texture part is decided in material()).
    ConvertedMaterial convert_material(const aiMaterial& am) const {
        ConvertedMaterial out;
        Material& m = out.material;
        aiColor4D colour(1, 1, 1, 1);
        if ((gltf_ && am.Get(AI_MATKEY_BASE_COLOR, colour) == AI_SUCCESS) || am.Get(AI_MATKEY_COLOR_DIFFUSE, colour) == AI_SUCCESS)
            m.base_colour = clamp_colour(colour);
        if (gltf_) {
            aiString mode;
            if (am.Get(AI_MATKEY_GLTF_ALPHAMODE, mode) == AI_SUCCESS) {
                const std::string_view s = mode.C_Str();
                m.alpha_mode = s == "MASK" ? AlphaMode::mask : s == "BLEND" ? AlphaMode::blend : AlphaMode::opaque;
            }
            float cutoff = 0.5f;
            if (am.Get(AI_MATKEY_GLTF_ALPHACUTOFF, cutoff) == AI_SUCCESS && std::isfinite(cutoff)) m.alpha_cutoff = cutoff;
        } else {
            float opacity = 1;
            if (am.Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS && std::isfinite(opacity))
                m.base_colour.w *= clamp(opacity, 0.0f, 1.0f);
            if (m.base_colour.w < 1) m.alpha_mode = AlphaMode::blend;
        }
        int two_sided = 0;
        if (am.Get(AI_MATKEY_TWOSIDED, two_sided) == AI_SUCCESS) m.double_sided = two_sided != 0;
        for (aiTextureType type : {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE})
            if (am.GetTextureCount(type) > 0) {
                out.has_texture = true;
                out.texture_type = type;
                int u = aiTextureMapMode_Wrap, v = aiTextureMapMode_Wrap;
                am.Get(AI_MATKEY_MAPPINGMODE_U(type, 0), u);
                am.Get(AI_MATKEY_MAPPINGMODE_V(type, 0), v);
                m.sampler.wrap_u = to_wrap(u);
                m.sampler.wrap_v = to_wrap(v);
                break;
            }
        return out;
    }

    // Loads (once per name) the first texture of `type`; on failure a warning and null.
    std::shared_ptr<const Texture> texture(const aiMaterial& am, aiTextureType type) {
        aiString name;
        if (am.GetTexture(type, 0, &name) != AI_SUCCESS) return nullptr;
        const std::string key = name.C_Str();
        // No name, or the placeholder assimp's MD2 reader puts in to keep the uvs: no texture.
        if (key.empty() || key == "$texture_dummy.bmp") return nullptr;
        auto it = textures_.find(key);
        if (it != textures_.end()) return it->second;
        Result<std::shared_ptr<const Texture>> loaded = load_texture(key);
        std::shared_ptr<const Texture> tex;
        if (loaded)
            tex = loaded.value();
        else
            warnings_.push_back(path_ + ": texture '" + key + "' not used, the material colour stands in: " + loaded.error().message);
        textures_.emplace(key, tex);
        return tex;
    }

    Result<std::shared_ptr<const Texture>> load_texture(const std::string& name) const {
        if (const aiTexture* embedded = scene_.GetEmbeddedTexture(name.c_str())) return decode_embedded(*embedded, name);
        if (!name.empty() && name[0] == '*')
            return Error{ErrorCode::bad_format, "embedded texture " + name + " does not exist in the file"};
        const std::optional<fs::path> file = find_texture_file(dir_, name);
        if (!file)
            return Error{ErrorCode::io, "file not found (looked for '" + name + "' in '" +
                                            (dir_.empty() ? std::string(".") : dir_.string()) + "')"};
        return Texture::load(file->string(), options_.texture_limits);
    }

    // Compressed (PNG, JPEG, ...): mHeight == 0 and mWidth bytes. Uncompressed: mWidth x mHeight
    // BGRA texels.
    Result<std::shared_ptr<const Texture>> decode_embedded(const aiTexture& t, const std::string& name) const {
        const std::string label = path_ + " (embedded texture " + name + ")";
        if (!t.pcData) return Error{ErrorCode::bad_format, label + ": no data"};
        if (t.mHeight == 0) {
            // Every reader that embeds a compressed file names its format in achFormatHint ("png",
            // "jpg", the file's extension). assimp's MDL reader, given a skin of height 0, leaves
            // the hint empty and mWidth far beyond the bytes it allocated: not a byte of such a
            // buffer can be read safely.
            if (t.achFormatHint[0] == '\0')
                return Error{ErrorCode::bad_format, label + ": compressed data without a format hint, not read "
                                                            "(assimp gives no trustworthy size for it)"};
            return Texture::decode(t.pcData, t.mWidth, label, options_.texture_limits);
        }
        const TextureLimits& limits = options_.texture_limits;
        if (t.mWidth > static_cast<unsigned>(limits.max_size) || t.mHeight > static_cast<unsigned>(limits.max_size) ||
            std::uint64_t{t.mWidth} * t.mHeight > limits.max_pixels)
            return Error{ErrorCode::limit_exceeded, label + ": " + std::to_string(t.mWidth) + "x" +
                                                        std::to_string(t.mHeight) + " is larger than the texture limits"};
        Image image{static_cast<int>(t.mWidth), static_cast<int>(t.mHeight), {}};
        image.pixels.reserve(std::size_t{t.mWidth} * t.mHeight);
        for (std::size_t i = 0; i < std::size_t{t.mWidth} * t.mHeight; ++i)
            image.pixels.push_back({t.pcData[i].r, t.pcData[i].g, t.pcData[i].b, t.pcData[i].a});
        try {
            return std::shared_ptr<const Texture>(std::make_shared<Texture>(std::move(image)));
        } catch (const FacetError& e) {
            return Error{e.error().code, label + ": " + e.error().message};
        }
    }

    std::string path_;
    fs::path dir_;
    const aiScene& scene_;
    const LoadOptions& options_;
    bool gltf_ = false, use_file_normals_ = true;
    std::map<unsigned, ConvertedMesh> meshes_;
    std::map<unsigned, ConvertedMaterial> materials_;
    std::map<std::string, std::shared_ptr<const Texture>> textures_;
    std::vector<std::string> warnings_;
};

Result<LoadedModel> convert_scene(const std::string& path, const aiScene& scene, const LoadOptions& options) {
    const Mat4 root = options.up_axis == UpAxis::z ? z_up_to_y_up() : Mat4::identity();

    // The limits count every instance, since each becomes a mesh of its own.
    std::size_t instance_triangles = 0;
    std::uint64_t scene_bytes = 0;
    std::vector<std::size_t> references(scene.mNumMeshes, 0);
    Status counted = walk_nodes(path, scene, root, [&](unsigned mesh, const Mat4&) -> Status {
        ++references[mesh];
        instance_triangles += triangle_count(*scene.mMeshes[mesh]);
        if (instance_triangles > options.max_triangles) return too_many_triangles(path, instance_triangles, options);
        scene_bytes += estimated_bytes(*scene.mMeshes[mesh]);
        if (scene_bytes > options.max_scene_bytes)
            return fail(ErrorCode::limit_exceeded, path,
                        "would take at least " + std::to_string(scene_bytes) +
                            " bytes once converted (every instance of a mesh is a copy), more than the limit of " +
                            std::to_string(options.max_scene_bytes) + " bytes");
        return Ok{};
    });
    if (!counted) return counted.error();
    if (instance_triangles == 0)
        return fail(ErrorCode::bad_format, path, "contains no triangles (only points or lines, or nothing placed in the scene)");

    Converter converter(path, scene, options);
    LoadedModel out;
    std::size_t dropped = 0, kept = 0, degenerate = 0;
    std::unordered_set<unsigned> counted_meshes;
    Status placed = walk_nodes(path, scene, root, [&](unsigned index, const Mat4& world) -> Status {
        if (!is_triangle_mesh(*scene.mMeshes[index])) return Ok{};
        ConvertedMesh& converted = converter.mesh(index);
        if (counted_meshes.insert(index).second) {
            dropped += converted.dropped;
            kept += converted.mesh.triangle_count();
            degenerate += converted.degenerate;
        }
        if (converted.mesh.indices.empty()) return Ok{};
        SceneObject object;
        object.material = converter.material(index, !converted.mesh.uvs.empty());
        object.model = world;
        // The last instance takes the mesh, the others copy it.
        object.mesh = --references[index] == 0 ? std::move(converted.mesh) : converted.mesh;
        out.scene.objects.push_back(std::move(object));
        return Ok{};
    });
    if (!placed) return placed.error();
    if (out.scene.objects.empty())
        return fail(ErrorCode::bad_format, path,
                    "has no valid triangles (" + std::to_string(dropped) +
                        " dropped for non-finite coordinates or out-of-range indices)");
    // Zero-area triangles are harmless among others, but a file of nothing else shows nothing.
    if (degenerate == kept)
        return fail(ErrorCode::bad_format, path,
                    "has no valid triangles (all " + std::to_string(kept) + " have two corners at the same position)");
    if (dropped > 0)
        out.warnings.push_back(path + ": dropped " + std::to_string(dropped) +
                               " triangles with non-finite coordinates or out-of-range indices");
    for (std::string& w : converter.warnings()) out.warnings.push_back(std::move(w));
    return out;
}

// ---------------------------------------------------------------------------------------------
// The fast paths (io/plain_off.hpp, io/stl.hpp, io/ply.hpp): the Scene convert_scene makes of assimp's
// import of the same file, without assimp. Anything a fast reader does not take, and any limit or
// degenerate-file error, goes the assimp way, which reports it.

std::optional<std::string> read_whole_file(const std::string& path, std::uintmax_t size) {
    std::ifstream in(path, std::ios::binary);
    std::string text(static_cast<std::size_t>(size), '\0');
    if (!in.read(text.data(), static_cast<std::streamsize>(text.size())) || in.peek() != std::char_traits<char>::eof())
        return std::nullopt;  // changed while being read: assimp reads it again and decides
    return text;
}

// What assimp's OFF reader gives every file: a grey, two-sided material, converted as
// Converter::convert_material converts it.
Material off_material() {
    Material m;
    m.base_colour = clamp_colour(aiColor4D(0.6f, 0.6f, 0.6f, 1.0f));
    m.double_sided = true;
    return m;
}

// What assimp's STL reader gives a file without colours, binary or ASCII, and its PLY reader a file
// without colours: a white material, converted as Converter::convert_material converts it.
Material white_material() {
    Material m;
    m.base_colour = clamp_colour(aiColor4D(1.0f, 1.0f, 1.0f, 1.0f));
    return m;
}

// The file read by facet's own reader for its format, or nullopt for the assimp path.
std::optional<io_detail::JoinedMesh> read_with_own_parser(const std::string& ext, const std::string& bytes) {
    if (ext == "off") return io_detail::read_plain_off(bytes);
    if (ext == "stl") return io_detail::read_stl(bytes);
    if (ext == "ply") return io_detail::read_plain_ply(bytes);
    return std::nullopt;
}

std::optional<LoadedModel> load_with_own_parser(const std::string& path, const std::string& ext, std::uintmax_t size,
                                                const LoadOptions& options) {
    const std::optional<std::string> bytes = read_whole_file(path, size);
    if (!bytes) return std::nullopt;
    std::optional<io_detail::JoinedMesh> mesh = read_with_own_parser(ext, *bytes);
    if (!mesh) return std::nullopt;
    const std::size_t triangles = mesh->indices.size() / 3;
    const std::uint64_t bytes_needed = std::min<std::uint64_t>(mesh->positions.size(), 3 * std::uint64_t{triangles}) * sizeof(Vec3) * 2 +
                                       std::uint64_t{triangles} * 3 * sizeof(std::uint32_t);  // as estimated_bytes
    if (triangles > options.max_triangles || bytes_needed > options.max_scene_bytes || mesh->degenerate == triangles)
        return std::nullopt;
    SceneObject object;
    object.mesh.positions = std::move(mesh->positions);
    object.mesh.indices = std::move(mesh->indices);
    compute_creased_normals(object.mesh, radians(options.crease_angle_degrees), options.threads);
    const Mat4 root = options.up_axis == UpAxis::z ? z_up_to_y_up() : Mat4::identity();
    object.model = root * to_mat4(aiMatrix4x4());  // the nodes' transforms, identity, as walk_nodes applies them
    object.material = ext == "off" ? off_material() : white_material();
    LoadedModel out;
    out.scene.objects.push_back(std::move(object));
    return out;
}

Error out_of_memory(const std::string& path) {
    return fail(ErrorCode::limit_exceeded, path, "needs more memory than is available");
}

}  // namespace

std::string model_extension(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    return lower(ext.empty() ? ext : ext.substr(1));
}

bool has_own_parser(const std::string& path) {
    const std::string ext = model_extension(path);
    return ext == "off" || ext == "stl" || ext == "ply";
}

bool is_supported_model_file(const std::string& path) {
    const std::string ext = model_extension(path);
    if (ext.empty()) return false;
    static const Assimp::Importer importer;  // IsExtensionSupported only reads the importer list
    return importer.IsExtensionSupported("." + ext);
}

namespace {

Result<LoadedModel> load_model_from(const std::string& path, const LoadOptions& options, bool fast_paths) {
    std::uintmax_t size = 0;
    std::string head;
    if (Status s = check_file(path, options, size, head); !s) return s.error();
    const std::string ext = model_extension(path);
    if (!is_supported_model_file(path))
        return fail(ErrorCode::unsupported, path,
                    ext.empty() ? "has no file extension to tell its format" : "'." + ext + "' is not a model format facet reads");
    if (Status s = check_header(path, ext, head, size, options); !s) return s.error();

    try {
        if (fast_paths && has_own_parser(path))
            if (std::optional<LoadedModel> model = load_with_own_parser(path, ext, size, options)) return std::move(*model);
        Assimp::Importer importer;
        unsigned flags = k_import_flags;
        if (ext == "stl") {
            // STL repeats every vertex per facet with the facet's normal; without the normals,
            // JoinIdenticalVertices welds the mesh, and facet computes creased normals instead.
            importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS, aiComponent_NORMALS);
            flags |= aiProcess_RemoveComponent;
        }
        AssimpErrors logged;
        const aiScene* scene = importer.ReadFile(path, flags);
        if (!scene) {
            const std::string why = importer.GetErrorString();
            // assimp catches the std::bad_alloc of a reader that asked for more than there is
            // (a damaged count in a header, or a process memory cap) and keeps only its name.
            if (why == "std::bad_alloc") return out_of_memory(path);
            if (means_no_triangles(why)) return fail(ErrorCode::bad_format, path, "contains no triangles (" + why + ")");
            return fail(ErrorCode::bad_format, path, "cannot be read as a model (" + readable_reason(why) + ")");
        }
        if (logged.bad_index()) return fail(ErrorCode::bad_format, path, "has out-of-range indices (" + *logged.bad_index() + ")");
        Result<LoadedModel> model = convert_scene(path, *scene, options);
        if (model)
            if (std::optional<std::string> w = logged.warning(path)) model->warnings.insert(model->warnings.begin(), *w);
        return model;
    } catch (const std::bad_alloc&) {
        return out_of_memory(path);
    } catch (const FacetError& e) {
        return fail(e.error().code, path, e.error().message);
    } catch (const std::exception& e) {
        return fail(ErrorCode::bad_format, path, std::string("cannot be converted (") + e.what() + ")");
    }
}

}  // namespace

Result<LoadedModel> load_model(const std::string& path, const LoadOptions& options) {
    return load_model_from(path, options, /*fast_paths=*/true);
}

Result<LoadedModel> io_detail::load_model_through_assimp(const std::string& path, const LoadOptions& options) {
    return load_model_from(path, options, /*fast_paths=*/false);
}

}  // namespace facet
