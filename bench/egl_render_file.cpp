// facet_egl_render_file: the llvmpipe side of the whole-process comparison. Loads a model file with
// facet's loader (as `facet render` does), frames it by facet's rule (azimuth 0, elevation 0, fov 45),
// renders it once with Mesa llvmpipe through EGL surfaceless in facet's lambert mode, and writes a PNG.
// The whole process (start, driver load, file load, shader compile, draw, read back, PNG) is what
// scripts/bench times against `facet render MODEL --shading lambert`. With --views N, the dataset
// comparison (`facet render --views orbit:N --passes color,depth,normal,instance`): N views on the
// orbit at elevation 0 from one load and one upload, each drawn once into four attachments, read
// back and written as facet writes those passes: OUT_DIR/color/K.png, OUT_DIR/depth/K.npy (distance
// along the viewing axis, float32, +inf on the background), OUT_DIR/normal/K.npy (world space,
// float32 (H, W, 3)) and OUT_DIR/instance/K.png (object + 1, 16-bit).
//
//   facet_egl_render_file MODEL [-o OUT.png] [--size WxH] [--threads N] [--views N -o OUT_DIR]
//   (--threads N: as facet's; LP_NUM_THREADS = 0 for 1, N otherwise; default: llvmpipe's own)
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <string>

#include <filesystem>

#include "facet/io.hpp"
#include "facet/model.hpp"
#include "facet/scene.hpp"
#include "gl_oracle.hpp"
#if FACET_EGL_VIEWS
#include "pass_files.hpp"  // apps/cli: write_npy
#endif

namespace {

#if FACET_EGL_VIEWS
// --views: every view drawn, read back and written before the next.
int render_views(facet::bench::GlOracle& oracle, const facet::Scene& scene, int views, int width, int height,
                 const std::string& folder) {
    using namespace facet;
    std::error_code ec;
    for (const char* pass : {"color", "depth", "normal", "instance"})
        std::filesystem::create_directories(std::filesystem::path(folder) / pass, ec);
    if (Status s = oracle.load(scene); !s) {
        std::cerr << "facet_egl_render_file: " << s.error().message << "\n";
        return 1;
    }
    if (Status s = oracle.resize(width, height, true); !s) {
        std::cerr << "facet_egl_render_file: " << s.error().message << "\n";
        return 1;
    }
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    std::vector<float> depth;
    std::vector<std::uint16_t> ids;
    for (int k = 0; k < views; ++k) {
        const float azimuth = radians(360.0f * static_cast<float>(k) / static_cast<float>(views));
        const Camera camera = frame_scene(scene, azimuth, 0, radians(45.0f), aspect);
        oracle.draw(camera, RenderSettings{}.background);
        bench::GlFrame frame = oracle.read();
        // Window depth z to the distance along the viewing axis d: z = P22 h + P23 / d (h = -1 for a
        // right-handed camera, which looks down -z), as facet's depth pass gives it.
        const Mat4 p = camera.projection(aspect);
        const float h = camera.handedness == Handedness::right ? -1.0f : 1.0f;
        depth.resize(frame.depth.size());
        ids.resize(frame.instance.size());
        for (std::size_t i = 0; i < depth.size(); ++i) {
            const float z = frame.depth[i];
            depth[i] = z < 1 ? p(2, 3) / (z - p(2, 2) * h) : std::numeric_limits<float>::infinity();
            ids[i] = static_cast<std::uint16_t>(frame.instance[i]);
        }
        char name[32];
        std::snprintf(name, sizeof(name), "%04d", k);
        const std::string base = folder + "/";
        Status s = write_png(base + "color/" + name + ".png", Image{width, height, std::move(frame.colour)});
        if (s) s = cli::write_npy(base + "depth/" + name + ".npy", depth.data(), "<f4", {height, width});
        if (s) s = cli::write_npy(base + "normal/" + name + ".npy", frame.normal.data(), "<f4", {height, width, 3});
        if (s) s = write_png_gray16(base + "instance/" + name + ".png", width, height, ids);
        if (!s) {
            std::cerr << "facet_egl_render_file: " << s.error().message << "\n";
            return 1;
        }
    }
    return 0;
}
#endif

}  // namespace

int main(int argc, char** argv) {
    using namespace facet;
    std::string model, output = "egl.png";
    int width = 800, height = 600, threads = 0, views = 0;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool has_value = i + 1 < argc;
        if ((a == "-o" || a == "--output") && has_value) output = argv[++i];
        else if (a == "--size" && has_value) {
            if (std::sscanf(argv[++i], "%dx%d", &width, &height) != 2 || width < 1 || height < 1 || width > 8192 || height > 8192) {
                std::cerr << "facet_egl_render_file: bad --size\n";
                return 2;
            }
        } else if (a == "--threads" && has_value) threads = std::atoi(argv[++i]);
        else if (a == "--views" && has_value) views = std::atoi(argv[++i]);
        else if (!a.empty() && a[0] != '-' && model.empty()) model = a;
        else {
            std::cerr << "usage: facet_egl_render_file MODEL [-o OUT.png] [--size WxH] [--threads N] [--views N]\n";
            return 2;
        }
    }
    if (model.empty()) {
        std::cerr << "usage: facet_egl_render_file MODEL [-o OUT.png] [--size WxH] [--threads N] [--views N]\n";
        return 2;
    }

    bench::GlOracleOptions options;
    if (threads > 0) options.llvmpipe_threads = bench::llvmpipe_threads_for(threads);
    auto oracle = bench::GlOracle::create(options);
    if (!oracle) {
        std::cerr << "facet_egl_render_file: " << oracle.error().message << "\n";
        return 1;
    }
    auto loaded = load_model(model);
    if (!loaded) {
        std::cerr << "facet_egl_render_file: " << loaded.error().message << "\n";
        return 1;
    }
    const Scene& scene = loaded->scene;
#if FACET_EGL_VIEWS
    if (views > 0) return render_views(**oracle, scene, views, width, height, output);
#else
    if (views > 0) {
        std::cerr << "facet_egl_render_file: --views needs the command line's parts (FACET_BUILD_APPS)\n";
        return 2;
    }
#endif
    const Camera camera = frame_scene(scene, 0, 0, radians(45.0f), static_cast<float>(width) / static_cast<float>(height));
    auto frame = (*oracle)->render(scene, camera, width, height, RenderSettings{}.background);
    if (!frame) {
        std::cerr << "facet_egl_render_file: " << frame.error().message << "\n";
        return 1;
    }
    if (Status s = write_png(output, Image{width, height, std::move(frame->colour)}); !s) {
        std::cerr << "facet_egl_render_file: " << s.error().message << "\n";
        return 1;
    }
    return 0;
}
