// facet benchmarks: compute_creased_normals on the 1,003,520-triangle geodesic sphere (its normals
// removed), or on a plain OFF file's mesh, the median over rounds of the thread's CPU time (one
// thread: on a shared machine CPU time moves far less with the load than wall time) or of the wall
// time (threads). Prints a checksum of the normals' bits, so that two builds can be compared for
// the same result. Not a stage of the renderer.
// --joined: the mesh's positions are distinct and the welding is left out, as facet's own readers
// call it (compute_creased_normals_on; the OBJ load and the bunny process go this way).
// --threads N: a pool of N started once, before the rounds (the readers' pool).
// --crease: the crease angle in degrees (30; facet render's default is 40).
// Usage: facet_bench_creased [ROUNDS=5] [--joined] [--threads N] [--crease DEGREES=30] [--off FILE]
#include <time.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "bench_scenes.hpp"
#include "facet/detail/thread_pool.hpp"
#include "facet/mesh.hpp"
#include "scene/creased_normals.hpp"

namespace {

double clock_ms(clockid_t clock) {
    timespec t{};
    clock_gettime(clock, &t);
    return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) / 1e6;
}

// A plain OFF file of triangles (no comments, no colours): enough for the CGAL meshes.
std::optional<facet::Mesh> read_off(const std::string& path) {
    std::ifstream in(path);
    std::string magic;
    std::size_t vertices = 0, faces = 0, edges = 0;
    if (!(in >> magic >> vertices >> faces >> edges) || magic != "OFF") return std::nullopt;
    facet::Mesh m;
    m.positions.resize(vertices);
    for (facet::Vec3& p : m.positions)
        if (!(in >> p.x >> p.y >> p.z)) return std::nullopt;
    for (std::size_t f = 0; f < faces; ++f) {
        std::uint32_t n = 0, a = 0, b = 0, c = 0;
        if (!(in >> n >> a >> b >> c) || n != 3) return std::nullopt;
        m.indices.insert(m.indices.end(), {a, b, c});
    }
    // Numbered by first use, as facet's readers' join leaves them (the order matters to the caches).
    std::vector<std::uint32_t> number(vertices, ~0u);
    std::vector<facet::Vec3> used;
    for (std::uint32_t& i : m.indices) {
        if (i >= vertices) return std::nullopt;
        if (number[i] == ~0u) number[i] = static_cast<std::uint32_t>(used.size()), used.push_back(m.positions[i]);
        i = number[i];
    }
    m.positions = std::move(used);
    return m;
}

}  // namespace

int main(int argc, char** argv) {
    int rounds = 5, threads = 1;
    float crease = 30.0f;
    bool joined = false;
    std::string off;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--joined") {
            joined = true;
        } else if (a == "--threads" && i + 1 < argc) {
            threads = std::max(1, std::atoi(argv[++i]));
        } else if (a == "--crease" && i + 1 < argc) {
            crease = static_cast<float>(std::atof(argv[++i]));
        } else if (a == "--off" && i + 1 < argc) {
            off = argv[++i];
        } else if (!a.empty() && a[0] != '-') {
            rounds = std::max(1, std::atoi(a.c_str()));
        } else {
            std::printf("usage: facet_bench_creased [ROUNDS=5] [--joined] [--threads N] [--crease DEGREES=30] [--off FILE]\n"
                        "Times compute_creased_normals on the 1M-triangle sphere or an OFF file's mesh:\n"
                        "median thread CPU ms (1 thread) or wall ms (threads), and a checksum of the normals' bits.\n");
            return a == "--help" ? 0 : 2;
        }
    }
    facet::Mesh mesh;
    if (off.empty()) {
        mesh = facet::bench::make_geodesic_sphere(1.0f, facet::bench::k_million_sphere_frequency);
        mesh.normals.clear();
    } else if (std::optional<facet::Mesh> m = read_off(off)) {
        mesh = std::move(*m);
    } else {
        std::fprintf(stderr, "facet_bench_creased: %s: not a plain OFF file of triangles\n", off.c_str());
        return 1;
    }
    std::optional<facet::detail::ThreadPool> pool;
    if (threads > 1) pool.emplace(threads);
    const clockid_t clock = threads > 1 ? CLOCK_MONOTONIC : CLOCK_THREAD_CPUTIME_ID;
    std::vector<double> ms;
    std::uint64_t checksum = 0, index_checksum = 0;
    for (int r = 0; r < rounds; ++r) {
        facet::Mesh m = mesh;
        const double start = clock_ms(clock);
        if (joined || pool)
            facet::detail::compute_creased_normals_on(m, facet::radians(crease), pool ? &*pool : nullptr, joined);
        else
            facet::compute_creased_normals(m, facet::radians(crease), 1);
        ms.push_back(clock_ms(clock) - start);
        checksum = 0;
        for (const facet::Vec3& n : m.normals)
            checksum = checksum * 31 + std::bit_cast<std::uint32_t>(n.x) + 7 * std::bit_cast<std::uint32_t>(n.y) +
                       13 * std::bit_cast<std::uint32_t>(n.z);
        index_checksum = 0;  // the corners moved to copies of their vertices
        for (const std::uint32_t i : m.indices) index_checksum = index_checksum * 3 + i;
    }
    std::sort(ms.begin(), ms.end());
    std::printf("{\"triangles\":%zu,\"threads\":%d,\"joined\":%s,\"rounds\":%d,\"%s_ms_median\":%.2f,\"%s_ms_min\":%.2f,"
                "\"checksum\":\"%016llx\",\"indices\":\"%016llx\"}\n",
                mesh.triangle_count(), threads, joined ? "true" : "false", rounds, pool ? "wall" : "cpu", ms[ms.size() / 2],
                pool ? "wall" : "cpu", ms.front(), static_cast<unsigned long long>(checksum), static_cast<unsigned long long>(index_checksum));
}
