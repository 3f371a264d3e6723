// facet io, the conversion every model reader ends in: a file's meshes, materials, nodes and
// embedded images, in the form assimp gives them after its post-processing (triangulated, identical
// vertices joined; materials as aiMaterial), into facet's Scene, with the limits of LoadOptions
// checked on the meshes' counts before converting. assimp's aiScene is one such source
// (assimp_import.cpp); facet's own OBJ and glTF readers build others (obj.hpp, gltf.hpp) from their
// own arrays, so that both give the same Scene by construction. No reading here.
#pragma once

#include <assimp/material.h>
#include <assimp/matrix4x4.h>
#include <assimp/types.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "facet/model.hpp"

struct aiScene;
struct aiNode;
struct aiFace;

namespace facet::io_detail {

class ResourceRoots;

// One mesh as views of its arrays (vertex_count entries each; normals, colours, uvs may be null).
// Its faces are either assimp's (of three, two and one indices: triangles, line segments and points,
// of a mesh whose primitive types include any of them) or, from facet's readers, three indices per
// triangle.
struct SourceMesh {
    std::uint32_t vertex_count = 0;
    const aiVector3D* positions = nullptr;
    const aiVector3D* normals = nullptr;
    const aiColor4D* colours = nullptr;
    const aiVector3D* uvs = nullptr;  // assimp's first uv channel (x, y used)
    const aiVector3D* tangents = nullptr;    // with bitangents, or neither (glTF's TANGENT, as assimp gives it)
    const aiVector3D* bitangents = nullptr;
    unsigned material = 0;
    bool drawn_mesh = false;           // assimp: its types include triangles, lines or points and it has faces
    const aiFace* faces = nullptr;     // assimp's
    std::uint32_t face_count = 0;
    const std::uint32_t* triangles = nullptr;  // facet's readers'
    std::size_t triangle_count = 0;
    // The vector that holds `triangles`, which the conversion may take as the Mesh's indices
    // instead of copying them (the array stays where it is); null for assimp's meshes.
    std::vector<std::uint32_t>* triangles_owner = nullptr;
    // The vector that holds `positions`, which the conversion frees once it has copied them, before
    // the normals are made (facet's readers'; null for assimp's): the heap then gives its pages to
    // the normals, of the same size, rather than fresh ones (docs/BENCHMARKS.md "Loading OBJ,
    // session 13").
    std::vector<aiVector3D>* positions_owner = nullptr;
    bool distinct_positions = false;  // facet's readers': positions pairwise distinct (creased normals need not weld)
    bool numbered = false;  // facet's readers': as kept_as_numbered finds (every vertex used, in order of first use; finite)
};

// A node of facet's readers' trees (assimp's are aiNodes): transform relative to the parent, the
// meshes it places, its children.
struct SourceNode {
    aiMatrix4x4 transform;
    std::vector<unsigned> meshes;
    std::vector<SourceNode> children;
};

// A whole file. `gltf` selects glTF's material rules (its base colour and alpha mode) over the
// others' (diffuse colour times opacity, blending when not opaque). Embedded images are found by
// the texture name a material gives ("*0", "*1", ... as assimp names them): in `assimp`'s aiScene,
// or, for facet's readers, in `embedded` (encoded PNG or JPEG bytes).
struct SourceScene {
    const aiNode* assimp_root = nullptr;  // the node tree: assimp's, or else
    const SourceNode* root = nullptr;     // facet's readers'
    std::vector<SourceMesh> meshes;
    std::vector<const aiMaterial*> materials;
    bool gltf = false;
    const aiScene* assimp = nullptr;
    std::map<std::string, std::string_view, std::less<>> embedded;
};

// What facet's own readers build (obj.hpp, gltf.hpp): the arrays a SourceScene views.
struct OwnMesh {
    std::vector<aiVector3D> positions, normals, uvs;  // normals and uvs empty, or one per position
    std::vector<aiColor4D> colours;                   // empty, or one per position
    std::vector<aiVector3D> tangents, bitangents;     // both empty, or one each per position (glTF's TANGENT)
    std::vector<std::uint32_t> triangles;             // three per triangle, each < positions.size()
    unsigned material = 0;
    bool distinct_positions = false;  // known to be pairwise distinct (by bits, -0 as +0)
    bool numbered = false;  // known to use every position, numbered in order of first use, and finite positions
};

struct OwnScene {
    std::vector<OwnMesh> meshes;
    std::vector<std::unique_ptr<aiMaterial>> materials;
    SourceNode root;
    bool gltf = false;
    std::map<std::string, std::string_view, std::less<>> embedded;  // views of data the reader keeps
    std::vector<std::string> kept;                                  // such data

    SourceScene view();  // the meshes' triangles may be taken, their positions freed, by the conversion
};

// The source of an aiScene (views of its arrays; the aiScene must outlive it).
SourceScene source_of(const aiScene& scene, bool gltf);

// Texture files are looked for where `roots` allows. Textures are decoded in parallel on
// options.threads threads.
Result<LoadedModel> convert_scene(const std::string& path, const SourceScene& scene, const LoadOptions& options,
                                  const ResourceRoots& roots);

}  // namespace facet::io_detail
