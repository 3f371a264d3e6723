// facet io, the assimp path's second half: an aiScene (assimp_import.hpp) converted into a Scene.
// The node hierarchy is walked, each mesh reference becomes a SceneObject (the mesh in its own
// space, the accumulated node transform as `model`); triangles with non-finite or out-of-range
// vertices are dropped with a warning; missing normals are computed with the crease angle; materials
// give base colour, opacity, alpha mode, sidedness and the base-colour texture (embedded, or a file
// the model's resource folders allow, found leniently: resources.hpp). Not the reading itself, nor facet's own readers.
#include "io/assimp_scene.hpp"

#include <assimp/GltfMaterial.h>
#include <assimp/material.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_set>
#include <utility>
#include <vector>

#include "facet/mesh.hpp"
#include "io/load_common.hpp"
#include "io/resources.hpp"

namespace facet::io_detail {
namespace {

namespace fs = std::filesystem;

Mat4 to_mat4(const aiMatrix4x4& m) {
    // aiMatrix4x4 is row-major with the translation in a4, b4, c4 (it also transforms column
    // vectors), so its rows are our rows.
    return Mat4::from_rows({m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4});
}

bool is_triangle_mesh(const aiMesh& m) { return (m.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) != 0 && m.mNumFaces > 0; }

std::size_t triangle_count(const aiMesh& m) {
    if (!is_triangle_mesh(m)) return 0;
    std::size_t n = 0;
    for (unsigned f = 0; f < m.mNumFaces; ++f) n += m.mFaces[f].mNumIndices == 3;
    return n;
}

std::uint64_t estimated_bytes(const aiMesh& m) {
    return estimated_scene_bytes(m.mNumVertices, triangle_count(m), m.HasVertexColors(0), m.HasTextureCoords(0));
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
    Converter(const std::string& path, const aiScene& scene, const LoadOptions& options, const ResourceRoots& roots)
        : path_(path), dir_(fs::path(path).parent_path()), scene_(scene), options_(options), roots_(roots) {
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
        const Result<fs::path> file = find_texture_file(roots_, dir_, name);
        if (!file) return file.error();
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
    const ResourceRoots& roots_;
    bool gltf_ = false, use_file_normals_ = true;
    std::map<unsigned, ConvertedMesh> meshes_;
    std::map<unsigned, ConvertedMaterial> materials_;
    std::map<std::string, std::shared_ptr<const Texture>> textures_;
    std::vector<std::string> warnings_;
};

}  // namespace

Result<LoadedModel> convert_scene(const std::string& path, const aiScene& scene, const LoadOptions& options,
                                  const ResourceRoots& roots) {
    const Mat4 root = up_axis_root(options.up_axis);

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

    Converter converter(path, scene, options, roots);
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

}  // namespace facet::io_detail
