// facet view: the SDL2 window, its event loop and the render-on-change policy.
//
// The loop sleeps in SDL_WaitEvent(Timeout) and renders only when something changed: the camera,
// a toggle, the window size, a model arriving, or the turntable spin (then at most 60 frames a
// second). While the mouse drags or the wheel turns, frames are rendered at half the window's
// resolution without supersampling and SDL scales them up; 200 ms after the input stops (or when
// the button is released) one full-resolution frame replaces it. Models load on a background thread
// that wakes the loop with an SDL user event when the result is ready.
#include "viewer.hpp"

#define SDL_MAIN_HANDLED
#include <SDL.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "font.hpp"
#include "overlay.hpp"
#include "screenshot.hpp"
#include "view_renderer.hpp"
#include "view_state.hpp"
#include "facet/primitive_counts.hpp"

namespace facet::viewer {
namespace {

using Clock = std::chrono::steady_clock;
using Ms = std::chrono::milliseconds;

constexpr auto k_refine_delay = Ms(200);     // input quiet this long: render at full resolution
constexpr auto k_spin_frame = Ms(16);        // at most ~60 frames a second while spinning
constexpr auto k_message_time = Ms(8000);    // how long a status message stays

struct SdlDeleter {
    void operator()(SDL_Window* w) const { SDL_DestroyWindow(w); }
    void operator()(SDL_Renderer* r) const { SDL_DestroyRenderer(r); }
    void operator()(SDL_Texture* t) const { SDL_DestroyTexture(t); }
};
template <class T>
using SdlPtr = std::unique_ptr<T, SdlDeleter>;

struct SdlSession {
    bool ok = false;
    SdlSession() { ok = SDL_Init(SDL_INIT_VIDEO) == 0; }
    ~SdlSession() {
        if (ok) SDL_Quit();
    }
};

std::string display_name(const std::string& path) {
    return path.empty() ? std::string("default scene") : std::filesystem::path(path).filename().string();
}

// A streaming texture of one size that is recreated when the size changes.
struct StreamingTexture {
    SdlPtr<SDL_Texture> texture;
    int width = 0, height = 0;
    bool upload(SDL_Renderer* renderer, const Image& image, SDL_BlendMode blend) {
        if (!texture || width != image.width || height != image.height) {
            // RGBA32 is the byte order R, G, B, A in memory: facet's Rgba8 (ABGR8888 on little-endian).
            texture.reset(SDL_CreateTexture(renderer, SDL_PIXELFORMAT_RGBA32, SDL_TEXTUREACCESS_STREAMING, image.width,
                                            image.height));
            if (!texture) return false;
            width = image.width;
            height = image.height;
            SDL_SetTextureBlendMode(texture.get(), blend);
        }
        return SDL_UpdateTexture(texture.get(), nullptr, image.pixels.data(), image.width * 4) == 0;
    }
};

class Viewer {
public:
    Viewer(const cli::RenderPlan& plan, int threads, SDL_Window* window, SDL_Renderer* renderer)
        : plan_(plan), window_(window), sdl_renderer_(renderer), view_renderer_({.threads = threads}) {
        load_event_ = SDL_RegisterEvents(1);
    }
    ~Viewer() {
        if (loader_.joinable()) loader_.join();  // a load in progress finishes first
    }
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    void open_default_scene(bool spin) {
        scene_ = default_scene();
        scene_axis_ = UpAxis::y;  // as `facet render`, --up-axis applies to model files only
        state_.toggles().up_axis = UpAxis::y;
        sync_viewport();
        init_view(state_, scene_, plan_.view, plan_.use_default_scene_camera);
        state_.toggles().shading = plan_.settings.shading;
        state_.toggles().ssaa = plan_.ssaa;
        state_.toggles().spin = spin;
        model_path_.clear();
        update_title();
    }

    void open_model(const std::string& path, bool spin) {
        scene_ = Scene{};
        state_.toggles().up_axis = plan_.load.up_axis;
        scene_axis_ = plan_.load.up_axis;
        sync_viewport();
        state_.toggles().shading = plan_.settings.shading;
        state_.toggles().ssaa = plan_.ssaa;
        state_.toggles().spin = spin;
        first_model_ = true;
        start_load(path);
    }

    void run() {
        Clock::time_point last_tick = Clock::now();
        while (running_) {
            SDL_Event event;
            const int timeout = wait_timeout_ms();
            const bool got = timeout < 0 ? SDL_WaitEvent(&event) != 0 : SDL_WaitEventTimeout(&event, timeout) != 0;
            if (got) {
                handle(event);
                while (running_ && SDL_PollEvent(&event)) handle(event);
            }
            if (!running_) break;
            const Clock::time_point now = Clock::now();
            if (loading_ && load_.valid() && load_.wait_for(Ms(0)) == std::future_status::ready) finish_load();
            if (state_.toggles().spin) {
                if (now - last_frame_ >= k_spin_frame) {
                    dirty_ |= state_.advance(std::chrono::duration<double>(now - last_tick).count());
                    last_tick = now;
                }
            } else {
                last_tick = now;
            }
            if (message_ && now >= message_->until) {
                message_.reset();
                present_only_ = true;
            }
            if (showing_low_res_ && !interactive(now)) dirty_ = true;  // refine
            if (dirty_) {
                render_frame(now);
            } else if (present_only_) {
                present();
            }
        }
    }

private:
    struct Message {
        std::string text;
        bool error;
        Clock::time_point until;
    };

    // Milliseconds until something is due without input; -1: nothing is (sleep until an event).
    int wait_timeout_ms() const {
        if (dirty_ || present_only_) return 0;
        const Clock::time_point now = Clock::now();
        std::optional<Clock::time_point> due;
        auto earliest = [&](Clock::time_point t) { due = due ? std::min(*due, t) : t; };
        if (state_.toggles().spin) earliest(last_frame_ + k_spin_frame);
        if (showing_low_res_) earliest(last_input_ + k_refine_delay);
        if (message_) earliest(message_->until);
        if (loading_) earliest(now + Ms(250));  // the load wakes the loop itself; this is a backstop
        if (!due) return -1;
        return static_cast<int>(std::clamp<long long>(std::chrono::duration_cast<Ms>(*due - now).count() + 1, 0, 1000));
    }

    // Whether the user is dragging or zooming right now: frames are then rendered at half size.
    bool interactive(Clock::time_point now) const {
        return (buttons_held_ != 0 || wheel_active_) && now - last_input_ < k_refine_delay;
    }

    void sync_viewport() {
        int w = 0, h = 0;
        SDL_GetWindowSize(window_, &w, &h);
        state_.set_viewport(w, h);
    }

    void update_title() {
        const std::string title = "facet view - " + display_name(model_path_);
        SDL_SetWindowTitle(window_, title.c_str());
    }

    void show_message(std::string text, bool error) {
        if (error) {
            std::fprintf(stderr, "facet view: %s\n", text.c_str());
            state_.toggles().overlay = true;  // an error is always shown
        }
        message_ = Message{std::move(text), error, Clock::now() + k_message_time};
        present_only_ = true;
    }

    void start_load(const std::string& path) {
        if (loading_) {
            show_message("still loading " + display_name(loading_path_) + "; drop " + display_name(path) + " again later", true);
            return;
        }
        loading_ = true;
        loading_path_ = path;
        LoadOptions options = plan_.load;
        options.up_axis = state_.toggles().up_axis;
        load_axis_ = options.up_axis;
        const Uint32 event_type = load_event_;
        std::promise<Result<LoadedModel>> promise;
        load_ = promise.get_future();
        if (loader_.joinable()) loader_.join();  // the previous load has delivered its result
        loader_ = std::thread([path, options, event_type, promise = std::move(promise)]() mutable {
            try {
                promise.set_value(load_model(path, options));
            } catch (const std::exception& e) {
                promise.set_value(Error{ErrorCode::bad_format, path + ": " + e.what()});
            }
            SDL_Event done{};
            done.type = event_type;
            SDL_PushEvent(&done);  // wakes the loop (thread-safe); the result is ready by now
        });
        present_only_ = true;
    }

    void finish_load() {
        Result<LoadedModel> result = load_.get();
        loading_ = false;
        if (!result) {
            show_message(result.error().message + " (keeping " + display_name(model_path_) + ")", true);
            dirty_ = true;
            return;
        }
        for (const std::string& w : result->warnings) std::fprintf(stderr, "facet view: warning: %s\n", w.c_str());
        scene_ = std::move(result->scene);
        scene_axis_ = load_axis_;
        model_path_ = loading_path_;
        reorient(scene_, scene_axis_, state_.toggles().up_axis);
        scene_axis_ = state_.toggles().up_axis;
        if (first_model_) {
            init_view(state_, scene_, plan_.view, false);  // the command line's camera, for the first model
            first_model_ = false;
        } else {
            state_.set_scene_bounds(scene_);
            state_.set_initial(state_.fitted(plan_.view.azimuth, plan_.view.elevation));
        }
        message_.reset();  // an earlier load's error no longer applies
        present_only_ = true;
        if (!result->warnings.empty())
            show_message(std::to_string(result->warnings.size()) + " warning(s) on stderr, first: " + result->warnings.front(), false);
        update_title();
        dirty_ = true;
    }

    void handle(const SDL_Event& e) {
        const Clock::time_point now = Clock::now();
        switch (e.type) {
            case SDL_QUIT: running_ = false; break;
            case SDL_KEYDOWN: {
                if (e.key.repeat || (e.key.keysym.mod & (KMOD_CTRL | KMOD_ALT | KMOD_GUI))) break;
                const SDL_Keycode key = e.key.keysym.sym;
                if (key == SDLK_ESCAPE || key == SDLK_q) {
                    running_ = false;
                } else if (key == SDLK_s) {
                    screenshot();
                } else if (key > 0 && key < 128) {
                    const Toggles before = state_.toggles();
                    if (state_.on_key(static_cast<char>(key))) {
                        if (state_.toggles().up_axis != before.up_axis) {
                            reorient(scene_, scene_axis_, state_.toggles().up_axis);
                            scene_axis_ = state_.toggles().up_axis;
                            state_.set_scene_bounds(scene_);
                            state_.fit();
                        }
                        if (key == SDLK_h)
                            present_only_ = true;  // only the overlay changed: no need to render again
                        else
                            dirty_ = true;
                    }
                }
                break;
            }
            case SDL_MOUSEBUTTONDOWN:
                buttons_held_ |= SDL_BUTTON(e.button.button);
                break;
            case SDL_MOUSEBUTTONUP:
                buttons_held_ &= ~SDL_BUTTON(e.button.button);
                if (buttons_held_ == 0 && showing_low_res_ && !wheel_active_) dirty_ = true;  // refine now
                break;
            case SDL_MOUSEMOTION: {
                std::optional<MouseButton> b;
                if (e.motion.state & SDL_BUTTON_LMASK) b = MouseButton::left;
                else if (e.motion.state & SDL_BUTTON_RMASK) b = MouseButton::right;
                else if (e.motion.state & SDL_BUTTON_MMASK) b = MouseButton::middle;
                buttons_held_ = e.motion.state;  // also forgets a release that happened outside the window
                if (b && state_.on_drag(static_cast<float>(e.motion.xrel), static_cast<float>(e.motion.yrel), *b)) {
                    last_input_ = now;
                    dirty_ = true;
                }
                break;
            }
            case SDL_MOUSEWHEEL: {
                float steps = e.wheel.preciseY;
                if (e.wheel.direction == SDL_MOUSEWHEEL_FLIPPED) steps = -steps;
                if (state_.on_wheel(steps)) {
                    wheel_active_ = true;
                    last_input_ = now;
                    dirty_ = true;
                }
                break;
            }
            case SDL_WINDOWEVENT:
                if (e.window.event == SDL_WINDOWEVENT_SIZE_CHANGED || e.window.event == SDL_WINDOWEVENT_RESIZED) {
                    sync_viewport();
                    dirty_ = true;
                } else if (e.window.event == SDL_WINDOWEVENT_EXPOSED) {
                    present_only_ = true;
                }
                break;
            case SDL_RENDER_TARGETS_RESET:
            case SDL_RENDER_DEVICE_RESET:
                scene_texture_ = {};
                overlay_texture_ = {};
                dirty_ = true;
                break;
            case SDL_DROPFILE: {
                const std::string path = e.drop.file ? e.drop.file : "";
                SDL_free(e.drop.file);
                if (!path.empty()) start_load(path);
                break;
            }
            default:
                if (e.type == load_event_ && loading_ && load_.wait_for(Ms(0)) == std::future_status::ready) finish_load();
                break;
        }
    }

    void render_frame(Clock::time_point now) {
        dirty_ = false;
        present_only_ = false;
        int pw = 0, ph = 0;
        if (SDL_GetRendererOutputSize(sdl_renderer_, &pw, &ph) != 0 || pw < 1 || ph < 1) return;
        const bool low_res = interactive(now);
        if (!low_res) wheel_active_ = false;
        const int rw = low_res ? std::max(1, pw / 2) : pw, rh = low_res ? std::max(1, ph / 2) : ph;
        const Clock::time_point start = Clock::now();
        view_renderer_.render(scene_, state_, plan_.settings, rw, rh, low_res ? 1 : state_.toggles().ssaa);
        frame_ms_ = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        showing_low_res_ = low_res;
        if (trace_)
            std::fprintf(stderr, "facet view: frame %dx%d ssaa %d %.1f ms\n", rw, rh, low_res ? 1 : state_.toggles().ssaa,
                         frame_ms_);
        if (!scene_texture_.upload(sdl_renderer_, view_renderer_.image(), SDL_BLENDMODE_NONE)) {
            show_message(std::string("cannot upload the frame: ") + SDL_GetError(), true);
            running_ = false;
            return;
        }
        last_frame_ = Clock::now();
        presents_.push_back(last_frame_);
        present();
    }

    // Draws the last frame and the overlay to the window.
    void present() {
        present_only_ = false;
        SDL_SetRenderDrawColor(sdl_renderer_, 0, 0, 0, 255);
        SDL_RenderClear(sdl_renderer_);
        if (scene_texture_.texture) SDL_RenderCopy(sdl_renderer_, scene_texture_.texture.get(), nullptr, nullptr);
        if (state_.toggles().overlay) draw_overlay();
        SDL_RenderPresent(sdl_renderer_);
    }

    double measured_fps() {
        // Frames presented in the last second, when the loop is rendering continuously.
        const Clock::time_point now = Clock::now();
        while (!presents_.empty() && now - presents_.front() > std::chrono::seconds(1)) presents_.pop_front();
        if (presents_.size() < 3) return 0;
        const double span = std::chrono::duration<double>(presents_.back() - presents_.front()).count();
        return span > 0 ? static_cast<double>(presents_.size() - 1) / span : 0;
    }

    void draw_overlay() {
        int pw = 0, ph = 0;
        SDL_GetRendererOutputSize(sdl_renderer_, &pw, &ph);
        const int scale = ph >= 1000 ? 2 : 1;
        OverlayInfo info;
        info.model = display_name(loading_ ? loading_path_ : model_path_);
        info.loading = loading_;
        info.triangles = scene_.triangle_count();
        info.points = point_count(scene_);
        info.segments = segment_count(scene_);
        info.fps = measured_fps();
        info.frame_ms = frame_ms_;
        info.width = pw;
        info.height = ph;
        info.render_width = view_renderer_.image().width;
        info.render_height = view_renderer_.image().height;
        info.threads = view_renderer_.threads();
        info.toggles = state_.toggles();
        if (message_) {
            info.message = message_->text;
            info.message_is_error = message_->error;
        }
        const int columns = (pw / scale - 2 * k_overlay_padding - 8) / k_glyph_advance;
        const Image overlay = render_overlay(overlay_lines(info, columns), scale);
        if (!overlay_texture_.upload(sdl_renderer_, overlay, SDL_BLENDMODE_BLEND)) return;
        const SDL_Rect where{4 * scale, 4 * scale, overlay.width, overlay.height};
        SDL_RenderCopy(sdl_renderer_, overlay_texture_.texture.get(), nullptr, &where);
    }

    void screenshot() {
        int pw = 0, ph = 0;
        if (SDL_GetRendererOutputSize(sdl_renderer_, &pw, &ph) != 0) return;
        // Always a full-resolution frame, without the overlay.
        view_renderer_.render(scene_, state_, plan_.settings, pw, ph, state_.toggles().ssaa);
        Result<std::string> path = save_screenshot(view_renderer_.image(), model_path_);
        if (path) {
            std::fprintf(stderr, "facet view: wrote %s\n", path->c_str());
            show_message("screenshot: " + *path, false);
        } else {
            show_message(path.error().message, true);
        }
        dirty_ = true;
    }

    const cli::RenderPlan& plan_;
    SDL_Window* window_;
    SDL_Renderer* sdl_renderer_;
    ViewRenderer view_renderer_;
    StreamingTexture scene_texture_, overlay_texture_;
    ViewState state_;
    Scene scene_;
    UpAxis scene_axis_ = UpAxis::y;  // the axis the scene in memory has up
    std::string model_path_;         // empty: the default scene

    std::thread loader_;
    std::future<Result<LoadedModel>> load_;
    bool loading_ = false, first_model_ = false;
    std::string loading_path_;
    UpAxis load_axis_ = UpAxis::y;
    Uint32 load_event_ = 0;

    bool running_ = true, dirty_ = true, present_only_ = false;
    bool showing_low_res_ = false, wheel_active_ = false;
    Uint32 buttons_held_ = 0;
    Clock::time_point last_input_{}, last_frame_{};
    double frame_ms_ = 0;
    std::deque<Clock::time_point> presents_;
    std::optional<Message> message_;
    const bool trace_ = std::getenv("FACET_VIEW_TRACE") != nullptr;  // one stderr line per rendered frame
};

}  // namespace

int run_view(const std::string& model, bool spin, const cli::RenderOptions& options, bool camera_options_given) {
    Result<cli::RenderPlan> plan = cli::make_plan(options, camera_options_given || !model.empty());
    if (!plan) {
        std::fprintf(stderr, "facet view: %s\n", plan.error().message.c_str());
        return cli::k_exit_usage;
    }
    std::error_code ec;
    if (!model.empty() && !std::filesystem::is_regular_file(model, ec)) {
        std::fprintf(stderr, "facet view: %s: no such file\n", model.c_str());
        return cli::k_exit_failed;
    }

    auto no_window = [](const std::string& why) {
        std::fprintf(stderr, "facet view: cannot open a window: %s (no display? use facet render for headless output)\n",
                     why.c_str());
        return cli::k_exit_failed;
    };
    // Pick the video driver from the environment, so that without a display SDL neither falls back
    // to an invisible "offscreen" window nor lets other drivers print their own complaints.
    // SDL_VIDEODRIVER, when set, decides (e.g. kmsdrm on a console).
    const char* forced_driver = std::getenv("SDL_VIDEODRIVER");
    if (!forced_driver || !*forced_driver) {
        const char* display = std::getenv("DISPLAY");
        const char* wayland = std::getenv("WAYLAND_DISPLAY");
        if (wayland && *wayland) {
            SDL_SetHint(SDL_HINT_VIDEODRIVER, "wayland,x11");
        } else if (display && *display) {
            SDL_SetHint(SDL_HINT_VIDEODRIVER, "x11");
        } else {
            return no_window("DISPLAY and WAYLAND_DISPLAY are not set");
        }
    }
    SDL_SetMainReady();
    SdlSession sdl;
    if (!sdl.ok) {
        const char* display = std::getenv("DISPLAY");
        return no_window(std::string(SDL_GetError()) + (display ? std::string(" (DISPLAY=") + display + ")" : ""));
    }
    if (const char* driver = SDL_GetCurrentVideoDriver();
        driver && (std::string(driver) == "offscreen" || std::string(driver) == "dummy") && !forced_driver)
        return no_window(std::string("SDL found only the '") + driver + "' video driver");
    SDL_SetHint(SDL_HINT_RENDER_SCALE_QUALITY, "linear");  // the half-resolution frames while dragging
    SDL_EventState(SDL_DROPFILE, SDL_ENABLE);
    SdlPtr<SDL_Window> window(SDL_CreateWindow("facet view", SDL_WINDOWPOS_UNDEFINED, SDL_WINDOWPOS_UNDEFINED, plan->width,
                                               plan->height, SDL_WINDOW_RESIZABLE | SDL_WINDOW_ALLOW_HIGHDPI));
    if (!window) return no_window(SDL_GetError());
    SdlPtr<SDL_Renderer> renderer(SDL_CreateRenderer(window.get(), -1, 0));
    if (!renderer) renderer.reset(SDL_CreateRenderer(window.get(), -1, SDL_RENDERER_SOFTWARE));
    if (!renderer) return no_window(SDL_GetError());

    Viewer viewer(*plan, options.threads, window.get(), renderer.get());
    if (model.empty())
        viewer.open_default_scene(spin);
    else
        viewer.open_model(model, spin);
    viewer.run();
    return cli::k_exit_ok;
}

}  // namespace facet::viewer
