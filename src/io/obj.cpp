// facet io: the OBJ reader (obj.hpp). Each step mirrors assimp 5.2.5 on the files it accepts:
//  - lines as its IOStreamBuffer cuts them (every '\r', '\n' or '\f' ends one; in a file of more
//    than 16 MiB a last line without a line end is lost) and its ObjFileParser reads them (a line
//    is dispatched on its first character: indented lines are ignored; numbers through fast_atof;
//    face indices through atoi, forward references allowed, negative ones relative);
//  - its model: objects ('o' reuses an object of that name, 'g' always starts one), meshes (a new
//    one per object and per change of material once the mesh has faces), the material library
//    (DefaultMaterial first, MTL files read where they are named, materials named by 'usemtl' but
//    never defined created with a logged error);
//  - ObjFileImporter: a vertex per face corner, normals, colours and uvs as it copies them
//    (zeros where a face lacks them, none for a mesh whose indices leave the arrays);
//  - post-processing: ScenePreprocessor, FlipUVs (v = 1 - v), Triangulate (quads split at their
//    concave corner by the same float arithmetic), JoinIdenticalVertices (equal positions, normals
//    and uvs; colours not compared, the first corner's kept; declined where its tolerance could
//    join differing ones: assimp_join.hpp);
//  - the materials' properties as createMaterials sets them, with its logged errors.
#include "io/obj.hpp"

#include <assimp/defs.h>
#include <assimp/material.h>
#include <assimp/vector2.h>
#include <assimp/vector3.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <strings.h>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "exec/fresh_pages.hpp"
#include "io/assimp_join.hpp"
#include "io/assimp_text.hpp"
#include "io/assimp_triangulate.hpp"
#include "io/import_notes.hpp"
#include "io/load_common.hpp"
#include "io/resources.hpp"

namespace facet::io_detail {
namespace {

namespace fs = std::filesystem;

// Thrown where assimp would read the file otherwise than this reader can mirror (or refuse it):
// the file goes to assimp.
struct Decline { int line = 0; };

constexpr std::uint32_t k_absent = 0xFFFFFFFFu;        // a corner without a texture coordinate or normal
constexpr std::uint32_t k_out_of_range = 0xFFFFFFFEu;  // an index that no array reaches
constexpr unsigned k_no_material = ~0u;
constexpr std::size_t k_stream_block = 4096 * 4096;  // assimp's IOStreamBuffer reads 16 MiB at a time
constexpr std::size_t k_max_word = 1000;             // shorter than every buffer assimp copies words into
constexpr std::size_t k_max_name = 1000;             // aiString holds 1023 characters
constexpr std::size_t k_min_obj_bytes = 16;          // ObjFileImporter: "OBJ-file is too small."
constexpr std::size_t k_min_text_bytes = 8;          // BaseImporter::ConvertToUTF8: "File is too small"

// assimp's IsLineEnd ('\0' too) and IsSpaceOrNewLine.
bool ends_line(char c) { return c == '\r' || c == '\n' || c == '\f' || c == '\0'; }
bool is_blank(char c) { return is_space(c) || ends_line(c); }

bool starts_with_nocase(const char* c, const char* word) { return strncasecmp(c, word, std::strlen(word)) == 0; }

// getNextWord: spaces and tabs skipped, stopping at a line end.
const char* skip_blanks(const char* c) {
    while (is_space(*c)) ++c;
    return c;
}
// getNextToken: the token at c skipped, then the spaces after it.
const char* next_token(const char* c) {
    while (!is_blank(*c)) ++c;
    return skip_blanks(c);
}
// The word at c (up to a space or line end).
std::string_view word_at(const char* c) {
    const char* e = c;
    while (!is_blank(*e)) ++e;
    if (static_cast<std::size_t>(e - c) > k_max_word) throw Decline{__LINE__};
    return {c, static_cast<std::size_t>(e - c)};
}
// The rest of the line from c.
std::string_view rest_of_line(const char* c) {
    const char* e = c;
    while (!ends_line(*e)) ++e;
    return {c, static_cast<std::size_t>(e - c)};
}

// fast_atof on a word: the number it starts with; a word that does not start with one makes
// assimp throw.
float word_float(std::string_view word) {
    if (word.empty()) throw Decline{__LINE__};
    float value = 0;
    try {
        read_float(word.data(), value);  // stops before the word's end, which is no part of a number
    } catch (const NotANumber&) {
        throw Decline{__LINE__};
    }
    return value;
}

// copyNextWord + fast_atof: the next word's number, and c moved past the word.
float next_float(const char*& c) {
    c = skip_blanks(c);
    if (*c == '\\') throw Decline{__LINE__};
    const std::string_view w = word_at(c);
    c += w.size();
    return word_float(w);
}

bool non_finite(const aiVector3D& v) { return !std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z); }

// ---- the model, as ObjFile::Model holds it

enum TextureSlot : int {
    diffuse, specular, ambient, emissive, bump, normal, reflection_sphere, reflection_cube_top, reflection_cube_bottom,
    reflection_cube_front, reflection_cube_back, reflection_cube_left, reflection_cube_right, specularity, opacity,
    displacement, roughness, metallic, sheen, rma, slot_count
};

struct ObjMaterial {
    std::string name;
    unsigned index = 0;  // in the library
    std::string texture[slot_count];
    std::string reflection[6];  // textureReflection: a sphere map, or a cube map's faces (-type)
    bool clamp[slot_count] = {};
    aiColor3D ambient, diffuse{0.6f, 0.6f, 0.6f}, specular, emissive, transparent{1.0f, 1.0f, 1.0f};
    float alpha = 1.0f, shininess = 0.0f, ior = 1.0f, anisotropy = 0.0f, bump_multiplier = 1.0f;
    int illumination = 1;
    std::optional<float> roughness_factor, metallic_factor, clearcoat_thickness, clearcoat_roughness;
    std::optional<aiColor3D> sheen_colour;
};

// A mesh's faces, which are consecutive in the file (faces go to the current mesh, and a mesh
// once left is never current again): their corners and corner counts are ObjModel's from
// first_corner and first_face on.
struct ObjMesh {
    std::string name;
    unsigned material = k_no_material;
    std::size_t first_corner = 0, first_face = 0, corners = 0;
    std::size_t faces = 0, triangles = 0;  // triangles: as Triangulate makes them of simple polygons
    bool has_normals = false;  // some face gave normal indices
    std::size_t uv_count = 0;  // texture coordinate indices given, in all
};

struct ObjObject {
    std::string name;
    std::vector<unsigned> meshes;
};

struct ObjModel {
    std::vector<aiVector3D> vertices, colours, texcoords, normals;
    // Per face corner, all meshes': its vertex, and (for the corners of a mesh some face of which
    // has them) its texture coordinate and normal or k_absent; per face its corner count.
    std::vector<std::uint32_t> corner_v, corner_vt, corner_vn;
    // Per face its corner count (at most 0x7fff), from the first face that is not a triangle on:
    // the `leading_triangles` faces before it are not listed (a file of triangles lists none).
    std::vector<std::uint16_t> face_corners;
    std::size_t leading_triangles = 0;
    std::size_t announced_faces = 0;  // the "f" lines counted before reading: face_corners' reserve
    unsigned texcoord_dim = 0;
    std::vector<ObjMesh> meshes;
    std::vector<ObjObject> objects;
    std::map<std::string, ObjMaterial> materials;
    std::vector<ObjMaterial*> library;  // in order; DefaultMaterial first
    ObjMaterial* current_material = nullptr;
    int current_object = -1, current_mesh = -1;
    std::string active_group;
    std::size_t total_triangles = 0;
    bool counting_only = false;  // past max_triangles: faces are counted, not kept
    bool has_polygons = false;   // faces of more than four corners
    std::uint32_t largest_vertex = 0;

    ObjMaterial& add_material(const std::string& name) {
        if (name.size() > k_max_name) throw Decline{__LINE__};
        ObjMaterial& m = materials[name];
        m.name = name;
        m.index = static_cast<unsigned>(library.size());
        library.push_back(&m);
        return m;
    }

    unsigned material_index(const std::string& name) const {
        auto it = materials.find(name);
        return name.empty() || it == materials.end() ? k_no_material : it->second.index;
    }

    void create_mesh(const std::string& name, ImportNotes& notes) {
        meshes.push_back({});
        meshes.back().name = name;
        meshes.back().first_corner = corner_v.size();
        meshes.back().first_face = face_count();
        current_mesh = static_cast<int>(meshes.size() - 1);
        if (current_object >= 0)
            objects[static_cast<std::size_t>(current_object)].meshes.push_back(static_cast<unsigned>(current_mesh));
        else
            notes.error("OBJ: No object detected to attach a new mesh instance.");
    }

    void create_object(const std::string& name, ImportNotes& notes) {
        objects.push_back({name, {}});
        current_object = static_cast<int>(objects.size() - 1);
        create_mesh(name, notes);
        if (current_material) meshes[static_cast<std::size_t>(current_mesh)].material = material_index(current_material->name);
    }

    std::size_t face_count() const { return leading_triangles + face_corners.size(); }
    std::uint32_t corners_of(std::size_t face) const { return face < leading_triangles ? 3 : face_corners[face - leading_triangles]; }
    void add_triangles(std::size_t n) {
        if (face_corners.empty())
            leading_triangles += n;
        else
            face_corners.insert(face_corners.end(), n, std::uint16_t{3});
    }
    void add_face_corners(std::uint16_t n) {
        if (n == 3) return add_triangles(1);
        if (face_corners.empty()) detail::reserve_in_huge_pages(face_corners, announced_faces - std::min(announced_faces, leading_triangles));
        face_corners.push_back(n);
    }

    // ObjFileParser::needsNewMesh.
    bool needs_new_mesh(const std::string& material) const {
        if (current_mesh < 0) return true;
        const ObjMesh& m = meshes[static_cast<std::size_t>(current_mesh)];
        return m.material != k_no_material && m.material != material_index(material) && m.faces > 0;
    }
};

// ---- MTL files (ObjFileMtlImporter)

class MtlReader {
public:
    MtlReader(ObjModel& model, ImportNotes& notes) : model_(model), notes_(notes) {}

    // `text` ends with the NUL TextFileToBuffer appends.
    void read(const std::string& text) {
        const char* p = text.data();
        end_ = text.data() + text.size();
        while (p != end_) {
            ObjMaterial* m = model_.current_material;
            switch (*p) {
                case 'k':
                case 'K':
                    ++p;
                    if (*p == 'a' || *p == 'd' || *p == 's' || *p == 'e') {
                        const char which = *p++;
                        if (m) colour(p, which == 'a' ? m->ambient : which == 'd' ? m->diffuse : which == 's' ? m->specular : m->emissive);
                    }
                    p = skip_line(p);
                    break;
                case 'T':
                    ++p;
                    if (*p == 'f') {
                        ++p;
                        if (m) colour(p, m->transparent);
                    } else if (*p == 'r') {
                        ++p;
                        const float d = float_value(p, 0.0f);
                        if (m) m->alpha = 1.0f - d;
                    }
                    p = skip_line(p);
                    break;
                case 'd':
                    if (p[1] == 'i' && p[2] == 's' && p[3] == 'p') {
                        p = texture(p);
                    } else {
                        ++p;
                        if (m) m->alpha = float_value(p, 0.0f);
                        p = skip_line(p);
                    }
                    break;
                case 'N':
                case 'n':
                    ++p;
                    if (*p == 's') {
                        ++p;
                        if (m) m->shininess = float_value(p, 0.0f);
                    } else if (*p == 'i') {
                        ++p;
                        if (m) m->ior = float_value(p, 0.0f);
                    } else if (*p == 'e') {
                        p = new_material(p);
                    } else if (*p == 'o') {
                        p = texture(p - 1);
                    }
                    p = skip_line(p);
                    break;
                case 'P':
                    ++p;
                    if (*p == 'r') {
                        ++p;
                        if (m) m->roughness_factor = maybe_float(p);
                    } else if (*p == 'm') {
                        ++p;
                        if (m) m->metallic_factor = maybe_float(p);
                    } else if (*p == 's') {
                        ++p;
                        if (m) {
                            aiColor3D c;
                            colour(p, c);
                            m->sheen_colour = c;
                        }
                    } else if (*p == 'c') {
                        ++p;
                        if (*p == 'r') {
                            ++p;
                            if (m) m->clearcoat_roughness = maybe_float(p);
                        } else if (m) {
                            m->clearcoat_thickness = maybe_float(p);
                        }
                    }
                    p = skip_line(p);
                    break;
                case 'm':
                case 'b':
                case 'r':
                    p = skip_line(texture(p));
                    break;
                case 'i':
                    p = next_token(p);
                    if (m) m->illumination = atoi_word(p);
                    p = skip_line(p);
                    break;
                case 'a':
                    if (!m) throw Decline{__LINE__};  // assimp reads through a null material here
                    ++p;
                    m->anisotropy = float_value(p, 0.0f);
                    p = skip_line(p);
                    break;
                default: p = skip_line(p); break;
            }
        }
    }

private:
    // skipLine: past the line end, then past the next line's leading spaces and tabs.
    const char* skip_line(const char* p) const {
        while (p < end_ - 1 && !ends_line(*p)) ++p;
        if (p != end_) ++p;
        while (p != end_ && is_space(*p)) ++p;
        return p;
    }

    // CopyNextWord: the next word (possibly empty), p moved past it.
    std::string_view next_word(const char*& p) const {
        p = skip_blanks(p);
        const std::string_view w = word_at(p);
        p += w.size();
        return w;
    }

    // getFloat: the next word's number; a missing one makes assimp throw.
    float get_float(const char*& p) const { return word_float(next_word(p)); }

    // getFloatValue: the next word's number, or `empty` when there is none.
    float float_value(const char*& p, float empty) const {
        const std::string_view w = next_word(p);
        return w.empty() ? empty : word_float(w);
    }
    std::optional<float> maybe_float(const char*& p) const {
        const std::string_view w = next_word(p);
        if (w.empty()) return std::nullopt;
        return word_float(w);
    }

    // getIlluminationModel: atoi of the next word (declined when atoi's result is not plain).
    int atoi_word(const char*& p) const {
        const std::string_view w = next_word(p);
        std::size_t digits = 0;
        const std::size_t sign = !w.empty() && (w[0] == '-' || w[0] == '+');
        while (sign + digits < w.size() && w[sign + digits] >= '0' && w[sign + digits] <= '9') ++digits;
        if (digits > 9) throw Decline{__LINE__};
        return std::atoi(std::string(w).c_str());
    }

    // getColorRGBA: r, and g and b when more follows on the line; missing ones stay 0.
    void colour(const char*& p, aiColor3D& out) const {
        float r = get_float(p), g = 0, b = 0;
        if (!ends_line(*p)) {
            g = get_float(p);
            b = get_float(p);
        }
        out = {r, g, b};
    }

    // createMaterial: "newmtl NAME" (the rest of the line, trailing spaces cut; none: DefaultMaterial).
    const char* new_material(const char* p) {
        const std::string_view line = rest_of_line(p);
        std::string name;
        const std::size_t first_space = line.find_first_of(" \t");
        const std::size_t first_word = first_space == std::string_view::npos ? first_space : line.find_first_not_of(" \t", first_space);
        if (first_word == std::string_view::npos)
            name = "DefaultMaterial";  // one token only
        else
            name = std::string(line.substr(first_word));
        while (!name.empty() && is_space(name.back())) name.pop_back();
        auto it = model_.materials.find(name);
        if (it == model_.materials.end()) {
            ObjMaterial& m = model_.add_material(name);
            model_.current_material = &m;
            if (model_.current_mesh >= 0) model_.meshes[static_cast<std::size_t>(model_.current_mesh)].material = m.index;
        } else {
            model_.current_material = &it->second;
        }
        return p + line.size();
    }

    // getTexture: the statement at p ("map_Kd [options] NAME", "bump ...", ...).
    const char* texture(const char* p) {
        struct Keyword {
            const char* word;
            int slot;
        };
        static const Keyword keywords[] = {{"map_Kd", diffuse},         {"map_Ka", ambient},      {"map_Ks", specular},
                                           {"map_disp", displacement},  {"disp", displacement},   {"map_d", opacity},
                                           {"map_emissive", emissive},  {"map_Ke", emissive},     {"map_bump", bump},
                                           {"bump", bump},              {"map_Kn", normal},       {"norm", normal},
                                           {"refl", -1},                {"map_ns", specularity},  {"map_Pr", roughness},
                                           {"map_Pm", metallic},        {"map_Ps", sheen}};
        int slot = -2;
        for (const Keyword& k : keywords)
            if (starts_with_nocase(p, k.word)) {
                slot = k.slot;
                break;
            }
        if (slot == -1) return p;  // reflection statements are skipped
        if (slot == -2) {
            notes_.error("OBJ/MTL: Encountered unknown texture type");
            return p;
        }
        ObjMaterial* m = model_.current_material;
        if (!m) throw Decline{__LINE__};  // assimp writes through a null material here
        int clamp_slot = slot, reflection_face = -1;
        bool clamp = false;
        p = next_token(p);
        // getTextureOption: "-clamp on", "-type sphere", "-bm 0.5", ... each with its values.
        while (p < end_ - 1 && *p == '-') {
            int skip = 1;
            if (starts_with_nocase(p, "-clamp")) {
                const char* v = next_token(p);
                clamp = strncasecmp(std::string(word_at(v).substr(0, 2)).c_str(), "on", 2) == 0;
                skip = 2;
            } else if (starts_with_nocase(p, "-type")) {
                const std::string value(word_at(next_token(p)).substr(0, 11));
                // Each type's clamp slot and face (the sphere map is face 0, as the cube's top).
                static const Keyword types[] = {{"cube_top", reflection_cube_top},       {"cube_bottom", reflection_cube_bottom},
                                                {"cube_front", reflection_cube_front},   {"cube_back", reflection_cube_back},
                                                {"cube_left", reflection_cube_left},     {"cube_right", reflection_cube_right},
                                                {"sphere", reflection_sphere}};
                for (const Keyword& t : types)
                    if (starts_with_nocase(value.c_str(), t.word)) {
                        clamp_slot = t.slot;
                        reflection_face = t.slot == reflection_sphere ? 0 : t.slot - reflection_cube_top;
                        break;
                    }
                skip = 2;
            } else if (starts_with_nocase(p, "-bm")) {
                const char* v = next_token(p);
                m->bump_multiplier = get_float(v);
                skip = 2;
            } else if (starts_with_nocase(p, "-blendu") || starts_with_nocase(p, "-blendv") || starts_with_nocase(p, "-boost") ||
                       starts_with_nocase(p, "-texres") || starts_with_nocase(p, "-imfchan")) {
                skip = 2;
            } else if (starts_with_nocase(p, "-mm")) {
                skip = 3;
            } else if (starts_with_nocase(p, "-o") || starts_with_nocase(p, "-s") || starts_with_nocase(p, "-t")) {
                skip = 4;
            }
            for (int i = 0; i < skip; ++i) p = next_token(p);
        }
        m->clamp[clamp_slot] = clamp;
        const std::string_view name = rest_of_line(p);  // getName: trailing spaces kept
        if (name.size() > k_max_name) throw Decline{__LINE__};
        (reflection_face >= 0 ? m->reflection[reflection_face] : m->texture[slot]) = std::string(name);
        return p + name.size();
    }

    ObjModel& model_;
    ImportNotes& notes_;
    const char* end_ = nullptr;
};

// ---- OBJ lines (ObjFileParser)

class ObjReader {
public:
    ObjReader(const std::string& path, const LoadOptions& options, const ResourceRoots& roots, ImportNotes& notes)
        : path_(path), options_(options), roots_(roots), notes_(notes) {
        model_.current_material = nullptr;
        model_.add_material("DefaultMaterial");
    }

    ObjModel& model() { return model_; }

    void read(std::string_view text) {
        const bool backslash = survey(text);
        // A backslash before a line end joins lines in assimp's reading (and at the end of a 16 MiB
        // block it reads past the block): declined.
        for (const char* b = backslash ? static_cast<const char*>(std::memchr(text.data(), '\\', text.size())) : nullptr; b;
             b = static_cast<const char*>(std::memchr(b + 1, '\\', static_cast<std::size_t>(text.data() + text.size() - b - 1)))) {
            const std::size_t at = static_cast<std::size_t>(b - text.data());
            if (at + 1 == text.size() || ends_line(b[1]) || (at + 1) % k_stream_block == 0) throw Decline{__LINE__};
        }
        std::size_t end = text.size();
        // In a file read in more than one block, a last line without a line end is lost.
        if (text.size() > k_stream_block && !ends_line(text.back()))
            while (end > 0 && !ends_line(text[end - 1])) --end;
        readable_end_ = text.data() + text.size() + 1;  // the NUL
        const char* const limit = text.data() + end;
        bool in_cstype = false;
        for (std::size_t begin = 0; begin < end;) {
            const char* line = text.data() + begin;
            const char* stop = nullptr;
            if (!in_cstype) {
                // The common lines first, in this loop (runs of them in loops of their own); then
                // every line's statement.
                if (line[0] == 'v' && is_space(line[1])) {
                    if (const char* next = plain_vertices(line, limit); next != line) {
                        begin = static_cast<std::size_t>(next - text.data());
                        continue;
                    }
                    stop = plain_vertex(line + 1);
                } else if (line[0] == 'f' && is_space(line[1])) {
                    if (const char* next = face_run(line, limit); next != line) {
                        begin = static_cast<std::size_t>(next - text.data());
                        continue;
                    }
                    stop = plain_face(line + 1);
                }
                else if (line[0] == 'v' && line[1] == 't' && is_space(line[2]))
                    stop = plain_texcoord(line + 2);
                else if (line[0] == 'v' && line[1] == 'n' && is_space(line[2]))
                    stop = plain_normal(line + 2);
                if (!stop) stop = read_line(line, in_cstype);
            } else if (*line == 'e' && word_at(line) == "end")
                in_cstype = false;
            if (!stop)
                for (stop = line; !ends_line(*stop);) ++stop;
            begin = static_cast<std::size_t>(stop - text.data()) + 1;
        }
    }

private:
    // One pass over the text, 16 bytes at a time: a NUL declines the file; the arrays are sized
    // once for the vertices and faces its lines announce (lines starting "v " and "f"; three
    // corners a face), so that they are not grown and copied while read. Returns whether the text
    // has a backslash.
    bool survey(std::string_view text) {
        std::size_t v = 0, f = 0;
        bool nul = false, backslash = false;
        const std::size_t n = text.size();
        const unsigned char* t = reinterpret_cast<const unsigned char*>(text.data());
        // 16 bytes at a time in byte-wide counters (added up every 255 steps, before they overflow).
        using Bytes = unsigned char __attribute__((vector_size(16)));
        const auto load = [](const unsigned char* p) {
            Bytes b;
            std::memcpy(&b, p, sizeof b);
            return b;
        };
        std::size_t i = 0;
        while (i + 18 <= n) {
            Bytes vs{}, fs{}, nuls{}, backslashes{};
            for (int k = 0; k < 255 && i + 18 <= n; ++k, i += 16) {
                const Bytes here = load(t + i), next = load(t + i + 1);
                const Bytes line = reinterpret_cast<Bytes>(here == '\n');
                vs -= line & reinterpret_cast<Bytes>(next == 'v') & reinterpret_cast<Bytes>(load(t + i + 2) == ' ');
                fs -= line & reinterpret_cast<Bytes>(next == 'f');
                nuls |= reinterpret_cast<Bytes>(here == 0);
                backslashes |= reinterpret_cast<Bytes>(here == '\\');
            }
            for (int k = 0; k < 16; ++k) v += vs[k], f += fs[k], nul |= nuls[k] != 0, backslash |= backslashes[k] != 0;
        }
        for (; i < n; ++i) {
            v += i + 2 < n && t[i] == '\n' && t[i + 1] == 'v' && t[i + 2] == ' ';
            f += i + 1 < n && t[i] == '\n' && t[i + 1] == 'f';
            nul |= t[i] == 0;
            backslash |= t[i] == '\\';
        }
        if (nul) throw Decline{__LINE__};
        v += n > 0 && t[0] == 'v';
        f += n > 0 && t[0] == 'f';
        f = std::min(f, options_.max_triangles);
        detail::reserve_in_huge_pages(model_.vertices, v);
        detail::reserve_in_huge_pages(model_.corner_v, 3 * f);
        model_.announced_faces = f;
        return backslash;
    }

    // A line's statement; the line's end when the statement found it.
    const char* read_line(const char* line, bool& in_cstype) {
        switch (line[0]) {
            case 'v':
                if (is_space(line[1]))
                    return vertex(line + 1);
                else if (line[1] == 't')
                    texcoord(line + 2);
                else if (line[1] == 'n')
                    normal(line + 2);
                break;
            case 'f': return face(line);
            case 'p':
            case 'l': throw Decline{__LINE__};  // points and lines: meshes sorted by primitive type
            case 'u':
                if (word_at(line) == "usemtl") use_material(line);
                break;
            case 'm': {
                const std::string_view w = word_at(line);
                if (w == "mtllib") material_library(line);
                break;
            }
            case 'g': group(line); break;
            case 'o': object(line); break;
            case 'c': in_cstype = word_at(line) == "cstype"; break;
            default: break;  // comments, 's', 'mg', indented lines, anything else
        }
        return nullptr;
    }

    // "v x y z", "v x y z w" (divided by w) or "v x y z r g b"; other counts of numeric-looking
    // tokens are ignored, as assimp ignores them. Returns the line's end for the common form.
    // The common "v x y z" of "%f" numbers (read_plain_float's) and the line end: the line's end,
    // or null (nothing done) for vertex() to read.
    [[gnu::always_inline]] const char* plain_vertex(const char* c) {
        float x, y, z;
        const char* p = read_plain_float(skip_blanks(c), x, readable_end_);
        p = p && is_space(*p) ? read_plain_float(skip_blanks(p), y, readable_end_) : nullptr;
        p = p && is_space(*p) ? read_plain_float(skip_blanks(p), z, readable_end_) : nullptr;
        if (!p || !ends_line(*(p = skip_blanks(p)))) return nullptr;
        model_.vertices.push_back({x, y, z});  // finite: read as at most 7 + 7 digits
        return p;
    }

    // A run of plain_vertex's lines from `line` (before `limit`), read as it reads each, without a
    // turn of the line loop each: the start of the first line not taken (`line` when none).
    const char* plain_vertices(const char* line, const char* limit) {
        std::vector<aiVector3D>& vertices = model_.vertices;
        for (; line < limit && line[0] == 'v' && is_space(line[1]);) {
            float xyz[3];
            const char* p = plain_vertex_of_masks(line, xyz);
            if (!p) {
                p = read_plain_float(skip_blanks(line + 1), xyz[0], readable_end_);
                p = p && is_space(*p) ? read_plain_float(skip_blanks(p), xyz[1], readable_end_) : nullptr;
                p = p && is_space(*p) ? read_plain_float(skip_blanks(p), xyz[2], readable_end_) : nullptr;
                if (!p || !ends_line(*(p = skip_blanks(p)))) break;
            }
            vertices.push_back({xyz[0], xyz[1], xyz[2]});
            line = p + 1;
        }
        return line;
    }

#if defined(__SSE2__)
    // Bit masks of 16 bytes from `at`: decimal digits, blanks (space, tab), '.' and '-'.
    struct Masks {
        std::uint64_t digits = 0, blanks = 0, dots = 0, minus = 0;
    };
    [[gnu::always_inline]] static void add_masks(const char* at, int shift, Masks& m) {
        const __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(at));
        const __m128i d = _mm_sub_epi8(x, _mm_set1_epi8('0'));  // a digit: 0..9
        const auto bits = [&](__m128i lanes) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(_mm_movemask_epi8(lanes))) << shift; };
        m.digits |= bits(_mm_cmpeq_epi8(_mm_min_epu8(d, _mm_set1_epi8(9)), d));
        m.blanks |= bits(_mm_or_si128(_mm_cmpeq_epi8(x, _mm_set1_epi8(' ')), _mm_cmpeq_epi8(x, _mm_set1_epi8('\t'))));
        m.dots |= bits(_mm_cmpeq_epi8(x, _mm_set1_epi8('.')));
        m.minus |= bits(_mm_cmpeq_epi8(x, _mm_set1_epi8('-')));
    }
#endif

    // plain_vertex's line at `line` ('v' and a blank checked) when it lies in its first 48 bytes,
    // read from bit masks of them: each number "[-]D.F" with 1 to 7 digits each side (where
    // read_plain_float reads them, by its arithmetic), blanks between them, then the line's end.
    // Its line end, or null (nothing read) for read_plain_float's reading.
    [[gnu::always_inline]] const char* plain_vertex_of_masks(const char* line, float* xyz) const {
#if defined(__SSE2__)
        if (readable_end_ - line < 64) return nullptr;
        Masks m;
        add_masks(line, 0, m);
        add_masks(line + 16, 16, m);
        add_masks(line + 32, 32, m);
        const auto run = [](std::uint64_t mask, unsigned at) { return static_cast<unsigned>(std::countr_zero(~(mask >> at))); };
        unsigned at = 1 + run(m.blanks, 1);  // at most 48
        for (int k = 0; k < 3; ++k) {
            const unsigned negative = static_cast<unsigned>(m.minus >> at & 1);
            at += negative;
            const unsigned n = run(m.digits, at);  // at + n at most 48
            if (n - 1 >= 7 || !(m.dots >> (at + n) & 1)) return nullptr;
            const unsigned fraction_at = at + n + 1;
            const unsigned f = run(m.digits, fraction_at);
            if (f - 1 >= 7) return nullptr;
            std::uint64_t whole, fraction;
            std::memcpy(&whole, line + at, sizeof whole);  // within the 64 bytes
            std::memcpy(&fraction, line + fraction_at, sizeof fraction);
            float value = static_cast<float>(static_cast<std::int64_t>(text_detail::digits_value(whole, n)));
            value += static_cast<float>(static_cast<double>(static_cast<std::int64_t>(text_detail::digits_value(fraction, f))) *
                                        Assimp::fast_atof_table[f]);
            xyz[k] = std::bit_cast<float>(std::bit_cast<std::uint32_t>(value) ^ negative << 31);
            at = fraction_at + f;
            const unsigned blanks = run(m.blanks, at);
            if (k < 2 && blanks == 0) return nullptr;
            at += blanks;
        }
        return ends_line(line[at]) ? line + at : nullptr;
#else
        (void)line, (void)xyz;
        return nullptr;
#endif
    }

    // A run of face lines from `line` (before `limit`) in one of the two forms that have loops of
    // their own, as the current mesh allows: the start of the first line not taken (`line` when none).
    const char* face_run(const char* line, const char* limit) {
        if (model_.current_object < 0 || model_.current_mesh < 0 || model_.total_triangles >= options_.max_triangles) return line;
        ObjMesh& mesh = model_.meshes[static_cast<std::size_t>(model_.current_mesh)];
        const std::size_t most = options_.max_triangles - model_.total_triangles;
        if (mesh.uv_count == 0 && !mesh.has_normals) return plain_triangles(line, limit, mesh, most);
        // Corners "v/vt/vn" where both arrays have values and this mesh's corners have both (each
        // face of it adds its corners to all three arrays).
        if (mesh.uv_count != 0 && mesh.has_normals && !model_.texcoords.empty() && !model_.normals.empty() &&
            model_.corner_vt.size() == model_.corner_v.size() && model_.corner_vn.size() == model_.corner_v.size())
            return attributed_triangles(line, limit, mesh, most);
        return line;
    }

    // A run of "f a b c" lines of plain indices (plain_face's form of three corners, which
    // add_plain_triangle takes) in a mesh without texture coordinates and normals, at most `most`:
    // the mesh's counts kept in registers and the corners gathered in batches until the run ends.
    const char* plain_triangles(const char* line, const char* limit, ObjMesh& mesh, std::size_t most) {
        constexpr std::size_t k_batch = 512;
        std::uint32_t batch[3 * k_batch];
        std::size_t in_batch = 0, taken = 0;
        const auto flush = [&] {
            model_.corner_v.insert(model_.corner_v.end(), batch, batch + 3 * in_batch);
            model_.add_triangles(in_batch);
            taken += in_batch;
            in_batch = 0;
        };
        std::uint32_t largest = model_.largest_vertex;
        while (taken + in_batch < most && line < limit && line[0] == 'f' && is_space(line[1])) {
            std::uint32_t* const v = batch + 3 * in_batch;
            const char* p = single_spaced_triangle(line, v);
            if (!p) {
                p = read_plain_index<false>(skip_blanks(line + 1), v[0]);
                p = p && is_space(*p) ? read_plain_index<false>(skip_blanks(p), v[1]) : nullptr;
                p = p && is_space(*p) ? read_plain_index<false>(skip_blanks(p), v[2]) : nullptr;
                if (!p || !ends_line(*(p = skip_blanks(p)))) break;
            }
            largest = std::max(largest, std::max(v[0], std::max(v[1], v[2])));
            line = p + 1;
            if (++in_batch == k_batch) flush();
        }
        flush();
        end_triangle_run(mesh, taken, largest, false);
        return line;
    }

    // What a run of `taken` triangles adds to the mesh's and the model's counts (their corners'
    // texture coordinate indices too when `uvs`), once at the run's end.
    void end_triangle_run(ObjMesh& mesh, std::size_t taken, std::uint32_t largest, bool uvs) {
        mesh.faces += taken;
        mesh.triangles += taken;
        mesh.corners += 3 * taken;
        if (uvs) mesh.uv_count += 3 * taken;
        model_.total_triangles += taken;
        model_.largest_vertex = largest;
    }

    // A run of "f a/b/c a/b/c a/b/c" lines (plain_face_with_attributes's lists, three each, as
    // add_face adds them to a mesh whose corners have texture coordinates and normals) when each
    // corner is read by attributed_corner, at most `most`: the mesh's counts kept in registers and
    // the corners gathered in batches until the run ends.
    const char* attributed_triangles(const char* line, const char* limit, ObjMesh& mesh, std::size_t most) {
        constexpr std::size_t k_batch = 512;
        std::uint32_t batch[3][3 * k_batch];  // vertex, texture coordinate, normal indices
        std::size_t in_batch = 0, taken = 0;
        const auto flush = [&] {
            model_.corner_v.insert(model_.corner_v.end(), batch[0], batch[0] + 3 * in_batch);
            model_.corner_vt.insert(model_.corner_vt.end(), batch[1], batch[1] + 3 * in_batch);
            model_.corner_vn.insert(model_.corner_vn.end(), batch[2], batch[2] + 3 * in_batch);
            model_.add_triangles(in_batch);
            taken += in_batch;
            in_batch = 0;
        };
        std::uint32_t largest = model_.largest_vertex;
        while (taken + in_batch < most && line < limit && line[0] == 'f' && is_space(line[1])) {
            const char* p = line + 2;
            for (std::size_t k = 0; p && k < 3; ++k) {
                p = attributed_corner(p, batch[0][3 * in_batch + k], batch[1][3 * in_batch + k], batch[2][3 * in_batch + k]);
                if (p && !(k < 2 ? is_space(*p++) : ends_line(*p))) p = nullptr;
            }
            if (!p) break;
            const std::uint32_t* v = batch[0] + 3 * in_batch;
            largest = std::max(largest, std::max(v[0], std::max(v[1], v[2])));
            line = p + 1;
            if (++in_batch == k_batch) flush();
        }
        flush();
        end_triangle_run(mesh, taken, largest, true);
        return line;
    }

    // The corner "A/B/C" at p, each index 1 to 8 digits without a leading zero (read_plain_index's),
    // read from bit masks of its 32 bytes (digits and slashes): the byte after it, or null (nothing
    // read).
    [[gnu::always_inline]] const char* attributed_corner(const char* p, std::uint32_t& v, std::uint32_t& vt, std::uint32_t& vn) const {
#if defined(__SSE2__)
        if (readable_end_ - p < 40) return nullptr;
        std::uint32_t digits = 0, slashes = 0;
        for (int half = 0; half < 2; ++half) {
            const __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + 16 * half));
            const __m128i d = _mm_sub_epi8(x, _mm_set1_epi8('0'));  // a digit: 0..9
            digits |= static_cast<std::uint32_t>(_mm_movemask_epi8(_mm_cmpeq_epi8(_mm_min_epu8(d, _mm_set1_epi8(9)), d))) << 16 * half;
            slashes |= static_cast<std::uint32_t>(_mm_movemask_epi8(_mm_cmpeq_epi8(x, _mm_set1_epi8('/')))) << 16 * half;
        }
        std::uint32_t* const out[3] = {&v, &vt, &vn};
        std::uint32_t at = 0;
        for (int j = 0; j < 3; ++j) {
            const auto n = static_cast<std::uint32_t>(std::countr_zero(~(digits >> at)));  // at most 32 - at
            if (n - 1 >= 8 || p[at] == '0') return nullptr;
            std::uint64_t word;
            std::memcpy(&word, p + at, sizeof word);  // at most 26 bytes from p
            *out[j] = static_cast<std::uint32_t>(text_detail::digits_value(word, n) - 1);
            at += n;  // at most 26
            if (j < 2 && !(slashes >> at++ & 1)) return nullptr;
        }
        return is_blank(p[at]) ? p + at : nullptr;
#else
        (void)p, (void)v, (void)vt, (void)vn;
        return nullptr;
#endif
    }

    // The line "f A B C" at `line` ('f' checked) when each of its separators is one space or tab
    // and it ends right after C, each index 1 to 8 digits without a leading zero (the lines
    // read_plain_index's reading above takes, in this form), read from 32 bytes at once: the digits
    // and blanks as bit masks, each index's end the first byte past its run of digits. Its line end,
    // or null (nothing read) for that reading.
    [[gnu::always_inline]] const char* single_spaced_triangle(const char* line, std::uint32_t* v) const {
#if defined(__SSE2__)
        if (readable_end_ - line < 32) return nullptr;
        const auto masks = [](const char* at, std::uint32_t& digits, std::uint32_t& blanks) {
            const __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(at));
            const __m128i d = _mm_sub_epi8(x, _mm_set1_epi8('0'));  // a digit: 0..9
            digits = static_cast<std::uint32_t>(_mm_movemask_epi8(_mm_cmpeq_epi8(_mm_min_epu8(d, _mm_set1_epi8(9)), d)));
            blanks = static_cast<std::uint32_t>(
                _mm_movemask_epi8(_mm_or_si128(_mm_cmpeq_epi8(x, _mm_set1_epi8(' ')), _mm_cmpeq_epi8(x, _mm_set1_epi8('\t')))));
        };
        std::uint32_t digits_low, blanks_low, digits_high, blanks_high;
        masks(line, digits_low, blanks_low);
        masks(line + 16, digits_high, blanks_high);
        const std::uint32_t digits = digits_low | digits_high << 16, blanks = blanks_low | blanks_high << 16;
        if (!(blanks >> 1 & 1)) return nullptr;
        std::uint32_t at = 2;  // the index's first digit
        for (int k = 0; k < 3; ++k) {
            const auto n = static_cast<std::uint32_t>(std::countr_zero(~(digits >> at)));  // at most 32 - at
            if (n - 1 >= 8 || line[at] == '0') return nullptr;
            std::uint64_t word;
            std::memcpy(&word, line + at, sizeof word);  // at most 28 bytes from line
            v[k] = static_cast<std::uint32_t>(text_detail::digits_value(word, n) - 1);
            at += n;  // at most 26
            if (k < 2 ? !(blanks >> at & 1) : !ends_line(line[at])) return nullptr;
            ++at;
        }
        return line + at - 1;
#else
        (void)line, (void)v;
        return nullptr;
#endif
    }

    // Up to `most` plain numbers (read_plain_float's, each followed by a blank) from c, into out, and
    // the line's end after them: their count, or 0 where the line holds anything else.
    [[gnu::always_inline]] std::size_t plain_floats(const char*& c, float* out, std::size_t most) const {
        const char* p = skip_blanks(c);
        std::size_t n = 0;
        while (n < most && !ends_line(*p)) {
            p = read_plain_float(p, out[n], readable_end_);
            if (!p || !is_blank(*p)) return 0;
            ++n;
            p = skip_blanks(p);
        }
        if (!ends_line(*p)) return 0;
        c = p;
        return n;
    }

    // The common "vt u v" and "vt u v w" of plain numbers (texcoord()'s, whose token count they
    // are and whose values are finite): the line's end, or null (nothing done) for texcoord().
    [[gnu::always_inline]] const char* plain_texcoord(const char* c) {
        float t[3] = {0, 0, 0};
        const std::size_t n = plain_floats(c, t, 3);
        if (n < 2) return nullptr;
        model_.texcoords.push_back({t[0], t[1], t[2]});
        model_.texcoord_dim = std::max(model_.texcoord_dim, static_cast<unsigned>(n));
        return c;
    }

    // The common "vn x y z" of plain numbers (normal()'s first three words): the line's end, or
    // null (nothing done) for normal().
    [[gnu::always_inline]] const char* plain_normal(const char* c) {
        float n[3];
        if (plain_floats(c, n, 3) != 3) return nullptr;
        model_.normals.push_back({n[0], n[1], n[2]});
        return c;
    }

    const char* vertex(const char* c) {
        // Three plain numbers (other than plain_vertex's), then other forms.
        const char* p = c;
        aiVector3D v;
        bool plain = true;
        float* out[3] = {&v.x, &v.y, &v.z};
        for (float* o : out) {
            p = skip_blanks(p);
            if (!((*p >= '0' && *p <= '9') || *p == '-' || *p == '.')) {
                plain = false;
                break;
            }
            const char* start = p;
            try {
                p = read_float(p, *o, readable_end_);
            } catch (const NotANumber&) {
                throw Decline{__LINE__};
            }
            if (p == start || !is_blank(*p) || static_cast<std::size_t>(p - start) > k_max_word) {
                plain = false;
                break;
            }
        }
        if (plain && ends_line(*(p = skip_blanks(p)))) {
            add_position(v);
            return p;
        }
        const std::size_t n = numeric_tokens(c);
        p = c;
        if (n == 3) {
            add_position({next_float(p), next_float(p), next_float(p)});
        } else if (n == 4) {
            const float x = next_float(p), y = next_float(p), z = next_float(p), w = next_float(p);
            if (w == 0) throw Decline{__LINE__};
            add_position({x / w, y / w, z / w});
        } else if (n == 6) {
            add_position({next_float(p), next_float(p), next_float(p)});
            model_.colours.push_back({next_float(p), next_float(p), next_float(p)});
        }
        return nullptr;
    }

    void add_position(const aiVector3D& v) {
        if (non_finite(v)) throw Decline{__LINE__};  // left to assimp, whose conversion drops such triangles
        model_.vertices.push_back(v);
    }

    // getNumComponentsInDataDefinition: tokens that start like a number (a digit, '+', '-', or
    // "nan"/"inf" in any case).
    static std::size_t numeric_tokens(const char* c) {
        std::size_t n = 0;
        for (c = skip_blanks(c); !ends_line(*c); c = skip_blanks(c)) {
            n += (*c >= '0' && *c <= '9') || *c == '-' || *c == '+' || starts_with_nocase(c, "nan") || starts_with_nocase(c, "inf");
            while (!is_blank(*c)) ++c;
        }
        return n;
    }

    // "vt u v" or "vt u v w"; non-finite values become 0.
    void texcoord(const char* c) {
        if (!is_space(*c)) throw Decline{__LINE__};
        const std::size_t n = numeric_tokens(c);
        if (n != 2 && n != 3) throw Decline{__LINE__};  // assimp: "Invalid number of components"
        const char* p = c;
        aiVector3D t;
        t.x = next_float(p);
        t.y = next_float(p);
        t.z = n == 3 ? next_float(p) : 0.0f;
        for (float* f : {&t.x, &t.y, &t.z})
            if (!std::isfinite(*f)) *f = 0;
        model_.texcoords.push_back(t);
        model_.texcoord_dim = std::max(model_.texcoord_dim, static_cast<unsigned>(n));
    }

    void normal(const char* c) {
        if (!is_space(*c)) throw Decline{__LINE__};
        const char* p = c;
        const aiVector3D n{next_float(p), next_float(p), next_float(p)};
        if (non_finite(n)) throw Decline{__LINE__};
        model_.normals.push_back(n);
    }

    // getFace: indices separated by '/' (vertex, texture coordinate, normal) and corners by spaces.
    // Returns the line's end.
    // The common "f 1 2 3" (from c, past the 'f'): vertex indices alone, each plain
    // (read_plain_index's), up to 8 corners. The line's end, or null (nothing done) for face().
    // Also "f 1/2/3 ...", "f 1/2 ..." and "f 1//3 ...": face()'s lists of each corner's plain indices
    // (plain_face_with_attributes).
    [[gnu::always_inline]] const char* plain_face(const char* c) {
        std::uint32_t v[8];
        std::size_t corners = 0;
        const char* p = skip_blanks(c);
        for (const char* e; corners < 8 && (e = read_plain_index<false>(p, v[corners]));) {
            ++corners;
            p = e;
            if (!is_space(*p)) break;  // the line's end
            p = skip_blanks(p + 1);
        }
        if (corners == 0) return plain_face_with_attributes(p);
        if (!ends_line(*p)) return nullptr;
        if (corners != 3 || !add_plain_triangle(v)) add_face(v, corners, nullptr, 0, nullptr, 0);
        return p;
    }

    // Corners of plain indices separated by slashes, up to 8, each index in the list of face()'s
    // position (the slashes before it; the second names a normal when only normals were read):
    // the line's end, or null (nothing done) for face().
    const char* plain_face_with_attributes(const char* p) {
        const bool vt = !model_.texcoords.empty(), vn = !model_.normals.empty();
        std::uint32_t lists[3][8];
        std::size_t counts[3] = {0, 0, 0};
        while (!ends_line(*p)) {
            if (counts[0] == 8) return nullptr;
            for (std::size_t position = 0;;) {
                if (position == 1 && !vt && vn) position = 2;
                if (position > 2 || counts[position] == 8) return nullptr;
                const char* e = read_plain_index<true>(p, lists[position][counts[position]]);
                if (!e) return nullptr;
                ++counts[position];
                for (p = e; *p == '/'; ++p) ++position;
                if (p == e) break;
            }
            p = skip_blanks(p);
        }
        add_face(lists[0], counts[0], lists[1], counts[1], lists[2], counts[2]);
        return p;
    }

    const char* face(const char* line) {
        const char* p = next_token(line);
        for (std::vector<std::uint32_t>& l : lists_) l.clear();
        const std::int64_t sizes[3] = {static_cast<std::int64_t>(model_.vertices.size()),
                                       static_cast<std::int64_t>(model_.texcoords.size()),
                                       static_cast<std::int64_t>(model_.normals.size())};
        const bool vt = !model_.texcoords.empty(), vn = !model_.normals.empty();
        int position = 0;
        while (!ends_line(*p)) {
            if (*p == '/') {
                ++position;
                ++p;
                continue;
            }
            if (is_space(*p)) {
                position = 0;
                ++p;
                continue;
            }
            // atoi's number, which must be plain for assimp to step over it as one: no leading
            // zero or '+', at most nine digits, ending at '/', a space or the line end.
            const bool negative = *p == '-';
            const char* d = p + negative;
            if (*d < '1' || *d > '9') throw Decline{__LINE__};
            std::int64_t value = 0;
            const char* e = d;
            while (*e >= '0' && *e <= '9') value = value * 10 + (*e++ - '0');
            if (e - d > 9 || !(*e == '/' || is_blank(*e))) throw Decline{__LINE__};
            p = e;
            if (position == 1 && !vt && vn) position = 2;  // no texture coordinates: "1/2" names a normal
            if (position > 2) throw Decline{__LINE__};     // assimp then reads on past the line
            const std::int64_t index = negative ? sizes[position] - value : value - 1;
            lists_[position].push_back(index < 0 || index >= 0x7fffffff ? k_out_of_range : static_cast<std::uint32_t>(index));
        }
        add_face(lists_[0].data(), lists_[0].size(), lists_[1].data(), lists_[1].size(), lists_[2].data(), lists_[2].size());
        return p;
    }

    // A vertex index as the face's reading below takes it ("[1-9]D{0,7}" then a space or line end),
    // minus one, from one 8-byte word when 9 bytes from p may be read: its end, or null.
    // `Slash`: a '/' may end it too.
    template <bool Slash>
    [[gnu::always_inline]] const char* read_plain_index(const char* p, std::uint32_t& index) const {
        if (readable_end_ - p < 9) return nullptr;
        std::uint64_t word;
        std::memcpy(&word, p, sizeof word);
        const unsigned n = text_detail::leading_digits(word);
        if (n == 0 || (word & 0xFF) == '0' || !(is_blank(p[n]) || (Slash && p[n] == '/'))) return nullptr;
        index = static_cast<std::uint32_t>(text_detail::digits_value(word, n) - 1);
        return p + n;
    }

    // add_face's work for three vertex indices alone in a mesh without texture coordinates and
    // normals, below the triangle limit; false where add_face must do it.
    [[gnu::always_inline]] bool add_plain_triangle(const std::uint32_t* v) {
        if (model_.current_object < 0 || model_.current_mesh < 0 || model_.total_triangles >= options_.max_triangles) return false;
        ObjMesh& mesh = model_.meshes[static_cast<std::size_t>(model_.current_mesh)];
        if (mesh.uv_count != 0 || mesh.has_normals) return false;
        ++mesh.faces;
        ++mesh.triangles;
        ++model_.total_triangles;
        mesh.corners += 3;
        model_.largest_vertex = std::max(model_.largest_vertex, std::max(v[0], std::max(v[1], v[2])));
        model_.add_triangles(1);
        model_.corner_v.insert(model_.corner_v.end(), v, v + 3);
        return true;
    }

    // A face's corners (vertex indices, and the texture coordinate and normal indices given) into
    // the current mesh.
    void add_face(const std::uint32_t* v, std::size_t corners, const std::uint32_t* vt, std::size_t vts, const std::uint32_t* vn,
                  std::size_t vns) {
        // Empty faces are logged and skipped, faces of 1 or 2 corners are lines in all but name,
        // faces past AI_MAX_FACE_INDICES fail validation.
        if (corners < 3 || corners > 0x7fff) throw Decline{__LINE__};
        if (model_.current_object < 0) model_.create_object("defaultobject", notes_);
        if (model_.current_mesh < 0) model_.create_mesh("defaultobject", notes_);
        ObjMesh& mesh = model_.meshes[static_cast<std::size_t>(model_.current_mesh)];
        ++mesh.faces;
        mesh.triangles += corners - 2;
        model_.total_triangles += corners - 2;
        model_.has_polygons = model_.has_polygons || corners > 4;
        mesh.uv_count += vts;
        mesh.has_normals = mesh.has_normals || vns > 0;
        std::uint32_t largest = model_.largest_vertex;  // in a register (v might point at the member)
        for (std::size_t k = 0; k < corners; ++k) largest = std::max(largest, v[k]);
        model_.largest_vertex = largest;
        if (model_.total_triangles > options_.max_triangles) model_.counting_only = true;
        if (model_.counting_only) return;
        model_.add_face_corners(static_cast<std::uint16_t>(corners));
        const std::size_t before = model_.corner_v.size();
        for (std::size_t k = 0; k < corners; ++k) model_.corner_v.push_back(v[k]);
        mesh.corners += corners;
        // Texture coordinates and normals per corner, once some face of the mesh has them.
        if (mesh.uv_count == 0 && !mesh.has_normals) return;
        const struct {
            std::vector<std::uint32_t>& out;
            const std::uint32_t* given;
            std::size_t count;
            bool mesh_has;
        } attributes[2] = {{model_.corner_vt, vt, vts, mesh.uv_count > 0}, {model_.corner_vn, vn, vns, mesh.has_normals}};
        for (const auto& a : attributes) {
            if (!a.mesh_has) continue;
            if (a.out.size() < before) a.out.resize(before, k_absent);
            for (std::size_t k = 0; k < corners; ++k) a.out.push_back(k < a.count ? a.given[k] : k_absent);
        }
    }

    // getMaterialDesc: "usemtl NAME" (the rest of the line, trailing spaces cut).
    void use_material(const char* line) {
        std::string name(rest_of_line(next_token(line)));
        while (!name.empty() && is_space(name.back())) name.pop_back();
        if (name.size() > k_max_name) throw Decline{__LINE__};
        if (name.empty() || (model_.current_material && model_.current_material->name == name)) return;
        auto it = model_.materials.find(name);
        if (it == model_.materials.end()) {
            notes_.error("OBJ: failed to locate material " + name + ", creating new material");
            model_.current_material = &model_.add_material(name);
        } else {
            model_.current_material = &it->second;
        }
        if (model_.needs_new_mesh(name)) model_.create_mesh(name, notes_);
        model_.meshes[static_cast<std::size_t>(model_.current_mesh)].material = model_.material_index(name);
    }

    // getGroupName: "g NAME" (the rest of the line) starts an object when the group changes.
    void group(const char* line) {
        const std::string name(rest_of_line(next_token(line)));
        if (name.size() > k_max_name) throw Decline{__LINE__};
        if (model_.active_group == name) return;
        model_.create_object(name, notes_);
        model_.active_group = name;
    }

    // getObjectName: "o NAME" (the first word) selects the object of that name or starts one; the
    // current mesh stays.
    void object(const char* line) {
        const std::string name(word_at(next_token(line)));
        if (name.empty()) return;
        if (name.size() > k_max_name) throw Decline{__LINE__};
        for (std::size_t i = 0; i < model_.objects.size(); ++i)
            if (model_.objects[i].name == name) {
                model_.current_object = static_cast<int>(i);
                return;
            }
        model_.create_object(name, notes_);
    }

    // getMaterialLib: "mtllib NAME" (the rest of the line, as written) next to the model, else the
    // model's own name with ".mtl".
    void material_library(const char* line) {
        const std::string name(rest_of_line(next_token(line)));
        if (name.empty()) return;
        const std::size_t slash = path_.find_last_of("\\/");
        std::string file = name;
        if (slash != std::string::npos && slash > 0) {  // assimp's IOSystem has the model's folder pushed
            std::string folder = path_.substr(0, slash);
            if (folder.back() != '/') folder += '/';
            file = folder + name;
        }
        std::optional<std::string> text = open_text(file);
        if (!text) {
            notes_.error("OBJ: Unable to locate material file " + name);
            const std::string fallback = path_.substr(0, path_.size() - 3) + "mtl";
            text = open_text(fallback);
            if (!text) {
                notes_.error("OBJ: Unable to locate fallback material file " + fallback);
                return;
            }
        }
        MtlReader(model_, notes_).read(*text);
    }

    // What TextFileToBuffer makes of a file assimp's (confined) IOSystem opens: its text without a
    // UTF-8 byte order mark, and a NUL; nullopt when it does not exist. A file assimp cannot open
    // sends its importer's FileSystemFilter looking for other spellings of the name (the model's
    // folder joined with the name and with each of its tails), which this reader does not mirror:
    // the file is declined when the resource rules refuse it, or when it is missing and one of
    // those other files exists.
    std::optional<std::string> open_text(const std::string& file) {
        if (file.find('\\') != std::string::npos) throw Decline{__LINE__};
        std::error_code ec;
        const fs::file_status status = fs::status(file, ec);
        if (ec || !fs::exists(status)) {
            const std::string base = path_.substr(0, path_.find_last_of('/') + 1);
            if (fs::exists(base + file, ec)) throw Decline{__LINE__};
            for (std::size_t slash = file.find('/'); slash != std::string::npos; slash = file.find('/', slash + 1))
                if (fs::exists(base + file.substr(slash + 1), ec)) throw Decline{__LINE__};
            return std::nullopt;
        }
        if (!notes_.may_open(roots_, file)) throw Decline{__LINE__};
        if (!fs::is_regular_file(status)) throw Decline{__LINE__};
        std::ifstream in(file, std::ios::binary);
        if (!in) throw Decline{__LINE__};
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (text.size() > 0 && text.size() < k_min_text_bytes) throw Decline{__LINE__};  // assimp: "File is too small"
        if (text.find('\0') != std::string::npos) throw Decline{__LINE__};
        const unsigned char b0 = text.empty() ? 0 : static_cast<unsigned char>(text[0]);
        if (text.size() >= 3 && b0 == 0xEF && static_cast<unsigned char>(text[1]) == 0xBB && static_cast<unsigned char>(text[2]) == 0xBF)
            text.erase(0, 3);
        else if (b0 == 0xFE || b0 == 0xFF)
            throw Decline{__LINE__};  // UTF-16 and UTF-32 byte order marks
        text.push_back('\0');
        return text;
    }

    const std::string& path_;
    const LoadOptions& options_;
    const ResourceRoots& roots_;
    ImportNotes& notes_;
    ObjModel model_;
    std::vector<std::uint32_t> lists_[3];  // the face being read: vertex, texture coordinate, normal indices
    const char* readable_end_ = nullptr;   // past the text's NUL
};

// ---- meshes: ObjFileImporter's vertex per corner, then the post-processing

// ObjFileImporter's aiMesh of one mesh (a vertex per face corner), post-processed.
class MeshBuilder {
public:
    MeshBuilder(ObjModel& model, ImportNotes& notes) : model_(model), notes_(notes) {
        detail::reserve_in_huge_pages(by_vertex_, model.vertices.size());  // probed at random; sized when first needed
    }

    OwnMesh build(const ObjMesh& mesh, unsigned material) {
        const std::size_t corners = mesh.corners;
        const bool has_vt = mesh.uv_count > 0, has_vn = mesh.has_normals;
        // The mesh's corners: vertex, texture coordinate and normal indices (these two when has_vt,
        // has_vn).
        const std::uint32_t* const mesh_v = model_.corner_v.data() + mesh.first_corner;
        const std::uint32_t* const mesh_vt = has_vt ? model_.corner_vt.data() + mesh.first_corner : nullptr;
        const std::uint32_t* const mesh_vn = has_vn ? model_.corner_vn.data() + mesh.first_corner : nullptr;
        // createVertexArray's arrays, and whether every index reaches its array.
        bool normals = !model_.normals.empty() && mesh.has_normals;
        bool uvs = !model_.texcoords.empty() && mesh.uv_count > 0;
        const bool colours = !model_.colours.empty();
        for (std::size_t c = 0; normals && has_vn && c < corners; ++c)
            normals = mesh_vn[c] == k_absent || mesh_vn[c] < model_.normals.size();
        for (std::size_t c = 0; uvs && has_vt && c < corners; ++c) uvs = mesh_vt[c] == k_absent || mesh_vt[c] < model_.texcoords.size();
        const bool with_vn = normals && has_vn, with_vt = uvs && has_vt;
        // A corner's attributes as JoinIdenticalVertices sees them: uvs flipped by FlipUVs.
        auto value_of = [&](std::size_t c) {
            JoinVertex v{model_.vertices[mesh_v[c]], {}, {}, {}, {}};
            if (with_vn && mesh_vn[c] != k_absent) v.normal = model_.normals[mesh_vn[c]];
            if (uvs) {
                if (with_vt && mesh_vt[c] != k_absent) v.uv = model_.texcoords[mesh_vt[c]];
                v.uv.y = 1.0f - v.uv.y;
            }
            return v;
        };

        // Corners with the same indices have the same values: the join looks at the first corner
        // of each such group (JoinIdenticalVertices keeps a group's first corner).
        // Without texture coordinates and normals a group is a vertex, its number by_vertex_'s head
        // (no array per corner).
        const bool by_vertex = !with_vt && !with_vn;
        // Most files use their vertices in the order they list them: then vertex v is group v, found
        // by one sequential pass (no stamps written at random, no list of groups' first corners).
        bool in_order = by_vertex;
        std::uint32_t in_order_groups = 0;
        for (std::uint32_t c = 0; in_order && c < corners; ++c) {
            const std::uint32_t v = mesh_v[c];
            in_order_groups += v == in_order_groups;
            in_order = v < in_order_groups;
        }
        std::vector<std::uint32_t> group_of(by_vertex ? 0 : corners), group_corner;
        if (!in_order) detail::reserve_in_huge_pages(group_corner, by_vertex ? std::min(corners, model_.vertices.size()) : corners);
        if (!in_order && by_vertex_.empty()) by_vertex_.resize(model_.vertices.size());
        ++stamp_;
        indices_.clear();
        for (std::size_t c = 0; by_vertex && !in_order && c < corners; ++c) {
            Stamped& s = by_vertex_[mesh_v[c]];
            if (s.stamp != stamp_) {
                s = {stamp_, static_cast<std::uint32_t>(group_corner.size())};
                group_corner.push_back(static_cast<std::uint32_t>(c));
            }
        }
        for (std::size_t c = 0; !by_vertex && c < corners; ++c) {
            const std::uint32_t vt = with_vt ? mesh_vt[c] : k_absent, vn = with_vn ? mesh_vn[c] : k_absent;
            Stamped& s = by_vertex_[mesh_v[c]];
            if (s.stamp != stamp_) s = {stamp_, k_absent};
            std::uint32_t e = s.head;
            while (e != k_absent && (indices_[e].vt != vt || indices_[e].vn != vn)) e = indices_[e].next;
            if (e == k_absent) {
                indices_.push_back({vt, vn, static_cast<std::uint32_t>(group_corner.size()), s.head});
                e = s.head = static_cast<std::uint32_t>(indices_.size() - 1);
                group_corner.push_back(static_cast<std::uint32_t>(c));
            }
            group_of[c] = indices_[e].group;
        }
        const auto group_value = [&](std::size_t g) { return value_of(group_corner[g]); };
        const std::size_t groups = in_order ? in_order_groups : group_corner.size();
        OwnMesh out;
        out.material = material;
        // (Group g in order is vertex g, read without its first corner; unjoined, they are the
        // unique vertices as they are.)
        std::optional<Join> exact_join =
            in_order ? join_as_assimp(groups, [&](std::size_t g) { return JoinVertex{model_.vertices[g], {}, {}, {}, {}}; }, corners,
                                      out.positions, model_.vertices.data())
                     : join_as_assimp(groups, group_value, corners, out.positions);
        const bool exact = exact_join.has_value();
        Join join;
        std::vector<std::uint32_t> unique_of_corner = std::move(group_of);
        if (exact) {
            join = std::move(*exact_join);
            if (!in_order) {
                for (std::uint32_t& f : join.first) f = group_corner[f];
                for (std::uint32_t& u : unique_of_corner) u = join.unique[u];
            }
        } else {
            join = assimp_join(corners, value_of, [](std::size_t) { return true; });
            unique_of_corner = join.unique;
            out.positions.clear();
            for (std::uint32_t c : join.first) out.positions.push_back(model_.vertices[mesh_v[c]]);
        }
        // A unique vertex's first corner; in order, its vertex (by vertex, colours are all it has).
        const std::size_t unique_count = join.identity ? groups : join.first.size();
        const auto first_of = [&](std::size_t u) { return join.identity ? static_cast<std::uint32_t>(u) : join.first[u]; };

        if (normals) out.normals.reserve(unique_count);
        if (uvs) out.uvs.reserve(unique_count);
        if (colours) out.colours.reserve(unique_count);
        for (std::size_t u = 0; in_order && colours && u < unique_count; ++u) out.colours.push_back(colour_of(first_of(u)));
        for (std::size_t u = 0; !in_order && (normals || uvs || colours) && u < unique_count; ++u) {
            const std::uint32_t c = join.first[u];
            const JoinVertex v = value_of(c);
            if (normals) out.normals.push_back(v.normal);
            if (uvs) out.uvs.push_back(v.uv);
            if (colours) out.colours.push_back(colour_of(mesh_v[c]));
        }
        // Unjoined vertices in order are the first `groups` vertices: taken when this mesh, of
        // triangles alone, uses every vertex and every corner (nothing reads them after it), else copied.
        if (join.identity) {
            if (mesh.first_corner == 0 && corners == model_.corner_v.size() && groups == model_.vertices.size() && 3 * mesh.triangles == corners) {
                out.positions = std::move(model_.vertices);
            } else {
                detail::reserve_in_huge_pages(out.positions, groups);
                out.positions.assign(model_.vertices.begin(), model_.vertices.begin() + static_cast<std::ptrdiff_t>(groups));
            }
        }
        // Joined by position alone: no two positions are the same (the creased normals need not weld).
        out.distinct_positions = by_vertex;
        // A mesh of all the model's corners, in triangles: its triangles are written over its
        // corners (each triangle's read before it is written), not into fresh pages.
        if (mesh.first_corner == 0 && corners == model_.corner_v.size() && 3 * mesh.triangles == corners)
            out.triangles = std::move(model_.corner_v);  // mesh_v still points at them
        if (exact && in_order) {
            // Vertex v is group v: with no two groups joined, each corner's unique vertex is its vertex.
            const bool joined = !join.identity;
            if (joined || out.triangles.data() != mesh_v || 3 * mesh.triangles != corners)
                triangulate(mesh, mesh_v, [&](std::uint32_t c) { return joined ? join.unique[mesh_v[c]] : mesh_v[c]; }, out.triangles);
            out.numbered = 3 * mesh.triangles == corners;
        } else if (exact && by_vertex) {
            // Each vertex's unique vertex kept in its stamp (in the place of its group's number, the
            // same when no two groups joined): a corner then looks up one number, not two.
            if (join.first.size() != group_corner.size())
                for (std::size_t g = 0; g < group_corner.size(); ++g) by_vertex_[mesh_v[group_corner[g]]].head = join.unique[g];
            triangulate(mesh, mesh_v, [&](std::uint32_t c) { return by_vertex_[mesh_v[c]].head; }, out.triangles);
            // Triangles alone keep their corners' order: numbered in order of first use.
            out.numbered = 3 * mesh.triangles == corners;
        } else {
            triangulate(mesh, mesh_v, [&](std::uint32_t c) { return unique_of_corner[c]; }, out.triangles);
        }
        return out;
    }

private:
    struct Stamped {
        std::uint32_t stamp = 0;
        std::uint32_t head = k_absent;  // in indices_; without them the group, then the unique vertex
    };
    struct ByIndices {
        std::uint32_t vt, vn, group, next;
    };

    aiColor4D colour_of(std::uint32_t vertex) const {
        if (vertex >= model_.colours.size()) return aiColor4D();  // zeros, as assimp's array starts
        const aiVector3D& c = model_.colours[vertex];
        return aiColor4D(c.x, c.y, c.z, 1.0f);
    }

    // Triangulate: triangles as they are, quads split at their concave corner, larger polygons cut
    // into ears; each triangle's corners rotated as NGONEncoder rotates them (a triangle starting
    // where the last one did would read as part of its polygon).
    template <class UniqueOf>
    void triangulate(const ObjMesh& mesh, const std::uint32_t* mesh_v, const UniqueOf& unique_of_corner,
                     std::vector<std::uint32_t>& out) {
        detail::reserve_in_huge_pages(out, 3 * mesh.triangles);
        if (3 * mesh.triangles == mesh.corners) {
            // Triangles alone, as they are: NgonEncoder compares corners, which never repeat, and
            // turns none. (out may hold the mesh's corners themselves: each is read, then written.)
            out.resize(mesh.corners);
            for (std::uint32_t c = 0; c < mesh.corners; ++c) out[c] = unique_of_corner(c);
            return;
        }
        triangulator_.encoder = {};
        const auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
            out.insert(out.end(), {unique_of_corner(a), unique_of_corner(b), unique_of_corner(c)});
        };
        std::uint32_t c = 0;
        for (std::size_t face = mesh.first_face; face < mesh.first_face + mesh.faces; ++face) {
            const std::uint32_t n = model_.corners_of(face);
            const auto corner = [c](std::uint32_t k) { return c + k; };
            const auto position = [&](std::uint32_t k) -> const aiVector3D& { return model_.vertices[mesh_v[c + k]]; };
            if (!triangulator_.face(n, corner, position, emit))
                notes_.error("Failed to triangulate polygon (no ear found). Probably not a simple polygon?");
            c += n;
        }
    }

    ObjModel& model_;  // its corners taken by a mesh that has them all
    ImportNotes& notes_;
    std::vector<Stamped> by_vertex_;  // stamped by mesh
    std::vector<ByIndices> indices_;
    std::uint32_t stamp_ = 0;
    Triangulator triangulator_;
};

// ---- materials (ObjFileImporter::createMaterials)

std::unique_ptr<aiMaterial> make_material(const ObjMaterial& m, ImportNotes& notes) {
    auto out = std::make_unique<aiMaterial>();
    aiMaterial& mat = *out;
    const aiString name(m.name);
    mat.AddProperty(&name, AI_MATKEY_NAME);
    int shading = aiShadingMode_Gouraud;
    if (m.illumination == 0) shading = aiShadingMode_NoShading;
    if (m.illumination == 2) shading = aiShadingMode_Phong;
    if (m.illumination < 0 || m.illumination > 2) notes.error("OBJ: unexpected illumination model (0-2 recognized)");
    mat.AddProperty(&shading, 1, AI_MATKEY_SHADING_MODEL);
    mat.AddProperty(&m.illumination, 1, "$mat.illum", 0, 0);
    mat.AddProperty(&m.ambient, 1, AI_MATKEY_COLOR_AMBIENT);
    mat.AddProperty(&m.diffuse, 1, AI_MATKEY_COLOR_DIFFUSE);
    mat.AddProperty(&m.specular, 1, AI_MATKEY_COLOR_SPECULAR);
    mat.AddProperty(&m.emissive, 1, AI_MATKEY_COLOR_EMISSIVE);
    mat.AddProperty(&m.shininess, 1, AI_MATKEY_SHININESS);
    mat.AddProperty(&m.alpha, 1, AI_MATKEY_OPACITY);
    mat.AddProperty(&m.transparent, 1, AI_MATKEY_COLOR_TRANSPARENT);
    if (m.roughness_factor) mat.AddProperty(&*m.roughness_factor, 1, AI_MATKEY_ROUGHNESS_FACTOR);
    if (m.metallic_factor) mat.AddProperty(&*m.metallic_factor, 1, AI_MATKEY_METALLIC_FACTOR);
    if (m.sheen_colour) mat.AddProperty(&*m.sheen_colour, 1, AI_MATKEY_SHEEN_COLOR_FACTOR);
    if (m.clearcoat_thickness) mat.AddProperty(&*m.clearcoat_thickness, 1, AI_MATKEY_CLEARCOAT_FACTOR);
    if (m.clearcoat_roughness) mat.AddProperty(&*m.clearcoat_roughness, 1, AI_MATKEY_CLEARCOAT_ROUGHNESS_FACTOR);
    mat.AddProperty(&m.anisotropy, 1, AI_MATKEY_ANISOTROPY_FACTOR);
    mat.AddProperty(&m.ior, 1, AI_MATKEY_REFRACTI);

    const int uv_source = 0;
    const int clamp_mode = aiTextureMapMode_Clamp;
    auto add_texture = [&](int slot, aiTextureType type, bool with_clamp) {
        if (m.texture[slot].empty()) return;
        const aiString file(m.texture[slot]);
        mat.AddProperty(&file, _AI_MATKEY_TEXTURE_BASE, type, 0);
        mat.AddProperty(&uv_source, 1, _AI_MATKEY_UVWSRC_BASE, type, 0);
        if (type == aiTextureType_HEIGHT || type == aiTextureType_NORMALS)
            if (m.bump_multiplier != 1.0f) mat.AddProperty(&m.bump_multiplier, 1, "$tex.bumpmult", type, 0);
        if (with_clamp && m.clamp[slot]) {
            mat.AddProperty(&clamp_mode, 1, _AI_MATKEY_MAPPINGMODE_U_BASE, type, 0);
            mat.AddProperty(&clamp_mode, 1, _AI_MATKEY_MAPPINGMODE_V_BASE, type, 0);
        }
    };
    add_texture(diffuse, aiTextureType_DIFFUSE, true);
    add_texture(ambient, aiTextureType_AMBIENT, true);
    add_texture(emissive, aiTextureType_EMISSIVE, false);
    add_texture(specular, aiTextureType_SPECULAR, true);
    add_texture(bump, aiTextureType_HEIGHT, true);
    add_texture(normal, aiTextureType_NORMALS, true);
    if (!m.reflection[0].empty()) {
        // A sphere map, or the six faces of a cube map when a bottom face is given.
        const bool cube = !m.reflection[1].empty();
        const int clamp_slot = cube ? reflection_cube_top : reflection_sphere;
        const int faces = cube ? 6 : 1;
        for (int i = 0; i < faces; ++i) {
            const aiString file(m.reflection[i]);
            mat.AddProperty(&file, _AI_MATKEY_TEXTURE_BASE, aiTextureType_REFLECTION, static_cast<unsigned>(i));
            mat.AddProperty(&uv_source, 1, _AI_MATKEY_UVWSRC_BASE, aiTextureType_REFLECTION, static_cast<unsigned>(i));
            if (m.clamp[clamp_slot]) {
                const int one = 1;
                mat.AddProperty(&one, 1, _AI_MATKEY_MAPPINGMODE_U_BASE, aiTextureType_REFLECTION, static_cast<unsigned>(i));
                mat.AddProperty(&one, 1, _AI_MATKEY_MAPPINGMODE_V_BASE, aiTextureType_REFLECTION, static_cast<unsigned>(i));
            }
        }
    }
    add_texture(displacement, aiTextureType_DISPLACEMENT, true);
    add_texture(opacity, aiTextureType_OPACITY, true);
    add_texture(specularity, aiTextureType_SHININESS, true);
    add_texture(roughness, aiTextureType_DIFFUSE_ROUGHNESS, true);
    add_texture(metallic, aiTextureType_METALNESS, true);
    add_texture(sheen, aiTextureType_SHEEN, true);
    add_texture(rma, aiTextureType_UNKNOWN, true);
    return out;
}

}  // namespace

std::optional<Result<OwnScene>> read_obj(const std::string& path, std::string_view bytes, const LoadOptions& options,
                                         const ResourceRoots& roots, ImportNotes& notes, const std::function<void()>& bytes_read) {
    try {
        if (bytes.size() < k_min_obj_bytes) return std::nullopt;  // a NUL byte: declined by ObjReader::read
        if (path.find('\\') != std::string::npos) return std::nullopt;
        ObjReader reader(path, options, roots, notes);
        reader.read(bytes);
        if (bytes_read) bytes_read();  // the model holds no views of them
        ObjModel& model = reader.model();
        if (model.total_triangles == 0) return std::nullopt;
        if (model.largest_vertex >= model.vertices.size()) return std::nullopt;  // assimp: "vertex index out of range"

        // The meshes in the order of the nodes (each object's, in order), those without faces left out.
        if (model.counting_only) {
            if (model.has_polygons) return std::nullopt;  // what their triangulation makes is not counted
            std::size_t triangles = 0;
            for (const ObjObject& o : model.objects)
                for (unsigned id : o.meshes) {
                    triangles += model.meshes[id].triangles;
                    if (triangles > options.max_triangles) return Result<OwnScene>(too_many_triangles(path, triangles, options));
                }
            return std::nullopt;
        }
        OwnScene scene;
        // createMaterials (with its logged errors) runs before Triangulate (with its own).
        for (const ObjMaterial* m : model.library) scene.materials.push_back(make_material(*m, notes));
        MeshBuilder builder(model, notes);
        for (const ObjObject& o : model.objects) {
            SourceNode node;
            for (unsigned id : o.meshes) {
                const ObjMesh& mesh = model.meshes[id];
                if (mesh.faces == 0) continue;
                node.meshes.push_back(static_cast<unsigned>(scene.meshes.size()));
                scene.meshes.push_back(builder.build(mesh, mesh.material == k_no_material ? 0 : mesh.material));
            }
            scene.root.children.push_back(std::move(node));
        }
        return Result<OwnScene>(std::move(scene));
    } catch (const Decline& d) {
        if (std::getenv("FACET_DEBUG_DECLINE")) std::fprintf(stderr, "declined at obj.cpp:%d\n", d.line);
        return std::nullopt;
    }
}

}  // namespace facet::io_detail
