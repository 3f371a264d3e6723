// facet: a scene seen from many cameras, with render passes. One call renders a set of passes
// (facet/passes.hpp) for a list of cameras into the caller's memory or into returned images: the
// scene is read where it is (one load for every view), and each view draws every object once (one
// vertex stage per object and view), writing colour and passes from the same visibility, with the
// anti-aliasing (supersampling, jittered frames) and contact shadow of `facet render`, which draws
// its images through it. Also the camera rigs of `facet render --views`: orbits, Fibonacci spheres
// and random views. Writing files is the command line's.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "facet/api.hpp"
#include "facet/contact_shadow.hpp"
#include "facet/passes.hpp"
#include "facet/scene.hpp"

FACET_API_BEGIN
namespace facet {

// What to render of each view.
struct ViewRequest {
    int width = defaults::k_image_width, height = defaults::k_image_height;
    // Anti-aliasing: NxN supersampling (ssaa) and `aa` jittered frames (1, 2, 4 or 8; antialias_offsets,
    // each frame offset by settings.pixel_offset plus its jitter). Colour and alpha average every
    // sample of every frame (colour per frame, then the frames per channel, rounded to nearest).
    // Every other pass takes the surface at the pixel's centre, which an even N and the jittered
    // frames have no sample at: with ssaa or aa above 1 those passes are rendered by one more draw
    // of the view at 1x, unjittered, so they are the same bytes whatever ssaa and aa are.
    int ssaa = defaults::k_ssaa;
    int aa = defaults::k_aa;
    // The lit mode's contact shadow (facet/contact_shadow.hpp): its opacity, 0 for none (the other
    // modes draw none). Made once per render call, drawn after the objects in the views whose eye is
    // above its ground; it is in the colour only (alpha, depth and the ids are the objects').
    float contact_shadow = defaults::k_contact_shadow;
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
    // Not a pass, whatever the PassSet: if given, the window depth (0 at the near plane .. 1 at the
    // far plane and on the background), the nearest of each pixel's samples in every frame, as
    // `facet render --depth-out` writes it.
    float* window_depth = nullptr;
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
    // large, aa not 1, 2, 4 or 8, no pass, out.size() != cameras.size(), a pass asked for without its
    // pointer). The stats are those of each view's first frame.
    DrawStats render(std::span<const ObjectView> objects, std::span<const Camera> cameras, const ViewRequest& request,
                     std::span<const PassImages> out);
    DrawStats render(const Scene& scene, std::span<const Camera> cameras, const ViewRequest& request,
                     std::span<const PassImages> out);
    // The same one view at a time into one set of images, for views written out one by one: view i
    // is rendered into `out`, then view_done(i) is called, before view i + 1 overwrites it; when it
    // returns false the views after i are not rendered. (The contact shadow and the material ids are
    // made once for all the views.)
    DrawStats render_each(std::span<const ObjectView> objects, std::span<const Camera> cameras, const ViewRequest& request,
                          const PassImages& out, const std::function<bool(std::size_t)>& view_done);
    // The same into images it allocates, one per camera.
    std::vector<ViewImages> render(std::span<const ObjectView> objects, std::span<const Camera> cameras,
                                   const ViewRequest& request);
    std::vector<ViewImages> render(const Scene& scene, std::span<const Camera> cameras, const ViewRequest& request);

private:
    void prepare(std::span<const ObjectView> objects, const ViewRequest& request);
    DrawStats render_view(std::span<const ObjectView> objects, const Camera& camera, const ViewRequest& request,
                          const PassImages& out);
    DrawStats render_frames(std::span<const ObjectView> objects, const Camera& camera, const ViewRequest& request,
                            Rgba8* colour, float* alpha, float* window_depth);

    Renderer renderer_;
    std::optional<Framebuffer> direct_;      // at the requested size, drawing into the caller's colour image
    std::optional<Framebuffer> target_;      // at the requested size, its own colour
    std::optional<Framebuffer> samples_;     // supersampled (or a jittered frame's)
    std::vector<ObjectView> scene_views_;    // a Scene's objects as views
    std::vector<std::uint32_t> material_ids_;
    std::vector<const Material*> materials_;  // the distinct materials so far, numbering material_ids_
    std::optional<ContactShadow> shadow_;     // this call's, if any
    std::vector<ObjectView> shadowed_;        // the objects and then the shadow's quad
    // The jittered frames' sums: each frame's colour, its per-channel sum, the samples covered, the
    // frame's window depth.
    std::vector<Rgba8> frame_;
    std::vector<std::uint16_t> colour_sum_, covered_;
    std::vector<float> frame_depth_;
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
