// facet io: the glTF 2.0 reader (gltf.hpp). The JSON is parsed by RapidJSON with assimp's flags (the
// same library, so the same numbers); the objects are visited in the order assimp's lazy
// dictionaries retrieve them (a node's children before its mesh, a mesh's materials, a material's
// textures), which numbers the embedded images as assimp does ("*0", "*1", ...); materials become the
// aiMaterial properties assimp's importer sets, vertices are joined as JoinIdenticalVertices joins
// them (assimp_join.hpp). Every check assimp makes that would fail, and anything it would read
// out of bounds, declines the file instead.
#include "io/gltf.hpp"

#include <assimp/GltfMaterial.h>
#include <assimp/material.h>
#include <assimp/matrix3x3.inl>
#include <assimp/matrix4x4.inl>
#include <assimp/quaternion.inl>
#include <assimp/vector3.inl>
#include <fcntl.h>
#include <rapidjson/document.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "exec/fresh_pages.hpp"
#include "io/assimp_join.hpp"
#include "io/import_notes.hpp"
#include "io/resources.hpp"
#include "math/portable_trig.hpp"

namespace facet::io_detail {
namespace {

using rapidjson::Value;

struct Decline {
    int line;
};

#define GLTF_REQUIRE(condition)                             \
    do {                                                    \
        if (!(condition)) throw Decline{__LINE__};          \
    } while (0)

constexpr int k_float = 5126, k_ubyte = 5121, k_ushort = 5123, k_uint = 5125;

const Value* find(const Value& object, const char* key) {
    const auto it = object.FindMember(key);
    return it == object.MemberEnd() ? nullptr : &it->value;
}

// A non-negative int (assimp reads sizes and offsets only when they are ints), 0 when absent.
std::size_t size_member(const Value& object, const char* key) {
    const Value* v = find(object, key);
    if (!v) return 0;
    GLTF_REQUIRE(v->IsInt() && v->GetInt() >= 0);
    return static_cast<std::size_t>(v->GetInt());
}

std::optional<std::uint32_t> uint_member(const Value& object, const char* key) {
    const Value* v = find(object, key);
    if (!v) return std::nullopt;
    GLTF_REQUIRE(v->IsUint());
    return v->GetUint();
}

float float_of(const Value& v) {
    GLTF_REQUIRE(v.IsNumber());
    return static_cast<float>(v.GetDouble());
}

void read_float(const Value& object, const char* key, float& out) {
    if (const Value* v = find(object, key)) out = float_of(*v);
}

// An array of exactly N numbers; false when absent.
template <std::size_t N>
bool read_floats(const Value& object, const char* key, float (&out)[N]) {
    const Value* v = find(object, key);
    if (!v) return false;
    GLTF_REQUIRE(v->IsArray() && v->Size() == N);
    for (unsigned i = 0; i < N; ++i) out[i] = float_of((*v)[i]);
    return true;
}

// Element `index` of the document's array `list`, an object whose name (when it has one) is a string.
const Value& element(const Value* list, std::uint32_t index) {
    GLTF_REQUIRE(list && list->IsArray() && index < list->Size());
    const Value& v = (*list)[index];
    GLTF_REQUIRE(v.IsObject());
    if (const Value* name = find(v, "name")) GLTF_REQUIRE(name->IsString());
    return v;
}

int base64_digit(char c) {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
}

// A data URI "data:<media type>;base64,<data>" decoded (strict base64, padded); nullopt for any
// other URI.
struct DataUri {
    std::string media_type;
    std::string bytes;
};

std::optional<DataUri> parse_data_uri(std::string_view uri) {
    if (uri.substr(0, 5) != "data:") return std::nullopt;
    const std::size_t comma = uri.find(',');
    GLTF_REQUIRE(comma != std::string_view::npos);
    const std::string_view head = uri.substr(5, comma - 5);
    GLTF_REQUIRE(head.size() >= 7 && head.substr(head.size() - 7) == ";base64" && head.size() < 100);
    DataUri out;
    out.media_type = std::string(head.substr(0, head.size() - 7));
    GLTF_REQUIRE(out.media_type.find(';') == std::string::npos && !out.media_type.empty());
    const std::string_view data = uri.substr(comma + 1);
    GLTF_REQUIRE(data.size() % 4 == 0 && !data.empty());
    const std::size_t pad = (data.back() == '=') + (data[data.size() - 2] == '=');
    out.bytes.reserve(data.size() / 4 * 3);
    for (std::size_t i = 0; i < data.size(); i += 4) {
        int d[4];
        for (int k = 0; k < 4; ++k) {
            const bool padding = i + 4 == data.size() && k >= 4 - static_cast<int>(pad);
            d[k] = padding ? 0 : base64_digit(data[i + k]);
            GLTF_REQUIRE(d[k] >= 0);
        }
        const std::uint32_t v = static_cast<std::uint32_t>(d[0] << 18 | d[1] << 12 | d[2] << 6 | d[3]);
        out.bytes.push_back(static_cast<char>(v >> 16));
        out.bytes.push_back(static_cast<char>(v >> 8 & 0xFF));
        out.bytes.push_back(static_cast<char>(v & 0xFF));
    }
    out.bytes.resize(out.bytes.size() - pad);
    return out;
}

std::uint32_t read_u32(std::string_view bytes, std::size_t at) {
    std::uint32_t v;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
}

struct BufferView {
    const std::uint8_t* data;  // the buffer's bytes from the view's offset
    std::size_t length, stride;
};

// An accessor's elements: `count` of `elem` bytes each, `stride` apart.
struct Accessor {
    const std::uint8_t* data;
    std::size_t count, stride, elem;
    int component;
    unsigned components;
};

// A textureInfo as assimp's importer keeps it.
struct TextureInfo {
    std::optional<std::uint32_t> texture;
    int tex_coord = 0;
    bool transform = false;
    float offset[2] = {0, 0}, rotation = 0, scale[2] = {1, 1};
    float normal_scale = 1, occlusion_strength = 1;
};

struct MaterialData {
    float base_colour[4] = {1, 1, 1, 1};
    float metallic = 1, roughness = 1;
    float emissive[3] = {0, 0, 0};
    std::string alpha_mode = "OPAQUE";
    float alpha_cutoff = 0.5f;
    bool double_sided = false;
    bool unlit = false;
    TextureInfo base_colour_texture, metallic_roughness_texture, normal_texture, occlusion_texture, emissive_texture;
};

struct TextureData {
    std::optional<std::uint32_t> image, sampler;
};

struct ImageData {
    std::string name;  // the material's texture name: "*N" for an embedded image, else the uri
};

struct NodeData {
    std::vector<std::uint32_t> children;
    aiMatrix4x4 transform;
    std::optional<std::uint32_t> mesh;
};

enum class State { unread, reading, read };

class GltfReader {
public:
    GltfReader(const std::string& path, const LoadOptions& options, const ResourceRoots& roots, ImportNotes& notes)
        : options_(options), roots_(roots), notes_(notes) {
        // assimp's mCurrentAssetDir: the path up to its last separator.
        const std::size_t slash = path.find_last_of('/');
        dir_ = slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
    }

    OwnScene read(std::string_view bytes, bool binary) {
        parse(bytes, binary);
        // The scene: "scene" or the first; its nodes and what they reach, retrieved as assimp does.
        std::uint32_t scene_index = uint_member(doc_, "scene").value_or(0);
        const Value& scene = element(find(doc_, "scenes"), scene_index);
        std::vector<std::uint32_t> roots;
        if (const Value* list = find(scene, "nodes")) {
            GLTF_REQUIRE(list->IsArray());
            for (const Value& n : list->GetArray()) {
                GLTF_REQUIRE(n.IsUint());
                retrieve_node(n.GetUint());
                roots.push_back(n.GetUint());
            }
        }
        GLTF_REQUIRE(!roots.empty());
        OwnScene out;
        out.gltf = true;
        for (std::uint32_t m : material_order_) out.materials.push_back(make_material(materials_[m]));
        out.materials.push_back(make_material(MaterialData{}));  // assimp's default material, last
        std::vector<unsigned> first_mesh;
        for (std::uint32_t m : mesh_order_) {
            first_mesh.push_back(static_cast<unsigned>(out.meshes.size()));
            for (const Primitive& p : primitives_[m]) out.meshes.push_back(build_mesh(p));
        }
        first_mesh.push_back(static_cast<unsigned>(out.meshes.size()));
        auto node = [&](auto& self, std::uint32_t index, std::size_t depth) -> SourceNode {
            GLTF_REQUIRE(depth < 1000 && ++built_nodes_ < 1000000);
            const NodeData& n = nodes_[index];
            SourceNode s;
            s.transform = n.transform;
            if (n.mesh) {
                const int slot = mesh_slot_[*n.mesh];
                for (unsigned i = first_mesh[slot]; i < first_mesh[slot + 1]; ++i) s.meshes.push_back(i);
            }
            for (std::uint32_t c : n.children) s.children.push_back(self(self, c, depth + 1));
            return s;
        };
        if (roots.size() == 1) {
            out.root = node(node, roots[0], 0);
        } else {
            for (std::uint32_t r : roots) out.root.children.push_back(node(node, r, 0));
        }
        out.kept = std::move(embedded_);
        for (std::size_t i = 0; i < out.kept.size(); ++i) out.embedded.emplace("*" + std::to_string(i), out.kept[i]);
        return out;
    }

private:
    struct Primitive {
        int mode = 4;  // TRIANGLES, TRIANGLE_STRIP (5) or TRIANGLE_FAN (6)
        Accessor positions;
        std::optional<Accessor> indices, normals, tangents, uvs, colours;
        std::optional<std::uint32_t> material;
    };

    void parse(std::string_view bytes, bool binary) {
        std::string_view json = bytes;
        if (binary) {
            // assimp's ReadBinaryHeader: header, JSON chunk, then a BIN chunk when the header's length
            // reaches past the JSON chunk's padding (the body buffer, glTF's buffer 0).
            GLTF_REQUIRE(bytes.size() >= 20 && bytes.substr(0, 4) == "glTF" && read_u32(bytes, 4) == 2 &&
                         read_u32(bytes, 8) == bytes.size() && read_u32(bytes, 16) == 0x4E4F534A);
            const std::size_t length = read_u32(bytes, 12);
            GLTF_REQUIRE(length <= bytes.size() - 20);
            json = bytes.substr(20, length);
            const std::size_t padding = ((length + 3) & ~std::size_t{3}) - length;
            const std::size_t body = 12 + 8 + length + padding + 8;
            if (bytes.size() >= body) {
                GLTF_REQUIRE(read_u32(bytes, body - 4) == 0x004E4942);
                const std::size_t body_length = read_u32(bytes, body - 8);
                GLTF_REQUIRE(body_length <= bytes.size() - body);
                body_ = bytes.substr(body, body_length);
            }
            binary_ = true;
        }
        json_.assign(json.begin(), json.end());
        json_.push_back('\0');
        doc_.ParseInsitu(json_.data());  // assimp's call, with its (default) flags
        GLTF_REQUIRE(!doc_.HasParseError() && doc_.IsObject());

        const Value* asset = find(doc_, "asset");
        GLTF_REQUIRE(asset && asset->IsObject());
        const Value* version = find(*asset, "version");
        GLTF_REQUIRE(version && version->IsString() && version->GetString()[0] == '2');
        for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
            const Value* list = find(doc_, key);
            if (!list) continue;
            GLTF_REQUIRE(list->IsArray());
            for (const Value& e : list->GetArray()) {
                GLTF_REQUIRE(e.IsString());
                const std::string_view name = e.GetString();
                // KHR_materials_emissive_strength: unknown to assimp 5.2.5, which reads the file without
                // it (the emissive colour unscaled); so does this reader, unless the file requires it.
                GLTF_REQUIRE(name == "KHR_texture_transform" || name == "KHR_materials_unlit" ||
                             (name == "KHR_materials_emissive_strength" && std::string_view(key) == "extensionsUsed"));
                if (name == "KHR_texture_transform" && std::string_view(key) == "extensionsUsed") texture_transform_ = true;
            }
        }
        GLTF_REQUIRE(!find(doc_, "skins"));
        for (const char* key : {"nodes", "meshes", "materials", "textures", "images", "samplers", "accessors", "bufferViews",
                                "buffers", "scenes"})
            if (const Value* list = find(doc_, key)) GLTF_REQUIRE(list->IsArray());
        auto count = [&](const char* key) {
            const Value* list = find(doc_, key);
            return list ? list->Size() : 0u;
        };
        node_state_.assign(count("nodes"), State::unread);
        nodes_.resize(count("nodes"));
        mesh_slot_.assign(count("meshes"), -1);
        primitives_.resize(count("meshes"));
        material_slot_.assign(count("materials"), -1);
        materials_.resize(count("materials"));
        textures_.resize(count("textures"));
        texture_read_.assign(count("textures"), false);
        images_.resize(count("images"));
        image_read_.assign(count("images"), false);
        wraps_.resize(count("samplers"));
        sampler_read_.assign(count("samplers"), false);
        buffers_.resize(count("buffers"));
        buffer_read_.assign(count("buffers"), false);
        // Animations move nodes over time; the scene is the nodes' own pose, as assimp's is. Their
        // samplers' accessors are read (assimp refuses a file whose accessors are broken).
        if (const Value* animations = find(doc_, "animations")) {
            GLTF_REQUIRE(animations->IsArray());
            for (const Value& a : animations->GetArray()) {
                GLTF_REQUIRE(a.IsObject());
                const Value* samplers = find(a, "samplers");
                GLTF_REQUIRE(samplers && samplers->IsArray());
                for (const Value& sampler : samplers->GetArray()) {
                    GLTF_REQUIRE(sampler.IsObject());
                    for (const char* k : {"input", "output"}) {
                        const std::optional<std::uint32_t> at = uint_member(sampler, k);
                        GLTF_REQUIRE(at);
                        accessor(*at);
                    }
                }
                const Value* nodes = find(doc_, "nodes");
                const Value* channels = find(a, "channels");
                GLTF_REQUIRE(channels && channels->IsArray());
                for (const Value& channel : channels->GetArray()) {
                    GLTF_REQUIRE(channel.IsObject());
                    const std::optional<std::uint32_t> sampler = uint_member(channel, "sampler");
                    GLTF_REQUIRE(sampler && *sampler < samplers->Size());
                    const Value* target = find(channel, "target");
                    GLTF_REQUIRE(target && target->IsObject());
                    const std::optional<std::uint32_t> node = uint_member(*target, "node");
                    GLTF_REQUIRE(node && nodes && nodes->IsArray() && *node < nodes->Size());
                }
            }
        }
    }

    // Node::Read: children first, then the transform, then the mesh.
    void retrieve_node(std::uint32_t index) {
        const Value& obj = element(find(doc_, "nodes"), index);
        GLTF_REQUIRE(node_state_[index] != State::reading);  // a cycle: assimp refuses it
        if (node_state_[index] == State::read) return;
        node_state_[index] = State::reading;
        GLTF_REQUIRE(!find(obj, "skin"));
        if (const std::optional<std::uint32_t> camera = uint_member(obj, "camera")) {
            // Camera::Read fails only without the parameters of its type; cameras place no meshes.
            const Value& c = element(find(doc_, "cameras"), *camera);
            const Value* type = find(c, "type");
            const bool orthographic = type && type->IsString() && std::string_view(type->GetString()) == "orthographic";
            const Value* parameters = find(c, orthographic ? "orthographic" : "perspective");
            GLTF_REQUIRE(parameters && parameters->IsObject());
        }
        if (const Value* children = find(obj, "children")) {
            GLTF_REQUIRE(children->IsArray());
            for (const Value& c : children->GetArray()) {
                GLTF_REQUIRE(c.IsUint());
                retrieve_node(c.GetUint());
                nodes_[index].children.push_back(c.GetUint());
            }
        }
        // GetNodeTransform: the matrix (column-major), or identity * T * R * S in assimp's arithmetic.
        aiMatrix4x4 m;
        float matrix[16];
        if (read_floats(obj, "matrix", matrix)) {
            m = aiMatrix4x4(matrix[0], matrix[4], matrix[8], matrix[12], matrix[1], matrix[5], matrix[9], matrix[13],
                            matrix[2], matrix[6], matrix[10], matrix[14], matrix[3], matrix[7], matrix[11], matrix[15]);
        } else {
            float t[3], r[4], s[3];
            if (read_floats(obj, "translation", t)) {
                aiMatrix4x4 tm;
                aiMatrix4x4::Translation(aiVector3D(t[0], t[1], t[2]), tm);
                m = m * tm;
            }
            if (read_floats(obj, "rotation", r)) {
                const aiQuaternion q(r[3], r[0], r[1], r[2]);
                m = m * aiMatrix4x4(q.GetMatrix());
            }
            if (read_floats(obj, "scale", s)) {
                aiMatrix4x4 sm;
                aiMatrix4x4::Scaling(aiVector3D(s[0], s[1], s[2]), sm);
                m = m * sm;
            }
        }
        nodes_[index].transform = m;
        if (const std::optional<std::uint32_t> mesh = uint_member(obj, "mesh")) {
            retrieve_mesh(*mesh);
            nodes_[index].mesh = mesh;
        }
        node_state_[index] = State::read;
    }

    void retrieve_mesh(std::uint32_t index) {
        const Value& obj = element(find(doc_, "meshes"), index);
        if (mesh_slot_[index] >= 0) return;
        mesh_slot_[index] = static_cast<int>(mesh_order_.size());
        mesh_order_.push_back(index);
        std::vector<Primitive> primitives;
        if (const Value* list = find(obj, "primitives")) {
            GLTF_REQUIRE(list->IsArray());
            for (const Value& p : list->GetArray()) {
                GLTF_REQUIRE(p.IsObject());
                Primitive prim;
                if (const Value* mode = find(p, "mode")) {
                    GLTF_REQUIRE(mode->IsInt() && mode->GetInt() >= 4 && mode->GetInt() <= 6);
                    prim.mode = mode->GetInt();
                }
                GLTF_REQUIRE(!find(p, "targets"));
                if (const auto i = uint_member(p, "indices")) {
                    prim.indices = accessor(*i);
                    GLTF_REQUIRE(prim.indices->components == 1 &&
                                 (prim.indices->component == k_ubyte || prim.indices->component == k_ushort ||
                                  prim.indices->component == k_uint));
                }
                if (const auto m = uint_member(p, "material")) {
                    retrieve_material(*m);
                    prim.material = m;
                }
                const Value* attributes = find(p, "attributes");
                GLTF_REQUIRE(attributes && attributes->IsObject());
                bool has_position = false;
                for (const auto& a : attributes->GetObject()) {
                    GLTF_REQUIRE(a.value.IsUint());
                    const std::string_view name = a.name.GetString();
                    const Accessor acc = accessor(a.value.GetUint());
                    const bool float_vec = acc.component == k_float;
                    if (name == "POSITION") {
                        GLTF_REQUIRE(float_vec && acc.components == 3);
                        prim.positions = acc;
                        has_position = true;
                    } else if (name == "NORMAL") {
                        GLTF_REQUIRE(float_vec && acc.components == 3);
                        prim.normals = acc;
                    } else if (name == "TANGENT") {
                        GLTF_REQUIRE(float_vec && acc.components == 4);
                        prim.tangents = acc;
                    } else if (name == "TEXCOORD_0") {
                        GLTF_REQUIRE(float_vec && acc.components == 2);
                        prim.uvs = acc;
                    } else if (name == "COLOR_0") {
                        GLTF_REQUIRE((acc.component == k_float || acc.component == k_ubyte || acc.component == k_ushort) &&
                                     (acc.components == 3 || acc.components == 4));
                        prim.colours = acc;
                    } else {
                        GLTF_REQUIRE(false);
                    }
                }
                GLTF_REQUIRE(has_position);
                primitives.push_back(prim);
            }
        }
        primitives_[index] = std::move(primitives);
    }

    void retrieve_material(std::uint32_t index) {
        const Value& obj = element(find(doc_, "materials"), index);
        if (material_slot_[index] >= 0) return;
        material_slot_[index] = static_cast<int>(material_order_.size());
        material_order_.push_back(index);
        MaterialData m;
        if (const Value* pbr = find(obj, "pbrMetallicRoughness")) {
            GLTF_REQUIRE(pbr->IsObject());
            read_floats(*pbr, "baseColorFactor", m.base_colour);
            texture_info(*pbr, "baseColorTexture", m.base_colour_texture);
            texture_info(*pbr, "metallicRoughnessTexture", m.metallic_roughness_texture);
            read_float(*pbr, "metallicFactor", m.metallic);
            read_float(*pbr, "roughnessFactor", m.roughness);
        }
        texture_info(obj, "normalTexture", m.normal_texture);
        texture_info(obj, "occlusionTexture", m.occlusion_texture);
        texture_info(obj, "emissiveTexture", m.emissive_texture);
        read_floats(obj, "emissiveFactor", m.emissive);
        if (const Value* v = find(obj, "doubleSided")) {
            GLTF_REQUIRE(v->IsBool());
            m.double_sided = v->GetBool();
        }
        if (const Value* v = find(obj, "alphaMode")) {
            GLTF_REQUIRE(v->IsString());
            m.alpha_mode = std::string(v->GetString(), v->GetStringLength());
        }
        read_float(obj, "alphaCutoff", m.alpha_cutoff);
        if (const Value* extensions = find(obj, "extensions")) {
            GLTF_REQUIRE(extensions->IsObject());
            for (const auto& e : extensions->GetObject()) {
                const std::string_view name = e.name.GetString();
                GLTF_REQUIRE((name == "KHR_materials_unlit" || name == "KHR_materials_emissive_strength") && e.value.IsObject());
                m.unlit = m.unlit || name == "KHR_materials_unlit";
            }
        }
        materials_[index] = std::move(m);
    }

    // Material::SetTextureProperties (and the normal scale, occlusion strength).
    void texture_info(const Value& parent, const char* key, TextureInfo& out) {
        const Value* info = find(parent, key);
        if (!info) return;
        GLTF_REQUIRE(info->IsObject());
        if (const Value* extensions = find(*info, "extensions")) {
            GLTF_REQUIRE(extensions->IsObject());
            if (const Value* t = find(*extensions, "KHR_texture_transform"); t && texture_transform_) {
                GLTF_REQUIRE(t->IsObject());
                out.transform = true;
                read_floats(*t, "offset", out.offset);
                read_float(*t, "rotation", out.rotation);
                read_floats(*t, "scale", out.scale);
            }
        }
        if (const auto index = uint_member(*info, "index")) {
            retrieve_texture(*index);
            out.texture = index;
        }
        if (const auto set = uint_member(*info, "texCoord")) out.tex_coord = static_cast<int>(*set);
        if (std::string_view(key) == "normalTexture") read_float(*info, "scale", out.normal_scale);
        if (std::string_view(key) == "occlusionTexture") read_float(*info, "strength", out.occlusion_strength);
    }

    void retrieve_texture(std::uint32_t index) {
        const Value& obj = element(find(doc_, "textures"), index);
        if (texture_read_[index]) return;
        texture_read_[index] = true;
        GLTF_REQUIRE(!find(obj, "extensions"));
        if (const auto source = uint_member(obj, "source")) {
            retrieve_image(*source);
            textures_[index].image = source;
        }
        if (const auto sampler = uint_member(obj, "sampler")) {
            const Value& s = element(find(doc_, "samplers"), *sampler);
            if (!sampler_read_[*sampler]) {
                sampler_read_[*sampler] = true;
                auto wrap = [&](const char* k) {
                    const Value* v = find(s, k);
                    if (!v) return aiTextureMapMode_Wrap;
                    GLTF_REQUIRE(v->IsInt());
                    return v->GetInt() == 33648 ? aiTextureMapMode_Mirror
                                                : v->GetInt() == 33071 ? aiTextureMapMode_Clamp : aiTextureMapMode_Wrap;
                };
                wraps_[*sampler] = {wrap("wrapS"), wrap("wrapT")};
            }
            textures_[index].sampler = sampler;
        }
    }

    // An image with data (a data URI, or a buffer view with a MIME type) is embedded, numbered in
    // the order images are retrieved; assimp keeps a format hint of at most three letters from the
    // MIME type, without which it decodes nothing (so such images are left to it).
    void retrieve_image(std::uint32_t index) {
        const Value& obj = element(find(doc_, "images"), index);
        if (image_read_[index]) return;
        image_read_[index] = true;
        std::string mime;
        std::string data;
        if (const Value* uri = find(obj, "uri")) {
            GLTF_REQUIRE(uri->IsString());
            const std::string_view text(uri->GetString(), uri->GetStringLength());
            std::optional<DataUri> d = parse_data_uri(text);
            if (!d) {
                GLTF_REQUIRE(text.find('\\') == std::string_view::npos);
                images_[index].name = std::string(text);
                return;
            }
            mime = std::move(d->media_type);
            data = std::move(d->bytes);
        } else {
            const BufferView view = buffer_view(uint_member(obj, "bufferView").value_or(~0u));
            const Value* type = find(obj, "mimeType");
            GLTF_REQUIRE(type && type->IsString());
            mime = type->GetString();
            data.assign(reinterpret_cast<const char*>(view.data), view.length);
        }
        const std::size_t slash = mime.find('/');
        GLTF_REQUIRE(slash != std::string::npos && !data.empty());
        const std::string ext = mime.substr(slash + 1);
        GLTF_REQUIRE((!ext.empty() && ext.size() <= 3) || ext == "jpeg" || ext == "ktx2" || ext == "basis");
        images_[index].name = "*" + std::to_string(embedded_.size());
        embedded_.push_back(std::move(data));
    }

    std::string_view buffer(std::uint32_t index) {
        if (binary_ && index == 0) return body_;  // assimp's body buffer takes index 0 whatever the JSON says
        const Value& obj = element(find(doc_, "buffers"), index);
        if (buffer_read_[index]) return buffers_[index];
        buffer_read_[index] = true;
        const std::size_t stated = size_member(obj, "byteLength");
        const Value* uri = find(obj, "uri");
        if (!uri) {
            GLTF_REQUIRE(stated == 0);
            return buffers_[index];
        }
        GLTF_REQUIRE(uri->IsString());
        const std::string_view text(uri->GetString(), uri->GetStringLength());
        if (std::optional<DataUri> d = parse_data_uri(text)) {
            GLTF_REQUIRE(stated == 0 || stated == d->bytes.size());
            buffers_[index] = std::move(d->bytes);
            return buffers_[index];
        }
        if (stated == 0) return buffers_[index];
        // An external file: read where assimp's IOSystem would open it, if the resource rules allow.
        GLTF_REQUIRE(text.find('\\') == std::string_view::npos && stated <= options_.max_file_bytes);
        const std::string file = dir_ + std::string(text);
        GLTF_REQUIRE(notes_.may_open(roots_, file));
        const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
        GLTF_REQUIRE(fd >= 0);
        struct stat st {};
        std::string& out = buffers_[index];
        bool ok = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && static_cast<std::uint64_t>(st.st_size) >= stated;
        if (ok) {
            out.resize(stated);
            std::size_t got = 0;
            while (ok && got < stated) {
                const ssize_t n = ::read(fd, out.data() + got, stated - got);
                if (n < 0 && errno == EINTR) continue;
                ok = n > 0;
                if (ok) got += static_cast<std::size_t>(n);
            }
        }
        ::close(fd);
        GLTF_REQUIRE(ok);
        return out;
    }

    BufferView buffer_view(std::uint32_t index) {
        const Value& obj = element(find(doc_, "bufferViews"), index);
        const std::optional<std::uint32_t> b = uint_member(obj, "buffer");
        GLTF_REQUIRE(b.has_value());
        const std::string_view bytes = buffer(*b);
        const std::size_t offset = size_member(obj, "byteOffset"), length = size_member(obj, "byteLength");
        const std::size_t stride = size_member(obj, "byteStride");
        GLTF_REQUIRE(offset <= bytes.size() && length <= bytes.size() - offset);
        return {reinterpret_cast<const std::uint8_t*>(bytes.data()) + offset, length, stride};
    }

    // Accessor::Read's checks and ExtractData's, and one more: every element lies inside its view.
    Accessor accessor(std::uint32_t index) {
        const Value& obj = element(find(doc_, "accessors"), index);
        GLTF_REQUIRE(!find(obj, "sparse"));
        const BufferView view = buffer_view(uint_member(obj, "bufferView").value_or(~0u));
        const std::size_t offset = size_member(obj, "byteOffset");
        const Value* component = find(obj, "componentType");
        GLTF_REQUIRE(component && component->IsInt());
        const int type = component->GetInt();
        const std::size_t bytes = type == k_float || type == k_uint ? 4 : type == k_ushort ? 2 : type == k_ubyte ? 1 : 0;
        GLTF_REQUIRE(bytes > 0);
        const std::optional<std::uint32_t> count = uint_member(obj, "count");
        GLTF_REQUIRE(count && *count >= 1);
        const Value* kind = find(obj, "type");
        GLTF_REQUIRE(kind && kind->IsString());
        const std::string_view k = kind->GetString();
        const unsigned components = k == "SCALAR" ? 1 : k == "VEC2" ? 2 : k == "VEC3" ? 3 : k == "VEC4" ? 4 : 0;
        GLTF_REQUIRE(components > 0);
        const std::uint64_t elem = bytes * components, stride = view.stride ? view.stride : elem;
        GLTF_REQUIRE(offset <= view.length && bytes * *count <= view.length - offset && *count * stride <= view.length &&
                     (*count - 1) * stride + elem <= view.length - offset);
        return {view.data + offset, *count, static_cast<std::size_t>(stride), static_cast<std::size_t>(elem), type, components};
    }

    template <class T>
    static std::vector<T> extract(const Accessor& a) {
        std::vector<T> out;
        detail::reserve_in_huge_pages(out, a.count);  // faulted in per 2 MiB, not 4 KiB (a process loads once)
        out.resize(a.count);  // value-initialised: components beyond the accessor's stay zero
        for (std::size_t i = 0; i < a.count; ++i) std::memcpy(&out[i], a.data + i * a.stride, a.elem);
        return out;
    }

    // ImportMeshes, then JoinIdenticalVertices (over the vertices the faces use), FlipUVs.
    OwnMesh build_mesh(const Primitive& p) {
        const std::size_t n = p.positions.count;
        const std::vector<aiVector3D> positions = extract<aiVector3D>(p.positions);
        std::vector<aiVector3D> normals, tangents, bitangents, uvs;
        std::vector<aiColor4D> colours;
        if (p.normals && p.normals->count == n) {
            normals = extract<aiVector3D>(*p.normals);
            if (p.tangents && p.tangents->count == n) {
                struct Tangent {
                    aiVector3D xyz;
                    float w;
                };
                const std::vector<Tangent> t = extract<Tangent>(*p.tangents);
                detail::reserve_in_huge_pages(tangents, n);
                detail::reserve_in_huge_pages(bitangents, n);
                for (std::size_t i = 0; i < n; ++i) {
                    tangents.push_back(t[i].xyz);
                    bitangents.push_back((normals[i] ^ t[i].xyz) * t[i].w);
                }
            }
        }
        if (p.colours && p.colours->count == n) {
            if (p.colours->component == k_float) {
                colours = extract<aiColor4D>(*p.colours);
            } else if (p.colours->component == k_ubyte) {
                colours = normalised_colours<unsigned char>(*p.colours);
            } else {
                colours = normalised_colours<unsigned short>(*p.colours);
            }
        }
        if (p.uvs && p.uvs->count == n) {
            uvs = extract<aiVector3D>(*p.uvs);
            for (aiVector3D& t : uvs) t.y = 1 - t.y;     // the importer's flip
            for (aiVector3D& t : uvs) t.y = 1.0f - t.y;  // FlipUVs
        }
        // The primitive's vertex numbers (its indices, or 0, 1, 2, ...), then its triangles as
        // ImportMeshes makes them: a list, a strip (every second triangle's first two corners
        // swapped) or a fan.
        const std::size_t count = p.indices ? p.indices->count : n;
        std::vector<std::uint32_t> number;
        detail::reserve_in_huge_pages(number, count);
        number.resize(count);
        for (std::size_t i = 0; i < count; ++i) {
            std::uint32_t v = static_cast<std::uint32_t>(i);
            if (p.indices) std::memcpy(&v, p.indices->data + i * p.indices->stride, p.indices->elem);
            GLTF_REQUIRE(v < n);
            number[i] = v;
        }
        std::vector<std::uint32_t> corners;
        if (p.mode == 4) {
            corners = std::move(number);  // not read again
            corners.resize(count / 3 * 3);
        } else {
            GLTF_REQUIRE(count >= 3);
            detail::reserve_in_huge_pages(corners, 3 * (count - 2));
            for (std::size_t i = 0; i + 2 < count; ++i) {
                const bool strip = p.mode == 5, swap = strip && (i + 1) % 2 == 0;
                const std::uint32_t a = strip ? number[swap ? i + 1 : i] : number[0];
                const std::uint32_t b = strip ? number[swap ? i : i + 1] : number[i + 1];
                corners.insert(corners.end(), {a, b, number[i + 2]});
            }
        }
        GLTF_REQUIRE(!corners.empty());

        std::vector<char> used(n, 0);
        for (std::uint32_t c : corners) used[c] = 1;
        const aiVector3D zero;
        auto value_of = [&](std::size_t v) {
            return JoinVertex{positions[v], normals.empty() ? zero : normals[v], uvs.empty() ? zero : uvs[v],
                              tangents.empty() ? zero : tangents[v], bitangents.empty() ? zero : bitangents[v]};
        };
        std::vector<std::uint32_t> used_list;
        detail::reserve_in_huge_pages(used_list, n);
        for (std::size_t v = 0; v < n; ++v)
            if (used[v]) used_list.push_back(static_cast<std::uint32_t>(v));
        const auto item_value = [&](std::size_t i) { return value_of(used_list[i]); };
        std::vector<aiVector3D> unique_positions;
        std::optional<Join> exact_join = join_as_assimp(used_list.size(), item_value, n, unique_positions);
        const bool exact = exact_join.has_value();
        Join join;
        std::vector<std::uint32_t> unique_of;
        detail::reserve_in_huge_pages(unique_of, n);
        unique_of.assign(n, ~0u);
        if (exact) {
            join = std::move(*exact_join);
            for (std::size_t i = 0; i < used_list.size(); ++i) unique_of[used_list[i]] = join.unique[i];
            for (std::uint32_t& f : join.first) f = used_list[f];
        } else {
            join = assimp_join(n, value_of, [&](std::size_t v) { return used[v] != 0; });
            unique_of = join.unique;
        }
        OwnMesh out;
        out.material = p.material ? static_cast<unsigned>(material_slot_[*p.material]) : static_cast<unsigned>(material_order_.size());
        if (exact) out.positions = std::move(unique_positions);
        const std::size_t joined = join.first.size();
        if (!exact) detail::reserve_in_huge_pages(out.positions, joined);
        if (!normals.empty()) detail::reserve_in_huge_pages(out.normals, joined);
        if (!uvs.empty()) detail::reserve_in_huge_pages(out.uvs, joined);
        if (!colours.empty()) detail::reserve_in_huge_pages(out.colours, joined);
        if (!tangents.empty()) {
            detail::reserve_in_huge_pages(out.tangents, joined);
            detail::reserve_in_huge_pages(out.bitangents, joined);
        }
        for (std::uint32_t v : join.first) {
            if (!exact) out.positions.push_back(positions[v]);
            if (!normals.empty()) out.normals.push_back(normals[v]);
            if (!uvs.empty()) out.uvs.push_back(uvs[v]);
            if (!colours.empty()) out.colours.push_back(colours[v]);
            if (!tangents.empty()) out.tangents.push_back(tangents[v]), out.bitangents.push_back(bitangents[v]);
        }
        detail::reserve_in_huge_pages(out.triangles, corners.size());
        for (std::uint32_t c : corners) out.triangles.push_back(unique_of[c]);
        return out;
    }

    // GetVertexColorsForType: each channel over the type's maximum (alpha 0 for three channels).
    template <class T>
    static std::vector<aiColor4D> normalised_colours(const Accessor& a) {
        const std::vector<aiColor4t<T>> raw = extract<aiColor4t<T>>(a);
        const float max = std::numeric_limits<T>::max();
        std::vector<aiColor4D> out;
        out.reserve(raw.size());
        for (const aiColor4t<T>& c : raw) out.emplace_back(c.r / max, c.g / max, c.b / max, c.a / max);
        return out;
    }

    // ImportMaterial's properties (those the conversion reads), FlipUVs applied to the uv transforms.
    std::unique_ptr<aiMaterial> make_material(const MaterialData& m) const {
        auto out = std::make_unique<aiMaterial>();
        aiMaterial* a = out.get();
        const aiColor4D base(m.base_colour[0], m.base_colour[1], m.base_colour[2], m.base_colour[3]);
        a->AddProperty(&base, 1, AI_MATKEY_COLOR_DIFFUSE);
        a->AddProperty(&base, 1, AI_MATKEY_BASE_COLOR);
        texture_property(m.base_colour_texture, a, aiTextureType_DIFFUSE);
        texture_property(m.base_colour_texture, a, aiTextureType_BASE_COLOR);
        texture_property(m.metallic_roughness_texture, a, AI_MATKEY_GLTF_PBRMETALLICROUGHNESS_METALLICROUGHNESS_TEXTURE);
        a->AddProperty(&m.metallic, 1, AI_MATKEY_METALLIC_FACTOR);
        a->AddProperty(&m.roughness, 1, AI_MATKEY_ROUGHNESS_FACTOR);
        float shininess = 1 - m.roughness;
        shininess *= shininess * 1000;
        a->AddProperty(&shininess, 1, AI_MATKEY_SHININESS);
        if (texture_property(m.normal_texture, a, aiTextureType_NORMALS))
            a->AddProperty(&m.normal_texture.normal_scale, 1, AI_MATKEY_GLTF_TEXTURE_SCALE(aiTextureType_NORMALS, 0));
        if (texture_property(m.occlusion_texture, a, aiTextureType_LIGHTMAP))
            a->AddProperty(&m.occlusion_texture.occlusion_strength, 1, AI_MATKEY_GLTF_TEXTURE_STRENGTH(aiTextureType_LIGHTMAP, 0));
        texture_property(m.emissive_texture, a, aiTextureType_EMISSIVE);
        const aiColor4D emissive(m.emissive[0], m.emissive[1], m.emissive[2], 1.0f);
        a->AddProperty(&emissive, 1, AI_MATKEY_COLOR_EMISSIVE);
        a->AddProperty(&m.double_sided, 1, AI_MATKEY_TWOSIDED);
        a->AddProperty(&m.base_colour[3], 1, AI_MATKEY_OPACITY);
        const aiString alpha_mode(m.alpha_mode);
        a->AddProperty(&alpha_mode, AI_MATKEY_GLTF_ALPHAMODE);
        a->AddProperty(&m.alpha_cutoff, 1, AI_MATKEY_GLTF_ALPHACUTOFF);
        const aiShadingMode shading = m.unlit ? aiShadingMode_Unlit : aiShadingMode_PBR_BRDF;
        a->AddProperty(&shading, 1, AI_MATKEY_SHADING_MODEL);
        return out;
    }

    // SetMaterialTextureProperty; false when the info names no texture with an image.
    bool texture_property(const TextureInfo& info, aiMaterial* a, aiTextureType type, unsigned slot = 0) const {
        if (!info.texture || !textures_[*info.texture].image) return false;
        const TextureData& t = textures_[*info.texture];
        const aiString uri(images_[*t.image].name);
        a->AddProperty(&uri, AI_MATKEY_TEXTURE(type, slot));
        a->AddProperty(&info.tex_coord, 1, AI_MATKEY_UVWSRC(type, slot));
        if (info.transform) {
            aiUVTransform transform;
            transform.mScaling.x = info.scale[0];
            transform.mScaling.y = info.scale[1];
            transform.mRotation = -info.rotation;
            double rsin_d, rcos_d;  // assimp's std::sin and std::cos, with the same bits on every machine
            portable::sincos(static_cast<double>(-transform.mRotation), rsin_d, rcos_d);
            const float rcos(rcos_d);
            const float rsin(rsin_d);
            transform.mTranslation.x = (0.5f * transform.mScaling.x) * (-rcos + rsin + 1) + info.offset[0];
            transform.mTranslation.y = ((0.5f * transform.mScaling.y) * (rsin + rcos - 1)) + 1 - transform.mScaling.y - info.offset[1];
            transform.mTranslation.y *= -1.f;  // FlipUVs
            transform.mRotation *= -1.f;
            a->AddProperty(&transform, 1, _AI_MATKEY_UVTRANSFORM_BASE, type, slot);
        }
        aiTextureMapMode wrap_s = aiTextureMapMode_Wrap, wrap_t = aiTextureMapMode_Wrap;
        if (t.sampler) wrap_s = wraps_[*t.sampler].first, wrap_t = wraps_[*t.sampler].second;
        a->AddProperty(&wrap_s, 1, AI_MATKEY_MAPPINGMODE_U(type, slot));
        a->AddProperty(&wrap_t, 1, AI_MATKEY_MAPPINGMODE_V(type, slot));
        return true;
    }

    const LoadOptions& options_;
    const ResourceRoots& roots_;
    ImportNotes& notes_;
    std::string dir_;
    std::vector<char> json_;
    rapidjson::Document doc_;
    bool binary_ = false, texture_transform_ = false;
    std::string_view body_;
    std::vector<State> node_state_;
    std::vector<NodeData> nodes_;
    std::vector<int> mesh_slot_, material_slot_;
    std::vector<std::uint32_t> mesh_order_, material_order_;
    std::vector<std::vector<Primitive>> primitives_;
    std::vector<MaterialData> materials_;
    std::vector<TextureData> textures_;
    std::vector<bool> texture_read_, image_read_, sampler_read_, buffer_read_;
    std::vector<ImageData> images_;
    std::vector<std::pair<aiTextureMapMode, aiTextureMapMode>> wraps_;
    std::vector<std::string> buffers_;
    std::vector<std::string> embedded_;
    std::size_t built_nodes_ = 0;
};

}  // namespace

std::optional<OwnScene> read_gltf(const std::string& path, std::string_view bytes, bool binary, const LoadOptions& options,
                                  const ResourceRoots& roots, ImportNotes& notes) {
    try {
        if (path.find('\\') != std::string::npos) return std::nullopt;
        GltfReader reader(path, options, roots, notes);
        return reader.read(bytes, binary);
    } catch (const Decline& d) {
        if (std::getenv("FACET_DEBUG_DECLINE")) std::fprintf(stderr, "%s: declined at gltf.cpp:%d\n", path.c_str(), d.line);
        return std::nullopt;
    }
}

}  // namespace facet::io_detail
