// facet._facet: the module, its exceptions, and loading model files (load, load_isolated) into
// Scenes. Loading releases the GIL; errors carry facet's message.
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "binding.hpp"
#include "facet/io.hpp"

namespace facet::python {
namespace {

std::atomic<bool> g_gil_held_at_last_call{false};
py::object g_error_type;    // facet.Error
py::object g_warning_type;  // facet.LoadWarning

const char* code_name(ErrorCode code) {
    switch (code) {
        case ErrorCode::invalid_argument: return "invalid_argument";
        case ErrorCode::io: return "io";
        case ErrorCode::bad_format: return "bad_format";
        case ErrorCode::unsupported: return "unsupported";
        case ErrorCode::limit_exceeded: return "limit_exceeded";
    }
    return "error";
}

LoadOptions load_options(float crease_angle, const std::string& up_axis, Integer max_triangles, Integer max_texture_size,
                         std::optional<Integer> threads) {
    LoadOptions o;
    if (!(crease_angle >= 0 && crease_angle <= 180)) value_error("crease_angle must be 0..180 degrees");
    if (up_axis != "y" && up_axis != "z") value_error("up_axis must be 'y' or 'z', got '" + up_axis + "'");
    if (max_triangles.value < 1) value_error("max_triangles must be 1 or more");
    in_range(max_texture_size, "max_texture_size", 1, INT_MAX);
    if (threads) in_range(*threads, "threads", 1, INT_MAX);
    o.crease_angle_degrees = crease_angle;
    o.up_axis = up_axis == "z" ? UpAxis::z : UpAxis::y;
    o.max_triangles = static_cast<std::size_t>(max_triangles.value);
    // As `facet render --max-texture-size`: a side limit, and at most its square in pixels.
    o.texture_limits.max_size = static_cast<int>(max_texture_size.value);
    const auto side = static_cast<std::size_t>(max_texture_size.value);
    o.texture_limits.max_pixels = std::min(o.texture_limits.max_pixels, side * side);
    o.threads = threads ? static_cast<int>(threads->value) : 0;
    return o;
}

// The scene, its warnings issued as facet.LoadWarning; failures as raise_file_error.
std::shared_ptr<PyScene> finish_load(Result<LoadedModel> model, const std::string& path) {
    if (!model) raise_file_error(model.error(), path);
    for (const std::string& w : model->warnings)
        if (PyErr_WarnEx(g_warning_type.ptr(), w.c_str(), 2) != 0) throw py::error_already_set();
    return PyScene::from_loaded(std::move(*model));
}

}  // namespace

void value_error(const std::string& message) { throw py::value_error(message); }

void raise_file_error(const Error& error, const std::string& path) {
    std::error_code ec;
    if (error.code == ErrorCode::io && !std::filesystem::exists(path, ec)) {
        // (errno, strerror, filename), as open() raises it: given the message alone with errno and filename set
        // after, str(e) read "[Errno 2] None: 'path'".
        py::object e = py::reinterpret_steal<py::object>(
            PyObject_CallFunction(PyExc_FileNotFoundError, "iss", ENOENT, std::strerror(ENOENT), path.c_str()));
        if (!e) throw py::error_already_set();
        PyErr_SetObject(PyExc_FileNotFoundError, e.ptr());
        throw py::error_already_set();
    }
    raise_facet_error(error);
}

int in_range(Integer v, const char* name, long long lo, long long hi) {
    if (v.value < lo || v.value > hi)
        value_error(std::string(name) + " must be " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " +
                    (v.value == LLONG_MAX ? std::string("more") : v.value == LLONG_MIN ? std::string("less") : std::to_string(v.value)));
    return static_cast<int>(v.value);
}

void note_gil_state() { g_gil_held_at_last_call = PyGILState_Check() != 0; }

void raise_facet_error(const Error& error) {
    py::object e = g_error_type(error.message);
    e.attr("code") = code_name(error.code);
    PyErr_SetObject(g_error_type.ptr(), e.ptr());
    throw py::error_already_set();
}

}  // namespace facet::python

using namespace facet;
using namespace facet::python;

PYBIND11_MODULE(_facet, m) {
    m.doc() = "facet's C++ core; use the `facet` package.";
    m.attr("__version__") = FACET_VERSION;

    g_error_type = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
        "facet.Error",
        "A model file could not be loaded (or another failure of facet's own): the message names the file and the "
        "problem, `code` says which kind: 'io', 'bad_format', 'unsupported', 'limit_exceeded'.",
        PyExc_RuntimeError, nullptr));
    g_error_type.attr("code") = "error";
    m.attr("Error") = g_error_type;
    g_warning_type = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
        "facet.LoadWarning", "Recoverable trouble while loading (a missing texture, invalid triangles dropped).",
        PyExc_UserWarning, nullptr));
    m.attr("LoadWarning") = g_warning_type;
    // The library's own argument errors (FacetError, invalid_argument) are ValueErrors.
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const FacetError& e) {
            if (e.error().code == ErrorCode::invalid_argument) PyErr_SetString(PyExc_ValueError, e.what());
            else raise_facet_error(e.error());
        }
    });

    m.def("_gil_held_at_last_call", [] { return g_gil_held_at_last_call.load(); },
          "Whether the last load or render held the GIL where it called the library (for the tests).");

    bind_scene(m);
    bind_camera(m);
    bind_render(m);

    const LoadOptions load_defaults;
    m.def(
        "load",
        [](const std::filesystem::path& file, float crease_angle, const std::string& up_axis, Integer max_triangles,
           Integer max_texture_size, std::optional<Integer> threads) {
            const LoadOptions options = load_options(crease_angle, up_axis, max_triangles, max_texture_size, threads);
            const std::string path = file.string();
            Result<LoadedModel> model = [&] {
                py::gil_scoped_release release;
                note_gil_state();
                return load_model(path, options);
            }();
            return finish_load(std::move(model), path);
        },
        py::arg("path"), py::kw_only(), py::arg("crease_angle") = load_defaults.crease_angle_degrees,
        py::arg("up_axis") = "y", py::arg("max_triangles") = Integer{static_cast<long long>(load_defaults.max_triangles)},
        py::arg("max_texture_size") = Integer{load_defaults.texture_limits.max_size}, py::arg("threads") = py::none(),
        R"doc(Load a model file into a Scene, as `facet render` does.

Every format `facet render` reads (OBJ + MTL, STL, PLY, OFF, glTF / GLB, FBX, 3MF, COLLADA, ...),
with the same limits, checked before anything large is allocated, and the same normals for
files without them.

Parameters
----------
path : str or os.PathLike
    The model file.
crease_angle : float
    Degrees. Normals computed for files without them are split where faces meet at more
    than this (`--crease-angle`).
up_axis : {'y', 'z'}
    Which axis of the file is up ('z': CAD, STL and 3MF files often are).
max_triangles : int
    Refuse larger models before loading them (`--max-triangles`).
max_texture_size : int
    Textures larger than this per side (or its square in pixels) are left out with a warning.
threads : int or None
    Threads for computing normals of large meshes; None: all cores. The result is the same.

Returns
-------
Scene

Raises
------
FileNotFoundError
    The file does not exist.
facet.Error
    The file cannot be read, is malformed, unsupported or over a limit; the message names
    the file and the problem, `code` says which.

Warns
-----
facet.LoadWarning
    Recoverable trouble: a missing texture, invalid triangles dropped (also in Scene.warnings).

Notes
-----
The model reader runs in this process. A few damaged files crash or hang assimp itself; load
files you do not trust with `load_isolated`. The GIL is released while loading.
)doc");

    m.def(
        "write_png",
        [](const std::filesystem::path& file, py::object image) {
            py::array a;
            try {
                a = py::array::ensure(image);
            } catch (const py::error_already_set&) {
            }
            if (!a || !a.dtype().is(py::dtype::of<std::uint8_t>()) || a.ndim() != 3 || (a.shape(2) != 3 && a.shape(2) != 4) ||
                a.shape(0) < 1 || a.shape(1) < 1)
                value_error("image must be a uint8 array of shape (H, W, 3) or (H, W, 4)");
            const auto px = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(a);
            Image out{static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)), {}};
            out.pixels.resize(static_cast<std::size_t>(out.width) * out.height);
            const auto channels = static_cast<std::size_t>(a.shape(2));
            for (std::size_t i = 0; i < out.pixels.size(); ++i) {
                const std::uint8_t* p = px.data() + i * channels;
                out.pixels[i] = {p[0], p[1], p[2], channels == 4 ? p[3] : std::uint8_t{255}};
            }
            Status s = [&] {
                py::gil_scoped_release release;
                return write_png(file.string(), out);
            }();
            if (!s) raise_facet_error(s.error());
        },
        py::arg("path"), py::arg("image"), R"doc(Write an image to a PNG file, as `facet render` writes its output.

8-bit RGB when every pixel is opaque, RGBA otherwise. Written to a temporary file and renamed,
so a failed write never leaves a partial file.

Parameters
----------
path : str or os.PathLike
image : numpy.ndarray, shape (H, W, 3) or (H, W, 4), uint8
    Rows top first, as render returns them.

Raises
------
ValueError
    The image is not a uint8 (H, W, 3|4) array.
facet.Error
    The file cannot be written (the message names it).
)doc");

    m.def(
        "load_isolated",
        [](const std::filesystem::path& file, double timeout, std::optional<Integer> max_memory, float crease_angle,
           const std::string& up_axis, Integer max_triangles, Integer max_texture_size, std::optional<Integer> threads) {
            const LoadOptions options = load_options(crease_angle, up_axis, max_triangles, max_texture_size, threads);
            const std::string path = file.string();
            if (!(timeout >= 0 && std::isfinite(timeout))) value_error("timeout must be 0 (no limit) or a number of seconds");
            IsolationLimits limits;
            limits.timeout_seconds = timeout;
            if (max_memory && max_memory->value < 1) value_error("max_memory must be None (no limit) or a number of bytes");
            limits.max_memory_bytes = max_memory ? static_cast<std::uint64_t>(max_memory->value) : 0;
            Result<LoadedModel> model = [&] {
                py::gil_scoped_release release;
                note_gil_state();
                return load_model_isolated(path, options, limits);
            }();
            return finish_load(std::move(model), path);
        },
        py::arg("path"), py::kw_only(), py::arg("timeout") = defaults::k_timeout_seconds,
        py::arg("max_memory") = py::none(), py::arg("crease_angle") = load_defaults.crease_angle_degrees,
        py::arg("up_axis") = "y", py::arg("max_triangles") = Integer{static_cast<long long>(load_defaults.max_triangles)},
        py::arg("max_texture_size") = Integer{load_defaults.texture_limits.max_size}, py::arg("threads") = py::none(),
        R"doc(Load a model file you do not trust: `load` in a child process.

A file that crashes, hangs or exhausts memory inside the model reader gives a facet.Error
("the importer crashed (SIGSEGV: Segmentation fault)", "gave up after 60 s", "needs more
memory than is available") and this process goes on. Costs a fork and a copy of the scene
(about a millisecond per megabyte).

Parameters
----------
path : str or os.PathLike
timeout : float
    Seconds before the child is killed; 0: no limit.
max_memory : int or None
    The child's memory cap in bytes; None: no limit.
crease_angle, up_axis, max_triangles, max_texture_size, threads
    As for `load`.

Returns
-------
Scene

Raises
------
FileNotFoundError, facet.Error
    As for `load`, and facet.Error when the child crashed, hung or ran out of memory.
)doc");
}
