// Golden images of real model files, rendered by the facet command line and compared pixel for
// pixel with tests/golden/data (tests/support/golden.hpp): CGAL's scanned meshes (OFF), assimp's
// test models in OBJ with textures, glTF with textures and a node hierarchy, binary STL (Z-up),
// PLY and OBJ with vertex colours. Each test skips, saying so, when its file is not installed.
// To accept new images after an intended change:
//   FACET_UPDATE_GOLDEN=1 build/release/tests/facet_tests --gtest_filter='GoldenRealModels*'
// and look at every image before committing it.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "support/cli.hpp"
#include "support/golden.hpp"
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;
using facet_test::k_assimp_models;

// Renders `model` with `options` to golden_out/<golden_name> and compares it with the stored image.
void expect_render_matches_golden(const fs::path& model, const std::string& golden_name,
                                  const std::vector<std::string>& options) {
    if (!fs::exists(model)) GTEST_SKIP() << model << " is missing: install Debian's assimp-testmodels (scripts/setup does)";
    const fs::path out = facet_test::golden_scratch_dir() / golden_name;
    std::vector<std::string> args{"render", model.string(), "-o", out.string()};
    args.insert(args.end(), options.begin(), options.end());
    const facet_test::CliRun r = facet_test::run_facet(args);
    ASSERT_EQ(r.exit_code, 0) << r.all();
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;  // every texture was found
    // Not an empty picture, whatever the stored image says: a good share of pixels show the model.
    const facet_test::DecodedPng img = facet_test::decode_png(out);
    ASSERT_TRUE(img.ok()) << img.error;
    const auto model_pixels = std::count_if(img.rgba.begin(), img.rgba.end(), [&](facet::Rgba8 p) { return p != img.at(0, 0); });
    EXPECT_GT(model_pixels, static_cast<long>(img.rgba.size() / 50)) << out;
    facet_test::expect_matches_golden(out);
}

void expect_cgal_mesh_matches_golden(const char* mesh, const std::string& golden_name, std::vector<std::string> options) {
    const std::optional<fs::path> dir = facet_test::cgal_meshes();
    if (!dir) GTEST_SKIP() << facet_test::cgal_meshes_missing();
    expect_render_matches_golden(*dir / mesh, golden_name, options);
}

// The comparison mode of the contract (lambert), at 320x240.
TEST(GoldenRealModels, BunnyLambert) {
    expect_cgal_mesh_matches_golden("bunny00.off", "real_bunny00_lambert.png", {"--size", "320x240", "--shading", "lambert"});
}

TEST(GoldenRealModels, ArmadilloLambert) {
    // Seen from the front: the file faces -Z.
    expect_cgal_mesh_matches_golden("armadillo.off", "real_armadillo_lambert.png",
                                    {"--size", "320x240", "--shading", "lambert", "--azimuth", "180"});
}

TEST(GoldenRealModels, ElephantLambert) {
    expect_cgal_mesh_matches_golden("elephant.off", "real_elephant_lambert.png", {"--size", "320x240", "--shading", "lambert"});
}

// OBJ with an MTL and five JPEG textures named with Windows paths (".\SpiderTex.jpg").
TEST(GoldenRealModels, SpiderObjTexturedLit) {
    expect_render_matches_golden(k_assimp_models / "OBJ" / "spider.obj", "real_spider_obj_lit.png",
                                 {"--size", "256x192", "--azimuth", "30", "--elevation", "20"});
}

// glTF 2.0: a textured cube (mirrored-repeat and clamp wrapping), the logo upright on its faces.
TEST(GoldenRealModels, BoxTexturedGltfLit) {
    expect_render_matches_golden(k_assimp_models / "glTF2" / "BoxTextured-glTF" / "BoxTextured.gltf",
                                 "real_box_textured_gltf_lit.png",
                                 {"--size", "256x192", "--azimuth", "30", "--elevation", "30"});
}

// glTF: node transforms (one wheel mesh placed twice), several materials, a texture.
TEST(GoldenRealModels, CesiumMilkTruckGltfLit) {
    expect_render_matches_golden(k_assimp_models / "glTF" / "CesiumMilkTruck" / "CesiumMilkTruck.gltf",
                                 "real_cesium_milk_truck_lit.png",
                                 {"--size", "256x192", "--azimuth", "40", "--elevation", "20"});
}

// Binary STL written Z-up: upright only with --up-axis z.
TEST(GoldenRealModels, SpiderBinaryStlZUp) {
    expect_render_matches_golden(k_assimp_models / "STL" / "Spider_binary.stl", "real_spider_binary_stl_zup.png",
                                 {"--size", "256x192", "--azimuth", "30", "--elevation", "20", "--up-axis", "z"});
}

// PLY with float vertex colours (the only coloured PLY with faces in assimp's models: one blue triangle).
TEST(GoldenRealModels, FloatColourPlyVertexColours) {
    expect_render_matches_golden(k_assimp_models / "PLY" / "float-color.ply", "real_float_color_ply.png",
                                 {"--size", "256x192", "--shading", "vertex-color"});
}

// OBJ with a colour per vertex ("v x y z r g b"): interpolated across each face.
TEST(GoldenRealModels, VertexColouredObjCube) {
    expect_render_matches_golden(k_assimp_models / "OBJ" / "cube_with_vertexcolors.obj", "real_cube_vertex_colors_obj.png",
                                 {"--size", "256x192", "--shading", "vertex-color", "--azimuth", "30", "--elevation", "30"});
}

}  // namespace
