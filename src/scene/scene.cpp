// facet scene: rendering a Scene with a shading mode, automatic framing, the default scene.
#include "facet/scene.hpp"

#include "facet/primitive_counts.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include "facet/shaders.hpp"
#include "facet/views.hpp"
#include "math/portable_trig.hpp"
#include "scene/lit_shading.hpp"
#include "scene/scene_passes.hpp"
#include "tile/passes.hpp"

#include <utility>

namespace facet {
namespace {

constexpr struct {
    Shading shading;
    const char* name;
} k_shading_names[] = {{Shading::lit, "lit"},         {Shading::lambert, "lambert"}, {Shading::flat, "flat"},
                       {Shading::normals, "normals"}, {Shading::mask, "mask"},       {Shading::vertex_color, "vertex-color"},
                       {Shading::texture, "texture"}};

ShadingUniforms uniforms_for(const ObjectView& object, const Camera& camera, const Mat4& clip_from_world,
                             const RenderSettings& settings) {
    ShadingUniforms u;
    u.model = object.model;
    u.clip_from_object = clip_from_world * object.model;
    u.normal_to_world = normal_matrix(object.model);
    u.handedness = determinant(object.model.upper3x3()) < 0 ? -1.0f : 1.0f;
    u.eye = camera.position;
    u.base_colour = object.material->base_colour;
    const CameraBasis basis = camera_basis(camera.target - camera.position, camera.up, camera.handedness);
    const Vec3 to_eye = -basis.forward;
    if (settings.shading == Shading::lambert) {
        // The comparison mode's contract (facet/defaults.hpp): a white light at the eye.
        constexpr float a = defaults::k_lambert_albedo;
        u.base_colour = {a, a, a, 1};
        u.key = {to_eye, {1, 1, 1}};
        u.ambient = defaults::k_lambert_ambient;
        u.diffuse = defaults::k_lambert_diffuse;
    } else {
        const Lighting& l = settings.lighting;
        u.key = {world_light_direction(l.key, basis), l.key.colour};
        u.fill = {world_light_direction(l.fill, basis), l.fill.colour};
        u.ambient = l.ambient;
        u.diffuse = l.diffuse;
        u.specular = l.specular;
        u.shininess = l.shininess;
    }
    return u;
}

template <class S>
DrawStats draw_with(Renderer& r, Framebuffer& target, const DrawState& state, const ObjectView& o, const S& shader,
                    const DrawPasses* passes) {
    return r.draw(target, state, DrawInput{o.vertex_count, o.indices}, shader, passes);
}

// Which of an object's primitives a draw of it takes: anti-aliased lines, which blend without
// writing depth, are drawn after every opaque object's surfaces (render_objects).
enum class Parts { all, all_but_lines, lines };

// An object's points and lines, after its triangles (state.clear, if any, is done by the first draw).
template <class S>
DrawStats draw_points_lines_with(Renderer& r, Framebuffer& target, DrawState state, const ObjectView& o,
                                 const S& shader, const DrawPasses* passes, const PrimitiveStyle& style, Parts parts) {
    DrawStats stats;
    for (const Topology topology : {Topology::points, Topology::lines}) {
        const std::span<const std::uint32_t> indices = topology == Topology::points ? o.points : o.lines;
        const bool wanted = parts == Parts::all || (parts == Parts::lines) == (topology == Topology::lines);
        if (indices.empty() || !wanted) continue;
        stats += r.draw(target, state, DrawInput{o.vertex_count, indices, topology, style}, shader, passes);
        state.clear.reset();
    }
    return stats;
}

// The shader of an object's points and lines: as its triangles' where the mode needs no derivatives
// and the normals are there; unlit (vertex or base colour) in the lit, lambert and flat modes
// without normals, and Blinn-Phong under the flat mode's lights rather than flat with them (a point
// has no face to take a normal from).
DrawStats draw_points_lines(Renderer& r, Framebuffer& target, const DrawState& state, const ObjectView& o,
                            const ShadingUniforms& u, MeshArrays arrays, const RenderSettings& settings,
                            const DrawPasses* passes, const PrimitiveStyle& style, Parts parts) {
    const bool has_normals = arrays.normals != nullptr;
    const auto draw = [&](const auto& shader) {
        return draw_points_lines_with(r, target, state, o, shader, passes, style, parts);
    };
    switch (settings.shading) {
        case Shading::lit:
            if (!has_normals) return draw(shaders::VertexColour{arrays, u});
            return draw(shaders::Pbr{arrays, u, scene_detail::pbr_uniforms(*o.material, arrays.uvs != nullptr, settings)});
        case Shading::flat:
            if (!has_normals) return draw(shaders::VertexColour{arrays, u});
            if (!arrays.colours) return draw(shaders::BlinnPhongBaseColour{arrays, u});
            return draw(shaders::BlinnPhong{arrays, u});
        case Shading::lambert:
            if (!has_normals) return draw(shaders::VertexColour{arrays, u});
            return draw(shaders::LambertBaseColour{arrays, u});
        case Shading::normals: return draw(shaders::Normals{arrays, u});
        case Shading::mask: return draw(shaders::Mask{arrays, u});
        case Shading::vertex_color:
        case Shading::texture: return draw(shaders::VertexColour{arrays, u});
    }
    return {};
}

TextureBinding binding_of(const Material& m) {
    return {m.base_colour_texture.get(), m.sampler, m.alpha_mode == AlphaMode::mask ? m.alpha_cutoff : -1.0f};
}

// Picks the shader for the mode and the object's data, then draws (with `passes`, if given).
DrawStats draw_object(Renderer& r, Framebuffer& target, const DrawState& state, const ObjectView& o,
                      const ShadingUniforms& u, MeshArrays arrays, const RenderSettings& settings, const DrawPasses* passes) {
    const Shading shading = settings.shading;
    const Material& material = *o.material;
    const bool has_normals = arrays.normals != nullptr;
    const bool textured = material.base_colour_texture && arrays.uvs;
    const TextureBinding tex = textured ? binding_of(material) : TextureBinding{nullptr, {}, binding_of(material).alpha_cutoff};
    switch (shading) {
        case Shading::lit: return scene_detail::draw_lit(r, target, state, o, u, arrays, settings, passes);
        case Shading::lambert:
            if (!has_normals) return draw_with(r, target, state, o, shaders::Flat{arrays, u}, passes);
            return draw_with(r, target, state, o, shaders::LambertBaseColour{arrays, u}, passes);  // colours are off
        case Shading::flat: return draw_with(r, target, state, o, shaders::Flat{arrays, u}, passes);
        case Shading::normals: return draw_with(r, target, state, o, shaders::Normals{arrays, u}, passes);
        case Shading::mask: return draw_with(r, target, state, o, shaders::Mask{arrays, u}, passes);
        case Shading::vertex_color: return draw_with(r, target, state, o, shaders::VertexColour{arrays, u}, passes);
        case Shading::texture:
            if (material.alpha_mode == AlphaMode::mask) return draw_with(r, target, state, o, shaders::TextureUnlit{arrays, u, tex}, passes);
            return draw_with(r, target, state, o, shaders::TextureUnlitOpaque{arrays, u, tex}, passes);
    }
    return {};
}

}  // namespace

namespace detail {

// The shaders read normals, colours and uvs at every index they read positions at: an object whose
// non-empty attribute arrays are shorter than its positions would have them read past the end.
// That is a caller's mistake, reported as such (out-of-range indices, by contrast, are bad geometry
// and are only dropped by the draw).
void require_aligned_arrays(const Scene& scene) {
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const Mesh& m = scene.objects[i].mesh;
        const std::size_t n = m.positions.size();
        const char* bad = !m.normals.empty() && m.normals.size() != n   ? "normals"
                          : !m.colours.empty() && m.colours.size() != n ? "colours"
                          : !m.uvs.empty() && m.uvs.size() != n         ? "uvs"
                          : !m.tangents.empty() && m.tangents.size() != n ? "tangents"
                                                                        : nullptr;
        if (bad)
            throw FacetError(Error{ErrorCode::invalid_argument, "render_scene: object " + std::to_string(i) + " has " +
                                                                    std::string(bad) + " and positions of different counts"});
    }
}

}  // namespace detail

Vec3 world_light_direction(const CameraLight& light, const CameraBasis& basis) {
    const Vec3 d = light.direction;
    const Vec3 toward_viewer = -basis.forward;
    const Vec3 up = basis.up * d.y, right = basis.right * d.x;
    // (Summed in this order, the default lights keep the bits they were designed with.)
    const Vec3 sum = std::abs(d.y) >= std::abs(d.x) ? toward_viewer * d.z + up + right : toward_viewer * d.z + right + up;
    return normalize(sum);
}

bool parse_shading(std::string_view name, Shading& out) {
    for (const auto& s : k_shading_names)
        if (name == s.name) {
            out = s.shading;
            return true;
        }
    return false;
}

const char* to_string(Shading s) {
    for (const auto& n : k_shading_names)
        if (n.shading == s) return n.name;
    return "?";
}

ObjectView view_of(const SceneObject& o) {
    const MeshArrays a = MeshArrays::of(o.mesh);
    return {a.positions, a.normals, a.colours, a.uvs, static_cast<std::uint32_t>(o.mesh.positions.size()),
            o.mesh.indices, o.model, &o.material, a.tangents, o.mesh.points, o.mesh.lines};
}

namespace {

// A Scene and a span of ObjectViews, read the same way: the functions below are written once for
// both (the views of a Scene's objects are made as they are read, so nothing is allocated).
std::size_t object_count(const Scene& s) { return s.objects.size(); }
std::size_t object_count(std::span<const ObjectView> v) { return v.size(); }
ObjectView object_at(const Scene& s, std::size_t i) { return view_of(s.objects[i]); }
ObjectView object_at(std::span<const ObjectView> v, std::size_t i) { return v[i]; }

// The scene's bounds and radius over each finite position p of the objects, placed by their models:
// transform_point(model, p), which with the identity (the model of nearly every file read) is
// p + 0 (the products by 0 and 1 are exact, and the last term, +0, makes a -0 +0). Those positions
// are taken four at a time (the bunny's two passes took 0.27 ms, serial, before its first frame),
// with the same results: each position's arithmetic is the same, the min and max of values that
// are never NaN (not finite: left out) nor -0 do not depend on their order, and they join the
// running ones as one value (the last of equal values taken, as Aabb::extend takes them).
using Floats4 = float __attribute__((vector_size(16)));
using Ints4 = std::int32_t __attribute__((vector_size(16)));

// Positions 4k .. 4k + 3 of p as x, y and z of four positions, + 0.
struct Four {
    Floats4 x, y, z;
    Ints4 finite() const { return (x - x == 0) & (y - y == 0) & (z - z == 0); }  // -1 where finite
};
Four four_at(const Vec3* p) {
    static_assert(sizeof(Vec3) == 3 * sizeof(float));
    Floats4 v[3];
    std::memcpy(v, p, sizeof v);  // x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3
    // __builtin_shufflevector: GCC's (12 on) and clang's (the fuzz build) alike.
    const Floats4 x = __builtin_shufflevector(__builtin_shufflevector(v[0], v[1], 0, 3, 6, 0), v[2], 0, 1, 2, 5);
    const Floats4 y = __builtin_shufflevector(__builtin_shufflevector(v[0], v[1], 1, 4, 7, 0), v[2], 0, 1, 2, 6);
    const Floats4 z = __builtin_shufflevector(__builtin_shufflevector(v[0], v[1], 2, 5, 0, 0), v[2], 0, 1, 4, 7);
    return {x + 0.0f, y + 0.0f, z + 0.0f};
}
float lowest(Floats4 v) { return std::min(std::min(v[0], v[1]), std::min(v[2], v[3])); }
float highest(Floats4 v) { return std::max(std::max(v[0], v[1]), std::max(v[2], v[3])); }

// four(f) for the positions of identity-placed objects four at a time (f.finite() marks the lanes
// to keep), one(p) for each other finite placed position.
template <class Objects, class FourAtATime, class OneAtATime>
void for_each_placed_position(const Objects& objects, const FourAtATime& four, const OneAtATime& one) {
    for (std::size_t i = 0; i < object_count(objects); ++i) {
        const ObjectView o = object_at(objects, i);
        const bool identity = o.model == Mat4::identity();
        std::uint32_t k = 0;
        if (identity)
            for (; k + 4 <= o.vertex_count; k += 4) four(four_at(o.positions + k));
        for (; k < o.vertex_count; ++k)
            if (is_finite(o.positions[k]))
                one(identity ? o.positions[k] + Vec3{0, 0, 0} : transform_point(o.model, o.positions[k]));
    }
}

template <class Objects>
Aabb bounds_of(const Objects& objects) {
    constexpr float inf = std::numeric_limits<float>::infinity();
    Floats4 lo[3] = {Floats4{} + inf, Floats4{} + inf, Floats4{} + inf};
    Floats4 hi[3] = {Floats4{} - inf, Floats4{} - inf, Floats4{} - inf};
    Aabb box;
    for_each_placed_position(
        objects,
        [&](const Four& f) {
            const Ints4 finite = f.finite();
            const Floats4 c[3] = {f.x, f.y, f.z};
            for (int d = 0; d < 3; ++d) {
                lo[d] = (finite & (c[d] < lo[d])) ? c[d] : lo[d];
                hi[d] = (finite & (c[d] > hi[d])) ? c[d] : hi[d];
            }
        },
        [&](Vec3 p) { box.extend(p); });
    box.min = facet::min(box.min, Vec3{lowest(lo[0]), lowest(lo[1]), lowest(lo[2])});  // infinite: none
    box.max = facet::max(box.max, Vec3{highest(hi[0]), highest(hi[1]), highest(hi[2])});
    return box;
}

// The largest distance, as the square root of the largest squared distance: the same bits, as
// sqrt is correctly rounded and so never decreasing (and a NaN is passed over by both).
template <class Objects>
float radius_of(const Objects& objects, Vec3 centre) {
    Floats4 most{};
    float r2 = 0;
    for_each_placed_position(
        objects,
        [&](const Four& f) {
            const Floats4 dx = f.x - centre.x, dy = f.y - centre.y, dz = f.z - centre.z;
            const Floats4 d2 = dx * dx + dy * dy + dz * dz;  // dot's order
            most = (f.finite() & (most < d2)) ? d2 : most;
        },
        [&](Vec3 p) { r2 = std::max(r2, dot(p - centre, p - centre)); });
    return std::sqrt(std::max(r2, highest(most)));
}

}  // namespace

Aabb Scene::bounds() const { return bounds_of(*this); }

float Scene::radius_about(Vec3 centre) const { return radius_of(*this, centre); }

std::size_t Scene::triangle_count() const {
    std::size_t n = 0;
    for (const SceneObject& o : objects) n += o.mesh.triangle_count();
    return n;
}

std::size_t point_count(const Scene& scene) {
    std::size_t n = 0;
    for (const SceneObject& o : scene.objects) n += o.mesh.points.size();
    return n;
}

std::size_t segment_count(const Scene& scene) {
    std::size_t n = 0;
    for (const SceneObject& o : scene.objects) n += o.mesh.lines.size() / 2;
    return n;
}

std::string describe_primitives(std::size_t triangles, std::size_t points, std::size_t segments) {
    std::string s;
    const auto add = [&](std::size_t n, const char* what) {
        if (!s.empty()) s += ", ";
        s += std::to_string(n) + " " + what;
    };
    if (triangles > 0 || (points == 0 && segments == 0)) add(triangles, "triangles");
    if (points > 0) add(points, "points");
    if (segments > 0) add(segments, "segments");
    return s;
}

std::string describe_primitives(const Scene& scene) {
    return describe_primitives(scene.triangle_count(), point_count(scene), segment_count(scene));
}

namespace {

// The sphere that frames a scene: the centre of its bounds and the farthest vertex from it (a unit
// sphere for a single point or an empty scene).
struct FramingSphere {
    Vec3 centre;
    float radius;
};

template <class Objects>
FramingSphere framing_sphere(const Objects& objects) {
    const Aabb box = bounds_of(objects);
    const Vec3 centre = box.empty() ? Vec3{} : box.centre();
    const float r = radius_of(objects, centre);
    return {centre, r > 0 ? r : 1.0f};
}

Camera frame_sphere(FramingSphere s, float azimuth, float elevation, float fovy, float aspect) {
    const float fovx = 2 * static_cast<float>(portable::atan(static_cast<float>(portable::tan(fovy / 2)) * aspect));
    float half_sin, half_cos;
    portable::sincos(std::min(fovy, fovx) / 2, half_sin, half_cos);
    const float dist = s.radius / half_sin;
    Camera c = Camera::orbit(s.centre, azimuth, elevation, dist);
    c.fovy = fovy;
    c.near = std::max(dist - 1.5f * s.radius, 0.01f * s.radius);
    c.far = dist + 1.5f * s.radius;
    return c;
}

// The camera of `view` for a scene framed by `sphere` (framing_sphere: one pass over the vertices
// for the bounds and one for the radius, shared by the framing and the explicit view's defaults).
Camera camera_for(const FramingSphere& sphere, const ViewSpec& view, float aspect) {
    const Vec3 centre = sphere.centre;
    const float r = sphere.radius;
    // The clip planes of an explicit eye: from the bounding sphere, unless given.
    auto set_planes = [&](Camera& c) {
        const float dist = length(c.position - centre);
        c.near = view.near ? *view.near : std::max(dist - 1.5f * r, 0.01f * r);
        c.far = view.far ? *view.far : dist + 1.5f * r;
    };
    if (view.opencv) {
        Camera c = Camera::from_opencv(*view.opencv, 0, 0);
        set_planes(c);
        return c;
    }
    if (!view.eye && !view.target && !view.near && !view.far && !view.orthographic && !view.distance &&
        view.up == Vec3{0, 1, 0})
        return frame_sphere(sphere, view.azimuth, view.elevation, view.fovy, aspect);
    Camera c = frame_sphere(sphere, view.azimuth, view.elevation, view.fovy, aspect);
    c.up = view.up;
    if (view.target) c.target = *view.target;
    if (view.eye) c.position = *view.eye;
    else if (view.distance) c.position = Camera::orbit(centre, view.azimuth, view.elevation, *view.distance).position;
    set_planes(c);
    if (view.orthographic) {
        c.projection_kind = ProjectionKind::orthographic;
        c.ortho_height = 2 * r * std::max(1.0f, 1.0f / aspect);
    }
    return c;
}

}  // namespace

Mat4 clip_from_world(const Camera& camera, const Framebuffer& target) {
    const float aspect = static_cast<float>(target.width()) / static_cast<float>(target.height());
    return camera.projection(aspect) * camera.view();
}

CullMode cull_mode(const ObjectView& object, const RenderSettings& settings) {
    if (settings.shading == Shading::lambert) return CullMode::none;
    if (settings.cull != CullMode::none) return settings.cull;
    return object.material->double_sided ? CullMode::none : CullMode::back;
}

CullMode cull_mode(const SceneObject& object, const RenderSettings& settings) { return cull_mode(view_of(object), settings); }

namespace {

// Moves clip space by `offset` pixels of `target` (right and down): x_clip += (2 offset.x / width) w.
Mat4 jittered(Vec2 offset, const Framebuffer& target) {
    Mat4 m = Mat4::identity();
    m(0, 3) = 2 * offset.x / static_cast<float>(target.width());
    m(1, 3) = -2 * offset.y / static_cast<float>(target.height());
    return m;
}

// With `passes`, every draw writes render passes too (the blended ones' write none: they write no
// depth), object i as instance i + 1.
template <class Objects>
DrawStats render_objects(Renderer& renderer, Framebuffer& target, const Objects& objects, const Camera& camera,
                         const RenderSettings& settings, const detail::ScenePasses* passes = nullptr) {
    // The clear goes with the first draw, which does it tile by tile (DrawState::clear).
    std::optional<ClearValues> clear = ClearValues{settings.background, 1.0f};
    const Mat4 clip_from_world = jittered(settings.pixel_offset, target) * facet::clip_from_world(camera, target);
    const bool lambert = settings.shading == Shading::lambert;
    PrimitiveStyle primitives = settings.primitives;
    // Pixels per world unit at w = 1: the projection's y scale times half the height.
    primitives.model_scale = settings.point_size_in_model_units
                                 ? camera.projection(static_cast<float>(target.width()) / static_cast<float>(target.height()))(1, 1) *
                                       (0.5f * static_cast<float>(target.height()))
                                 : 0.0f;
    DrawPasses draw_passes;
    if (passes) {
        draw_passes.targets = passes->targets;
        detail::set_camera_passes(draw_passes, camera, target.width(), target.height(), passes->normal_space);
    }

    // Opaque objects first, in the file's order; blended ones last, farthest first. Only a scene with
    // blended objects needs a list (and its allocation) for that order.
    auto blends = [&](const ObjectView& o) {
        return o.material->alpha_mode == AlphaMode::blend && !lambert && settings.shading != Shading::mask;
    };
    // A frame of one draw (DrawState::keep_depth): one object, and triangles only.
    const bool only_draw = object_count(objects) == 1 && object_at(objects, 0).points.empty() && object_at(objects, 0).lines.empty();
    // Anti-aliased lines blend without writing depth: an opaque object's are drawn after every opaque
    // object's surfaces (in the file's order), before the blended objects.
    const bool lines_later = primitives.line_aa;
    auto draw = [&](const ObjectView& o, std::size_t index, bool blended, Parts parts = Parts::all) {
        const bool triangles = parts != Parts::lines && (!o.indices.empty() || (o.points.empty() && o.lines.empty()));
        const bool points_lines = parts == Parts::lines ? !o.lines.empty()
                                                        : !o.points.empty() || (parts == Parts::all && !o.lines.empty());
        if (!triangles && !points_lines) return DrawStats{};  // the clear goes to the next draw
        const ShadingUniforms u = uniforms_for(o, camera, clip_from_world, settings);
        if (passes) {
            draw_passes.instance = static_cast<std::uint32_t>(index + 1);
            draw_passes.material = passes->material_ids ? passes->material_ids[index] : 0;
            draw_passes.positions = o.positions;
            draw_passes.normals = o.normals;
            draw_passes.uvs = o.uvs;
            draw_passes.model = o.model;
            draw_passes.normal_to_world = u.normal_to_world;
        }
        MeshArrays arrays{o.positions, o.normals, o.colours, o.uvs, o.tangents};
        if (lambert) arrays.colours = nullptr;  // the contract ignores materials
        DrawState state;
        state.cull = cull_mode(o, settings);
        if (blended) {
            state.blend = Blend::alpha;
            state.depth_write = false;
        }
        state.clear = std::exchange(clear, std::nullopt);
        state.keep_depth = settings.keep_depth || !only_draw;
        const DrawPasses* p = passes ? &draw_passes : nullptr;
        // An object of points or lines alone draws no triangles (and a mesh of nothing draws nothing,
        // but still clears).
        DrawStats stats;
        if (triangles) {
            stats = draw_object(renderer, target, state, o, u, arrays, settings, p);
            state.clear.reset();
        }
        if (points_lines) stats += draw_points_lines(renderer, target, state, o, u, arrays, settings, p, primitives, parts);
        return stats;
    };
    DrawStats total;
    std::vector<std::pair<float, std::size_t>> blended;
    for (std::size_t i = 0; i < object_count(objects); ++i) {
        const ObjectView o = object_at(objects, i);
        if (!blends(o)) {
            total += draw(o, i, false, lines_later ? Parts::all_but_lines : Parts::all);
            continue;
        }
        Aabb box;
        for (std::uint32_t k = 0; k < o.vertex_count; ++k) box.extend(transform_point(o.model, o.positions[k]));
        blended.push_back({-length(box.centre() - camera.position), i});
    }
    if (lines_later)
        for (std::size_t i = 0; i < object_count(objects); ++i)
            if (const ObjectView o = object_at(objects, i); !blends(o)) total += draw(o, i, false, Parts::lines);
    std::stable_sort(blended.begin(), blended.end());
    for (const auto& b : blended) total += draw(object_at(objects, b.second), b.second, true);
    if (clear) {  // nothing was drawn
        target.clear(clear->colour, clear->depth);
        if (passes) detail::clear_pass_targets(passes->targets, {0, 0, target.width(), target.height()}, target.width());
    }
    return total;
}

}  // namespace

Camera frame_scene(const Scene& scene, float azimuth, float elevation, float fovy, float aspect) {
    return frame_sphere(framing_sphere(scene), azimuth, elevation, fovy, aspect);
}

Camera make_camera(const Scene& scene, const ViewSpec& view, float aspect) {
    return camera_for(framing_sphere(scene), view, aspect);
}

Camera make_camera(std::span<const ObjectView> objects, const ViewSpec& view, float aspect) {
    return camera_for(framing_sphere(objects), view, aspect);
}

std::vector<Camera> make_cameras(std::span<const ObjectView> objects, std::span<const ViewSpec> views, float aspect) {
    const FramingSphere sphere = framing_sphere(objects);
    std::vector<Camera> cameras;
    cameras.reserve(views.size());
    for (const ViewSpec& v : views) cameras.push_back(camera_for(sphere, v, aspect));
    return cameras;
}

Aabb bounds(std::span<const ObjectView> objects) { return bounds_of(objects); }

DrawStats render_scene(Renderer& renderer, Framebuffer& target, const Scene& scene, const Camera& camera,
                       const RenderSettings& settings) {
    detail::require_aligned_arrays(scene);
    return render_objects(renderer, target, scene, camera, settings);
}

DrawStats render_scene(Renderer& renderer, Framebuffer& target, std::span<const ObjectView> objects,
                       const Camera& camera, const RenderSettings& settings) {
    return render_objects(renderer, target, objects, camera, settings);
}

namespace detail {

DrawStats render_scene_passes(Renderer& renderer, Framebuffer& target, std::span<const ObjectView> objects,
                              const Camera& camera, const RenderSettings& settings, const ScenePasses& passes) {
    return render_objects(renderer, target, objects, camera, settings, &passes);
}

void set_camera_passes(DrawPasses& out, const Camera& camera, int width, int height, NormalSpace space) {
    const Mat4 p = camera.projection(static_cast<float>(width) / static_cast<float>(height));
    // Depth along the viewing axis d = h z_view, h = -1 for right-handed view spaces (looking down
    // -Z), +1 for left-handed ones.
    const double h = camera.handedness == Handedness::right ? -1.0 : 1.0;
    out.normal_space = space == NormalSpace::camera ? camera.view().upper3x3() : Mat3::identity();
    out.ray = {};
    if (p(3, 3) != 0) {
        // Orthographic: window depth z = P22 z_view + P23, so d = h (z - P23) / P22; rays are parallel
        // to the axis (range = depth).
        out.depth_offset = static_cast<float>(-h * p(2, 3) / p(2, 2));
        out.depth_scale = static_cast<float>(h / p(2, 2));
        return;
    }
    // Perspective: clip w = P32 z_view = d (P32 = h), which the draw interpolates as q = 1/w. The ray
    // through the pixel centre (px, py) at depth d is (a d, b d, h d) in view space, where
    // x_ndc = P00 a + P01 b + P02 h and y_ndc = P10 a + P11 b + P12 h, x_ndc = 2 px / W - 1 and
    // y_ndc = 1 - 2 py / H: (a, b) is affine in (px, py), its coefficients solved here in double.
    out.depth_offset = 0;
    out.depth_scale = 0;
    const double p00 = p(0, 0), p01 = p(0, 1), p10 = p(1, 0), p11 = p(1, 1);
    const double inv = 1.0 / (p00 * p11 - p01 * p10);
    const double cx = -1 - h * p(0, 2), cy = 1 - h * p(1, 2);  // x_ndc, y_ndc minus P02 h, P12 h at (0, 0)
    const double sx = 2.0 / width, sy = -2.0 / height;       // their steps per pixel
    out.ray = {static_cast<float>(inv * (p11 * cx - p01 * cy)), static_cast<float>(inv * p11 * sx),
               static_cast<float>(-inv * p01 * sy), static_cast<float>(inv * (p00 * cy - p10 * cx)),
               static_cast<float>(-inv * p10 * sx), static_cast<float>(inv * p00 * sy)};
}

}  // namespace detail

std::span<const Vec2> antialias_offsets(int n) {
    static constexpr float s = 1 / 16.0f;
    static constexpr Vec2 k_one[] = {{0, 0}};
    static constexpr Vec2 k_two[] = {{4 * s, 4 * s}, {-4 * s, -4 * s}};
    static constexpr Vec2 k_four[] = {{-2 * s, -6 * s}, {6 * s, -2 * s}, {-6 * s, 2 * s}, {2 * s, 6 * s}};
    static constexpr Vec2 k_eight[] = {{1 * s, -3 * s}, {-1 * s, 3 * s}, {5 * s, 1 * s},  {-3 * s, -5 * s},
                                       {-5 * s, 5 * s}, {-7 * s, -1 * s}, {3 * s, 7 * s}, {7 * s, -7 * s}};
    switch (n) {
        case 1: return k_one;
        case 2: return k_two;
        case 4: return k_four;
        case 8: return k_eight;
        default: return {};
    }
}

void resolve_supersampled(const Framebuffer& source, int factor, Image& colour, std::vector<float>* depth) {
    if (factor < 1 || source.width() % factor != 0 || source.height() % factor != 0)
        throw FacetError(Error{ErrorCode::invalid_argument,
                               "resolve_supersampled: factor " + std::to_string(factor) + " does not divide the " +
                                   std::to_string(source.width()) + "x" + std::to_string(source.height()) + " source"});
    const int w = source.width() / factor, h = source.height() / factor;
    colour.width = w;
    colour.height = h;
    colour.pixels.resize(static_cast<std::size_t>(w) * h);
    if (depth) depth->resize(static_cast<std::size_t>(w) * h);
    resolve_supersampled(source, factor, colour.pixels.data(), depth ? depth->data() : nullptr);
}

void resolve_supersampled(const Framebuffer& source, int factor, Rgba8* colour, float* depth) {
    if (factor < 1 || source.width() % factor != 0 || source.height() % factor != 0)
        throw FacetError(Error{ErrorCode::invalid_argument,
                               "resolve_supersampled: factor " + std::to_string(factor) + " does not divide the " +
                                   std::to_string(source.width()) + "x" + std::to_string(source.height()) + " source"});
    const int w = source.width() / factor, h = source.height() / factor;
    const std::size_t n = static_cast<std::size_t>(w) * h;
    if (factor == 1) {  // nothing to filter: a plain copy
        if (colour && colour != source.colour_data()) std::copy(source.colour_data(), source.colour_data() + n, colour);
        if (depth) std::copy(source.depth_data(), source.depth_data() + n, depth);
        return;
    }
    const int samples = factor * factor;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            int sum[4] = {0, 0, 0, 0};
            float nearest = 1.0f;
            for (int sy = 0; sy < factor; ++sy)
                for (int sx = 0; sx < factor; ++sx) {
                    const Rgba8 c = source.colour(x * factor + sx, y * factor + sy);
                    sum[0] += c.r, sum[1] += c.g, sum[2] += c.b, sum[3] += c.a;
                    nearest = std::min(nearest, source.depth(x * factor + sx, y * factor + sy));
                }
            auto avg = [&](int v) { return static_cast<std::uint8_t>((v + samples / 2) / samples); };
            if (colour) colour[static_cast<std::size_t>(y) * w + x] = {avg(sum[0]), avg(sum[1]), avg(sum[2]), avg(sum[3])};
            if (depth) depth[static_cast<std::size_t>(y) * w + x] = nearest;
        }
}

namespace {

// Procedural textures for the default scene, so it shows texturing without shipping image files.
// A floor tile: light face with a soft diagonal sheen and dark grout at the border.
std::shared_ptr<const Texture> make_tile_texture() {
    constexpr int k_size = 64, k_grout = 3;
    Image img{k_size, k_size, std::vector<Rgba8>(k_size * k_size)};
    for (int y = 0; y < k_size; ++y)
        for (int x = 0; x < k_size; ++x) {
            const bool grout = x < k_grout || y < k_grout || x >= k_size - k_grout || y >= k_size - k_grout;
            const int sheen = 235 + (x + y) * 20 / (2 * k_size);
            const auto v = static_cast<std::uint8_t>(grout ? 70 : sheen);
            img.at(x, y) = {v, v, v, 255};
        }
    return std::make_shared<const Texture>(std::move(img));
}

// A test-card pattern for the cube: a grid of fine lines and a ring, tinted by each face's colour.
std::shared_ptr<const Texture> make_card_texture() {
    constexpr int k_size = 128;
    Image img{k_size, k_size, std::vector<Rgba8>(k_size * k_size)};
    for (int y = 0; y < k_size; ++y)
        for (int x = 0; x < k_size; ++x) {
            const float dx = x + 0.5f - k_size / 2.0f, dy = y + 0.5f - k_size / 2.0f;
            const float r = std::sqrt(dx * dx + dy * dy);
            const bool line = x % 16 == 0 || y % 16 == 0;
            const bool ring = r > 34 && r < 44;
            const auto v = static_cast<std::uint8_t>(ring ? 255 : (line ? 120 : 215));
            img.at(x, y) = {v, v, v, 255};
        }
    return std::make_shared<const Texture>(std::move(img));
}

Material coloured(Vec4 colour) {
    Material m;
    m.base_colour = colour;
    return m;
}

Material textured(std::shared_ptr<const Texture> texture) {
    Material m;
    m.base_colour_texture = std::move(texture);
    return m;
}

}  // namespace

Scene default_scene() {
    constexpr int k_floor_cells = 14;
    Scene scene;
    Mesh floor = make_checker_plane(7.0f, k_floor_cells, {0.86f, 0.87f, 0.90f, 1}, {0.40f, 0.45f, 0.55f, 1});
    for (Vec2& uv : floor.uvs) uv = uv * static_cast<float>(k_floor_cells);  // one tile per cell, repeated
    scene.objects.push_back({std::move(floor), Mat4::identity(), textured(make_tile_texture())});
    scene.objects.push_back({make_cube(0.55f), translate({-1.5f, 0.55f, 0.4f}) * rotate_y(radians(30)),
                             textured(make_card_texture())});
    scene.objects.push_back({make_uv_sphere(0.75f, 48, 32), translate({0.7f, 0.75f, -0.6f}), coloured({0.95f, 0.45f, 0.35f, 1})});
    scene.objects.push_back({make_torus(0.55f, 0.2f, 64, 24),
                             translate({1.0f, 0.76f, 1.2f}) * rotate_y(radians(35)) * rotate_x(radians(90)),
                             coloured({0.25f, 0.75f, 0.80f, 1})});
    scene.objects.push_back({split_faces_flat(make_icosphere(0.4f, 1)), translate({-0.6f, 0.4f, -1.8f}), coloured({0.95f, 0.85f, 0.35f, 1})});
    return scene;
}

Camera default_scene_camera(float aspect) {
    Camera c = Camera::orbit({0, 0.4f, 0}, radians(35), radians(28), 7.2f);
    c.fovy = radians(aspect >= 1 ? 40.0f : 55.0f);
    c.near = 0.5f;
    c.far = 30.0f;
    return c;
}

}  // namespace facet
