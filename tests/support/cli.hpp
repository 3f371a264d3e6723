// Test support: the facet command line as a script sees it. Runs build/<preset>/bin/facet with an
// argument vector (no shell, so paths need no quoting), stdin from /dev/null, and collects the exit
// code, stdout and stderr separately; stderr can be a terminal (a pseudo-terminal) instead of a
// pipe. PNG files are decoded here with libspng directly, not with facet's own reader, including
// the exact values of 16-bit grayscale images.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "facet/image.hpp"

namespace facet_test {

struct CliRun {
    int exit_code = -1;   // -1: did not exit normally (crashed, or could not be started)
    std::string out;      // stdout
    std::string err;      // stderr
    std::string all() const { return out + err; }
};

std::filesystem::path facet_binary();

// Runs facet with these arguments. With `stderr_tty`, stderr is a pseudo-terminal.
CliRun run_facet(const std::vector<std::string>& args, bool stderr_tty = false);

// The same for another executable (a copy of facet, the viewer executable).
CliRun run_program(const std::filesystem::path& program, const std::vector<std::string>& args, bool stderr_tty = false);

struct DecodedPng {
    std::string error;            // empty: decoded
    std::uint32_t width = 0, height = 0;
    int bit_depth = 0, colour_type = 0;  // as in the PNG header (colour type 0 grey, 6 RGBA, ...)
    std::vector<facet::Rgba8> rgba;      // every image, converted to 8-bit RGBA
    std::vector<std::uint16_t> gray16;   // 16-bit greyscale images only: the stored values, exactly
    bool ok() const { return error.empty(); }
    facet::Rgba8 at(std::uint32_t x, std::uint32_t y) const { return rgba[std::size_t{y} * width + x]; }
    std::uint16_t value(std::uint32_t x, std::uint32_t y) const { return gray16[std::size_t{y} * width + x]; }
};

DecodedPng decode_png(const std::filesystem::path& path);

// A closed box of 12 triangles, as an OBJ file.
inline const char* const k_box_obj =
    "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n"
    "f 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\nf 1 2 6\nf 1 6 5\nf 3 7 8\nf 3 8 4\nf 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\n";

// Sets an environment variable for the facet processes a test starts (each test runs in a process
// of its own under CTest), and restores it.
class ScopedEnv {
public:
    ScopedEnv(const char* name, const std::string& value) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old;
        setenv(name, value.c_str(), 1);
    }
    ~ScopedEnv() {
        if (old_) setenv(name_, old_->c_str(), 1);
        else unsetenv(name_);
    }
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;

private:
    const char* name_;
    std::optional<std::string> old_;
};

// Writes `text` to `path` (creating parent directories); returns the path as a string.
std::string write_text(const std::filesystem::path& path, const std::string& text);

}  // namespace facet_test
