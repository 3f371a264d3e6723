// `facet render`: one model (or the default scene) to a PNG, optionally a depth PNG and timings.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "facet/io.hpp"
#include "options.hpp"

namespace facet::cli {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Window depth in [0, 1] to 16 bits: round(d * 65535); the background (depth 1) is 65535.
std::vector<std::uint16_t> depth_to_u16(const std::vector<float>& depth) {
    std::vector<std::uint16_t> out(depth.size());
    for (std::size_t i = 0; i < depth.size(); ++i)
        out[i] = static_cast<std::uint16_t>(std::lround(std::clamp(depth[i], 0.0f, 1.0f) * 65535.0f));
    return out;
}

void print_benchmark(std::vector<double> frame_ms, double load_ms, std::size_t triangles, int threads, int w, int h) {
    std::sort(frame_ms.begin(), frame_ms.end());
    const std::size_t n = frame_ms.size();
    const double median = n % 2 ? frame_ms[n / 2] : (frame_ms[n / 2 - 1] + frame_ms[n / 2]) / 2;
    std::printf("{\"frames\":%zu,\"median_ms\":%.3f,\"min_ms\":%.3f,\"max_ms\":%.3f,\"load_ms\":%.3f,"
                "\"triangles\":%zu,\"threads\":%d,\"width\":%d,\"height\":%d}\n",
                n, median, frame_ms.front(), frame_ms.back(), load_ms, triangles, threads, w, h);
    std::fflush(stdout);
}

}  // namespace

int run_render(const std::string& model, const std::string& output, const std::string& depth_out, int benchmark_frames,
               const RenderOptions& options, bool camera_options_given) {
    Result<RenderPlan> plan = make_plan(options, camera_options_given || !model.empty());
    if (!plan) {
        std::fprintf(stderr, "facet render: %s\n", plan.error().message.c_str());
        return k_exit_usage;
    }
    if (benchmark_frames < 0) {
        std::fprintf(stderr, "facet render: --benchmark must be 1 or more frames\n");
        return k_exit_usage;
    }
    const Clock::time_point load_start = Clock::now();
    Result<Scene> scene = load_scene(model, *plan, "facet render");
    if (!scene) {
        std::fprintf(stderr, "facet render: %s\n", scene.error().message.c_str());
        return k_exit_failed;
    }
    const double load_ms = ms_since(load_start);

    Renderer renderer({.threads = options.threads});
    Framebuffer target(plan->width * plan->ssaa, plan->height * plan->ssaa);
    Image colour;
    std::vector<float> depth;
    std::vector<float>* depth_ptr = depth_out.empty() ? nullptr : &depth;

    const Clock::time_point render_start = Clock::now();
    DrawStats stats = render_plan(renderer, *scene, *plan, target, colour, depth_ptr);
    double render_ms = ms_since(render_start);
    if (benchmark_frames > 0) {
        // The first frame above was the warm-up; time the next ones.
        std::vector<double> frames;
        for (int i = 0; i < benchmark_frames; ++i) {
            const Clock::time_point start = Clock::now();
            stats = render_plan(renderer, *scene, *plan, target, colour, depth_ptr);
            frames.push_back(ms_since(start));
        }
        print_benchmark(frames, load_ms, scene->triangle_count(), renderer.threads(), plan->width, plan->height);
    }

    if (stats.triangles_in > 0 && stats.triangles_invalid == stats.triangles_in) {
        std::fprintf(stderr, "facet render: %s: no valid triangles to draw\n", model.c_str());
        return k_exit_failed;
    }
    if (Status s = write_png(output, colour); !s) {
        std::fprintf(stderr, "facet render: %s\n", s.error().message.c_str());
        return k_exit_failed;
    }
    if (depth_ptr) {
        if (Status s = write_png_gray16(depth_out, plan->width, plan->height, depth_to_u16(depth)); !s) {
            std::fprintf(stderr, "facet render: %s\n", s.error().message.c_str());
            // A failed run leaves no output behind: take back the colour image just written
            // (only a regular file: -o may name a device such as /dev/null).
            std::error_code ec;
            if (std::filesystem::is_regular_file(output, ec)) std::filesystem::remove(output, ec);
            return k_exit_failed;
        }
    }
    std::fprintf(stderr, "facet render: %s (%dx%d, %zu triangles, load %.1f ms, render %.1f ms, %d threads)\n",
                 output.c_str(), plan->width, plan->height, scene->triangle_count(), load_ms, render_ms,
                 renderer.threads());
    return k_exit_ok;
}

}  // namespace facet::cli
