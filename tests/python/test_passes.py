"""Render passes from Python: render(passes=...) gives each pass as an array of the documented
shape and dtype, for one camera and for a list of them; depth back-projects onto an analytic
sphere through the camera's own K and pose, normals are that sphere's, instance ids name the
mesh nearest the eye, and the arrays are `facet render --passes`'s files to the byte."""
import json
import subprocess

import numpy as np
import pytest

import facet

ALL = ("color", "alpha", "depth", "range", "normal", "instance", "material", "primitive", "uv")
SHAPES = {"color": (4, np.uint8), "alpha": (None, np.float32), "depth": (None, np.float32), "range": (None, np.float32),
          "normal": (3, np.float32), "instance": (None, np.uint32), "material": (None, np.uint32),
          "primitive": (None, np.uint32), "uv": (2, np.float32)}


def uv_sphere(radius, centre, rings=96, segments=192):
    """A finely tessellated sphere with its analytic normals and uvs, built here."""
    theta = np.linspace(0, np.pi, rings + 1)
    phi = np.linspace(0, 2 * np.pi, segments + 1)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    n = np.stack([np.sin(t) * np.cos(p), np.cos(t), np.sin(t) * np.sin(p)], axis=-1).reshape(-1, 3)
    uv = np.stack([p / (2 * np.pi), 1 - t / np.pi], axis=-1).reshape(-1, 2)
    faces = []
    for i in range(rings):
        for j in range(segments):
            a, b = i * (segments + 1) + j, (i + 1) * (segments + 1) + j
            faces += [(a, b, a + 1), (a + 1, b, b + 1)]
    return (np.asarray(centre) + radius * n).astype(np.float32), np.array(faces, np.uint32), n.astype(np.float32), uv.astype(np.float32)


def sphere_scene(radius=1.0, centre=(0, 0, 0)):
    v, f, n, uv = uv_sphere(radius, centre)
    return facet.Scene.from_arrays(v, f, normals=n, uvs=uv, color=(0.7, 0.7, 0.7))


def test_every_pass_has_its_shape_and_dtype_and_a_list_of_cameras_stacks_them():
    scene = sphere_scene()
    cameras = [facet.Camera.orbit(a, 15) for a in (0, 90, 200)]
    one = facet.render(scene, cameras[0], 64, 48, passes=ALL)
    batch = facet.render(scene, cameras, 64, 48, passes=list(ALL), ssaa=2)
    assert set(one) == set(batch) == set(ALL)
    for name, (channels, dtype) in SHAPES.items():
        shape = (48, 64) + ((channels,) if channels else ())
        assert one[name].shape == shape and one[name].dtype == dtype, name
        assert batch[name].shape == (3,) + shape and batch[name].dtype == dtype, name
    # Each view of the batch is that camera's render alone; every pass but color and alpha is the
    # same whatever the supersampling.
    for i, camera in enumerate(cameras):
        single = facet.render(scene, camera, 64, 48, passes=ALL, ssaa=2)
        for name in ALL:
            assert np.array_equal(batch[name][i], single[name]), name
    plain = facet.render(scene, cameras, 64, 48, passes=ALL)
    for name in ("depth", "range", "normal", "instance", "material", "primitive", "uv"):
        assert np.array_equal(np.nan_to_num(plain[name], posinf=-1), np.nan_to_num(batch[name], posinf=-1)), name


def test_background_values_and_the_colour_is_the_colour_alone():
    scene = sphere_scene()
    camera = facet.Camera.look_at((0, 0, 6), (0, 0, 0), fov_y=40)
    p = facet.render(scene, camera, 80, 60, passes=ALL)
    assert np.array_equal(p["color"], facet.render(scene, camera, 80, 60)["color"])
    bg = p["instance"] == 0
    assert bg[0, 0] and not bg[30, 40]
    assert np.isinf(p["depth"][bg]).all() and np.isinf(p["range"][bg]).all()
    assert (p["normal"][bg] == 0).all() and (p["uv"][bg] == 0).all() and (p["alpha"][bg] == 0).all()
    assert (p["material"][bg] == 0).all() and (p["primitive"][bg] == 0).all()
    assert (p["alpha"][~bg] == 1).all() and (p["material"][~bg] == 1).all() and (p["instance"][~bg] == 1).all()


def test_depth_lies_on_the_sphere_through_the_cameras_K_and_pose_and_normals_are_its_normals():
    radius, centre = 1.0, np.array([0.3, -0.2, 0.1])
    scene = sphere_scene(radius, centre)
    w, h = 160, 120
    camera = facet.Camera.look_at((2.0, 1.5, 3.5), centre, fov_y=35).resolve(scene, w, h)
    p = facet.render(scene, camera, w, h, passes=("depth", "range", "normal"))
    k, pose = camera.K, camera.world_to_camera
    r, t = pose[:3, :3], pose[:3, 3]
    j, i = np.nonzero(np.isfinite(p["depth"]))
    assert len(i) > 3000
    rays = np.stack([i, j, np.ones_like(i)], axis=1).astype(np.float64) @ np.linalg.inv(k).T
    points_cam = rays * p["depth"][j, i, None]
    points = (points_cam - t) @ r  # R^T (x - t)
    # On the sphere within the tessellation's error: the facets lie inside it, by at most about
    # 1 - cos(half a facet's angle) in each of its two directions (the facets span pi/96).
    dist = np.linalg.norm(points - centre, axis=1)
    sag = radius * 2 * (1 - np.cos(np.pi / 192))
    assert dist.max() < radius + 5e-5 and dist.min() > radius - 1.1 * sag - 5e-5  # float32 vertices and depth
    np.testing.assert_allclose(p["range"][j, i], p["depth"][j, i] * np.linalg.norm(rays, axis=1), rtol=2e-6)
    # Interpolated normals of a fine sphere: the analytic normal at the point, within the
    # tessellation's angle.
    analytic = (points - centre) / dist[:, None]
    got = p["normal"][j, i]
    np.testing.assert_allclose(np.linalg.norm(got, axis=1), 1, atol=1e-3)
    assert np.abs(got - analytic).max() < 2e-2
    # Camera-space normals are the world ones turned by the camera (OpenGL axes: y up, z toward the viewer).
    cam = facet.render(scene, camera, w, h, passes=("normal",), normal_space="camera")["normal"][j, i]
    np.testing.assert_allclose(cam, (got @ r.T) * np.array([1, -1, -1]), atol=1e-5)


def test_instance_ids_name_the_nearest_mesh():
    near_v, near_f, near_n, _ = uv_sphere(0.6, (0.4, 0, 1.0), 24, 48)
    far_v, far_f, far_n, _ = uv_sphere(1.0, (-0.3, 0, -1.0), 24, 48)
    scene = facet.Scene.from_arrays(far_v, far_f, normals=far_n, color=(1, 0, 0))
    scene.add_mesh(near_v, near_f, normals=near_n, color=(0, 1, 0))
    camera = facet.Camera.look_at((0, 0, 6), (0, 0, 0), fov_y=45)
    p = facet.render(scene, camera, 96, 72, passes=("instance", "material", "depth"))
    alone = [facet.render(facet.Scene.from_arrays(v, f, normals=n), camera, 96, 72, passes=("depth",))["depth"]
             for v, f, n in ((far_v, far_f, far_n), (near_v, near_f, near_n))]
    nearest = np.where(np.isinf(alone[0]) & np.isinf(alone[1]), 0, np.where(alone[1] < alone[0], 2, 1))
    assert np.array_equal(p["instance"], nearest)
    assert np.array_equal(p["material"], nearest)  # two materials, numbered as the objects
    assert set(np.unique(p["instance"])) == {0, 1, 2}


def test_out_arrays_are_filled_in_place():
    scene = sphere_scene()
    camera = facet.Camera.orbit(30, 20)
    renderer = facet.Renderer(threads=2)
    expected = renderer.render(scene, camera, 40, 30, passes=("depth", "normal", "instance"))
    depth = np.zeros((40 * 30,), np.float32)[: 30 * 40].reshape(30, 40)
    normal = np.zeros((30, 40, 3), np.float32)
    got = renderer.render(scene, camera, 40, 30, passes=("depth", "normal", "instance"), out={"depth": depth, "normal": normal})
    assert got["depth"] is depth and got["normal"] is normal
    assert np.array_equal(depth, expected["depth"]) and np.array_equal(normal, expected["normal"])
    assert np.array_equal(got["instance"], expected["instance"])
    with pytest.raises(ValueError, match="out\\['instance'\\] must be"):
        renderer.render(scene, camera, 40, 30, passes=("instance",), out={"instance": np.zeros((30, 40), np.int32)})
    with pytest.raises(ValueError, match="not among the passes"):
        renderer.render(scene, camera, 40, 30, passes=("depth",), out={"normal": normal})


def test_the_arrays_are_facet_renders_files_to_the_byte(bunny, facet_exe, tmp_path):
    out = tmp_path / "out"
    r = subprocess.run([str(facet_exe), "render", str(bunny), "--views", "orbit:2:30", "--passes",
                        "color,depth,normal,instance,primitive,uv", "--ssaa", "2", "--size", "96x72", "-o", str(out)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    scene = facet.load(bunny)
    views = json.loads((out / "cameras.json").read_text())["views"]
    cameras = [facet.Camera.from_intrinsics(v["K"], v["width"], v["height"], np.hstack([v["R"], np.array(v["t"])[:, None]]),
                                            near=v["near"], far=v["far"]) for v in views]
    got = facet.render(scene, cameras, 96, 72, passes=("depth", "normal", "uv", "primitive"), ssaa=2)
    for i in range(2):
        for name in ("depth", "normal", "uv"):
            stored = np.load(out / name / f"{i:04d}.npy")
            assert stored.dtype == np.float32 and stored.tobytes() == got[name][i].tobytes(), name
        primitive = out / "primitive" / f"{i:04d}.npy"  # the bunny has more than 65535 triangles
        assert np.array_equal(np.load(primitive), got["primitive"][i])


def test_pass_names_are_checked():
    scene = sphere_scene()
    for passes, message in ((("colour",), "unknown pass 'colour'"), (("depth", "depth"), "asked for twice"),
                            (("color,depth",), "unknown pass"), ((), "passes is empty")):
        with pytest.raises(ValueError, match=message):
            facet.render(scene, facet.Camera(), 8, 8, passes=passes)
    with pytest.raises(ValueError, match="normal_space"):
        facet.render(scene, facet.Camera(), 8, 8, passes=("normal",), normal_space="screen")
