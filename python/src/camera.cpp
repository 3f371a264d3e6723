// facet._facet.Camera: how to look at a scene, as `facet render`'s camera options say it (an
// orbit framed by the framing rule, an explicit eye and target) or as OpenCV's K and [R|t]. A
// Camera is a ViewSpec: what depends on the scene (the framing distance, the default target and
// clip planes) is settled when it renders, or by resolve(). The conversions are the library's
// (facet/camera.hpp), shared with the command line.
#include <cmath>

#include "binding.hpp"

namespace facet::python {
namespace {

Vec3 checked_vec3(py::handle obj, const char* name) {
    const std::vector<double> v = checked_numbers(obj, name, 3, 3, "3 numbers (x, y, z)");
    for (double x : v)
        if (!std::isfinite(x)) value_error(std::string(name) + " must be finite");
    return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

// The options every kind shares, checked as `facet render` checks --fov, --near and --far.
void set_common(ViewSpec& spec, std::optional<float> fov_y, std::optional<float> near, std::optional<float> far) {
    if (fov_y) {
        if (!(*fov_y > 0 && *fov_y < 180)) value_error("fov_y must be between 0 and 180 degrees");
        spec.fovy = radians(*fov_y);
    }
    if (near && !(*near > 0 && std::isfinite(*near))) value_error("near must be positive");
    if (far && !(*far > (near ? *near : 0) && std::isfinite(*far))) value_error("far must be positive and beyond near");
    spec.near = near;
    spec.far = far;
}

py::array_t<double> matrix(const double* values, int rows, int columns) {
    py::array_t<double> out({rows, columns});
    std::copy(values, values + rows * columns, out.mutable_data());
    return out;
}

py::array_t<double> k_matrix(const OpenCvCamera& c) {
    const double k[9] = {c.fx, c.skew, c.cx, 0, c.fy, c.cy, 0, 0, 1};
    return matrix(k, 3, 3);
}

py::array_t<double> world_to_camera(const OpenCvCamera& c) {
    double m[16] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) m[i * 4 + j] = c.rotation[static_cast<std::size_t>(i * 3 + j)];
        m[i * 4 + 3] = c.translation[static_cast<std::size_t>(i)];
    }
    return matrix(m, 4, 4);
}

const OpenCvCamera& resolved(const PyCamera& c, const char* what) {
    if (!c.spec.opencv)
        value_error(std::string(what) + " is known once the camera is placed in a scene: use camera.resolve(scene, width, height)");
    return *c.spec.opencv;
}

// A PyCamera of OpenCV's form.
PyCamera from_opencv(const OpenCvCamera& cv, std::optional<float> near, std::optional<float> far) {
    if (Status s = validate(cv); !s) value_error(s.error().message);
    PyCamera c;
    c.kind = "intrinsics";
    c.spec.opencv = cv;
    set_common(c.spec, std::nullopt, near, far);
    return c;
}

}  // namespace

PyCamera& camera_of(py::handle obj) {
    try {
        return obj.cast<PyCamera&>();
    } catch (const py::cast_error&) {
        throw py::type_error("camera must be a facet.Camera (or a list of them), got " +
                             std::string(py::str(py::type::handle_of(obj).attr("__name__"))));
    }
}

void bind_camera(py::module_& m) {
    py::class_<PyCamera> camera(m, "Camera", R"doc(How to look at a scene.

Made by Camera.orbit (the default: `facet render`'s automatic framing), Camera.look_at (an
explicit eye, `--eye --target --up`), or Camera.from_intrinsics (OpenCV's K and [R|t]). What
depends on the scene (the framing distance, the default target and clip planes) is settled
when the camera renders, the same way for any scene it is used with; resolve() settles it into
OpenCV's form, which then gives K, world_to_camera and camera_to_world.

Conventions: world +Y is up for orbits; OpenCV's camera space has +X right, +Y down the image,
and looks down +Z; pixel (i, j)'s centre is at (u, v) = (i, j) in K's coordinates (OpenCV's
convention; facet's screen puts it at (i + 0.5, j + 0.5)).
)doc");
    camera.def(py::init([] { return PyCamera{ViewSpec{}, "orbit"}; }),
               "The automatic framing of `facet render` without camera options: Camera.orbit().")
        .def_static(
            "orbit",
            [](float azimuth, float elevation, std::optional<float> distance, float fov_y, std::optional<float> near,
               std::optional<float> far, bool orthographic) {
                PyCamera c{ViewSpec{}, "orbit"};
                if (!std::isfinite(azimuth) || !std::isfinite(elevation)) value_error("azimuth and elevation must be finite");
                if (distance && !(*distance > 0 && std::isfinite(*distance))) value_error("distance must be positive");
                c.spec.azimuth = radians(azimuth);
                c.spec.elevation = radians(elevation);
                c.spec.distance = distance;
                c.spec.orthographic = orthographic;
                set_common(c.spec, fov_y, near, far);
                return c;
            },
            py::arg("azimuth") = defaults::k_azimuth_degrees, py::arg("elevation") = defaults::k_elevation_degrees, py::kw_only(), py::arg("distance") = py::none(),
            py::arg("fov_y") = defaults::k_fov_degrees, py::arg("near") = py::none(), py::arg("far") = py::none(),
            py::arg("orthographic") = false, R"doc(An eye on a sphere around the centre of the scene's bounds, looking at it.

`facet render --azimuth A --elevation E --fov F`: the framing rule puts the eye at
distance r / sin(min(fov_y, fov_x) / 2), r the largest distance of a vertex from the centre,
so the whole scene is in view; near = max(dist - 1.5 r, 0.01 r), far = dist + 1.5 r.

Parameters
----------
azimuth : float
    Degrees about +Y, from +Z toward +X.
elevation : float
    Degrees above the XZ plane.
distance : float, optional
    The eye's distance from the centre instead of the framing rule's.
fov_y : float
    Vertical field of view in degrees (0..180).
near, far : float, optional
    Clip planes instead of the bounding sphere's.
orthographic : bool
    An orthographic view fitted to the bounding sphere (`--ortho`).
)doc")
        .def_static(
            "look_at",
            [](py::object eye, py::object target, py::object up, float fov_y, std::optional<float> near,
               std::optional<float> far, bool orthographic) {
                PyCamera c{ViewSpec{}, "look_at"};
                c.spec.eye = checked_vec3(eye, "eye");
                if (!target.is_none()) c.spec.target = checked_vec3(target, "target");
                c.spec.up = checked_vec3(up, "up");
                if (!(length(c.spec.up) > 0)) value_error("up must not be the zero vector");
                c.spec.orthographic = orthographic;
                set_common(c.spec, fov_y, near, far);
                return c;
            },
            py::arg("eye"), py::arg("target") = py::none(), py::arg("up") = py::make_tuple(0, 1, 0),
            py::arg("fov_y") = defaults::k_fov_degrees, py::kw_only(), py::arg("near") = py::none(),
            py::arg("far") = py::none(), py::arg("orthographic") = false,
            R"doc(An eye at `eye` looking at `target`: `facet render --eye --target --up --fov`.

Parameters
----------
eye : sequence of 3 floats
target : sequence of 3 floats, optional
    Default: the centre of the scene's bounds.
up : sequence of 3 floats
    The direction that is up in the image (need not be perpendicular to the view).
fov_y : float
    Vertical field of view in degrees (0..180).
near, far : float, optional
    Clip planes; default from the scene's bounding sphere: near = max(d - 1.5 r, 0.01 r),
    far = d + 1.5 r, d the eye's distance from the centre.
orthographic : bool
    An orthographic view fitted to the bounding sphere.
)doc")
        .def_static(
            "from_intrinsics",
            [](py::object k, Integer width_arg, Integer height_arg, py::object pose, std::optional<float> near,
               std::optional<float> far) {
                const int width = in_range(width_arg, "width", 1, k_max_target_size);
                const int height = in_range(height_arg, "height", 1, k_max_target_size);
                py::array_t<double, py::array::c_style | py::array::forcecast> kk, rt;
                try {
                    kk = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(k);
                    rt = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(pose);
                } catch (const py::error_already_set&) {
                }
                if (!kk || kk.ndim() != 2 || kk.shape(0) != 3 || kk.shape(1) != 3) value_error("K must be a 3x3 matrix");
                if (!rt || rt.ndim() != 2 || rt.shape(1) != 4 || (rt.shape(0) != 3 && rt.shape(0) != 4))
                    value_error("world_to_camera must be a 3x4 [R|t] or 4x4 matrix");
                if (kk.at(1, 0) != 0 || kk.at(2, 0) != 0 || kk.at(2, 1) != 0 || kk.at(2, 2) != 1)
                    value_error("K must be [[fx, skew, cx], [0, fy, cy], [0, 0, 1]]");
                if (rt.shape(0) == 4 && (rt.at(3, 0) != 0 || rt.at(3, 1) != 0 || rt.at(3, 2) != 0 || rt.at(3, 3) != 1))
                    value_error("world_to_camera's last row must be (0, 0, 0, 1)");
                OpenCvCamera cv;
                cv.fx = kk.at(0, 0), cv.skew = kk.at(0, 1), cv.cx = kk.at(0, 2);
                cv.fy = kk.at(1, 1), cv.cy = kk.at(1, 2);
                cv.width = width, cv.height = height;
                for (int i = 0; i < 3; ++i) {
                    for (int j = 0; j < 3; ++j) cv.rotation[static_cast<std::size_t>(i * 3 + j)] = rt.at(i, j);
                    cv.translation[static_cast<std::size_t>(i)] = rt.at(i, 3);
                }
                return from_opencv(cv, near, far);
            },
            py::arg("K"), py::arg("width"), py::arg("height"), py::arg("world_to_camera"), py::kw_only(),
            py::arg("near") = py::none(), py::arg("far") = py::none(),
            R"doc(A camera in OpenCV's convention: intrinsics K and the world-to-camera pose [R|t].

A world point p is at x = R p + t in camera space (+X right, +Y down the image, looking down
+Z), and at pixel u = fx x/z + skew y/z + cx, v = fy y/z + cy, where pixel (i, j)'s centre is
(u, v) = (i, j). Rendered at another size, K scales with the image.

Parameters
----------
K : array_like, shape (3, 3)
    [[fx, skew, cx], [0, fy, cy], [0, 0, 1]], in pixels of a width x height image.
width, height : int
    The image K is for.
world_to_camera : array_like, shape (3, 4) or (4, 4)
    [R | t]; R must be a rotation (orthonormal within 1e-4, determinant +1).
near, far : float, optional
    Clip planes; default from the scene's bounding sphere, as for look_at.

Raises
------
ValueError
    A malformed K, a non-positive focal length, R not a rotation, a size outside 1..8192.
)doc")
        .def(
            "resolve",
            [](const PyCamera& c, py::object scene, Integer width_arg, Integer height_arg) {
                const int width = in_range(width_arg, "width", 1, k_max_target_size);
                const int height = in_range(height_arg, "height", 1, k_max_target_size);
                const bool needs_scene = !c.spec.near || !c.spec.far ||
                                         (!c.spec.opencv && (!c.spec.eye || !c.spec.target || c.spec.orthographic));
                if (scene.is_none() && needs_scene)
                    value_error("this camera depends on the scene (framing, default target or clip planes): pass scene");
                Camera placed;
                if (scene.is_none()) {
                    placed = make_camera(std::span<const ObjectView>{}, c.spec, static_cast<float>(width) / height);
                } else {
                    const PyScene& s = scene_of(scene);
                    std::shared_lock lock(s.mutex());
                    placed = make_camera(s.views(), c.spec, static_cast<float>(width) / height);
                }
                const std::optional<OpenCvCamera> cv = to_opencv(placed, width, height);
                if (!cv) value_error("an orthographic camera has no intrinsics K");
                return from_opencv(*cv, placed.near, placed.far);
            },
            py::arg("scene") = py::none(), py::arg("width") = Integer{defaults::k_image_width},
            py::arg("height") = Integer{defaults::k_image_height},
            R"doc(This camera, placed in `scene` for a width x height image, in OpenCV's form.

The result has K, world_to_camera, camera_to_world, near and far, and renders the same view
(the same view and projection matrices) for any scene. Without a scene, only cameras that do
not depend on one: from_intrinsics with near and far, look_at with target, near and far.
)doc")
        .def_property_readonly(
            "K", [](const PyCamera& c) { return k_matrix(resolved(c, "K")); },
            "Intrinsics [[fx, skew, cx], [0, fy, cy], [0, 0, 1]] (float64) for (width, height).")
        .def_property_readonly(
            "world_to_camera", [](const PyCamera& c) { return world_to_camera(resolved(c, "world_to_camera")); },
            "OpenCV's [R|t] as a 4x4 float64 matrix: camera = world_to_camera @ [x, y, z, 1].")
        .def_property_readonly(
            "camera_to_world",
            [](const PyCamera& c) {
                const Mat4 m = camera_to_world_gl(Camera::from_opencv(resolved(c, "camera_to_world"), 1, 2));
                double v[16];
                for (int i = 0; i < 16; ++i) v[i] = m(i / 4, i % 4);
                return matrix(v, 4, 4);
            },
            "Camera-to-world in the OpenGL convention NeRF tools read (transforms.json's transform_matrix): the "
            "camera looks down -Z with +Y up.")
        .def_property_readonly("width", [](const PyCamera& c) { return resolved(c, "width").width; })
        .def_property_readonly("height", [](const PyCamera& c) { return resolved(c, "height").height; })
        .def_property_readonly("near", [](const PyCamera& c) { return c.spec.near; },
                               "The near clip plane, or None: from the scene's bounding sphere.")
        .def_property_readonly("far", [](const PyCamera& c) { return c.spec.far; },
                               "The far clip plane, or None: from the scene's bounding sphere.")
        .def("__repr__", [](const PyCamera& c) {
            std::string s = "<facet.Camera " + c.kind;
            if (c.kind == "orbit")
                s += " azimuth=" + std::to_string(degrees(c.spec.azimuth)) + " elevation=" + std::to_string(degrees(c.spec.elevation));
            if (c.spec.opencv) s += " " + std::to_string(c.spec.opencv->width) + "x" + std::to_string(c.spec.opencv->height);
            return s + ">";
        });
}

}  // namespace facet::python
