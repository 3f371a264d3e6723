// facet_bench_passes: what render passes cost over colour alone, measured in the same run.
//
// For every scene x thread count at one size: the median time of ViewRenderer::render of one view
// into caller memory with colour alone, and with every pass at once (colour, alpha, depth, range,
// normal, instance, material, primitive, uv), after a warm-up; the ratio all / colour (the issue's
// bound: at most 1.5). The two take turns in rounds (the order swapped every round) so that a shared
// machine whose speed drifts slows both alike; each median is over all the rounds' frames.
//
//   facet_bench_passes [--frames N] [--rounds R] [--threads 1,2] [--size 1920x1080]
//                      [--scenes bunny,sphere1m] [--shading lit|lambert|...] [--passes LIST] [--cpu]
//
// --cpu times each frame by the process's CPU time (all its threads) instead of the wall clock: on
// a machine loaded by others, the time this process is not running is left out (what it costs is
// not its latency: with 2 threads it is the sum of both).
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "bench_scenes.hpp"
#include "facet/views.hpp"

namespace {

using namespace facet;
using namespace facet::bench;
using Clock = std::chrono::steady_clock;

struct Options {
    int frames = 11, rounds = 3, width = 1920, height = 1080;
    std::vector<int> threads{1, 2};
    std::vector<std::string> scenes{"bunny", "sphere1m"};
    std::string shading = "lit";
    std::string passes = "color,alpha,depth,range,normal,instance,material,primitive,uv";
    bool cpu = false;
};

double cpu_ms() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream in(s);
    for (std::string item; std::getline(in, item, ',');)
        if (!item.empty()) out.push_back(item);
    return out;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

Result<Scene> load(const std::string& name) {
    if (name == "bunny") return load_cgal_mesh("bunny00.off");
    if (name == "armadillo") return load_cgal_mesh("armadillo.off");
    if (name == "sphere1m") {
        Scene s;
        SceneObject o;
        o.mesh = make_geodesic_sphere(1.0f, k_million_sphere_frequency);
        s.objects.push_back(std::move(o));
        return s;
    }
    return Error{ErrorCode::invalid_argument, "unknown scene '" + name + "' (bunny, armadillo, sphere1m)"};
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool has_value = i + 1 < argc;
        if (a == "--frames" && has_value) o.frames = std::atoi(argv[++i]);
        else if (a == "--rounds" && has_value) o.rounds = std::atoi(argv[++i]);
        else if (a == "--threads" && has_value) {
            o.threads.clear();
            for (const std::string& t : split(argv[++i])) o.threads.push_back(std::atoi(t.c_str()));
        } else if (a == "--size" && has_value) {
            if (std::sscanf(argv[++i], "%dx%d", &o.width, &o.height) != 2) return 2;
        } else if (a == "--scenes" && has_value) o.scenes = split(argv[++i]);
        else if (a == "--shading" && has_value) o.shading = argv[++i];
        else if (a == "--passes" && has_value) o.passes = argv[++i];
        else if (a == "--cpu") o.cpu = true;
        else {
            std::fprintf(stderr,
                         "usage: facet_bench_passes [--frames N] [--rounds R] [--threads 1,2] [--size WxH] "
                         "[--scenes bunny,sphere1m] [--shading MODE] [--passes LIST] [--cpu]\n");
            return a == "--help" ? 0 : 2;
        }
    }
    const Result<PassSet> passes = parse_passes(o.passes);
    if (!passes) {
        std::fprintf(stderr, "facet_bench_passes: %s\n", passes.error().message.c_str());
        return 2;
    }
    ViewRequest colour_only;
    colour_only.width = o.width, colour_only.height = o.height;
    if (!parse_shading(o.shading, colour_only.settings.shading)) return 2;
    ViewRequest all = colour_only;
    all.passes = *passes;

    std::printf("%-10s %7s %9s %12s %12s %7s   (%s, %dx%d, %s; median of %d rounds x %d frames%s)\n", "scene", "threads",
                "triangles", "colour_ms", "passes_ms", "ratio", o.passes.c_str(), o.width, o.height, o.shading.c_str(),
                o.rounds, o.frames, o.cpu ? "; CPU time" : "");
    for (const std::string& name : o.scenes) {
        Result<Scene> scene = load(name);
        if (!scene) {
            std::fprintf(stderr, "facet_bench_passes: %s\n", scene.error().message.c_str());
            return 1;
        }
        const float aspect = static_cast<float>(o.width) / static_cast<float>(o.height);
        const Camera cameras[] = {frame_scene(*scene, 0, 0, radians(45.0f), aspect)};
        ViewImages images;
        images.width = o.width, images.height = o.height;
        const std::size_t n = static_cast<std::size_t>(o.width) * static_cast<std::size_t>(o.height);
        images.colour.resize(n), images.alpha.resize(n), images.depth.resize(n), images.range.resize(n);
        images.normal.resize(n), images.instance.resize(n), images.material.resize(n), images.primitive.resize(n);
        images.uv.resize(n);
        const PassImages out[] = {images.images()};
        for (int threads : o.threads) {
            ViewRenderer renderer({.threads = threads});
            std::vector<double> colour_ms, passes_ms;
            auto time = [&](const ViewRequest& r, std::vector<double>& into, int frames) {
                for (int f = 0; f < frames; ++f) {
                    const Clock::time_point start = Clock::now();
                    const double cpu_start = cpu_ms();
                    renderer.render(*scene, cameras, r, out);
                    into.push_back(o.cpu ? cpu_ms() - cpu_start
                                         : std::chrono::duration<double, std::milli>(Clock::now() - start).count());
                }
            };
            std::vector<double> warm;
            time(colour_only, warm, 3);
            time(all, warm, 3);
            for (int round = 0; round < o.rounds; ++round) {
                if (round % 2 == 0) {
                    time(colour_only, colour_ms, o.frames);
                    time(all, passes_ms, o.frames);
                } else {
                    time(all, passes_ms, o.frames);
                    time(colour_only, colour_ms, o.frames);
                }
            }
            const double c = median(colour_ms), p = median(passes_ms);
            std::printf("%-10s %7d %9zu %12.2f %12.2f %7.3f\n", name.c_str(), threads, scene->triangle_count(), c, p,
                        p / c);
            std::fflush(stdout);
        }
    }
    return 0;
}
