// facet view: the viewer's frame, rendered with libfacet exactly as `facet render` renders (same
// Scene, Camera, RenderSettings and render_scene), plus the wireframe overlay pass. No SDL here.
#pragma once

#include <optional>

#include "facet/renderer.hpp"
#include "facet/scene.hpp"
#include "view_state.hpp"

namespace facet::viewer {

// The wireframe pass: every triangle again, with a shader that keeps only pixels within about
// `half_width` pixels of the triangle's edges (distance from the exact screen derivatives of its
// barycentrics) and blends `colour` there. It tests depth with lequal against what render_scene
// wrote and writes none: the vertex positions and the depth interpolation are bit-identical to the
// first pass, so visible edges pass and hidden ones fail. Culling matches render_scene's per object.
DrawStats draw_wireframe(Renderer& renderer, Framebuffer& target, const Scene& scene, const Camera& camera,
                         const RenderSettings& settings, float half_width, Vec4 colour);

constexpr Vec4 k_wire_colour{0.03f, 0.03f, 0.04f, 0.85f};

// Renders the view into an image, keeping its buffers between frames.
class ViewRenderer {
public:
    explicit ViewRenderer(RendererConfig config = {}) : renderer_(config) {}

    // The state's camera and toggles (shading, culling, wireframe) over `base` (background), at
    // width x height pixels, supersampled ssaa x ssaa. Width and height are clamped to 1..8192/ssaa.
    DrawStats render(const Scene& scene, const ViewState& state, const RenderSettings& base, int width, int height,
                     int ssaa);
    const Image& image() const { return image_; }
    int threads() const { return renderer_.threads(); }

    // The settings a state renders with.
    static RenderSettings settings_for(const ViewState& state, const RenderSettings& base);

private:
    Renderer renderer_;
    std::optional<Framebuffer> target_;
    Image image_;
};

}  // namespace facet::viewer
