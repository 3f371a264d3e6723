// facet benchmarks: the llvmpipe oracle. Renders the same scene as facet's lambert mode
// (render_scene with Shading::lambert) with Mesa's llvmpipe, headless, through EGL's surfaceless
// platform and desktop OpenGL (3.3 core or later):
//   - one framebuffer object: RGBA8 colour + DEPTH_COMPONENT32F depth, the target's size;
//   - per object one VAO (interleaved position + normal VBO, uint32 index buffer), one glDrawElements;
//   - the camera's matrices from facet (Camera::projection * Camera::view * model, computed on the
//     CPU exactly as render_scene does, column-major like GL) and glClipControl(GL_LOWER_LEFT,
//     GL_ZERO_TO_ONE), so clip space and window depth are facet's _zo convention;
//   - per-pixel Lambert exactly as facet: 0.8 * (0.15 + 0.85 * max(dot(normalize(n), l), 0)), l the
//     unit vector from the target to the eye; no culling, depth test LESS, no blending, no dither;
//   - read back as float depth and RGBA8 colour, rows flipped so row 0 is the top, like facet;
//   - on request (resize's `passes`), facet's normal and instance passes from the same draw: two
//     more colour attachments, RGBA32F (the normalized world-space normal) and R32UI (the scene
//     object's index + 1, 0 for the background), read back with the others.
//
// Threads: llvmpipe reads LP_NUM_THREADS once, when the driver loads at EGL initialisation, so a
// process can have one thread count only; run other counts in child processes. facet --threads 1
// corresponds to LP_NUM_THREADS=0 (everything on the calling thread); facet --threads N >= 2 to
// LP_NUM_THREADS=N (N rasterizer threads; vertex processing, clipping, setup and binning stay on the
// calling thread, which waits in glFinish while they rasterize). LP_NUM_THREADS=1 would be two
// threads: the caller binning and one rasterizer thread. See llvmpipe_threads_for().
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "facet/camera.hpp"
#include "facet/error.hpp"
#include "facet/image.hpp"
#include "facet/scene.hpp"

namespace facet::bench {

// LP_NUM_THREADS for a facet thread count (see above): 1 -> 0, N >= 2 -> N.
inline int llvmpipe_threads_for(int facet_threads) { return facet_threads <= 1 ? 0 : facet_threads; }

struct GlOracleOptions {
    // LP_NUM_THREADS to set before the driver loads; negative: leave the environment as it is.
    int llvmpipe_threads = -1;
};

// What llvmpipe drew, in facet's layout: row-major, row 0 at the top.
struct GlFrame {
    int width = 0, height = 0;
    std::vector<Rgba8> colour;
    std::vector<float> depth;  // window depth in [0, 1], 1 where nothing was drawn (the clear value)
    // With passes (resize): world-space unit normals (0 on the background) and instance ids.
    std::vector<Vec3> normal;
    std::vector<std::uint32_t> instance;
};

// Errors of GlOracle::create that mean "no llvmpipe through EGL surfaceless here" (no EGL, no Mesa
// surfaceless platform, no context, another driver) start with this; tests skip on them and fail on
// anything else (a shader that does not compile, a GL error).
inline constexpr const char* k_unavailable_prefix = "llvmpipe oracle unavailable: ";
inline bool oracle_unavailable(const Error& e) { return e.message.rfind(k_unavailable_prefix, 0) == 0; }

class GlOracle {
public:
    // Sets GALLIUM_DRIVER=llvmpipe (and LP_NUM_THREADS when asked), then initialises EGL on the
    // surfaceless platform and makes a desktop GL 3.3+ core context current on this thread. The
    // error names the EGL or GL call that failed (tests skip with it). LP_NUM_THREADS can be set
    // once per process: asking for a different count later is an error.
    static Result<std::unique_ptr<GlOracle>> create(const GlOracleOptions& options = {});
    ~GlOracle();
    GlOracle(const GlOracle&) = delete;
    GlOracle& operator=(const GlOracle&) = delete;

    std::string renderer() const;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::string version() const;   // GL_VERSION, e.g. "4.5 (Core Profile) Mesa 22.3.6"
    // True when depth is [0, 1] through glClipControl; false: GL 3.3 without ARB_clip_control, and the
    // projection is remapped to GL's [-1, 1] clip z instead (same planes, slightly different rounding).
    bool has_clip_control() const { return clip_control_; }
    int llvmpipe_threads() const;  // LP_NUM_THREADS as the driver saw it (-1: not set)

    // Uploads the scene's meshes (positions, normals, indices, points and lines; one set of buffers
    // per object).
    // Objects without normals are an error: facet would fall back to flat shading for them.
    Status load(const Scene& scene);
    // (Re)creates the framebuffer object at this size; with `passes`, with the normal and instance
    // attachments too, which draw then clears and writes and read reads back.
    Status resize(int width, int height, bool passes = false);
    // The size of GL_POINTS (glPointSize: square points) and the width of GL_LINES (glLineWidth), in
    // pixels, for the objects' points and lines; `line_blend`: lines alpha-blended without depth
    // writes (facet's --line-aa peer; GL_LINE_SMOOTH crashes llvmpipe 22.3 here).
    void set_primitive_style(float point_size, float line_width, bool line_blend = false);
    // Clears to `background` and depth 1, then draws every loaded object with the camera: one
    // glDrawElements per object and kind (triangles, then points, then lines). Does not wait for the GPU thread(s): see finish().
    void draw(const Camera& camera, Vec4 background);
    void finish();  // glFinish: returns when llvmpipe has rasterized everything drawn
    GlFrame read(); // glReadPixels of colour and depth, flipped to row 0 = top
    // The GL error flag (glGetError), as text; empty when there is none.
    std::string gl_error();

    // load + resize + draw + read.
    Result<GlFrame> render(const Scene& scene, const Camera& camera, int width, int height, Vec4 background);

private:
    GlOracle() = default;
    struct Impl;
    std::unique_ptr<Impl> impl_;
    bool clip_control_ = false;
};

// How two renderings of one scene agree. Coverage is depth < 1 in each; the union is the pixels
// either covers. Depth and colour are compared on the pixels both cover.
struct Agreement {
    std::size_t pixels = 0;
    std::size_t covered_union = 0, covered_both = 0;
    std::size_t only_facet = 0, only_gl = 0;
    double coverage_agreement = 1;  // covered_both / covered_union (1 when nothing is covered)
    double max_depth_diff = 0, mean_depth_diff = 0;
    std::size_t depth_over_1e4 = 0;  // pixels covered by both with |depth difference| > 1e-4
    int max_colour_diff = 0;         // largest difference of one channel, in 8-bit steps
    double mean_colour_diff = 0;     // mean over covered pixels of the largest channel difference
    std::size_t colour_over_2 = 0;   // pixels covered by both with a channel differing by more than 2
};

// facet's colour and depth (Framebuffer layout) against llvmpipe's frame; sizes must match.
Agreement compare(const Rgba8* facet_colour, const float* facet_depth, const GlFrame& gl);
std::string describe(const Agreement& a);  // one line of figures, for logs

// The one systematic depth difference between the two: facet builds a triangle's depth plane from
// its vertices after snapping them to 1/256 pixel, llvmpipe from the unsnapped float positions. On
// ordinary triangles the planes differ by ~1e-7; on sub-pixel slivers (edge-on triangles a fraction
// of a pixel wide) the snap tilts the plane and depths can differ by 1e-4 or more at a few pixels.
// This finds the pixels both cover whose depths differ by more than `tolerance` and, for each, the
// triangle facet drew there (an extra facet render with triangle ids), and counts it as explained
// when facet's depth is the plane through that triangle's snapped vertices (within 1e-5) and
// llvmpipe's the plane through its unsnapped ones (within 1e-5 plus a quarter of the gap between the
// two planes: llvmpipe sets planes up in float, which on the thinnest slivers is itself off by ~1e-5).
// `facet` must be render_scene's output for the scene and camera (only its depth is used).
struct DepthOutliers {
    std::size_t total = 0, explained = 0;
    std::vector<std::string> explained_details;  // one line per explained pixel (at most 50)
    std::string unexplained;                     // the first few others, for a failure message
};
DepthOutliers explain_depth_outliers(const Scene& scene, const Camera& camera, const Framebuffer& facet,
                                     const GlFrame& gl, double tolerance);

}  // namespace facet::bench
