// facet: cameras and the cached transformation chain (object -> world -> view -> clip -> screen).
// A Camera says where the eye is and what it looks at; it produces the view and projection
// matrices. TransformChain keeps the concatenated matrices and recomputes only what changed.
#pragma once

#include <optional>

#include "facet/api.hpp"
#include "facet/defaults.hpp"
#include "facet/math/transform.hpp"

FACET_API_BEGIN
namespace facet {

enum class Handedness { right, left };
enum class ProjectionKind { perspective, orthographic };

struct Camera {
    Vec3 position{0, 0, 5};
    Vec3 target{0, 0, 0};
    Vec3 up{0, 1, 0};
    float roll = 0;                       // radians, turns the image clockwise as seen by the viewer
    ProjectionKind projection_kind = ProjectionKind::perspective;
    float fovy = radians(defaults::k_fov_degrees);  // perspective: vertical field of view
    float ortho_height = 2.0f;            // orthographic: height of the view volume in world units
    float near = 0.1f;
    float far = 100.0f;
    Handedness handedness = Handedness::right;

    // Eye at `position` looking along `direction` (need not be unit length).
    static Camera looking(Vec3 position, Vec3 direction, float roll = 0);
    // Eye on a sphere around `target`: azimuth about +Y from +Z toward +X, elevation up from the
    // XZ plane, both radians. eye = target + distance * (cos el sin az, sin el, cos el cos az).
    static Camera orbit(Vec3 target, float azimuth, float elevation, float distance);

    Vec3 forward() const { return normalize(target - position); }
    Mat4 view() const;
    Mat4 projection(float aspect) const;
};

// The camera basis (right, up, forward) for a view direction, stable at the poles: when `up` is
// parallel to `forward` (looking straight up or down) the up vector falls back to the direction the
// camera would tilt to, as the geometry-pipeline seed does, instead of producing NaN.
struct CameraBasis {
    Vec3 right, up, forward;
};
CameraBasis camera_basis(Vec3 forward, Vec3 up, Handedness handedness);

// Divides by w, keeping 1/w in the w slot for perspective-correct interpolation:
// (x/w, y/w, z/w, 1/w). Returns nothing for w <= 0 or non-finite input: such a point is behind the
// eye and must be clipped, never divided.
std::optional<Vec4> homogenize(Vec4 pos_clip);

// The seeds' Transformation object: world, view, projection and viewport matrices with their
// products cached. Setting one matrix marks the products that depend on it; they are rebuilt on the
// next read, so moving one object costs one matrix product, not four.
class TransformChain {
public:
    void set_world(const Mat4& world);
    void set_view(const Mat4& view);
    void set_projection(const Mat4& projection);
    void set_viewport(const Mat4& viewport);

    const Mat4& world() const { return world_; }
    const Mat4& view() const { return view_; }
    const Mat4& projection() const { return projection_; }
    const Mat4& viewport() const { return viewport_; }

    const Mat4& clip_from_world() const;   // projection * view
    const Mat4& clip_from_object() const;  // projection * view * world
    const Mat4& screen_from_object() const;  // viewport * projection * view * world

    // Number of matrix products computed so far (lets tests see that the cache works).
    int products_computed() const { return products_; }

private:
    Mat4 world_, view_, projection_, viewport_;
    mutable Mat4 clip_from_world_, clip_from_object_, screen_from_object_;
    mutable bool view_projection_dirty_ = false, object_dirty_ = false, screen_dirty_ = false;
    mutable int products_ = 0;
};

}  // namespace facet
FACET_API_END
