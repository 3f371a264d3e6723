// Camera basis, Camera (view, roll, orbit, projection), homogenize and the cached TransformChain.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "facet/camera.hpp"
#include "support/glm_compare.hpp"

namespace {

using namespace facet;
using facet_test::all_finite;
using facet_test::float_near;
using facet_test::mat_near;
using facet_test::Rng;
using facet_test::to_glm;
using facet_test::vec_near;

constexpr float k_nan = std::numeric_limits<float>::quiet_NaN();
constexpr float k_inf = std::numeric_limits<float>::infinity();
constexpr Handedness k_both[] = {Handedness::right, Handedness::left};

const char* name(Handedness h) { return h == Handedness::right ? "RH" : "LH"; }

// ---- camera_basis -------------------------------------------------------------------------------------

// Unit, mutually perpendicular, finite, and with the orientation of the handedness: in RH view space
// (right, up, backward) is right-handed, so right x up = -forward; in LH, right x up = +forward.
::testing::AssertionResult orthonormal(const CameraBasis& b, Handedness h) {
    if (!is_finite(b.right) || !is_finite(b.up) || !is_finite(b.forward))
        return ::testing::AssertionFailure() << "non-finite basis";
    const double tol = 1e-6;
    for (Vec3 v : {b.right, b.up, b.forward})
        if (std::fabs(length(v) - 1) > tol) return ::testing::AssertionFailure() << "length " << length(v);
    if (std::fabs(dot(b.right, b.up)) > tol || std::fabs(dot(b.right, b.forward)) > tol ||
        std::fabs(dot(b.up, b.forward)) > tol)
        return ::testing::AssertionFailure() << "not perpendicular: " << dot(b.right, b.up) << " "
                                             << dot(b.right, b.forward) << " " << dot(b.up, b.forward);
    Vec3 expected = h == Handedness::right ? -b.forward : b.forward;
    if (length(cross(b.right, b.up) - expected) > 1e-5f) return ::testing::AssertionFailure() << "wrong orientation";
    return ::testing::AssertionSuccess();
}

TEST(CameraBasis, OrthonormalForRandomDirections) {
    Rng rng(501);
    for (int it = 0; it < 2000; ++it) {
        Vec3 f = rng.unit3() * rng.uniform(0.01f, 100);
        Vec3 up = it % 2 ? rng.unit3() * rng.uniform(0.01f, 100) : Vec3{0, 1, 0};
        if (length(cross(normalize(f), normalize(up))) < 0.01f) continue;
        for (Handedness h : k_both) {
            CameraBasis b = camera_basis(f, up, h);
            EXPECT_TRUE(orthonormal(b, h)) << name(h);
            EXPECT_TRUE(vec_near(b.forward, normalize(f), 1e-6f));
            // The requested up is in the (up, forward) plane and on the up side.
            EXPECT_NEAR(dot(b.right, normalize(up)), 0.0f, 1e-5f);
            EXPECT_GT(dot(b.up, up), 0.0f);
        }
    }
}

// At the poles cross(forward, up) vanishes: the basis must still be orthonormal and NaN-free, for
// forward exactly along +-up, within 1e-7 of it, and for ups that are not the Y axis.
TEST(CameraBasis, OrthonormalAtAndNearThePoles) {
    Rng rng(502);
    std::vector<Vec3> ups = {{0, 1, 0}, {0, -1, 0}, {1, 0, 0}, {0, 0, 1}, {0, 0, -1}, {0, 3, 0}};
    for (int i = 0; i < 20; ++i) ups.push_back(rng.unit3() * rng.uniform(0.1f, 10));
    for (Vec3 up : ups)
        for (float s : {1.0f, -1.0f})
            for (Handedness h : k_both) {
                Vec3 exact = normalize(up) * s;
                CameraBasis b = camera_basis(exact, up, h);
                EXPECT_TRUE(orthonormal(b, h)) << name(h);
                EXPECT_TRUE(vec_near(b.forward, exact, 1e-6f));
                for (int k = 0; k < 20; ++k) {
                    Vec3 nearly = exact * rng.uniform(0.5f, 2) + rng.vec3(-1e-7f, 1e-7f);
                    CameraBasis bn = camera_basis(nearly, up, h);
                    EXPECT_TRUE(orthonormal(bn, h)) << name(h);
                    EXPECT_TRUE(vec_near(bn.forward, normalize(nearly), 1e-6f));
                }
            }
}

TEST(CameraBasis, ZeroOrNonFiniteInputsStillGiveABasis) {
    for (Handedness h : k_both) {
        // No direction: the handedness' default view direction (RH -Z, LH +Z).
        CameraBasis b = camera_basis({0, 0, 0}, {0, 1, 0}, h);
        EXPECT_TRUE(orthonormal(b, h));
        EXPECT_TRUE(vec_near(b.forward, h == Handedness::right ? Vec3{0, 0, -1} : Vec3{0, 0, 1}, 0));
        EXPECT_TRUE(vec_near(b.up, Vec3{0, 1, 0}, 0));
        // No up: world +Y.
        Vec3 f{1, 2, -3};
        CameraBasis bu = camera_basis(f, {0, 0, 0}, h);
        EXPECT_TRUE(orthonormal(bu, h));
        CameraBasis by = camera_basis(f, {0, 1, 0}, h);
        EXPECT_TRUE(vec_near(bu.right, by.right, 0));
        EXPECT_TRUE(vec_near(bu.up, by.up, 0));
        EXPECT_TRUE(vec_near(bu.forward, by.forward, 0));
        // Neither.
        EXPECT_TRUE(orthonormal(camera_basis({0, 0, 0}, {0, 0, 0}, h), h));
        // Non-finite.
        EXPECT_TRUE(orthonormal(camera_basis({k_nan, 0, 1}, {0, 1, 0}, h), h));
        EXPECT_TRUE(orthonormal(camera_basis({0, k_inf, 0}, {0, 1, 0}, h), h));
        EXPECT_TRUE(orthonormal(camera_basis({1, 0, 0}, {k_nan, k_nan, k_nan}, h), h));
    }
}

// Looking straight up or down, the up vector is where the top of the image would be had the camera
// pitched there from its default view direction: RH (looks -Z) straight up has up +Z, LH (looks +Z,
// the seed) straight up has up -Z.
TEST(CameraBasis, PoleFallbackTiltsFromTheDefaultDirection) {
    EXPECT_TRUE(vec_near(camera_basis({0, 1, 0}, {0, 1, 0}, Handedness::right).up, Vec3{0, 0, 1}, 0));
    EXPECT_TRUE(vec_near(camera_basis({0, -1, 0}, {0, 1, 0}, Handedness::right).up, Vec3{0, 0, -1}, 0));
    EXPECT_TRUE(vec_near(camera_basis({0, 1, 0}, {0, 1, 0}, Handedness::left).up, Vec3{0, 0, -1}, 0));
    EXPECT_TRUE(vec_near(camera_basis({0, -1, 0}, {0, 1, 0}, Handedness::left).up, Vec3{0, 0, 1}, 0));
    // Continuity from the default side: pitching up from the default direction to 0.01 rad short of
    // vertical (outside the fallback, whose threshold is 1e-3) gives an up vector within that same
    // 0.01 rad of the fallback's, not the opposite one.
    for (Handedness h : k_both) {
        float d = h == Handedness::right ? -1.0f : 1.0f;
        Vec3 almost{0, std::cos(0.01f), d * std::sin(0.01f)};
        Vec3 up_almost = camera_basis(almost, {0, 1, 0}, h).up;
        Vec3 up_pole = camera_basis({0, 1, 0}, {0, 1, 0}, h).up;
        EXPECT_NEAR(std::acos(std::min(1.0f, dot(up_almost, up_pole))), 0.01f, 1e-4f) << name(h);
    }
}

// ---- Camera::view ---------------------------------------------------------------------------------------

TEST(CameraView, EqualsLookAt) {
    Rng rng(503);
    for (int it = 0; it < 500; ++it) {
        Camera c;
        c.position = rng.vec3(-20, 20);
        c.target = rng.vec3(-20, 20);
        if (length(cross(normalize(c.target - c.position), c.up)) < 0.01f) continue;
        EXPECT_TRUE(mat_near(c.view(), look_at_rh(c.position, c.target, c.up), 0));
        EXPECT_TRUE(mat_near(c.view(), glm::lookAtRH(to_glm(c.position), to_glm(c.target), to_glm(c.up))));
        c.handedness = Handedness::left;
        EXPECT_TRUE(mat_near(c.view(), look_at_lh(c.position, c.target, c.up), 0));
        EXPECT_TRUE(mat_near(c.view(), glm::lookAtLH(to_glm(c.position), to_glm(c.target), to_glm(c.up))));
    }
}

TEST(CameraView, StraightUpAndDownHasNoNaNAndLooksAtTheTarget) {
    for (Handedness h : k_both)
        for (float s : {1.0f, -1.0f}) {
            Camera c;
            c.handedness = h;
            c.position = {1, 2, 3};
            c.target = c.position + Vec3{0, 7 * s, 0};
            Mat4 v = c.view();
            EXPECT_TRUE(all_finite(v)) << name(h) << " " << s;
            // The eye at the origin, the target on the view axis 7 units ahead.
            EXPECT_LT(length(transform_point(v, c.position)), 1e-5f);
            Vec3 t = transform_point(v, c.target);
            EXPECT_NEAR(t.x, 0.0f, 1e-5f);
            EXPECT_NEAR(t.y, 0.0f, 1e-5f);
            EXPECT_NEAR(t.z, h == Handedness::right ? -7.0f : 7.0f, 1e-5f);
            // A rigid motion: orthonormal rotation part with determinant +1.
            EXPECT_TRUE(mat_near(v.upper3x3() * transpose(v.upper3x3()), Mat3::identity(), 1e-6f));
            EXPECT_NEAR(determinant(v), 1.0f, 1e-6f);
        }
}

// Screen position, in pixels with y down, of a world point seen by `cam` on a 200 x 200 viewport.
Vec2 on_screen(const Camera& cam, Vec3 p) {
    std::optional<Vec4> s = homogenize(viewport(0, 0, 200, 200) * cam.projection(1.0f) * cam.view() * Vec4(p, 1));
    EXPECT_TRUE(s.has_value());
    return s ? Vec2{s->x, s->y} : Vec2{k_nan, k_nan};
}
// Angle of a screen point about the centre, measured with y down: increasing = clockwise as seen.
float screen_angle(Vec2 s) { return std::atan2(s.y - 100, s.x - 100); }

// A positive roll turns the image clockwise as seen by the viewer: a point to the right of centre
// moves down, a point above centre moves right, and every point turns about the centre by the roll.
TEST(CameraRoll, PositiveRollTurnsTheImageClockwise) {
    for (Handedness h : k_both)
        for (ProjectionKind kind : {ProjectionKind::perspective, ProjectionKind::orthographic}) {
            Camera cam;
            cam.handedness = h;
            cam.projection_kind = kind;
            cam.ortho_height = 4;
            cam.position = {1, 2, 3};
            cam.target = {-2, 0.5f, -4};
            CameraBasis b = camera_basis(cam.target - cam.position, cam.up, h);
            Vec3 ahead = cam.position + b.forward * 5.0f;
            Vec3 right_pt = ahead + b.right * 1.0f, up_pt = ahead + b.up * 1.0f;

            // No roll: right is right on screen, up is up (smaller y).
            Vec2 r0 = on_screen(cam, right_pt), u0 = on_screen(cam, up_pt);
            EXPECT_GT(r0.x, 110.0f) << name(h);
            EXPECT_NEAR(r0.y, 100.0f, 1e-3f) << name(h);
            EXPECT_NEAR(u0.x, 100.0f, 1e-3f) << name(h);
            EXPECT_LT(u0.y, 90.0f) << name(h);

            cam.roll = 0.2f;
            Vec2 r1 = on_screen(cam, right_pt), u1 = on_screen(cam, up_pt);
            EXPECT_GT(r1.y, r0.y + 1) << name(h) << ": the point right of centre must move down";
            EXPECT_GT(u1.x, u0.x + 1) << name(h) << ": the point above centre must move right";

            for (float roll : {0.2f, 1.0f, -0.5f, 2.5f}) {
                cam.roll = roll;
                for (Vec3 p : {right_pt, up_pt, ahead + b.right * 0.7f - b.up * 0.4f}) {
                    cam.roll = 0;
                    Vec2 before = on_screen(cam, p);
                    cam.roll = roll;
                    Vec2 after = on_screen(cam, p);
                    float turned = std::remainder(screen_angle(after) - screen_angle(before), 2 * k_pi);
                    EXPECT_NEAR(turned, roll, 1e-4f) << name(h) << " roll " << roll;
                    // Turning keeps the distance from the centre (square pixels, aspect 1).
                    EXPECT_NEAR(length(after - Vec2{100, 100}), length(before - Vec2{100, 100}), 1e-3f);
                }
            }
        }
}

// ---- Camera constructors --------------------------------------------------------------------------------

TEST(CameraOrbit, PlacesTheEyeOnTheSphereAndLooksAtTheTarget) {
    const Vec3 t{1, -2, 3};
    // Hand-derived: azimuth 0 is +Z, azimuth 90 degrees is +X, elevation 90 degrees is straight above.
    EXPECT_TRUE(vec_near(Camera::orbit(t, 0, 0, 4).position, t + Vec3{0, 0, 4}, 1e-6f));
    EXPECT_TRUE(vec_near(Camera::orbit(t, k_pi / 2, 0, 4).position, t + Vec3{4, 0, 0}, 1e-6f));
    EXPECT_TRUE(vec_near(Camera::orbit(t, 0, k_pi / 2, 4).position, t + Vec3{0, 4, 0}, 1e-6f));
    EXPECT_TRUE(vec_near(Camera::orbit(t, k_pi, 0, 4).position, t + Vec3{0, 0, -4}, 1e-6f));

    Rng rng(504);
    for (int it = 0; it < 500; ++it) {
        Vec3 target = rng.vec3(-10, 10);
        float az = rng.uniform(-k_pi, k_pi), el = rng.uniform(-1.5f, 1.5f), d = rng.uniform(0.5f, 50);
        Camera c = Camera::orbit(target, az, el, d);
        Vec3 expected = target + d * Vec3{std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az)};
        EXPECT_TRUE(vec_near(c.position, expected, 1e-6f));
        EXPECT_EQ(c.target, target);
        EXPECT_TRUE(float_near(length(c.position - target), d, 1e-5));
        // The target sits on the view axis, d ahead (RH: -Z).
        Vec3 v = transform_point(c.view(), target);
        EXPECT_TRUE(float_near(length(v - Vec3{0, 0, -d}), 0, 1e-5, d + length(target)));
    }
}

TEST(CameraLooking, LooksAlongTheDirection) {
    Camera c = Camera::looking({1, 2, 3}, {0, 0, -2}, 0.3f);
    EXPECT_EQ(c.position, (Vec3{1, 2, 3}));
    EXPECT_EQ(c.target, (Vec3{1, 2, 1}));
    EXPECT_EQ(c.roll, 0.3f);
    EXPECT_TRUE(vec_near(c.forward(), Vec3{0, 0, -1}, 0));
    // Roll only turns about the view axis: the target stays on it.
    Vec3 t = transform_point(c.view(), c.target);
    EXPECT_NEAR(t.x, 0.0f, 1e-6f);
    EXPECT_NEAR(t.y, 0.0f, 1e-6f);
    EXPECT_NEAR(t.z, -2.0f, 1e-6f);
}

TEST(CameraProjection, MatchesGlm) {
    Rng rng(505);
    for (int it = 0; it < 500; ++it) {
        Camera c;
        c.fovy = rng.uniform(0.2f, 2.8f);
        c.near = rng.uniform(0.01f, 5);
        c.far = c.near + rng.uniform(1, 1000);
        c.ortho_height = rng.uniform(0.1f, 100);
        float aspect = rng.uniform(0.3f, 3);
        float h = c.ortho_height / 2, w = h * aspect;

        c.handedness = Handedness::right;
        c.projection_kind = ProjectionKind::perspective;
        EXPECT_TRUE(mat_near(c.projection(aspect), glm::perspectiveRH_ZO(c.fovy, aspect, c.near, c.far)));
        c.projection_kind = ProjectionKind::orthographic;
        EXPECT_TRUE(mat_near(c.projection(aspect), glm::orthoRH_ZO(-w, w, -h, h, c.near, c.far)));

        c.handedness = Handedness::left;
        c.projection_kind = ProjectionKind::perspective;
        EXPECT_TRUE(mat_near(c.projection(aspect), glm::perspectiveLH_ZO(c.fovy, aspect, c.near, c.far)));
        c.projection_kind = ProjectionKind::orthographic;
        EXPECT_TRUE(mat_near(c.projection(aspect), glm::orthoLH_ZO(-w, w, -h, h, c.near, c.far)));
    }
}

TEST(CameraProjection, OrthographicViewVolumeIsOrthoHeightTall) {
    Camera c;
    c.projection_kind = ProjectionKind::orthographic;
    c.ortho_height = 6;
    c.near = 1;
    c.far = 11;
    // RH: the top-right of the box at aspect 2 is (6, 3) and the far plane is z = -11.
    EXPECT_TRUE(vec_near(c.projection(2) * Vec4(6, 3, -11, 1), Vec4{1, 1, 1, 1}, 1e-6f));
    EXPECT_TRUE(vec_near(c.projection(2) * Vec4(-6, -3, -1, 1), Vec4{-1, -1, 0, 1}, 1e-6f));
}

// ---- homogenize ---------------------------------------------------------------------------------------

TEST(Homogenize, DividesByWAndKeepsItsReciprocal) {
    std::optional<Vec4> h = homogenize({2, 4, 6, 2});
    ASSERT_TRUE(h.has_value());
    EXPECT_EQ(*h, (Vec4{1, 2, 3, 0.5f}));
    Rng rng(506);
    for (int it = 0; it < 500; ++it) {
        Vec4 p(rng.vec3(-100, 100), rng.uniform(1e-3f, 1e3f));
        std::optional<Vec4> r = homogenize(p);
        ASSERT_TRUE(r.has_value());
        EXPECT_TRUE(float_near(r->x, double(p.x) / p.w, 1e-6));
        EXPECT_TRUE(float_near(r->y, double(p.y) / p.w, 1e-6));
        EXPECT_TRUE(float_near(r->z, double(p.z) / p.w, 1e-6));
        EXPECT_TRUE(float_near(r->w, 1.0 / p.w, 1e-6));
    }
}

TEST(Homogenize, RejectsPointsBehindTheEyeAndNonFiniteInput) {
    for (float w : {0.0f, -0.0f, -1.0f, -1e-30f, -k_inf, k_inf, k_nan})
        EXPECT_FALSE(homogenize({1, 2, 3, w}).has_value()) << "w = " << w;
    for (int i = 0; i < 3; ++i)
        for (float bad : {k_nan, k_inf, -k_inf}) {
            Vec4 p{1, 2, 3, 1};
            p[static_cast<std::size_t>(i)] = bad;
            EXPECT_FALSE(homogenize(p).has_value()) << "component " << i << " = " << bad;
        }
    EXPECT_TRUE(homogenize({0, 0, 0, 1e-20f}).has_value());  // tiny but positive is in front
}

// ---- TransformChain -------------------------------------------------------------------------------------

struct ChainMatrices {
    Mat4 world, view, projection, port;
};
ChainMatrices random_chain(Rng& rng) {
    return {translate(rng.vec3(-10, 10)) * rotate(rng.unit3(), rng.uniform(-3, 3)) * scale(rng.uniform(0.5f, 2)),
            look_at_rh(rng.vec3(-20, 20), rng.vec3(-1, 1), {0, 1, 0}),
            perspective_rh_zo(rng.uniform(0.5f, 2), rng.uniform(0.5f, 2), 0.1f, 100),
            viewport(0, 0, rng.uniform(100, 2000), rng.uniform(100, 2000))};
}

TEST(TransformChain, DefaultIsIdentity) {
    TransformChain chain;
    EXPECT_EQ(chain.world(), Mat4::identity());
    EXPECT_EQ(chain.clip_from_world(), Mat4::identity());
    EXPECT_EQ(chain.clip_from_object(), Mat4::identity());
    EXPECT_EQ(chain.screen_from_object(), Mat4::identity());
}

TEST(TransformChain, ProductsMatchTheirDefinitions) {
    Rng rng(507);
    for (int it = 0; it < 200; ++it) {
        ChainMatrices m = random_chain(rng);
        TransformChain chain;
        chain.set_world(m.world);
        chain.set_view(m.view);
        chain.set_projection(m.projection);
        chain.set_viewport(m.port);
        EXPECT_EQ(chain.world(), m.world);
        EXPECT_EQ(chain.view(), m.view);
        EXPECT_EQ(chain.projection(), m.projection);
        EXPECT_EQ(chain.viewport(), m.port);
        glm::mat4 w = to_glm(m.world), v = to_glm(m.view), p = to_glm(m.projection), vp = to_glm(m.port);
        EXPECT_TRUE(mat_near(chain.clip_from_world(), p * v));
        EXPECT_TRUE(mat_near(chain.clip_from_object(), p * v * w));
        EXPECT_TRUE(mat_near(chain.screen_from_object(), vp * p * v * w));
        // After changing each input, the products follow.
        ChainMatrices n = random_chain(rng);
        chain.set_world(n.world);
        EXPECT_TRUE(mat_near(chain.screen_from_object(), vp * p * v * to_glm(n.world)));
        chain.set_view(n.view);
        EXPECT_TRUE(mat_near(chain.clip_from_object(), p * to_glm(n.view) * to_glm(n.world)));
        chain.set_projection(n.projection);
        EXPECT_TRUE(mat_near(chain.clip_from_world(), to_glm(n.projection) * to_glm(n.view)));
        EXPECT_TRUE(mat_near(chain.screen_from_object(), vp * to_glm(n.projection) * to_glm(n.view) * to_glm(n.world)));
        chain.set_viewport(n.port);
        EXPECT_TRUE(mat_near(chain.screen_from_object(),
                             to_glm(n.port) * to_glm(n.projection) * to_glm(n.view) * to_glm(n.world)));
    }
}

TEST(TransformChain, CachesProducts) {
    Rng rng(508);
    ChainMatrices m = random_chain(rng), n = random_chain(rng);
    TransformChain chain;
    chain.set_world(m.world);
    chain.set_view(m.view);
    chain.set_projection(m.projection);
    chain.set_viewport(m.port);
    EXPECT_EQ(chain.products_computed(), 0) << "setting computes nothing";

    chain.screen_from_object();  // projection*view, then *world, then viewport*
    EXPECT_EQ(chain.products_computed(), 3);
    chain.screen_from_object();
    chain.clip_from_object();
    chain.clip_from_world();
    EXPECT_EQ(chain.products_computed(), 3) << "reading again computes nothing";

    // Moving the object: clip_from_world is reused, one product for clip_from_object.
    chain.set_world(n.world);
    chain.clip_from_world();
    EXPECT_EQ(chain.products_computed(), 3);
    EXPECT_TRUE(mat_near(chain.clip_from_object(), to_glm(m.projection) * to_glm(m.view) * to_glm(n.world)));
    EXPECT_EQ(chain.products_computed(), 4);
    chain.screen_from_object();  // one more: viewport * clip_from_object
    EXPECT_EQ(chain.products_computed(), 5);
    // Setting the world twice before reading still costs one product.
    chain.set_world(m.world);
    chain.set_world(n.world);
    chain.clip_from_object();
    chain.clip_from_object();
    EXPECT_EQ(chain.products_computed(), 6);

    chain.screen_from_object();
    EXPECT_EQ(chain.products_computed(), 7);

    // The viewport only affects the screen matrix (which was up to date before it changed).
    chain.set_viewport(n.port);
    chain.clip_from_object();
    EXPECT_EQ(chain.products_computed(), 7);
    EXPECT_TRUE(mat_near(chain.screen_from_object(),
                         to_glm(n.port) * to_glm(m.projection) * to_glm(m.view) * to_glm(n.world)));
    EXPECT_EQ(chain.products_computed(), 8);

    // Moving the camera recomputes the view-projection too.
    chain.set_view(n.view);
    EXPECT_TRUE(mat_near(chain.clip_from_object(), to_glm(m.projection) * to_glm(n.view) * to_glm(n.world)));
    EXPECT_EQ(chain.products_computed(), 10);
    chain.screen_from_object();
    EXPECT_EQ(chain.products_computed(), 11);

    // So does a new projection, and then everything downstream.
    chain.set_projection(n.projection);
    EXPECT_TRUE(mat_near(chain.screen_from_object(),
                         to_glm(n.port) * to_glm(n.projection) * to_glm(n.view) * to_glm(n.world)));
    EXPECT_EQ(chain.products_computed(), 14);
    chain.screen_from_object();
    EXPECT_EQ(chain.products_computed(), 14);
}

}  // namespace
