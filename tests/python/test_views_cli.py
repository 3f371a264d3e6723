"""`facet render --views ... --passes ...` read by an independent script (json, NumPy and the
test's own PNG reader, nothing of facet's): the exported cameras put the bunny's vertices where the
primitive pass has their triangles (within 0.5 px), the depth pass back-projects onto those
triangles, range is depth through the ray's angle, and transforms.json, converted here to OpenCV's
K and [R|t], renders a view again through `--views file:` byte for byte."""
import json
import subprocess

import numpy as np

from pngfile import read_png
from test_cli_parity import read_off

PASSES = "color,depth,range,normal,instance,primitive"


def facet_views(facet_exe, model, out, *options):
    args = [str(facet_exe), "render", str(model), "-o", str(out)] + [str(o) for o in options]
    r = subprocess.run(args, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return out


def opencv_from_transforms(top, frame):
    """K and [R|t] from a NeRF frame: intrinsics with pixel centres at +0.5, transform_matrix
    camera-to-world with OpenGL's axes (x right, y up, looking down -z)."""
    get = lambda key: frame.get(key, top.get(key))
    k = np.array([[get("fl_x"), 0, get("cx") - 0.5], [0, get("fl_y"), get("cy") - 0.5], [0, 0, 1]], np.float64)
    c2w = np.array(frame["transform_matrix"], np.float64)
    flip = np.diag([1.0, -1.0, -1.0])  # OpenCV's camera axes: y down, looking down +z
    r = flip @ c2w[:3, :3].T
    t = -r @ c2w[:3, 3]
    return k, r, t, int(get("w")), int(get("h"))


def test_vertices_reproject_onto_the_primitive_pass_and_depth_onto_the_triangles(bunny, facet_exe, tmp_path):
    out = facet_views(facet_exe, bunny, tmp_path / "out", "--views", "orbit:3:25", "--passes", PASSES,
                      "--size", "200x150", "--ssaa", "2")
    vertices, faces = read_off(bunny)
    vertices = vertices.astype(np.float64)
    cameras = json.loads((out / "cameras.json").read_text())
    transforms = json.loads((out / "transforms.json").read_text())
    assert len(cameras["views"]) == len(transforms["frames"]) == 3
    for view, frame in zip(cameras["views"], transforms["frames"]):
        k, r, t = np.array(view["K"]), np.array(view["R"]), np.array(view["t"])
        # The two files describe one camera.
        k2, r2, t2, w, h = opencv_from_transforms(transforms, frame)
        assert (w, h) == (view["width"], view["height"]) == (200, 150)
        np.testing.assert_allclose(k2, k, atol=1e-9)
        np.testing.assert_allclose(r2, r, atol=1e-12)
        np.testing.assert_allclose(t2, t, atol=1e-9)

        primitive = read_ids(out / frame["primitive_file_path"])
        depth = np.load(out / frame["depth_file_path"])
        range_ = np.load(out / frame["range_file_path"])
        normal = np.load(out / frame["normal_file_path"])
        assert depth.dtype == np.float32 and depth.shape == (h, w)
        assert normal.dtype == np.float32 and normal.shape == (h, w, 3)
        covered = primitive > 0
        assert covered.sum() > 2000
        # Background values: +inf depth and range, zero normals.
        assert np.isinf(depth[~covered]).all() and np.isinf(range_[~covered]).all() and (normal[~covered] == 0).all()

        # Every vertex in camera space and at its pixel (OpenCV: pixel (i, j) is centred at (i, j)).
        cam = vertices @ r.T + t
        uv = cam @ k.T
        uv = uv[:, :2] / uv[:, 2:3]
        j, i = np.nonzero(covered)
        tri = faces[primitive[j, i] - 1]
        a, b, c = uv[tri[:, 0]], uv[tri[:, 1]], uv[tri[:, 2]]
        p = np.stack([i, j], axis=1).astype(np.float64)
        # Each pixel's centre lies in its triangle's projection, within 0.5 px of it.
        assert distance_to_triangle(p, a, b, c).max() <= 0.5

        # Back-projected with its depth, the pixel's centre lies on its triangle's plane.
        rays = np.stack([i, j, np.ones_like(i)], axis=1).astype(np.float64) @ np.linalg.inv(k).T
        points = rays * depth[j, i, None]
        ca, cb, cc = cam[tri[:, 0]], cam[tri[:, 1]], cam[tri[:, 2]]
        n = np.cross(cb - ca, cc - ca)
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        off_plane = np.abs(np.einsum("ij,ij->i", points - ca, n))
        assert off_plane.max() <= 1e-4 * depth[covered].max()
        # Range is depth through the ray's angle.
        np.testing.assert_allclose(range_[j, i], depth[j, i] * np.linalg.norm(rays, axis=1), rtol=1e-5)
        # Normals are unit vectors.
        np.testing.assert_allclose(np.linalg.norm(normal[covered], axis=1), 1, atol=1e-5)


def read_ids(path):
    """An id pass: a 16-bit PNG when every id fits, else .npy uint32."""
    if path.suffix == ".npy":
        ids = np.load(path)
        assert ids.dtype == np.uint32
        return ids.astype(np.int64)
    png = read_png(path)
    assert png.dtype == np.uint16
    return png[..., 0].astype(np.int64)


def distance_to_triangle(p, a, b, c):
    """Distance of each point to its 2D triangle (0 inside)."""
    def side(u, v):  # signed area of (u, v, p), sign of the triangle's orientation
        return (v[:, 0] - u[:, 0]) * (p[:, 1] - u[:, 1]) - (v[:, 1] - u[:, 1]) * (p[:, 0] - u[:, 0])

    def segment(u, v):
        d = v - u
        s = np.clip(np.einsum("ij,ij->i", p - u, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300), 0, 1)
        return np.linalg.norm(p - (u + s[:, None] * d), axis=1)

    s1, s2, s3 = side(a, b), side(b, c), side(c, a)
    inside = ((s1 >= 0) & (s2 >= 0) & (s3 >= 0)) | ((s1 <= 0) & (s2 <= 0) & (s3 <= 0))
    return np.where(inside, 0.0, np.minimum(np.minimum(segment(a, b), segment(b, c)), segment(c, a)))


def test_transforms_json_read_back_renders_a_view_again_byte_for_byte(bunny, facet_exe, tmp_path):
    out = facet_views(facet_exe, bunny, tmp_path / "out", "--views", "sphere:5", "--passes", PASSES, "--size", "96x72")
    transforms = json.loads((out / "transforms.json").read_text())
    frame = transforms["frames"][3]
    k, r, t, w, h = opencv_from_transforms(transforms, frame)
    # OpenCV's form, written here: facet's cameras-file layout with K, R and t.
    opencv_file = tmp_path / "opencv.json"
    opencv_file.write_text(json.dumps({"views": [{"width": w, "height": h, "K": k.tolist(), "R": r.tolist(),
                                                  "t": t.tolist()}]}))
    # The NeRF layout itself: this frame alone, its intrinsics copied into it.
    nerf_file = tmp_path / "nerf.json"
    one = {key: transforms[key] for key in ("fl_x", "fl_y", "cx", "cy", "w", "h")}
    one["frames"] = [{"file_path": "x.png", "transform_matrix": frame["transform_matrix"]}]
    nerf_file.write_text(json.dumps(one))
    for name, cameras in (("opencv", opencv_file), ("nerf", nerf_file)):
        again = facet_views(facet_exe, bunny, tmp_path / name, "--views", f"file:{cameras}", "--passes", PASSES)
        frame_again = json.loads((again / "transforms.json").read_text())["frames"][0]
        for key in ("file_path", "depth_file_path", "range_file_path", "normal_file_path", "instance_file_path",
                    "primitive_file_path"):
            assert (again / frame_again[key]).read_bytes() == (out / frame[key]).read_bytes(), f"{name}: {key}"
