// facet benchmarks: points and lines against llvmpipe (issue 26). A cloud of N points on a sphere
// (with normals, drawn in the lambert mode: facet's LambertBaseColour per splat, the oracle's lambert
// shader per GL_POINTS fragment), and M line segments (random short chords around the sphere, GL_LINES),
// at one size and thread count per process (llvmpipe reads LP_NUM_THREADS once per process):
//   facet_bench_points --threads T [--points N] [--segments M] [--size WxH] [--frames F]
//                      [--point-size PX] [--line-width PX] [--line-aa 1] [--facet-only 1]
// Each frame is a whole render_scene (clear, draw) against glClear + glDrawElements + glFinish;
// facet and llvmpipe alternate frame by frame after a warm-up of each, and the medians are printed
// with their ratio as one Markdown table row per workload. Square points (GL_POINTS are squares).
// --line-aa 1: anti-aliased lines (PrimitiveStyle::line_aa) against GL_LINES blended without depth
// writes (GL_LINE_SMOOTH, the true peer, crashes llvmpipe 22.3 compiling the oracle's shader).
// --facet-only 1 draws facet's frames alone (for profilers: callgrind on llvmpipe takes minutes), with
// the median CPU time of a frame beside the wall time.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include "facet/scene.hpp"
#include "gl_oracle.hpp"

namespace {

using namespace facet;
using namespace facet::bench;
using Clock = std::chrono::steady_clock;

struct Options {
    int threads = 1, width = 1920, height = 1080, frames = 7;
    std::size_t points = 10'000'000, segments = 1'000'000;
    float point_size = 2, line_width = 1;
    bool facet_only = false, line_aa = false;
};

[[noreturn]] void usage(const std::string& why) {
    std::fprintf(stderr, "facet_bench_points: %s\nusage: facet_bench_points --threads T [--points N] [--segments M] "
                         "[--size WxH] [--frames F] [--point-size PX] [--line-width PX] [--line-aa 1] [--facet-only 1]\n", why.c_str());
    std::exit(2);
}

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--help") usage("points and lines against llvmpipe");
        if (i + 1 >= argc) usage(a + " needs a value");
        const std::string v = argv[++i];
        if (a == "--threads") o.threads = std::stoi(v);
        else if (a == "--points") o.points = std::stoull(v);
        else if (a == "--segments") o.segments = std::stoull(v);
        else if (a == "--frames") o.frames = std::stoi(v);
        else if (a == "--point-size") o.point_size = std::stof(v);
        else if (a == "--line-width") o.line_width = std::stof(v);
        else if (a == "--facet-only") o.facet_only = v == "1";
        else if (a == "--line-aa") o.line_aa = v == "1";
        else if (a == "--size") {
            if (std::sscanf(v.c_str(), "%dx%d", &o.width, &o.height) != 2) usage("--size must be WxH");
        } else usage("unknown option " + a);
    }
    if (o.threads < 1 || o.frames < 1) usage("--threads and --frames must be at least 1");
    return o;
}

// Points on the unit sphere (uniform), each with its outward normal.
Scene point_cloud(std::size_t n) {
    std::mt19937 rng(26);
    std::uniform_real_distribution<float> u(-1, 1), a(0, 6.2831853f);
    SceneObject o;
    o.mesh.positions.reserve(n);
    o.mesh.normals.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const float z = u(rng), t = a(rng), r = std::sqrt(std::max(0.0f, 1 - z * z));
        const Vec3 p{r * std::cos(t), r * std::sin(t), z};
        o.mesh.positions.push_back(p);
        o.mesh.normals.push_back(p);
        o.mesh.points.push_back(static_cast<std::uint32_t>(i));
    }
    Scene s;
    s.objects.push_back(std::move(o));
    return s;
}

// Segments between nearby points on the unit sphere (a few pixels long at 1080p).
Scene line_set(std::size_t n) {
    std::mt19937 rng(27);
    std::uniform_real_distribution<float> u(-1, 1), a(0, 6.2831853f), d(-0.01f, 0.01f);
    SceneObject o;
    for (std::size_t i = 0; i < n; ++i) {
        const float z = u(rng), t = a(rng), r = std::sqrt(std::max(0.0f, 1 - z * z));
        const Vec3 p{r * std::cos(t), r * std::sin(t), z};
        const Vec3 q = normalize(p + Vec3{d(rng), d(rng), d(rng)});
        for (const Vec3& v : {p, q}) {
            o.mesh.lines.push_back(static_cast<std::uint32_t>(o.mesh.positions.size()));
            o.mesh.positions.push_back(v);
            o.mesh.normals.push_back(v);
        }
    }
    Scene s;
    s.objects.push_back(std::move(o));
    return s;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// The process's CPU time (all threads), ms: under load, steadier than the wall clock for A/B runs.
double cpu_ms() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

void run(const char* name, const Scene& scene, const Options& o, GlOracle* gl) {
    Renderer renderer({.threads = o.threads});
    Framebuffer target(o.width, o.height);
    const float aspect = static_cast<float>(o.width) / static_cast<float>(o.height);
    const Camera camera = frame_scene(scene, 0.3f, 0.2f, radians(45.0f), aspect);
    RenderSettings settings;
    settings.shading = Shading::lambert;
    settings.primitives.point_size = o.point_size;
    settings.primitives.point_shape = PointShape::square;
    settings.primitives.line_width = o.line_width;
    settings.primitives.line_aa = o.line_aa;
    if (gl) {
        if (Status s = gl->load(scene); !s) usage(s.error().message);
        if (Status s = gl->resize(o.width, o.height); !s) usage(s.error().message);
        gl->set_primitive_style(o.point_size, o.line_width, o.line_aa);
    }
    const auto facet_frame = [&] {
        const Clock::time_point t = Clock::now();
        render_scene(renderer, target, scene, camera, settings);
        return ms_since(t);
    };
    const auto gl_frame = [&] {
        const Clock::time_point t = Clock::now();
        gl->draw(camera, settings.background);
        gl->finish();
        return ms_since(t);
    };
    std::vector<double> facet_ms, gl_ms;
    if (!gl) {
        facet_frame();  // warm-up
        std::vector<double> cpu;
        for (int f = 0; f < o.frames; ++f) {
            const double c = cpu_ms();
            facet_ms.push_back(facet_frame());
            cpu.push_back(cpu_ms() - c);
        }
        std::printf("| %s | %dx%d | %d | %.1f (CPU %.1f) | - | - | - |\n", name, o.width, o.height, o.threads,
                    median(facet_ms), median(cpu));
        return;
    }
    facet_frame(), gl_frame();  // warm-up
    for (int f = 0; f < o.frames; ++f) facet_ms.push_back(facet_frame()), gl_ms.push_back(gl_frame());
    const GlFrame frame = gl->read();
    const Agreement agree = compare(target.colour_data(), target.depth_data(), frame);
    const double fm = median(facet_ms), gm = median(gl_ms);
    std::printf("| %s | %dx%d | %d | %.1f | %.1f | %.2fx | %.3f |\n", name, o.width, o.height, o.threads, fm, gm, gm / fm,
                agree.coverage_agreement);
    std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
    const Options o = parse(argc, argv);
    std::unique_ptr<GlOracle> gl;
    if (!o.facet_only) {
        Result<std::unique_ptr<GlOracle>> made = GlOracle::create({.llvmpipe_threads = llvmpipe_threads_for(o.threads)});
        if (!made) usage(made.error().message);
        gl = std::move(*made);
        std::printf("<!-- %s, %s; point size %g, line width %g, %d frames (median) -->\n", gl->renderer().c_str(),
                    gl->version().c_str(), o.point_size, o.line_width, o.frames);
    }
    std::printf("| workload | size | threads | facet ms | llvmpipe ms | llvmpipe / facet | coverage agreement |\n");
    std::printf("|---|---|---|---|---|---|---|\n");
    if (o.points) run((std::to_string(o.points) + " points").c_str(), point_cloud(o.points), o, gl.get());
    if (o.segments)
        run((std::to_string(o.segments) + (o.line_aa ? " segments, anti-aliased" : " segments")).c_str(), line_set(o.segments), o,
            gl.get());
    return 0;
}
