// Materials as loaded: glTF 2.0's metallic-roughness fields and each of its texture slots, the
// mapping of OBJ/MTL's Phong terms (README, "Materials"), KHR_texture_transform, and the tangents
// normal maps are read with (the file's, or compute_tangents' by its documented rule).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "facet/io.hpp"
#include "facet/model.hpp"
#include "facet/scene.hpp"
#include "support/gltf_writer.hpp"
#include "support/test_data.hpp"

namespace {

using namespace facet;
using namespace facet_test;
namespace fs = std::filesystem;

void expect_vec_near(Vec3 a, Vec3 b, float tolerance = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(Tangents, FollowIncreasingUAndTheImagesUpwardV) {
    Mesh m = facing_quad();
    compute_tangents(m);
    ASSERT_EQ(m.tangents.size(), 4u);
    for (const Vec4& t : m.tangents) {
        expect_vec_near(t.xyz(), {1, 0, 0});
        EXPECT_EQ(t.w, 1.0f);  // b = cross(+Z, +X) = +Y, the image's top
    }
}

TEST(Tangents, MirroredUvsTurnTheBitangentsSideOver) {
    Mesh m = facing_quad(true);
    compute_tangents(m);
    for (const Vec4& t : m.tangents) {
        expect_vec_near(t.xyz(), {-1, 0, 0});
        EXPECT_EQ(t.w, -1.0f);  // cross(+Z, -X) = -Y, but the image's top is still +Y
    }
}

TEST(Tangents, AreUnitOrthogonalToTheNormalAndAlongU) {
    Mesh m = make_uv_sphere(2.0f, 24, 12);
    compute_tangents(m);
    ASSERT_EQ(m.tangents.size(), m.positions.size());
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        const Vec3 t = m.tangents[i].xyz(), n = m.normals[i];
        EXPECT_NEAR(length(t), 1.0f, 1e-5f);
        EXPECT_NEAR(dot(t, n), 0.0f, 1e-5f);
        if (std::fabs(n.y) > 0.99f) continue;  // the poles: u has no direction there
        // make_uv_sphere: u grows with theta, dP/dtheta is along (cos theta, 0, -sin theta).
        const float theta = m.uvs[i].x * 2 * k_pi;
        EXPECT_GT(dot(t, Vec3{std::cos(theta), 0, -std::sin(theta)}), 0.97f) << i;
        EXPECT_EQ(m.tangents[i].w, 1.0f) << i;
    }
}

TEST(Tangents, DegenerateUvsGiveSomeOrthogonalUnitTangent) {
    Mesh m = facing_quad();
    for (Vec2& uv : m.uvs) uv = {0.5f, 0.5f};
    compute_tangents(m);
    for (const Vec4& t : m.tangents) {
        EXPECT_NEAR(length(t.xyz()), 1.0f, 1e-5f);
        EXPECT_NEAR(t.z, 0.0f, 1e-6f);
    }
    Mesh none = facing_quad();
    none.uvs.clear();
    compute_tangents(none);
    EXPECT_TRUE(none.tangents.empty());  // nothing to compute them from
}

TEST(Tangents, AppendTransformsThemAndAMirrorFlipsTheirSide) {
    Mesh m = facing_quad();
    compute_tangents(m);
    Mesh out;
    out.append(m, rotate_z(radians(90)));
    out.append(m, scale({-1, 1, 1}));
    ASSERT_EQ(out.tangents.size(), 8u);
    expect_vec_near(out.tangents[0].xyz(), {0, 1, 0});
    EXPECT_EQ(out.tangents[0].w, 1.0f);
    expect_vec_near(out.tangents[4].xyz(), {-1, 0, 0});
    EXPECT_EQ(out.tangents[4].w, -1.0f);
    EXPECT_TRUE(out.validate());
}

// An 8x8 image of one colour.
Image flat_image(Rgba8 c) { return Image{8, 8, std::vector<Rgba8>(64, c)}; }

TEST(GltfMaterials, EveryTextureSlotAndFactorArrives) {
    const fs::path dir = test_temp_dir("facet_materials");
    GltfDocument doc;
    doc.images = {flat_image({200, 100, 50, 255}), flat_image({0, 128, 255, 255}), flat_image({128, 128, 255, 255}),
                  flat_image({77, 0, 0, 255}), flat_image({10, 20, 30, 255})};
    GltfMaterial m;
    m.base_colour[0] = 0.5f, m.base_colour[1] = 0.25f, m.base_colour[2] = 1.0f, m.base_colour[3] = 1.0f;
    m.metallic = 0.25f, m.roughness = 0.75f;
    m.base_colour_texture.image = 0;
    m.base_colour_texture.wrap_s = 33071;  // CLAMP_TO_EDGE
    m.metallic_roughness_texture.image = 1;
    m.normal_texture.image = 2;
    m.normal_texture.wrap_t = 33648;  // MIRRORED_REPEAT
    m.normal_scale = 0.6f;
    m.occlusion_texture.image = 3;
    m.occlusion_strength = 0.4f;
    m.emissive_texture.image = 4;
    m.emissive[0] = 1, m.emissive[1] = 0.5f, m.emissive[2] = 0.25f;
    m.double_sided = false;
    doc.materials = {m};
    doc.nodes.push_back({facing_quad(), 0, {}});
    const Result<LoadedModel> r = load_model(write_gltf(dir / "slots.gltf", doc));
    ASSERT_TRUE(r) << r.error().message;
    ASSERT_EQ(r->scene.objects.size(), 1u);
    const SceneObject& o = r->scene.objects[0];
    const Material& mat = o.material;
    EXPECT_EQ(mat.metallic, 0.25f);
    EXPECT_EQ(mat.roughness, 0.75f);
    EXPECT_EQ(mat.base_colour.y, 0.25f);
    EXPECT_FALSE(mat.double_sided);
    EXPECT_FALSE(mat.unlit);
    auto texel = [](const TextureMap& map) { return map.texture ? map.texture->level(0).at(0, 0) : Rgba8{}; };
    ASSERT_TRUE(mat.base_colour_texture);
    EXPECT_EQ(mat.base_colour_texture->level(0).at(0, 0).r, 200);
    EXPECT_EQ(mat.sampler.wrap_u, Wrap::clamp);
    EXPECT_EQ(texel(mat.metallic_roughness_map).b, 255);
    EXPECT_EQ(texel(mat.normal_map).b, 255);
    EXPECT_EQ(texel(mat.normal_map).r, 128);
    EXPECT_EQ(mat.normal_map.sampler.wrap_v, Wrap::mirror);
    EXPECT_EQ(mat.normal_map.sampler.wrap_u, Wrap::repeat);
    EXPECT_FLOAT_EQ(mat.normal_scale, 0.6f);
    EXPECT_EQ(texel(mat.occlusion_map).r, 77);
    EXPECT_FLOAT_EQ(mat.occlusion_strength, 0.4f);
    EXPECT_EQ(texel(mat.emissive_map).b, 30);
    expect_vec_near(mat.emissive, {1, 0.5f, 0.25f}, 0);
    EXPECT_TRUE(mat.base_colour_transform.is_identity());
    // The file has no TANGENT: computed for the normal map, by the quad's uvs.
    ASSERT_EQ(o.mesh.tangents.size(), o.mesh.positions.size());
    for (const Vec4& t : o.mesh.tangents) {
        expect_vec_near(t.xyz(), {1, 0, 0});
        EXPECT_EQ(t.w, 1.0f);
    }
}

TEST(GltfMaterials, TangentsOfTheFileAreKeptWithTheirSide) {
    const fs::path dir = test_temp_dir("facet_materials");
    GltfDocument doc;
    doc.images = {flat_image({128, 128, 255, 255})};
    GltfMaterial m;
    m.normal_texture.image = 0;
    doc.materials = {m};
    Mesh q = facing_quad();
    q.tangents.assign(4, Vec4{0, 1, 0, -1});  // deliberately not what the uvs would give
    doc.nodes.push_back({q, 0, {}});
    const Result<LoadedModel> r = load_model(write_gltf(dir / "tangents.gltf", doc));
    ASSERT_TRUE(r) << r.error().message;
    const Mesh& mesh = r->scene.objects[0].mesh;
    ASSERT_EQ(mesh.tangents.size(), mesh.positions.size());
    for (const Vec4& t : mesh.tangents) {
        expect_vec_near(t.xyz(), {0, 1, 0});
        EXPECT_EQ(t.w, -1.0f);
    }
}

TEST(GltfMaterials, WithoutANormalMapNoTangentsAreKept) {
    const fs::path dir = test_temp_dir("facet_materials");
    GltfDocument doc;
    doc.materials = {GltfMaterial{}};
    doc.nodes.push_back({facing_quad(), 0, {}});
    const Result<LoadedModel> r = load_model(write_gltf(dir / "plain.gltf", doc));
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_TRUE(r->scene.objects[0].mesh.tangents.empty());
    EXPECT_EQ(r->scene.objects[0].material.metallic, 1.0f);  // glTF's own defaults
    EXPECT_EQ(r->scene.objects[0].material.roughness, 1.0f);
}

TEST(GltfMaterials, TextureTransformIsGltfsOffsetRotationScale) {
    const fs::path dir = test_temp_dir("facet_materials");
    GltfDocument doc;
    doc.extensions_used = {"KHR_texture_transform"};
    doc.images = {flat_image({255, 255, 255, 255})};
    GltfMaterial m;
    m.base_colour_texture.image = 0;
    const float ox = 0.1f, oy = 0.2f, r = 0.3f, sx = 2, sy = 3;
    m.base_colour_texture.extensions = R"({"KHR_texture_transform":{"offset":[0.1,0.2],"rotation":0.3,"scale":[2,3]}})";
    doc.materials = {m};
    doc.nodes.push_back({facing_quad(), 0, {}});
    const Result<LoadedModel> loaded = load_model(write_gltf(dir / "transform.gltf", doc));
    ASSERT_TRUE(loaded) << loaded.error().message;
    const UvTransform& t = loaded->scene.objects[0].material.base_colour_transform;
    // KHR_texture_transform: uv' = T(offset) R(rotation) S(scale) uv, R = [cos, sin; -sin, cos].
    const float want[6] = {std::cos(r) * sx, std::sin(r) * sy, ox, -std::sin(r) * sx, std::cos(r) * sy, oy};
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(t.m[i], want[i], 2e-6f) << i;
}

TEST(GltfMaterials, AlphaModesAndUnlit) {
    const fs::path dir = test_temp_dir("facet_materials");
    GltfDocument doc;
    doc.extensions_used = {"KHR_materials_unlit"};
    GltfMaterial mask, blend, unlit;
    mask.alpha_mode = "MASK";
    mask.alpha_cutoff = 0.3f;
    blend.alpha_mode = "BLEND";
    unlit.extensions = R"({"KHR_materials_unlit":{}})";
    doc.materials = {mask, blend, unlit};
    for (int i = 0; i < 3; ++i) doc.nodes.push_back({facing_quad(), i, {2.0f * static_cast<float>(i), 0, 0}});
    const Result<LoadedModel> r = load_model(write_gltf(dir / "alpha.gltf", doc));
    ASSERT_TRUE(r) << r.error().message;
    ASSERT_EQ(r->scene.objects.size(), 3u);
    EXPECT_EQ(r->scene.objects[0].material.alpha_mode, AlphaMode::mask);
    EXPECT_FLOAT_EQ(r->scene.objects[0].material.alpha_cutoff, 0.3f);
    EXPECT_EQ(r->scene.objects[1].material.alpha_mode, AlphaMode::blend);
    EXPECT_FALSE(r->scene.objects[1].material.unlit);
    EXPECT_TRUE(r->scene.objects[2].material.unlit);
}

// OBJ/MTL: Kd is the base colour, metallic 0, roughness from Ns (or 1 for a black Ks), map_Kd the
// base-colour texture, map_Ke the emissive one, norm the normal map.
TEST(ObjMaterials, PhongTermsMapOntoMetallicRoughness) {
    const fs::path dir = test_temp_dir("facet_materials");
    ASSERT_TRUE(write_png((dir / "albedo.png").string(), flat_image({10, 20, 30, 255})));
    ASSERT_TRUE(write_png((dir / "glow.png").string(), flat_image({40, 50, 60, 255})));
    ASSERT_TRUE(write_png((dir / "bumps.png").string(), flat_image({128, 128, 255, 255})));
    write_file(dir / "m.mtl",
               "newmtl shiny\nKd 0.5 0.25 0.125\nKs 0.5 0.5 0.5\nNs 254\nmap_Kd albedo.png\nmap_Ke glow.png\nnorm bumps.png\n"
               "newmtl matte\nKd 0.2 0.2 0.2\nKs 0 0 0\nNs 100\n");
    write_file(dir / "m.obj",
               "mtllib m.mtl\nv -1 1 0\nv 1 1 0\nv 1 -1 0\nv -1 -1 0\nvt 0 1\nvt 1 1\nvt 1 0\nvt 0 0\nvn 0 0 1\n"
               "usemtl shiny\nf 1/1/1 4/4/1 3/3/1\nusemtl matte\nf 1/1/1 3/3/1 2/2/1\n");
    const Result<LoadedModel> r = load_model((dir / "m.obj").string());
    ASSERT_TRUE(r) << r.error().message;
    ASSERT_EQ(r->scene.objects.size(), 2u);
    const Material *shiny = nullptr, *matte = nullptr;
    for (const SceneObject& o : r->scene.objects) (o.material.base_colour.x == 0.5f ? shiny : matte) = &o.material;
    ASSERT_TRUE(shiny && matte);
    EXPECT_EQ(shiny->metallic, 0.0f);
    EXPECT_NEAR(shiny->roughness, std::pow(2.0f / 256.0f, 0.25f), 1e-6f);  // (2 / (Ns + 2))^(1/4)
    EXPECT_EQ(matte->roughness, 1.0f);  // no highlight: matte
    ASSERT_TRUE(shiny->base_colour_texture);
    EXPECT_EQ(shiny->base_colour_texture->level(0).at(0, 0).g, 20);
    ASSERT_TRUE(shiny->emissive_map.texture);
    EXPECT_EQ(shiny->emissive_map.texture->level(0).at(0, 0).g, 50);
    expect_vec_near(shiny->emissive, {1, 1, 1}, 0);  // map_Ke alone: the map as it is
    ASSERT_TRUE(shiny->normal_map.texture);
    EXPECT_EQ(matte->normal_map.texture, nullptr);
}

}  // namespace
