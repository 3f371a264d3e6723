// facet: render passes, the ground truth a dataset needs beside the colour image, from the same
// visibility as the colour: per pixel, the surface the visible-only order shades there gives its
// depth, normal, ids and uv. This header names the passes (Pass, PassSet) and says what one draw
// call writes for them (DrawPasses, given to Renderer::draw); facet/views.hpp renders them for
// scenes and lists of cameras. It does not pick cameras or write files.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>

#include "facet/api.hpp"
#include "facet/error.hpp"
#include "facet/math/mat.hpp"

FACET_API_BEGIN
namespace facet {

// The passes, with their value on the background (where no surface is):
//   colour     RGBA8, shaded as the shading mode says (the background colour)
//   alpha      float, the share of the pixel's samples some surface covers (0)
//   depth      float, distance from the eye along the camera's viewing axis, model units (+inf)
//   range      float, distance from the eye along the pixel's ray, model units (+inf)
//   normal     3 floats, unit surface normal, world space or camera space (0, 0, 0)
//   instance   uint32, the scene object + 1 (0)
//   material   uint32, the scene's material + 1 (0)
//   primitive  uint32, the triangle's index within its mesh + 1 (0)
//   uv         2 floats, the mesh's texture coordinates (0, 0; also where the mesh has none)
// Alpha-blended surfaces write no depth, so they show in colour only, as with a GPU's depth buffer.
enum class Pass : std::uint8_t { colour, alpha, depth, range, normal, instance, material, primitive, uv };
inline constexpr int k_pass_count = 9;
inline constexpr std::array<Pass, k_pass_count> k_all_passes{Pass::colour,   Pass::alpha,    Pass::depth,
                                                             Pass::range,    Pass::normal,   Pass::instance,
                                                             Pass::material, Pass::primitive, Pass::uv};

// "color", "alpha", "depth", "range", "normal", "instance", "material", "primitive", "uv".
const char* pass_name(Pass pass);

struct PassSet {
    std::uint32_t bits = 0;
    constexpr bool has(Pass p) const { return (bits >> static_cast<int>(p)) & 1u; }
    constexpr PassSet& add(Pass p) {
        bits |= 1u << static_cast<int>(p);
        return *this;
    }
    constexpr bool empty() const { return bits == 0; }
    // Whether a pass other than colour and alpha is asked for: those come from the surface at each
    // pixel (DrawPasses), the two others from the colour render's samples.
    constexpr bool needs_surface() const {
        return (bits & ~((1u << static_cast<int>(Pass::colour)) | (1u << static_cast<int>(Pass::alpha)))) != 0;
    }
    static constexpr PassSet all() { return {(1u << k_pass_count) - 1}; }
    friend constexpr bool operator==(PassSet, PassSet) = default;
};

// "color,depth,normal" (any order, each once) into a PassSet; the error names the unknown or
// repeated pass and lists the known ones.
Result<PassSet> parse_passes(std::string_view list);
// The passes as a list parse_passes reads, in the order of k_all_passes.
std::string to_string(PassSet passes);

// Which space the normal pass is in: world, or the camera's (OpenGL's: +X right, +Y up, +Z toward
// the viewer, so a surface facing the camera has z > 0).
enum class NormalSpace { world, camera };

// The background values above, for code that fills pass images.
inline constexpr float k_background_depth = std::numeric_limits<float>::infinity();

// Per pixel of a draw's target (its width x height, row-major, top row first): where the draw
// writes each pass. Null where a pass is not wanted. A draw writes the pixels where one of its
// triangles is visible when it is done, and with DrawState::clear first sets every pixel to the
// background value.
struct PassTargets {
    float* alpha = nullptr;  // 1 where a surface is visible
    float* depth = nullptr;
    float* range = nullptr;
    Vec3* normal = nullptr;
    std::uint32_t* instance = nullptr;
    std::uint32_t* material = nullptr;
    std::uint32_t* primitive = nullptr;
    Vec2* uv = nullptr;
};

// What a draw call needs to write render passes (Renderer::draw's last argument). The passes read
// the visibility the draw resolves (the triangle visible at each pixel, as the colour's) and the
// mesh the draw's indices name, not the shader: any shader's draw can write them.
struct DrawPasses {
    PassTargets targets;
    std::uint32_t instance = 0, material = 0;  // this draw's ids
    // The mesh, object space, indexed like the shader's vertex(): positions for face normals (needed
    // when the normal pass is wanted and there are no normals), per-vertex normals (may be null:
    // each triangle then has its face normal, pointing out of its front face, DrawState::front_face),
    // uvs (may be null: uv 0).
    const Vec3* positions = nullptr;
    const Vec3* normals = nullptr;
    const Vec2* uvs = nullptr;
    Mat4 model = Mat4::identity();              // object -> world
    Mat3 normal_to_world = Mat3::identity();    // normal_matrix(model)
    Mat3 normal_space = Mat3::identity();       // world -> the normal pass's space (a rotation)
    // Depth: the clip-space w of a perspective projection (depth_scale 0), which is the distance along
    // the viewing axis, or, for an orthographic one, depth_offset + depth_scale * window depth.
    float depth_offset = 0, depth_scale = 0;
    // Range: the ray through the centre (px, py) of a pixel (screen space, pixels) has view-space
    // direction (a, b, 1) per unit of depth along the axis, a = ray[0] + ray[1] px + ray[2] py and
    // b = ray[3] + ray[4] px + ray[5] py, so range = depth * sqrt(1 + a^2 + b^2). Zeros: range = depth.
    std::array<float, 6> ray{};
};

}  // namespace facet
FACET_API_END
