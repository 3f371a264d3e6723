// facet view: orbit, pan, zoom, presets and toggles as plain logic (see view_state.hpp).
#include "view_state.hpp"

#include <algorithm>
#include <cmath>

namespace facet::viewer {
namespace {

float wrap_angle(float a) { return std::remainder(a, 2 * k_pi); }

// The horizontal field of view for a vertical one at an aspect (width / height).
float fovx_of(float fovy, float aspect) { return 2 * std::atan(std::tan(fovy / 2) * aspect); }

}  // namespace

void ViewState::set_scene_bounds(Vec3 centre, float radius) {
    centre_ = centre;
    radius_ = radius > 0 && std::isfinite(radius) ? radius : 1.0f;  // as frame_scene: a point frames a unit sphere
}

void ViewState::set_scene_bounds(const Scene& scene) {
    const Aabb box = scene.bounds();
    const Vec3 centre = box.empty() ? Vec3{} : box.centre();
    set_scene_bounds(centre, scene.radius_about(centre));
}

void ViewState::set_viewport(int width, int height) {
    width_ = std::max(width, 1);
    height_ = std::max(height, 1);
}

void ViewState::set_initial(const Orbit& orbit) {
    initial_ = orbit;
    orbit_ = orbit;
}

Orbit ViewState::fitted(float azimuth, float elevation) const {
    const float fov = std::min(fovy_, fovx_of(fovy_, aspect()));
    return Orbit{centre_, azimuth, elevation, radius_ / std::sin(fov / 2)};
}

bool ViewState::on_drag(float dx, float dy, MouseButton button) {
    if (!std::isfinite(dx) || !std::isfinite(dy) || (dx == 0 && dy == 0)) return false;
    if (button == MouseButton::left) {
        // The model follows the mouse: dragging right turns it right, so the eye moves left.
        orbit_.azimuth = wrap_angle(orbit_.azimuth - dx * k_orbit_radians_per_pixel);
        orbit_.elevation = std::clamp(orbit_.elevation + dy * k_orbit_radians_per_pixel, -k_max_elevation, k_max_elevation);
        return true;
    }
    // Pan in the camera plane by as many world units as the pixels cover at the target's depth, so
    // the point under the cursor stays under it.
    const Camera c = camera(aspect());
    const CameraBasis basis = camera_basis(c.target - c.position, c.up, c.handedness);
    const float step = world_per_pixel();
    orbit_.target = orbit_.target - basis.right * (dx * step) + basis.up * (dy * step);
    return true;
}

bool ViewState::on_wheel(float steps) {
    if (!std::isfinite(steps) || steps == 0) return false;
    const float d = orbit_.distance * std::pow(k_zoom_per_step, steps);
    // Multiplicative, so always positive; bounded so that neither end loses the scene in float.
    orbit_.distance = std::clamp(d, radius_ * 1e-3f, radius_ * 1e4f);
    return true;
}

bool ViewState::on_key(char key) {
    for (const ViewPreset& p : k_view_presets)
        if (p.key == key) {
            orbit_ = fitted(radians(p.azimuth_degrees), std::clamp(radians(p.elevation_degrees), -k_max_elevation, k_max_elevation));
            return true;
        }
    Toggles& t = toggles_;
    switch (key) {
        case 'f': fit(); return true;
        case 'r': orbit_ = initial_; return true;
        case 'u': t.up_axis = t.up_axis == UpAxis::y ? UpAxis::z : UpAxis::y; return true;
        case 'p': t.orthographic = !t.orthographic; return true;
        case 'm': {
            const auto* begin = std::begin(k_shading_cycle), *end = std::end(k_shading_cycle);
            const auto* it = std::find(begin, end, t.shading);
            t.shading = (it == end || it + 1 == end) ? *begin : *(it + 1);
            return true;
        }
        case 'w': t.wireframe = !t.wireframe; return true;
        case 'c': t.cull_back = !t.cull_back; return true;
        case ' ': t.spin = !t.spin; return true;
        case 'a': t.ssaa = t.ssaa > 1 ? 1 : 2; return true;
        case 'h': t.overlay = !t.overlay; return true;
        default: return false;
    }
}

bool ViewState::advance(double seconds) {
    if (!toggles_.spin || !(seconds > 0)) return false;
    orbit_.azimuth = wrap_angle(orbit_.azimuth + static_cast<float>(seconds) * k_spin_radians_per_second);
    return true;
}

Camera ViewState::camera(float aspect) const {
    Camera c = Camera::orbit(orbit_.target, orbit_.azimuth, orbit_.elevation, orbit_.distance);
    c.fovy = fovy_;
    // The framing rule's clip planes, measured from the scene's centre so panning keeps them right.
    const float d = length(c.position - centre_);
    c.near = near_ ? *near_ : std::max(d - 1.5f * radius_, 0.01f * radius_);
    c.far = far_ ? *far_ : d + 1.5f * radius_;
    if (toggles_.orthographic) {
        // As make_camera at the fitted distance (height 2r, or 2r / aspect when narrow), scaled
        // with the distance so the wheel zooms here too.
        c.projection_kind = ProjectionKind::orthographic;
        const float fov = std::min(fovy_, fovx_of(fovy_, aspect));
        c.ortho_height = orbit_.distance * 2 * std::sin(fov / 2) * std::max(1.0f, 1.0f / aspect);
        c.near = near_ ? *near_ : 0.01f * radius_;
    }
    return c;
}

float ViewState::world_per_pixel() const {
    const Camera c = camera(aspect());
    const float height = c.projection_kind == ProjectionKind::orthographic ? c.ortho_height
                                                                           : 2 * orbit_.distance * std::tan(fovy_ / 2);
    return height / static_cast<float>(height_);
}

Orbit orbit_of(const Camera& camera) {
    const Vec3 offset = camera.position - camera.target;
    const float d = length(offset);
    if (!(d > 0)) return Orbit{camera.target, 0, 0, 1};
    const float el = std::asin(std::clamp(offset.y / d, -1.0f, 1.0f));
    const float az = std::atan2(offset.x, offset.z);
    return Orbit{camera.target, az, std::clamp(el, -k_max_elevation, k_max_elevation), d};
}

void init_view(ViewState& state, const Scene& scene, const ViewSpec& view, bool default_scene_camera) {
    state.set_scene_bounds(scene);
    if (default_scene_camera) {
        const Camera c = facet::default_scene_camera(state.aspect());
        state.set_fovy(c.fovy);
        state.set_initial(orbit_of(c));
        return;
    }
    state.set_fovy(view.fovy);
    state.set_clip_planes(view.near, view.far);
    state.toggles().orthographic = view.orthographic;
    const Camera c = make_camera(scene, view, state.aspect());
    state.set_initial(orbit_of(c));
}

void reorient(Scene& scene, UpAxis from, UpAxis to) {
    if (from == to) return;
    // Exact quarter turns about X: z-up to y-up maps (x, y, z) to (x, z, -y); y-up to z-up undoes it.
    const Mat4 z_up_to_y_up = Mat4::from_rows({1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1});
    const Mat4 turn = to == UpAxis::z ? z_up_to_y_up : transpose(z_up_to_y_up);
    for (SceneObject& o : scene.objects) o.model = turn * o.model;
}

}  // namespace facet::viewer
