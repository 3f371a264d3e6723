// `facet view` in a real X server: Xvfb on a free display, the viewer in it, input from xdotool and
// screenshots of the window from xwd (decoded here: the XWD format is a header and raw pixels).
// Skips only when Xvfb cannot start; every wait is bounded.
// Also the command line without a display: --help, the one-line error and its exit code.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "facet/image.hpp"
#include "facet/io.hpp"
#include "support/paths.hpp"

// After facet's headers: Xlib defines macros named Status and Bool.
#include <X11/Xatom.h>
#include <X11/Xlib.h>
#undef Status
#undef Bool

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

const fs::path k_facet = fs::path(facet_test::k_binary_dir) / "bin" / "facet";

struct CommandResult {
    int exit_code = -1;
    std::string output;
};

// Runs a shell command (which bounds itself with `timeout`), capturing stdout (and stderr if asked).
CommandResult run(const std::string& command) {
    CommandResult r;
    FILE* p = popen(command.c_str(), "r");
    if (!p) return r;
    char buf[65536];
    while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) r.output.append(buf, n);
    const int status = pclose(p);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

// A child process started with fork/exec, killed (TERM, then KILL) when it goes out of scope.
class Child {
public:
    Child() = default;
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;
    ~Child() { stop(); }

    // `env` entries are NAME=VALUE added to the environment; `keep_fd` stays open in the child.
    bool start(const std::vector<std::string>& argv, const std::vector<std::string>& env, const fs::path& cwd,
               const fs::path& log, int keep_fd = -1) {
        pid_ = fork();
        if (pid_ < 0) return false;
        if (pid_ == 0) {
            if (!cwd.empty() && chdir(cwd.c_str()) != 0) _exit(126);
            const int out = open(log.empty() ? "/dev/null" : log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            const int in = open("/dev/null", O_RDONLY);
            dup2(in, 0);
            dup2(out, 1);
            dup2(out, 2);
            for (int fd = 3; fd < 1024; ++fd)
                if (fd != keep_fd) close(fd);
            for (const std::string& e : env) putenv(const_cast<char*>(e.c_str()));
            std::vector<char*> args;
            for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
            args.push_back(nullptr);
            execvp(args[0], args.data());
            _exit(127);
        }
        return true;
    }

    // The exit code once the process has ended within `timeout`; nothing if it is still running.
    std::optional<int> wait_exit(std::chrono::milliseconds timeout) {
        if (pid_ <= 0) return exit_code_;
        const Clock::time_point end = Clock::now() + timeout;
        do {
            int status = 0;
            if (waitpid(pid_, &status, WNOHANG) == pid_) {
                pid_ = -1;
                exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
                return exit_code_;
            }
            std::this_thread::sleep_for(20ms);
        } while (Clock::now() < end);
        return std::nullopt;
    }

    void stop() {
        if (pid_ <= 0) return;
        kill(pid_, SIGTERM);
        if (!wait_exit(3000ms)) {
            kill(pid_, SIGKILL);
            wait_exit(3000ms);
        }
    }

    bool running() const { return pid_ > 0; }
    pid_t pid() const { return pid_; }

private:
    pid_t pid_ = -1;
    std::optional<int> exit_code_;
};

// ---- XWD: a big-endian header of 25 32-bit fields, the window name, the colour map, the pixels ----

std::uint32_t be32(const std::string& d, std::size_t at) {
    return static_cast<std::uint32_t>(static_cast<unsigned char>(d[at])) << 24 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(d[at + 1])) << 16 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(d[at + 2])) << 8 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(d[at + 3]));
}

std::optional<facet::Image> decode_xwd(const std::string& d, std::string& error) {
    if (d.size() < 100) return error = "xwd: short file", std::nullopt;
    auto field = [&](int i) { return be32(d, static_cast<std::size_t>(i) * 4); };
    const std::uint32_t header_size = field(0), version = field(1), format = field(2), width = field(4), height = field(5);
    const std::uint32_t byte_order = field(7), bits_per_pixel = field(11), bytes_per_line = field(12);
    const std::uint32_t visual_class = field(13), masks[3] = {field(14), field(15), field(16)}, ncolors = field(19);
    if (version != 7 || format != 2) return error = "xwd: not a version 7 ZPixmap", std::nullopt;
    if (bits_per_pixel != 32 && bits_per_pixel != 24) return error = "xwd: unsupported bits per pixel", std::nullopt;
    const std::size_t colours_at = header_size, pixels_at = colours_at + 12 * static_cast<std::size_t>(ncolors);
    if (d.size() < pixels_at + static_cast<std::size_t>(bytes_per_line) * height) return error = "xwd: truncated", std::nullopt;
    // DirectColor pixels index a colour map per channel (entry i holds channel value i of each).
    std::vector<std::uint8_t> map[3];
    if (visual_class == 5 && ncolors > 0)
        for (std::uint32_t i = 0; i < ncolors; ++i)
            for (int c = 0; c < 3; ++c) {
                const std::size_t at = colours_at + 12 * i + 4 + 2 * c;
                map[c].push_back(static_cast<unsigned char>(d[at]));  // high byte of the 16-bit value
            }
    facet::Image img;
    img.width = static_cast<int>(width);
    img.height = static_cast<int>(height);
    img.pixels.resize(static_cast<std::size_t>(width) * height);
    const std::size_t bytes = bits_per_pixel / 8;
    for (std::uint32_t y = 0; y < height; ++y)
        for (std::uint32_t x = 0; x < width; ++x) {
            const std::size_t at = pixels_at + static_cast<std::size_t>(y) * bytes_per_line + x * bytes;
            std::uint32_t p = 0;
            for (std::size_t b = 0; b < bytes; ++b) {
                const std::uint32_t byte = static_cast<unsigned char>(d[at + b]);
                p |= byte_order == 0 ? byte << (8 * b) : byte << (8 * (bytes - 1 - b));  // 0: LSBFirst
            }
            std::uint8_t rgb[3];
            for (int c = 0; c < 3; ++c) {
                const int shift = masks[c] ? __builtin_ctz(masks[c]) : 0;
                const std::uint32_t v = (p & masks[c]) >> shift;
                rgb[c] = !map[c].empty() ? map[c][std::min<std::size_t>(v, map[c].size() - 1)] : static_cast<std::uint8_t>(v);
            }
            img.at(static_cast<int>(x), static_cast<int>(y)) = {rgb[0], rgb[1], rgb[2], 255};
        }
    return img;
}

// ---- XDND: dropping a file onto a window, as a file manager does ----

// Acts as the drag source of the XDND protocol (version 5): Enter, Position, wait for Status, Drop,
// answer the target's request for the selection with a text/uri-list, wait for Finished.
bool xdnd_drop(const std::string& display_name, unsigned long target, const fs::path& file, std::string& error) {
    Display* d = XOpenDisplay(display_name.c_str());
    if (!d) return error = "cannot open " + display_name, false;
    const Window root = DefaultRootWindow(d);
    const Window source = XCreateSimpleWindow(d, root, 0, 0, 1, 1, 0, 0, 0);
    auto atom = [&](const char* name) { return XInternAtom(d, name, False); };
    const Atom selection = atom("XdndSelection"), uri_list = atom("text/uri-list");
    XSetSelectionOwner(d, selection, source, CurrentTime);
    auto send = [&](const char* type, long l1, long l2, long l3, long l4) {
        XEvent e{};
        e.xclient.type = ClientMessage;
        e.xclient.display = d;
        e.xclient.window = target;
        e.xclient.message_type = atom(type);
        e.xclient.format = 32;
        e.xclient.data.l[0] = static_cast<long>(source);
        e.xclient.data.l[1] = l1;
        e.xclient.data.l[2] = l2;
        e.xclient.data.l[3] = l3;
        e.xclient.data.l[4] = l4;
        XSendEvent(d, target, False, NoEventMask, &e);
        XFlush(d);
    };
    // The drop point: the middle of the target, in root coordinates.
    int x = 0, y = 0;
    Window child = 0;
    XTranslateCoordinates(d, target, root, 100, 100, &x, &y, &child);
    send("XdndEnter", 5L << 24, static_cast<long>(uri_list), 0, 0);
    send("XdndPosition", 0, static_cast<long>(x) << 16 | y, CurrentTime, static_cast<long>(atom("XdndActionCopy")));
    const std::string uri = "file://" + fs::absolute(file).string() + "\r\n";
    bool dropped = false, finished = false;
    const Clock::time_point end = Clock::now() + 10s;
    while (!finished && Clock::now() < end) {
        if (!XPending(d)) {
            pollfd p{ConnectionNumber(d), POLLIN, 0};
            poll(&p, 1, 100);
            continue;
        }
        XEvent e;
        XNextEvent(d, &e);
        if (e.type == ClientMessage && e.xclient.message_type == atom("XdndStatus") && !dropped) {
            if (!(e.xclient.data.l[1] & 1)) {
                error = "the window does not accept the drop";
                break;
            }
            send("XdndDrop", 0, CurrentTime, 0, 0);
            dropped = true;
        } else if (e.type == SelectionRequest) {
            const XSelectionRequestEvent& r = e.xselectionrequest;
            XEvent reply{};
            reply.xselection.type = SelectionNotify;
            reply.xselection.display = d;
            reply.xselection.requestor = r.requestor;
            reply.xselection.selection = r.selection;
            reply.xselection.target = r.target;
            reply.xselection.time = r.time;
            reply.xselection.property = None;
            if (r.target == uri_list) {
                XChangeProperty(d, r.requestor, r.property, r.target, 8, PropModeReplace,
                                reinterpret_cast<const unsigned char*>(uri.data()), static_cast<int>(uri.size()));
                reply.xselection.property = r.property;
            }
            XSendEvent(d, r.requestor, False, NoEventMask, &reply);
            XFlush(d);
        } else if (e.type == ClientMessage && e.xclient.message_type == atom("XdndFinished")) {
            finished = true;
        }
    }
    if (!finished && error.empty()) error = dropped ? "no XdndFinished from the window" : "no XdndStatus from the window";
    XDestroyWindow(d, source);
    XCloseDisplay(d);
    return finished;
}

// ---- the X server and the viewer ----

// Pixels that differ between two captures (all of them when the sizes differ).
int differing(const facet::Image& a, const facet::Image& b) {
    if (a.width != b.width || a.height != b.height) return a.width * a.height;
    int n = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) n += !(a.pixels[i] == b.pixels[i]);
    return n;
}

class XvfbViewer : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("facet_viewer_xvfb_" + std::to_string(getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        // -displayfd: Xvfb picks a free display itself and writes its number when it accepts clients.
        int fds[2];
        ASSERT_EQ(pipe(fds), 0);
        const bool started = xvfb_.start({"Xvfb", "-displayfd", std::to_string(fds[1]), "-screen", "0", "1024x768x24",
                                          "-nolisten", "tcp", "-noreset"},
                                         {}, "", dir_ / "xvfb.log", fds[1]);
        close(fds[1]);
        std::string number;
        if (started) {
            pollfd p{fds[0], POLLIN, 0};
            const Clock::time_point end = Clock::now() + 15s;
            while (Clock::now() < end && number.find('\n') == std::string::npos) {
                if (poll(&p, 1, 200) <= 0) continue;
                char buf[32];
                const ssize_t n = read(fds[0], buf, sizeof buf);
                if (n <= 0) break;
                number.append(buf, static_cast<std::size_t>(n));
            }
        }
        close(fds[0]);
        if (number.empty() || number.find('\n') == std::string::npos) {
            std::ifstream log(dir_ / "xvfb.log");
            std::string first_line;
            std::getline(log, first_line);
            xvfb_.stop();
            GTEST_SKIP() << "Xvfb could not start (is the xvfb package installed?): " << first_line;
        }
        display_ = ":" + number.substr(0, number.find('\n'));
    }

    void TearDown() override {
        viewer_.stop();
        xvfb_.stop();
        // Kept on failure (the captures are saved there as PNGs), or when FACET_KEEP_VIEWER_TEST is set.
        if (HasFailure() || std::getenv("FACET_KEEP_VIEWER_TEST"))
            std::fprintf(stderr, "viewer test files kept in %s\n", dir_.c_str());
        else
            fs::remove_all(dir_);
    }

    std::string x(const std::string& command) const { return "DISPLAY=" + display_ + " timeout 20 " + command; }

    // Waits (bounded) for a visible window whose name matches `pattern`: xdotool's output (the ids)
    // and exit code. A search fails with BadWindow when a window it walks past is destroyed under it
    // (a closing client's): then it searches again.
    CommandResult find_window(const std::string& pattern) const {
        CommandResult search;
        for (const Clock::time_point end = Clock::now() + 20s; Clock::now() < end;) {
            search = run(x("xdotool search --sync --onlyvisible --name '" + pattern + "'"));
            if (search.exit_code == 0) break;
            std::this_thread::sleep_for(100ms);
        }
        return search;
    }

    // Starts the viewer and waits for its window; returns the window id.
    std::string start_viewer(const std::vector<std::string>& args) {
        std::vector<std::string> argv = {k_facet.string(), "view"};
        argv.insert(argv.end(), args.begin(), args.end());
        EXPECT_TRUE(viewer_.start(argv, {"DISPLAY=" + display_, "FACET_VIEW_TRACE=1"}, dir_, dir_ / "viewer.log"));
        const CommandResult search = find_window("^facet view");
        if (search.exit_code != 0) {
            const std::optional<int> ended = viewer_.wait_exit(0ms);
            ADD_FAILURE() << "no viewer window appeared (xdotool: " << search.exit_code << "); the viewer "
                          << (ended ? "ended with status " + std::to_string(*ended) : std::string("is running"))
                          << "; viewer log:\n" << log();
        }
        const std::string id = search.output.substr(0, search.output.find('\n'));
        EXPECT_FALSE(id.empty());
        return id;
    }

    std::string log() const {
        std::ifstream in(dir_ / "viewer.log");
        return std::string(std::istreambuf_iterator<char>(in), {});
    }

    // Frames the viewer has rendered (FACET_VIEW_TRACE writes a line for each).
    int frames() const {
        const std::string text = log();
        int n = 0;
        const std::string line = "facet view: frame ";
        for (std::size_t at = text.find(line); at != std::string::npos; at = text.find(line, at + 1)) ++n;
        return n;
    }

    facet::Image capture(const std::string& window) {
        const CommandResult r = run(x("xwd -silent -id " + window));
        std::string error;
        std::optional<facet::Image> img = r.exit_code == 0 ? decode_xwd(r.output, error) : std::nullopt;
        if (!img) {
            ADD_FAILURE() << "xwd failed (" << r.exit_code << "): " << error;
            return {};
        }
        return *img;
    }

    // Captures until `ok` holds, or fails after `timeout`; returns the last capture.
    template <class Pred>
    facet::Image capture_until(const std::string& window, Pred ok, std::chrono::seconds timeout, const char* what) {
        const Clock::time_point end = Clock::now() + timeout;
        facet::Image img;
        do {
            img = capture(window);
            if (img.width > 0 && ok(img)) return img;
            std::this_thread::sleep_for(150ms);
        } while (Clock::now() < end);
        save("timeout", img);
        ADD_FAILURE() << "timed out waiting for: " << what << "; viewer log:\n" << log();
        return img;
    }

    // Captures until the viewer has rendered no frame and the window has not changed for `quiet`
    // (a window event that comes late can bring a frame after the first one), or fails after
    // `timeout`; returns the last capture.
    facet::Image capture_settled(const std::string& window, std::chrono::milliseconds quiet,
                                 std::chrono::seconds timeout) {
        const Clock::time_point end = Clock::now() + timeout;
        int rendered = frames();
        facet::Image img = capture(window);
        do {
            std::this_thread::sleep_for(quiet);
            const int now_rendered = frames();
            const facet::Image now = capture(window);
            if (now.width > 0 && now_rendered == rendered && differing(now, img) == 0) return now;
            rendered = now_rendered;
            img = now;
        } while (Clock::now() < end);
        save("timeout", img);
        ADD_FAILURE() << "timed out waiting for the viewer to settle; viewer log:\n" << log();
        return img;
    }

    void save(const std::string& name, const facet::Image& img) {
        if (img.width > 0) (void)facet::write_png((dir_ / (name + ".png")).string(), img);
    }

    void key(const std::string& window, const std::string& keys) {
        // The pointer in the window gives it the keyboard (no window manager: focus follows the pointer).
        EXPECT_EQ(run(x("xdotool mousemove --window " + window + " 300 220 key " + keys)).exit_code, 0);
    }

    fs::path dir_;
    std::string display_;
    Child xvfb_, viewer_;
};

constexpr facet::Rgba8 k_background{28, 31, 36, 255};  // RenderSettings' default (0.11, 0.12, 0.14)

bool is_background(facet::Rgba8 p) {
    return std::abs(p.r - k_background.r) <= 2 && std::abs(p.g - k_background.g) <= 2 && std::abs(p.b - k_background.b) <= 2;
}

// Pixels in a rectangle that are not the background.
int foreground(const facet::Image& img, int x0, int y0, int x1, int y1) {
    int n = 0;
    for (int y = y0; y < y1 && y < img.height; ++y)
        for (int x = x0; x < x1 && x < img.width; ++x) n += !is_background(img.at(x, y));
    return n;
}

int bright(const facet::Image& img, int x0, int y0, int x1, int y1) {
    int n = 0;
    for (int y = y0; y < y1 && y < img.height; ++y)
        for (int x = x0; x < x1 && x < img.width; ++x) n += img.at(x, y).r > 200 && img.at(x, y).g > 200 && img.at(x, y).b > 200;
    return n;
}

int coloured(const facet::Image& img, facet::Rgba8 c) {
    int n = 0;
    for (facet::Rgba8 p : img.pixels) n += std::abs(p.r - c.r) <= 3 && std::abs(p.g - c.g) <= 3 && std::abs(p.b - c.b) <= 3;
    return n;
}

// CPU time (user + system) a process has used, in clock ticks.
long cpu_ticks(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
    std::string stat((std::istreambuf_iterator<char>(in)), {});
    std::istringstream fields(stat.substr(stat.rfind(')') + 2));  // after "pid (comm) "
    std::string f;
    long utime = 0, stime = 0;
    for (int i = 3; fields >> f; ++i) {
        if (i == 14) utime = std::stol(f);
        if (i == 15) {
            stime = std::stol(f);
            break;
        }
    }
    return utime + stime;
}

// A cube as an OBJ file: small, quick to load, surrounded by background when framed.
void write_cube(const fs::path& path) {
    std::ofstream f(path);
    f << "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
         "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n";
}

// The window is 320x240; the overlay sits in its top-left corner, above y = 90.
constexpr int k_w = 320, k_h = 240;
// Below the overlay, around the middle of the window: where the framed model must be.
constexpr int k_centre_area = 80 * 60;
int centre(const facet::Image& img) { return foreground(img, 120, 100, 200, 160); }
// A frame is on screen: until the first one is presented the window is black, which is not the
// background either and would pass for the model.
bool drawn(const facet::Image& img) { return coloured(img, k_background) > 0; }

TEST_F(XvfbViewer, ShowsTheModelAndOrbitsWhenDragged) {
    write_cube(dir_ / "cube.obj");
    const std::string win = start_viewer({"cube.obj", "--size", "320x240", "--azimuth", "30", "--elevation", "20"});
    ASSERT_FALSE(HasFailure());
    // The model loads on a background thread: wait until it is drawn in the middle of the window.
    const facet::Image first = capture_until(
        win, [](const facet::Image& img) { return drawn(img) && centre(img) > k_centre_area / 2; }, 20s,
        "the cube in the centre of the window");
    save("first", first);
    ASSERT_EQ(first.width, k_w);
    ASSERT_EQ(first.height, k_h);
    EXPECT_GT(centre(first), k_centre_area * 9 / 10) << "the cube covers the centre";
    EXPECT_EQ(foreground(first, 0, k_h - 12, 12, k_h), 0) << "bottom-left corner is background";
    EXPECT_EQ(foreground(first, k_w - 12, k_h - 12, k_w, k_h), 0) << "bottom-right corner is background";
    EXPECT_GT(bright(first, 0, 0, 200, 80), 200) << "overlay text in the top-left corner";

    // Drag with the left button: the cube turns.
    ASSERT_EQ(run(x("xdotool mousemove --window " + win + " 160 160 mousedown 1 mousemove --window " + win +
                    " 190 165 sleep 0.1 mousemove --window " + win + " 240 175 sleep 0.1 mouseup 1"))
                  .exit_code,
              0);
    // After the drag, the full-resolution frame settles: two equal captures that differ from the first.
    facet::Image previous;
    const facet::Image turned = capture_until(
        win,
        [&](const facet::Image& img) {
            const bool settled = differing(img, previous) == 0;
            previous = img;
            return settled && differing(img, first) > 0;
        },
        15s, "a new, settled view after the drag");
    save("turned", turned);
    EXPECT_GT(differing(turned, first), k_w * k_h / 50) << "the view changed";
    EXPECT_GT(centre(turned), k_centre_area / 2) << "the cube is still there";
    // Frames during the drag were rendered at half size; the last one, after it, at full size.
    const std::string frames = log();
    EXPECT_NE(frames.find("frame 160x120 ssaa 1"), std::string::npos) << frames;
    const std::size_t last = frames.rfind("frame ");
    ASSERT_NE(last, std::string::npos);
    EXPECT_EQ(frames.compare(last, 17, "frame 320x240 ssa"), 0) << frames;

    // S writes a screenshot next to the model, at the window's size, without the overlay.
    key(win, "s");
    const fs::path shot = dir_ / "cube.screenshot-001.png";
    for (Clock::time_point end = Clock::now() + 10s; Clock::now() < end && !fs::exists(shot);) std::this_thread::sleep_for(100ms);
    ASSERT_TRUE(fs::exists(shot)) << log();
    facet::Result<facet::Image> png = facet::read_png(shot.string());
    ASSERT_TRUE(png.ok());
    EXPECT_EQ(png->width, k_w);
    EXPECT_EQ(png->height, k_h);
    EXPECT_EQ(bright(*png, 0, 0, 100, 40), 0) << "no overlay text in the screenshot";
    EXPECT_GT(centre(*png), k_centre_area / 2);

    // Q closes the viewer, with exit code 0.
    key(win, "q");
    const std::optional<int> code = viewer_.wait_exit(10000ms);
    ASSERT_TRUE(code.has_value()) << "the viewer did not close on Q";
    EXPECT_EQ(*code, 0) << log();
}

TEST_F(XvfbViewer, KeysToggleTheOverlayAndWireframe) {
    const std::string win = start_viewer({"--size", "320x240"});
    ASSERT_FALSE(HasFailure());
    facet::Image first = capture_until(
        win, [](const facet::Image& img) { return bright(img, 0, 0, 200, 80) > 200 && foreground(img, 0, 120, k_w, k_h) > 0; },
        20s, "the default scene with the overlay");
    EXPECT_GT(foreground(first, 0, 120, k_w, k_h), k_w * 120 * 9 / 10) << "the default scene fills the lower half";
    // Measured from when the start-up's frames are all on screen (a loaded machine can deliver a
    // window event, and a frame, after the first capture).
    first = capture_settled(win, 300ms, 20s);
    save("default", first);

    // Idle, the viewer sleeps: no frame, and well under 5% of a core over a second (it renders only
    // on change).
    const int frames_before = frames();
    const long ticks_before = cpu_ticks(viewer_.pid());
    std::this_thread::sleep_for(1000ms);
    const long idle_ticks = cpu_ticks(viewer_.pid()) - ticks_before;
    EXPECT_EQ(frames(), frames_before) << "frames rendered while idle";
    EXPECT_LE(idle_ticks, sysconf(_SC_CLK_TCK) / 20) << "CPU ticks used in an idle second";
    EXPECT_TRUE(differing(capture(win), first) == 0) << "nothing changes while idle";

    key(win, "h");
    const facet::Image hidden = capture_until(
        win, [&](const facet::Image& img) { return differing(img, first) > 0; }, 10s, "the overlay to disappear");
    save("hidden", hidden);
    // Only the overlay's box changed: the scene below it is the same.
    EXPECT_LT(bright(hidden, 0, 0, 200, 12), bright(first, 0, 0, 200, 12));
    for (int y = 120; y < k_h; ++y)
        for (int x = 0; x < k_w; x += 7) ASSERT_TRUE(hidden.at(x, y) == first.at(x, y)) << x << "," << y;

    key(win, "w");
    const facet::Image wired = capture_until(
        win, [&](const facet::Image& img) { return differing(img, hidden) > 0; }, 10s, "the wireframe");
    save("wired", wired);
    // Edges are drawn dark over the shaded scene.
    int darker = 0, lighter = 0;
    for (std::size_t i = 0; i < wired.pixels.size(); ++i) {
        darker += wired.pixels[i].g + 20 < hidden.pixels[i].g;
        lighter += wired.pixels[i].g > hidden.pixels[i].g + 20;
    }
    EXPECT_GT(darker, 1000);
    EXPECT_LT(lighter, darker / 20);

    // Space spins the turntable: the picture keeps changing, and stops when Space is pressed again.
    key(win, "space");
    const facet::Image spin_a = capture_until(
        win, [&](const facet::Image& img) { return differing(img, wired) > k_w * k_h / 20; }, 10s, "the spin to start");
    // The next turn, however long a frame takes on a loaded machine (they took up to 0.5 s).
    capture_until(
        win, [&](const facet::Image& img) { return differing(img, spin_a) > k_w * k_h / 20; }, 10s,
        "the spin to go on");
    key(win, "space");
    capture_settled(win, 300ms, 10s);  // the spin stops

    // Escape closes the viewer.
    key(win, "Escape");
    const std::optional<int> code = viewer_.wait_exit(10000ms);
    ASSERT_TRUE(code.has_value()) << "the viewer did not close on Escape";
    EXPECT_EQ(*code, 0) << log();
}

TEST_F(XvfbViewer, DroppedFilesOpenAndBadOnesShowTheirError) {
    write_cube(dir_ / "cube.obj");
    const std::string win = start_viewer({"cube.obj", "--size", "320x240"});
    ASSERT_FALSE(HasFailure());
    const facet::Image cube = capture_until(
        win, [](const facet::Image& img) { return drawn(img) && centre(img) > k_centre_area * 9 / 10; }, 20s,
        "the cube");
    auto title = [&]() {
        const std::string name = run(x("xdotool getwindowname " + win)).output;
        return name.substr(0, name.find('\n'));
    };
    EXPECT_EQ(title(), "facet view - cube.obj");

    // A broken file: the error appears in the overlay (in the error colour), the cube stays.
    std::ofstream(dir_ / "broken.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1 2\n";
    std::string error;
    ASSERT_TRUE(xdnd_drop(display_, std::stoul(win), dir_ / "broken.ply", error)) << error;
    const facet::Image failed = capture_until(
        win, [](const facet::Image& img) { return coloured(img, {255, 130, 110, 255}) > 50; }, 15s,
        "the load error in the overlay");
    save("failed", failed);
    EXPECT_GT(centre(failed), k_centre_area * 9 / 10) << "the cube is still shown";
    EXPECT_EQ(title(), "facet view - cube.obj");
    EXPECT_NE(log().find("broken.ply"), std::string::npos) << "the error is on stderr too";

    // A good file replaces the model.
    std::ofstream(dir_ / "wedge.obj") << "v -2 -1 -1\nv 2 -1 -1\nv 0 1 -1\nv -2 -1 1\nv 2 -1 1\nv 0 1 1\n"
                                         "f 1 3 2\nf 4 5 6\nf 1 2 5 4\nf 2 3 6 5\nf 3 1 4 6\n";
    ASSERT_TRUE(xdnd_drop(display_, std::stoul(win), dir_ / "wedge.obj", error)) << error;
    for (Clock::time_point end = Clock::now() + 15s; Clock::now() < end && title() != "facet view - wedge.obj";)
        std::this_thread::sleep_for(100ms);
    EXPECT_EQ(title(), "facet view - wedge.obj") << log();
    const facet::Image wedge = capture_until(
        win, [&](const facet::Image& img) { return differing(img, failed) > k_w * k_h / 20; }, 15s, "the wedge");
    save("wedge", wedge);
    EXPECT_GT(bright(wedge, 0, 0, 200, 12), 10) << "the overlay names the new model";
    EXPECT_EQ(coloured(wedge, {255, 130, 110, 255}), 0) << "the old error is gone";

    key(win, "q");
    EXPECT_TRUE(viewer_.wait_exit(10000ms).has_value());
}

TEST_F(XvfbViewer, ExamplesShowTheirFramesInAWindow) {
    for (const char* name : {"triangle", "spinning_triangle", "lit_cube"}) {
        Child example;
        const fs::path binary = fs::path(facet_test::k_binary_dir) / "examples" / (std::string("example_") + name);
        ASSERT_TRUE(example.start({binary.string(), "--window"}, {"DISPLAY=" + display_}, dir_, dir_ / "example.log"));
        std::string title = name;  // the example's window: "facet: lit cube" (not the last one's, closing)
        std::replace(title.begin(), title.end(), '_', ' ');
        const CommandResult search = find_window("^facet: " + title + "$");
        ASSERT_EQ(search.exit_code, 0) << name << ": no window";
        const std::string win = search.output.substr(0, search.output.find('\n'));
        // Something besides the dark background is drawn.
        capture_until(
            win,
            [](const facet::Image& img) {
                int lit = 0;
                for (facet::Rgba8 p : img.pixels) lit += p.r + p.g + p.b > 150;
                return lit > img.width * img.height / 10;
            },
            10s, name);
        key(win, "q");
        const std::optional<int> code = example.wait_exit(10000ms);
        ASSERT_TRUE(code.has_value()) << name << " did not close on Q";
        EXPECT_EQ(*code, 0) << name;
    }
    // Shown, not written.
    for (const auto& entry : fs::directory_iterator(dir_)) EXPECT_NE(entry.path().extension(), ".png") << entry.path();
}

// ---- without a display ----

CommandResult run_facet(const std::string& env, const std::string& args) {
    return run("env " + env + " timeout 30 " + k_facet.string() + " " + args + " 2>&1");
}

TEST(ViewerCli, HelpListsTheViewerOptions) {
    const CommandResult r = run_facet("", "view --help");
    EXPECT_EQ(r.exit_code, 0);
    for (const char* s : {"--spin", "--size", "--shading", "--azimuth", "--fov", "--ssaa", "--up-axis", "orbit", "screenshot"})
        EXPECT_NE(r.output.find(s), std::string::npos) << s;
    EXPECT_NE(run_facet("", "--help").output.find("view"), std::string::npos);
}

TEST(ViewerCli, WithoutADisplayExitsWithOneClearLine) {
    for (const char* env : {"-u DISPLAY -u WAYLAND_DISPLAY -u SDL_VIDEODRIVER", "-u WAYLAND_DISPLAY -u SDL_VIDEODRIVER DISPLAY=:9999"}) {
        const CommandResult r = run_facet(env, "view --size 64x48");
        EXPECT_EQ(r.exit_code, 1) << env << ": " << r.output;
        EXPECT_EQ(r.output.rfind("facet view: cannot open a window: ", 0), 0u) << r.output;
        EXPECT_NE(r.output.find("use facet render"), std::string::npos) << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    }
}

TEST(ViewerCli, BadOptionsAndMissingFilesFailBeforeAnyWindow) {
    const CommandResult size = run_facet("-u DISPLAY", "view --size 0x10");
    EXPECT_EQ(size.exit_code, 2);
    EXPECT_NE(size.output.find("--size"), std::string::npos);
    const CommandResult missing = run_facet("", "view /nonexistent-facet-dir/model.obj --size 64x48");
    EXPECT_EQ(missing.exit_code, 1);
    EXPECT_NE(missing.output.find("/nonexistent-facet-dir/model.obj"), std::string::npos);
}

// `facet view` executes the viewer executable next to `facet`; only that one links SDL2, so `facet
// render` starts without SDL2's libraries (and the dozens they need). LD_DEBUG=libs has the dynamic
// linker name every library it loads.
TEST(ViewerCli, OnlyTheViewerLoadsSdl) {
    const fs::path out = fs::temp_directory_path() / ("facet_viewer_libs_" + std::to_string(getpid()) + ".png");
    const CommandResult render = run_facet("LD_DEBUG=libs", "render --size 16x16 -o " + out.string());
    fs::remove(out);
    EXPECT_EQ(render.exit_code, 0) << render.output;
    EXPECT_NE(render.output.find("libc.so"), std::string::npos) << "LD_DEBUG named no libraries:\n" << render.output;
    EXPECT_EQ(render.output.find("libSDL2"), std::string::npos) << render.output;

    const CommandResult view = run_facet("-u DISPLAY -u WAYLAND_DISPLAY -u SDL_VIDEODRIVER LD_DEBUG=libs", "view --size 64x48");
    EXPECT_EQ(view.exit_code, 1) << view.output;
    EXPECT_NE(view.output.find("libSDL2"), std::string::npos) << view.output;
    EXPECT_NE(view.output.find("facet view: cannot open a window: "), std::string::npos) << view.output;
}

TEST(ViewerCli, WithoutTheViewerExecutableSaysWhatIsMissing) {
    const fs::path dir = fs::temp_directory_path() / ("facet_without_viewer_" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::copy_file(k_facet, dir / "facet");
    const CommandResult r = run((dir / "facet").string() + " view --size 64x48 2>&1");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(r.output, "facet view: cannot run the viewer " + (dir / "facet-view").string() + ": No such file or directory\n");
    // facet's own parsing still comes first: an unknown option is a usage error, viewer or not.
    EXPECT_EQ(run((dir / "facet").string() + " view --no-such-option 2>&1").exit_code, 2);
    fs::remove_all(dir);
}

TEST(ExamplesCli, WindowWithoutADisplayWritesThePngInstead) {
    const fs::path dir = fs::temp_directory_path() / ("facet_examples_no_display_" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path binary = fs::path(facet_test::k_binary_dir) / "examples" / "example_triangle";
    const CommandResult r = run("cd " + dir.string() + " && env -u DISPLAY -u WAYLAND_DISPLAY -u SDL_VIDEODRIVER timeout 30 " +
                                binary.string() + " --window 2>&1");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("writing PNG files instead"), std::string::npos) << r.output;
    EXPECT_TRUE(fs::exists(dir / "triangle.png"));
    fs::remove_all(dir);
}

// The examples' own command lines: --help prints the usage (and writes no file named --help), an
// unknown option, too many arguments or a bad frame count is a usage error (exit 2) naming the problem.
TEST(ExamplesCli, HelpAndBadArguments) {
    const fs::path dir = fs::temp_directory_path() / ("facet_examples_args_" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    auto example = [&](const std::string& name, const std::string& args) {
        const fs::path binary = fs::path(facet_test::k_binary_dir) / "examples" / ("example_" + name);
        return run("cd " + dir.string() + " && timeout 30 " + binary.string() + " " + args + " 2>&1");
    };
    for (const char* name : {"triangle", "spinning_triangle", "lit_cube"}) {
        const CommandResult help = example(name, "--help");
        EXPECT_EQ(help.exit_code, 0) << name;
        EXPECT_EQ(help.output.rfind(std::string("usage: example_") + name, 0), 0u) << help.output;
        EXPECT_NE(help.output.find("--window"), std::string::npos) << help.output;
        const CommandResult bad = example(name, "--bogus");
        EXPECT_EQ(bad.exit_code, 2) << name;
        EXPECT_EQ(bad.output.rfind(std::string("example_") + name + ": unknown option --bogus\n", 0), 0u) << bad.output;
        EXPECT_EQ(example(name, "a b c").exit_code, 2) << name;
    }
    for (const char* frames : {"x", "0", "2x", "10001"}) {
        const CommandResult r = example("lit_cube", std::string("out ") + frames);
        EXPECT_EQ(r.exit_code, 2) << frames;
        EXPECT_NE(r.output.find("FRAMES must be a whole number"), std::string::npos) << r.output;
    }
    EXPECT_NE(example("lit_cube", "out -3").output.find("unknown option -3"), std::string::npos);  // not a count
    const CommandResult two = example("spinning_triangle", "spin 2");
    EXPECT_EQ(two.exit_code, 0) << two.output;
    EXPECT_TRUE(fs::exists(dir / "spin_001.png"));
    EXPECT_FALSE(fs::exists(dir / "spin_002.png"));
    EXPECT_FALSE(fs::exists(dir / "--help"));
    EXPECT_FALSE(fs::exists(dir / "--help_000.png"));
    fs::remove_all(dir);
}

}  // namespace
