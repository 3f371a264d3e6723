// facet._facet.render and Renderer: a scene seen by one camera or a list of them into NumPy
// arrays, one per pass. Without supersampling the renderer draws straight into the colour array
// (Framebuffer::use_colour_memory); with it, resolve_supersampled writes the array. The GIL is
// released from the first camera to the last image.
#include <algorithm>
#include <chrono>
#include <mutex>

#include "binding.hpp"

namespace facet::python {
namespace {

// The passes this build renders, and those of the render-passes issue still to come, which are
// refused by name rather than as unknown.
constexpr const char* k_passes[] = {"color", "alpha"};
constexpr const char* k_future_passes[] = {"depth", "range", "normal", "instance", "material", "primitive", "uv"};

struct Passes {
    bool color = false, alpha = false;
};

std::string available_passes() {
    std::string s;
    for (const char* p : k_passes) s += (s.empty() ? "" : ", ") + std::string(p);
    return s;
}

Passes parse_passes(py::handle obj) {
    std::vector<std::string> names;
    if (py::isinstance<py::str>(obj)) {
        names.push_back(obj.cast<std::string>());
    } else {
        try {
            names = obj.cast<std::vector<std::string>>();
        } catch (const py::cast_error&) {
            value_error("passes must be a sequence of pass names (" + available_passes() + ")");
        }
    }
    if (names.empty()) value_error("passes is empty: ask for at least one of " + available_passes());
    Passes p;
    for (const std::string& n : names) {
        if (n == "color") p.color = true;
        else if (n == "alpha") p.alpha = true;
        else if (std::find(std::begin(k_future_passes), std::end(k_future_passes), n) != std::end(k_future_passes))
            value_error("pass '" + n + "' is not available yet (available: " + available_passes() + ")");
        else
            value_error("unknown pass '" + n + "' (available: " + available_passes() + ")");
    }
    return p;
}

RenderSettings parse_settings(const std::string& shading, py::handle background) {
    RenderSettings s;
    if (!parse_shading(shading, s.shading))
        value_error("unknown shading '" + shading + "' (lit, lambert, flat, normals, mask, vertex-color, texture)");
    if (py::isinstance<py::str>(background)) {
        if (background.cast<std::string>() != "transparent")
            value_error("background must be (R, G, B[, A]) in 0..1 or 'transparent'");
        s.background = {0, 0, 0, 0};
    } else if (!background.is_none()) {
        s.background = checked_colour(background, "background");
    }
    return s;
}

// An uninitialized C-contiguous array of `shape`, its memory 64-byte aligned (the renderer writes
// whole aligned rows fastest) and owned by the array.
template <class T>
py::array_t<T> aligned_array(std::vector<py::ssize_t> shape) {
    std::size_t n = 1;
    for (py::ssize_t d : shape) n *= static_cast<std::size_t>(d);
    constexpr std::align_val_t k_alignment{64};
    void* memory = ::operator new(std::max<std::size_t>(n * sizeof(T), 1), k_alignment);
    py::capsule owner(memory, [](void* p) { ::operator delete(p, k_alignment); });
    return py::array_t<T>(shape, static_cast<T*>(memory), owner);
}

// A caller's output array: C-contiguous, writeable, of `T` and `shape`; named for errors.
template <class T>
py::array_t<T> checked_out(py::handle obj, const std::string& name, const std::vector<py::ssize_t>& shape) {
    auto fail = [&] {
        std::string s = "(";
        for (std::size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
        value_error(name + " must be a C-contiguous, writeable " + std::string(py::str(py::dtype::of<T>())) + " array of shape " +
                    s + ")");
    };
    if (!py::isinstance<py::array>(obj)) fail();
    const py::array a = py::reinterpret_borrow<py::array>(obj);
    if (!a.dtype().is(py::dtype::of<T>()) || !(a.flags() & py::array::c_style) || !a.writeable() ||
        a.ndim() != static_cast<py::ssize_t>(shape.size()))
        fail();
    for (std::size_t i = 0; i < shape.size(); ++i)
        if (a.shape(static_cast<py::ssize_t>(i)) != shape[i]) fail();
    return py::reinterpret_borrow<py::array_t<T>>(a);
}

// What one render call draws, settled while the GIL is held.
struct Job {
    std::vector<ViewSpec> views;
    int width = 0, height = 0, ssaa = 1;
    RenderSettings settings;
    Rgba8* colour = nullptr;  // views.size() images, or null
    float* alpha = nullptr;   // likewise
};

// Coverage from the depth the draw left: a sample is covered when some surface wrote depth there
// (the clear value is 1, which the default depth test never lets a surface write). Blended
// surfaces do not write depth.
void resolve_alpha(const Framebuffer& fb, int factor, float* out) {
    const int w = fb.width() / factor, h = fb.height() / factor;
    const float per_sample = 1.0f / static_cast<float>(factor * factor);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            int covered = 0;
            for (int sy = 0; sy < factor; ++sy)
                for (int sx = 0; sx < factor; ++sx) covered += fb.depth(x * factor + sx, y * factor + sy) < 1.0f;
            out[static_cast<std::size_t>(y) * w + x] = static_cast<float>(covered) * per_sample;
        }
}

}  // namespace

// A Renderer and the target it keeps between calls; one call at a time (the lock).
class PyRenderer {
public:
    explicit PyRenderer(int threads) : renderer_({.threads = threads}) {}

    // Draws the job; called without the GIL.
    void draw(std::span<const ObjectView> objects, const Job& job) {
        const int tw = job.width * job.ssaa, th = job.height * job.ssaa;
        if (!target_ || target_->width() != tw || target_->height() != th) target_.emplace(tw, th);
        const std::size_t pixels = static_cast<std::size_t>(job.width) * job.height;
        const float aspect = static_cast<float>(job.width) / static_cast<float>(job.height);
        stats_ = {};
        for (std::size_t i = 0; i < job.views.size(); ++i) {
            const Camera camera = make_camera(objects, job.views[i], aspect);
            Rgba8* colour = job.colour ? job.colour + i * pixels : nullptr;
            // Without supersampling, straight into the caller's image.
            target_->use_colour_memory(job.ssaa == 1 ? colour : nullptr);
            stats_ += render_scene(renderer_, *target_, objects, camera, job.settings);
            if (job.ssaa > 1 && colour) resolve_supersampled(*target_, job.ssaa, colour, nullptr);
            if (job.alpha) resolve_alpha(*target_, job.ssaa, job.alpha + i * pixels);
        }
        target_->use_colour_memory(nullptr);
    }

    std::mutex& mutex() { return mutex_; }
    int threads() const { return renderer_.threads(); }
    const DrawStats& stats() const { return stats_; }
    // How long the last render's draw took (seconds), for the benchmark of the Python overhead.
    double& draw_seconds() { return draw_seconds_; }

private:
    Renderer renderer_;
    std::optional<Framebuffer> target_;
    DrawStats stats_;
    double draw_seconds_ = 0;
    std::mutex mutex_;
};

namespace {

// None: one per core. More than a few thousand is a mistake, not a machine.
int checked_threads(std::optional<Integer> threads) { return threads ? in_range(*threads, "threads", 1, 4096) : 0; }

py::dict render(PyRenderer& r, py::object scene_obj, py::object cameras, Integer width_arg, Integer height_arg,
                py::object passes_obj, const std::string& shading, Integer ssaa_arg, py::object background, py::object out) {
    PyScene& scene = scene_of(scene_obj);
    Job job;
    const bool batch = !py::isinstance<PyCamera>(cameras);
    if (batch) {
        if (!py::isinstance<py::sequence>(cameras) || py::isinstance<py::str>(cameras))
            throw py::type_error("camera must be a facet.Camera or a list of them");
        for (py::handle c : cameras) job.views.push_back(camera_of(c).spec);
        if (job.views.empty()) value_error("the list of cameras is empty");
    } else {
        job.views.push_back(camera_of(cameras).spec);
    }
    const int width = in_range(width_arg, "width", 1, k_max_target_size);
    const int height = in_range(height_arg, "height", 1, k_max_target_size);
    const int ssaa = in_range(ssaa_arg, "ssaa", 1, 8);
    if (static_cast<long>(width) * ssaa > k_max_target_size || static_cast<long>(height) * ssaa > k_max_target_size)
        value_error("width and height times ssaa must stay within " + std::to_string(k_max_target_size));
    job.width = width, job.height = height, job.ssaa = ssaa;
    job.settings = parse_settings(shading, background);
    const Passes passes = parse_passes(passes_obj);

    // The outputs: the caller's (out=) or new arrays.
    std::vector<py::ssize_t> lead;
    if (batch) lead.push_back(static_cast<py::ssize_t>(job.views.size()));
    lead.push_back(height);
    lead.push_back(width);
    py::dict out_arrays;
    if (!out.is_none()) {
        if (!py::isinstance<py::dict>(out)) value_error("out must be a dict of arrays by pass name");
        out_arrays = py::reinterpret_borrow<py::dict>(out);
        for (auto item : out_arrays) {
            const std::string name = py::str(item.first);
            if ((name == "color" && !passes.color) || (name == "alpha" && !passes.alpha) || (name != "color" && name != "alpha"))
                value_error("out['" + name + "'] is not among the passes asked for");
        }
    }
    py::dict result;
    if (passes.color) {
        std::vector<py::ssize_t> shape = lead;
        shape.push_back(4);
        py::array_t<std::uint8_t> a = out_arrays.contains("color") ? checked_out<std::uint8_t>(out_arrays["color"], "out['color']", shape)
                                                                 : aligned_array<std::uint8_t>(shape);
        job.colour = reinterpret_cast<Rgba8*>(a.mutable_data());
        result["color"] = a;
    }
    if (passes.alpha) {
        py::array_t<float> a = out_arrays.contains("alpha") ? checked_out<float>(out_arrays["alpha"], "out['alpha']", lead)
                                                          : aligned_array<float>(lead);
        job.alpha = a.mutable_data();
        result["alpha"] = a;
    }
    {
        py::gil_scoped_release release;
        std::scoped_lock lock(r.mutex());
        std::shared_lock scene_lock(scene.mutex());  // other renders may read it too
        note_gil_state();
        const auto start = std::chrono::steady_clock::now();
        r.draw(scene.views(), job);
        r.draw_seconds() = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return result;
}

const char* k_render_doc = R"doc(

Parameters
----------
scene : Scene
camera : Camera or list of Camera
    A list of N cameras gives arrays with a leading axis of N.
width, height : int
    Image size in pixels, 1..8192 (default 800x600, as `facet render`).
passes : sequence of str
    What to return: 'color' (H, W, 4) uint8 RGBA; 'alpha' (H, W) float32, the fraction of
    samples a surface covers (alpha-blended surfaces do not count). Later passes (depth,
    normal, instance, ...) raise ValueError until they exist.
shading : str
    'lit' (default), 'lambert', 'flat', 'normals', 'mask', 'vertex-color', 'texture'; as
    `facet render --shading`.
ssaa : int
    Supersampling, NxN samples per pixel (1..8).
background : sequence of 3 or 4 floats in 0..1, or 'transparent', optional
    Default: `facet render`'s dark grey.
%s
Returns
-------
dict of str to numpy.ndarray
    One array per pass, rows top first.

Notes
-----
The same scene, camera and options give the same bytes as `facet render`'s PNG, for any
number of threads. The GIL is released while rendering: renders in several threads run in
parallel.
)doc";

// The docstring: a summary, the parameters with `extra` ones last, what is returned.
std::string doc(const char* summary, const char* extra) {
    const std::string body = k_render_doc;
    const std::size_t at = body.find("%s");
    return summary + body.substr(0, at) + extra + body.substr(at + 2);
}

}  // namespace

PyScene& scene_of(py::handle obj) {
    try {
        return obj.cast<PyScene&>();
    } catch (const py::cast_error&) {
        throw py::type_error("scene must be a facet.Scene, got " + std::string(py::str(py::type::handle_of(obj).attr("__name__"))));
    }
}

void bind_render(py::module_& m) {
    py::class_<PyRenderer>(m, "Renderer", R"doc(A renderer that keeps its threads and memory between calls.

Renderer(threads=None) starts `threads` workers (None: one per core); render() then draws
without allocating anything but the arrays it returns (none, with out=). One render at a time
per Renderer: calls from several threads take turns; use a Renderer per thread to render in
parallel.
)doc")
        .def(py::init([](std::optional<Integer> threads) { return std::make_unique<PyRenderer>(checked_threads(threads)); }),
             py::arg("threads") = py::none())
        .def(
            "render",
            [](PyRenderer& r, py::object scene, py::object camera, Integer width, Integer height, py::object passes,
               const std::string& shading, Integer ssaa, py::object background, py::object out) {
                return render(r, scene, camera, width, height, passes, shading, ssaa, background, out);
            },
            py::arg("scene"), py::arg("camera"), py::arg("width") = Integer{defaults::k_image_width},
            py::arg("height") = Integer{defaults::k_image_height}, py::kw_only(), py::arg("passes") = py::make_tuple("color"),
            py::arg("shading") = "lit", py::arg("ssaa") = Integer{defaults::k_ssaa},
            py::arg("background") = py::none(), py::arg("out") = py::none(),
            doc("Render `scene` seen by `camera` into arrays.",
                "out : dict of str to numpy.ndarray, optional\n    Arrays to render into (C-contiguous, of each pass's "
                "shape and dtype),\n    returned in the dict: no allocation.\n")
                .c_str())
        .def_property_readonly("threads", &PyRenderer::threads, "Threads drawing, the calling one included.")
        .def_property_readonly(
            "_last_draw_seconds", [](PyRenderer& r) { return r.draw_seconds(); },
            "The last render's draw, timed in C++ (what the call adds to it is the Python overhead).")
        .def_property_readonly(
            "stats",
            [](const PyRenderer& r) {
                const DrawStats& s = r.stats();
                py::dict d;
                d["triangles_in"] = s.triangles_in;
                d["triangles_invalid"] = s.triangles_invalid;
                d["triangles_culled"] = s.triangles_culled;
                d["triangles_clipped"] = s.triangles_clipped;
                d["triangles_rasterized"] = s.triangles_rasterized;
                return d;
            },
            "What the last render drew: triangles_in, triangles_invalid (dropped: a non-finite vertex), "
            "triangles_culled, triangles_clipped, triangles_rasterized.");

    m.def(
        "render",
        [](py::object scene, py::object camera, Integer width, Integer height, py::object passes, const std::string& shading,
           Integer ssaa, py::object background, std::optional<Integer> threads) {
            PyRenderer r(checked_threads(threads));
            return render(r, scene, camera, width, height, passes, shading, ssaa, background, py::none());
        },
        py::arg("scene"), py::arg("camera"), py::arg("width") = Integer{defaults::k_image_width},
        py::arg("height") = Integer{defaults::k_image_height}, py::kw_only(), py::arg("passes") = py::make_tuple("color"),
        py::arg("shading") = "lit", py::arg("ssaa") = Integer{defaults::k_ssaa},
        py::arg("background") = py::none(), py::arg("threads") = py::none(),
        doc("Render `scene` seen by `camera` into arrays (with a Renderer made for the call; keep a\nfacet.Renderer "
            "for many renders).",
            "threads : int, optional\n    Threads drawing; None: one per core. The image is the same.\n")
            .c_str());

    // For docs/BENCHMARKS.md: the C++ side of Renderer.render alone, timed in C++ (per frame,
    // seconds), so the Python overhead is the difference in the same process and renderer.
    m.def("_time_cpp_render",
          [](PyRenderer& r, py::object scene_obj, py::object camera, int width, int height, int frames) {
              PyScene& scene = scene_of(scene_obj);
              // The image in memory like Renderer.render's arrays (aligned_array): the same draw.
              py::array_t<std::uint8_t> colour = aligned_array<std::uint8_t>({height, width, 4});
              Job job;
              job.views.push_back(camera_of(camera).spec);
              job.width = width, job.height = height;
              job.colour = reinterpret_cast<Rgba8*>(colour.mutable_data());
              std::vector<double> seconds;
              py::gil_scoped_release release;
              std::scoped_lock lock(r.mutex());
              std::shared_lock scene_lock(scene.mutex());
              for (int i = 0; i < frames; ++i) {
                  const auto start = std::chrono::steady_clock::now();
                  r.draw(scene.views(), job);
                  seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
              }
              return seconds;
          });
}

}  // namespace facet::python
