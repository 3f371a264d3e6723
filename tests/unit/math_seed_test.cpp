// The geometry-pipeline seed ("The 3D Geometry Pipeline", Sean Baxter, 1998) in its own conventions,
// checked against facet. The seed uses Direct3D row vectors: x' = x * M, so a concatenation reads
// left to right (x * A * B * C * D) and its matrices are the transposes of facet's column-vector
// matrices (facet: x' = D^T C^T B^T A^T x). Direct3D is left-handed: the camera looks down +Z.
//
// The seed's matrices are written here as the text and its code give them (element names _11.._44,
// row then column), not derived from facet, so that each comparison is between two independent
// constructions.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "facet/camera.hpp"
#include "facet/math/transform.hpp"
#include "support/glm_compare.hpp"

namespace {

using namespace facet;
using facet_test::float_near;
using facet_test::mat_near;
using facet_test::Rng;
using facet_test::vec_near;

// ---- the seed's code, transcribed ------------------------------------------------------------------

// The seed's Matrix: _m[row][column], _11 is _m[0][0]. Vectors are rows.
struct SeedMatrix {
    float m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};  // Matrix() is Identity()
    float& _(int row, int col) { return m[row - 1][col - 1]; }  // _(2, 3) is _23
};

// Matrix::operator*: c_ij = sum_k a_ik b_kj.
SeedMatrix operator*(const SeedMatrix& a, const SeedMatrix& b) {
    SeedMatrix c;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            float s = 0;
            for (int k = 0; k < 4; ++k) s += a.m[i][k] * b.m[k][j];
            c.m[i][j] = s;
        }
    return c;
}

// operator*(Vector, Matrix): ret._x = v._x * m._11 + v._y * m._21 + v._z * m._31 + v._w * m._41, ...
Vec4 operator*(Vec4 v, const SeedMatrix& m) {
    Vec4 r;
    for (int j = 0; j < 4; ++j) r[j] = v.x * m.m[0][j] + v.y * m.m[1][j] + v.z * m.m[2][j] + v.w * m.m[3][j];
    return r;
}

// Vector::homogenize: x /= w, y /= w, z /= w, w = 1 / w.
Vec4 seed_homogenize(Vec4 v) { return {v.x / v.w, v.y / v.w, v.z / v.w, 1 / v.w}; }

// The text's scale matrix: sx, sy, sz on the diagonal.
SeedMatrix Scale(float sx, float sy, float sz) {
    SeedMatrix r;
    r._(1, 1) = sx;
    r._(2, 2) = sy;
    r._(3, 3) = sz;
    return r;
}
SeedMatrix Scale(float s) { return Scale(s, s, s); }

// Matrix::RotateX: _22 = _33 = cos, _23 = sin, _32 = -sin.
SeedMatrix RotateX(float ang) {
    SeedMatrix r;
    r._(2, 2) = r._(3, 3) = std::cos(ang);
    r._(2, 3) = std::sin(ang);
    r._(3, 2) = -r._(2, 3);
    return r;
}
// Matrix::RotateY: _11 = _33 = cos, _31 = sin, _13 = -sin.
SeedMatrix RotateY(float ang) {
    SeedMatrix r;
    r._(1, 1) = r._(3, 3) = std::cos(ang);
    r._(3, 1) = std::sin(ang);
    r._(1, 3) = -r._(3, 1);
    return r;
}
// Matrix::RotateZ: _11 = _22 = cos, _12 = sin, _21 = -sin.
SeedMatrix RotateZ(float ang) {
    SeedMatrix r;
    r._(1, 1) = r._(2, 2) = std::cos(ang);
    r._(1, 2) = std::sin(ang);
    r._(2, 1) = -r._(1, 2);
    return r;
}
// Matrix::Translate: _41, _42, _43.
SeedMatrix Translate(float x, float y, float z) {
    SeedMatrix r;
    r._(4, 1) = x;
    r._(4, 2) = y;
    r._(4, 3) = z;
    return r;
}
// Projection(near, far): _44 = 0, _34 = 1, _33 = f / (f - n), _43 = -n * _33.
SeedMatrix Projection(float nearp, float farp) {
    SeedMatrix r;
    r._(4, 4) = 0;
    r._(3, 4) = 1;
    r._(3, 3) = farp / (farp - nearp);
    r._(4, 3) = -nearp * r._(3, 3);
    return r;
}
// Viewport(w, h, clip x, clip y, clip width, clip height): _11 = w/cw, _22 = -h/ch, _41 = -x*_11,
// _42 = -y*_22. (x, y) is the top-left corner of the clip window (D3DVIEWPORT2's dvClipX/dvClipY).
SeedMatrix Viewport(int w, int h, float x, float y, float cw, float ch) {
    SeedMatrix r;
    r._(1, 1) = float(w) / cw;
    r._(2, 2) = float(-h) / ch;
    r._(4, 1) = -x * r._(1, 1);
    r._(4, 2) = -y * r._(2, 2);
    return r;
}

// Camera(from, to, roll). Despite its name the seed's `to` is the view *direction*: the code
// normalizes it and uses it as the Z axis. Transcribed line by line.
SeedMatrix SeedCamera(Vec3 from, Vec3 to, float roll) {
    auto Normalize = [](Vec3 v) { return v / std::sqrt(dot(v, v)); };
    auto Magnitude = [](Vec3 v) { return std::sqrt(dot(v, v)); };
    SeedMatrix c;
    to = Normalize(to);
    float shadow = dot(Vec3{0, 1, 0}, to);
    Vec3 up = Vec3{0, 1, 0} - shadow * to;
    if (1e-3f > Magnitude(up)) up = Vec3{0, 0, -to.y};
    up = Normalize(up);
    Vec3 right = cross(up, to);
    c._(1, 1) = right.x;
    c._(2, 1) = right.y;
    c._(3, 1) = right.z;
    c._(1, 2) = up.x;
    c._(2, 2) = up.y;
    c._(3, 2) = up.z;
    c._(1, 3) = to.x;
    c._(2, 3) = to.y;
    c._(3, 3) = to.z;
    c._(4, 1) = -dot(from, right);
    c._(4, 2) = -dot(from, up);
    c._(4, 3) = -dot(from, to);
    return c * RotateZ(-roll);  // RotateZ(-roll): *this *= ret
}

// The seed matrix as written on paper, in a facet Mat4 (element (r, c) = _{r+1}{c+1}). Its transpose
// is the column-vector form that facet builds.
Mat4 as_written(const SeedMatrix& s) {
    Mat4 m;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m(r, c) = s.m[r][c];
    return m;
}

// Screen-space points compare component by component: x and y are pixels in the hundreds while z and
// 1/w are below 1, so one tolerance relative to the whole vector would not test z and 1/w at all.
void expect_components_near(Vec4 actual, Vec4 expected, double tol = 1e-5) {
    for (int i = 0; i < 4; ++i)
        EXPECT_TRUE(float_near(actual[i], expected[i], tol)) << "component " << i;
}

// ---- the transformations ------------------------------------------------------------------------------

// Derivation of the rotation sense. Row vector times RotateX:
//   y' = y*_22 + z*_32 = y cos a - z sin a,   z' = y*_23 + z*_33 = y sin a + z cos a,
// so a = +90 degrees takes +Y to +Z: the same sense as facet's rotate_x (right-hand rule about +X).
// Likewise RotateY: x' = x cos a + z sin a, z' = -x sin a + z cos a (+Z to +X), and RotateZ:
// x' = x cos a - y sin a, y' = x sin a + y cos a (+X to +Y). So each seed rotation is exactly the
// transpose of facet's rotation by the *same* angle; no sign flip between the conventions.
TEST(Seed, RotationsAreTransposesOfFacetsWithTheSameAngle) {
    // The derivation, on the basis vectors.
    EXPECT_TRUE(vec_near(Vec4(0, 1, 0, 1) * RotateX(k_pi / 2), Vec4{0, 0, 1, 1}, 1e-6f));
    EXPECT_TRUE(vec_near(Vec4(0, 0, 1, 1) * RotateY(k_pi / 2), Vec4{1, 0, 0, 1}, 1e-6f));
    EXPECT_TRUE(vec_near(Vec4(1, 0, 0, 1) * RotateZ(k_pi / 2), Vec4{0, 1, 0, 1}, 1e-6f));
    Rng rng(401);
    for (int it = 0; it < 200; ++it) {
        float a = rng.uniform(-2 * k_pi, 2 * k_pi);
        EXPECT_TRUE(mat_near(transpose(as_written(RotateX(a))), rotate_x(a), 1e-6f));
        EXPECT_TRUE(mat_near(transpose(as_written(RotateY(a))), rotate_y(a), 1e-6f));
        EXPECT_TRUE(mat_near(transpose(as_written(RotateZ(a))), rotate_z(a), 1e-6f));
        // And the opposite angle would be wrong (unless sin a is ~0).
        if (std::fabs(std::sin(a)) > 0.1f) {
            EXPECT_FALSE(mat_near(transpose(as_written(RotateX(a))), rotate_x(-a), 1e-3f));
        }
    }
}

TEST(Seed, TranslateAndScaleAreTransposesOfFacets) {
    Rng rng(402);
    for (int it = 0; it < 100; ++it) {
        Vec3 t = rng.vec3(-100, 100), s = rng.vec3(-5, 5);
        EXPECT_EQ(transpose(as_written(Translate(t.x, t.y, t.z))), translate(t));
        EXPECT_EQ(transpose(as_written(Scale(s.x, s.y, s.z))), scale(s));
        // Homogeneous translation, as the text writes it: x' = (x + Tx w, y + Ty w, z + Tz w, w).
        Vec4 p{1, 2, 3, 1};
        EXPECT_EQ(p * Translate(t.x, t.y, t.z), translate(t) * p);
    }
}

// The product of row-vector matrices is the reversed product of the transposes: (AB)^T = B^T A^T.
TEST(Seed, RowVectorProductsReverseInColumnForm) {
    Rng rng(403);
    for (int it = 0; it < 200; ++it) {
        float a = rng.uniform(-3, 3), b = rng.uniform(-3, 3);
        Vec3 t = rng.vec3(-10, 10);
        SeedMatrix e = RotateX(a) * RotateY(b) * Translate(t.x, t.y, t.z);
        EXPECT_TRUE(mat_near(transpose(as_written(e)), translate(t) * rotate_y(b) * rotate_x(a), 1e-6f));
        Vec4 p(rng.vec3(-10, 10), 1);
        EXPECT_TRUE(vec_near(p * e, translate(t) * rotate_y(b) * rotate_x(a) * p, 1e-6f));
    }
}

// The house: scale 3, rotate 90 degrees about Y, -30 degrees about Z, translate (-10, 0, 40).
// Row form x' = x A B C D; column form x' = T(-10,0,40) Rz(-30) Ry(90) S(3) x, same angles.
TEST(Seed, HouseExample) {
    const float ry = radians(90.0f), rz = radians(-30.0f);
    SeedMatrix e = Scale(3) * RotateY(ry) * RotateZ(rz) * Translate(-10, 0, 40);
    Mat4 facet_e = translate({-10, 0, 40}) * rotate_z(rz) * rotate_y(ry) * scale(3.0f);
    EXPECT_TRUE(mat_near(transpose(as_written(e)), facet_e, 1e-6f));

    // Hand-derived (cos 30 = 0.8660254, sin 30 = 0.5):
    // roof apex (0,1,0) -> scale (0,3,0) -> about Y unchanged -> about Z by -30: (3 sin 30, 3 cos 30, 0)
    // = (1.5, 2.5980762, 0) -> translate: (-8.5, 2.5980762, 40).
    const Vec3 apex{-8.5f, 2.5980762f, 40};
    // front door (0,0,1) -> (0,0,3) -> about Y by 90: (3,0,0) (it now faces +X, the right of the screen)
    // -> about Z by -30: (3 cos 30, -3 sin 30, 0) = (2.5980762, -1.5, 0) -> (-7.4019238, -1.5, 40).
    const Vec3 door{-7.4019238f, -1.5f, 40};
    EXPECT_TRUE(vec_near((Vec4(0, 1, 0, 1) * e).xyz(), apex, 1e-6f));
    EXPECT_TRUE(vec_near(transform_point(facet_e, {0, 1, 0}), apex, 1e-6f));
    EXPECT_TRUE(vec_near((Vec4(0, 0, 1, 1) * e).xyz(), door, 1e-6f));
    EXPECT_TRUE(vec_near(transform_point(facet_e, {0, 0, 1}), door, 1e-6f));
    // Pre-multiplying once (E = A B C D) equals multiplying the vertex step by step.
    Vec4 x{0.3f, -0.7f, 0.2f, 1};
    Vec4 stepwise = (((x * Scale(3)) * RotateY(ry)) * RotateZ(rz)) * Translate(-10, 0, 40);
    EXPECT_TRUE(vec_near(stepwise, x * e, 1e-6f));
}

// Projection(n, f) is facet's left-handed perspective with a 90 degree field of view and square
// aspect (the seed's perspective is x/z, y/z).
TEST(Seed, ProjectionIsTheTransposeOfLeftHandedPerspective) {
    Rng rng(404);
    for (int it = 0; it < 200; ++it) {
        float n = rng.uniform(1, 10), f = n + rng.uniform(1, 1000);
        EXPECT_TRUE(mat_near(transpose(as_written(Projection(n, f))), perspective_lh_zo(k_pi / 2, 1, n, f), 1e-6f));
        // The text's derivation: w is the depth, z/w is 0 at Zn and 1 at Zf.
        Vec4 at_near = Vec4(0.5f, -0.5f, n, 1) * Projection(n, f);
        Vec4 at_far = Vec4(0.5f, -0.5f, f, 1) * Projection(n, f);
        EXPECT_FLOAT_EQ(at_near.w, n);
        EXPECT_NEAR(seed_homogenize(at_near).z, 0.0f, 1e-6f);
        EXPECT_NEAR(seed_homogenize(at_far).z, 1.0f, 1e-6f);
        // And x/w = x/z, the text's perspective divide.
        EXPECT_FLOAT_EQ(seed_homogenize(at_far).x, 0.5f / f);
    }
}

// Viewport with the standard clip window (top-left (-1, 1), size 2 x 2) is facet's viewport at the
// origin. A general clip window [x, x+cw] x [y-ch, y] is first mapped onto [-1, 1]^2, which is
// facet's ortho_lh_zo over that window with depth [0, 1] left alone.
TEST(Seed, ViewportIsTheTransposeOfFacets) {
    EXPECT_TRUE(mat_near(transpose(as_written(Viewport(640, 480, -1, 1, 2, 2))), viewport(0, 0, 640, 480), 0));
    EXPECT_TRUE(mat_near(transpose(as_written(Viewport(800, 600, -1, 1, 2, 2))), viewport(0, 0, 800, 600), 0));
    // The 4:3 clip window the text recommends (dvClipWidth / dvClipHeight = width / height).
    const float x = -4.0f / 3, y = 1, cw = 8.0f / 3, ch = 2;
    EXPECT_TRUE(mat_near(transpose(as_written(Viewport(640, 480, x, y, cw, ch))),
                         viewport(0, 0, 640, 480) * ortho_lh_zo(x, x + cw, y - ch, y, 0, 1), 1e-6f));
    // The text: the visible cube (-1, 1, 0) .. (1, -1, 1) lands on the screen corners.
    EXPECT_TRUE(vec_near(Vec4(-1, 1, 0, 1) * Viewport(640, 480, -1, 1, 2, 2), Vec4{0, 0, 0, 1}, 0));
    EXPECT_TRUE(vec_near(Vec4(1, -1, 1, 1) * Viewport(640, 480, -1, 1, 2, 2), Vec4{640, 480, 1, 1}, 0));
}

// The airplane: W = Scale(3) RotateZ(45) Translate(5, 22, 120), T = W Projection Viewport, then
// xs = (xt.x/xt.w, xt.y/xt.w, xt.z/xt.w, 1/xt.w). facet's TransformChain builds the same matrix in
// column form (view = identity: the seed's "default camera").
TEST(Seed, AirplaneConcatenationAndHomogenize) {
    const float n = 1, f = 1000;
    SeedMatrix w = Scale(3) * RotateZ(radians(45.0f)) * Translate(5, 22, 120);
    SeedMatrix t = w * Projection(n, f) * Viewport(640, 480, -1, 1, 2, 2);

    TransformChain chain;
    chain.set_world(translate({5, 22, 120}) * rotate_z(radians(45.0f)) * scale(3.0f));
    chain.set_view(Mat4::identity());
    chain.set_projection(perspective_lh_zo(k_pi / 2, 1, n, f));
    chain.set_viewport(viewport(0, 0, 640, 480));
    EXPECT_TRUE(mat_near(transpose(as_written(t)), chain.screen_from_object(), 1e-6f));

    Rng rng(405);
    for (int it = 0; it < 200; ++it) {
        Vec4 x(rng.vec3(-5, 5), 1);
        Vec4 xt = x * t;
        Vec4 xs = seed_homogenize(xt);
        std::optional<Vec4> h = homogenize(chain.screen_from_object() * x);
        ASSERT_TRUE(h.has_value());
        expect_components_near(*h, xs);
    }

    // Hand-derived for the plane's origin, which lands on (5, 22, 120): w = 120 (the depth),
    // x = 320 + 320 * 5/120 = 333.3333, y = 240 - 240 * 22/120 = 196,
    // z = (120 - n) f / (f - n) / 120 = 119000 / 999 / 120 = 0.99265932, 1/w = 1/120.
    std::optional<Vec4> o = homogenize(chain.screen_from_object() * Vec4(0, 0, 0, 1));
    ASSERT_TRUE(o.has_value());
    expect_components_near(*o, Vec4{333.33333f, 196, 0.99265932f, 1 / 120.0f});
    expect_components_near(seed_homogenize(Vec4(0, 0, 0, 1) * t), *o);

    // Next frame: W' = W Translate(.5, 0, 1.5) in row form is T(.5, 0, 1.5) * world in column form.
    SeedMatrix w2 = w * Translate(0.5f, 0, 1.5f);
    EXPECT_TRUE(mat_near(transpose(as_written(w2)), translate({0.5f, 0, 1.5f}) * chain.world(), 1e-6f));
}

// ---- the camera ---------------------------------------------------------------------------------------

// The seed's camera is a left-handed look-at along a direction with world up (0, 1, 0).
TEST(Seed, CameraIsTheTransposeOfLookAtLh) {
    Rng rng(406);
    for (int it = 0; it < 500; ++it) {
        Vec3 from = rng.vec3(-20, 20);
        Vec3 dir = rng.unit3() * rng.uniform(0.5f, 10);
        if (std::fabs(normalize(dir).y) > 0.99f) continue;  // the seed is not orthonormal near the poles
        EXPECT_TRUE(mat_near(transpose(as_written(SeedCamera(from, dir, 0))), look_at_lh(from, from + dir, {0, 1, 0})));
    }
    // The text's example position (0, 10, 12): translating by -p.
    SeedMatrix c = SeedCamera({0, 10, 12}, {0, 0, 1}, 0);
    EXPECT_TRUE(mat_near(transpose(as_written(c)), translate({0, -10, -12}), 0));
    // "The default camera": at the origin looking down +Z with +Y up is the identity.
    EXPECT_TRUE(mat_near(transpose(as_written(SeedCamera({0, 0, 0}, {0, 0, 1}, 0))), Mat4::identity(), 0));
    EXPECT_TRUE(mat_near(look_at_lh({0, 0, 0}, {0, 0, 1}, {0, 1, 0}), Mat4::identity(), 0));
}

// The seed's roll: Camera * RotateZ(-roll) in row form, i.e. rotate_z(-roll) * view in column form.
// facet's left-handed Camera with the same roll must build the same matrix.
TEST(Seed, CameraRollMatchesFacetLeftHandedCamera) {
    Rng rng(407);
    for (int it = 0; it < 200; ++it) {
        Vec3 from = rng.vec3(-20, 20);
        Vec3 dir = rng.unit3() * rng.uniform(0.5f, 10);
        if (std::fabs(normalize(dir).y) > 0.99f) continue;
        float roll = rng.uniform(-k_pi, k_pi);
        Camera cam = Camera::looking(from, dir, roll);
        cam.handedness = Handedness::left;
        EXPECT_TRUE(mat_near(transpose(as_written(SeedCamera(from, dir, roll))), cam.view()))
            << "roll " << roll;
    }
}

// Looking straight up, the seed picks yc = (0, 0, -1); straight down, (0, 0, 1). facet's left-handed
// camera basis does the same, and the whole matrix agrees.
TEST(Seed, CameraLookingStraightUpOrDown) {
    CameraBasis up = camera_basis({0, 1, 0}, {0, 1, 0}, Handedness::left);
    EXPECT_TRUE(vec_near(up.up, Vec3{0, 0, -1}, 0));
    EXPECT_TRUE(vec_near(up.forward, Vec3{0, 1, 0}, 0));
    CameraBasis down = camera_basis({0, -1, 0}, {0, 1, 0}, Handedness::left);
    EXPECT_TRUE(vec_near(down.up, Vec3{0, 0, 1}, 0));
    EXPECT_TRUE(vec_near(down.forward, Vec3{0, -1, 0}, 0));

    SeedMatrix s_up = SeedCamera({1, 2, 3}, {0, 4, 0}, 0);
    EXPECT_EQ(s_up._(1, 2), 0.0f);  // the camera's y axis is the second column
    EXPECT_EQ(s_up._(2, 2), 0.0f);
    EXPECT_EQ(s_up._(3, 2), -1.0f);
    EXPECT_TRUE(mat_near(transpose(as_written(s_up)), look_at_lh({1, 2, 3}, {1, 6, 3}, {0, 1, 0})));
    SeedMatrix s_down = SeedCamera({1, 2, 3}, {0, -4, 0}, 0);
    EXPECT_EQ(s_down._(3, 2), 1.0f);
    EXPECT_TRUE(mat_near(transpose(as_written(s_down)), look_at_lh({1, 2, 3}, {1, -2, 3}, {0, 1, 0})));
}

}  // namespace
