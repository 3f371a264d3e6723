// Test support: glTF 2.0 files written from facet meshes, for the loader's and the lit mode's tests
// (a grid of spheres from metallic 0..1 by roughness 0..1, one texture of each kind). What is
// written is exactly what the structs say: every mesh's positions, normals, uvs (and tangents when
// the mesh has them) in one buffer embedded as a data URI, images as PNG files next to the document.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "facet/image.hpp"
#include "facet/mesh.hpp"

namespace facet_test {

// A material's reference to a texture (textureInfo): an image of GltfDocument::images.
struct GltfTextureRef {
    int image = -1;                  // -1: none
    int wrap_s = 10497, wrap_t = 10497;  // REPEAT
    std::string extensions;          // the textureInfo's "extensions" object, e.g. KHR_texture_transform
};

struct GltfMaterial {
    float base_colour[4] = {1, 1, 1, 1};
    float metallic = 1, roughness = 1;
    GltfTextureRef base_colour_texture, metallic_roughness_texture, normal_texture, occlusion_texture,
        emissive_texture;
    float normal_scale = 1, occlusion_strength = 1;
    float emissive[3] = {0, 0, 0};
    std::string alpha_mode = "OPAQUE";
    float alpha_cutoff = 0.5f;
    bool double_sided = false;
    std::string extensions;  // the material's "extensions" object, e.g. KHR_materials_emissive_strength
};

struct GltfNode {
    facet::Mesh mesh;  // positions, normals; uvs and tangents written when present
    int material = 0;
    facet::Vec3 translation{};
};

struct GltfDocument {
    std::vector<GltfNode> nodes;
    std::vector<GltfMaterial> materials;
    std::vector<facet::Image> images;  // written as <stem>_image<i>.png next to the document
    std::vector<std::string> extensions_used;
};

// Writes `doc` as `path` (a .gltf) and its images beside it; returns the path as a string.
std::string write_gltf(const std::filesystem::path& path, const GltfDocument& doc);

// A quad of side 2 in the XY plane facing +Z (the default camera), normals +Z, uv (0, 0) at the top
// left (+Y), as glTF lays images out; `mirrored_u` flips u (the tangent then points to -X).
facet::Mesh facing_quad(bool mirrored_u = false);

// The lit mode's test chart: spheres in a rows x columns grid on the XY plane, facing +Z (the
// default camera's view), metallic = row / (rows - 1) from the top row down and roughness =
// column / (columns - 1) from left to right, base colour `colour`. Spheres `spacing` apart, radius 1.
GltfDocument sphere_grid(int rows, int columns, float spacing, const float (&colour)[3]);

}  // namespace facet_test
