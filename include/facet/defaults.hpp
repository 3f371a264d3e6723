// facet: every default in one place. The library's settings (RendererConfig, LoadOptions,
// TextureLimits, RenderSettings, ViewSpec, Camera, IsolationLimits, ShadingUniforms), the command
// line's (`facet render`, `facet thumbs`) and the viewer's (`facet view`) take their defaults from
// the named values below, and the zeros that mean "choose for me" (threads, batch size) are resolved
// by the functions at the end, which the Renderer and the command line both call. What a run of the
// command line resolves it to is printed by `--print-config` (README, "Printing the settings").
// Nothing here validates: each setting's user checks its range.
#pragma once

#include <cstddef>

#include "facet/api.hpp"
#include "facet/math/vec.hpp"

FACET_API_BEGIN
namespace facet {
namespace defaults {

// ---- Rendering (RendererConfig) ----

// Worker threads of a Renderer: 0 means one per core (resolve_threads).
inline constexpr int k_threads = 0;
// Tile side in pixels: 64 x 64 RGBA8 colour and float depth is 32 KiB, one core's L1 data cache.
inline constexpr int k_tile_size = 64;
// A draw is set up and rasterized one batch of triangles at a time, so a batch bounds the set-up
// records held at once (about 130 bytes each). Per thread, and at least the second per batch:
// more batches revisit the tiles they touch, which costs more than the caches save
// (docs/architecture.md, "batches").
inline constexpr std::size_t k_batch_triangles_per_thread = 131072;
inline constexpr std::size_t k_min_batch_triangles = std::size_t{1} << 20;

// ---- Loading (LoadOptions, TextureLimits) ----

// Files without normals get smooth normals split where faces meet at more than this: sharp enough
// for CAD and STL edges, smooth enough for scans.
inline constexpr float k_crease_angle_degrees = 40.0f;
inline constexpr std::size_t k_max_triangles = 50'000'000;           // refused before loading
inline constexpr int k_max_texture_size = 16384;                      // per side
inline constexpr std::size_t k_max_texture_pixels = std::size_t{64} << 20;  // width * height
inline constexpr std::size_t k_max_file_bytes = std::size_t{2} << 30;
inline constexpr std::size_t k_max_scene_bytes = std::size_t{4} << 30;
// Threads for a large mesh's normals: the library loads on the calling thread (callers may load
// several files at once); `facet render` passes its --threads, as it loads one file.
inline constexpr int k_load_threads = 1;

// ---- Scenes, views and cameras (RenderSettings, ViewSpec, Camera) ----

inline constexpr Vec4 k_background{0.11f, 0.12f, 0.14f, 1.0f};  // a dark grey; alpha 0: transparent
inline constexpr float k_fov_degrees = 45.0f;                     // vertical field of view
// The automatic framing's orbit (`facet render`, `facet view`): from the front.
inline constexpr float k_azimuth_degrees = 0.0f, k_elevation_degrees = 0.0f;

// The lit mode's lights (RenderSettings::lighting), fixed to the camera so that every view reads
// well: a warm key light above-left of the camera, a dim cool fill from the right, ambient and a
// Blinn-Phong highlight. Directions in the camera's frame: (right, up, toward the viewer).
inline constexpr Vec3 k_key_light_direction{-0.5f, 0.8f, 1.0f};
inline constexpr Vec3 k_key_light_colour{1.0f, 0.97f, 0.92f};
inline constexpr Vec3 k_fill_light_direction{1.0f, -0.2f, 0.3f};
inline constexpr Vec3 k_fill_light_colour{0.25f, 0.28f, 0.35f};
inline constexpr float k_lit_ambient = 0.18f, k_lit_diffuse = 0.8f, k_lit_specular = 0.35f, k_lit_shininess = 40.0f;

// The lambert comparison mode's constants, a contract rather than a taste (README, "Shading
// modes"): colour = albedo * (ambient + diffuse * max(dot(n, l), 0)), l toward the eye, white light.
// A ShadingUniforms block starts with these terms, no fill light and no highlight.
inline constexpr float k_lambert_albedo = 0.8f, k_lambert_ambient = 0.15f, k_lambert_diffuse = 0.85f;
inline constexpr float k_uniform_shininess = 32.0f;  // ShadingUniforms' exponent, used once specular > 0

// ---- Materials (Material) ----

// A material that does not say, as from STL, PLY, OFF or an OBJ without MTL: a dielectric of
// medium roughness, which shows a shape's curvature without mirroring the studio. (glTF files
// always give both; glTF's own default material is metallic 1, roughness 1.)
inline constexpr float k_metallic = 0.0f, k_roughness = 0.5f;

// The lit mode's exposure: a linear factor on the radiance before tone mapping. At 1 a white
// diffuse surface facing the built-in studio's key light reads a little below white.
inline constexpr float k_exposure = 1.0f;

// Points and lines (RenderSettings::primitives), in pixels of the target: splats that read as a
// surface on a dense scan at 800x600 without hiding its detail, and lines a little heavier than one
// pixel so that thin diagonals do not look dotted.
inline constexpr float k_point_size = 3.0f, k_line_width = 1.5f;

// ---- The command line and the viewer ----

inline constexpr int k_image_width = 800, k_image_height = 600;  // render: the image; view: the window
// `facet thumbs`: square thumbnails seen from above and to the right, which show a model's shape
// better than the front view.
inline constexpr int k_thumbnail_size = 256;
inline constexpr float k_thumbnail_azimuth_degrees = 35.0f, k_thumbnail_elevation_degrees = 25.0f;
inline constexpr int k_ssaa = 1;  // supersampling factor per side
// Anti-aliasing by jittered frames (antialias_offsets): 1 for render (none), 2 for thumbnails,
// whose edges show most at their small size, at twice a frame's cost (docs/BENCHMARKS.md).
inline constexpr int k_aa = 1, k_thumbnail_aa = 2;
// The lit mode's contact shadow (facet/contact_shadow.hpp): its opacity, 0 for none.
inline constexpr float k_contact_shadow = 0.0f, k_thumbnail_contact_shadow = 0.6f;
// Seconds a file may take (load, render, write) before its worker process is abandoned
// (IsolationLimits, --timeout): generous for real models, short enough for a batch to move on.
inline constexpr double k_timeout_seconds = 60;
// The worker process's memory cap: this share of the physical memory, divided among thumbs'
// workers (--max-memory), and never below k_min_memory_bytes, under which the worker cannot start.
inline constexpr unsigned k_memory_share_numerator = 3, k_memory_share_denominator = 4;
inline constexpr std::size_t k_min_memory_bytes = std::size_t{64} << 20;

}  // namespace defaults

// The number of threads a setting of `threads` means: itself when positive, else one per core
// (at least 1).
int resolve_threads(int threads);

// Triangles per batch of a draw (all threads together) for RendererConfig::batch_triangles =
// `per_thread` (0: the defaults above) and `threads` resolved threads.
std::size_t resolve_batch_triangles(int per_thread, int threads);

}  // namespace facet
FACET_API_END
