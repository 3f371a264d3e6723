// facet: scenes of meshes rendered with a camera and a shading mode, the automatic framing rule,
// and the built-in default scene. This is what `facet render` and `facet view` share up to the pixels.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "facet/api.hpp"
#include "facet/camera.hpp"
#include "facet/defaults.hpp"
#include "facet/environment.hpp"
#include "facet/mesh.hpp"
#include "facet/renderer.hpp"
#include "facet/texture.hpp"
#include "facet/tone_mapping.hpp"

FACET_API_BEGIN
namespace facet {

enum class Shading { lit, lambert, flat, normals, mask, vertex_color, texture };
// Parses "lit", "lambert", ... Returns false for an unknown name.
bool parse_shading(std::string_view name, Shading& out);
const char* to_string(Shading s);

enum class AlphaMode { opaque, mask, blend };  // as glTF: ignore alpha, cut at alpha_cutoff, blend

// A texture as a material uses it: the image, how it is sampled, and where (KHR_texture_transform).
struct TextureMap {
    std::shared_ptr<const Texture> texture;  // null: no map, the material's factor alone
    Sampler sampler;
    UvTransform transform;
};

// glTF 2.0's metallic-roughness material; other formats are mapped onto it when loaded (README,
// "Materials"). Colours and factors are linear; textures marked sRGB are decoded when sampled by the
// lit mode. The other modes read the base colour (and its texture and alpha) only.
struct Material {
    Vec4 base_colour{1, 1, 1, 1};    // multiplies vertex colours and the texture
    std::shared_ptr<const Texture> base_colour_texture;  // sRGB; sampled with the mesh's uvs; may be null
    Sampler sampler;
    AlphaMode alpha_mode = AlphaMode::opaque;
    float alpha_cutoff = 0.5f;
    bool double_sided = true;
    UvTransform base_colour_transform;  // where base_colour_texture is sampled (lit mode)
    float metallic = defaults::k_metallic;    // 0 dielectric .. 1 metal
    float roughness = defaults::k_roughness;  // perceptual roughness, 0 mirror .. 1 matte
    TextureMap metallic_roughness_map;  // linear: B multiplies metallic, G roughness
    TextureMap normal_map;              // linear, tangent space (the mesh's tangents)
    float normal_scale = 1;             // scales the map's x and y
    TextureMap occlusion_map;           // linear: R is the ambient occlusion
    float occlusion_strength = 1;       // 0: none, 1: the map's full value
    Vec3 emissive{0, 0, 0};             // linear radiance, times the map (KHR_materials_emissive_strength folded in)
    TextureMap emissive_map;            // sRGB
    bool unlit = false;                 // KHR_materials_unlit: the base colour, not lit
};

struct SceneObject {
    Mesh mesh;                       // object space; needs normals for lit, lambert and normals modes
    Mat4 model = Mat4::identity();   // object -> world
    Material material;
};

// What rendering and framing read of an object: its arrays, placement and material, none of them
// owned. view_of gives one for a SceneObject; a caller that keeps meshes in memory of its own (the
// Python package's NumPy arrays) fills one in instead, with no copy. The arrays must hold
// vertex_count entries each (normals, colours and uvs may be null) and outlive the call.
struct ObjectView {
    const Vec3* positions = nullptr;
    const Vec3* normals = nullptr;
    const Vec4* colours = nullptr;
    const Vec2* uvs = nullptr;
    std::uint32_t vertex_count = 0;
    std::span<const std::uint32_t> indices;  // three per triangle
    Mat4 model = Mat4::identity();
    const Material* material = nullptr;  // never null
    const Vec4* tangents = nullptr;      // Mesh::tangents, or null (normal maps are then not used)
    std::span<const std::uint32_t> points;  // one per point (Mesh::points)
    std::span<const std::uint32_t> lines;   // two per segment (Mesh::lines)
};
ObjectView view_of(const SceneObject& object);

struct Scene {
    std::vector<SceneObject> objects;
    Aabb bounds() const;  // world space
    // Largest distance of a (world-space) vertex from `centre`.
    float radius_about(Vec3 centre) const;
    std::size_t triangle_count() const;
};

// A light fixed to the camera, so that it lights every view alike. `direction` points toward the
// light in the camera's frame: x right, y up, z toward the viewer (it need not be unit length).
struct CameraLight {
    Vec3 direction;
    Vec3 colour;
};

// The lights of the lit and flat modes (not of lambert, whose lighting is a fixed contract, nor of
// the unlit modes). Defaults: facet/defaults.hpp.
struct Lighting {
    CameraLight key{defaults::k_key_light_direction, defaults::k_key_light_colour};
    CameraLight fill{defaults::k_fill_light_direction, defaults::k_fill_light_colour};
    float ambient = defaults::k_lit_ambient;
    float diffuse = defaults::k_lit_diffuse;
    float specular = defaults::k_lit_specular;  // strength of the Blinn-Phong highlight
    float shininess = defaults::k_lit_shininess;
};

// The world-space direction toward `light` (normalized) for a camera with this basis. The terms
// are summed toward-the-viewer first, then the larger of up and right: the order fixes the bits.
Vec3 world_light_direction(const CameraLight& light, const CameraBasis& basis);

struct RenderSettings {
    Shading shading = Shading::lit;
    Vec4 background = defaults::k_background;  // alpha 0 for a transparent PNG
    // none: files often have inconsistent winding, so only single-sided materials are culled.
    // back/front: forced for every object. The lambert mode never culls.
    CullMode cull = CullMode::none;
    Lighting lighting{};  // the flat mode's lights
    // The lit mode's light and display transform (README, "The lit mode"): the environment
    // (null: the built-in studio, Environment::studio()), exposure and tone mapping.
    std::shared_ptr<const Environment> environment{};
    float exposure = defaults::k_exposure;
    ToneMapping tone_mapping = ToneMapping::neutral;
    // Moves the image by this many pixels of the target, right and down: the sub-pixel offset of
    // one frame of anti-aliasing by jittered frames (antialias_offsets). Zero: none.
    Vec2 pixel_offset{0, 0};
    // Points and lines (Mesh::points, Mesh::lines): size, shape and width, in pixels of the target;
    // with point_size_in_model_units, the point size is in world units, perspective-scaled
    // (render_scene sets primitives.model_scale from the camera; the value given there is ignored).
    // Points and lines without normals are drawn unlit (their vertex or base colour) in the lit,
    // lambert and flat modes; with normals they are lit like surfaces facing that way.
    PrimitiveStyle primitives{defaults::k_point_size, PointShape::round, 0.0f, defaults::k_line_width};
    bool point_size_in_model_units = false;
    // false: nothing reads the target's depth after render_scene, so a frame of one draw (one
    // object, triangles only) does not store it (DrawState::keep_depth): the same colour, the
    // target's depth unspecified. The command line sets it when no depth image is asked for.
    bool keep_depth = true;
};

// Anti-aliasing by n jittered frames (n = 1, 2, 4 or 8): each frame drawn with one of these
// RenderSettings::pixel_offset values, in pixels from the pixel's centre, and the frames averaged,
// samples each pixel where n-sample MSAA would (Direct3D's standard sample positions, rotated
// grids). Empty for another n.
std::span<const Vec2> antialias_offsets(int n);

// How to look at a scene, as the command line and the viewer take it. Without an eye, the camera
// orbits the scene by the framing rule below; with one, it looks from there at `target` (default:
// the centre of the bounds). Angles in radians.
struct ViewSpec {
    float azimuth = radians(defaults::k_azimuth_degrees), elevation = radians(defaults::k_elevation_degrees);
    float fovy = radians(defaults::k_fov_degrees);
    std::optional<Vec3> eye, target;
    Vec3 up{0, 1, 0};
    std::optional<float> near, far;  // default: from the scene's bounding sphere
    bool orthographic = false;       // the view volume then fits the bounding sphere
    std::optional<float> distance;   // without an eye: the orbit's distance (default: the framing rule's)
    // A validated OpenCV camera: its pose and intrinsics replace everything above but near and far.
    std::optional<OpenCvCamera> opencv;
};

// The framing rule that other renderers can reproduce exactly: centre = centre of the bounds,
// r = largest vertex distance from it, dist = r / sin(min(fovy, fovx) / 2),
// near = max(dist - 1.5 r, 0.01 r), far = dist + 1.5 r, eye on the orbit sphere at (azimuth, elevation).
Camera frame_scene(const Scene& scene, float azimuth, float elevation, float fovy, float aspect);

Camera make_camera(const Scene& scene, const ViewSpec& view, float aspect);
Camera make_camera(std::span<const ObjectView> objects, const ViewSpec& view, float aspect);
// World-space bounds of the objects' finite vertices (Scene::bounds for views).
Aabb bounds(std::span<const ObjectView> objects);

// Clears the target to the background and draws every object: opaque and alpha-masked ones in
// order, then alpha-blended ones from back to front (by the distance of their bounds' centre) with
// depth writes off.
DrawStats render_scene(Renderer& renderer, Framebuffer& target, const Scene& scene, const Camera& camera,
                       const RenderSettings& settings);
DrawStats render_scene(Renderer& renderer, Framebuffer& target, std::span<const ObjectView> objects,
                       const Camera& camera, const RenderSettings& settings);

// What render_scene draws each object with, for passes that must match it bit for bit (the viewer's
// wireframe): the clip matrix (the camera's projection for the target's aspect, times its view) and
// the culling (none in the lambert mode; otherwise the settings' when forced, else the back faces of
// single-sided materials).
Mat4 clip_from_world(const Camera& camera, const Framebuffer& target);
CullMode cull_mode(const SceneObject& object, const RenderSettings& settings);
CullMode cull_mode(const ObjectView& object, const RenderSettings& settings);

// Box-filters a supersampled target down by `factor` in each direction into `colour` (and, if
// given, `depth`: the nearest of each block's samples, so silhouettes keep their depth). The
// outputs keep their memory between calls.
void resolve_supersampled(const Framebuffer& source, int factor, Image& colour, std::vector<float>* depth);
// The same into caller memory of (source size / factor) pixels: `colour` (may be null) and `depth`
// (may be null).
void resolve_supersampled(const Framebuffer& source, int factor, Rgba8* colour, float* depth);

// Built from embedded data, no files: a checkered floor, a cube, a sphere and a torus.
Scene default_scene();
// The camera the default scene is meant to be seen from.
Camera default_scene_camera(float aspect);

}  // namespace facet
FACET_API_END
