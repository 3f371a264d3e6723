// facet benchmarks: the scenes that facet and the llvmpipe oracle both render, shared by the scene
// benchmark, the whole-process comparison and the oracle tests.
//  - CGAL's meshes (bunny00.off, armadillo.off, refined_elephant.off), unpacked from Debian's
//    libcgal-demo tarball into the build tree on first use and loaded with facet's own loader;
//  - generated ones: a geodesic sphere of exactly 1,003,520 triangles, a stack of screen-filling
//    quads, a ground plane reaching behind the eye, a jittered grid of triangles.
// Every generated mesh carries per-vertex normals, so facet's lambert mode uses its Lambert shader
// (not the flat fallback) and both renderers shade the same normals.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "facet/camera.hpp"
#include "facet/error.hpp"
#include "facet/scene.hpp"

namespace facet::bench {

// Debian's libcgal-demo ships CGAL's data as one tarball.
inline const std::filesystem::path k_cgal_data = "/usr/share/doc/libcgal-dev/data.tar.gz";

// The directory holding bunny00.off, armadillo.off and refined_elephant.off, unpacked from
// k_cgal_data into <build>/bench_data/cgal/data/meshes on first use (safe when several processes
// race to do it: each unpacks privately and renames complete files into place). Nothing when the
// tarball is missing or cannot be unpacked.
std::optional<std::filesystem::path> cgal_mesh_dir();
std::string cgal_missing_message();

// Loads one of the CGAL meshes above with facet::load_model (creased normals, as `facet render`).
Result<Scene> load_cgal_mesh(const std::string& file_name);

// A class-I geodesic sphere: every face of an icosahedron cut into frequency^2 triangles, points
// pushed onto the sphere; 20 f^2 triangles and 10 f^2 + 2 shared vertices, normals = directions.
// frequency 224 gives 1,003,520 triangles. Vertices on the icosahedron's edges are shared exactly.
Mesh make_geodesic_sphere(float radius, int frequency);
constexpr int k_million_sphere_frequency = 224;  // 20 * 224^2 = 1,003,520

// `count` quads facing +Z, stacked 0.01 apart along -Z and listed back to front (the farthest
// first), so with depth test less every quad overwrites the previous one: a fill-bound draw of
// 2 * count triangles. Each quad spans [-aspect, aspect] x [-1, 1] scaled by `overfill`.
Scene make_quad_stack(int count, float aspect, float overfill = 1.1f);
// The camera that makes the quad stack fill the view: on +Z looking at the nearest quad, fov 45,
// at the distance where a [-aspect, aspect] x [-1, 1] rectangle exactly fills the image.
Camera quad_stack_camera();

// A flat ground plane y = 0 of 2 * half_size on a side (two triangles), normal +Y.
Scene make_ground_plane(float half_size = 1000.0f);
// An eye 1 above the plane looking slightly down: the plane reaches behind the eye (clipped by the
// near plane) and past the far plane.
Camera ground_plane_camera();

// A cells_x * cells_y grid of quads (two triangles each) in the XY plane over [-1, 1] x [-0.75, 0.75],
// its interior vertices jittered by up to `jitter` of a cell, with a gentle height field in z so depth
// and normals vary (smooth normals). Deterministic for a seed.
Scene make_jittered_grid(int cells_x, int cells_y, float jitter, unsigned seed);

// Peak resident memory of this process so far (VmHWM in /proc/self/status), in KiB; -1 if unknown.
long peak_rss_kib();

}  // namespace facet::bench
