// Fuzz target: model files through facet::load_model, the entry point `facet render` and
// `facet thumbs` use, then a tiny render of what loaded (framing, materials, textures, shaders).
// Input: byte 0 picks the format (its extension, from k_formats), the rest is the file. The file is
// written to a per-process temporary directory (assimp reads by path and picks its importer by
// extension), loaded and removed; the directory is removed at exit.
// A finding is a crash, a sanitizer report, or load_model returning neither a model nor an Error
// (it must never throw). Small limits keep each run fast: they are part of what is tested.
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "facet/model.hpp"
#include "facet/renderer.hpp"
#include "facet/scene.hpp"

namespace {

namespace fs = std::filesystem;

// The formats load_model reads that matter most (see the README), then the rest of assimp's.
// The order is the meaning of byte 0: append, never reorder (scripts/fuzz seeds by it, through
// FACET_FUZZ_LIST_FORMATS below).
constexpr const char* k_formats[] = {"obj",  "stl", "ply", "off",     "gltf", "glb", "fbx", "3mf",     "dae", "3ds",
                                     "ase",  "ac",  "x",   "ms3d",    "lwo",  "md2", "md3", "smd",     "nff", "raw",
                                     "b3d",  "cob", "xgl", "amf",     "q3o",  "irrmesh", "ter", "hmp", "mdl", "x3d",
                                     "lws",  "irr", "dxf", "md5mesh", "zgl",  "ogex", "blend", "csm"};
constexpr std::size_t k_format_count = sizeof(k_formats) / sizeof(k_formats[0]);

fs::path g_dir;
// FACET_FUZZ_FORMAT_COUNT=N restricts byte 0 to the first N formats (10: the README's main ones).
std::size_t g_format_count = k_format_count;

void remove_dir() {
    std::error_code ec;
    if (!g_dir.empty()) fs::remove_all(g_dir, ec);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    // For scripts/fuzz: print "<byte> <extension>" per format and stop, so seeds get the right byte 0.
    if (std::getenv("FACET_FUZZ_LIST_FORMATS")) {
        for (std::size_t i = 0; i < k_format_count; ++i) std::printf("%zu %s\n", i, k_formats[i]);
        std::exit(0);
    }
    if (const char* n = std::getenv("FACET_FUZZ_FORMAT_COUNT"))
        g_format_count = std::clamp<std::size_t>(std::strtoul(n, nullptr, 10), 1, k_format_count);
    std::string pattern = (fs::temp_directory_path() / "facet_fuzz_model_XXXXXX").string();
    if (!mkdtemp(pattern.data())) {
        std::perror("load_model_fuzzer: mkdtemp");
        std::abort();
    }
    g_dir = pattern;
    std::atexit(remove_dir);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    const std::string ext = k_formats[data[0] % g_format_count];
    const fs::path file = g_dir / ("model." + ext);
    {
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
        if (!out) std::abort();  // the fuzzer's own temporary directory must be writable
    }
    facet::LoadOptions options;
    options.max_triangles = 200'000;
    options.max_file_bytes = 4 << 20;
    options.texture_limits = {.max_size = 512, .max_pixels = 256 * 256};
    facet::Result<facet::LoadedModel> model = facet::load_model(file.string(), options);
    if (model) {
        // What the command line does next: frame the scene and draw it, here at 24x16.
        static facet::Renderer renderer({.threads = 1});
        static facet::Framebuffer target(24, 16);
        const facet::Scene& scene = model->scene;
        const facet::Camera camera = facet::make_camera(scene, facet::ViewSpec{}, 1.5f);
        facet::RenderSettings settings;
        settings.shading = static_cast<facet::Shading>(data[0] / k_format_count % 7);
        facet::render_scene(renderer, target, scene, camera, settings);
    }
    std::error_code ec;
    fs::remove(file, ec);
    return 0;
}
