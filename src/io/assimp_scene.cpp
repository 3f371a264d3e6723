// facet io, the conversion every reader ends in (assimp_scene.hpp): a SourceScene into a Scene.
// The node hierarchy is walked, each mesh reference becomes a SceneObject (the mesh in its own
// space, the accumulated node transform as `model`; faces of 3, 2 and 1 vertices as triangles, line
// segments and points); those with non-finite or out-of-range vertices are dropped with a warning;
// missing normals are computed with the crease angle (and tangents where a normal map needs them);
// materials become glTF metallic-roughness (README, "Materials"): factors, alpha mode, sidedness and
// each map's texture (embedded, or a file the model's resource folders allow, found leniently:
// resources.hpp), a file's textures decoded in
// parallel. Not the reading itself.
#include "io/assimp_scene.hpp"

#include <assimp/GltfMaterial.h>
#include <assimp/material.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_set>
#include <utility>
#include <vector>

#include "exec/fresh_pages.hpp"
#include "facet/detail/thread_pool.hpp"
#include "facet/mesh.hpp"
#include "io/load_common.hpp"
#include "io/resources.hpp"
#include "math/portable_trig.hpp"
#include "scene/creased_normals.hpp"

namespace facet::io_detail {
namespace {

namespace fs = std::filesystem;

Mat4 to_mat4(const aiMatrix4x4& m) {
    // aiMatrix4x4 is row-major with the translation in a4, b4, c4 (it also transforms column
    // vectors), so its rows are our rows.
    return Mat4::from_rows({m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4});
}

// The faces of a mesh, in order: triangles, line segments and points (3, 2 and 1 vertex indices).
template <class F>
void for_each_face(const SourceMesh& m, F&& f) {
    if (m.triangles) {
        for (std::size_t t = 0; t < 3 * m.triangle_count; t += 3) f(m.triangles + t, 3u);
        return;
    }
    for (std::uint32_t i = 0; m.drawn_mesh && i < m.face_count; ++i)
        if (m.faces[i].mNumIndices >= 1 && m.faces[i].mNumIndices <= 3) f(m.faces[i].mIndices, m.faces[i].mNumIndices);
}

bool is_drawn_mesh(const SourceMesh& m) { return m.triangles ? m.triangle_count > 0 : m.drawn_mesh; }

// Triangles, points and segments: what the limits (max_triangles, the size estimate) count.
std::size_t face_count(const SourceMesh& m) {
    if (m.triangles) return m.triangle_count;
    std::size_t n = 0;
    for_each_face(m, [&](const unsigned*, unsigned) { ++n; });
    return n;
}

std::uint64_t estimated_bytes(const SourceMesh& m) {
    return estimated_scene_bytes(m.vertex_count, face_count(m), m.colours != nullptr, m.uvs != nullptr);
}

// Node transforms are composed parent-first. The walk is iterative (deep hierarchies cannot
// overflow the stack) and refuses cycles, which a corrupt file could build. assimp's nodes and
// facet's readers' are walked alike, through these accessors.
const aiMatrix4x4& transform_of(const aiNode& n) { return n.mTransformation; }
const aiMatrix4x4& transform_of(const SourceNode& n) { return n.transform; }
std::size_t mesh_count(const aiNode& n) { return n.mNumMeshes; }
std::size_t mesh_count(const SourceNode& n) { return n.meshes.size(); }
unsigned mesh_of(const aiNode& n, std::size_t i) { return n.mMeshes[i]; }
unsigned mesh_of(const SourceNode& n, std::size_t i) { return n.meshes[i]; }
std::size_t child_count(const aiNode& n) { return n.mNumChildren; }
std::size_t child_count(const SourceNode& n) { return n.children.size(); }
const aiNode* child_of(const aiNode& n, std::size_t i) { return n.mChildren[i]; }
const SourceNode* child_of(const SourceNode& n, std::size_t i) { return &n.children[i]; }

template <class Node>
struct NodeVisit {
    const Node* node;
    Mat4 world;
};

template <class Node, class F>
Status walk_tree(const std::string& path, const Node* root_node, std::size_t meshes, const Mat4& root, F&& visit_mesh) {
    std::vector<NodeVisit<Node>> stack;
    std::unordered_set<const Node*> seen;
    if (root_node) stack.push_back({root_node, root});
    while (!stack.empty()) {
        const NodeVisit<Node> v = stack.back();
        stack.pop_back();
        if (!seen.insert(v.node).second) return fail(ErrorCode::bad_format, path, "node hierarchy has a cycle");
        const Mat4 world = v.world * to_mat4(transform_of(*v.node));
        for (std::size_t i = 0; i < mesh_count(*v.node); ++i) {
            const unsigned mesh = mesh_of(*v.node, i);
            if (mesh >= meshes) return fail(ErrorCode::bad_format, path, "a node refers to a missing mesh");
            if (Status s = visit_mesh(mesh, world); !s) return s;
        }
        // Children pushed in reverse so they are visited in file order.
        for (std::size_t c = child_count(*v.node); c-- > 0;)
            if (const Node* child = child_of(*v.node, c)) stack.push_back({child, world});
    }
    return Ok{};
}

template <class F>
Status walk_nodes(const std::string& path, const SourceScene& scene, const Mat4& root, F&& visit_mesh) {
    if (scene.assimp_root) return walk_tree(path, scene.assimp_root, scene.meshes.size(), root, visit_mesh);
    return walk_tree(path, scene.root, scene.meshes.size(), root, visit_mesh);
}

// One mesh converted, shared by every node that refers to it.
struct ConvertedMesh {
    Mesh mesh;
    std::size_t dropped = 0;     // triangles, points and segments with a non-finite or out-of-range vertex
    std::size_t degenerate = 0;  // kept triangles with two corners at the same position
};

Vec3 to_vec3(const aiVector3D& v) { return {v.x, v.y, v.z}; }

bool finite_and_nonzero(const aiVector3D& n) {
    return std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z) && (n.x != 0 || n.y != 0 || n.z != 0);
}

Vec4 clamp_colour(const aiColor4D& c) { return unit_colour(c.r, c.g, c.b, c.a); }

bool finite_position(const SourceMesh& m, std::uint32_t i) {
    const aiVector3D& p = m.positions[i];
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

// Whether a reader's triangles use every vertex, numbered already in order of first use, and every
// position is finite: then the conversion keeps them as they are (no renumbering). Two sequential
// passes, the first stopping at the first number out of order.
bool kept_as_numbered(const SourceMesh& in) {
    if (!in.triangles) return false;
    if (in.numbered) return true;  // known to the reader
    std::uint32_t next = 0;  // the number the next new vertex must have
    for (std::size_t c = 0; c < 3 * in.triangle_count; ++c) {
        if (in.triangles[c] > next) return false;
        next += in.triangles[c] == next;
    }
    if (next != in.vertex_count) return false;
    for (std::uint32_t i = 0; i < in.vertex_count; ++i)
        if (!finite_position(in, i)) return false;
    return true;
}

// Keeps the triangles, segments and points whose vertices exist and are finite, then only the
// vertices they use, numbered in order of first use. With `tangents` (its material has a normal
// map), the file's tangents when it has them for its normals, else computed (compute_tangents).
ConvertedMesh convert_mesh(const SourceMesh& in, bool use_file_normals, float crease_angle_radians, int threads,
                           bool tangents) {
    ConvertedMesh out;
    const bool as_numbered = kept_as_numbered(in);
    std::vector<std::uint32_t> used;  // source vertex of each kept vertex (none kept here when as_numbered: all, in order)
    std::vector<std::uint32_t> remap(as_numbered ? 0 : in.vertex_count, ~0u);
    const auto source = [&](std::size_t k) { return as_numbered ? static_cast<std::uint32_t>(k) : used[k]; };
    auto finite = [&](unsigned i) { return finite_position(in, i); };
    auto degenerate = [&](const unsigned* corner) {
        const aiVector3D &pa = in.positions[corner[0]], &pb = in.positions[corner[1]], &pc = in.positions[corner[2]];
        return pa == pb || pb == pc || pc == pa;
    };
    if (as_numbered && in.triangles_owner) {
        out.mesh.indices = std::move(*in.triangles_owner);  // taken, not copied: in.triangles still points at them
    } else if (in.triangles) {
        detail::reserve_in_huge_pages(out.mesh.indices, 3 * in.triangle_count);
        if (as_numbered) out.mesh.indices.assign(in.triangles, in.triangles + 3 * in.triangle_count);
    }
    if (as_numbered) {
        for (std::size_t t = 0; t < 3 * in.triangle_count; t += 3) out.degenerate += degenerate(in.triangles + t);
    }
    // (None when kept as numbered: a mesh without faces.)
    for_each_face(as_numbered ? SourceMesh{} : in, [&](const unsigned* corner, unsigned n) {
        bool ok = true;
        for (unsigned k = 0; k < n; ++k) ok = ok && corner[k] < in.vertex_count && finite(corner[k]);
        if (!ok) {
            ++out.dropped;
            return;
        }
        if (n == 3) out.degenerate += degenerate(corner);
        std::vector<std::uint32_t>& list = n == 3 ? out.mesh.indices : n == 2 ? out.mesh.lines : out.mesh.points;
        for (unsigned k = 0; k < n; ++k) {
            std::uint32_t& r = remap[corner[k]];
            if (r == ~0u) {
                r = static_cast<std::uint32_t>(used.size());
                used.push_back(corner[k]);
            }
            list.push_back(r);
        }
    });
    Mesh& m = out.mesh;
    const std::size_t kept = as_numbered ? in.vertex_count : used.size();
    detail::reserve_in_huge_pages(m.positions, kept);
    for (std::size_t k = 0; k < kept; ++k) {
        const aiVector3D& p = in.positions[source(k)];
        m.positions.push_back({p.x, p.y, p.z});
    }
    // Read no more (the checks above were the last): freed, for the normals below to take their pages.
    if (in.positions_owner) std::vector<aiVector3D>().swap(*in.positions_owner);
    if (in.colours) {
        detail::reserve_in_huge_pages(m.colours, kept);
        for (std::size_t k = 0; k < kept; ++k) m.colours.push_back(clamp_colour(in.colours[source(k)]));
    }
    if (in.uvs) {
        detail::reserve_in_huge_pages(m.uvs, kept);
        for (std::size_t k = 0; k < kept; ++k) {
            const aiVector3D& t = in.uvs[source(k)];
            m.uvs.push_back({std::isfinite(t.x) ? t.x : 0.0f, std::isfinite(t.y) ? t.y : 0.0f});
        }
    }
    // The file's normals are used only when every one is usable; otherwise all are recomputed, so
    // a mesh never mixes the two.
    bool normals_ok = use_file_normals && in.normals;
    for (std::size_t k = 0; normals_ok && k < kept; ++k) normals_ok = finite_and_nonzero(in.normals[source(k)]);
    if (normals_ok) {
        detail::reserve_in_huge_pages(m.normals, kept);
        for (std::size_t k = 0; k < kept; ++k) {
            const aiVector3D& n = in.normals[source(k)];
            m.normals.push_back(normalize(Vec3{n.x, n.y, n.z}));
        }
    } else if (!m.indices.empty()) {
        // Reserved before the normals' scratch arrays: the freed positions' pages, where they fit.
        detail::reserve_in_huge_pages(m.normals, kept);
        // Positions known distinct (and so the used ones, renumbered): no welding.
        detail::compute_creased_normals_with(m, crease_angle_radians, threads, in.distinct_positions);
    }
    if (!tangents || m.uvs.empty()) return out;
    bool file_tangents = normals_ok && in.tangents && in.bitangents;
    for (std::size_t k = 0; file_tangents && k < kept; ++k)
        file_tangents = finite_and_nonzero(in.tangents[source(k)]) && is_finite(to_vec3(in.bitangents[source(k)]));
    if (!file_tangents) {
        compute_tangents(m);
        return out;
    }
    // assimp gives glTF's TANGENT w as the bitangent w cross(n, t).
    for (std::size_t k = 0; k < kept; ++k) {
        const Vec3 n = m.normals[k], t = normalize(to_vec3(in.tangents[source(k)]));
        m.tangents.push_back(Vec4(t, dot(cross(n, t), to_vec3(in.bitangents[source(k)])) < 0 ? -1.0f : 1.0f));
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

// Below this in every channel a specular colour is black: the material has no highlight.
constexpr float k_black_specular = 1e-3f;
// The smoothest roughness a Phong exponent maps to (n = 2e4): mirror-like, but with a highlight
// wider than a texel of the environment's sharpest level.
constexpr float k_min_phong_roughness = 0.1f;

// glTF's KHR_texture_transform from what assimp 5.2.5 makes of it. assimp re-centres the rotation
// for its bottom-left uv origin and aiProcess_FlipUVs then negates the rotation and the v translation;
// undone here, the glTF fields are offset (ox, oy), rotation r, scale (sx, sy), and uv' = T R S uv
// with R = [cos r, sin r; -sin r, cos r] in glTF's uv space (v = 0 at the top), which is facet's.
UvTransform gltf_uv_transform(const aiUVTransform& t) {
    const double r = t.mRotation, sx = t.mScaling.x, sy = t.mScaling.y;
    double sin_r = 0, cos_r = 1;
    portable::sincos(r, sin_r, cos_r);
    const double ox = t.mTranslation.x - 0.5 * sx * (-cos_r + sin_r + 1);
    const double oy = t.mTranslation.y + 0.5 * sy * (sin_r + cos_r - 1) + 1 - sy;
    UvTransform out;
    const double m[6] = {cos_r * sx, sin_r * sy, ox, -sin_r * sx, cos_r * sy, oy};
    for (int i = 0; i < 6; ++i) out.m[i] = std::isfinite(m[i]) ? static_cast<float>(m[i]) : (i == 0 || i == 4 ? 1.0f : 0.0f);
    return out;
}

// Everything about one file's conversion that outlives a single mesh.
class Converter {
public:
    Converter(const std::string& path, const SourceScene& scene, const LoadOptions& options, const ResourceRoots& roots)
        : path_(path), dir_(fs::path(path).parent_path()), scene_(scene), options_(options), roots_(roots) {
        gltf_ = scene.gltf;
        // STL's normals are per facet (often zero or stale): they are removed on import (see
        // load_model) and creased ones computed; this is a second guard.
        use_file_normals_ = model_extension(path) != "stl";
    }

    std::vector<std::string>& warnings() { return warnings_; }

    // The converted mesh `index` (converted once, on first use).
    ConvertedMesh& mesh(unsigned index) {
        auto it = meshes_.find(index);
        if (it == meshes_.end())
            it = meshes_.emplace(index, convert_mesh(scene_.meshes[index], use_file_normals_,
                                                     radians(options_.crease_angle_degrees), options_.threads,
                                                     has_normal_map(index))).first;
        return it->second;
    }

    // Notes that mesh `index` is placed (with uvs or not), so that its material's textures are
    // decoded with the others by load_textures.
    void request_material(unsigned mesh_index, bool has_uvs) {
        const unsigned index = scene_.meshes[mesh_index].material;
        if (index >= scene_.materials.size() || !has_uvs) return;
        const ConvertedMaterial& m = converted_material(index);
        for (const std::optional<MapSource>* map : {&m.base_colour, &m.metallic_roughness, &m.normal, &m.occlusion, &m.emissive})
            if (*map && textures_.emplace((*map)->name, nullptr).second) texture_order_.push_back((*map)->name);
    }

    // Decodes every requested texture, in parallel on options.threads threads; a texture that
    // cannot be used gives a warning (in the order the textures were first requested) and null.
    void load_textures() {
        std::vector<Result<std::shared_ptr<const Texture>>> loaded(texture_order_.size(), Error{});
        auto load = [&](std::size_t i) { loaded[i] = load_texture(texture_order_[i]); };
        if (options_.threads != 1 && texture_order_.size() > 1) {
            detail::ThreadPool pool(options_.threads <= 0 ? 0 : options_.threads);
            pool.parallel_for(texture_order_.size(), load);
        } else {
            for (std::size_t i = 0; i < texture_order_.size(); ++i) load(i);
        }
        for (std::size_t i = 0; i < texture_order_.size(); ++i) {
            const std::string& key = texture_order_[i];
            if (loaded[i])
                textures_[key] = loaded[i].value();
            else
                warnings_.push_back(path_ + ": texture '" + key + "' not used, the material colour stands in: " +
                                    loaded[i].error().message);
        }
    }

    // The material of mesh `index`, with its textures only when the mesh has uvs to sample them with
    // (after load_textures).
    Material material(unsigned mesh_index, bool has_uvs) {
        const unsigned index = scene_.meshes[mesh_index].material;
        if (index >= scene_.materials.size()) return Material{};
        const ConvertedMaterial& c = converted_material(index);
        Material m = c.material;
        if (!has_uvs) return m;
        auto texture = [&](const std::optional<MapSource>& map) { return map ? textures_[map->name] : nullptr; };
        if (c.base_colour) {
            m.base_colour_texture = texture(c.base_colour);
            if (!gltf_ && m.base_colour_texture && m.base_colour_texture->has_transparency()) m.alpha_mode = AlphaMode::blend;
        }
        m.metallic_roughness_map.texture = texture(c.metallic_roughness);
        m.normal_map.texture = texture(c.normal);
        m.occlusion_map.texture = texture(c.occlusion);
        m.emissive_map.texture = texture(c.emissive);
        return m;
    }

    // Whether the material of the file's mesh `mesh_index` has a normal map (its mesh then needs tangents).
    bool has_normal_map(unsigned mesh_index) {
        const unsigned index = scene_.meshes[mesh_index].material;
        return index < scene_.materials.size() && converted_material(index).normal.has_value();
    }

private:
    // A material's map: the assimp texture type it was found under and the texture's name ("*N"
    // for embedded ones).
    struct MapSource {
        aiTextureType type;
        std::string name;
    };
    struct ConvertedMaterial {
        Material material;  // factors, samplers and transforms; the textures are attached per mesh
        std::optional<MapSource> base_colour, metallic_roughness, normal, occlusion, emissive;
    };

    const ConvertedMaterial& converted_material(unsigned index) {
        auto it = materials_.find(index);
        if (it == materials_.end()) it = materials_.emplace(index, convert_material(*scene_.materials[index])).first;
        return it->second;
    }

    // The first of `types` the material has a texture of, with its sampler (and, for glTF, its
    // KHR_texture_transform) written into `sampler` and `transform`. A texture that reads another uv
    // set than the first is left out with a warning: meshes keep only the first.
    std::optional<MapSource> find_map(const aiMaterial& am, std::initializer_list<aiTextureType> types, Sampler& sampler,
                                      UvTransform& transform) const {
        for (aiTextureType type : types) {
            if (am.GetTextureCount(type) == 0) continue;
            int uv_set = 0;
            if (am.Get(AI_MATKEY_UVWSRC(type, 0), uv_set) == AI_SUCCESS && uv_set != 0) {
                warnings_.push_back(path_ + ": a texture reads uv set " + std::to_string(uv_set) +
                                    ", which facet does not keep; it is not used");
                return std::nullopt;
            }
            int u = aiTextureMapMode_Wrap, v = aiTextureMapMode_Wrap;
            am.Get(AI_MATKEY_MAPPINGMODE_U(type, 0), u);
            am.Get(AI_MATKEY_MAPPINGMODE_V(type, 0), v);
            sampler.wrap_u = to_wrap(u);
            sampler.wrap_v = to_wrap(v);
            aiUVTransform t;
            if (gltf_ && am.Get(AI_MATKEY_UVTRANSFORM(type, 0), t) == AI_SUCCESS) transform = gltf_uv_transform(t);
            aiString name;
            // No name, or the placeholder assimp's MD2 reader puts in to keep the uvs: no texture.
            if (am.GetTexture(type, 0, &name) != AI_SUCCESS || name.length == 0 ||
                std::string_view(name.C_Str()) == "$texture_dummy.bmp")
                return std::nullopt;
            return MapSource{type, name.C_Str()};
        }
        return std::nullopt;
    }

    // glTF 2.0's metallic-roughness as assimp gives it, or the mapping of other formats' materials
    // (README, "Materials"): base colour from glTF's base colour (its alpha the opacity) or the
    // diffuse colour times AI_MATKEY_OPACITY; metallic and roughness from their factors when the
    // file has them, else from the Phong terms: metallic 0, roughness 1 for a black specular colour,
    // (2 / (shininess + 2))^(1/4) for a positive shininess (GGX's alpha = sqrt(2 / (n + 2)) matches a
    // Blinn-Phong exponent n), the default otherwise. Alpha mode: glTF's alphaMode and alphaCutoff;
    // other formats blend when the material or its texture is not fully opaque (the texture part is
    // decided in material()).
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
        int shading = 0;
        if (am.Get(AI_MATKEY_SHADING_MODEL, shading) == AI_SUCCESS) m.unlit = shading == aiShadingMode_Unlit;

        auto unit = [](float v, float fallback) { return std::isfinite(v) ? clamp(v, 0.0f, 1.0f) : fallback; };
        float metallic = 0, roughness = 0;
        const bool has_metallic = am.Get(AI_MATKEY_METALLIC_FACTOR, metallic) == AI_SUCCESS;
        const bool has_roughness = am.Get(AI_MATKEY_ROUGHNESS_FACTOR, roughness) == AI_SUCCESS;
        if (has_metallic || has_roughness) {
            if (has_metallic) m.metallic = unit(metallic, m.metallic);
            if (has_roughness) m.roughness = unit(roughness, m.roughness);
        } else {
            m.metallic = 0;
            aiColor4D specular(1, 1, 1, 1);
            float shininess = 0;
            if (am.Get(AI_MATKEY_COLOR_SPECULAR, specular) == AI_SUCCESS &&
                std::max({specular.r, specular.g, specular.b}) < k_black_specular)
                m.roughness = 1;
            else if (am.Get(AI_MATKEY_SHININESS, shininess) == AI_SUCCESS && std::isfinite(shininess) && shininess > 0)
                m.roughness = clamp(std::sqrt(std::sqrt(2 / (shininess + 2))), k_min_phong_roughness, 1.0f);
        }
        aiColor4D emissive(0, 0, 0, 1);
        if (am.Get(AI_MATKEY_COLOR_EMISSIVE, emissive) == AI_SUCCESS) {
            auto positive = [](float v) { return std::isfinite(v) && v > 0 ? v : 0.0f; };
            m.emissive = {positive(emissive.r), positive(emissive.g), positive(emissive.b)};
        }
        float strength = 1;
        if (am.Get(AI_MATKEY_EMISSIVE_INTENSITY, strength) == AI_SUCCESS && std::isfinite(strength) && strength >= 0)
            m.emissive = m.emissive * strength;

        out.base_colour = find_map(am, {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE}, m.sampler, m.base_colour_transform);
        if (gltf_)
            // (AI_MATKEY_GLTF_PBRMETALLICROUGHNESS_METALLICROUGHNESS_TEXTURE: assimp 5.2.5 files it as UNKNOWN)
            out.metallic_roughness = find_map(am, {aiTextureType_UNKNOWN},
                                              m.metallic_roughness_map.sampler, m.metallic_roughness_map.transform);
        out.normal = find_map(am, {aiTextureType_NORMALS}, m.normal_map.sampler, m.normal_map.transform);
        if (out.normal) {
            float scale = 1;
            if (am.Get(AI_MATKEY_GLTF_TEXTURE_SCALE(aiTextureType_NORMALS, 0), scale) == AI_SUCCESS && std::isfinite(scale))
                m.normal_scale = scale;
        }
        // glTF's occlusion map arrives as assimp's light map; other formats' light maps are not occlusion.
        out.occlusion = find_map(am, gltf_ ? std::initializer_list<aiTextureType>{aiTextureType_LIGHTMAP}
                                           : std::initializer_list<aiTextureType>{aiTextureType_AMBIENT_OCCLUSION},
                                 m.occlusion_map.sampler, m.occlusion_map.transform);
        if (out.occlusion) {
            const aiTextureType type = out.occlusion->type;
            float s = 1;
            if (am.Get(AI_MATKEY_GLTF_TEXTURE_STRENGTH(type, 0), s) == AI_SUCCESS && std::isfinite(s))
                m.occlusion_strength = clamp(s, 0.0f, 1.0f);
        }
        out.emissive = find_map(am, {aiTextureType_EMISSIVE, aiTextureType_EMISSION_COLOR}, m.emissive_map.sampler,
                                m.emissive_map.transform);
        // An emissive map without an emissive colour (OBJ's map_Ke alone) means the map as it is.
        if (out.emissive && m.emissive == Vec3{0, 0, 0} && !gltf_) m.emissive = {1, 1, 1};
        return out;
    }

    Result<std::shared_ptr<const Texture>> load_texture(const std::string& name) const {
        if (const aiTexture* embedded = scene_.assimp ? scene_.assimp->GetEmbeddedTexture(name.c_str()) : nullptr)
            return decode_embedded(*embedded, name);
        if (auto it = scene_.embedded.find(name); it != scene_.embedded.end())
            return Texture::decode(it->second.data(), it->second.size(), embedded_label(name), options_.texture_limits);
        if (!name.empty() && name[0] == '*')
            return Error{ErrorCode::bad_format, "embedded texture " + name + " does not exist in the file"};
        const Result<fs::path> file = find_texture_file(roots_, dir_, name);
        if (!file) return file.error();
        return Texture::load(file->string(), options_.texture_limits);
    }

    std::string embedded_label(const std::string& name) const { return path_ + " (embedded texture " + name + ")"; }

    // Compressed (PNG, JPEG, ...): mHeight == 0 and mWidth bytes. Uncompressed: mWidth x mHeight
    // BGRA texels.
    Result<std::shared_ptr<const Texture>> decode_embedded(const aiTexture& t, const std::string& name) const {
        const std::string label = embedded_label(name);
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
    const SourceScene& scene_;
    const LoadOptions& options_;
    const ResourceRoots& roots_;
    bool gltf_ = false, use_file_normals_ = true;
    std::map<unsigned, ConvertedMesh> meshes_;
    std::map<unsigned, ConvertedMaterial> materials_;
    std::map<std::string, std::shared_ptr<const Texture>> textures_;
    std::vector<std::string> texture_order_;  // the names in textures_, in order of first request
    mutable std::vector<std::string> warnings_;
};

}  // namespace

SourceScene source_of(const aiScene& scene, bool gltf) {
    SourceScene out;
    out.assimp_root = scene.mRootNode;
    out.gltf = gltf;
    out.assimp = &scene;
    out.meshes.reserve(scene.mNumMeshes);
    for (unsigned i = 0; i < scene.mNumMeshes; ++i) {
        const aiMesh& m = *scene.mMeshes[i];
        SourceMesh s;
        s.vertex_count = m.mNumVertices;
        s.positions = m.mVertices;
        s.normals = m.mNormals;
        s.colours = m.HasVertexColors(0) ? m.mColors[0] : nullptr;
        s.uvs = m.HasTextureCoords(0) ? m.mTextureCoords[0] : nullptr;
        if (m.HasTangentsAndBitangents()) s.tangents = m.mTangents, s.bitangents = m.mBitangents;
        s.material = m.mMaterialIndex;
        s.drawn_mesh = (m.mPrimitiveTypes & (aiPrimitiveType_TRIANGLE | aiPrimitiveType_LINE | aiPrimitiveType_POINT)) != 0 &&
                       m.mNumFaces > 0;
        s.faces = m.mFaces;
        s.face_count = m.mNumFaces;
        out.meshes.push_back(s);
    }
    out.materials.assign(scene.mMaterials, scene.mMaterials + scene.mNumMaterials);
    return out;
}

SourceScene OwnScene::view() {
    SourceScene out;
    out.root = &root;
    out.gltf = gltf;
    out.embedded = embedded;
    out.meshes.reserve(meshes.size());
    for (OwnMesh& m : meshes) {
        SourceMesh s;
        s.vertex_count = static_cast<std::uint32_t>(m.positions.size());
        s.positions = m.positions.data();
        s.normals = m.normals.empty() ? nullptr : m.normals.data();
        s.colours = m.colours.empty() ? nullptr : m.colours.data();
        s.uvs = m.uvs.empty() ? nullptr : m.uvs.data();
        if (!m.tangents.empty()) s.tangents = m.tangents.data(), s.bitangents = m.bitangents.data();
        s.material = m.material;
        s.triangles = m.triangles.data();
        s.triangle_count = m.triangles.size() / 3;
        s.triangles_owner = &m.triangles;
        s.positions_owner = &m.positions;
        s.distinct_positions = m.distinct_positions;
        s.numbered = m.numbered;
        s.drawn_mesh = s.triangle_count > 0;
        out.meshes.push_back(s);
    }
    for (const std::unique_ptr<aiMaterial>& m : materials) out.materials.push_back(m.get());
    return out;
}

Result<LoadedModel> convert_scene(const std::string& path, const SourceScene& scene, const LoadOptions& options,
                                  const ResourceRoots& roots) {
    const Mat4 root = up_axis_root(options.up_axis);

    // The limits count every instance, since each becomes a mesh of its own.
    std::size_t instance_triangles = 0;
    std::uint64_t scene_bytes = 0;
    std::vector<std::size_t> references(scene.meshes.size(), 0);
    Status counted = walk_nodes(path, scene, root, [&](unsigned mesh, const Mat4&) -> Status {
        ++references[mesh];
        instance_triangles += face_count(scene.meshes[mesh]);
        if (instance_triangles > options.max_triangles) return too_many_triangles(path, instance_triangles, options);
        scene_bytes += estimated_bytes(scene.meshes[mesh]);
        if (scene_bytes > options.max_scene_bytes)
            return fail(ErrorCode::limit_exceeded, path,
                        "would take at least " + std::to_string(scene_bytes) +
                            " bytes once converted (every instance of a mesh is a copy), more than the limit of " +
                            std::to_string(options.max_scene_bytes) + " bytes");
        return Ok{};
    });
    if (!counted) return counted.error();
    if (instance_triangles == 0)
        return fail(ErrorCode::bad_format, path, "contains no triangles, points or lines (or nothing placed in the scene)");

    // The meshes converted and placed, then their textures decoded together, then the objects.
    Converter converter(path, scene, options, roots);
    struct Placement {
        unsigned mesh;
        Mat4 world;
    };
    std::vector<Placement> placements;
    std::size_t dropped = 0, kept = 0, degenerate = 0, points_lines = 0;
    std::unordered_set<unsigned> counted_meshes;
    Status placed = walk_nodes(path, scene, root, [&](unsigned index, const Mat4& world) -> Status {
        if (!is_drawn_mesh(scene.meshes[index])) {
            --references[index];
            return Ok{};
        }
        ConvertedMesh& converted = converter.mesh(index);
        if (counted_meshes.insert(index).second) {
            dropped += converted.dropped;
            kept += converted.mesh.triangle_count();
            degenerate += converted.degenerate;
            points_lines += converted.mesh.points.size() + converted.mesh.lines.size();
        }
        const Mesh& m = converted.mesh;
        if (m.indices.empty() && m.points.empty() && m.lines.empty()) {
            --references[index];
            return Ok{};
        }
        converter.request_material(index, !converted.mesh.uvs.empty());
        placements.push_back({index, world});
        return Ok{};
    });
    if (!placed) return placed.error();
    converter.load_textures();
    LoadedModel out;
    out.scene.objects.reserve(placements.size());
    for (const Placement& p : placements) {
        ConvertedMesh& converted = converter.mesh(p.mesh);
        SceneObject object;
        object.material = converter.material(p.mesh, !converted.mesh.uvs.empty());
        object.model = p.world;
        // The last instance takes the mesh, the others copy it.
        object.mesh = --references[p.mesh] == 0 ? std::move(converted.mesh) : converted.mesh;
        out.scene.objects.push_back(std::move(object));
    }
    if (out.scene.objects.empty())
        return fail(ErrorCode::bad_format, path,
                    "has no valid triangles, points or lines (" + std::to_string(dropped) +
                        " dropped for non-finite coordinates or out-of-range indices)");
    // Zero-area triangles are harmless among others, but a file of nothing else shows nothing.
    if (degenerate == kept && points_lines == 0)
        return fail(ErrorCode::bad_format, path,
                    "has no valid triangles (all " + std::to_string(kept) + " have two corners at the same position)");
    if (dropped > 0)
        out.warnings.push_back(path + ": dropped " + std::to_string(dropped) +
                               " triangles, points or segments with non-finite coordinates or out-of-range indices");
    for (std::string& w : converter.warnings()) out.warnings.push_back(std::move(w));
    return out;
}

}  // namespace facet::io_detail
