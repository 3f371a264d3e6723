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
        ASSERT_EQ(!x.material.base_colour_texture, !y.material.base_colour_texture);
        if (const Texture* t = x.material.base_colour_texture.get()) {
            const Texture& u = *y.material.base_colour_texture;
            ASSERT_EQ(t->level_count(), u.level_count());
            for (int l = 0; l < t->level_count(); ++l)
                EXPECT_TRUE(same_bytes(t->level(l).pixels, u.level(l).pixels)) << "mip level " << l;
        }
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
    for (const auto& e : fs::directory_iterator(fs::path(FACET_SOURCE_DIR) / "tests" / "regression" / "assimp_crashes"))
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
