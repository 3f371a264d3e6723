// facet: scenes of meshes rendered with a camera and a shading mode, the automatic framing rule,
// and the built-in default scene. This is what `facet render` and `facet view` share up to the pixels.
#pragma once

#include <memory>
#include <string_view>
#include <vector>

#include "facet/camera.hpp"
#include "facet/mesh.hpp"
#include "facet/renderer.hpp"
#include "facet/texture.hpp"

namespace facet {

enum class Shading { lit, lambert, flat, normals, mask, vertex_color };
// Parses "lit", "lambert", ... Returns false for an unknown name.
bool parse_shading(std::string_view name, Shading& out);
const char* to_string(Shading s);

enum class AlphaMode { opaque, mask, blend };  // as glTF: ignore alpha, cut at alpha_cutoff, blend

struct Material {
    Vec4 base_colour{1, 1, 1, 1};    // multiplies vertex colours and the texture
    std::shared_ptr<const Texture> base_colour_texture;  // sampled with the mesh's uvs; may be null
    Sampler sampler;
    AlphaMode alpha_mode = AlphaMode::opaque;
    float alpha_cutoff = 0.5f;
    bool double_sided = true;
};

struct SceneObject {
    Mesh mesh;                       // object space; needs normals for lit, lambert and normals modes
    Mat4 model = Mat4::identity();   // object -> world
    Material material;
};

struct Scene {
    std::vector<SceneObject> objects;
    Aabb bounds() const;  // world space
    // Largest distance of a (world-space) vertex from `centre`.
    float radius_about(Vec3 centre) const;
    std::size_t triangle_count() const;
};

struct RenderSettings {
    Shading shading = Shading::lit;
    Vec4 background{0.11f, 0.12f, 0.14f, 1.0f};
    CullMode cull = CullMode::none;  // files often have inconsistent winding; the depth test sorts it out
};

// The framing rule that other renderers can reproduce exactly: centre = centre of the bounds,
// r = largest vertex distance from it, dist = r / sin(min(fovy, fovx) / 2),
// near = max(dist - 1.5 r, 0.01 r), far = dist + 1.5 r, eye on the orbit sphere at (azimuth, elevation).
Camera frame_scene(const Scene& scene, float azimuth, float elevation, float fovy, float aspect);

// Clears the target to the background and draws every object.
DrawStats render_scene(Renderer& renderer, Framebuffer& target, const Scene& scene, const Camera& camera,
                       const RenderSettings& settings);

// Built from embedded data, no files: a checkered floor, a cube, a sphere and a torus.
Scene default_scene();
// The camera the default scene is meant to be seen from.
Camera default_scene_camera(float aspect);

}  // namespace facet
