// facet view: everything the viewer's input does to the view, as plain logic without SDL, so it is
// unit-tested without a window. The camera orbits a target point: azimuth about +Y from +Z toward +X,
// elevation up from the XZ plane (as Camera::orbit and `facet render --azimuth/--elevation`).
//
// Mouse: left drag orbits (0.4 degrees per pixel; the model follows the mouse), right or middle
// drag pans (the point under the cursor stays under it), the wheel zooms (x0.9 distance per step in).
// Keys (lower-case ASCII; ' ' is Space), see on_key:
//   f fit   r reset   1..7 views   u up axis y/z   p perspective/orthographic
//   m shading   w wireframe   c back-face culling   space spin   a supersampling   h overlay
#pragma once

#include <optional>

#include "facet/camera.hpp"
#include "facet/model.hpp"
#include "facet/scene.hpp"

namespace facet::viewer {

enum class MouseButton { left, middle, right };

// A camera on a sphere around `target`. Angles in radians.
struct Orbit {
    Vec3 target;
    float azimuth = 0, elevation = 0, distance = 1;
    friend bool operator==(const Orbit&, const Orbit&) = default;
};

// Orbiting stops this short of the poles, so "up" never flips and azimuth stays meaningful.
constexpr float k_max_elevation = radians(89.0f);
constexpr float k_orbit_radians_per_pixel = radians(0.4f);
constexpr float k_zoom_per_step = 0.9f;        // distance factor per wheel step toward the target
constexpr float k_spin_radians_per_second = radians(45.0f);

// The view presets on the number keys: {key, azimuth, elevation} in degrees. They also fit.
struct ViewPreset {
    char key;
    const char* name;
    float azimuth_degrees, elevation_degrees;
};
inline constexpr ViewPreset k_view_presets[] = {
    {'1', "front", 0, 0},    {'2', "right", 90, 0},  {'3', "top", 0, 89},      {'4', "iso", 45, 35.264f},
    {'5', "back", 180, 0},   {'6', "left", -90, 0},  {'7', "bottom", 0, -89},
};

// The order M steps through the shading modes.
inline constexpr Shading k_shading_cycle[] = {Shading::lit,          Shading::flat,    Shading::normals, Shading::texture,
                                              Shading::vertex_color, Shading::lambert, Shading::mask};

// The toggles the keys flip, read by the viewer when it renders.
struct Toggles {
    Shading shading = Shading::lit;
    bool wireframe = false;
    bool cull_back = false;  // off: only single-sided materials are culled (as `facet render`)
    bool spin = false;
    int ssaa = defaults::k_ssaa;  // A toggles 1 <-> 2
    bool overlay = true;
    UpAxis up_axis = UpAxis::y;
    bool orthographic = false;
    friend bool operator==(const Toggles&, const Toggles&) = default;
};

class ViewState {
public:
    // The scene's bounding sphere by the framing rule (centre of the bounds, largest vertex distance).
    void set_scene_bounds(Vec3 centre, float radius);
    void set_scene_bounds(const Scene& scene);
    Vec3 scene_centre() const { return centre_; }
    float scene_radius() const { return radius_; }

    // Window size in pixels (pan speed and the aspect used by fit).
    void set_viewport(int width, int height);
    float aspect() const { return static_cast<float>(width_) / static_cast<float>(height_); }

    void set_fovy(float fovy) { fovy_ = fovy; }
    float fovy() const { return fovy_; }
    // Explicit clip planes from the command line; by default they follow the bounding sphere.
    void set_clip_planes(std::optional<float> near, std::optional<float> far) { near_ = near, far_ = far; }

    // Sets the current orbit and the one R returns to.
    void set_initial(const Orbit& orbit);
    const Orbit& initial() const { return initial_; }
    const Orbit& orbit() const { return orbit_; }
    void set_orbit(const Orbit& orbit) { orbit_ = orbit; }

    Toggles& toggles() { return toggles_; }
    const Toggles& toggles() const { return toggles_; }

    // The orbit that frames the scene from (azimuth, elevation) at the current aspect: the framing
    // rule of frame_scene (target = centre, distance = r / sin(min(fovy, fovx) / 2)).
    Orbit fitted(float azimuth, float elevation) const;
    void fit() { orbit_ = fitted(orbit_.azimuth, orbit_.elevation); }

    // Input. Each returns true when the image must be rendered again.
    bool on_drag(float dx, float dy, MouseButton button);  // pixels, y down
    bool on_wheel(float steps);                            // positive: away from the user (zoom in)
    bool on_key(char key);
    // Time passing: turntable spin advances the azimuth. True when the view changed.
    bool advance(double seconds);

    Camera camera(float aspect) const;

    // Pixels per world unit at the target's depth, for panning.
    float world_per_pixel() const;

private:
    Vec3 centre_;
    float radius_ = 1;
    int width_ = defaults::k_image_width, height_ = defaults::k_image_height;
    float fovy_ = radians(defaults::k_fov_degrees);
    std::optional<float> near_, far_;
    Orbit initial_, orbit_;
    Toggles toggles_;
};

// The orbit a camera sits on: target, and the eye's direction and distance from it. Elevation is
// clamped to k_max_elevation.
Orbit orbit_of(const Camera& camera);

// Sets up the view of a scene from the command line's ViewSpec at the state's aspect: the bounds,
// field of view, clip planes, projection and the initial orbit, which is the default scene's
// designed camera when `default_scene_camera`, else make_camera's (framing by azimuth and
// elevation, or an explicit eye and target; an explicit --up is not kept: the orbit is about +Y).
void init_view(ViewState& state, const Scene& scene, const ViewSpec& view, bool default_scene_camera);

// Turns the scene so that `to`'s axis is up, given that it was loaded with `from`'s axis up
// (load_model's --up-axis z rotates the file's +Z onto +Y; this applies or undoes that rotation).
void reorient(Scene& scene, UpAxis from, UpAxis to);

}  // namespace facet::viewer
