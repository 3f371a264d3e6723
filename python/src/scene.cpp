// facet._facet.Scene: meshes from NumPy arrays (or anything with .vertices and .faces) and loaded
// models, held as ObjectViews for render_scene. Arrays that are C-contiguous float32 (vertices,
// normals, RGBA colours, uvs) and uint32 (faces) already are used in place; others are converted
// once. Bad arrays are ValueErrors naming the argument.
#include <cmath>
#include <limits>
#include <mutex>

#include "binding.hpp"

namespace facet::python {
namespace {

std::string shape_text(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

// `obj` as an array of real numbers (any float or integer dtype; never bool, complex, object or
// strings) of shape (rows, one of `columns`): `rows` -1 takes any number of rows.
py::array checked_array(py::handle obj, const char* name, py::ssize_t rows, std::initializer_list<py::ssize_t> columns,
                        const char* shape_doc) {
    py::array a;
    try {
        a = py::array::ensure(obj);
    } catch (const py::error_already_set&) {
    }
    if (!a) value_error(std::string(name) + " must be an array, got " + std::string(py::str(py::type::handle_of(obj).attr("__name__"))));
    const char kind = a.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u')
        value_error(std::string(name) + " must hold numbers, got dtype " + std::string(py::str(a.dtype())));
    bool ok = a.ndim() == 2 && (rows < 0 || a.shape(0) == rows);
    bool column_ok = false;
    for (py::ssize_t c : columns) column_ok = column_ok || (a.ndim() == 2 && a.shape(1) == c);
    if (!ok || !column_ok) value_error(std::string(name) + " must have shape " + shape_doc + ", got " + shape_text(a));
    return a;
}

// The array as C-contiguous `T`: itself when it is one already (no copy), else a converted copy.
template <class T>
py::array_t<T> contiguous(const py::array& a) {
    constexpr int k_aligned = py::detail::npy_api::NPY_ARRAY_ALIGNED_;
    if (a.dtype().is(py::dtype::of<T>()) && (a.flags() & py::array::c_style) && (a.flags() & k_aligned))
        return py::reinterpret_borrow<py::array_t<T>>(a);
    return py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(a);
}

bool all_finite(const py::array_t<float>& a) {
    const float* p = a.data();
    for (py::ssize_t i = 0; i < a.size(); ++i)
        if (!std::isfinite(p[i])) return false;
    return true;
}

Mat4 checked_transform(py::handle obj) {
    const py::array t = checked_array(obj, "transform", 4, {4}, "(4, 4)");
    const py::array_t<double> d = contiguous<double>(t);
    Mat4 m;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            const double v = d.at(r, c);
            if (!std::isfinite(v)) value_error("transform must be finite");
            m(r, c) = static_cast<float>(v);
        }
    if (!(m(3, 0) == 0 && m(3, 1) == 0 && m(3, 2) == 0 && m(3, 3) == 1))
        value_error("transform must be affine: its last row (0, 0, 0, 1)");
    return m;
}

}  // namespace

std::vector<double> checked_numbers(py::handle obj, const std::string& name, std::size_t min, std::size_t max,
                                    const std::string& what) {
    std::vector<double> v;
    try {
        v = obj.cast<std::vector<double>>();
    } catch (const py::cast_error&) {
        value_error(name + " must be " + what);
    }
    if (v.size() < min || v.size() > max) value_error(name + " must be " + what);
    return v;
}

Vec4 checked_colour(py::handle obj, const char* name) {
    const std::vector<double> v = checked_numbers(obj, name, 3, 4, "3 or 4 numbers (R, G, B[, A]) in 0..1");
    for (double x : v)
        if (!(x >= 0 && x <= 1)) value_error(std::string(name) + " values must lie in 0..1");
    return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]),
            v.size() == 4 ? static_cast<float>(v[3]) : 1.0f};
}

namespace {

std::shared_ptr<const Texture> checked_texture(py::handle obj) {
    py::array a;
    try {
        a = py::array::ensure(obj);
    } catch (const py::error_already_set&) {
    }
    if (!a) value_error("texture must be an array");
    if (!a.dtype().is(py::dtype::of<std::uint8_t>()))
        value_error("texture must be uint8 (0..255), got dtype " + std::string(py::str(a.dtype())));
    if (a.ndim() != 3 || (a.shape(2) != 3 && a.shape(2) != 4) || a.shape(0) < 1 || a.shape(1) < 1)
        value_error("texture must have shape (H, W, 3) or (H, W, 4), got " + shape_text(a));
    const TextureLimits limits;
    if (a.shape(0) > limits.max_size || a.shape(1) > limits.max_size ||
        static_cast<std::size_t>(a.shape(0) * a.shape(1)) > limits.max_pixels)
        value_error("texture " + shape_text(a) + " is larger than " + std::to_string(limits.max_size) + " per side or " +
                    std::to_string(limits.max_pixels) + " pixels");
    const auto px = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(a);
    Image image;
    image.width = static_cast<int>(a.shape(1));
    image.height = static_cast<int>(a.shape(0));
    image.pixels.resize(static_cast<std::size_t>(image.width) * image.height);
    const int channels = static_cast<int>(a.shape(2));
    const std::uint8_t* p = px.data();
    for (std::size_t i = 0; i < image.pixels.size(); ++i, p += channels)
        image.pixels[i] = {p[0], p[1], p[2], channels == 4 ? p[3] : std::uint8_t{255}};
    return std::make_shared<const Texture>(std::move(image));
}

// The arguments of from_arrays and add_mesh, checked and converted.
struct MeshArgs {
    py::array_t<float> vertices;
    std::optional<py::array_t<float>> normals, colours, uvs;  // (a default array_t is not "none" but empty)
    py::array_t<std::uint32_t> faces, points, lines;  // points and lines: empty when not given
    std::uint32_t vertex_count = 0;
    Material material;
    Mat4 model = Mat4::identity();
};

// Vertex indices of shape (rows, one of `columns`), integers each in 0..n-1, as uint32; `name` for errors.
py::array_t<std::uint32_t> checked_indices(py::handle obj, const char* name, std::initializer_list<py::ssize_t> columns,
                                           const char* shape_doc, py::ssize_t n) {
    const py::array f = checked_array(obj, name, -1, columns, shape_doc);
    if (f.dtype().kind() == 'f') value_error(std::string(name) + " must hold integers, got dtype " + std::string(py::str(f.dtype())));
    if (f.shape(0) > 0) {
        // The range in the array's own dtype, before any conversion could wrap a negative index.
        const py::module_ np = py::module_::import("numpy");
        const long long lo = np.attr("min")(f).cast<long long>();
        if (lo < 0) value_error(std::string(name) + ": negative index " + std::to_string(lo));
        const auto hi = np.attr("max")(f).cast<unsigned long long>();
        if (hi >= static_cast<unsigned long long>(n))
            value_error(std::string(name) + ": index " + std::to_string(hi) + " is out of range for " + std::to_string(n) +
                        " vertices");
    }
    return contiguous<std::uint32_t>(f);
}

MeshArgs checked_mesh(py::object vertices, py::object faces, py::object normals, py::object colors, py::object uvs,
                      py::object texture, py::object transform, py::object color, py::object points, py::object lines) {
    // Duck typing: a mesh object (trimesh's, say) in place of the vertices.
    if (faces.is_none() && py::hasattr(vertices, "vertices") && py::hasattr(vertices, "faces")) {
        faces = vertices.attr("faces");
        vertices = vertices.attr("vertices");
    }
    const bool primitives = !points.is_none() || !lines.is_none();
    if (faces.is_none() && !primitives)
        value_error("faces are missing: pass vertices and faces (or points or lines), or an object with .vertices and .faces");
    MeshArgs out;
    const py::array v = checked_array(vertices, "vertices", -1, {3}, "(N, 3)");
    if (v.shape(0) > static_cast<py::ssize_t>(std::numeric_limits<std::uint32_t>::max()))
        value_error("vertices: at most 2^32 - 1 of them, got " + std::to_string(v.shape(0)));
    out.vertices = contiguous<float>(v);
    out.vertex_count = static_cast<std::uint32_t>(v.shape(0));
    const py::ssize_t n = v.shape(0);

    out.faces = faces.is_none() ? py::array_t<std::uint32_t>(0) : checked_indices(faces, "faces", {3}, "(M, 3)", n);
    if (!points.is_none()) {
        // A flat list of point indices is the common form: taken as one column.
        py::array a;
        try {
            a = py::array::ensure(points);
        } catch (const py::error_already_set&) {
        }
        if (a && a.ndim() == 1) points = a.attr("reshape")(-1, 1);
        out.points = checked_indices(points, "points", {1}, "(P,)", n);
    }
    if (!lines.is_none()) out.lines = checked_indices(lines, "lines", {2}, "(L, 2)", n);

    const std::string rows = "(" + std::to_string(n) + ", ";  // like the vertices
    if (!normals.is_none()) {
        out.normals = contiguous<float>(checked_array(normals, "normals", n, {3}, (rows + "3) like vertices").c_str()));
        if (!all_finite(*out.normals)) value_error("normals must be finite");
    }
    if (!colors.is_none()) {
        const py::array c = checked_array(colors, "colors", n, {3, 4}, (rows + "3) or " + rows + "4) like vertices").c_str());
        if (c.dtype().is(py::dtype::of<std::uint8_t>())) {
            out.colours = py::array_t<float>({n, py::ssize_t{4}});
            const auto bytes = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(c);
            const py::ssize_t k = c.shape(1);
            float* o = out.colours->mutable_data();
            for (py::ssize_t i = 0; i < n; ++i)
                for (py::ssize_t j = 0; j < 4; ++j) o[i * 4 + j] = j < k ? bytes.data()[i * k + j] / 255.0f : 1.0f;
        } else if (c.shape(1) == 3) {
            const py::array_t<float> rgb = contiguous<float>(c);
            out.colours = py::array_t<float>({n, py::ssize_t{4}});
            float* o = out.colours->mutable_data();
            for (py::ssize_t i = 0; i < n; ++i)
                for (py::ssize_t j = 0; j < 4; ++j) o[i * 4 + j] = j < 3 ? rgb.data()[i * 3 + j] : 1.0f;
        } else {
            out.colours = contiguous<float>(c);
        }
        if (!all_finite(*out.colours)) value_error("colors must be finite");
    }
    if (!uvs.is_none()) {
        out.uvs = contiguous<float>(checked_array(uvs, "uvs", n, {2}, (rows + "2) like vertices").c_str()));
        if (!all_finite(*out.uvs)) value_error("uvs must be finite");
    }
    if (!texture.is_none()) {
        if (uvs.is_none()) value_error("texture needs uvs: one (u, v) per vertex, v = 0 at the texture's first row");
        out.material.base_colour_texture = checked_texture(texture);
    }
    if (!transform.is_none()) out.model = checked_transform(transform);
    if (!color.is_none()) out.material.base_colour = checked_colour(color, "color");
    return out;
}

template <class T>
const T* data_of(const py::array_t<float>& a) {
    return reinterpret_cast<const T*>(a.data());
}
template <class T>
const T* data_or_null(const std::optional<py::array_t<float>>& a) {
    return a ? data_of<T>(*a) : nullptr;
}

// Adds the mesh: over the caller's arrays, or, when normals are to be computed (which may split
// vertices), as a copy with them. Returns the object's index.
std::size_t add_mesh(PyScene& scene, MeshArgs&& a, std::optional<float> crease_angle) {
    if (!a.normals && crease_angle && a.faces.size() > 0) {
        if (!(*crease_angle >= 0 && *crease_angle <= 180)) value_error("crease_angle must be 0..180 degrees, or None");
        SceneObject o;
        const std::size_t n = a.vertex_count;
        o.mesh.positions.assign(data_of<Vec3>(a.vertices), data_of<Vec3>(a.vertices) + n);
        o.mesh.indices.assign(a.faces.data(), a.faces.data() + a.faces.size());
        o.mesh.points.assign(a.points.data(), a.points.data() + a.points.size());
        o.mesh.lines.assign(a.lines.data(), a.lines.data() + a.lines.size());
        if (a.colours) o.mesh.colours.assign(data_or_null<Vec4>(a.colours), data_or_null<Vec4>(a.colours) + n);
        if (a.uvs) o.mesh.uvs.assign(data_or_null<Vec2>(a.uvs), data_or_null<Vec2>(a.uvs) + n);
        o.model = a.model;
        o.material = std::move(a.material);
        {
            py::gil_scoped_release release;
            if (!o.mesh.indices.empty()) compute_creased_normals(o.mesh, radians(*crease_angle), 1);
        }
        return scene.add_owned(std::move(o));
    }
    auto b = std::make_unique<PyScene::Borrowed>();
    b->view.positions = data_of<Vec3>(a.vertices);
    b->view.normals = data_or_null<Vec3>(a.normals);
    b->view.colours = data_or_null<Vec4>(a.colours);
    b->view.uvs = data_or_null<Vec2>(a.uvs);
    b->view.vertex_count = a.vertex_count;
    b->view.indices = {a.faces.data(), static_cast<std::size_t>(a.faces.size())};
    b->view.points = {a.points.data(), static_cast<std::size_t>(a.points.size())};
    b->view.lines = {a.lines.data(), static_cast<std::size_t>(a.lines.size())};
    b->view.model = a.model;
    b->material = std::move(a.material);
    b->keep_alive = {a.vertices, a.faces, a.points, a.lines};
    for (const auto* o : {&a.normals, &a.colours, &a.uvs})
        if (*o) b->keep_alive.push_back(**o);
    return scene.add_borrowed(std::move(b));
}

const char* k_mesh_doc = R"doc(

Parameters
----------
vertices : array_like, shape (N, 3), or a mesh object
    Positions, float32 or float64 (any real dtype is converted to float32). Any object with
    `.vertices` and `.faces` (a trimesh.Trimesh, say) may be passed instead, without `faces`.
    Triangles with a NaN or infinite vertex are dropped when drawn (Renderer.stats counts them).
faces : array_like, shape (M, 3), integers, optional with points or lines
    Three vertex indices per triangle, counter-clockwise seen from the front; each in 0..N-1.
normals : array_like, shape (N, 3), optional
    Per-vertex normals (need not be unit length). Without them, facet computes them as
    `facet render` does for files without normals (see crease_angle).
colors : array_like, shape (N, 3) or (N, 4), optional
    Per-vertex colours, floats in 0..1 or uint8 in 0..255; they multiply `color`.
uvs : array_like, shape (N, 2), optional
    Texture coordinates, v = 0 at the texture's first (top) row, as glTF; repeat outside 0..1.
texture : array_like, shape (H, W, 3) or (H, W, 4), uint8, optional
    Base-colour texture (needs uvs); sampled trilinearly with mipmaps.
transform : array_like, shape (4, 4), optional
    Object-to-world matrix for column vectors (world = transform @ [x, y, z, 1]), affine.
color : sequence of 3 or 4 floats in 0..1, optional
    The material's base colour (default white).
points : array_like, shape (P,), integers, optional
    Vertices drawn as points (e.g. numpy.arange(N) for a point cloud): round or square splats
    of render()'s point_size, lit by their normal when there are normals, else coloured by
    colors and color; see README.md "Points and lines" for the exact pixels.
lines : array_like, shape (L, 2), integers, optional
    Line segments, two vertex indices each, drawn line_width pixels wide; consecutive segments
    that share a vertex (a strip, a loop) are joined with mitres.
crease_angle : float or None
    Degrees, used when normals are not given: normals are split where faces meet at more than
    this (`facet render --crease-angle`), which copies the mesh; None: no normals (faceted
    shading) and no copy.

Notes
-----
Arrays that are already C-contiguous float32 (vertices, normals, RGBA colours, uvs) and
uint32 (faces) are used in place, not copied: do not change them while a render runs.
Others are converted once, here.

Raises
------
ValueError
    An array of the wrong dtype or shape, non-finite normals, colours or uvs, a face index
    out of range, a texture without uvs or over 16384 per side, a non-affine transform; the
    message names the argument.
)doc";

}  // namespace

std::shared_ptr<PyScene> PyScene::from_loaded(LoadedModel model) {
    auto s = std::make_shared<PyScene>();
    s->owned_ = std::move(model.scene);
    s->warnings_ = std::move(model.warnings);
    for (std::size_t i = 0; i < s->owned_.objects.size(); ++i) s->order_.push_back({true, i});
    s->rebuild_views();
    return s;
}

// The exclusive lock is taken with the GIL held, and renders never wait for the GIL while they
// hold the shared one: so a render in progress ends first, and readers holding the GIL (len,
// bounds) never see views being rebuilt.
std::size_t PyScene::add_owned(SceneObject owned) {
    std::unique_lock lock(mutex_);
    owned_.objects.push_back(std::move(owned));
    order_.push_back({true, owned_.objects.size() - 1});
    rebuild_views();
    return order_.size() - 1;
}

std::size_t PyScene::add_borrowed(std::unique_ptr<Borrowed> borrowed) {
    borrowed->view.material = &borrowed->material;
    std::unique_lock lock(mutex_);
    borrowed_.push_back(std::move(borrowed));
    order_.push_back({false, borrowed_.size() - 1});
    rebuild_views();
    return order_.size() - 1;
}

void PyScene::rebuild_views() {
    views_.clear();
    for (const Slot& s : order_) views_.push_back(s.owned ? view_of(owned_.objects[s.index]) : borrowed_[s.index]->view);
}

std::size_t PyScene::triangle_count() const {
    std::size_t n = 0;
    for (const ObjectView& v : views_) n += v.indices.size() / 3;
    return n;
}

void bind_scene(py::module_& m) {
    py::class_<PyScene, std::shared_ptr<PyScene>> scene(m, "Scene", R"doc(Meshes to render: loaded with facet.load, or given as arrays.

Scene() is empty; Scene.from_arrays(...) makes one of a mesh; add_mesh adds more. Each mesh
keeps its own transform, material colour and texture. len(scene) is its number of meshes.
)doc");
    const float default_crease = defaults::k_crease_angle_degrees;
    // from_arrays and add_mesh take the same arguments: declared once.
    auto with_mesh_args = [&](auto&& define) {
        define(py::arg("vertices"), py::arg("faces") = py::none(), py::arg("normals") = py::none(),
               py::arg("colors") = py::none(), py::arg("uvs") = py::none(), py::arg("texture") = py::none(),
               py::arg("transform") = py::none(), py::kw_only(), py::arg("color") = py::none(),
               py::arg("crease_angle") = default_crease, py::arg("points") = py::none(), py::arg("lines") = py::none());
    };
    using Add = std::size_t (*)(PyScene&, py::object, py::object, py::object, py::object, py::object, py::object,
                                py::object, py::object, std::optional<float>, py::object, py::object);
    static constexpr Add add = [](PyScene& s, py::object vertices, py::object faces, py::object normals, py::object colors,
                                  py::object uvs, py::object texture, py::object transform, py::object color,
                                  std::optional<float> crease_angle, py::object points, py::object lines) {
        return add_mesh(s, checked_mesh(vertices, faces, normals, colors, uvs, texture, transform, color, points, lines),
                        crease_angle);
    };
    static const std::string from_arrays_doc = std::string("A scene of one mesh given as arrays.") + k_mesh_doc;
    static const std::string add_mesh_doc = std::string("Add a mesh; returns its index in the scene (0 for the first).") + k_mesh_doc;
    with_mesh_args([&](auto... args) {
        scene.def_static(
            "from_arrays",
            [](py::object vertices, py::object faces, py::object normals, py::object colors, py::object uvs,
               py::object texture, py::object transform, py::object color, std::optional<float> crease_angle,
               py::object points, py::object lines) {
                auto s = std::make_shared<PyScene>();
                add(*s, vertices, faces, normals, colors, uvs, texture, transform, color, crease_angle, points, lines);
                return s;
            },
            args..., from_arrays_doc.c_str());
    });
    with_mesh_args([&](auto... args) { scene.def("add_mesh", add, args..., add_mesh_doc.c_str()); });
    scene.def(py::init([] { return std::make_shared<PyScene>(); }))
        .def_static(
            "default", [] { return PyScene::from_loaded(LoadedModel{default_scene(), {}}); },
            "The built-in scene `facet render` draws without a model: a floor, a cube, spheres and a torus.")
        .def("__len__", [](const PyScene& s) { return s.views().size(); })
        .def_property_readonly("triangle_count", &PyScene::triangle_count, "Triangles of all meshes.")
        .def_property_readonly(
            "warnings", [](const PyScene& s) { return s.warnings(); },
            "The loader's warnings (also issued as facet.LoadWarning), each naming the file.")
        .def_property_readonly(
            "bounds",
            [](const PyScene& s) -> py::object {
                const Aabb box = bounds(s.views());
                if (box.empty()) return py::none();
                py::array_t<float> out({2, 3});
                for (int k = 0; k < 3; ++k) out.mutable_at(0, k) = box.min[static_cast<std::size_t>(k)];
                for (int k = 0; k < 3; ++k) out.mutable_at(1, k) = box.max[static_cast<std::size_t>(k)];
                return out;
            },
            "World-space bounds of the finite vertices, [[min x, y, z], [max x, y, z]], or None when empty.")
        .def("__repr__", [](const PyScene& s) {
            return "<facet.Scene: " + std::to_string(s.views().size()) + " meshes, " + std::to_string(s.triangle_count()) +
                   " triangles>";
        });
}

}  // namespace facet::python
