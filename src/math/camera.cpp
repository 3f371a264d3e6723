// facet: camera basis, look-at matrices, the Camera type and the cached TransformChain.
#include "facet/camera.hpp"

#include <cmath>

namespace facet {
namespace {

// Below this |cross(forward, up)| the two are treated as parallel: the seed's 1e-3 threshold.
// Past it the normalized side vector keeps about four significant digits of direction.
constexpr float k_parallel_threshold = 1e-3f;

// The direction a camera with this handedness looks by default (RH: -Z, LH: +Z).
Vec3 default_forward(Handedness h) { return h == Handedness::right ? Vec3{0, 0, -1} : Vec3{0, 0, 1}; }

// Up vector for a camera looking along +-up: it tilts as if pitched from the default forward,
// so looking straight up the top of the image points back (the seed's yc = (0, 0, -1) for LH).
Vec3 pole_up(Vec3 f, Vec3 up, Handedness h) {
    Vec3 d = default_forward(h);
    d = d - up * dot(d, up);
    if (length(d) < k_parallel_threshold) d = Vec3{0, 1, 0} - up * up.y;  // up is +-Z: use Y instead
    d = normalize(d);
    return dot(f, up) > 0 ? -d : d;
}

Mat4 view_from_rows(Vec3 r0, Vec3 r1, Vec3 r2, Vec3 eye) {
    Mat4 m;
    const Vec3 rows[3] = {r0, r1, r2};
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) m(r, c) = rows[r][static_cast<std::size_t>(c)];
        m(r, 3) = -dot(rows[r], eye);
    }
    return m;
}

Mat4 look_at(Vec3 eye, Vec3 target, Vec3 up, Handedness h) {
    CameraBasis b = camera_basis(target - eye, up, h);
    // RH view space looks down -Z, so its third row is the backward vector.
    return view_from_rows(b.right, b.up, h == Handedness::right ? -b.forward : b.forward, eye);
}

}  // namespace

CameraBasis camera_basis(Vec3 forward, Vec3 up, Handedness h) {
    Vec3 f = normalize(forward);
    if (!(dot(f, f) > 0)) f = default_forward(h);
    Vec3 u = normalize(up);
    if (!(dot(u, u) > 0)) u = Vec3{0, 1, 0};
    if (length(cross(f, u)) < k_parallel_threshold) u = pole_up(f, u, h);
    Vec3 side = h == Handedness::right ? normalize(cross(f, u)) : normalize(cross(u, f));
    Vec3 true_up = h == Handedness::right ? cross(side, f) : cross(f, side);
    return {side, true_up, f};
}

Mat4 look_at_rh(Vec3 eye, Vec3 target, Vec3 up) { return look_at(eye, target, up, Handedness::right); }
Mat4 look_at_lh(Vec3 eye, Vec3 target, Vec3 up) { return look_at(eye, target, up, Handedness::left); }

Camera Camera::looking(Vec3 position, Vec3 direction, float roll) {
    Camera c;
    c.position = position;
    c.target = position + direction;
    c.roll = roll;
    return c;
}

Camera Camera::orbit(Vec3 target, float azimuth, float elevation, float distance) {
    Camera c;
    c.target = target;
    Vec3 dir{std::cos(elevation) * std::sin(azimuth), std::sin(elevation), std::cos(elevation) * std::cos(azimuth)};
    c.position = target + dir * distance;
    return c;
}

Mat4 Camera::view() const {
    Mat4 v = look_at(position, target, up, handedness);
    if (roll == 0) return v;
    // Turning the camera counter-clockwise about its view direction turns the image clockwise.
    // In both handednesses view-space x is screen right and y is screen up (only z differs), so the
    // same clockwise turn of (x, y) serves both: the seed's RotateZ(-roll).
    return rotate_z(-roll) * v;
}

Mat4 Camera::projection(float aspect) const {
    bool rh = handedness == Handedness::right;
    if (projection_kind == ProjectionKind::perspective)
        return rh ? perspective_rh_zo(fovy, aspect, near, far) : perspective_lh_zo(fovy, aspect, near, far);
    float h = ortho_height / 2, w = h * aspect;
    return rh ? ortho_rh_zo(-w, w, -h, h, near, far) : ortho_lh_zo(-w, w, -h, h, near, far);
}

std::optional<Vec4> homogenize(Vec4 p) {
    if (!(p.w > 0) || !is_finite(p)) return std::nullopt;
    float inv_w = 1.0f / p.w;
    return Vec4{p.x * inv_w, p.y * inv_w, p.z * inv_w, inv_w};
}

void TransformChain::set_world(const Mat4& m) {
    world_ = m;
    object_dirty_ = screen_dirty_ = true;
}
void TransformChain::set_view(const Mat4& m) {
    view_ = m;
    view_projection_dirty_ = object_dirty_ = screen_dirty_ = true;
}
void TransformChain::set_projection(const Mat4& m) {
    projection_ = m;
    view_projection_dirty_ = object_dirty_ = screen_dirty_ = true;
}
void TransformChain::set_viewport(const Mat4& m) {
    viewport_ = m;
    screen_dirty_ = true;
}

const Mat4& TransformChain::clip_from_world() const {
    if (view_projection_dirty_) {
        clip_from_world_ = projection_ * view_;
        ++products_;
        view_projection_dirty_ = false;
    }
    return clip_from_world_;
}

const Mat4& TransformChain::clip_from_object() const {
    if (object_dirty_) {
        clip_from_object_ = clip_from_world() * world_;
        ++products_;
        object_dirty_ = false;
    }
    return clip_from_object_;
}

const Mat4& TransformChain::screen_from_object() const {
    if (screen_dirty_) {
        screen_from_object_ = viewport_ * clip_from_object();
        ++products_;
        screen_dirty_ = false;
    }
    return screen_from_object_;
}

}  // namespace facet
