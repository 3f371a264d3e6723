#include "support/test_data.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <iomanip>
#include <iterator>
#include <sstream>

#include "support/paths.hpp"

namespace facet_test {

namespace fs = std::filesystem;

std::optional<fs::path> cgal_meshes() {
    static const std::optional<fs::path> dir = []() -> std::optional<fs::path> {
        const fs::path out = fs::path(k_binary_dir) / "test_data" / "cgal";
        const fs::path meshes = out / "data" / "meshes";
        const char* names[] = {"bunny00.off", "armadillo.off", "elephant.off",
                               // OFF's other forms, for the OFF reader's tests (small files)
                               "sphere966.off", "dino.off", "cactus.off", "plane.off", "3torus.off", "corner_poly.off",
                               "double-torus-example.off", "P.off", "torus_quad.off", "mpi.off"};
        auto present = [&] {
            return std::all_of(std::begin(names), std::end(names), [&](const char* n) { return fs::exists(meshes / n); });
        };
        if (present()) return meshes;
        if (!fs::exists(k_cgal_data)) return std::nullopt;
        // CTest runs tests as separate processes in parallel: unpack into a private directory and
        // rename each complete file into place, so no process ever reads a half-written mesh.
        const fs::path staging = out / ("unpack_" + std::to_string(getpid()));
        std::error_code ec;
        fs::remove_all(staging, ec);
        fs::create_directories(staging);
        fs::create_directories(meshes);
        std::string cmd = "tar -xzf '" + k_cgal_data.string() + "' -C '" + staging.string() + "'";
        for (const char* n : names) cmd += std::string(" data/meshes/") + n;
        if (std::system(cmd.c_str()) == 0)
            for (const char* n : names) fs::rename(staging / "data" / "meshes" / n, meshes / n, ec);
        fs::remove_all(staging, ec);
        if (!present()) return std::nullopt;
        return meshes;
    }();
    return dir;
}

std::string assimp_models_missing() {
    return k_assimp_models.string() + " is missing: install Debian's assimp-testmodels (scripts/setup does)";
}

std::string cgal_meshes_missing() {
    return k_cgal_data.string() +
           " is missing or cannot be unpacked: install Debian's libcgal-demo (scripts/setup does)";
}

std::string random_number_text(std::mt19937& rng) {
    auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<std::uint32_t>(n)); };
    const float v = pick(3) == 0 ? static_cast<float>(pick(3)) : std::ldexp(static_cast<float>(pick(2000)) - 1000.0f, -pick(30));
    std::ostringstream o;
    switch (pick(5)) {
        case 0: o << std::scientific << v; break;
        case 1: o << std::setprecision(3) << v; break;
        case 2: o << std::showpos << v; break;
        default: o << std::setprecision(9) << v; break;
    }
    return o.str();
}

int sweep_size(int n, int minimum) {
    const char* text = std::getenv("FACET_TEST_SWEEP_DIVISOR");
    const long divisor = text ? std::strtol(text, nullptr, 10) : 1;
    if (divisor <= 1) return n;
    return std::max(static_cast<int>(n / divisor), std::min(n, minimum));
}

namespace {

// The directories test_temp_dir made for the running test. A test that passes has its directories
// removed when it ends; a failing test's stay for inspection (each run clears them first anyway).
std::vector<fs::path>& current_test_dirs() {
    static std::vector<fs::path> dirs;
    return dirs;
}

class RemoveDirsOfPassedTests : public ::testing::EmptyTestEventListener {
    void OnTestEnd(const ::testing::TestInfo& info) override {
        if (info.result() && info.result()->Passed()) {
            std::error_code ec;
            for (const fs::path& d : current_test_dirs()) fs::remove_all(d, ec);
        }
        current_test_dirs().clear();
    }
};

[[maybe_unused]] const bool g_listener_added = [] {
    ::testing::UnitTest::GetInstance()->listeners().Append(new RemoveDirsOfPassedTests);  // gtest owns it
    return true;
}();

}  // namespace

fs::path test_temp_dir(const std::string& prefix) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    // The build folder's hash: several checkouts' test runs on one machine (one user, one /tmp)
    // must not clear each other's folders.
    std::string name = prefix + "_" + std::to_string(geteuid()) + "_" +
                       std::to_string(std::hash<std::string>{}(k_binary_dir) % 1000000);
    if (info) name += std::string("_") + info->test_suite_name() + "_" + info->name();
    for (char& c : name)
        if (c == '/') c = '_';  // parameterized test names
    const fs::path d = fs::temp_directory_path() / name;
    fs::remove_all(d);
    fs::create_directories(d);
    if (info) current_test_dirs().push_back(d);
    return d;
}

std::string base64(const std::string& bytes) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        std::uint32_t n = static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i])) << 16;
        if (i + 1 < bytes.size()) n |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) n |= static_cast<unsigned char>(bytes[i + 2]);
        out += table[n >> 18 & 63];
        out += table[n >> 12 & 63];
        out += i + 1 < bytes.size() ? table[n >> 6 & 63] : '=';
        out += i + 2 < bytes.size() ? table[n & 63] : '=';
    }
    return out;
}

}  // namespace facet_test
