"""The package's API as a user calls it: scenes from files and arrays, cameras, render and
Renderer, the outputs' shapes and memory, docstrings and stubs, `python3 -m facet`."""
import ast
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import facet
from facet import _facet
from pngfile import read_png


def off_triangle_count(path: Path) -> int:
    """The face count an OFF file's header declares."""
    words = []
    for line in path.read_text().splitlines():
        words += line.split("#")[0].split()
        if len(words) >= 4:
            break
    return int(words[2])


def quad(z=0.0, size=1.0):
    """Two triangles facing +Z, counter-clockwise, at depth z."""
    v = np.array([[-size, -size, z], [size, -size, z], [size, size, z], [-size, size, z]], np.float32)
    f = np.array([[0, 1, 2], [0, 2, 3]], np.uint32)
    return v, f


FRONT = facet.Camera.look_at((0, 0, 3), (0, 0, 0), fov_y=60, near=0.5, far=10)


def test_load_reads_the_model(bunny):
    scene = facet.load(bunny)
    assert isinstance(scene, facet.Scene)
    assert len(scene) == 1
    assert scene.triangle_count == off_triangle_count(bunny)
    lo, hi = scene.bounds
    assert (lo < hi).all()
    assert scene.warnings == []
    assert "1 meshes" in repr(scene)


def test_load_isolated_gives_the_same_scene(bunny):
    a = facet.render(facet.load(bunny), facet.Camera.orbit(20, 10), 96, 64)["color"]
    b = facet.render(facet.load_isolated(bunny, timeout=60), facet.Camera.orbit(20, 10), 96, 64)["color"]
    assert np.array_equal(a, b)


def test_render_returns_arrays_of_the_documented_shapes(bunny):
    scene = facet.load(bunny)
    out = facet.render(scene, facet.Camera.orbit(30, 20), 160, 120, passes=("color", "alpha"))
    assert set(out) == {"color", "alpha"}
    color, alpha = out["color"], out["alpha"]
    assert color.shape == (120, 160, 4) and color.dtype == np.uint8
    assert alpha.shape == (120, 160) and alpha.dtype == np.float32
    assert color.flags["C_CONTIGUOUS"] and color.flags["WRITEABLE"] and color.flags["OWNDATA"] is False
    assert color.ctypes.data % 64 == 0  # the renderer drew into it, whole aligned rows
    # Without supersampling a pixel is covered or not; covered pixels differ from the background.
    assert set(np.unique(alpha)) == {0.0, 1.0}
    background = color[alpha == 0]
    assert (background == background[0]).all()
    assert 0.05 < alpha.mean() < 0.9
    assert (color[..., 3] == 255).all()


def test_alpha_with_supersampling_is_the_fraction_of_samples(bunny):
    scene = facet.load(bunny)
    out = facet.render(scene, facet.Camera.orbit(30, 20), 80, 60, passes=["alpha", "color"], ssaa=2)
    values = set(np.unique(out["alpha"]).tolist())
    assert values <= {0.0, 0.25, 0.5, 0.75, 1.0}
    assert {0.25, 0.5, 0.75} & values  # edges are partly covered
    # Transparent background: the colour's alpha is the coverage too (rounded to 8 bits).
    t = facet.render(scene, facet.Camera.orbit(30, 20), 80, 60, passes=["alpha", "color"], ssaa=2, background="transparent")
    assert np.array_equal(t["color"][..., 3], np.round(t["alpha"] * 255).astype(np.uint8))


def test_a_list_of_cameras_gives_a_leading_axis(bunny):
    scene = facet.load(bunny)
    cameras = [facet.Camera.orbit(a, 15) for a in (0, 90, 180)]
    batch = facet.render(scene, cameras, 64, 48, passes=("color", "alpha"))
    assert batch["color"].shape == (3, 48, 64, 4)
    assert batch["alpha"].shape == (3, 48, 64)
    for i, c in enumerate(cameras):
        single = facet.render(scene, c, 64, 48, passes=("color", "alpha"))
        assert np.array_equal(batch["color"][i], single["color"])
        assert np.array_equal(batch["alpha"][i], single["alpha"])


def test_renderer_reuses_itself_and_renders_the_same(bunny):
    scene = facet.load(bunny)
    camera = facet.Camera.orbit(30, 20)
    expected = facet.render(scene, camera, 128, 96, passes=("color", "alpha"))
    renderer = facet.Renderer(threads=2)
    assert renderer.threads == 2
    for ssaa in (1, 2, 1):  # the target changes size and back
        got = renderer.render(scene, camera, 128, 96, passes=("color", "alpha"), ssaa=ssaa)
        if ssaa == 1:
            assert np.array_equal(got["color"], expected["color"])
            assert np.array_equal(got["alpha"], expected["alpha"])
    stats = renderer.stats
    assert stats["triangles_in"] == scene.triangle_count
    assert 0 < stats["triangles_rasterized"] <= stats["triangles_in"]
    assert stats["triangles_invalid"] == 0


def test_out_arrays_are_rendered_into(bunny):
    scene = facet.load(bunny)
    camera = facet.Camera.orbit(30, 20)
    renderer = facet.Renderer()
    color = np.zeros((60, 80, 4), np.uint8)
    alpha = np.full((60, 80), -1, np.float32)
    got = renderer.render(scene, camera, 80, 60, passes=("color", "alpha"), out={"color": color, "alpha": alpha})
    assert got["color"] is color and got["alpha"] is alpha
    expected = renderer.render(scene, camera, 80, 60, passes=("color", "alpha"))
    assert np.array_equal(color, expected["color"]) and np.array_equal(alpha, expected["alpha"])
    # Only some outputs given: the others are made.
    got = renderer.render(scene, camera, 80, 60, passes=("color", "alpha"), out={"alpha": alpha})
    assert got["alpha"] is alpha and np.array_equal(got["color"], expected["color"])


def test_from_arrays_uses_contiguous_float32_arrays_in_place():
    v, f = quad()
    scene = facet.Scene.from_arrays(v, f, crease_angle=None)
    before = facet.render(scene, FRONT, 32, 32, passes=("alpha",))["alpha"]
    assert before.mean() > 0.2
    v[:] *= 0.1  # the scene sees the change: the array was not copied
    after = facet.render(scene, FRONT, 32, 32, passes=("alpha",))["alpha"]
    assert 0 < after.mean() < before.mean() / 10
    # float64 input is converted once: later changes do not reach the scene.
    v64 = quad()[0].astype(np.float64)
    scene64 = facet.Scene.from_arrays(v64, f, crease_angle=None)
    v64[:] *= 0.1
    assert np.array_equal(facet.render(scene64, FRONT, 32, 32, passes=("alpha",))["alpha"], before)


def test_faces_of_any_integer_type_and_vertices_of_any_real_type():
    v, f = quad()
    expected = facet.render(facet.Scene.from_arrays(v, f), FRONT, 40, 30)["color"]
    for faces in (f.astype(np.int64), f.astype(np.int32), f.astype(np.uint16), f.tolist()):
        for vertices in (v, v.astype(np.float64), v.tolist(), np.asfortranarray(v), np.repeat(v, 2, axis=0)[::2]):
            got = facet.render(facet.Scene.from_arrays(vertices, faces), FRONT, 40, 30)["color"]
            assert np.array_equal(got, expected)


def test_any_object_with_vertices_and_faces_is_a_mesh():
    class Mesh:  # as trimesh.Trimesh looks to facet
        def __init__(self):
            self.vertices, self.faces = quad()

    a = facet.render(facet.Scene.from_arrays(Mesh()), FRONT, 40, 30)["color"]
    scene = facet.Scene()
    assert scene.add_mesh(Mesh()) == 0
    assert np.array_equal(facet.render(scene, FRONT, 40, 30)["color"], a)
    assert np.array_equal(facet.render(facet.Scene.from_arrays(*quad()), FRONT, 40, 30)["color"], a)


def test_add_mesh_adds_objects_in_order_with_their_transforms():
    v, f = quad(size=0.5)
    scene = facet.Scene()
    left = np.eye(4)
    left[0, 3] = -1
    right = np.eye(4)
    right[0, 3] = 1
    assert scene.add_mesh(v, f, transform=left, color=(1, 0, 0)) == 0
    assert scene.add_mesh(v, f, transform=right, color=(0, 0, 1)) == 1
    assert len(scene) == 2 and scene.triangle_count == 4
    img = facet.render(scene, FRONT, 64, 32, shading="texture")["color"]  # unlit: the material colour
    # The view is 2 * 3 tan(30 deg) = 3.46 units high at z = 0, twice that wide: x = -1 and
    # x = 1 are at columns 22.8 and 41.2.
    assert tuple(img[16, 23, :3]) == (255, 0, 0)
    assert tuple(img[16, 41, :3]) == (0, 0, 255)
    assert tuple(img[16, 32, :3]) == tuple(img[0, 0, :3])  # the background between them
    bounds = scene.bounds
    assert np.allclose(bounds, [[-1.5, -0.5, 0], [1.5, 0.5, 0]])


def test_vertex_colours_as_bytes_or_floats_give_the_same_image():
    v, f = quad()
    rgb = np.array([[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 0]], np.uint8)
    a = facet.render(facet.Scene.from_arrays(v, f, colors=rgb), FRONT, 40, 40, shading="vertex-color")["color"]
    floats = np.concatenate([rgb / np.float32(255), np.ones((4, 1), np.float32)], axis=1).astype(np.float32)
    b = facet.render(facet.Scene.from_arrays(v, f, colors=floats), FRONT, 40, 40, shading="vertex-color")["color"]
    assert np.array_equal(a, b)
    assert len({tuple(p) for p in a[5:35, 5:35, :3].reshape(-1, 3)}) > 50  # interpolated


def test_textures_are_sampled_with_v_zero_at_the_first_row():
    v, f = quad()
    uvs = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], np.float32)  # bottom-left vertex at v = 1
    texture = np.full((64, 64, 3), 255, np.uint8)
    texture[:32, :32] = (255, 0, 0)  # top left
    texture[:32, 32:] = (0, 255, 0)  # top right
    texture[32:, :32] = (0, 0, 255)  # bottom left
    scene = facet.Scene.from_arrays(v, f, uvs=uvs, texture=texture)
    img = facet.render(scene, facet.Camera.look_at((0, 0, 2), (0, 0, 0), fov_y=53.13, near=0.5, far=5),
                       64, 64, shading="texture")["color"]
    assert tuple(img[8, 8, :3]) == (255, 0, 0)
    assert tuple(img[8, 56, :3]) == (0, 255, 0)
    assert tuple(img[56, 8, :3]) == (0, 0, 255)


def test_normals_are_computed_unless_given_or_switched_off():
    # A bent strip: computed normals are smooth across the 20-degree fold; crease_angle=None
    # draws facets (no normals); given normals are used as they are.
    v = np.array([[-1, -1, 0], [0, -1, 0.18], [1, -1, 0], [-1, 1, 0], [0, 1, 0.18], [1, 1, 0]], np.float32)
    f = np.array([[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]], np.uint32)
    def colours(img):
        return len({tuple(p) for p in img[10:38, 10:38, :3].reshape(-1, 3)})

    smooth = facet.render(facet.Scene.from_arrays(v, f), FRONT, 48, 48, shading="normals")["color"]
    sharp = facet.render(facet.Scene.from_arrays(v, f, crease_angle=5), FRONT, 48, 48, shading="normals")["color"]
    up = np.tile(np.array([[0, 0, 1]], np.float32), (6, 1))
    given = facet.render(facet.Scene.from_arrays(v, f, normals=up), FRONT, 48, 48, shading="normals")["color"]
    assert colours(smooth) > 8  # normals interpolated across the fold
    assert colours(sharp) <= 4 and colours(sharp) < colours(smooth)  # two flat halves
    assert colours(given) == 1  # all +Z
    # No normals: lit falls back to faceted shading, as for the flat mode.
    none = facet.Scene.from_arrays(v, f, crease_angle=None)
    assert np.array_equal(facet.render(none, FRONT, 48, 48)["color"],
                          facet.render(none, FRONT, 48, 48, shading="flat")["color"])


def test_the_default_scene_and_default_camera():
    scene = facet.Scene.default()
    assert len(scene) >= 4
    img = facet.render(scene, facet.Camera(), 80, 60)["color"]
    assert len({tuple(p) for p in img.reshape(-1, 4)}) > 100


def test_cameras_resolve_to_opencv_form(bunny):
    scene = facet.load(bunny)
    eye = (0.5, 0.4, 2.0)
    c = facet.Camera.look_at(eye, (0, 0, 0), fov_y=50).resolve(scene, 320, 240)
    K = c.K
    fy = 240 / (2 * np.tan(np.radians(50) / 2))
    assert K.shape == (3, 3) and K.dtype == np.float64
    assert K[1, 1] == pytest.approx(fy, rel=1e-6) and K[0, 0] == pytest.approx(fy, rel=1e-6)
    assert (K[0, 2], K[1, 2]) == (159.5, 119.5)  # OpenCV's pixel centres: the image centre is (W - 1) / 2
    assert (c.width, c.height) == (320, 240)
    w2c, c2w = c.world_to_camera, c.camera_to_world
    assert np.allclose(w2c @ np.array([*eye, 1]), [0, 0, 0, 1], atol=1e-5)  # the eye is the origin
    assert np.allclose(w2c @ np.array([0, 0, 0, 1])[:, None], [[0], [0], [np.linalg.norm(eye)], [1]], atol=1e-5)
    assert np.allclose(c2w[:3, 3], eye, atol=1e-5)
    # OpenGL's camera axes are OpenCV's with Y and Z negated.
    assert np.allclose(c2w @ np.diag([1, -1, -1, 1]), np.linalg.inv(w2c), atol=1e-5)
    assert 0 < c.near < c.far
    # Only resolved cameras have K; the others say how to get it.
    with pytest.raises(ValueError, match="resolve"):
        facet.Camera.orbit(10, 10).K


def test_python_m_facet_runs_the_command_line(bunny, tmp_path):
    r = subprocess.run([sys.executable, "-m", "facet", "--help"], capture_output=True, text=True)
    assert r.returncode == 0 and "render" in r.stdout
    out = tmp_path / "bunny.png"
    r = subprocess.run([sys.executable, "-m", "facet", "render", str(bunny), "--size", "64x48", "-o", str(out)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert read_png(out).shape == (48, 64, 3)
    r = subprocess.run([sys.executable, "-m", "facet", "render", "--no-such-option"], capture_output=True, text=True)
    assert r.returncode == 2 and r.stderr


def test_help_and_stubs_document_every_public_name():
    for name in facet.__all__:
        if name.startswith("__"):
            continue
        obj = getattr(facet, name)
        assert obj.__doc__ and len(obj.__doc__) > 40, name
        assert obj.__module__ == "facet", name
    assert "Parameters" in facet.render.__doc__ and "passes" in facet.render.__doc__
    assert "Raises" in facet.load.__doc__ and "FileNotFoundError" in facet.load.__doc__
    for cls, method in ((facet.Scene, "from_arrays"), (facet.Scene, "add_mesh"), (facet.Camera, "orbit"),
                        (facet.Camera, "look_at"), (facet.Camera, "from_intrinsics"), (facet.Camera, "resolve"),
                        (facet.Renderer, "render")):
        assert "Parameters" in getattr(cls, method).__doc__ or "scene" in getattr(cls, method).__doc__, method
    # The stubs are installed, parse, and declare every public name with the same parameters.
    stub = Path(facet.__file__).with_name("__init__.pyi")
    assert stub.is_file() and Path(facet.__file__).with_name("py.typed").is_file()
    tree = ast.parse(stub.read_text())
    declared = {n.name: n for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    for name in facet.__all__:
        if not name.startswith("__"):
            assert name in declared, f"{name} is not in the stubs"
    for name, obj in (("render", facet.render), ("load", facet.load), ("load_isolated", facet.load_isolated)):
        stub_params = [a.arg for a in declared[name].args.args + declared[name].args.kwonlyargs]
        signature = obj.__doc__.split("\n", 1)[0]
        assert stub_params == re.findall(r"(\w+):", signature), name


def test_gil_is_released_while_loading_and_rendering(bunny):
    scene = facet.load(bunny)
    assert _facet._gil_held_at_last_call() is False
    facet.render(scene, facet.Camera(), 32, 32)
    assert _facet._gil_held_at_last_call() is False
    facet.load_isolated(bunny)
    assert _facet._gil_held_at_last_call() is False
