// facet view's input logic without a window: orbit, pan, zoom, fit, reset, presets, toggles, spin,
// the initial view and the up-axis re-orientation.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "facet/scene.hpp"
#include "view_state.hpp"

namespace {

using namespace facet;
using namespace facet::viewer;

void expect_near(Vec3 a, Vec3 b, float tolerance, const char* what) {
    EXPECT_NEAR(a.x, b.x, tolerance) << what;
    EXPECT_NEAR(a.y, b.y, tolerance) << what;
    EXPECT_NEAR(a.z, b.z, tolerance) << what;
}

// A state looking at a sphere of radius 2 about (1, 2, 3) through a 400x300 window.
ViewState make_state() {
    ViewState s;
    s.set_viewport(400, 300);
    s.set_scene_bounds({1, 2, 3}, 2);
    s.set_initial(Orbit{{1, 2, 3}, radians(30), radians(20), 10});
    return s;
}

// Where a world point lands on the screen, in pixels from the top-left.
Vec2 project(const ViewState& s, int width, int height, Vec3 p) {
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    const Camera c = s.camera(aspect);
    const Vec4 clip = c.projection(aspect) * c.view() * Vec4(p, 1);
    return {(clip.x / clip.w * 0.5f + 0.5f) * width, (0.5f - clip.y / clip.w * 0.5f) * height};
}

TEST(ViewState, LeftDragOrbitsByTheDocumentedRate) {
    ViewState s = make_state();
    EXPECT_TRUE(s.on_drag(10, -5, MouseButton::left));
    EXPECT_NEAR(s.orbit().azimuth, radians(30) - 10 * k_orbit_radians_per_pixel, 1e-6f);
    EXPECT_NEAR(s.orbit().elevation, radians(20) - 5 * k_orbit_radians_per_pixel, 1e-6f);
    EXPECT_EQ(s.orbit().distance, 10);
    expect_near(s.orbit().target, {1, 2, 3}, 0, "orbiting keeps the target");
    EXPECT_NEAR(k_orbit_radians_per_pixel, radians(0.4f), 1e-7f);
    // Dragging right turns the model right: the eye moves toward -X when looking from +Z.
    ViewState front = make_state();
    front.set_orbit(Orbit{{0, 0, 0}, 0, 0, 5});
    front.on_drag(20, 0, MouseButton::left);
    EXPECT_LT(front.camera(4.0f / 3).position.x, 0);
    // Dragging down shows more of the top.
    front.on_drag(0, 20, MouseButton::left);
    EXPECT_GT(front.camera(4.0f / 3).position.y, 0);
    EXPECT_FALSE(front.on_drag(0, 0, MouseButton::left));
    EXPECT_FALSE(front.on_drag(NAN, 1, MouseButton::left));
}

TEST(ViewState, ElevationClampsShortOfThePoles) {
    ViewState s = make_state();
    s.on_drag(0, 100000, MouseButton::left);
    EXPECT_FLOAT_EQ(s.orbit().elevation, k_max_elevation);
    EXPECT_LT(s.orbit().elevation, radians(90));
    Camera c = s.camera(s.aspect());
    EXPECT_TRUE(is_finite(c.position));
    EXPECT_GT(std::abs(c.position.z - 3) + std::abs(c.position.x - 1), 0.01f);  // not straight above
    s.on_drag(0, -300000, MouseButton::left);
    EXPECT_FLOAT_EQ(s.orbit().elevation, -k_max_elevation);
}

TEST(ViewState, AzimuthWrapsAround) {
    ViewState s = make_state();
    for (int i = 0; i < 100; ++i) s.on_drag(-777, 0, MouseButton::left);
    EXPECT_LE(std::abs(s.orbit().azimuth), k_pi + 1e-6f);
    const float expected = std::remainder(radians(30) + 100 * 777 * k_orbit_radians_per_pixel, 2 * k_pi);
    EXPECT_NEAR(std::cos(s.orbit().azimuth), std::cos(expected), 1e-3f);
    EXPECT_NEAR(std::sin(s.orbit().azimuth), std::sin(expected), 1e-3f);
}

TEST(ViewState, PanKeepsThePointUnderTheCursor) {
    for (bool ortho : {false, true}) {
        ViewState s = make_state();
        s.toggles().orthographic = ortho;
        const Orbit before = s.orbit();
        const Vec2 centre = project(s, 400, 300, before.target);
        EXPECT_NEAR(centre.x, 200, 1e-3f);
        EXPECT_NEAR(centre.y, 150, 1e-3f);
        for (MouseButton b : {MouseButton::right, MouseButton::middle}) {
            const Vec3 old_target = s.orbit().target;
            const Vec2 old_screen = project(s, 400, 300, old_target);
            EXPECT_TRUE(s.on_drag(30, -12, b));
            // The old target moved with the mouse: 30 px right, 12 px up.
            const Vec2 moved = project(s, 400, 300, old_target);
            EXPECT_NEAR(moved.x, old_screen.x + 30, 0.02f) << "ortho " << ortho;
            EXPECT_NEAR(moved.y, old_screen.y - 12, 0.02f) << "ortho " << ortho;
            // In the camera plane: the angles and distance stay, the target moves across the view.
            EXPECT_EQ(s.orbit().azimuth, before.azimuth);
            EXPECT_EQ(s.orbit().elevation, before.elevation);
            EXPECT_EQ(s.orbit().distance, before.distance);
            const Camera c = s.camera(s.aspect());
            const Vec3 delta = s.orbit().target - old_target;
            EXPECT_GT(length(delta), 0.01f);
            EXPECT_NEAR(dot(delta, c.forward()), 0, 1e-4f);
        }
    }
}

TEST(ViewState, WheelZoomsMultiplicativelyAndStaysPositive) {
    ViewState s = make_state();
    EXPECT_TRUE(s.on_wheel(1));
    EXPECT_FLOAT_EQ(s.orbit().distance, 10 * k_zoom_per_step);
    EXPECT_TRUE(s.on_wheel(-3));
    EXPECT_NEAR(s.orbit().distance, 10 / (k_zoom_per_step * k_zoom_per_step), 1e-4f);
    EXPECT_FALSE(s.on_wheel(0));
    EXPECT_FALSE(s.on_wheel(NAN));
    for (int i = 0; i < 10000; ++i) s.on_wheel(5);
    EXPECT_GT(s.orbit().distance, 0);
    EXPECT_TRUE(std::isfinite(s.orbit().distance));
    const Camera near_cam = s.camera(s.aspect());
    EXPECT_GT(near_cam.near, 0);
    EXPECT_LT(near_cam.near, near_cam.far);
    for (int i = 0; i < 10000; ++i) s.on_wheel(-5);
    EXPECT_TRUE(std::isfinite(s.orbit().distance));
    EXPECT_TRUE(is_finite(s.camera(s.aspect()).position));
    // Zooming in an orthographic view shrinks the view volume.
    ViewState o = make_state();
    o.toggles().orthographic = true;
    const float h0 = o.camera(o.aspect()).ortho_height;
    o.on_wheel(2);
    EXPECT_NEAR(o.camera(o.aspect()).ortho_height, h0 * k_zoom_per_step * k_zoom_per_step, 1e-4f);
}

TEST(ViewState, FitIsTheFramingRule) {
    const Scene scene = default_scene();
    for (auto [w, h] : {std::pair{640, 480}, std::pair{300, 600}}) {
        ViewState s;
        s.set_viewport(w, h);
        s.set_fovy(radians(45));
        s.set_scene_bounds(scene);
        s.set_initial(Orbit{{9, 9, 9}, 1.0f, 0.5f, 100});
        s.on_drag(3, 4, MouseButton::right);
        EXPECT_TRUE(s.on_key('f'));
        const float aspect = static_cast<float>(w) / static_cast<float>(h);
        const float az = 1.0f, el = 0.5f;
        const Camera expected = frame_scene(scene, az, el, radians(45), aspect);
        const Camera c = s.camera(aspect);
        expect_near(c.target, expected.target, 1e-5f, "target");
        expect_near(c.position, expected.position, 1e-4f, "eye");
        EXPECT_NEAR(c.near, expected.near, 1e-4f);
        EXPECT_NEAR(c.far, expected.far, 1e-4f);
        EXPECT_EQ(c.fovy, expected.fovy);
    }
}

TEST(ViewState, OrthographicAtTheFittedDistanceMatchesMakeCamera) {
    const Scene scene = default_scene();
    for (auto [w, h] : {std::pair{640, 480}, std::pair{300, 600}}) {
        ViewSpec spec;
        spec.orthographic = true;
        spec.azimuth = 0.3f;
        spec.elevation = 0.2f;
        ViewState s;
        s.set_viewport(w, h);
        init_view(s, scene, spec, false);
        const float aspect = static_cast<float>(w) / static_cast<float>(h);
        const Camera expected = make_camera(scene, spec, aspect);
        const Camera c = s.camera(aspect);
        EXPECT_EQ(c.projection_kind, ProjectionKind::orthographic);
        EXPECT_NEAR(c.ortho_height, expected.ortho_height, 1e-4f);
        expect_near(c.position, expected.position, 1e-4f, "eye");
    }
}

TEST(ViewState, ResetRestoresTheInitialView) {
    ViewState s = make_state();
    const Orbit initial = s.orbit();
    s.on_drag(40, 30, MouseButton::left);
    s.on_drag(10, 10, MouseButton::right);
    s.on_wheel(3);
    s.on_key('3');
    ASSERT_NE(s.orbit(), initial);
    EXPECT_TRUE(s.on_key('r'));
    EXPECT_EQ(s.orbit(), initial);
}

TEST(ViewState, PresetsGiveTheDocumentedAnglesAndFit) {
    struct Expect {
        char key;
        float az, el;  // degrees
    };
    for (Expect e : {Expect{'1', 0, 0}, Expect{'2', 90, 0}, Expect{'3', 0, 89}, Expect{'4', 45, 35.264f},
                     Expect{'5', 180, 0}, Expect{'6', -90, 0}, Expect{'7', 0, -89}}) {
        ViewState s = make_state();
        s.on_drag(5, 5, MouseButton::right);
        EXPECT_TRUE(s.on_key(e.key)) << e.key;
        EXPECT_NEAR(s.orbit().azimuth, radians(e.az), 1e-6f) << e.key;
        EXPECT_NEAR(s.orbit().elevation, radians(e.el), 1e-6f) << e.key;
        EXPECT_EQ(s.orbit(), s.fitted(s.orbit().azimuth, s.orbit().elevation)) << e.key;
    }
    // Where the eye is, relative to the scene centre (1, 2, 3).
    ViewState s = make_state();
    s.on_key('1');
    Vec3 d = normalize(s.camera(s.aspect()).position - Vec3{1, 2, 3});
    expect_near(d, {0, 0, 1}, 1e-5f, "front looks from +Z");
    s.on_key('2');
    d = normalize(s.camera(s.aspect()).position - Vec3{1, 2, 3});
    expect_near(d, {1, 0, 0}, 1e-5f, "right looks from +X");
    s.on_key('3');
    d = normalize(s.camera(s.aspect()).position - Vec3{1, 2, 3});
    EXPECT_GT(d.y, 0.999f) << "top looks from +Y";
    s.on_key('4');
    d = normalize(s.camera(s.aspect()).position - Vec3{1, 2, 3});
    expect_near(d, normalize(Vec3{1, 1, 1}), 1e-4f, "iso looks along the cube diagonal");
}

TEST(ViewState, ShadingKeyCyclesThroughEveryMode) {
    ViewState s = make_state();
    std::set<Shading> seen;
    EXPECT_EQ(s.toggles().shading, Shading::lit);
    for (int i = 0; i < 7; ++i) {
        seen.insert(s.toggles().shading);
        EXPECT_TRUE(s.on_key('m'));
    }
    EXPECT_EQ(seen.size(), 7u);
    EXPECT_EQ(s.toggles().shading, Shading::lit);
    s.on_key('m');
    EXPECT_EQ(s.toggles().shading, Shading::flat);
}

TEST(ViewState, KeysFlipTheirToggles) {
    ViewState s = make_state();
    const Toggles start = s.toggles();
    struct Flip {
        char key;
        bool (*get)(const Toggles&);
    };
    const Flip flips[] = {
        {'w', [](const Toggles& t) { return t.wireframe; }},       {'c', [](const Toggles& t) { return t.cull_back; }},
        {' ', [](const Toggles& t) { return t.spin; }},            {'h', [](const Toggles& t) { return t.overlay; }},
        {'p', [](const Toggles& t) { return t.orthographic; }},    {'a', [](const Toggles& t) { return t.ssaa == 2; }},
        {'u', [](const Toggles& t) { return t.up_axis == UpAxis::z; }},
    };
    for (const Flip& f : flips) {
        const bool before = f.get(s.toggles());
        EXPECT_TRUE(s.on_key(f.key)) << f.key;
        EXPECT_NE(f.get(s.toggles()), before) << f.key;
        s.on_key(f.key);
        EXPECT_EQ(f.get(s.toggles()), before) << f.key;
    }
    EXPECT_EQ(s.toggles(), start);
    // A supersampling start above 2 toggles to 1 and then to 2.
    s.toggles().ssaa = 4;
    s.on_key('a');
    EXPECT_EQ(s.toggles().ssaa, 1);
    s.on_key('a');
    EXPECT_EQ(s.toggles().ssaa, 2);
    // Unknown keys change nothing.
    const Orbit orbit = s.orbit();
    const Toggles toggles = s.toggles();
    for (char k : {'x', 'z', '0', '9', 'Q', '\0'}) EXPECT_FALSE(s.on_key(k)) << k;
    EXPECT_EQ(s.orbit(), orbit);
    EXPECT_EQ(s.toggles(), toggles);
}

TEST(ViewState, SpinAdvancesTheAzimuthWithTime) {
    ViewState s = make_state();
    EXPECT_FALSE(s.advance(1.0));
    EXPECT_EQ(s.orbit().azimuth, radians(30));
    s.on_key(' ');
    EXPECT_TRUE(s.advance(0.5));
    EXPECT_NEAR(s.orbit().azimuth, radians(30) + 0.5f * k_spin_radians_per_second, 1e-6f);
    EXPECT_FALSE(s.advance(0));
    EXPECT_FALSE(s.advance(-1));
    EXPECT_EQ(s.orbit().elevation, radians(20));
}

TEST(ViewState, InitialViewMatchesWhatFacetRenderShows) {
    const Scene scene = default_scene();
    // The default scene's designed camera.
    ViewState d;
    d.set_viewport(800, 600);
    init_view(d, scene, ViewSpec{}, true);
    const Camera designed = default_scene_camera(800.0f / 600.0f);
    const Camera c = d.camera(800.0f / 600.0f);
    expect_near(c.position, designed.position, 1e-4f, "designed eye");
    expect_near(c.target, designed.target, 1e-6f, "designed target");
    EXPECT_EQ(c.fovy, designed.fovy);
    // The framing rule at --azimuth/--elevation, and an explicit eye and target.
    ViewSpec spec;
    spec.azimuth = radians(-40);
    spec.elevation = radians(15);
    spec.fovy = radians(30);
    ViewState f;
    f.set_viewport(640, 480);
    init_view(f, scene, spec, false);
    const Camera framed = make_camera(scene, spec, 640.0f / 480.0f);
    expect_near(f.camera(f.aspect()).position, framed.position, 1e-4f, "framed eye");
    spec.eye = Vec3{3, 4, 5};
    spec.target = Vec3{0, 1, 0};
    spec.near = 0.25f;
    init_view(f, scene, spec, false);
    const Camera explicit_cam = f.camera(f.aspect());
    expect_near(explicit_cam.position, {3, 4, 5}, 1e-5f, "explicit eye");
    expect_near(explicit_cam.target, {0, 1, 0}, 0, "explicit target");
    EXPECT_EQ(explicit_cam.near, 0.25f);
}

TEST(ViewState, OrbitOfInvertsCameraOrbit) {
    for (float az : {-3.0f, -1.0f, 0.0f, 0.7f, 3.0f})
        for (float el : {-1.2f, 0.0f, 0.4f, 1.5f}) {
            const Orbit o = orbit_of(Camera::orbit({1, -2, 3}, az, el, 7));
            EXPECT_NEAR(o.azimuth, az, 1e-4f);
            EXPECT_NEAR(o.elevation, std::min(el, k_max_elevation), 1e-4f);
            EXPECT_NEAR(o.distance, 7, 1e-4f);
        }
}

TEST(ViewState, ReorientTurnsZUpToYUpAndBack) {
    Scene scene;
    Mesh m;
    m.positions = {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}};
    m.indices = {0, 1, 2};
    scene.objects.push_back({m, translate({0, 0, 2}), {}});
    const Mat4 original = scene.objects[0].model;
    reorient(scene, UpAxis::y, UpAxis::z);
    // The file's +Z is now up: (0, 0, 1) + (0, 0, 2) = (0, 0, 3) lands at (0, 3, 0).
    expect_near(transform_point(scene.objects[0].model, {0, 0, 1}), {0, 3, 0}, 0, "+Z up");
    expect_near(transform_point(scene.objects[0].model, {0, 1, 0}), {0, 2, -1}, 0, "+Y toward -Z");
    reorient(scene, UpAxis::z, UpAxis::z);
    reorient(scene, UpAxis::z, UpAxis::y);
    EXPECT_EQ(scene.objects[0].model, original);  // quarter turns are exact
}

}  // namespace
