// facet scene: the contact shadow (facet/contact_shadow.hpp). In: objects and a renderer. Out: the
// ground quad and its shadow texture, from one small orthographic depth render seen from below and a
// box blur. Not the drawing of it (render_scene draws it as any alpha-blended object).
#include "facet/contact_shadow.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "scene/box_blur.hpp"

namespace facet {
namespace detail {

// Each output texel is the sum of its 2r + 1 inputs in order, from -r to r, times 1 / (2r + 1) (the
// rule's loop); the loops run along whole rows (a row padded with its end texels, or whole rows
// added), which the compiler vectorizes without changing any texel's sum.
void box_blur(std::vector<float>& v, int n, int r) {
    const auto w = static_cast<std::size_t>(n), radius = static_cast<std::size_t>(r);
    std::vector<float> tmp(v.size()), padded(w + 2 * radius);
    const float scale = 1.0f / static_cast<float>(2 * r + 1);
    for (int pass = 0; pass < 3; ++pass) {
        for (std::size_t j = 0; j < w; ++j) {  // along the rows
            const float* row = &v[j * w];
            std::fill_n(padded.begin(), radius, row[0]);
            std::copy_n(row, w, padded.begin() + static_cast<std::ptrdiff_t>(radius));
            std::fill_n(padded.begin() + static_cast<std::ptrdiff_t>(radius + w), radius, row[w - 1]);
            float* out = &tmp[j * w];
            std::fill_n(out, w, 0.0f);
            for (std::size_t k = 0; k <= 2 * radius; ++k)
                for (std::size_t i = 0; i < w; ++i) out[i] += padded[i + k];
            for (std::size_t i = 0; i < w; ++i) out[i] *= scale;
        }
        v.swap(tmp);
        for (int i = 0; i < n; ++i) {  // along the columns: output row i sums rows i - r to i + r
            float* out = &tmp[static_cast<std::size_t>(i) * w];
            std::fill_n(out, w, 0.0f);
            for (int k = -r; k <= r; ++k) {
                const float* row = &v[static_cast<std::size_t>(std::clamp(i + k, 0, n - 1)) * w];
                for (std::size_t j = 0; j < w; ++j) out[j] += row[j];
            }
            for (std::size_t j = 0; j < w; ++j) out[j] *= scale;
        }
        v.swap(tmp);
    }
}

}  // namespace detail

ObjectView ContactShadow::view() const {
    return {mesh.positions.data(), mesh.normals.data(), nullptr, mesh.uvs.data(), static_cast<std::uint32_t>(mesh.positions.size()),
            mesh.indices, Mat4::identity(), &material, nullptr, mesh.points, mesh.lines};
}

std::optional<ContactShadow> make_contact_shadow(Renderer& renderer, std::span<const ObjectView> objects, float opacity) {
    const Aabb b = bounds(objects);
    if (b.empty() || !(opacity > 0)) return std::nullopt;
    const Vec3 extent = b.max - b.min;
    const float largest = std::max({extent.x, extent.y, extent.z});
    if (!(largest > 0) || !std::isfinite(largest)) return std::nullopt;
    const float half = std::max(extent.x, extent.z) / 2 + largest / 4;  // room for the blur to fade out
    const float band = largest / 4;
    const float ground = b.min.y - largest * 1e-3f;  // a hair below: no fighting with a flat base
    const Vec3 centre{(b.min.x + b.max.x) / 2, ground, (b.min.z + b.max.z) / 2};

    // From below, looking up: depth 0 at the ground, 1 at the band's top (farther is clipped).
    Camera camera;
    camera.position = centre - Vec3{0, largest, 0};
    camera.target = centre;
    camera.up = {0, 0, -1};
    camera.projection_kind = ProjectionKind::orthographic;
    camera.ortho_height = 2 * half;
    camera.near = largest;
    camera.far = largest + band;
    constexpr int n = k_contact_shadow_resolution;
    Framebuffer depth(n, n);
    RenderSettings settings;
    settings.shading = Shading::lambert;  // never culls: a surface's either side casts
    render_scene(renderer, depth, objects, camera, settings);

    std::vector<float> shade(static_cast<std::size_t>(n) * n);
    for (std::size_t i = 0; i < shade.size(); ++i) {
        const float d = std::clamp(depth.depth_data()[i], 0.0f, 1.0f);
        shade[i] = (1 - d) * (1 - d);
    }
    detail::box_blur(shade, n, n / 32);
    Image image{n, n, std::vector<Rgba8>(static_cast<std::size_t>(n) * n)};
    for (std::size_t i = 0; i < shade.size(); ++i) {
        const float a = std::clamp(opacity * shade[i], 0.0f, 1.0f);
        image.pixels[i] = {0, 0, 0, static_cast<std::uint8_t>(std::lround(a * 255))};
    }

    ContactShadow s;
    Mesh& m = s.mesh;
    const Mat4 clip = camera.projection(1.0f) * camera.view();
    for (const Vec2 corner : {Vec2{-1, -1}, Vec2{1, -1}, Vec2{1, 1}, Vec2{-1, 1}}) {
        const Vec3 p{centre.x + corner.x * half, ground, centre.z + corner.y * half};
        const Vec4 c = clip * Vec4(p, 1);  // orthographic: w = 1
        m.positions.push_back(p);
        m.normals.push_back({0, 1, 0});
        m.uvs.push_back({(c.x / c.w + 1) / 2, (1 - c.y / c.w) / 2});  // the texture's row 0 is the image's top
    }
    m.indices = {0, 2, 1, 0, 3, 2};
    Material& mat = s.material;
    mat.base_colour = {0, 0, 0, 1};
    mat.base_colour_texture = std::make_shared<const Texture>(std::move(image));
    mat.sampler = {Wrap::clamp, Wrap::clamp, Filter::bilinear};
    mat.alpha_mode = AlphaMode::blend;
    mat.double_sided = true;
    mat.unlit = true;
    return s;
}

}  // namespace facet
