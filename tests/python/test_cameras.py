"""Cameras in OpenCV's convention, end to end through rendered pixels: points projected with K
and [R|t] (pixel centres at integer (u, v)) are where the render draws them, resolved cameras
give K, poses and the same images, and cameras round-trip through their numbers exactly."""
import numpy as np
import pytest

import facet


def random_rotation(rng):
    q = rng.normal(size=4)
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def marker_scene(points, camera_r, sizes):
    """A small triangle about each world point, its centroid, facing the camera (rows of R:
    right, down); `sizes` per point."""
    right, down = camera_r[0], camera_r[1]
    corners = np.array([-down, 0.866 * right + 0.5 * down, -0.866 * right + 0.5 * down])
    vertices = (points[:, None, :] + corners[None] * np.asarray(sizes, float).reshape(-1, 1, 1)).reshape(-1, 3)
    faces = np.arange(len(vertices)).reshape(-1, 3)
    return facet.Scene.from_arrays(vertices, faces, crease_angle=None)


def blob_centroids(mask, count):
    """Centroids (x, y) of the connected blobs of a boolean image, by flood fill."""
    seen = np.zeros_like(mask)
    out = []
    for y, x in zip(*np.nonzero(mask)):
        if seen[y, x]:
            continue
        stack, pixels = [(y, x)], []
        seen[y, x] = True
        while stack:
            cy, cx = stack.pop()
            pixels.append((cy, cx))
            for ny, nx in ((cy + 1, cx), (cy - 1, cx), (cy, cx + 1), (cy, cx - 1)):
                if 0 <= ny < mask.shape[0] and 0 <= nx < mask.shape[1] and mask[ny, nx] and not seen[ny, nx]:
                    seen[ny, nx] = True
                    stack.append((ny, nx))
        p = np.array(pixels, float)
        out.append((p[:, 1].mean(), p[:, 0].mean()))
    assert len(out) == count
    return np.array(out)


@pytest.mark.parametrize("seed", range(4))
def test_points_land_where_k_and_rt_project_them(seed):
    rng = np.random.default_rng(seed)
    w, h = 160, 120
    K = np.array([[rng.uniform(90, 140), rng.uniform(-3, 3), rng.uniform(60, 100)],
                  [0, rng.uniform(90, 140), rng.uniform(45, 75)],
                  [0, 0, 1]])
    R = random_rotation(rng)
    t = rng.uniform(-1, 1, 3)
    # Points at chosen pixels and depths, back-projected into the world.
    uv = np.array([[20, 20], [140, 25], [80, 60], [30, 100], [130, 95]], float) + rng.uniform(-0.5, 0.5, (5, 2))
    z = rng.uniform(4, 8, 5)
    cam = np.linalg.solve(K, np.vstack([uv.T, np.ones(5)])) * z
    world = (R.T @ (cam - t[:, None])).T
    scene = marker_scene(world, R, 0.06 * z)  # about 7 px across
    camera = facet.Camera.from_intrinsics(K, w, h, np.hstack([R, t[:, None]]))
    mask = facet.render(scene, camera, w, h, passes=("alpha",))["alpha"] > 0
    got = blob_centroids(mask, 5)
    # Each blob's centroid (pixel (i, j) at (i, j), as OpenCV counts) is its point's (u, v).
    order = np.argsort(got[:, 0] * 1000 + got[:, 1])
    expected = uv[np.argsort(uv[:, 0] * 1000 + uv[:, 1])]
    assert np.abs(got[order] - expected).max() < 0.5


def test_rendering_at_another_size_scales_k():
    rng = np.random.default_rng(7)
    R, t = random_rotation(rng), np.array([0.1, -0.2, 0.3])
    K = np.array([[100.0, 0, 70], [0, 110, 50], [0, 0, 1]])
    uv = np.array([[30.0, 40], [100, 70]])
    cam = np.linalg.solve(K, np.vstack([uv.T, np.ones(2)])) * 5
    world = (R.T @ (cam - t[:, None])).T
    scene = marker_scene(world, R, [0.3, 0.3])
    camera = facet.Camera.from_intrinsics(K, 140, 100, np.hstack([R, t[:, None]]))
    mask = facet.render(scene, camera, 280, 200, passes=("alpha",))["alpha"] > 0
    got = blob_centroids(mask, 2)
    expected = (uv + 0.5) * 2 - 0.5  # the same points in pixels of the doubled image
    got = got[np.argsort(got[:, 0])]
    assert np.abs(got - expected[np.argsort(expected[:, 0])]).max() < 0.5
    resolved = camera.resolve(scene, 280, 200)
    assert np.allclose(resolved.K, [[200, 0, 140.5], [0, 220, 100.5], [0, 0, 1]])


def test_resolved_cameras_render_the_same_view(bunny):
    scene = facet.load(bunny)
    for camera in (facet.Camera.orbit(30, 20), facet.Camera.look_at((0.4, 0.9, 1.1), fov_y=38),
                   facet.Camera.orbit(-60, 5, distance=2.5, fov_y=50)):
        resolved = camera.resolve(scene, 200, 150)
        assert resolved.near is not None and resolved.far is not None
        # The same view and projection: the same pixels in the modes whose shading does not
        # depend on the eye (the lit modes' lights follow the eye, whose position the OpenCV form
        # recomputes from [R|t] to within a float's last bit).
        for shading in ("normals", "mask"):
            a = facet.render(scene, camera, 200, 150, shading=shading)["color"]
            b = facet.render(scene, resolved, 200, 150, shading=shading)["color"]
            assert np.array_equal(a, b), shading
        # Its numbers round-trip exactly, and so does its image.
        again = facet.Camera.from_intrinsics(resolved.K, 200, 150, resolved.world_to_camera,
                                             near=resolved.near, far=resolved.far)
        assert np.array_equal(again.K, resolved.K) and np.array_equal(again.world_to_camera, resolved.world_to_camera)
        assert np.array_equal(facet.render(scene, again, 200, 150)["color"], facet.render(scene, resolved, 200, 150)["color"])
        # resolve of a resolved camera changes nothing.
        twice = resolved.resolve(None, 200, 150)
        assert np.array_equal(twice.K, resolved.K) and np.array_equal(twice.world_to_camera, resolved.world_to_camera)


def test_orbit_at_a_distance_and_look_at_agree(bunny):
    scene = facet.load(bunny)
    centre = scene.bounds.mean(axis=0)
    az, el, d = np.radians(40), np.radians(25), 3.0
    eye = centre + d * np.array([np.cos(el) * np.sin(az), np.sin(el), np.cos(el) * np.cos(az)])
    a = facet.Camera.orbit(40, 25, distance=d).resolve(scene, 100, 100)
    b = facet.Camera.look_at(eye, centre).resolve(scene, 100, 100)
    assert np.allclose(a.world_to_camera, b.world_to_camera, atol=1e-5)
    assert np.allclose(a.camera_to_world[:3, 3], eye, atol=1e-5)
