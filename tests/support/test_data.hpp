// Test support: where the real test data lives, per-test scratch directories, file and bit helpers.
//  - assimp's test models (Debian's assimp-testmodels) under /usr/share/assimp/models;
//  - three of CGAL's meshes (Debian's libcgal-demo ships them in a tarball), unpacked once into
//    the build tree.
// scripts/setup installs both; tests that need them skip, saying so, when they are absent.
#pragma once

#include <bit>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace facet_test {

inline const std::filesystem::path k_assimp_models = "/usr/share/assimp/models";             // assimp-testmodels
inline const std::filesystem::path k_cgal_data = "/usr/share/doc/libcgal-dev/data.tar.gz";   // libcgal-demo

// The directory holding bunny00.off, armadillo.off, elephant.off and a few small OFF files (test_data.cpp), unpacked from k_cgal_data
// into <build>/test_data/cgal on first use (safe when several test processes race to do it);
// nothing when the tarball is missing or cannot be unpacked.
std::optional<std::filesystem::path> cgal_meshes();

// Skip messages naming the package to install.
std::string assimp_models_missing();
std::string cgal_meshes_missing();

// An empty directory for the running test: <tmp>/<prefix>_<uid>_<build>_<suite>_<test>, cleared
// first, removed when the test passes (a failed test's is left to look at). Per user, because a
// directory left by another user's run could not be cleared.
std::filesystem::path test_temp_dir(const std::string& prefix);

// The size of a random sweep: `n`, divided by FACET_TEST_SWEEP_DIVISOR (a whole number >= 1) when
// that is set, but never below `minimum`. The sanitizer test presets set it: under ASan or TSan the
// same code runs 5 to 20 times slower, and a quarter of the random cases still takes every path
// (the kinds, windings and configurations cycle within the first few dozen cases); the release
// suite keeps the full counts.
int sweep_size(int n, int minimum = 100);

// A random coordinate as text, for the generated-file tests of the model readers: small integers
// (which repeat, so positions join), otherwise values from 1000 down to tiny ones, written in
// scientific, short, signed or 9-digit form.
std::string random_number_text(std::mt19937& rng);
// Standard base64 with padding, for data: URIs in generated glTF files.
std::string base64(const std::string& bytes);

// A file's whole contents, and writing them (returns the path, for load calls).
inline std::string read_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}
inline std::string write_file(const std::filesystem::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return path.string();
}

// The bit patterns of a vector of float aggregates (Vec3, Vec4, ...), so that comparisons tell -0
// from +0 and NaN payloads apart.
template <class T>
std::vector<std::uint32_t> bits_of(const std::vector<T>& v) {
    std::vector<std::uint32_t> out;
    for (const T& x : v) {
        const auto* f = reinterpret_cast<const float*>(&x);
        for (std::size_t k = 0; k < sizeof(T) / sizeof(float); ++k) out.push_back(std::bit_cast<std::uint32_t>(f[k]));
    }
    return out;
}

}  // namespace facet_test

// Skips the running test when assimp's test models are not installed.
#define FACET_REQUIRE_ASSIMP_MODELS()                                        \
    if (!std::filesystem::is_directory(::facet_test::k_assimp_models))      \
    GTEST_SKIP() << ::facet_test::assimp_models_missing()
