// Benchmark support: the build folder's bench_data/, where the CGAL meshes are unpacked. Only
// bench_data_dir.cpp is compiled with the path (bench/CMakeLists.txt), so that bench_scenes.cpp's
// command line names no build folder and a fresh build folder reuses its ccache entry.
#pragma once

namespace facet::bench {

extern const char* const k_bench_data_dir;

}  // namespace facet::bench
