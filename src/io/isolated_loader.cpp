// facet io: load_model in a child process. The child loads the file and writes the result (scene
// or error) into an anonymous memory file; the parent waits (killing the child past its deadline),
// then reads the result back. A reader that crashes, hangs or allocates without bound costs the
// child only. The byte format below is private to this file and the same build on both sides.
#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <map>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "facet/model.hpp"
#include "facet/sandbox.hpp"

namespace facet {
namespace {

// ---- the result as bytes ----

class Writer {
public:
    template <class T>
    void pod(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        const auto* p = reinterpret_cast<const char*>(&v);
        bytes_.insert(bytes_.end(), p, p + sizeof(T));
    }
    template <class T>
    void array(const std::vector<T>& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        pod<std::uint64_t>(v.size());
        if (v.empty()) return;
        const auto* p = reinterpret_cast<const char*>(v.data());
        bytes_.insert(bytes_.end(), p, p + v.size() * sizeof(T));
    }
    void text(const std::string& s) { array(std::vector<char>(s.begin(), s.end())); }
    const std::vector<char>& bytes() const { return bytes_; }

private:
    std::vector<char> bytes_;
};

// Reads what Writer wrote; every read is bounds-checked, so a truncated result is an error.
class Reader {
public:
    Reader(const char* data, std::size_t size) : p_(data), end_(data + size) {}
    bool ok() const { return ok_; }
    template <class T>
    T pod() {
        T v{};
        if (!take(sizeof(T))) return v;
        std::memcpy(&v, p_ - sizeof(T), sizeof(T));
        return v;
    }
    template <class T>
    std::vector<T> array() {
        const auto n = pod<std::uint64_t>();
        std::vector<T> v;
        if (!ok_ || n > static_cast<std::uint64_t>(end_ - p_) / sizeof(T)) {
            ok_ = false;
            return v;
        }
        v.resize(n);
        if (n > 0) std::memcpy(v.data(), p_, n * sizeof(T));  // an empty vector's data() may be null
        p_ += n * sizeof(T);
        return v;
    }
    std::string text() {
        const std::vector<char> c = array<char>();
        return {c.begin(), c.end()};
    }

private:
    bool take(std::size_t n) {
        if (!ok_ || n > static_cast<std::size_t>(end_ - p_)) return ok_ = false;
        p_ += n;
        return true;
    }
    const char* p_;
    const char* end_;
    bool ok_ = true;
};

constexpr std::uint32_t k_ok = 0x464f4b31, k_failed = 0x46455231;  // what the child wrote first

// A material's textures, in one order for writing and reading.
constexpr int k_material_textures = 5;
std::array<std::shared_ptr<const Texture>*, k_material_textures> material_textures(Material& m) {
    return {&m.base_colour_texture, &m.metallic_roughness_map.texture, &m.normal_map.texture,
            &m.occlusion_map.texture, &m.emissive_map.texture};
}

// Every other value of a material, in one order for writing and reading: f(value) for each.
template <class F>
void material_values(Material& m, F&& f) {
    f(m.base_colour), f(m.sampler), f(m.alpha_mode), f(m.alpha_cutoff), f(m.double_sided);
    f(m.base_colour_transform), f(m.metallic), f(m.roughness);
    for (TextureMap* map : {&m.metallic_roughness_map, &m.normal_map, &m.occlusion_map, &m.emissive_map})
        f(map->sampler), f(map->transform);
    f(m.normal_scale), f(m.occlusion_strength), f(m.emissive), f(m.unlit);
}

void write_model(Writer& w, const LoadedModel& m) {
    // Textures are shared between materials: each is written once, materials refer to it by index.
    std::map<const Texture*, std::int32_t> texture_index;
    std::vector<const Texture*> textures;
    std::vector<Material> materials;  // copies, which material_textures and material_values can visit
    for (const SceneObject& o : m.scene.objects) {
        materials.push_back(o.material);
        for (const std::shared_ptr<const Texture>* p : material_textures(materials.back()))
            if (const Texture* t = p->get(); t && !texture_index.count(t)) {
                texture_index[t] = static_cast<std::int32_t>(textures.size());
                textures.push_back(t);
            }
    }
    w.pod<std::uint64_t>(textures.size());
    for (const Texture* t : textures) {
        w.pod<std::int32_t>(t->level(0).width);
        w.pod<std::int32_t>(t->level(0).height);
        w.array(t->level(0).pixels);
    }
    w.pod<std::uint64_t>(m.scene.objects.size());
    for (std::size_t i = 0; i < m.scene.objects.size(); ++i) {
        const SceneObject& o = m.scene.objects[i];
        w.array(o.mesh.positions);
        w.array(o.mesh.normals);
        w.array(o.mesh.colours);
        w.array(o.mesh.uvs);
        w.array(o.mesh.indices);
        w.array(o.mesh.tangents);
        w.array(o.mesh.points);
        w.array(o.mesh.lines);
        w.pod(o.model);
        for (const std::shared_ptr<const Texture>* t : material_textures(materials[i]))
            w.pod<std::int32_t>(*t ? texture_index[t->get()] : -1);
        material_values(materials[i], [&](const auto& v) { w.pod(v); });
    }
    w.pod<std::uint64_t>(m.warnings.size());
    for (const std::string& s : m.warnings) w.text(s);
}

std::optional<LoadedModel> read_model(Reader& r) {
    LoadedModel m;
    const auto texture_count = r.pod<std::uint64_t>();
    std::vector<std::shared_ptr<const Texture>> textures;
    for (std::uint64_t i = 0; r.ok() && i < texture_count; ++i) {
        Image base;
        base.width = r.pod<std::int32_t>();
        base.height = r.pod<std::int32_t>();
        base.pixels = r.array<Rgba8>();
        if (!r.ok() || base.width <= 0 || base.height <= 0 ||
            base.pixels.size() != static_cast<std::size_t>(base.width) * static_cast<std::size_t>(base.height))
            return std::nullopt;
        textures.push_back(std::make_shared<const Texture>(std::move(base)));  // the same mip chain again
    }
    const auto object_count = r.pod<std::uint64_t>();
    for (std::uint64_t i = 0; r.ok() && i < object_count; ++i) {
        SceneObject o;
        o.mesh.positions = r.array<Vec3>();
        o.mesh.normals = r.array<Vec3>();
        o.mesh.colours = r.array<Vec4>();
        o.mesh.uvs = r.array<Vec2>();
        o.mesh.indices = r.array<std::uint32_t>();
        o.mesh.tangents = r.array<Vec4>();
        o.mesh.points = r.array<std::uint32_t>();
        o.mesh.lines = r.array<std::uint32_t>();
        o.model = r.pod<Mat4>();
        for (std::shared_ptr<const Texture>* t : material_textures(o.material)) {
            const auto index = r.pod<std::int32_t>();
            if (index >= static_cast<std::int32_t>(textures.size())) return std::nullopt;
            if (index >= 0) *t = textures[static_cast<std::size_t>(index)];
        }
        material_values(o.material, [&](auto& v) { v = r.pod<std::remove_reference_t<decltype(v)>>(); });
        m.scene.objects.push_back(std::move(o));
    }
    const auto warning_count = r.pod<std::uint64_t>();
    for (std::uint64_t i = 0; r.ok() && i < warning_count; ++i) m.warnings.push_back(r.text());
    if (!r.ok()) return std::nullopt;
    return m;
}

void write_result(Writer& w, const Result<LoadedModel>& result) {
    if (result) {
        w.pod(k_ok);
        write_model(w, result.value());
    } else {
        w.pod(k_failed);
        w.pod(result.error().code);
        w.text(result.error().message);
    }
}

// ---- the child ----

bool write_all(int fd, const std::vector<char>& bytes) {
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        done += static_cast<std::size_t>(n);
    }
    return true;
}

[[noreturn]] void child(int fd, const std::string& path, const LoadOptions& options, const IsolationLimits& limits) {
    // A crash is the child's to report by dying of it: handlers the parent installed (a Python
    // interpreter's faulthandler, which would print its own traceback) go back to the default.
    for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) signal(sig, SIG_DFL);
    if (limits.max_memory_bytes > 0) {
        const rlimit cap{limits.max_memory_bytes, limits.max_memory_bytes};
        setrlimit(RLIMIT_DATA, &cap);
    }
    // The confinement of facet's worker processes (facet/sandbox.hpp): files read only in the model's
    // folders, none written (the result goes to the memory file already open), no sockets, exec or
    // new processes.
    enter_sandbox(sandbox_rules_for_model(path, options.resource_dirs));
    sandbox_test_probe();
    int status = 1;
    try {
        Writer w;
        // A SIGBUS from a mapped file cut short ends this child: the parent reports it.
        LoadOptions mapped = options;
        mapped.map_files = true;
        write_result(w, load_model(path, mapped));
        status = write_all(fd, w.bytes()) ? 0 : 1;
    } catch (...) {  // std::bad_alloc under the memory cap: reported as such by the parent
        status = 2;
    }
    _exit(status);  // no atexit handlers or static destructors of the parent's program
}

// ---- the parent ----

enum class End { exited, signalled, timed_out };

// Waits for the child, killing it at the deadline; returns how it ended and its status or signal.
std::pair<End, int> wait_for(pid_t pid, double timeout_seconds) {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    auto pause = std::chrono::microseconds(200);
    for (;;) {
        int status = 0;
        const pid_t r = waitpid(pid, &status, WNOHANG);
        if (r == pid) {
            if (WIFSIGNALED(status)) return {End::signalled, WTERMSIG(status)};
            return {End::exited, WEXITSTATUS(status)};
        }
        if (r < 0 && errno != EINTR) return {End::exited, -1};
        if (timeout_seconds > 0 && std::chrono::duration<double>(Clock::now() - start).count() >= timeout_seconds) {
            kill(pid, SIGKILL);
            while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
            }
            return {End::timed_out, 0};
        }
        std::this_thread::sleep_for(pause);  // short at first: most files load in milliseconds
        pause = std::min<std::chrono::microseconds>(pause * 2, std::chrono::milliseconds(20));
    }
}

Result<LoadedModel> read_result(int fd, const std::string& path) {
    struct stat st {};
    if (fstat(fd, &st) != 0) return Error{ErrorCode::io, path + ": cannot read the loading process's result"};
    std::vector<char> bytes(static_cast<std::size_t>(st.st_size));
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = pread(fd, bytes.data() + done, bytes.size() - done, static_cast<off_t>(done));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        done += static_cast<std::size_t>(n);
    }
    Reader r(bytes.data(), done);
    const auto tag = r.pod<std::uint32_t>();
    if (r.ok() && tag == k_failed) {
        const auto code = r.pod<ErrorCode>();
        std::string message = r.text();
        if (r.ok()) return Error{code, std::move(message)};
    } else if (r.ok() && tag == k_ok) {
        if (std::optional<LoadedModel> m = read_model(r)) return std::move(*m);
    }
    return Error{ErrorCode::io, path + ": the loading process's result is incomplete"};
}

std::string signal_text(int sig) {
    const char* abbrev = sigabbrev_np(sig);
    const std::string name = abbrev ? std::string("SIG") + abbrev : "signal " + std::to_string(sig);
    const char* what = strsignal(sig);
    return what ? name + ": " + what : name;
}

}  // namespace

std::string describe_signal(int sig) { return signal_text(sig); }

Result<LoadedModel> load_model_isolated(const std::string& path, const LoadOptions& options,
                                        const IsolationLimits& limits) {
    const int fd = memfd_create("facet-model", MFD_CLOEXEC);
    if (fd < 0) return Error{ErrorCode::io, path + ": cannot create the loading process's result file (" +
                                                std::strerror(errno) + ")"};
    std::fflush(nullptr);  // nothing buffered may be written twice
    const pid_t pid = fork();
    if (pid < 0) {
        const int e = errno;
        close(fd);
        return Error{ErrorCode::io, path + ": cannot start a loading process (" + std::strerror(e) + ")"};
    }
    if (pid == 0) child(fd, path, options, limits);
    const auto [end, value] = wait_for(pid, limits.timeout_seconds);
    Result<LoadedModel> result = Error{ErrorCode::io, path + ": the loading process failed"};
    if (end == End::timed_out) {
        char seconds[32];
        std::snprintf(seconds, sizeof seconds, "%g", limits.timeout_seconds);
        result = Error{ErrorCode::limit_exceeded, path + ": gave up after " + seconds + " s"};
    } else if (end == End::signalled) {
        // The child maps large files (map_files): a SIGBUS is most likely one cut short meanwhile.
        result = Error{ErrorCode::bad_format, path + ": the importer crashed (" + signal_text(value) + ")" +
                                                  (value == SIGBUS ? mapped_file_crash_hint(path) : "")};
    } else if (value == 2) {
        result = Error{ErrorCode::limit_exceeded, path + ": needs more memory than is available"};
    } else if (value == 0) {
        result = read_result(fd, path);
    } else {
        result = Error{ErrorCode::io, path + ": the loading process exited with status " + std::to_string(value)};
    }
    close(fd);
    return result;
}

}  // namespace facet
