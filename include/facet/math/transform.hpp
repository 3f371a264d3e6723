// facet math: matrices that build the geometry pipeline, object -> world -> view -> clip -> screen.
// Column vectors: a vertex is transformed by M * v, so T * R * S scales first, then rotates, then
// translates. Angles are in radians. Handedness and depth range are spelled in the names, as in GLM:
// _lh / _rh, _zo = clip-space depth in [0, 1] (the only range facet rasterizes).
#pragma once

#include "facet/api.hpp"
#include "facet/math/mat.hpp"

FACET_API_BEGIN
namespace facet {

Mat4 translate(Vec3 t);
Mat4 scale(Vec3 s);  // non-uniform and negative factors allowed
Mat4 scale(float s);

// Rotations by the right-hand rule about each axis (positive angle turns +Y toward +Z about X,
// +Z toward +X about Y, +X toward +Y about Z), identical to glm::rotate with a unit axis.
Mat4 rotate_x(float angle);
Mat4 rotate_y(float angle);
Mat4 rotate_z(float angle);
// About an arbitrary axis; a zero or non-finite axis gives the identity.
Mat4 rotate(Vec3 axis, float angle);
// Ry(yaw) * Rx(pitch) * Rz(roll): a vector is rolled first, then pitched, then yawed,
// as D3DXMatrixRotationYawPitchRoll and glm::yawPitchRoll do.
Mat4 yaw_pitch_roll(float yaw, float pitch, float roll);

// View matrices. RH: the camera looks down -Z of view space (OpenGL, glTF). LH: down +Z (Direct3D,
// the seeds). `up` need not be perpendicular to the view direction; when it is parallel (looking
// straight up or down) a perpendicular fallback is chosen so the result never holds NaN.
Mat4 look_at_rh(Vec3 eye, Vec3 target, Vec3 up);
Mat4 look_at_lh(Vec3 eye, Vec3 target, Vec3 up);

// Perspective projections: vertical field of view, aspect = width / height, depth [0, 1] from
// near to far. Preconditions: 0 < fovy < pi, aspect > 0, 0 < near < far.
Mat4 perspective_rh_zo(float fovy, float aspect, float near, float far);
Mat4 perspective_lh_zo(float fovy, float aspect, float near, float far);

// Orthographic projections of the box [left,right] x [bottom,top] x [near,far], depth [0, 1].
Mat4 ortho_rh_zo(float left, float right, float bottom, float top, float near, float far);
Mat4 ortho_lh_zo(float left, float right, float bottom, float top, float near, float far);

// Maps normalized device coordinates to window pixels: x in [-1,1] -> [x, x+width],
// y in [-1,1] -> [y+height, y] (y flipped: screen origin is the top-left, y grows down),
// depth z in [0,1] unchanged. Pixel centres then sit at integer + 0.5.
Mat4 viewport(float x, float y, float width, float height);

}  // namespace facet
FACET_API_END
