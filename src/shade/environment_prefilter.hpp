// facet shade: what environment_prefilter.cpp computes besides Environment::build, for the
// environment's own files: the built-in studio's radiance, level 0 from an equirectangular image and
// the split-sum table. The studio and the table are computed at build time by
// bake/bake_environment.cpp into the library's constants; tests compute them again to compare.
#pragma once

#include <vector>

#include "facet/environment.hpp"

namespace facet::environment_detail {

// The built-in studio's linear radiance toward unit d (README, "The lit mode").
Vec3 studio_radiance(Vec3 d);
// Level 0's interior (size^2 RGB) from an equirectangular image (Environment::from_equirect).
std::vector<float> equirect_to_octahedral(const float* rgb, int width, int height, int size);
// The split-sum table as split_sum_table() gives it.
std::vector<float> make_split_sum_table();

// The build-time constants (bake_environment writes them; the build's own generated file).
struct BakedStudio {
    const float* texels;  // Environment::texels() of the studio
    std::size_t texel_count;
    const float* sh;      // diffuse_sh(): 9 x RGB
    const float* split_sum;  // k_split_sum_size^2 x (A, B)
};
BakedStudio baked_studio();

}  // namespace facet::environment_detail
