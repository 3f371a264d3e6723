// facet view: rendering a frame, and the wireframe pass.
#include "view_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace facet::viewer {
namespace {

// Draws the triangles unindexed (vertex i is corner i % 3 of triangle i / 3), so each corner can
// carry its own barycentric coordinate even where the mesh shares vertices.
struct WireShader {
    static constexpr int k_varyings = 3;
    static constexpr bool k_derivatives = true;
    const Vec3* positions;
    const std::uint32_t* indices;
    std::size_t vertex_count;
    Mat4 clip_from_object;
    float half_width;
    Vec4 colour;

    Vec4 vertex(std::uint32_t i, Varyings<3>& out) const {
        out[0] = out[1] = out[2] = 0;
        out[static_cast<int>(i % 3)] = 1;
        const std::uint32_t v = indices[i];
        if (v >= vertex_count) {
            const float nan = std::numeric_limits<float>::quiet_NaN();
            return {nan, nan, nan, nan};  // dropped by the pipeline as invalid
        }
        return clip_from_object * Vec4(positions[v], 1);
    }

    std::optional<Vec4> fragment(const FragmentIn<3>& in) const {
        // Distance in pixels to the edge where barycentric k is zero: b_k / |grad b_k|.
        float d = std::numeric_limits<float>::infinity();
        for (int k = 0; k < 3; ++k) {
            const float g = std::sqrt(in.ddx[k] * in.ddx[k] + in.ddy[k] * in.ddy[k]);
            if (g > 0) d = std::min(d, in.v[k] / g);
        }
        // Coverage of a pixel by a line of half_width on this side of the edge, with a pixel of ramp.
        const float a = clamp(half_width + 0.5f - d, 0.0f, 1.0f);
        if (!(a > 0)) return std::nullopt;
        return Vec4{colour.x, colour.y, colour.z, colour.w * a};
    }
};

}  // namespace

DrawStats draw_wireframe(Renderer& renderer, Framebuffer& target, const Scene& scene, const Camera& camera,
                         const RenderSettings& settings, float half_width, Vec4 colour) {
    // render_scene's matrix and culling: the positions and the visible faces must match it bit for bit.
    const Mat4 clip_from_world = facet::clip_from_world(camera, target);
    DrawStats total;
    for (const SceneObject& o : scene.objects) {
        if (o.mesh.indices.empty()) continue;
        DrawState state;
        state.cull = cull_mode(o, settings);
        state.depth_test = DepthTest::lequal;
        state.depth_write = false;
        state.blend = Blend::alpha;
        const WireShader shader{o.mesh.positions.data(), o.mesh.indices.data(), o.mesh.positions.size(),
                                clip_from_world * o.model, half_width, colour};
        total += renderer.draw(target, state, DrawInput{static_cast<std::uint32_t>(o.mesh.indices.size()), {}}, shader);
    }
    return total;
}

RenderSettings ViewRenderer::settings_for(const ViewState& state, const RenderSettings& base) {
    RenderSettings s = base;
    s.shading = state.toggles().shading;
    s.cull = state.toggles().cull_back ? CullMode::back : CullMode::none;
    return s;
}

DrawStats ViewRenderer::render(const Scene& scene, const ViewState& state, const RenderSettings& base, int width,
                               int height, int ssaa) {
    ssaa = std::clamp(ssaa, 1, 8);
    width = std::clamp(width, 1, k_max_target_size / ssaa);
    height = std::clamp(height, 1, k_max_target_size / ssaa);
    if (!target_ || target_->width() != width * ssaa || target_->height() != height * ssaa)
        target_.emplace(width * ssaa, height * ssaa);
    const RenderSettings settings = settings_for(state, base);
    const Camera camera = state.camera(static_cast<float>(width) / static_cast<float>(height));
    const DrawStats stats = render_scene(renderer_, *target_, scene, camera, settings);
    if (state.toggles().wireframe)
        draw_wireframe(renderer_, *target_, scene, camera, settings, 0.75f * static_cast<float>(ssaa), k_wire_colour);
    resolve_supersampled(*target_, ssaa, image_, nullptr);
    return stats;
}

}  // namespace facet::viewer
