#include "bench_scenes.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <random>
#include <unordered_map>

#include "bench_data_dir.hpp"
#include "facet/model.hpp"

namespace facet::bench {

namespace fs = std::filesystem;

namespace {
constexpr const char* k_cgal_names[] = {"bunny00.off", "armadillo.off", "refined_elephant.off", "nefertiti.off", "homer.off"};
}

std::optional<fs::path> cgal_mesh_dir() {
    static const std::optional<fs::path> dir = []() -> std::optional<fs::path> {
        const fs::path out = fs::path(k_bench_data_dir) / "cgal";
        const fs::path meshes = out / "data" / "meshes";
        auto present = [&] {
            return std::all_of(std::begin(k_cgal_names), std::end(k_cgal_names),
                               [&](const char* n) { return fs::exists(meshes / n); });
        };
        if (present()) return meshes;
        std::error_code ec;
        if (!fs::exists(k_cgal_data, ec)) return std::nullopt;
        // Tests run as parallel processes: unpack into a private directory, then rename each
        // complete file into place, so no process ever reads a half-written mesh.
        const fs::path staging = out / ("unpack_" + std::to_string(getpid()));
        fs::remove_all(staging, ec);
        fs::create_directories(staging, ec);
        fs::create_directories(meshes, ec);
        std::string cmd = "tar -xzf '" + k_cgal_data.string() + "' -C '" + staging.string() + "'";
        for (const char* n : k_cgal_names) cmd += std::string(" data/meshes/") + n;
        if (std::system(cmd.c_str()) == 0)
            for (const char* n : k_cgal_names) fs::rename(staging / "data" / "meshes" / n, meshes / n, ec);
        fs::remove_all(staging, ec);
        if (!present()) return std::nullopt;
        return meshes;
    }();
    return dir;
}

std::string cgal_missing_message() {
    return k_cgal_data.string() + " is missing or cannot be unpacked: install Debian's libcgal-demo (scripts/setup does)";
}

Result<Scene> load_cgal_mesh(const std::string& file_name) {
    const auto dir = cgal_mesh_dir();
    if (!dir) return Error{ErrorCode::io, cgal_missing_message()};
    auto loaded = load_model((*dir / file_name).string());
    if (!loaded) return loaded.error();
    return std::move(loaded.value().scene);
}

Mesh make_geodesic_sphere(float radius, int frequency) {
    const double t = (1.0 + std::sqrt(5.0)) / 2;
    const std::array<std::array<double, 3>, 12> corner = {{{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                                            {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                                            {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}}};
    const std::uint32_t faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                        {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                        {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                        {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    const int f = std::clamp(frequency, 1, 4095);  // weights fit in 12 bits of the key
    Mesh m;
    m.positions.reserve(10 * static_cast<std::size_t>(f) * f + 2);
    m.normals.reserve(m.positions.capacity());
    m.indices.reserve(60 * static_cast<std::size_t>(f) * f);

    // A point is sum(w_k * corner_k) / f with integer weights summing to f. Points on an edge or at a
    // corner are shared between faces: key them by their (corner, weight) pairs in corner order and
    // compute them in that order, so every face gets the very same vertex.
    std::unordered_map<std::uint64_t, std::uint32_t> shared;
    auto add_point = [&](std::uint32_t c[3], int w[3]) -> std::uint32_t {
        std::array<std::pair<std::uint32_t, int>, 3> terms = {{{c[0], w[0]}, {c[1], w[1]}, {c[2], w[2]}}};
        std::sort(terms.begin(), terms.end());
        const bool on_edge = w[0] == 0 || w[1] == 0 || w[2] == 0;
        std::uint64_t key = 0;
        if (on_edge) {
            for (const auto& [ci, wi] : terms)
                if (wi != 0) key = (key << 16) | (std::uint64_t{ci} << 12) | static_cast<std::uint64_t>(wi);
            if (auto it = shared.find(key); it != shared.end()) return it->second;
        }
        double p[3] = {0, 0, 0};
        for (const auto& [ci, wi] : terms)
            for (int k = 0; k < 3; ++k) p[k] += wi * corner[ci][k];
        const double len = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        const Vec3 n{static_cast<float>(p[0] / len), static_cast<float>(p[1] / len), static_cast<float>(p[2] / len)};
        const auto index = static_cast<std::uint32_t>(m.positions.size());
        m.positions.push_back(n * radius);
        m.normals.push_back(n);
        if (on_edge) shared.emplace(key, index);
        return index;
    };

    std::vector<std::uint32_t> row_prev, row_cur;
    for (const auto& face : faces) {
        std::uint32_t c[3] = {face[0], face[1], face[2]};
        // Row i (0..f) from corner 0 toward the edge 1-2 holds i + 1 points: weights (f - i, i - j, j).
        row_prev.clear();
        for (int i = 0; i <= f; ++i) {
            row_cur.clear();
            for (int j = 0; j <= i; ++j) {
                int w[3] = {f - i, i - j, j};
                row_cur.push_back(add_point(c, w));
            }
            if (i > 0)
                for (int j = 0; j < i; ++j) {
                    // Same winding as the icosahedron's face (c0, c1, c2): outward, counter-clockwise.
                    m.indices.insert(m.indices.end(), {row_prev[j], row_cur[j], row_cur[j + 1]});
                    if (j + 1 < i) m.indices.insert(m.indices.end(), {row_prev[j], row_cur[j + 1], row_prev[j + 1]});
                }
            std::swap(row_prev, row_cur);
        }
    }
    return m;
}

Scene make_quad_stack(int count, float aspect, float overfill) {
    const Camera cam = quad_stack_camera();
    const float tan_half = std::tan(cam.fovy / 2);
    Mesh m;
    for (int q = 0; q < count; ++q) {
        const float z = -0.01f * static_cast<float>(count - 1 - q);  // back to front
        // Scaled with the distance so each quad overfills the view by the same factor.
        const float half_h = overfill * tan_half * (cam.position.z - z), half_w = half_h * aspect;
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (Vec3 p : {Vec3{-half_w, -half_h, z}, Vec3{half_w, -half_h, z}, Vec3{half_w, half_h, z}, Vec3{-half_w, half_h, z}}) {
            m.positions.push_back(p);
            m.normals.push_back({0, 0, 1});
        }
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    Scene s;
    s.objects.push_back({std::move(m), Mat4::identity(), {}});
    return s;
}

Camera quad_stack_camera() {
    Camera c;
    c.fovy = radians(45.0f);
    c.position = {0, 0, 1.0f / std::tan(c.fovy / 2)};  // a [-1, 1] rectangle at z = 0 fills the height
    c.target = {0, 0, 0};
    c.near = 0.1f;
    c.far = 10.0f;
    return c;
}

Scene make_ground_plane(float half_size) {
    Mesh m;
    const float h = half_size;
    m.positions = {{-h, 0, -h}, {-h, 0, h}, {h, 0, h}, {h, 0, -h}};
    m.normals.assign(4, Vec3{0, 1, 0});
    m.indices = {0, 1, 2, 0, 2, 3};
    Scene s;
    s.objects.push_back({std::move(m), Mat4::identity(), {}});
    return s;
}

Camera ground_plane_camera() {
    Camera c;
    c.position = {0.3f, 1.0f, 0.2f};
    c.target = {0.0f, 0.0f, -6.0f};
    c.fovy = radians(45.0f);
    c.near = 0.1f;
    c.far = 100.0f;
    return c;
}

Scene make_jittered_grid(int cells_x, int cells_y, float jitter, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-jitter, jitter);
    Mesh m;
    const float sx = 2.0f / static_cast<float>(cells_x), sy = 1.5f / static_cast<float>(cells_y);
    for (int j = 0; j <= cells_y; ++j)
        for (int i = 0; i <= cells_x; ++i) {
            float x = -1.0f + sx * static_cast<float>(i), y = -0.75f + sy * static_cast<float>(j);
            if (i > 0 && i < cells_x) x += u(rng) * sx;
            if (j > 0 && j < cells_y) y += u(rng) * sy;
            const float z = 0.15f * std::sin(3.0f * x) * std::cos(4.0f * y) + 0.1f * x;
            m.positions.push_back({x, y, z});
        }
    const int row = cells_x + 1;
    for (int j = 0; j < cells_y; ++j)
        for (int i = 0; i < cells_x; ++i) {
            const auto a = static_cast<std::uint32_t>(j * row + i), b = a + 1, c = a + static_cast<std::uint32_t>(row), d = c + 1;
            // Alternate the diagonal so edges run in every direction.
            if ((i + j) % 2 == 0)
                m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
            else
                m.indices.insert(m.indices.end(), {a, b, c, b, d, c});
        }
    compute_smooth_normals(m);
    Scene s;
    s.objects.push_back({std::move(m), Mat4::identity(), {}});
    return s;
}

long peak_rss_kib() {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("VmHWM:", 0) == 0) return std::strtol(line.c_str() + 6, nullptr, 10);
    return -1;
}

}  // namespace facet::bench
