// facet_bench_scenes: facet against Mesa llvmpipe, scene by scene, in one run.
//
// For every scene x resolution x thread count: the median frame time of facet (render_scene with
// Shading::lambert: clear + one Renderer::draw per object) and of llvmpipe (glClear + one
// glDrawElements per object + glFinish), same camera, resolution, shading and thread count, after
// a warm-up; the ratio llvmpipe_ms / facet_ms (> 1: facet is faster).
//
// llvmpipe reads LP_NUM_THREADS once per process, so its side runs in a child process per thread
// count: this program re-executes itself (/proc/self/exe) with --llvmpipe-worker T and sends it one
// command per measurement on its stdin; the child answers on its stdout. The two renderers take
// turns on each case, in rounds (--rounds, the order swapped every round), so that a machine whose
// speed drifts from minute to minute (a shared one) slows both alike; each median is over all the
// rounds' frames. Peak memory (VmHWM) of the 1M sphere at 1920x1080 is measured in fresh child
// processes (--memory-worker).
//
//   facet_bench_scenes [--frames N] [--rounds R] [--warmup N] [--threads 1,2] [--sizes 1920x1080,512x512]
//                      [--scenes bunny,armadillo,elephant,sphere1m,quads64,nefertiti,homer] [--markdown FILE]
//                      [--no-memory] [--no-agreement] [--no-llvmpipe]
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bench_scenes.hpp"
#include "facet/renderer.hpp"
#include "facet/scene.hpp"
#include "gl_oracle.hpp"

extern char** environ;

namespace {

using namespace facet;
using namespace facet::bench;
using Clock = std::chrono::steady_clock;

const Vec4 k_background{0.11f, 0.12f, 0.14f, 1.0f};

struct Size {
    int w, h;
    std::string str() const { return std::to_string(w) + "x" + std::to_string(h); }
};

struct Options {
    int frames = 11, rounds = 3, warmup = 3;
    std::vector<int> threads{1, 2};
    std::vector<Size> sizes{{1920, 1080}, {512, 512}};
    std::vector<std::string> scenes{"bunny", "armadillo", "elephant", "sphere1m", "quads64", "nefertiti", "homer"};
    std::string markdown;
    bool memory = true, agreement = true, llvmpipe = true;
    // Child modes.
    int llvmpipe_worker = -1;  // facet thread count whose llvmpipe equivalent to measure
    std::string memory_worker; // "facet" or "llvmpipe"
};

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::stringstream in(s);
    for (std::string item; std::getline(in, item, sep);)
        if (!item.empty()) out.push_back(item);
    return out;
}

constexpr const char* k_usage =
    "usage: facet_bench_scenes [--frames N] [--rounds R] [--warmup N] [--threads 1,2] [--sizes WxH,...]\n"
    "                          [--scenes bunny,armadillo,elephant,sphere1m,quads64,nefertiti,homer] [--markdown FILE]\n"
    "                          [--no-memory] [--no-agreement] [--no-llvmpipe]\n"
    "Renders each scene with facet and with Mesa llvmpipe (EGL, surfaceless) on the same camera, size,\n"
    "shading and thread count, and prints both median frame times and their ratio (llvmpipe / facet),\n"
    "then the peak memory of the 1M-triangle sphere and how far the two images agree. The two take\n"
    "turns on each case, R rounds of N frames each (the order swapped every round); the medians are\n"
    "over all R x N frames.\n"
    "  --frames N        frames per renderer, case and round, default 11\n"
    "  --rounds R        rounds per case, default 3\n"
    "  --warmup N        frames drawn first and not measured, default 3 (and 1 before every round)\n"
    "  --threads LIST    facet thread counts, default 1,2 (llvmpipe: LP_NUM_THREADS 0 for 1, else the same)\n"
    "  --sizes LIST      render sizes, WxH each, default 1920x1080,512x512\n"
    "  --scenes LIST     which scenes, default all seven\n"
    "  --markdown FILE   also write the results as the Markdown of docs/BENCHMARKS.md\n"
    "  --no-memory       skip the peak-memory measurement\n"
    "  --no-agreement    skip the image-agreement measurement\n"
    "  --no-llvmpipe     facet alone (A/B runs of two facet builds; implies --no-memory --no-agreement)\n";

[[noreturn]] void usage_error(const std::string& message) {
    std::cerr << "facet_bench_scenes: " << message << "\n" << k_usage;
    std::exit(2);
}

Options parse(int argc, char** argv) {
    Options o;
    auto value = [&](int& i) -> std::string {
        if (i + 1 >= argc) usage_error(std::string(argv[i]) + " needs a value");
        return argv[++i];
    };
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--help" || a == "-h") {
            std::cout << k_usage;
            std::exit(0);
        }
        if (a == "--frames") o.frames = std::max(1, std::atoi(value(i).c_str()));
        else if (a == "--rounds") o.rounds = std::max(1, std::atoi(value(i).c_str()));
        else if (a == "--warmup") o.warmup = std::max(0, std::atoi(value(i).c_str()));
        else if (a == "--threads") {
            o.threads.clear();
            for (const auto& t : split(value(i), ',')) o.threads.push_back(std::max(1, std::atoi(t.c_str())));
        } else if (a == "--sizes") {
            o.sizes.clear();
            for (const auto& s : split(value(i), ',')) {
                Size sz{};
                if (std::sscanf(s.c_str(), "%dx%d", &sz.w, &sz.h) != 2 || sz.w < 1 || sz.h < 1 || sz.w > 8192 || sz.h > 8192)
                    usage_error("bad size " + s);
                o.sizes.push_back(sz);
            }
        } else if (a == "--scenes") o.scenes = split(value(i), ',');
        else if (a == "--markdown") o.markdown = value(i);
        else if (a == "--no-memory") o.memory = false;
        else if (a == "--no-agreement") o.agreement = false;
        else if (a == "--no-llvmpipe") o.llvmpipe = false, o.memory = false, o.agreement = false;
        else if (a == "--llvmpipe-worker") o.llvmpipe_worker = std::max(1, std::atoi(value(i).c_str()));
        else if (a == "--memory-worker") o.memory_worker = value(i);
        else usage_error("unknown option " + a);
    }
    return o;
}

// ---- scenes ----

struct BenchScene {
    std::string name, label;
    Scene scene;
    bool framed = true;  // automatic framing; otherwise the quad stack's own camera
    Camera camera_for(Size s) const {
        const float aspect = static_cast<float>(s.w) / static_cast<float>(s.h);
        return framed ? frame_scene(scene, 0, 0, radians(45.0f), aspect) : quad_stack_camera();
    }
};

// The quad stack depends on the aspect (each quad overfills the view); the others do not.
Result<BenchScene> make_scene(const std::string& name, Size size) {
    BenchScene b;
    b.name = name;
    static const std::map<std::string, std::string> k_cgal_files = {
        {"bunny", "bunny00.off"}, {"armadillo", "armadillo.off"}, {"elephant", "refined_elephant.off"},
        // Small meshes, where the fixed cost of a frame (clear, stores) is most of it.
        {"nefertiti", "nefertiti.off"}, {"homer", "homer.off"}};
    if (const auto it = k_cgal_files.find(name); it != k_cgal_files.end()) {
        const std::string& file = it->second;
        auto s = load_cgal_mesh(file);
        if (!s) return s.error();
        b.scene = std::move(s.value());
        b.label = file;
    } else if (name == "sphere1m") {
        b.scene.objects.push_back({make_geodesic_sphere(1.0f, k_million_sphere_frequency), Mat4::identity(), {}});
        b.label = "geodesic sphere, f = 224";
    } else if (name == "quads64") {
        b.scene = make_quad_stack(64, static_cast<float>(size.w) / static_cast<float>(size.h));
        b.framed = false;
        b.label = "64 screen-filling quads, back to front";
    } else {
        return Error{ErrorCode::invalid_argument, "unknown scene " + name};
    }
    return b;
}

// Loads each scene once (model files take a while); the quad stack again when the aspect changes.
class SceneCache {
public:
    Result<const BenchScene*> get(const std::string& name, Size size) {
        const float aspect = static_cast<float>(size.w) / static_cast<float>(size.h);
        auto it = scenes_.find(name);
        if (it != scenes_.end() && (it->second.framed || aspect_[name] == aspect)) return &it->second;
        auto b = make_scene(name, size);
        if (!b) return b.error();
        aspect_[name] = aspect;
        scenes_[name] = std::move(b.value());
        return &scenes_[name];
    }

private:
    std::map<std::string, BenchScene> scenes_;
    std::map<std::string, float> aspect_;
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// CPU time of this process so far, every thread, user + system, in ms. Per frame it shows the work
// done: unlike the wall time, it does not grow when other programs take the cores.
double process_cpu_ms() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return (static_cast<double>(u.ru_utime.tv_sec) + static_cast<double>(u.ru_stime.tv_sec)) * 1e3 +
           (static_cast<double>(u.ru_utime.tv_usec) + static_cast<double>(u.ru_stime.tv_usec)) / 1e3;
}

// ---- child: llvmpipe at one thread count ----

// Frames drawn and timed as one measurement of one renderer: wall times, and the process's CPU time.
struct Timed {
    std::vector<double> ms;
    double cpu_ms = 0;
};

template <class Draw>
Timed time_frames(int warmup, int frames, const Draw& draw) {
    for (int i = 0; i < warmup; ++i) draw();
    Timed t;
    const double cpu0 = process_cpu_ms();
    for (int i = 0; i < frames; ++i) {
        const auto t0 = Clock::now();
        draw();
        t.ms.push_back(ms_since(t0));
    }
    t.cpu_ms = process_cpu_ms() - cpu0;
    return t;
}

// Serves the parent's commands on stdin, one per line; the answer to each ends with a DONE line:
//   MEASURE scene WxH warmup frames agree  ->  RESULT scene WxH cpu_ms t1 ... tn, and with agree = 1
//                                             an AGREE line (facet's image against llvmpipe's)
// It starts with INFO lines and READY; ERROR lines say what went wrong.
int run_llvmpipe_worker(const Options& o) {
    const int lp = llvmpipe_threads_for(o.llvmpipe_worker);
    auto created = GlOracle::create({.llvmpipe_threads = lp});
    if (!created) {
        std::cout << "ERROR " << created.error().message << std::endl;
        return 1;
    }
    GlOracle& gl = **created;
    std::cout << "INFO renderer " << gl.renderer() << "\nINFO version " << gl.version() << "\nINFO clip_control "
              << (gl.has_clip_control() ? 1 : 0) << "\nINFO lp_num_threads " << gl.llvmpipe_threads() << "\nREADY"
              << std::endl;
    Renderer agreement_renderer(RendererConfig{.threads = 1});
    SceneCache cache;
    std::string loaded;  // the scene and size the GL objects hold
    for (std::string line; std::getline(std::cin, line);) {
        std::istringstream in(line);
        std::string command, name, size_text;
        int warmup = 0, frames = 0, agree = 0;
        Size size{};
        in >> command >> name >> size_text >> warmup >> frames >> agree;
        if (command != "MEASURE" || std::sscanf(size_text.c_str(), "%dx%d", &size.w, &size.h) != 2) {
            std::cout << "ERROR bad command: " << line << "\nDONE" << std::endl;
            continue;
        }
        auto b = cache.get(name, size);
        if (!b) {
            std::cout << "ERROR " << b.error().message << "\nDONE" << std::endl;
            continue;
        }
        if (loaded != name + " " + size_text) {
            Status s = gl.load((*b)->scene);
            if (s) s = gl.resize(size.w, size.h);
            if (!s) {
                std::cout << "ERROR " << s.error().message << "\nDONE" << std::endl;
                continue;
            }
            loaded = name + " " + size_text;
        }
        const Camera camera = (*b)->camera_for(size);
        const Timed t = time_frames(warmup, frames, [&] {
            gl.draw(camera, k_background);
            gl.finish();
        });
        if (const std::string e = gl.gl_error(); !e.empty()) {
            std::cout << "ERROR GL error " << e << "\nDONE" << std::endl;
            continue;
        }
        std::cout << "RESULT " << name << " " << size_text << " " << t.cpu_ms;
        for (double ms : t.ms) std::cout << " " << ms;
        std::cout << std::endl;
        if (agree) {
            const GlFrame frame = gl.read();
            Framebuffer fb(size.w, size.h);
            RenderSettings settings;
            settings.shading = Shading::lambert;
            settings.background = k_background;
            render_scene(agreement_renderer, fb, (*b)->scene, camera, settings);
            const Agreement a = compare(fb.colour_data(), fb.depth_data(), frame);
            const DepthOutliers d = explain_depth_outliers((*b)->scene, camera, fb, frame, 1e-4);
            for (const std::string& l : d.explained_details) std::cerr << "  sliver: " << name << " " << size_text << " " << l << "\n";
            if (!d.unexplained.empty()) std::cerr << "  UNEXPLAINED depth difference: " << name << " " << size_text << " " << d.unexplained << "\n";
            std::cout << "AGREE " << name << " " << size_text << " " << a.coverage_agreement * 100 << " "
                      << a.only_facet << " " << a.only_gl << " " << a.max_depth_diff << " " << a.depth_over_1e4
                      << " " << a.max_colour_diff << " " << a.mean_colour_diff << " " << a.covered_union << " " << d.explained << std::endl;
        }
        std::cout << "DONE" << std::endl;
    }
    return 0;
}

// ---- child: peak memory of the 1M sphere at 1920x1080 ----

int run_memory_worker(const Options& o) {
    const Size size{1920, 1080};
    const float aspect = static_cast<float>(size.w) / static_cast<float>(size.h);
    const long before_mesh = peak_rss_kib();
    Scene scene;
    scene.objects.push_back({make_geodesic_sphere(1.0f, k_million_sphere_frequency), Mat4::identity(), {}});
    const Camera camera = frame_scene(scene, 0, 0, radians(45.0f), aspect);
    const long with_mesh = peak_rss_kib();
    const int threads = o.threads.empty() ? 2 : o.threads.back();
    if (o.memory_worker == "facet") {
        Renderer renderer(RendererConfig{.threads = threads});
        Framebuffer fb(size.w, size.h);
        RenderSettings settings;
        settings.shading = Shading::lambert;
        settings.background = k_background;
        for (int i = 0; i < 2; ++i) render_scene(renderer, fb, scene, camera, settings);
    } else if (o.memory_worker == "llvmpipe") {
        auto created = GlOracle::create({.llvmpipe_threads = llvmpipe_threads_for(threads)});
        if (!created) {
            std::cout << "ERROR " << created.error().message << std::endl;
            return 1;
        }
        auto frame = (*created)->render(scene, camera, size.w, size.h, k_background);
        if (!frame) {
            std::cout << "ERROR " << frame.error().message << std::endl;
            return 1;
        }
        (*created)->draw(camera, k_background);
        (*created)->finish();
    } else {
        usage_error("--memory-worker takes facet or llvmpipe");
    }
    std::cout << "MEMORY " << o.memory_worker << " " << threads << " " << before_mesh << " " << with_mesh << " "
              << peak_rss_kib() << std::endl;
    return 0;
}

// ---- parent ----

// Runs this program again with `args` and returns its stdout lines; stderr passes through.
std::vector<std::string> run_child(const std::vector<std::string>& args, int& status) {
    int fds[2];
    if (pipe(fds) != 0) {
        status = -1;
        return {};
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&actions, fds[0]);
    posix_spawn_file_actions_addclose(&actions, fds[1]);
    std::vector<std::string> full{"/proc/self/exe"};
    full.insert(full.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : full) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    const int err = posix_spawn(&pid, "/proc/self/exe", &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(fds[1]);
    std::vector<std::string> lines;
    if (err != 0) {
        close(fds[0]);
        status = -1;
        return lines;
    }
    std::string buffer;
    char chunk[4096];
    for (ssize_t n; (n = read(fds[0], chunk, sizeof chunk)) > 0;) buffer.append(chunk, static_cast<std::size_t>(n));
    close(fds[0]);
    int wstatus = 0;
    waitpid(pid, &wstatus, 0);
    status = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1;
    lines = split(buffer, '\n');
    return lines;
}

std::string fixed(double v, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

std::string with_commas(std::size_t n) {
    std::string s = std::to_string(n), out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (i && (s.size() - i) % 3 == 0) out += ',';
        out += s[i];
    }
    return out;
}

struct Row {
    std::string scene, label;
    std::size_t triangles = 0;
    Size size{};
    int threads = 0;
    double facet_ms = 0, facet_min = 0, gl_ms = -1, gl_min = -1;
    double facet_cpu = 0, gl_cpu = 0;  // mean process CPU time per frame, all threads
};

// A child process of this program with pipes to its stdin and from its stdout (stderr passes
// through): the llvmpipe worker, sent one command at a time.
class Child {
public:
    explicit Child(const std::vector<std::string>& args) {
        int to[2], from[2];
        if (pipe(to) != 0) return;
        if (pipe(from) != 0) {
            close(to[0]), close(to[1]);
            return;
        }
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_adddup2(&actions, to[0], STDIN_FILENO);
        posix_spawn_file_actions_adddup2(&actions, from[1], STDOUT_FILENO);
        for (int fd : {to[0], to[1], from[0], from[1]}) posix_spawn_file_actions_addclose(&actions, fd);
        std::vector<std::string> full{"/proc/self/exe"};
        full.insert(full.end(), args.begin(), args.end());
        std::vector<char*> argv;
        for (std::string& x : full) argv.push_back(x.data());
        argv.push_back(nullptr);
        const int err = posix_spawn(&pid_, "/proc/self/exe", &actions, nullptr, argv.data(), environ);
        posix_spawn_file_actions_destroy(&actions);
        close(to[0]), close(from[1]);
        if (err != 0) {
            close(to[1]), close(from[0]);
            pid_ = -1;
            return;
        }
        in_ = fdopen(to[1], "w");
        out_ = fdopen(from[0], "r");
    }
    ~Child() { finish(); }
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;

    bool running() const { return in_ && out_; }
    // Its output lines up to and excluding `last` (or to its end, when it exits first).
    std::vector<std::string> read_until(const std::string& last) {
        std::vector<std::string> lines;
        char buffer[1 << 16];
        while (out_ && std::fgets(buffer, sizeof buffer, out_)) {
            std::string line(buffer);
            while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
            if (line == last) return lines;
            lines.push_back(line);
        }
        lines.push_back("ERROR the llvmpipe worker ended early");
        return lines;
    }
    std::vector<std::string> ask(const std::string& command) {
        if (!running()) return {"ERROR the llvmpipe worker is not running"};
        std::fprintf(in_, "%s\n", command.c_str());
        std::fflush(in_);
        return read_until("DONE");
    }
    // Closes its stdin (it exits) and returns its exit status.
    int finish() {
        if (in_) std::fclose(in_), in_ = nullptr;
        if (out_) std::fclose(out_), out_ = nullptr;
        if (pid_ <= 0) return pid_ == 0 ? 0 : -1;
        int wstatus = 0;
        waitpid(pid_, &wstatus, 0);
        pid_ = 0;
        status_ = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1;
        return status_;
    }
    int status() const { return status_; }

private:
    pid_t pid_ = -1;
    FILE* in_ = nullptr;
    FILE* out_ = nullptr;
    int status_ = 0;
};

// All the frames of one renderer on one case, over the rounds.
struct Samples {
    std::vector<double> ms;
    double cpu_ms = 0;
    void add(const Timed& t) {
        ms.insert(ms.end(), t.ms.begin(), t.ms.end());
        cpu_ms += t.cpu_ms;
    }
};

int run_parent(const Options& o) {
    std::map<std::string, Row> rows;  // key: scene|size|threads
    auto key = [](const std::string& scene, const std::string& size, int threads) {
        return scene + "|" + size + "|" + std::to_string(threads);
    };

    // Per thread count: facet in this process, llvmpipe in a worker, taking turns on every case.
    std::map<std::string, std::string> info;
    std::vector<std::string> agreement_lines;
    bool gl_ok = true;
    SceneCache cache;
    for (std::size_t ti = 0; ti < o.threads.size(); ++ti) {
        const int t = o.threads[ti];
        Renderer renderer(RendererConfig{.threads = t});
        std::optional<Child> child;
        if (o.llvmpipe) child.emplace(std::vector<std::string>{"--llvmpipe-worker", std::to_string(t)});
        bool worker_ok = child && child->running();
        for (const std::string& line : child ? child->read_until("READY") : std::vector<std::string>{}) {
            std::istringstream in(line);
            std::string tag, k, rest;
            in >> tag;
            if (tag == "INFO") {
                in >> k;
                std::getline(in, rest);
                info[k + (k == "lp_num_threads" ? std::to_string(t) : "")] = rest.empty() ? rest : rest.substr(1);
            } else if (tag == "ERROR") {
                std::cerr << "facet_bench_scenes: llvmpipe: " << line.substr(6) << "\n";
                worker_ok = false;
            }
        }
        gl_ok = gl_ok && worker_ok;
        for (const std::string& name : o.scenes)
            for (const Size& size : o.sizes) {
                auto b = cache.get(name, size);
                if (!b) {
                    std::cerr << "facet_bench_scenes: " << b.error().message << "\n";
                    return 1;
                }
                Framebuffer fb(size.w, size.h);
                RenderSettings settings;
                settings.shading = Shading::lambert;
                settings.background = k_background;
                const Camera camera = (*b)->camera_for(size);
                settings.keep_depth = false;  // nothing reads it (the agreement frame draws its own)
                const auto draw_facet = [&] { render_scene(renderer, fb, (*b)->scene, camera, settings); };
                Samples facet, gl;
                bool have_gl = worker_ok;
                // llvmpipe's side of one round; the agreement once, with the last round's frame.
                auto gl_round = [&](int round, int warmup) {
                    if (!have_gl) return;
                    const bool agree = o.agreement && ti == 0 && round == o.rounds - 1;
                    const std::string command = "MEASURE " + name + " " + size.str() + " " + std::to_string(warmup) + " " +
                                                std::to_string(o.frames) + " " + (agree ? "1" : "0");
                    bool got = false;
                    for (const std::string& line : child->ask(command)) {
                        std::istringstream in(line);
                        std::string tag, n, sz;
                        in >> tag;
                        if (tag == "RESULT") {
                            Timed r;
                            in >> n >> sz >> r.cpu_ms;
                            for (double ms; in >> ms;) r.ms.push_back(ms);
                            gl.add(r);
                            got = !r.ms.empty();
                        } else if (tag == "AGREE") {
                            agreement_lines.push_back(line.substr(6));
                        } else if (tag == "ERROR") {
                            std::cerr << "facet_bench_scenes: llvmpipe: " << line.substr(6) << "\n";
                        }
                    }
                    if (!got) have_gl = false, gl_ok = false;
                };
                for (int round = 0; round < o.rounds; ++round) {
                    // The first round warms up with --warmup frames, later ones with one frame each,
                    // since the other renderer has just had the caches.
                    const int warmup = round == 0 ? o.warmup : 1;
                    if (round % 2 == 1) gl_round(round, warmup);
                    facet.add(time_frames(warmup, o.frames, draw_facet));
                    if (round % 2 == 0) gl_round(round, warmup);
                }
                Row r;
                r.scene = name;
                r.label = (*b)->label;
                r.triangles = (*b)->scene.triangle_count();
                r.size = size;
                r.threads = t;
                r.facet_ms = median(facet.ms);
                r.facet_min = *std::min_element(facet.ms.begin(), facet.ms.end());
                r.facet_cpu = facet.cpu_ms / static_cast<double>(facet.ms.size());
                if (have_gl) {
                    r.gl_ms = median(gl.ms);
                    r.gl_min = *std::min_element(gl.ms.begin(), gl.ms.end());
                    r.gl_cpu = gl.cpu_ms / static_cast<double>(gl.ms.size());
                }
                rows[key(name, size.str(), t)] = r;
                // The fastest frames too: on a shared machine they move less than the medians.
                std::cerr << name << " " << size.str() << " threads " << t << ": facet " << fixed(r.facet_ms, 2)
                          << " ms (min " << fixed(r.facet_min, 3) << "), llvmpipe " << (have_gl ? fixed(r.gl_ms, 2) : "-")
                          << " ms (min " << (have_gl ? fixed(r.gl_min, 3) : "-") << ")\n";
            }
        if (!child) continue;
        if (const int status = child->finish(); status != 0) {
            std::cerr << "facet_bench_scenes: the llvmpipe worker for " << t << " thread(s) exited with " << status << "\n";
            gl_ok = false;
        }
    }

    // Peak memory, each in a fresh process.
    std::vector<std::string> memory_lines;
    if (o.memory) {
        for (const char* who : {"facet", "llvmpipe"}) {
            int status = 0;
            for (const std::string& line :
                 run_child({"--memory-worker", who, "--threads", std::to_string(o.threads.back())}, status))
                if (line.rfind("MEMORY ", 0) == 0) memory_lines.push_back(line.substr(7));
                else if (line.rfind("ERROR ", 0) == 0) std::cerr << "facet_bench_scenes: memory: " << line.substr(6) << "\n";
        }
    }

    // Report.
    std::ostringstream md;
    md << "Renderer: facet " << "(this build) vs " << info["renderer"] << ", " << info["version"]
       << (info["clip_control"] == "1" ? ", glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE)" : "") << ".  \n";
    md << "Frames: median of " << o.rounds * o.frames << " per renderer and case: " << o.rounds << " rounds of " << o.frames
       << ", the two renderers taking turns (the order swapped every round), after " << o.warmup
       << " warm-up frames (1 before each later round). facet frame = render_scene (clear + Renderer::draw); llvmpipe frame = glClear + glDrawElements + glFinish.  \n";
    md << "Threads: facet `--threads T`; llvmpipe LP_NUM_THREADS = " << llvmpipe_threads_for(1) << " for T = 1, T for T >= 2";
    for (int t : o.threads) md << " (T=" << t << ": driver saw " << info["lp_num_threads" + std::to_string(t)] << ")";
    md << ".\n\n";
    md << "| scene | triangles | size | threads | facet ms | llvmpipe ms | ratio llvmpipe/facet | facet CPU ms | llvmpipe CPU ms |\n";
    md << "|---|---:|---|---:|---:|---:|---:|---:|---:|\n";
    std::printf("%-10s %10s %10s %3s %10s %12s %8s %10s %12s\n", "scene", "triangles", "size", "thr", "facet_ms", "llvmpipe_ms",
                "ratio", "facet_cpu", "llvmpipe_cpu");
    for (const std::string& name : o.scenes)
        for (const Size& size : o.sizes)
            for (int t : o.threads) {
                const auto it = rows.find(key(name, size.str(), t));
                if (it == rows.end()) continue;
                const Row& r = it->second;
                const bool have_gl = r.gl_ms > 0;
                const double ratio = have_gl ? r.gl_ms / r.facet_ms : 0;
                std::printf("%-10s %10zu %10s %3d %10.2f %12s %8s %10.2f %12s\n", r.scene.c_str(), r.triangles,
                            r.size.str().c_str(), r.threads, r.facet_ms, have_gl ? fixed(r.gl_ms, 2).c_str() : "-",
                            have_gl ? fixed(ratio, 3).c_str() : "-", r.facet_cpu, have_gl ? fixed(r.gl_cpu, 2).c_str() : "-");
                md << "| " << r.scene << " (" << r.label << ") | " << with_commas(r.triangles) << " | " << r.size.str() << " | "
                   << r.threads << " | " << fixed(r.facet_ms, 2) << " | " << (have_gl ? fixed(r.gl_ms, 2) : "-") << " | **"
                   << (have_gl ? fixed(ratio, 3) : "-") << "** | " << fixed(r.facet_cpu, 2) << " | "
                   << (have_gl ? fixed(r.gl_cpu, 2) : "-") << " |\n";
            }
    md << "\nms: median wall time of a frame. CPU ms: mean CPU time of the process per frame, all threads "
          "(user + system); with T threads on an otherwise idle machine it is at most T x the wall time, and "
          "a wall time much above CPU ms / T means other programs were taking the cores.\n";
    if (!agreement_lines.empty()) {
        md << "\nAgreement of the benchmarked frames (facet vs llvmpipe, same scene and camera; coverage = depth < 1):\n\n";
        md << "| scene | size | covered (union) | coverage agreement | only facet | only llvmpipe | max depth diff | pixels depth > 1e-4 | of which sliver-explained | max colour diff | mean colour diff |\n";
        md << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
        std::printf("\nagreement (scene size coverage%% only_facet only_llvmpipe max_depth depth>1e-4 max_colour mean_colour union sliver_explained)\n");
        for (const std::string& line : agreement_lines) {
            std::istringstream in(line);
            std::string name, size;
            double cov = 0, maxd = 0, meanc = 0;
            std::size_t of = 0, og = 0, over = 0, uni = 0, explained = 0;
            int maxc = 0;
            in >> name >> size >> cov >> of >> og >> maxd >> over >> maxc >> meanc >> uni >> explained;
            std::printf("  %s\n", line.c_str());
            char depth[32];
            std::snprintf(depth, sizeof depth, "%.2e", maxd);
            md << "| " << name << " | " << size << " | " << with_commas(uni) << " | " << fixed(cov, 4) << "% | " << of << " | "
               << og << " | " << depth << " | " << over << " | " << explained << " | " << maxc << " | " << fixed(meanc, 3) << " |\n";
        }
    }
    if (!memory_lines.empty()) {
        md << "\nPeak memory (VmHWM), geodesic sphere of 1,003,520 triangles at 1920x1080, each in a fresh process:\n\n";
        md << "| renderer | threads | VmHWM at start | after building the mesh | after rendering 2 frames |\n|---|---:|---:|---:|---:|\n";
        std::printf("\npeak memory (renderer threads start_kib mesh_kib peak_kib)\n");
        for (const std::string& line : memory_lines) {
            std::istringstream in(line);
            std::string who;
            int t = 0;
            long a = 0, b = 0, c = 0;
            in >> who >> t >> a >> b >> c;
            std::printf("  %s\n", line.c_str());
            md << "| " << (who == "facet" ? "facet" : "llvmpipe (" + info["renderer"] + ")") << " | " << t << " | "
               << fixed(a / 1024.0, 1) << " MiB | " << fixed(b / 1024.0, 1) << " MiB | " << fixed(c / 1024.0, 1) << " MiB |\n";
        }
    }
    if (!o.markdown.empty()) {
        std::ofstream out(o.markdown);
        out << md.str();
        if (!out) {
            std::cerr << "facet_bench_scenes: cannot write " << o.markdown << "\n";
            return 1;
        }
    }
    return gl_ok || !o.llvmpipe ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    const Options o = parse(argc, argv);
    try {
        if (o.llvmpipe_worker > 0) return run_llvmpipe_worker(o);
        if (!o.memory_worker.empty()) return run_memory_worker(o);
        return run_parent(o);
    } catch (const std::exception& e) {
        std::cerr << "facet_bench_scenes: " << e.what() << "\n";
        return 1;
    }
}
