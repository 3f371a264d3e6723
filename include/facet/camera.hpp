// facet: cameras and the cached transformation chain (object -> world -> view -> clip -> screen).
// A Camera says where the eye is and what it looks at; it produces the view and projection
// matrices. OpenCvCamera is the same camera in OpenCV's convention (intrinsics K, world-to-camera
// [R|t]), converted both ways here for `facet render --views` and the Python package alike.
// TransformChain keeps the concatenated matrices and recomputes only what changed.
#pragma once

#include <array>
#include <optional>

#include "facet/api.hpp"
#include "facet/defaults.hpp"
#include "facet/error.hpp"
#include "facet/math/transform.hpp"

FACET_API_BEGIN
namespace facet {

enum class Handedness { right, left };
enum class ProjectionKind { perspective, orthographic };

// A pinhole camera in OpenCV's convention, in double precision so that numbers read from a file
// or a NumPy array come back exactly. Camera space: +X right, +Y down the image, looking down +Z;
// a world point p is at x = R p + t in camera space, and at pixel
//     u = fx x/z + skew y/z + cx,   v = fy y/z + cy
// of a width x height image, where pixel (i, j)'s centre is at (u, v) = (i, j) (OpenCV's pixel
// centres; facet's screen has them at (i + 0.5, j + 0.5), so screen x = u + 0.5, y = v + 0.5).
struct OpenCvCamera {
    double fx = 0, fy = 0, cx = 0, cy = 0, skew = 0;  // K = [fx skew cx; 0 fy cy; 0 0 1], pixels
    int width = 0, height = 0;                        // the image K is for
    std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};  // R, row-major
    std::array<double, 3> translation{0, 0, 0};                  // t
};

// Checks what from_opencv needs: fx, fy > 0 and every number finite, width and height in
// 1..k_max_target_size, R a rotation (orthonormal within 1e-4, determinant +1: a reflection
// would mirror the image). The error names the offending value.
Status validate(const OpenCvCamera& camera);

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
    // Set by from_opencv: view() and projection() are this camera's exactly, K scaled to the
    // target's size (another aspect stretches the view), and position, target and up describe the
    // same pose (the lights follow them); the fields above other than near and far are unused.
    std::optional<OpenCvCamera> opencv;

    // Eye at `position` looking along `direction` (need not be unit length).
    static Camera looking(Vec3 position, Vec3 direction, float roll = 0);
    // Eye on a sphere around `target`: azimuth about +Y from +Z toward +X, elevation up from the
    // XZ plane, both radians. eye = target + distance * (cos el sin az, sin el, cos el cos az).
    static Camera orbit(Vec3 target, float azimuth, float elevation, float distance);
    // The OpenCV camera (validate() it first: this does not check) with these clip planes.
    static Camera from_opencv(const OpenCvCamera& camera, float near, float far);

    Vec3 forward() const { return normalize(target - position); }
    Mat4 view() const;
    Mat4 projection(float aspect) const;
};

// The camera in OpenCV's convention for a width x height image: K from the projection (square
// pixels, principal point at the image centre, (width - 1) / 2) and [R|t] from view(), both
// computed in double from the float matrices, so from_opencv gives the same view and projection
// matrices back, bit for bit; a from_opencv camera gives its own numbers, K scaled to the size.
// Orthographic cameras have no K, and left-handed ones see the world mirrored: nothing for either.
std::optional<OpenCvCamera> to_opencv(const Camera& camera, int width, int height);

// Camera-to-world in the OpenGL convention that NeRF tools read (transforms.json's
// transform_matrix): the camera at the origin looking down -Z, +Y up the image; the inverse of
// view(). For right-handed cameras (of either projection).
Mat4 camera_to_world_gl(const Camera& camera);
// The same for an OpenCV camera, in double (row-major 4x4, last row 0 0 0 1), and its inverse:
// sets R and t from such a matrix (its 3x3 part a rotation: validate() checks).
std::array<double, 16> camera_to_world_gl(const OpenCvCamera& camera);
void set_camera_to_world_gl(OpenCvCamera& camera, const std::array<double, 16>& camera_to_world);
// Makes R orthonormal in double precision (Gram-Schmidt from its viewing direction) unless it is
// within 1e-12: a camera read off float matrices (to_opencv) is orthonormal to float precision only,
// and then [R|t] read back from its camera-to-world, R^T's inverse, would not be the same numbers.
void orthonormalize(OpenCvCamera& camera);

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
