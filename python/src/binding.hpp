// facet's Python package, the C++ side (module `facet._facet`): what the binding's files share.
// NumPy arrays come in as ObjectViews over their own memory (no copy when they are contiguous
// float32 / uint32 already), images go out as arrays whose memory the renderer drew into. Every
// argument is checked here, whatever the Python layer above did: a bad one is a ValueError naming
// it, never a crash. Rendering and loading release the GIL.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <climits>
#include <cstdint>
#include <memory>
#include <shared_mutex>
#include <string>
#include <vector>

#include "facet/model.hpp"
#include "facet/scene.hpp"

namespace facet::python {

namespace py = pybind11;

// An integer argument however large Python's is, saturated to long long: an absurd size reaches its
// range check (a ValueError naming it) instead of failing conversion (a TypeError about overloads).
struct Integer {
    long long value = 0;
};
// `v` when in lo..hi, else a ValueError "NAME must be LO..HI, got V".
int in_range(Integer v, const char* name, long long lo, long long hi);

// A ValueError (or the facet.Error of load failures) with facet's message, thrown through pybind11.
[[noreturn]] void value_error(const std::string& message);
// facet.Error carrying `error.code` as the exception's `code` ("bad_format", "limit_exceeded", ...).
[[noreturn]] void raise_facet_error(const Error& error);
// Reading the file at `path` failed: a FileNotFoundError when it does not exist, else facet.Error.
[[noreturn]] void raise_file_error(const Error& error, const std::string& path);

// A scene the Python Scene object holds: loaded objects (owned) and meshes over the caller's
// arrays (borrowed, kept alive by the references held here), in the order they were added, and
// the ObjectViews over all of them that rendering reads. A render reads it without the GIL, under
// the shared lock; adding a mesh takes the exclusive one.
class PyScene {
public:
    // One mesh given as arrays: the references that keep them alive, its material and its view.
    struct Borrowed {
        std::vector<py::object> keep_alive;
        Material material;
        ObjectView view;
    };

    static std::shared_ptr<PyScene> from_loaded(LoadedModel model);

    // Adds an object: `owned` (its arrays in library memory, e.g. with computed normals) or
    // `borrowed`. Returns its index.
    std::size_t add_owned(SceneObject owned);
    std::size_t add_borrowed(std::unique_ptr<Borrowed> borrowed);

    std::span<const ObjectView> views() const { return views_; }
    std::shared_mutex& mutex() const { return mutex_; }
    const std::vector<std::string>& warnings() const { return warnings_; }
    std::size_t triangle_count() const;

private:
    void rebuild_views();

    Scene owned_;
    std::vector<std::unique_ptr<Borrowed>> borrowed_;
    struct Slot {
        bool owned;
        std::size_t index;
    };
    std::vector<Slot> order_;
    std::vector<ObjectView> views_;
    std::vector<std::string> warnings_;
    mutable std::shared_mutex mutex_;
};

// How a Python Camera is resolved against a scene: a ViewSpec (make_camera's), and what made it.
struct PyCamera {
    ViewSpec spec;
    std::string kind;  // "orbit", "look_at", "intrinsics", for repr
};

// `min` to `max` numbers (a ValueError "NAME must be WHAT" otherwise).
std::vector<double> checked_numbers(py::handle obj, const std::string& name, std::size_t min, std::size_t max,
                                    const std::string& what);
// 3 or 4 numbers in 0..1 (R, G, B[, A]; A 1 when left out); `name` for the error.
Vec4 checked_colour(py::handle obj, const char* name);

// The scene behind a Python Scene object (a TypeError unless it is one).
PyScene& scene_of(py::handle obj);
PyCamera& camera_of(py::handle obj);

// Records whether the calling thread holds the GIL, at the point where load and render call the
// library: the tests check that they do not (_facet._gil_held_at_last_call()).
void note_gil_state();

// Sections of the module, one per file.
void bind_scene(py::module_& m);
void bind_camera(py::module_& m);
void bind_render(py::module_& m);

}  // namespace facet::python

namespace pybind11::detail {
// Any Python int (or object with __index__, as NumPy's integers), shown as `int` in signatures.
template <>
struct type_caster<facet::python::Integer> {
    PYBIND11_TYPE_CASTER(facet::python::Integer, const_name("int"));
    bool load(handle src, bool) {
        if (!src || PyFloat_Check(src.ptr()) || !PyIndex_Check(src.ptr())) return false;
        const object i = reinterpret_steal<object>(PyNumber_Index(src.ptr()));
        if (!i) {
            PyErr_Clear();
            return false;
        }
        int overflow = 0;
        const long long v = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
        value.value = overflow > 0 ? LLONG_MAX : overflow < 0 ? LLONG_MIN : v;
        return true;
    }
    static handle cast(const facet::python::Integer& v, return_value_policy, handle) {
        return PyLong_FromLongLong(v.value);
    }
};
}  // namespace pybind11::detail
