#include "support/cli.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <spng.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <memory>

#include "support/paths.hpp"

extern char** environ;

namespace facet_test {

namespace fs = std::filesystem;

fs::path facet_binary() { return fs::path(k_binary_dir) / "bin" / "facet"; }

namespace {

std::string read_all(std::FILE* f) {
    std::string s;
    std::rewind(f);
    char buf[4096];
    while (std::size_t n = std::fread(buf, 1, sizeof buf, f)) s.append(buf, n);
    return s;
}

}  // namespace

CliRun run_facet(const std::vector<std::string>& args, bool stderr_tty) {
    return run_program(facet_binary(), args, stderr_tty);
}

CliRun run_program(const fs::path& program, const std::vector<std::string>& args, bool stderr_tty) {
    CliRun r;
    const std::string binary = program.string();
    std::vector<char*> argv{const_cast<char*>(binary.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);

    std::unique_ptr<std::FILE, int (*)(std::FILE*)> out(std::tmpfile(), &std::fclose), err(std::tmpfile(), &std::fclose);
    if (!out || !err) return r;
    int master = -1, slave = -1;
    if (stderr_tty) {
        master = posix_openpt(O_RDWR | O_NOCTTY);
        if (master < 0 || grantpt(master) != 0 || unlockpt(master) != 0) return r;
        slave = open(ptsname(master), O_RDWR | O_NOCTTY);
        if (slave < 0) return r;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, fileno(out.get()), STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, stderr_tty ? slave : fileno(err.get()), STDERR_FILENO);
    pid_t pid = -1;
    const int spawned = posix_spawn(&pid, binary.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (slave >= 0) close(slave);
    if (spawned == 0) {
        if (stderr_tty) {
            // Read the terminal while the child runs (its buffer is small); EIO once the child is gone.
            char buf[4096];
            for (;;) {
                const ssize_t n = read(master, buf, sizeof buf);
                if (n > 0) r.err.append(buf, static_cast<std::size_t>(n));
                else if (n < 0 && errno == EINTR) continue;
                else break;
            }
        }
        int status = 0;
        while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
        r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    if (master >= 0) close(master);
    r.out = read_all(out.get());
    if (!stderr_tty) r.err = read_all(err.get());
    return r;
}

DecodedPng decode_png(const fs::path& path) {
    DecodedPng png;
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        png.error = path.string() + ": cannot open";
        return png;
    }
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::unique_ptr<spng_ctx, void (*)(spng_ctx*)> ctx(spng_ctx_new(0), &spng_ctx_free);
    spng_ihdr ihdr{};
    auto fail = [&](int code) {
        png.error = path.string() + ": " + spng_strerror(code);
        return png;
    };
    if (int e = spng_set_png_buffer(ctx.get(), bytes.data(), bytes.size())) return fail(e);
    if (int e = spng_get_ihdr(ctx.get(), &ihdr)) return fail(e);
    png.width = ihdr.width;
    png.height = ihdr.height;
    png.bit_depth = ihdr.bit_depth;
    png.colour_type = ihdr.color_type;
    std::size_t size = 0;
    if (int e = spng_decoded_image_size(ctx.get(), SPNG_FMT_RGBA8, &size)) return fail(e);
    png.rgba.resize(size / 4);
    if (int e = spng_decode_image(ctx.get(), png.rgba.data(), size, SPNG_FMT_RGBA8, 0)) return fail(e);
    if (ihdr.bit_depth == 16 && ihdr.color_type == SPNG_COLOR_TYPE_GRAYSCALE) {
        // A fresh context: SPNG_FMT_PNG keeps the file's format (one 16-bit sample per pixel),
        // in host byte order.
        std::unique_ptr<spng_ctx, void (*)(spng_ctx*)> raw(spng_ctx_new(0), &spng_ctx_free);
        if (int e = spng_set_png_buffer(raw.get(), bytes.data(), bytes.size())) return fail(e);
        if (int e = spng_decoded_image_size(raw.get(), SPNG_FMT_PNG, &size)) return fail(e);
        png.gray16.resize(size / 2);
        if (int e = spng_decode_image(raw.get(), png.gray16.data(), size, SPNG_FMT_PNG, 0)) return fail(e);
    }
    if (png.rgba.size() != std::size_t{png.width} * png.height) png.error = path.string() + ": unexpected decoded size";
    return png;
}

std::string write_text(const fs::path& path, const std::string& text) {
    if (path.has_parent_path()) fs::create_directories(path.parent_path());
    std::ofstream out(path, std::ios::binary);
    out << text;
    return path.string();
}

}  // namespace facet_test
