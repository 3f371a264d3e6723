"""Every bad input raises the documented exception with a message naming what is wrong, and
never crashes the interpreter: files (FileNotFoundError, facet.Error), arrays (ValueError naming
the argument), options, cameras, outputs. Bad geometry is dropped and counted instead."""
import os
from pathlib import Path

import numpy as np
import pytest

import facet

REGRESSION = Path(__file__).resolve().parents[1] / "regression" / "assimp_crashes"

V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
F = np.array([[0, 1, 2]], np.uint32)


# ---- files ----------------------------------------------------------------------------------

def test_a_missing_file_is_a_file_not_found_error(tmp_path):
    path = tmp_path / "nothing.obj"
    with pytest.raises(FileNotFoundError) as e:
        facet.load(path)
    assert e.value.filename == str(path) and e.value.errno == 2
    # As open() words it, naming the file and the reason (not "[Errno 2] None: ...").
    assert e.value.strerror == os.strerror(2)
    assert str(e.value) == f"[Errno 2] {os.strerror(2)}: {str(path)!r}"
    with pytest.raises(FileNotFoundError):
        facet.load_isolated(str(path))


def test_malformed_and_unsupported_files_are_facet_errors(tmp_path):
    bad = tmp_path / "bad.off"
    bad.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n")  # fewer vertices than declared
    with pytest.raises(facet.Error) as e:
        facet.load(bad)
    assert str(bad) in str(e.value) and e.value.code in ("bad_format", "io", "unsupported")
    assert isinstance(e.value, RuntimeError)
    unknown = tmp_path / "model.xyz123"
    unknown.write_text("hello")
    with pytest.raises(facet.Error) as e:
        facet.load(unknown)
    assert str(unknown) in str(e.value)
    with pytest.raises(facet.Error) as e:
        facet.load(tmp_path)  # a directory
    assert str(tmp_path) in str(e.value)


def test_limits_are_facet_errors(bunny):
    with pytest.raises(facet.Error) as e:
        facet.load(bunny, max_triangles=100)
    assert e.value.code == "limit_exceeded" and str(bunny) in str(e.value)


def test_a_file_that_crashes_the_reader_is_an_error_in_isolation(capfd):
    crasher = REGRESSION / "mdl_segv_24b0a191.mdl"
    if not crasher.exists():
        pytest.skip(f"{crasher} is missing")
    with pytest.raises(facet.Error) as e:
        facet.load_isolated(crasher, timeout=60)
    assert str(crasher) in str(e.value)
    assert "the importer crashed (SIG" in str(e.value)
    # The loading process dies of the signal; pytest's faulthandler, inherited, says nothing.
    assert "Fatal Python error" not in capfd.readouterr().err


def test_load_warnings_are_warnings_and_kept(assimp_models, tmp_path):
    # An OBJ whose material names a texture that is not there.
    obj = tmp_path / "m.obj"
    (tmp_path / "m.mtl").write_text("newmtl a\nmap_Kd missing.png\n")
    obj.write_text("mtllib m.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n")
    with pytest.warns(facet.LoadWarning, match="missing.png"):
        scene = facet.load(obj)
    assert any("missing.png" in w for w in scene.warnings)


@pytest.mark.parametrize("kwargs, message", [
    ({"crease_angle": 200}, "crease_angle"),
    ({"up_axis": "x"}, "up_axis"),
    ({"max_triangles": 0}, "max_triangles"),
    ({"max_texture_size": 0}, "max_texture_size must be 1..2147483647, got 0"),
    ({"max_texture_size": 2 ** 40}, "max_texture_size must be 1..2147483647, got 1099511627776"),
    ({"threads": -1}, "threads"),
])
def test_bad_load_options_are_value_errors(bunny, kwargs, message):
    with pytest.raises(ValueError, match=message):
        facet.load(bunny, **kwargs)


def test_bad_isolation_options_are_value_errors(bunny):
    with pytest.raises(ValueError, match="timeout"):
        facet.load_isolated(bunny, timeout=-1)


# ---- arrays ---------------------------------------------------------------------------------

BAD_ARRAYS = [
    (dict(vertices=np.zeros((3, 2), np.float32)), r"vertices must have shape \(N, 3\), got \(3, 2\)"),
    (dict(vertices=np.zeros(9, np.float32)), r"vertices must have shape \(N, 3\), got \(9,\)"),
    (dict(vertices=np.zeros((3, 3), np.complex64)), "vertices must hold numbers, got dtype complex64"),
    (dict(vertices=np.array([["a", "b", "c"]] * 3)), "vertices must hold numbers"),
    (dict(vertices=np.zeros((3, 3), bool)), "vertices must hold numbers, got dtype bool"),
    (dict(vertices=None), "vertices must hold numbers"),
    (dict(faces=np.array([[0, 1, 2]], np.float32)), "faces must hold integers"),
    (dict(faces=np.array([[0, 1]], np.uint32)), r"faces must have shape \(M, 3\)"),
    (dict(faces=np.array([[0, 1, 3]], np.int64)), "faces: index 3 is out of range for 3 vertices"),
    (dict(faces=np.array([[0, 1, 2 ** 40]], np.int64)), "out of range for 3 vertices"),
    (dict(faces=np.array([[0, -1, 2]], np.int64)), "faces: negative index -1"),
    (dict(faces=None), "faces are missing"),
    (dict(normals=np.zeros((2, 3), np.float32)), r"normals must have shape \(3, 3\) like vertices, got \(2, 3\)"),
    (dict(normals=np.full((3, 3), np.nan, np.float32)), "normals must be finite"),
    (dict(colors=np.zeros((3, 5), np.float32)), r"colors must have shape \(3, 3\) or \(3, 4\)"),
    (dict(colors=np.full((3, 4), np.inf, np.float32)), "colors must be finite"),
    (dict(uvs=np.zeros((3, 3), np.float32)), r"uvs must have shape \(3, 2\)"),
    (dict(uvs=np.full((3, 2), np.nan), texture=np.zeros((2, 2, 3), np.uint8)), "uvs must be finite"),
    (dict(texture=np.zeros((2, 2, 3), np.uint8)), "texture needs uvs"),
    (dict(uvs=np.zeros((3, 2)), texture=np.zeros((2, 2, 3), np.float32)), "texture must be uint8"),
    (dict(uvs=np.zeros((3, 2)), texture=np.zeros((2, 2), np.uint8)), r"texture must have shape \(H, W, 3\)"),
    (dict(uvs=np.zeros((3, 2)), texture=np.zeros((0, 2, 3), np.uint8)), r"texture must have shape"),
    (dict(uvs=np.zeros((3, 2)), texture=np.broadcast_to(np.uint8(0), (20000, 1, 3))), "texture .* is larger than"),
    (dict(transform=np.eye(3)), r"transform must have shape \(4, 4\)"),
    (dict(transform=np.full((4, 4), np.nan)), "transform must be finite"),
    (dict(transform=np.ones((4, 4))), "transform must be affine"),
    (dict(color=(2, 0, 0)), "color values must lie in 0..1"),
    (dict(color=(1, 0)), "color must be 3 or 4 numbers"),
    (dict(color="red"), "color must be 3 or 4 numbers"),
    (dict(crease_angle=-1), "crease_angle"),
    (dict(points=np.array([0, 3])), "points: index 3 is out of range for 3 vertices"),
    (dict(points=np.array([-1])), "points: negative index -1"),
    (dict(points=np.array([0.0, 1.0])), "points must hold integers"),
    (dict(points=np.zeros((2, 2), np.uint32)), r"points must have shape \(P,\)"),
    (dict(lines=np.array([[0, 1, 2]])), r"lines must have shape \(L, 2\), got \(1, 3\)"),
    (dict(lines=np.array([[0, 7]])), "lines: index 7 is out of range for 3 vertices"),
]


@pytest.mark.parametrize("change, message", BAD_ARRAYS, ids=[m for _, m in BAD_ARRAYS])
def test_bad_arrays_are_value_errors_naming_the_argument(change, message):
    args = dict(vertices=V, faces=F)
    args.update(change)
    with pytest.raises(ValueError, match=message):
        facet.Scene.from_arrays(**args)
    scene = facet.Scene()
    with pytest.raises(ValueError, match=message):
        scene.add_mesh(**args)
    assert len(scene) == 0  # nothing half-added


def test_non_finite_vertices_are_dropped_and_counted():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [np.nan, 0, 0], [1, 1, 0]], np.float32)
    f = np.array([[0, 1, 2], [1, 3, 2], [1, 4, 2], [3, 3, 4]], np.uint32)
    renderer = facet.Renderer(threads=1)
    for crease_angle in (None, 40):
        scene = facet.Scene.from_arrays(v, f, crease_angle=crease_angle)
        out = renderer.render(scene, facet.Camera.look_at((0.5, 0.5, 2), (0.5, 0.5, 0), near=0.5, far=5), 32, 32)
        assert out["color"].shape == (32, 32, 4)
        assert renderer.stats["triangles_in"] == 4
        assert renderer.stats["triangles_invalid"] == 2


def test_non_finite_points_and_segments_are_dropped_and_counted():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [np.nan, 0, 0]], np.float32)
    scene = facet.Scene.from_arrays(v, points=[0, 1, 3, 2, 3], lines=[[0, 1], [1, 3], [3, 2]])
    renderer = facet.Renderer(threads=1)
    out = renderer.render(scene, facet.Camera.look_at((0.5, 0.5, 2), (0.5, 0.5, 0), near=0.5, far=5), 32, 32,
                          background="transparent")
    assert np.count_nonzero(out["color"][..., 3]) > 0
    s = renderer.stats
    assert (s["points_in"], s["points_invalid"], s["segments_in"], s["segments_invalid"]) == (5, 2, 3, 2)


# ---- render options -------------------------------------------------------------------------

@pytest.fixture(scope="module")
def scene():
    return facet.Scene.from_arrays(V, F)


BAD_RENDERS = [
    (dict(width=0), ValueError, r"width must be 1..8192, got 0"),
    (dict(height=9000), ValueError, "height must be 1..8192, got 9000"),
    (dict(width=10 ** 12), ValueError, "width must be 1..8192, got 1000000000000"),
    (dict(height=-10 ** 30), ValueError, "height must be 1..8192, got less"),
    (dict(width=2.5), TypeError, "incompatible function arguments"),
    (dict(ssaa=0), ValueError, "ssaa must be 1..8, got 0"),
    (dict(ssaa=np.int64(9)), ValueError, "ssaa must be 1..8, got 9"),
    (dict(ssaa=10 ** 20), ValueError, "ssaa must be 1..8, got more"),
    (dict(width=4000, ssaa=4), ValueError, "times ssaa must stay within 8192"),
    (dict(shading="phong"), ValueError, "unknown shading 'phong'"),
    (dict(passes=("depth", "color", "depth")), ValueError, "pass 'depth' is asked for twice"),
    (dict(passes=("normal", "normal_camera")), ValueError, "unknown pass 'normal_camera'"),
    (dict(normal_space="screen"), ValueError, "normal_space must be 'world' or 'camera'"),
    (dict(passes=("colour",)), ValueError, "unknown pass 'colour'"),
    (dict(passes=()), ValueError, "passes is empty"),
    (dict(passes=3), ValueError, "passes must be a sequence"),
    (dict(background=(2, 0, 0)), ValueError, "background values must lie in 0..1"),
    (dict(background="blue"), ValueError, "background must be"),
    (dict(background=(0, 0)), ValueError, "background must be 3 or 4 numbers"),
    (dict(camera=None), TypeError, "camera must be a facet.Camera"),
    (dict(camera="front"), TypeError, "camera must be a facet.Camera"),
    (dict(camera=[]), ValueError, "the list of cameras is empty"),
    (dict(camera=[facet.Camera(), 3]), TypeError, "camera must be a facet.Camera"),
    (dict(scene=V), TypeError, "scene must be a facet.Scene"),
    (dict(threads=0), ValueError, "threads must be 1..4096, got 0"),
    (dict(threads=10 ** 30), ValueError, "threads must be 1..4096, got more"),
    (dict(point_size=0), ValueError, "point_size must be more than 0 and at most 256 / ssaa pixels, got 0"),
    (dict(point_size=float("nan")), ValueError, "point_size must be more than 0"),
    (dict(point_size=200, ssaa=2), ValueError, "point_size must be more than 0 and at most 256 / ssaa"),
    (dict(line_width=-1), ValueError, "line_width must be more than 0"),
    (dict(line_width=1e9), ValueError, "line_width must be more than 0"),
    (dict(point_shape="hexagon"), ValueError, "point_shape must be 'round' or 'square'"),
    (dict(point_world_size=0), ValueError, "point_world_size must be more than 0 and less than 1e30 model units"),
    (dict(point_world_size=float("inf")), ValueError, "point_world_size must be more than 0"),
    (dict(point_world_size=1e30), ValueError, r"point_world_size must be more than 0 and less than 1e30 model units, or None, got 1e\+30"),
]


@pytest.mark.parametrize("change, error, message", BAD_RENDERS, ids=[m for _, _, m in BAD_RENDERS])
def test_bad_render_options_raise(scene, change, error, message):
    args = dict(scene=scene, camera=facet.Camera(), width=10, height=10)
    args.update(change)
    with pytest.raises(error, match=message):
        facet.render(**args)
    if "threads" not in change:
        with pytest.raises(error, match=message):
            facet.Renderer().render(**args)


@pytest.mark.parametrize("out, message", [
    ({"color": np.zeros((10, 10, 4), np.float32)}, r"out\['color'\] must be a C-contiguous, writeable uint8 array of shape \(10, 10, 4\)"),
    ({"color": np.zeros((10, 11, 4), np.uint8)}, r"out\['color'\] must be"),
    ({"color": np.zeros((10, 10, 8), np.uint8)[..., :4]}, r"out\['color'\] must be"),
    ({"color": np.broadcast_to(np.uint8(0), (10, 10, 4))}, r"out\['color'\] must be"),
    ({"color": [[0] * 4] * 10}, r"out\['color'\] must be"),
    ({"alpha": np.zeros((10, 10), np.float64)}, r"out\['alpha'\] is not among the passes"),
    ({"depth": np.zeros((10, 10), np.float32)}, r"out\['depth'\] is not among the passes"),
])
def test_bad_out_arrays_are_value_errors(scene, out, message):
    with pytest.raises(ValueError, match=message):
        facet.Renderer().render(scene, facet.Camera(), 10, 10, out=out)


def test_out_must_be_a_dict(scene):
    with pytest.raises(ValueError, match="out must be a dict"):
        facet.Renderer().render(scene, facet.Camera(), 10, 10, out=[np.zeros((10, 10, 4), np.uint8)])


def test_bad_renderer_threads():
    with pytest.raises(ValueError, match="threads must be 1..4096, got 0"):
        facet.Renderer(threads=0)
    with pytest.raises(ValueError, match="threads must be 1..4096, got more"):
        facet.Renderer(threads=2 ** 70)


# ---- cameras --------------------------------------------------------------------------------

K = np.array([[100, 0, 49.5], [0, 100, 39.5], [0, 0, 1]], float)
POSE = np.hstack([np.eye(3), [[0], [0], [5]]])

BAD_CAMERAS = [
    (lambda: facet.Camera.orbit(fov_y=0), "fov_y must be between 0 and 180"),
    (lambda: facet.Camera.orbit(fov_y=180), "fov_y must be between 0 and 180"),
    (lambda: facet.Camera.orbit(float("nan")), "azimuth and elevation must be finite"),
    (lambda: facet.Camera.orbit(distance=0), "distance must be positive"),
    (lambda: facet.Camera.orbit(near=-1), "near must be positive"),
    (lambda: facet.Camera.orbit(near=2, far=1), "far must be positive and beyond near"),
    (lambda: facet.Camera.look_at((0, 0, float("inf")), (0, 0, 0)), "eye must be finite"),
    (lambda: facet.Camera.look_at((0, 0), (0, 0, 0)), r"eye must be 3 numbers"),
    (lambda: facet.Camera.look_at((0, 0, 1), "origin"), r"target must be 3 numbers"),
    (lambda: facet.Camera.look_at((0, 0, 1), (0, 0, 0), up=(0, 0, 0)), "up must not be the zero vector"),
    (lambda: facet.Camera.from_intrinsics(np.eye(2), 100, 80, POSE), "K must be a 3x3 matrix"),
    (lambda: facet.Camera.from_intrinsics(K * 2, 100, 80, POSE), r"K must be \[\[fx, skew, cx\]"),
    (lambda: facet.Camera.from_intrinsics(K, 100, 80, np.eye(3)), r"world_to_camera must be a 3x4 \[R\|t\] or 4x4"),
    (lambda: facet.Camera.from_intrinsics(K, 100, 80, np.ones((4, 4))), "world_to_camera's last row"),
    (lambda: facet.Camera.from_intrinsics(K, 0, 80, POSE), "width must be 1..8192, got 0"),
    (lambda: facet.Camera.from_intrinsics(K, 100, 10 ** 40, POSE), "height must be 1..8192, got more"),
    (lambda: facet.Camera.from_intrinsics(np.diag([-100.0, 100, 1]), 100, 80, POSE), "focal lengths"),
    (lambda: facet.Camera.from_intrinsics(K, 100, 80, np.hstack([np.diag([1.0, 1, -1]), [[0], [0], [5]]])), "reflection"),
    (lambda: facet.Camera.from_intrinsics(K, 100, 80, np.hstack([np.eye(3) * 2, [[0], [0], [5]]])), "not a rotation"),
    (lambda: facet.Camera.from_intrinsics(K, 100, 80, np.hstack([np.eye(3), [[0], [np.nan], [5]]])), "translation"),
    (lambda: facet.Camera.orbit(orthographic=True).resolve(facet.Scene.from_arrays(V, F), 10, 10), "orthographic"),
    (lambda: facet.Camera.orbit().resolve(None, 10, 10), "depends on the scene"),
    (lambda: facet.Camera.orbit().resolve(facet.Scene(), 0, 10), "width must be 1..8192, got 0"),
    (lambda: facet.Camera.look_at((0, 0, 1)).world_to_camera, "resolve"),
]


@pytest.mark.parametrize("make, message", BAD_CAMERAS, ids=[m for _, m in BAD_CAMERAS])
def test_bad_cameras_are_value_errors(make, message):
    with pytest.raises(ValueError, match=message):
        make()


def test_the_process_is_alive_after_all_of_that():
    # Every case above ran in this process: it still renders.
    img = facet.render(facet.Scene.from_arrays(V, F), facet.Camera(), 16, 16)["color"]
    assert img.shape == (16, 16, 4)
    assert os.getpid() > 0
