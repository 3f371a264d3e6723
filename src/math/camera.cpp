// facet: camera basis, look-at matrices, the Camera type and the cached TransformChain.
#include "facet/camera.hpp"

#include <cmath>
#include <string>

#include "facet/image.hpp"
#include "math/portable_trig.hpp"

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
    float se, ce, sa, ca;
    portable::sincos(elevation, se, ce);
    portable::sincos(azimuth, sa, ca);
    Vec3 dir{ce * sa, se, ce * ca};
    c.position = target + dir * distance;
    return c;
}

namespace {

// ---- OpenCV's convention ----
// OpenCV's camera space is facet's right-handed view space with Y and Z negated (+Y down the
// image, looking down +Z). A left-handed view space has the same axes as OpenCV's but Y, and its
// view matrix keeps the world's orientation, so it sees the world mirrored: no OpenCV camera does.

// [R|t] of OpenCV's world-to-camera, in double.
struct Pose {
    double r[3][3];
    double t[3];
};

Pose pose_of(const Camera& c) {
    Pose p;
    if (c.opencv) {
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) p.r[i][j] = c.opencv->rotation[static_cast<std::size_t>(i * 3 + j)];
            p.t[i] = c.opencv->translation[static_cast<std::size_t>(i)];
        }
        return p;
    }
    const Mat4 v = c.view();  // right-handed (the callers check)
    const double flip[3] = {1, -1, -1};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) p.r[i][j] = flip[i] * v(i, j);
        p.t[i] = flip[i] * v(i, 3);
    }
    return p;
}

}  // namespace

Status validate(const OpenCvCamera& c) {
    auto bad = [](const std::string& what) { return Error{ErrorCode::invalid_argument, "OpenCV camera: " + what}; };
    if (!(c.width >= 1 && c.width <= k_max_target_size && c.height >= 1 && c.height <= k_max_target_size))
        return bad("image size " + std::to_string(c.width) + "x" + std::to_string(c.height) + " is outside 1.." +
                   std::to_string(k_max_target_size));
    if (!(std::isfinite(c.fx) && std::isfinite(c.fy) && c.fx > 0 && c.fy > 0))
        return bad("the focal lengths fx and fy must be positive and finite");
    if (!(std::isfinite(c.cx) && std::isfinite(c.cy) && std::isfinite(c.skew)))
        return bad("the principal point (cx, cy) and the skew must be finite");
    for (double v : c.rotation)
        if (!std::isfinite(v)) return bad("the rotation R holds a non-finite value");
    for (double v : c.translation)
        if (!std::isfinite(v)) return bad("the translation t holds a non-finite value");
    // Orthonormal rows within 1e-4 (numbers printed with 6 digits still pass), determinant +1.
    const auto& r = c.rotation;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double d = 0;
            for (int k = 0; k < 3; ++k) d += r[static_cast<std::size_t>(i * 3 + k)] * r[static_cast<std::size_t>(j * 3 + k)];
            if (std::fabs(d - (i == j ? 1.0 : 0.0)) > 1e-4) return bad("R is not a rotation (its rows are not orthonormal)");
        }
    const double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) + r[2] * (r[3] * r[7] - r[4] * r[6]);
    if (!(det > 0)) return bad("R is a reflection (determinant -1), not a rotation");
    return Ok{};
}

Camera Camera::from_opencv(const OpenCvCamera& cv, float near, float far) {
    Camera c;
    const auto& r = cv.rotation;
    const auto& t = cv.translation;
    Vec3 eye;
    for (int i = 0; i < 3; ++i) {  // eye = -R^T t
        const auto col = static_cast<std::size_t>(i);
        eye[col] = static_cast<float>(-(r[col] * t[0] + r[3 + col] * t[1] + r[6 + col] * t[2]));
    }
    c.position = eye;
    // Camera +Z (the third row of R) is forward, camera -Y (minus the second row) is up.
    c.target = eye + Vec3{static_cast<float>(r[6]), static_cast<float>(r[7]), static_cast<float>(r[8])};
    c.up = -Vec3{static_cast<float>(r[3]), static_cast<float>(r[4]), static_cast<float>(r[5])};
    c.fovy = static_cast<float>(2 * portable::atan(cv.height / (2 * cv.fy)));
    c.near = near;
    c.far = far;
    c.opencv = cv;
    return c;
}

std::optional<OpenCvCamera> to_opencv(const Camera& c, int width, int height) {
    OpenCvCamera out;
    if (c.opencv) {
        out = *c.opencv;
        if (width == out.width && height == out.height) return out;
        // The same normalized intrinsics for another size (projection() is size-independent).
        const double sx = static_cast<double>(width) / out.width, sy = static_cast<double>(height) / out.height;
        out.fx *= sx, out.skew *= sx, out.cx = (out.cx + 0.5) * sx - 0.5;
        out.fy *= sy, out.cy = (out.cy + 0.5) * sy - 0.5;
        out.width = width, out.height = height;
        return out;
    }
    if (c.projection_kind != ProjectionKind::perspective || c.handedness != Handedness::right) return std::nullopt;
    // Read off the float matrix, in double: from_opencv's projection() gives back its entries.
    const Mat4 p = c.projection(static_cast<float>(width) / static_cast<float>(height));
    const double w = width, h = height;
    out.fx = p(0, 0) * w / 2;
    out.fy = p(1, 1) * h / 2;
    out.skew = 0;
    out.cx = (1 - static_cast<double>(p(0, 2))) * w / 2 - 0.5;
    out.cy = (1 + static_cast<double>(p(1, 2))) * h / 2 - 0.5;
    out.width = width, out.height = height;
    const Pose pose = pose_of(c);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) out.rotation[static_cast<std::size_t>(i * 3 + j)] = pose.r[i][j];
        out.translation[static_cast<std::size_t>(i)] = pose.t[i];
    }
    return out;
}

namespace {

// [R^T | -R^T t] is OpenCV's camera-to-world; OpenGL's camera axes are OpenCV's with Y and Z negated.
std::array<double, 16> camera_to_world_gl(const Pose& p) {
    const double flip[3] = {1, -1, -1};
    std::array<double, 16> m{};
    for (int i = 0; i < 3; ++i) {
        double eye = 0;
        for (int k = 0; k < 3; ++k) eye -= p.r[k][i] * p.t[k];
        for (int j = 0; j < 3; ++j) m[static_cast<std::size_t>(i * 4 + j)] = p.r[j][i] * flip[j];
        m[static_cast<std::size_t>(i * 4 + 3)] = eye;
    }
    m[15] = 1;
    return m;
}

}  // namespace

Mat4 camera_to_world_gl(const Camera& c) {
    const std::array<double, 16> d = camera_to_world_gl(pose_of(c));
    Mat4 m;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) m(i, j) = static_cast<float>(d[static_cast<std::size_t>(i * 4 + j)]);
    return m;
}

std::array<double, 16> camera_to_world_gl(const OpenCvCamera& c) {
    Camera camera;
    camera.opencv = c;
    return camera_to_world_gl(pose_of(camera));
}

void orthonormalize(OpenCvCamera& c) {
    auto& r = c.rotation;
    double worst = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double d = 0;
            for (int k = 0; k < 3; ++k) d += r[static_cast<std::size_t>(i * 3 + k)] * r[static_cast<std::size_t>(j * 3 + k)];
            worst = std::max(worst, std::fabs(d - (i == j ? 1.0 : 0.0)));
        }
    if (worst <= 1e-12) return;  // already is: a camera read back keeps its numbers
    // Gram-Schmidt from the viewing direction (the third row), then the right (the first); the
    // second is their cross product, so the determinant stays +1.
    auto row = [&](int i) { return std::array<double, 3>{r[static_cast<std::size_t>(3 * i)], r[static_cast<std::size_t>(3 * i + 1)], r[static_cast<std::size_t>(3 * i + 2)]}; };
    auto dot = [](const std::array<double, 3>& a, const std::array<double, 3>& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    auto unit = [&](std::array<double, 3> a) {
        const double n = std::sqrt(dot(a, a));
        return std::array<double, 3>{a[0] / n, a[1] / n, a[2] / n};
    };
    const std::array<double, 3> z = unit(row(2));
    std::array<double, 3> x = row(0);
    const double along = dot(x, z);
    x = unit({x[0] - along * z[0], x[1] - along * z[1], x[2] - along * z[2]});
    const std::array<double, 3> y{z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]};
    for (int j = 0; j < 3; ++j) {
        const auto k = static_cast<std::size_t>(j);
        r[k] = x[k], r[3 + k] = y[k], r[6 + k] = z[k];
    }
}

void set_camera_to_world_gl(OpenCvCamera& c, const std::array<double, 16>& m) {
    // R's rows are the camera's axes in world space (OpenGL's with Y and Z negated), t = -R eye.
    const double flip[3] = {1, -1, -1};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) c.rotation[static_cast<std::size_t>(i * 3 + j)] = flip[i] * m[static_cast<std::size_t>(j * 4 + i)];
    for (int i = 0; i < 3; ++i) {
        double t = 0;
        for (int j = 0; j < 3; ++j) t -= c.rotation[static_cast<std::size_t>(i * 3 + j)] * m[static_cast<std::size_t>(j * 4 + 3)];
        c.translation[static_cast<std::size_t>(i)] = t;
    }
}

Mat4 Camera::view() const {
    if (opencv) {
        const Pose p = pose_of(*this);
        Mat4 v;
        const double flip[3] = {1, -1, -1};
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) v(i, j) = static_cast<float>(flip[i] * p.r[i][j]);
            v(i, 3) = static_cast<float>(flip[i] * p.t[i]);
        }
        return v;
    }
    Mat4 v = look_at(position, target, up, handedness);
    if (roll == 0) return v;
    // Turning the camera counter-clockwise about its view direction turns the image clockwise.
    // In both handednesses view-space x is screen right and y is screen up (only z differs), so the
    // same clockwise turn of (x, y) serves both: the seed's RotateZ(-roll).
    return rotate_z(-roll) * v;
}

Mat4 Camera::projection(float aspect) const {
    if (opencv) {
        // Screen x = u + 0.5 = (ndc x + 1) w / 2 and screen y = v + 0.5 = (1 - ndc y) h / 2 (the
        // viewport), with x_cv = x_view, y_cv = -y_view, z_cv = -z_view = w_clip.
        const OpenCvCamera& k = *opencv;
        const double w = k.width, h = k.height;
        Mat4 m = Mat4::zero();
        m(0, 0) = static_cast<float>(2 * k.fx / w);
        m(0, 1) = static_cast<float>(-2 * k.skew / w) + 0.0f;  // + 0: no -0 for skew 0, as look-at's matrices have
        m(0, 2) = static_cast<float>(1 - 2 * (k.cx + 0.5) / w);
        m(1, 1) = static_cast<float>(2 * k.fy / h);
        m(1, 2) = static_cast<float>(2 * (k.cy + 0.5) / h - 1);
        m(2, 2) = far / (near - far);  // depth as perspective_rh_zo
        m(2, 3) = -(far * near) / (far - near);
        m(3, 2) = -1;
        return m;
    }
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
