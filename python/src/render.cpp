// facet._facet.render and Renderer: a scene seen by one camera or a list of them into NumPy
// arrays, one per pass (facet/passes.hpp), through the library's ViewRenderer: without
// supersampling it draws straight into the colour array, and every pass comes from the visibility
// the colour resolves. The GIL is released from the first camera to the last image.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>

#include "binding.hpp"
#include "facet/views.hpp"

namespace facet::python {
namespace {

PassSet parse_passes(py::handle obj) {
    const std::string known = to_string(PassSet::all());
    std::vector<std::string> names;
    if (py::isinstance<py::str>(obj)) {
        names.push_back(obj.cast<std::string>());
    } else {
        try {
            names = obj.cast<std::vector<std::string>>();
        } catch (const py::cast_error&) {
            value_error("passes must be a sequence of pass names (" + known + ")");
        }
    }
    if (names.empty()) value_error("passes is empty: ask for at least one of " + known);
    PassSet passes;
    for (const std::string& n : names) {
        if (n.find(',') != std::string::npos) value_error("unknown pass '" + n + "' (passes: " + known + ")");
        Result<PassSet> one = facet::parse_passes(n);
        if (!one) value_error("unknown pass '" + n + "' (passes: " + known + ")");
        if ((passes.bits & one->bits) != 0) value_error("pass '" + n + "' is asked for twice");
        passes.bits |= one->bits;
    }
    return passes;
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

// render()'s point and line arguments, as `facet render`'s options: sizes in pixels of the output image.
struct PrimitiveArgs {
    double point_size = defaults::k_point_size;
    std::string point_shape = "round";
    std::optional<double> point_world_size;
    double line_width = defaults::k_line_width;
    bool line_aa = false;
};

// An environment light read once (facet.Environment) and shared by the renders given it.
struct PyEnvironment {
    std::shared_ptr<const Environment> light;
    std::string path;
};

std::shared_ptr<const Environment> load_environment(const std::string& path) {
    Result<std::shared_ptr<const Environment>> e = [&] {
        py::gil_scoped_release release;
        return Environment::load_hdr(path);
    }();
    if (!e) raise_file_error(e.error(), path);
    return *e;
}

// render()'s lit-mode and anti-aliasing arguments, as `facet render`'s --environment, --exposure,
// --tone-mapping, --aa and --contact-shadow.
struct LitArgs {
    py::object environment = py::none();  // None (the studio), a facet.Environment or a path
    double exposure = defaults::k_exposure;
    std::string tone_mapping = "neutral";
    Integer aa{defaults::k_aa};
    double contact_shadow = defaults::k_contact_shadow;
};

// Checked as `facet render` checks them; the contact shadow is the lit mode's only.
void set_lit(ViewRequest& r, const LitArgs& a) {
    if (antialias_offsets(static_cast<int>(std::clamp<long long>(a.aa.value, 0, 64))).empty())
        value_error("aa must be 1, 2, 4 or 8, got " + std::to_string(a.aa.value));
    r.aa = static_cast<int>(a.aa.value);
    if (!(a.exposure > 0 && std::isfinite(a.exposure)))
        value_error("exposure must be a positive number, got " + py::str(py::float_(a.exposure)).cast<std::string>());
    r.settings.exposure = static_cast<float>(a.exposure);
    if (!parse_tone_mapping(a.tone_mapping, r.settings.tone_mapping))
        value_error("tone_mapping must be 'neutral', 'aces' or 'linear', got '" + a.tone_mapping + "'");
    if (!(a.contact_shadow >= 0 && a.contact_shadow <= 1))
        value_error("contact_shadow must be 0..1, got " + py::str(py::float_(a.contact_shadow)).cast<std::string>());
    r.contact_shadow = r.settings.shading == Shading::lit ? static_cast<float>(a.contact_shadow) : 0.0f;
    const py::handle env = a.environment;
    if (py::isinstance<PyEnvironment>(env)) {
        r.settings.environment = env.cast<const PyEnvironment&>().light;
    } else if (py::isinstance<py::str>(env) || py::hasattr(env, "__fspath__")) {
        r.settings.environment = load_environment(py::str(py::module_::import("os").attr("fspath")(env)).cast<std::string>());
    } else if (!env.is_none()) {
        throw py::type_error("environment must be a facet.Environment, a path to a .hdr file or None, got " +
                             std::string(py::str(py::type::handle_of(env).attr("__name__"))));
    }
}

// The style of points and lines: the supersampled target draws them ssaa times larger.
void set_primitives(RenderSettings& s, const PrimitiveArgs& a, int ssaa) {
    const double most = PrimitiveStyle::k_max_point_size / ssaa;
    const std::string range = " must be more than 0 and at most 256 / ssaa pixels, got ";
    if (!(a.point_size > 0 && a.point_size <= most)) value_error("point_size" + range + py::str(py::float_(a.point_size)).cast<std::string>());
    if (!(a.line_width > 0 && a.line_width <= most)) value_error("line_width" + range + py::str(py::float_(a.line_width)).cast<std::string>());
    // Tested as the float the draw gets (the bound is a float; below 1e30 the conversion is defined).
    if (a.point_world_size && !(*a.point_world_size > 0 && *a.point_world_size < 1e30 &&
                                static_cast<float>(*a.point_world_size) < PrimitiveStyle::k_model_point_size_bound))
        value_error("point_world_size must be more than 0 and less than 1e30 model units, or None, got " +
                    py::str(py::float_(*a.point_world_size)).cast<std::string>());
    if (a.point_shape != "round" && a.point_shape != "square") value_error("point_shape must be 'round' or 'square'");
    PrimitiveStyle& style = s.primitives;
    style.point_size = a.point_world_size ? static_cast<float>(*a.point_world_size) : static_cast<float>(a.point_size) * static_cast<float>(ssaa);
    style.point_shape = a.point_shape == "square" ? PointShape::square : PointShape::round;
    style.line_width = static_cast<float>(a.line_width) * static_cast<float>(ssaa);
    style.line_aa = a.line_aa;
    s.point_size_in_model_units = a.point_world_size.has_value();
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
    ViewRequest request;
    std::vector<PassImages> out;  // one per view
};

}  // namespace

// A ViewRenderer and the cameras it keeps between calls; one call at a time (the lock).
class PyRenderer {
public:
    explicit PyRenderer(int threads) : views_({.threads = threads}) {}

    // Draws the job; called without the GIL.
    void draw(std::span<const ObjectView> objects, const Job& job) {
        const float aspect = static_cast<float>(job.request.width) / static_cast<float>(job.request.height);
        cameras_.clear();
        for (const ViewSpec& v : job.views) cameras_.push_back(make_camera(objects, v, aspect));
        stats_ = views_.render(objects, cameras_, job.request, job.out);
    }

    std::mutex& mutex() { return mutex_; }
    int threads() { return views_.renderer().threads(); }
    const DrawStats& stats() const { return stats_; }
    // How long the last render's draw took (seconds), for the benchmark of the Python overhead.
    double& draw_seconds() { return draw_seconds_; }

private:
    ViewRenderer views_;
    std::vector<Camera> cameras_;
    DrawStats stats_;
    double draw_seconds_ = 0;
    std::mutex mutex_;
};

namespace {

// None: one per core. More than a few thousand is a mistake, not a machine.
int checked_threads(std::optional<Integer> threads) { return threads ? in_range(*threads, "threads", 1, 4096) : 0; }

// The caller's array for `p` (checked_out) or a new one; returns its memory.
template <class T>
T* pass_output(Pass p, std::vector<py::ssize_t> shape, int channels, const py::dict& given, py::dict& result) {
    if (channels) shape.push_back(channels);
    const char* name = pass_name(p);
    py::array_t<T> a = given.contains(name) ? checked_out<T>(given[name], "out['" + std::string(name) + "']", shape)
                                            : aligned_array<T>(shape);
    result[name] = a;
    return a.mutable_data();
}

py::dict render(PyRenderer& r, py::object scene_obj, py::object cameras, Integer width_arg, Integer height_arg,
                py::object passes_obj, const std::string& shading, Integer ssaa_arg, py::object background,
                const std::string& normal_space, py::object out, const PrimitiveArgs& primitives, const LitArgs& lit) {
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
    ViewRequest& request = job.request;
    request.width = width, request.height = height, request.ssaa = ssaa;
    request.settings = parse_settings(shading, background);
    set_primitives(request.settings, primitives, ssaa);
    set_lit(request, lit);
    request.passes = parse_passes(passes_obj);
    if (normal_space != "world" && normal_space != "camera") value_error("normal_space must be 'world' or 'camera'");
    request.normal_space = normal_space == "camera" ? NormalSpace::camera : NormalSpace::world;

    // The outputs: the caller's (out=) or new arrays.
    std::vector<py::ssize_t> lead;
    if (batch) lead.push_back(static_cast<py::ssize_t>(job.views.size()));
    lead.push_back(height);
    lead.push_back(width);
    py::dict given;
    if (!out.is_none()) {
        if (!py::isinstance<py::dict>(out)) value_error("out must be a dict of arrays by pass name");
        given = py::reinterpret_borrow<py::dict>(out);
        for (auto item : given) {
            const std::string name = py::str(item.first);
            Result<PassSet> p = facet::parse_passes(name);
            if (!p || name.find(',') != std::string::npos || (p->bits & request.passes.bits) == 0)
                value_error("out['" + name + "'] is not among the passes asked for");
        }
    }
    py::dict result;
    PassImages first;  // the first view's images; the others follow, one image apart
    for (Pass p : k_all_passes) {
        if (!request.passes.has(p)) continue;
        PassTargets& t = first.passes;
        switch (p) {
            case Pass::colour: first.colour = reinterpret_cast<Rgba8*>(pass_output<std::uint8_t>(p, lead, 4, given, result)); break;
            case Pass::alpha: t.alpha = pass_output<float>(p, lead, 0, given, result); break;
            case Pass::depth: t.depth = pass_output<float>(p, lead, 0, given, result); break;
            case Pass::range: t.range = pass_output<float>(p, lead, 0, given, result); break;
            case Pass::normal: t.normal = reinterpret_cast<Vec3*>(pass_output<float>(p, lead, 3, given, result)); break;
            case Pass::instance: t.instance = pass_output<std::uint32_t>(p, lead, 0, given, result); break;
            case Pass::material: t.material = pass_output<std::uint32_t>(p, lead, 0, given, result); break;
            case Pass::primitive: t.primitive = pass_output<std::uint32_t>(p, lead, 0, given, result); break;
            case Pass::uv: t.uv = reinterpret_cast<Vec2*>(pass_output<float>(p, lead, 2, given, result)); break;
        }
    }
    const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    for (std::size_t i = 0; i < job.views.size(); ++i) {
        auto at = [&](auto* p) { return p ? p + i * pixels : nullptr; };
        PassImages v;
        v.colour = at(first.colour);
        const PassTargets& t = first.passes;
        v.passes = {at(t.alpha), at(t.depth), at(t.range), at(t.normal), at(t.instance), at(t.material), at(t.primitive), at(t.uv)};
        job.out.push_back(v);
    }
    std::optional<std::string> error;  // the request checks of ViewRenderer::render (all made above)
    {
        py::gil_scoped_release release;
        std::scoped_lock lock(r.mutex());
        std::shared_lock scene_lock(scene.mutex());  // other renders may read it too
        note_gil_state();
        const auto start = std::chrono::steady_clock::now();
        try {
            r.draw(scene.views(), job);
        } catch (const FacetError& e) {
            error = e.what();
        }
        r.draw_seconds() = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    if (error) value_error(*error);
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
    What to return, each from the same visibility (background value in brackets):
    'color' (H, W, 4) uint8 RGBA; 'alpha' (H, W) float32, the fraction of samples a surface
    covers (alpha-blended surfaces do not count) [0]; 'depth' (H, W) float32, distance along
    the viewing axis [inf]; 'range' (H, W) float32, distance from the eye along the ray [inf];
    'normal' (H, W, 3) float32 unit normals [0]; 'instance' (H, W) uint32, scene object + 1
    [0]; 'material' (H, W) uint32, material + 1 [0]; 'primitive' (H, W) uint32, triangle
    index within its mesh + 1 [0]; 'uv' (H, W, 2) float32 [0]. With ssaa, color and alpha
    average the samples, the other passes are the surface at each pixel's centre.
shading : str
    'lit' (default), 'lambert', 'flat', 'normals', 'mask', 'vertex-color', 'texture'; as
    `facet render --shading`.
ssaa : int
    Supersampling, NxN samples per pixel (1..8).
background : sequence of 3 or 4 floats in 0..1, or 'transparent', optional
    Default: `facet render`'s dark grey.
normal_space : str
    'world' (default) or 'camera' (x right, y up, z toward the viewer) for the normal pass.
point_size : float
    Diameter of the scene's points in pixels of the image (0 < size <= 256 / ssaa), as
    `facet render --point-size`.
point_shape : str
    'round' (default: the pixel centres within point_size / 2) or 'square'.
point_world_size : float, optional
    The points' diameter in model units instead (0 < size < 1e30), perspective-scaled (at most
    256 / ssaa pixels).
line_width : float
    Width of the scene's line segments in pixels of the image (0 < width <= 256 / ssaa).
line_aa : bool
    Anti-aliased lines: each blended by its coverage of the pixels, writing no depth, as
    `facet render --line-aa` (default False).
aa : int
    Anti-aliasing by jittered frames: 1 (default, none), 2, 4 or 8 frames (N frames cost
    about N renders); combines with ssaa. Color and alpha average every sample of every frame, the
    other passes are the unjittered frame's (the same as aa=1's). As `facet render --aa`.
environment : Environment, str or os.PathLike, optional
    The lit mode's light: a facet.Environment, or a Radiance .hdr path read (and
    prefiltered) on every call; keep a facet.Environment to render many times with one
    (default: the built-in studio). As `facet render --environment`.
exposure : float
    The lit mode's linear exposure factor before tone mapping (> 0, default 1).
tone_mapping : str
    The lit mode's display transform: 'neutral' (default, Khronos PBR Neutral), 'aces' or
    'linear' (clamp).
contact_shadow : float
    The lit mode's contact shadow under the model, its opacity 0..1 (default 0: none); in
    the color only.
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
    // The point and line arguments of Renderer.render and render, keyword-only, last.
    const py::arg_v point_size = py::arg("point_size") = double{defaults::k_point_size};
    const py::arg_v point_shape = py::arg("point_shape") = "round";
    const py::arg_v point_world_size = py::arg("point_world_size") = py::none();
    const py::arg_v line_width = py::arg("line_width") = double{defaults::k_line_width};
    const py::arg_v line_aa = py::arg("line_aa") = false;
    // The lit mode's and the jittered anti-aliasing's arguments, after them.
    const py::arg_v aa = py::arg("aa") = Integer{defaults::k_aa};
    const py::arg_v environment = py::arg("environment") = py::none();
    const py::arg_v exposure = py::arg("exposure") = double{defaults::k_exposure};
    const py::arg_v tone_mapping = py::arg("tone_mapping") = "neutral";
    const py::arg_v contact_shadow = py::arg("contact_shadow") = double{defaults::k_contact_shadow};
    py::class_<PyEnvironment>(m, "Environment", R"doc(An environment light for the lit mode, read once from a Radiance .hdr file.

Environment(path) reads the equirectangular image (+Y up, its centre column toward +X, as
three.js and <model-viewer> map them) and prefilters it for every roughness; render(...,
environment=env) then lights with it without reading the file again, from any thread. A
missing file raises FileNotFoundError, an unreadable one facet.Error, naming the file. The
GIL is released while reading.
)doc")
        .def(py::init([](const std::filesystem::path& path) {
                 return PyEnvironment{load_environment(path.string()), path.string()};
             }),
             py::arg("path"))
        .def_property_readonly("path", [](const PyEnvironment& e) { return e.path; }, "The file it was read from.")
        .def("__repr__", [](const PyEnvironment& e) {
            return "facet.Environment(" + py::repr(py::str(e.path)).cast<std::string>() + ")";
        });
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
               const std::string& shading, Integer ssaa, py::object background, const std::string& normal_space,
               py::object out, double point_size, const std::string& point_shape, std::optional<double> point_world_size,
               double line_width, bool line_aa, Integer aa, py::object environment, double exposure, const std::string& tone_mapping,
               double contact_shadow) {
                return render(r, scene, camera, width, height, passes, shading, ssaa, background, normal_space, out,
                              {point_size, point_shape, point_world_size, line_width, line_aa},
                              {environment, exposure, tone_mapping, aa, contact_shadow});
            },
            py::arg("scene"), py::arg("camera"), py::arg("width") = Integer{defaults::k_image_width},
            py::arg("height") = Integer{defaults::k_image_height}, py::kw_only(), py::arg("passes") = py::make_tuple("color"),
            py::arg("shading") = "lit", py::arg("ssaa") = Integer{defaults::k_ssaa},
            py::arg("background") = py::none(), py::arg("normal_space") = "world", py::arg("out") = py::none(),
            point_size, point_shape, point_world_size, line_width, line_aa, aa, environment, exposure, tone_mapping, contact_shadow,
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
                d["points_in"] = s.points_in;
                d["points_invalid"] = s.points_invalid;
                d["segments_in"] = s.segments_in;
                d["segments_invalid"] = s.segments_invalid;
                return d;
            },
            "What the last render drew: triangles_in, triangles_invalid (dropped: a non-finite vertex), "
            "triangles_culled, triangles_clipped, triangles_rasterized; points_in, segments_in and the "
            "points_invalid, segments_invalid dropped (a non-finite position).");

    m.def(
        "render",
        [](py::object scene, py::object camera, Integer width, Integer height, py::object passes, const std::string& shading,
           Integer ssaa, py::object background, const std::string& normal_space, std::optional<Integer> threads,
           double point_size, const std::string& point_shape, std::optional<double> point_world_size, double line_width,
           bool line_aa, Integer aa, py::object environment, double exposure, const std::string& tone_mapping, double contact_shadow) {
            PyRenderer r(checked_threads(threads));
            return render(r, scene, camera, width, height, passes, shading, ssaa, background, normal_space, py::none(),
                          {point_size, point_shape, point_world_size, line_width, line_aa},
                          {environment, exposure, tone_mapping, aa, contact_shadow});
        },
        py::arg("scene"), py::arg("camera"), py::arg("width") = Integer{defaults::k_image_width},
        py::arg("height") = Integer{defaults::k_image_height}, py::kw_only(), py::arg("passes") = py::make_tuple("color"),
        py::arg("shading") = "lit", py::arg("ssaa") = Integer{defaults::k_ssaa},
        py::arg("background") = py::none(), py::arg("normal_space") = "world", py::arg("threads") = py::none(),
        point_size, point_shape, point_world_size, line_width, line_aa, aa, environment, exposure, tone_mapping, contact_shadow,
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
              job.request.width = width, job.request.height = height;
              PassImages out;
              out.colour = reinterpret_cast<Rgba8*>(colour.mutable_data());
              job.out.push_back(out);
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
