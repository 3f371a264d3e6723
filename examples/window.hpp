// What the examples share: their command line (--help, --window, their own arguments) and the
// --window mode, a tiny SDL2 window that shows facet images. Just enough for a demo: upload the
// picture, present it, stop when the window is closed (or Esc or Q is pressed). Without a display,
// ok() is false after one line on stderr, and the examples write PNGs instead.
#pragma once

#define SDL_MAIN_HANDLED
#include <SDL.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "facet/image.hpp"
#include "facet/io.hpp"

namespace example {

class Window {
public:
    Window(const char* title, int width, int height) {
        // Without a display SDL would pick its invisible "offscreen" driver: refuse instead.
        if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY") && !std::getenv("SDL_VIDEODRIVER")) {
            std::fprintf(stderr, "no display (DISPLAY is not set): writing PNG files instead\n");
            return;
        }
        SDL_SetMainReady();
        if (SDL_Init(SDL_INIT_VIDEO) == 0) {
            window_ = SDL_CreateWindow(title, SDL_WINDOWPOS_UNDEFINED, SDL_WINDOWPOS_UNDEFINED, width, height,
                                       SDL_WINDOW_RESIZABLE);
            if (window_) renderer_ = SDL_CreateRenderer(window_, -1, SDL_RENDERER_PRESENTVSYNC);
            if (renderer_)  // RGBA32: R, G, B, A bytes in memory, as facet::Rgba8
                texture_ = SDL_CreateTexture(renderer_, SDL_PIXELFORMAT_RGBA32, SDL_TEXTUREACCESS_STREAMING, width, height);
        }
        if (!texture_) std::fprintf(stderr, "cannot open a window (%s): writing PNG files instead\n", SDL_GetError());
    }
    ~Window() {
        if (texture_) SDL_DestroyTexture(texture_);
        if (renderer_) SDL_DestroyRenderer(renderer_);
        if (window_) SDL_DestroyWindow(window_);
        SDL_Quit();
    }
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

    bool ok() const { return texture_ != nullptr; }

    // Shows one frame (the size the window was opened with) and handles pending events, at most
    // about 60 times a second. False once the user has closed the window.
    bool show(const facet::Image& image) {
        const Uint32 due = last_ + 16, now = SDL_GetTicks();
        if (now < due) SDL_Delay(due - now);
        last_ = SDL_GetTicks();
        SDL_UpdateTexture(texture_, nullptr, image.pixels.data(), image.width * 4);
        SDL_RenderClear(renderer_);
        SDL_RenderCopy(renderer_, texture_, nullptr, nullptr);
        SDL_RenderPresent(renderer_);
        SDL_Event e;
        while (SDL_PollEvent(&e))
            if (closes(e)) return false;
        return true;
    }

    // Shows a still picture until the window is closed, sleeping between events.
    void show_until_closed(const facet::Image& image) {
        if (!show(image)) return;
        SDL_Event e;
        while (SDL_WaitEvent(&e) && !closes(e))
            if (e.type == SDL_WINDOWEVENT) show(image);  // exposed or resized: draw again
    }

private:
    static bool closes(const SDL_Event& e) {
        return e.type == SDL_QUIT ||
               (e.type == SDL_KEYDOWN && (e.key.keysym.sym == SDLK_ESCAPE || e.key.keysym.sym == SDLK_q));
    }
    SDL_Window* window_ = nullptr;
    SDL_Renderer* renderer_ = nullptr;
    SDL_Texture* texture_ = nullptr;
    Uint32 last_ = 0;
};

// Writes render_frame(0) ... render_frame(count - 1) to PREFIX_000.png, PREFIX_001.png, ...
// Returns the program's exit code: 1 after the first frame that cannot be written.
template <class RenderFrame>
int write_frames(const std::string& prefix, int count, RenderFrame render_frame) {
    for (int f = 0; f < count; ++f) {
        char name[32];
        std::snprintf(name, sizeof name, "_%03d.png", f);
        if (facet::Status s = facet::write_png(prefix + name, render_frame(f)); !s) {
            std::fprintf(stderr, "%s\n", s.error().message.c_str());
            return 1;
        }
    }
    std::printf("wrote %d frames %s_000.png ...\n", count, prefix.c_str());
    return 0;
}

// An example's command line: --help prints `usage` and exits 0; --window asks for the window (and
// takes no other argument); the other arguments are the example's own, at most `max_args` of them.
// Anything else (an unknown option, too many arguments) prints the usage to stderr and exits 2.
struct CommandLine {
    std::string program;  // argv[0]'s file name, for messages
    bool window = false;
    std::vector<std::string> args;
    // args[i], or `otherwise` when it was not given.
    std::string arg(std::size_t i, const std::string& otherwise) const { return i < args.size() ? args[i] : otherwise; }
};

[[noreturn]] inline void usage_error(const CommandLine& line, const char* usage, const std::string& problem) {
    std::fprintf(stderr, "%s: %s\n%s", line.program.c_str(), problem.c_str(), usage);
    std::exit(2);
}

inline CommandLine parse_command_line(int argc, char** argv, const char* usage, std::size_t max_args) {
    CommandLine line;
    line.program = argc > 0 ? argv[0] : "example";
    line.program.erase(0, line.program.find_last_of('/') + 1);
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--help" || a == "-h") {
            std::printf("%s", usage);
            std::exit(0);
        }
        if (a == "--window") line.window = true;
        else if (a.size() > 1 && a[0] == '-') usage_error(line, usage, "unknown option " + a);
        else line.args.push_back(a);
    }
    if (line.args.size() > (line.window ? 0 : max_args)) usage_error(line, usage, "too many arguments");
    return line;
}

// A frame count argument: a whole number from 1 to 10000.
inline int frame_count(const CommandLine& line, std::size_t i, int otherwise, const char* usage) {
    if (i >= line.args.size()) return otherwise;
    const std::string& a = line.args[i];
    char* end = nullptr;
    const long n = std::strtol(a.c_str(), &end, 10);
    if (a.empty() || *end != '\0' || n < 1 || n > 10000) usage_error(line, usage, "FRAMES must be a whole number from 1 to 10000, got " + a);
    return static_cast<int>(n);
}

// The command line of an example that writes numbered frames: [OUT_PREFIX] [FRAMES], or --window.
struct FramesCommandLine {
    bool window;
    std::string prefix;
    int frames;
};
inline FramesCommandLine parse_frames_command_line(int argc, char** argv, const char* usage, const char* prefix,
                                                   int frames) {
    const CommandLine line = parse_command_line(argc, argv, usage, 2);
    return {line.window, line.arg(0, prefix), frame_count(line, 1, frames, usage)};
}

}  // namespace example
