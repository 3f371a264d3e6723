// facet: a scene seen from many cameras, with render passes. One call renders a set of passes
// (facet/passes.hpp) for a list of cameras into the caller's memory or into returned images: the
// scene is read where it is (one load for every view), and each view draws every object once (one
// vertex stage per object and view), writing colour and passes from the same visibility. Also the
// camera rigs of `facet render --views`: orbits, Fibonacci spheres and random views. Writing
// files is the command line's.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "facet/api.hpp"
#include "facet/passes.hpp"
#include "facet/scene.hpp"

FACET_API_BEGIN
namespace facet {

// What to render of each view.
struct ViewRequest {
    int width = defaults::k_image_width, height = defaults::k_image_height;
    // Colour and alpha average the NxN samples of each pixel. Every other pass takes the surface at
    // the pixel's centre, which an even N has no sample at: those passes are rendered by a second
    // draw of the view at 1x, so they are the same bytes whatever N is.
    int ssaa = defaults::k_ssaa;
    PassSet passes = PassSet{}.add(Pass::colour);
    NormalSpace normal_space = NormalSpace::world;
    RenderSettings settings;
};

// One view's images in the caller's memory: width x height pixels each, rows top first, the normal
// 3 floats and the uv 2 floats per pixel. Each pass asked for needs its pointer; the others are
// ignored.
struct PassImages {
    Rgba8* colour = nullptr;
    PassTargets passes;  // alpha, depth, range, normal, instance, material, primitive, uv
};

// Pixels in memory whose rows the renderer can write in whole cache lines (64-byte aligned).
template <class T>
using PixelVector = std::vector<T, detail::CacheLineAllocator<T>>;

// One view's images, owned: the passes asked for are width x height, the others empty.
struct ViewImages {
    int width = 0, height = 0;
    PixelVector<Rgba8> colour;
    PixelVector<float> alpha, depth, range;
    PixelVector<Vec3> normal;
    PixelVector<std::uint32_t> instance, material, primitive;
    PixelVector<Vec2> uv;
    PassImages images();  // pointers to the non-empty ones
};
// Images for `request`'s passes at its size.
ViewImages make_view_images(const ViewRequest& request);

// Renders views of scenes. Keeps its Renderer and targets between calls: once warm, rendering the
// same scene at the same size into the caller's memory allocates nothing.
class ViewRenderer {
public:
    explicit ViewRenderer(RendererConfig config = {});
    ~ViewRenderer();

    Renderer& renderer() { return renderer_; }

    // Renders `objects` seen by cameras[i] into out[i], for each camera. Throws FacetError when the
    // request is bad (size outside 1..k_max_target_size, ssaa outside 1..8 or the size times it too
    // large, no pass, out.size() != cameras.size(), a pass asked for without its pointer).
    DrawStats render(std::span<const ObjectView> objects, std::span<const Camera> cameras, const ViewRequest& request,
                     std::span<const PassImages> out);
    DrawStats render(const Scene& scene, std::span<const Camera> cameras, const ViewRequest& request,
                     std::span<const PassImages> out);
    // The same into images it allocates, one per camera.
    std::vector<ViewImages> render(std::span<const ObjectView> objects, std::span<const Camera> cameras,
                                   const ViewRequest& request);
    std::vector<ViewImages> render(const Scene& scene, std::span<const Camera> cameras, const ViewRequest& request);

private:
    void render_view(std::span<const ObjectView> objects, const Camera& camera, const ViewRequest& request,
                     const PassImages& out, DrawStats& stats);

    Renderer renderer_;
    std::optional<Framebuffer> direct_;      // at the requested size, drawing into the caller's colour image
    std::optional<Framebuffer> target_;      // at the requested size, its own colour
    std::optional<Framebuffer> samples_;     // supersampled
    std::vector<ObjectView> scene_views_;    // a Scene's objects as views
    std::vector<std::uint32_t> material_ids_;
    std::vector<const Material*> materials_;  // the distinct materials so far, numbering material_ids_
};

// The scene's materials numbered from 1 in the order objects first use them; objects whose
// materials are equal (base colour, texture, sampler, alpha mode and cut-off, sidedness) share one.
// This is the material pass's id.
void material_ids(std::span<const ObjectView> objects, std::vector<std::uint32_t>& ids,
                  std::vector<const Material*>& scratch);

// Each view's camera for `objects` at `aspect`, as make_camera makes it, with one pass over the
// vertices for all of them (make_camera reads them all each time).
std::vector<Camera> make_cameras(std::span<const ObjectView> objects, std::span<const ViewSpec> views, float aspect);

// ---- Camera rigs: views around a scene, each framed by the framing rule (scene.hpp) ----
// Each is `base` (field of view, up, clip planes, ...) with its azimuth and elevation set.

// n views on a horizontal circle at `elevation` (radians), azimuths 0, 360/n, ... degrees.
std::vector<ViewSpec> orbit_views(int n, float elevation, const ViewSpec& base = {});
// n views spread evenly over the sphere of directions, deterministically (the Fibonacci sphere:
// view k at height 1 - (2k + 1)/n, turned by the golden angle from the one before).
std::vector<ViewSpec> sphere_views(int n, const ViewSpec& base = {});
// n views uniformly at random over the sphere of directions, the same for the same seed on every
// machine (facet's own generator, not the standard library's distributions).
std::vector<ViewSpec> random_views(int n, std::uint64_t seed, const ViewSpec& base = {});
// "orbit:N[:ELEVATION]" (degrees; default: base's elevation), "sphere:N", "random:N:SEED", N in
// 1..k_max_rig_views. The error says what is wrong with the spec. ("file:" is the command line's.)
inline constexpr int k_max_rig_views = 10000;
Result<std::vector<ViewSpec>> parse_rig(std::string_view spec, const ViewSpec& base = {});

}  // namespace facet
FACET_API_END
