// load_model_isolated: the same scene as load_model for good files (meshes, materials, shared
// textures, warnings), the same error for bad ones, and for files that crash, hang or exhaust
// memory inside assimp an Error while this test process goes on.
#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "facet/model.hpp"
#include "support/gltf_writer.hpp"
#include "support/paths.hpp"
#include "support/test_data.hpp"

namespace {

using namespace facet;
namespace fs = std::filesystem;

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool k_sanitized = true;  // a sanitizer reports the reader's crash itself (exit 99)
#else
constexpr bool k_sanitized = false;
#endif

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

void expect_same_texture(const Texture* t, const Texture* u) {
    ASSERT_EQ(!t, !u);
    if (!t) return;
    ASSERT_EQ(t->level_count(), u->level_count());
    for (int l = 0; l < t->level_count(); ++l) EXPECT_TRUE(same_bytes(t->level(l).pixels, u->level(l).pixels)) << "mip level " << l;
}

void expect_same_model(const LoadedModel& a, const LoadedModel& b) {
    ASSERT_EQ(a.scene.objects.size(), b.scene.objects.size());
    for (std::size_t i = 0; i < a.scene.objects.size(); ++i) {
        SCOPED_TRACE("object " + std::to_string(i));
        const SceneObject &x = a.scene.objects[i], &y = b.scene.objects[i];
        EXPECT_TRUE(same_bytes(x.mesh.positions, y.mesh.positions));
        EXPECT_TRUE(same_bytes(x.mesh.normals, y.mesh.normals));
        EXPECT_TRUE(same_bytes(x.mesh.colours, y.mesh.colours));
        EXPECT_TRUE(same_bytes(x.mesh.uvs, y.mesh.uvs));
        EXPECT_TRUE(same_bytes(x.mesh.indices, y.mesh.indices));
        EXPECT_EQ(std::memcmp(&x.model, &y.model, sizeof(Mat4)), 0);
        EXPECT_EQ(std::memcmp(&x.material.base_colour, &y.material.base_colour, sizeof(Vec4)), 0);
        EXPECT_EQ(x.material.alpha_mode, y.material.alpha_mode);
        EXPECT_EQ(x.material.alpha_cutoff, y.material.alpha_cutoff);
        EXPECT_EQ(x.material.double_sided, y.material.double_sided);
        EXPECT_EQ(x.material.sampler.filter, y.material.sampler.filter);
        EXPECT_TRUE(same_bytes(x.mesh.tangents, y.mesh.tangents));
        const Material &p = x.material, &q = y.material;
        EXPECT_EQ(std::memcmp(&p.base_colour_transform, &q.base_colour_transform, sizeof(UvTransform)), 0);
        EXPECT_EQ(p.metallic, q.metallic);
        EXPECT_EQ(p.roughness, q.roughness);
        EXPECT_EQ(p.normal_scale, q.normal_scale);
        EXPECT_EQ(p.occlusion_strength, q.occlusion_strength);
        EXPECT_EQ(std::memcmp(&p.emissive, &q.emissive, sizeof(Vec3)), 0);
        EXPECT_EQ(p.unlit, q.unlit);
        const std::pair<const TextureMap*, const TextureMap*> maps[] = {
            {&p.metallic_roughness_map, &q.metallic_roughness_map}, {&p.normal_map, &q.normal_map},
            {&p.occlusion_map, &q.occlusion_map}, {&p.emissive_map, &q.emissive_map}};
        for (const auto& [m, n] : maps) {
            EXPECT_EQ(std::memcmp(&m->sampler, &n->sampler, sizeof(Sampler)), 0);
            EXPECT_EQ(std::memcmp(&m->transform, &n->transform, sizeof(UvTransform)), 0);
            expect_same_texture(m->texture.get(), n->texture.get());
        }
        expect_same_texture(p.base_colour_texture.get(), q.base_colour_texture.get());
    }
    EXPECT_EQ(a.warnings, b.warnings);
}

TEST(IsolatedLoader, GoodFilesGiveTheSceneLoadModelGives) {
    FACET_REQUIRE_ASSIMP_MODELS();
    int textured = 0;
    for (const char* file : {"glTF2/BoxTextured-glTF/BoxTextured.gltf", "OBJ/spider.obj", "PLY/cube.ply",
                             "STL/Spider_binary.stl"}) {
        SCOPED_TRACE(file);
        const std::string path = (facet_test::k_assimp_models / file).string();
        const Result<LoadedModel> direct = load_model(path);
        const Result<LoadedModel> isolated = load_model_isolated(path);
        ASSERT_TRUE(direct) << direct.error().message;
        ASSERT_TRUE(isolated) << isolated.error().message;
        EXPECT_FALSE(isolated->scene.objects.empty());
        expect_same_model(*isolated, *direct);
        for (const SceneObject& o : isolated->scene.objects) textured += o.material.base_colour_texture != nullptr;
    }
    EXPECT_GT(textured, 0);  // the texture path was taken
}

TEST(IsolatedLoader, EveryMaterialValueTextureAndTangentComesBack) {
    const fs::path dir = facet_test::test_temp_dir("facet_isolated");
    facet_test::GltfDocument doc;
    for (std::uint8_t i = 0; i < 5; ++i)
        doc.images.push_back(Image{2, 2, std::vector<Rgba8>(4, Rgba8{static_cast<std::uint8_t>(40 * i), 7, 9, 255})});
    doc.extensions_used = {"KHR_texture_transform"};
    facet_test::GltfMaterial m;
    m.metallic = 0.3f, m.roughness = 0.6f, m.normal_scale = 0.5f, m.occlusion_strength = 0.7f;
    m.emissive[1] = 0.25f;
    m.base_colour_texture.image = 0;
    m.base_colour_texture.extensions = R"({"KHR_texture_transform":{"offset":[0.5,0.25],"scale":[2,2]}})";
    m.metallic_roughness_texture.image = 1;
    m.normal_texture.image = 2;
    m.normal_texture.wrap_s = 33648;
    m.occlusion_texture.image = 3;
    m.emissive_texture.image = 4;
    doc.materials = {m};
    Mesh sphere = make_uv_sphere(1, 8, 6);
    doc.nodes.push_back({sphere, 0, {}});
    const std::string path = facet_test::write_gltf(dir / "slots.gltf", doc);
    const Result<LoadedModel> direct = load_model(path);
    const Result<LoadedModel> isolated = load_model_isolated(path);
    ASSERT_TRUE(direct) << direct.error().message;
    ASSERT_TRUE(isolated) << isolated.error().message;
    ASSERT_FALSE(direct->scene.objects[0].mesh.tangents.empty());
    ASSERT_TRUE(direct->scene.objects[0].material.emissive_map.texture);
    ASSERT_FALSE(direct->scene.objects[0].material.base_colour_transform.is_identity());
    expect_same_model(*isolated, *direct);
}

TEST(IsolatedLoader, ErrorsOfTheReaderComeBackUnchanged) {
    const fs::path dir = facet_test::test_temp_dir("facet_isolated");
    const std::string missing = (dir / "missing.obj").string();
    std::FILE* f = std::fopen((dir / "garbage.stl").string().c_str(), "wb");
    std::fputs("solid x\nfacet normal 0 0 nonsense\n", f);
    std::fclose(f);
    for (const std::string& path : {missing, (dir / "garbage.stl").string()}) {
        const Result<LoadedModel> direct = load_model(path);
        const Result<LoadedModel> isolated = load_model_isolated(path);
        ASSERT_FALSE(direct);
        ASSERT_FALSE(isolated);
        EXPECT_EQ(isolated.error().code, direct.error().code);
        EXPECT_EQ(isolated.error().message, direct.error().message);
    }
}

// The inputs of tests/regression/assimp_crashes/ (the same the command line's isolation tests use).
std::vector<fs::path> crash_inputs() {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(fs::path(facet_test::k_source_dir) / "tests" / "regression" / "assimp_crashes"))
        files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files;
}

TEST(IsolatedLoader, FilesThatCrashHangOrExhaustTheReaderAreErrorsAndThisProcessGoesOn) {
    const std::vector<fs::path> inputs = crash_inputs();
    ASSERT_GE(inputs.size(), 16u);
    int crashed = 0, out_of_memory = 0, hung = 0;
    for (const fs::path& input : inputs) {
        const std::string name = input.filename().string();
        SCOPED_TRACE(name);
        const bool hangs = name.find("_hang_") != std::string::npos;
        const bool allocates = name.find("out-of-memory") != std::string::npos;
        // Under a sanitizer there is no memory cap (shadow memory) and TSan misses the double free.
        if (k_sanitized && (allocates || name.find("double-free") != std::string::npos)) continue;
        IsolationLimits limits;
        limits.timeout_seconds = hangs ? 1.5 : 120;
        limits.max_memory_bytes = k_sanitized ? 0 : std::uint64_t{1} << 30;
        const Result<LoadedModel> r = load_model_isolated(input.string(), {}, limits);
        // Some of these bugs read memory they do not own, so whether they crash depends on the heap
        // the child inherits: x_segv_*.x crashes in a fresh process but loads after this process
        // has loaded other models. Either way this process must go on; the counts below require
        // most of them to crash.
        if (r) {
            EXPECT_FALSE(hangs || allocates) << "only a crash can depend on the heap";
            continue;
        }
        const std::string& m = r.error().message;
        EXPECT_EQ(m.rfind(input.string() + ": ", 0), 0u) << m;  // names the file
        if (hangs) {
            EXPECT_EQ(r.error().code, ErrorCode::limit_exceeded);
            EXPECT_NE(m.find("gave up after 1.5 s"), std::string::npos) << m;
            ++hung;
        } else if (!k_sanitized) {
            const bool crash = m.find(": the importer crashed (SIG") != std::string::npos;
            const bool memory = m.find(": needs more memory than is available") != std::string::npos;
            EXPECT_TRUE(crash || memory) << m;
            crashed += crash;
            out_of_memory += memory;
        }
    }
    EXPECT_EQ(hung, 1);
    if (!k_sanitized) {
        EXPECT_GE(crashed, 10);
        EXPECT_GE(out_of_memory, 3);
    }
}

TEST(IsolatedLoader, DescribeSignalNamesTheSignal) {
    EXPECT_EQ(describe_signal(SIGSEGV).rfind("SIGSEGV: ", 0), 0u) << describe_signal(SIGSEGV);
    EXPECT_EQ(describe_signal(SIGKILL).rfind("SIGKILL", 0), 0u);
}

}  // namespace
