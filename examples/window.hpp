// The examples' --window mode: a tiny SDL2 window that shows facet images. Just enough for a demo:
// upload the picture, present it, stop when the window is closed (or Esc or Q is pressed).
// Without a display, ok() is false after one line on stderr, and the examples write PNGs instead.
#pragma once

#define SDL_MAIN_HANDLED
#include <SDL.h>

#include <cstdio>
#include <cstdlib>
#include <string>

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

// True when the first argument is --window (the examples then take no other arguments).
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

inline bool window_requested(int argc, char** argv) { return argc > 1 && std::string(argv[1]) == "--window"; }

}  // namespace example
