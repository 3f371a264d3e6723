// facet math: the transformation matrices of the geometry pipeline (column-vector forms).
#include "facet/math/transform.hpp"

#include <cmath>

#include "math/portable_trig.hpp"

namespace facet {

Mat4 translate(Vec3 t) {
    Mat4 m;
    m.col[3] = Vec4(t, 1);
    return m;
}

Mat4 scale(Vec3 s) {
    Mat4 m;
    m(0, 0) = s.x;
    m(1, 1) = s.y;
    m(2, 2) = s.z;
    return m;
}

Mat4 scale(float s) { return scale(Vec3{s, s, s}); }

namespace {

// Rotation in the plane of axes a -> b (a positive angle turns a toward b).
Mat4 plane_rotation(int a, int b, float angle) {
    float s, c;
    portable::sincos(angle, s, c);
    Mat4 m;
    m(a, a) = c;
    m(a, b) = -s;
    m(b, a) = s;
    m(b, b) = c;
    return m;
}

}  // namespace

Mat4 rotate_x(float angle) { return plane_rotation(1, 2, angle); }
Mat4 rotate_y(float angle) { return plane_rotation(2, 0, angle); }
Mat4 rotate_z(float angle) { return plane_rotation(0, 1, angle); }

Mat4 rotate(Vec3 axis, float angle) {
    Vec3 u = normalize(axis);
    if (!(dot(u, u) > 0)) return Mat4::identity();
    float s, c;
    portable::sincos(angle, s, c);
    const float t = 1 - c;
    Mat4 m;
    m(0, 0) = c + t * u.x * u.x;
    m(1, 0) = t * u.x * u.y + s * u.z;
    m(2, 0) = t * u.x * u.z - s * u.y;
    m(0, 1) = t * u.x * u.y - s * u.z;
    m(1, 1) = c + t * u.y * u.y;
    m(2, 1) = t * u.y * u.z + s * u.x;
    m(0, 2) = t * u.x * u.z + s * u.y;
    m(1, 2) = t * u.y * u.z - s * u.x;
    m(2, 2) = c + t * u.z * u.z;
    return m;
}

Mat4 yaw_pitch_roll(float yaw, float pitch, float roll) { return rotate_y(yaw) * rotate_x(pitch) * rotate_z(roll); }


Mat4 perspective_rh_zo(float fovy, float aspect, float near, float far) {
    float f = 1.0f / static_cast<float>(portable::tan(fovy / 2));
    Mat4 m = Mat4::zero();
    m(0, 0) = f / aspect;
    m(1, 1) = f;
    m(2, 2) = far / (near - far);
    m(2, 3) = -(far * near) / (far - near);
    m(3, 2) = -1;
    return m;
}

Mat4 perspective_lh_zo(float fovy, float aspect, float near, float far) {
    float f = 1.0f / static_cast<float>(portable::tan(fovy / 2));
    Mat4 m = Mat4::zero();
    m(0, 0) = f / aspect;
    m(1, 1) = f;
    m(2, 2) = far / (far - near);
    m(2, 3) = -(far * near) / (far - near);
    m(3, 2) = 1;
    return m;
}

namespace {

Mat4 ortho_xy(float left, float right, float bottom, float top) {
    Mat4 m;
    m(0, 0) = 2 / (right - left);
    m(1, 1) = 2 / (top - bottom);
    m(0, 3) = -(right + left) / (right - left);
    m(1, 3) = -(top + bottom) / (top - bottom);
    return m;
}

}  // namespace

Mat4 ortho_rh_zo(float left, float right, float bottom, float top, float near, float far) {
    Mat4 m = ortho_xy(left, right, bottom, top);
    m(2, 2) = -1 / (far - near);
    m(2, 3) = -near / (far - near);
    return m;
}

Mat4 ortho_lh_zo(float left, float right, float bottom, float top, float near, float far) {
    Mat4 m = ortho_xy(left, right, bottom, top);
    m(2, 2) = 1 / (far - near);
    m(2, 3) = -near / (far - near);
    return m;
}

Mat4 viewport(float x, float y, float width, float height) {
    Mat4 m;
    m(0, 0) = width / 2;
    m(0, 3) = x + width / 2;
    m(1, 1) = -height / 2;
    m(1, 3) = y + height / 2;
    return m;
}

}  // namespace facet

// look_at lives with the camera basis (camera.cpp), which handles the straight-up singularity.
