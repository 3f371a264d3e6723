// Transform builders (translate, scale, rotations, look-at, projections, viewport) against GLM's
// functions of the same conventions, plus hand-derived behaviour.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>

#define GLM_ENABLE_EXPERIMENTAL
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtx/euler_angles.hpp>

#include "facet/camera.hpp"
#include "facet/math/transform.hpp"
#include "support/glm_compare.hpp"

namespace {

using namespace facet;
using facet_test::float_near;
using facet_test::mat_near;
using facet_test::Rng;
using facet_test::to_glm;
using facet_test::vec_near;

constexpr float k_nan = std::numeric_limits<float>::quiet_NaN();
constexpr float k_inf = std::numeric_limits<float>::infinity();

const glm::mat4 k_glm_identity(1.0f);

// ---- translate / scale -------------------------------------------------------------------------------

TEST(Transform, TranslateMatchesGlm) {
    Rng rng(301);
    for (int it = 0; it < 200; ++it) {
        Vec3 t = rng.vec3(-100, 100);
        EXPECT_TRUE(mat_near(translate(t), glm::translate(k_glm_identity, to_glm(t)), 0));
        Vec3 p = rng.vec3(-10, 10);
        EXPECT_EQ(transform_point(translate(t), p), p + t);
        EXPECT_EQ(transform_direction(translate(t), p), p);
    }
}

TEST(Transform, ScaleMatchesGlmIncludingNonUniformAndNegative) {
    Rng rng(302);
    for (int it = 0; it < 200; ++it) {
        Vec3 s = rng.vec3(-5, 5);
        EXPECT_TRUE(mat_near(scale(s), glm::scale(k_glm_identity, to_glm(s)), 0));
        Vec3 p = rng.vec3(-10, 10);
        EXPECT_EQ(transform_point(scale(s), p), p * s);
    }
    EXPECT_TRUE(mat_near(scale(Vec3{-1, 2, -3}), glm::scale(k_glm_identity, glm::vec3(-1, 2, -3)), 0));
    EXPECT_EQ(scale(2.5f), scale(Vec3{2.5f, 2.5f, 2.5f}));
    EXPECT_EQ(transform_point(scale(Vec3{-1, 1, 1}), {3, 4, 5}), (Vec3{-3, 4, 5}));  // a mirror
}

// ---- rotations ---------------------------------------------------------------------------------------

TEST(Transform, AxisRotationsMatchGlmRotateWithUnitAxes) {
    Rng rng(303);
    for (int it = 0; it < 500; ++it) {
        float a = rng.uniform(-2 * k_pi, 2 * k_pi);
        EXPECT_TRUE(mat_near(rotate_x(a), glm::rotate(k_glm_identity, a, glm::vec3(1, 0, 0)), 1e-6f));
        EXPECT_TRUE(mat_near(rotate_y(a), glm::rotate(k_glm_identity, a, glm::vec3(0, 1, 0)), 1e-6f));
        EXPECT_TRUE(mat_near(rotate_z(a), glm::rotate(k_glm_identity, a, glm::vec3(0, 0, 1)), 1e-6f));
        EXPECT_TRUE(mat_near(rotate({1, 0, 0}, a), rotate_x(a), 1e-6f));
        EXPECT_TRUE(mat_near(rotate({0, 1, 0}, a), rotate_y(a), 1e-6f));
        EXPECT_TRUE(mat_near(rotate({0, 0, 1}, a), rotate_z(a), 1e-6f));
    }
}

TEST(Transform, AxisRotationsFollowTheRightHandRule) {
    const Vec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
    const float q = k_pi / 2;
    // A quarter turn about X takes +Y to +Z, about Y takes +Z to +X, about Z takes +X to +Y.
    EXPECT_TRUE(vec_near(transform_direction(rotate_x(q), y), z, 1e-6f));
    EXPECT_TRUE(vec_near(transform_direction(rotate_y(q), z), x, 1e-6f));
    EXPECT_TRUE(vec_near(transform_direction(rotate_z(q), x), y, 1e-6f));
    EXPECT_TRUE(vec_near(transform_direction(rotate_x(q), z), -y, 1e-6f));
    // 30 degrees about Z: (cos 30, sin 30) = (sqrt(3)/2, 1/2).
    EXPECT_TRUE(vec_near(transform_direction(rotate_z(k_pi / 6), x), Vec3{0.8660254f, 0.5f, 0}, 1e-6f));
    // The axis itself does not move.
    EXPECT_TRUE(vec_near(transform_direction(rotate_x(0.7f), x), x, 0));
    EXPECT_TRUE(vec_near(transform_direction(rotate_y(0.7f), y), y, 0));
    EXPECT_TRUE(vec_near(transform_direction(rotate_z(0.7f), z), z, 0));
}

TEST(Transform, ArbitraryAxisRotationMatchesGlmWithTheNormalizedAxis) {
    Rng rng(304);
    for (int it = 0; it < 1000; ++it) {
        Vec3 axis = rng.vec3(-10, 10);  // not unit length
        if (length(axis) < 0.1f) continue;
        float a = rng.uniform(-2 * k_pi, 2 * k_pi);
        Mat4 r = rotate(axis, a);
        EXPECT_TRUE(mat_near(r, glm::rotate(k_glm_identity, a, glm::normalize(to_glm(axis))), 1e-6f));
        // A rotation: orthonormal with determinant 1, fixes its axis, and the inverse is the
        // rotation by -a.
        EXPECT_TRUE(mat_near(r * transpose(r), Mat4::identity(), 1e-6f));
        EXPECT_TRUE(float_near(determinant(r), 1.0, 1e-6));
        EXPECT_TRUE(vec_near(transform_direction(r, axis), axis, 1e-6f));
        EXPECT_TRUE(mat_near(rotate(axis, a) * rotate(axis, -a), Mat4::identity(), 1e-6f));
        EXPECT_TRUE(mat_near(rotate(axis * 3.0f, a), r, 1e-6f));  // only the direction matters
        EXPECT_TRUE(mat_near(rotate(-axis, a), rotate(axis, -a), 1e-6f));
    }
}

TEST(Transform, RotateAboutZeroOrNonFiniteAxisIsIdentity) {
    EXPECT_EQ(rotate(Vec3{}, 1.0f), Mat4::identity());
    EXPECT_EQ(rotate(Vec3{0, 0, 0}, -2.5f), Mat4::identity());
    EXPECT_EQ(rotate(Vec3{k_nan, 0, 1}, 1.0f), Mat4::identity());
    EXPECT_EQ(rotate(Vec3{0, k_inf, 0}, 1.0f), Mat4::identity());
}

TEST(Transform, YawPitchRollMatchesGlm) {
    Rng rng(305);
    for (int it = 0; it < 1000; ++it) {
        float yaw = rng.uniform(-k_pi, k_pi), pitch = rng.uniform(-k_pi, k_pi), roll = rng.uniform(-k_pi, k_pi);
        Mat4 m = yaw_pitch_roll(yaw, pitch, roll);
        EXPECT_TRUE(mat_near(m, glm::yawPitchRoll(yaw, pitch, roll), 1e-6f));
        EXPECT_TRUE(mat_near(m, rotate_y(yaw) * rotate_x(pitch) * rotate_z(roll), 1e-6f));
    }
    // Hand-derived: yaw alone is a rotation about Y, pitch alone about X, roll alone about Z.
    EXPECT_TRUE(mat_near(yaw_pitch_roll(0.4f, 0, 0), rotate_y(0.4f), 1e-7f));
    EXPECT_TRUE(mat_near(yaw_pitch_roll(0, 0.4f, 0), rotate_x(0.4f), 1e-7f));
    EXPECT_TRUE(mat_near(yaw_pitch_roll(0, 0, 0.4f), rotate_z(0.4f), 1e-7f));
    // Roll is applied first: +X rolled a quarter turn becomes +Y, then pitching a quarter turn about X
    // takes +Y to +Z.
    EXPECT_TRUE(vec_near(transform_direction(yaw_pitch_roll(0, k_pi / 2, k_pi / 2), {1, 0, 0}), Vec3{0, 0, 1}, 1e-6f));
}

// ---- look-at -----------------------------------------------------------------------------------------

// Random eye, target and up with the view direction at least ~6 degrees from up (so the look-at is
// well defined and GLM, which has no fallback for the degenerate case, is a valid oracle).
struct LookAtCase {
    Vec3 eye, target, up;
};
LookAtCase random_look_at(Rng& rng, bool random_up) {
    for (;;) {
        LookAtCase c{rng.vec3(-20, 20), rng.vec3(-20, 20), random_up ? rng.vec3(-2, 2) : Vec3{0, 1, 0}};
        Vec3 d = c.target - c.eye;
        if (length(d) < 0.5f || length(c.up) < 0.1f) continue;
        if (length(cross(normalize(d), normalize(c.up))) < 0.1f) continue;
        return c;
    }
}

TEST(Transform, LookAtRhMatchesGlm) {
    Rng rng(306);
    for (int it = 0; it < 2000; ++it) {
        LookAtCase c = random_look_at(rng, it % 2 == 1);
        Mat4 v = look_at_rh(c.eye, c.target, c.up);
        EXPECT_TRUE(mat_near(v, glm::lookAtRH(to_glm(c.eye), to_glm(c.target), to_glm(c.up))));
        // The eye goes to the origin and the target onto -Z at its distance.
        float d = length(c.target - c.eye);
        EXPECT_TRUE(float_near(length(transform_point(v, c.eye)), 0, 1e-5, length(c.eye)));
        EXPECT_TRUE(float_near(length(transform_point(v, c.target) - Vec3{0, 0, -d}), 0, 1e-5, length(c.eye) + d));
    }
}

TEST(Transform, LookAtLhMatchesGlm) {
    Rng rng(307);
    for (int it = 0; it < 2000; ++it) {
        LookAtCase c = random_look_at(rng, it % 2 == 1);
        Mat4 v = look_at_lh(c.eye, c.target, c.up);
        EXPECT_TRUE(mat_near(v, glm::lookAtLH(to_glm(c.eye), to_glm(c.target), to_glm(c.up))));
        float d = length(c.target - c.eye);
        EXPECT_TRUE(float_near(length(transform_point(v, c.eye)), 0, 1e-5, length(c.eye)));
        EXPECT_TRUE(float_near(length(transform_point(v, c.target) - Vec3{0, 0, d}), 0, 1e-5, length(c.eye) + d));
    }
}

TEST(Transform, LookAtHandDerived) {
    // Eye on +Z looking at the origin: RH view is a plain translation by -eye.
    EXPECT_TRUE(mat_near(look_at_rh({0, 0, 5}, {0, 0, 0}, {0, 1, 0}), translate({0, 0, -5}), 0));
    // LH eye on -Z looking at the origin (toward +Z): also a plain translation.
    EXPECT_TRUE(mat_near(look_at_lh({0, 0, -5}, {0, 0, 0}, {0, 1, 0}), translate({0, 0, 5}), 0));
    // RH eye on +X looking at the origin: world -X is forward (view -Z), world -Z is to the right.
    Mat4 v = look_at_rh({3, 0, 0}, {0, 0, 0}, {0, 1, 0});
    EXPECT_TRUE(vec_near(transform_direction(v, {0, 0, -1}), Vec3{1, 0, 0}, 1e-7f));
    EXPECT_TRUE(vec_near(transform_direction(v, {0, 1, 0}), Vec3{0, 1, 0}, 1e-7f));
    EXPECT_TRUE(vec_near(transform_direction(v, {-1, 0, 0}), Vec3{0, 0, -1}, 1e-7f));
    // Only the part of `up` perpendicular to the view direction counts: looking along -X, the ups
    // (1, 1, 0) and (-2, 1, 0) differ from (0, 1, 0) only along X, so they give the same view.
    EXPECT_TRUE(mat_near(look_at_rh({3, 0, 0}, {0, 0, 0}, {1, 1, 0}), v, 1e-6f));
    EXPECT_TRUE(mat_near(look_at_rh({3, 0, 0}, {0, 0, 0}, {-2, 1, 0}), v, 1e-6f));
    EXPECT_TRUE(mat_near(look_at_rh({3, 0, 0}, {0, 0, 0}, {0, 5, 0}), v, 1e-6f));  // nor its length
}

// ---- projections ---------------------------------------------------------------------------------------

struct PerspectiveCase {
    float fovy, aspect, near, far;
};
PerspectiveCase random_perspective(Rng& rng) {
    float near = std::pow(10.0f, rng.uniform(-2, 1));
    return {rng.uniform(0.2f, 2.8f), rng.uniform(0.3f, 3), near, near * std::pow(10.0f, rng.uniform(0.3f, 4))};
}

TEST(Transform, PerspectiveMatchesGlm) {
    Rng rng(308);
    for (int it = 0; it < 1000; ++it) {
        PerspectiveCase p = random_perspective(rng);
        EXPECT_TRUE(mat_near(perspective_rh_zo(p.fovy, p.aspect, p.near, p.far),
                             glm::perspectiveRH_ZO(p.fovy, p.aspect, p.near, p.far)));
        EXPECT_TRUE(mat_near(perspective_lh_zo(p.fovy, p.aspect, p.near, p.far),
                             glm::perspectiveLH_ZO(p.fovy, p.aspect, p.near, p.far)));
    }
}

// Depth after the divide by w: 0 on the near plane, 1 on the far plane, w > 0 in front of the eye.
TEST(Transform, PerspectiveMapsNearToZeroAndFarToOne) {
    Rng rng(309);
    for (int it = 0; it < 1000; ++it) {
        PerspectiveCase p = random_perspective(rng);
        for (Handedness h : {Handedness::right, Handedness::left}) {
            Mat4 m = h == Handedness::right ? perspective_rh_zo(p.fovy, p.aspect, p.near, p.far)
                                            : perspective_lh_zo(p.fovy, p.aspect, p.near, p.far);
            float ahead = h == Handedness::right ? -1.0f : 1.0f;  // sign of z in front of the eye
            Vec2 xy = rng.vec2(-1, 1);
            std::optional<Vec4> n = homogenize(m * Vec4(xy.x * p.near, xy.y * p.near, ahead * p.near, 1));
            std::optional<Vec4> f = homogenize(m * Vec4(xy.x * p.far, xy.y * p.far, ahead * p.far, 1));
            ASSERT_TRUE(n && f);
            EXPECT_NEAR(n->z, 0.0f, 1e-5f);
            EXPECT_NEAR(f->z, 1.0f, 1e-5f);
            // w is the distance in front of the eye, so 1/w comes back in the w slot.
            EXPECT_TRUE(float_near(n->w, 1 / p.near, 1e-6));
            EXPECT_TRUE(float_near(f->w, 1 / p.far, 1e-6));
            // Anything in front has w > 0 and depth increasing with distance; behind has w < 0.
            float mid = std::sqrt(p.near * p.far);
            Vec4 c = m * Vec4(0.3f, -0.2f, ahead * mid, 1);
            EXPECT_GT(c.w, 0.0f);
            EXPECT_GT(c.z / c.w, 0.0f);
            EXPECT_LT(c.z / c.w, 1.0f);
            EXPECT_LT((m * Vec4(0, 0, -ahead * mid, 1)).w, 0.0f);
            EXPECT_FALSE(homogenize(m * Vec4(0, 0, -ahead * mid, 1)).has_value());
        }
    }
}

TEST(Transform, PerspectiveFrustumEdgesMapToNdcEdges) {
    const float fovy = radians(60.0f), aspect = 16.0f / 9.0f, near = 0.5f, far = 50.0f;
    const float half_h = std::tan(fovy / 2), half_w = half_h * aspect;
    for (Handedness h : {Handedness::right, Handedness::left}) {
        Mat4 m = h == Handedness::right ? perspective_rh_zo(fovy, aspect, near, far)
                                        : perspective_lh_zo(fovy, aspect, near, far);
        float ahead = h == Handedness::right ? -1.0f : 1.0f;
        for (float d : {near, 3.0f, far}) {
            // Top-right corner of the frustum cross-section at distance d is NDC (1, 1).
            std::optional<Vec4> tr = homogenize(m * Vec4(half_w * d, half_h * d, ahead * d, 1));
            std::optional<Vec4> bl = homogenize(m * Vec4(-half_w * d, -half_h * d, ahead * d, 1));
            ASSERT_TRUE(tr && bl);
            EXPECT_NEAR(tr->x, 1.0f, 1e-5f);
            EXPECT_NEAR(tr->y, 1.0f, 1e-5f);
            EXPECT_NEAR(bl->x, -1.0f, 1e-5f);
            EXPECT_NEAR(bl->y, -1.0f, 1e-5f);
        }
    }
}

TEST(Transform, OrthoMatchesGlm) {
    Rng rng(310);
    for (int it = 0; it < 1000; ++it) {
        float l = rng.uniform(-50, 10), r = l + rng.uniform(0.1f, 60);
        float b = rng.uniform(-50, 10), t = b + rng.uniform(0.1f, 60);
        float n = rng.uniform(-10, 10), f = n + rng.uniform(0.1f, 100);
        EXPECT_TRUE(mat_near(ortho_rh_zo(l, r, b, t, n, f), glm::orthoRH_ZO(l, r, b, t, n, f)));
        EXPECT_TRUE(mat_near(ortho_lh_zo(l, r, b, t, n, f), glm::orthoLH_ZO(l, r, b, t, n, f)));
    }
}

TEST(Transform, OrthoMapsTheBoxToTheNdcCube) {
    const float l = -3, r = 5, b = -1, t = 2, n = 1, f = 9;
    Mat4 rh = ortho_rh_zo(l, r, b, t, n, f), lh = ortho_lh_zo(l, r, b, t, n, f);
    // RH looks down -Z: the near plane is z = -n. LH: z = +n.
    EXPECT_TRUE(vec_near(rh * Vec4(l, b, -n, 1), Vec4{-1, -1, 0, 1}, 1e-6f));
    EXPECT_TRUE(vec_near(rh * Vec4(r, t, -f, 1), Vec4{1, 1, 1, 1}, 1e-6f));
    EXPECT_TRUE(vec_near(lh * Vec4(l, b, n, 1), Vec4{-1, -1, 0, 1}, 1e-6f));
    EXPECT_TRUE(vec_near(lh * Vec4(r, t, f, 1), Vec4{1, 1, 1, 1}, 1e-6f));
    // w stays 1: no perspective.
    EXPECT_EQ((rh * Vec4(2, 3, -4, 1)).w, 1.0f);
}

// ---- viewport ------------------------------------------------------------------------------------------

TEST(Transform, ViewportMapsNdcToPixelsWithYDown) {
    Rng rng(311);
    for (int it = 0; it < 200; ++it) {
        float x = rng.uniform(-100, 100), y = rng.uniform(-100, 100);
        float w = rng.uniform(1, 4000), h = rng.uniform(1, 4000);
        Mat4 v = viewport(x, y, w, h);
        // Pixel coordinates are sums of terms as large as |x| + w (the corner x is x + w/2 - w/2), so
        // that is the scale of their rounding error.
        auto expect_pixel = [&](Vec3 ndc, Vec3 expected) {
            Vec3 p = transform_point(v, ndc);
            EXPECT_TRUE(float_near(p.x, expected.x, 1e-6, std::fabs(x) + w)) << "ndc x " << ndc.x;
            EXPECT_TRUE(float_near(p.y, expected.y, 1e-6, std::fabs(y) + h)) << "ndc y " << ndc.y;
            EXPECT_EQ(p.z, expected.z);  // depth unchanged, exactly
        };
        for (float z : {0.0f, 0.25f, 1.0f}) {
            // NDC top-left (-1, 1) is the pixel corner (x, y); bottom-right (1, -1) is (x+w, y+h).
            expect_pixel({-1, 1, z}, {x, y, z});
            expect_pixel({1, -1, z}, {x + w, y + h, z});
            expect_pixel({0, 0, z}, {x + w / 2, y + h / 2, z});
            expect_pixel({-1, -1, z}, {x, y + h, z});
            expect_pixel({1, 1, z}, {x + w, y, z});
        }
        // It is affine: w passes through, so it commutes with the perspective divide.
        Vec4 clip{0.4f, -0.3f, 0.6f, 2.5f};
        Vec4 a = v * clip;
        EXPECT_EQ(a.w, clip.w);
        std::optional<Vec4> after = homogenize(a), before = homogenize(clip);
        ASSERT_TRUE(after && before);
        EXPECT_TRUE(vec_near(after->xyz(), transform_point(v, before->xyz()), 1e-6f));
        EXPECT_EQ(after->w, before->w);
    }
    // Hand-derived: 640x480 from the origin. NDC (0.5, 0.5) is 3/4 across and 1/4 down.
    EXPECT_EQ(transform_point(viewport(0, 0, 640, 480), {0.5f, 0.5f, 0.5f}), (Vec3{480, 120, 0.5f}));
}

}  // namespace
