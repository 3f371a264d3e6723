"""Renders from several Python threads at once: the GIL is released while rendering, and four
threads rendering different scenes at the same time give the same arrays as serial renders,
through facet.render, a Renderer each, or one Renderer shared (its calls take turns). A scene
may be added to while another thread renders it."""
import threading

import numpy as np
import pytest

import facet


@pytest.fixture(scope="module")
def jobs(meshes):
    """Four different scenes, each with its own cameras and options."""
    rng = np.random.default_rng(23)
    v = rng.uniform(-1, 1, (300, 3)).astype(np.float32)
    f = rng.integers(0, 300, (200, 3))
    colors = rng.uniform(0, 1, (300, 4)).astype(np.float32)
    return [
        (facet.load(meshes / "bunny00.off"), [facet.Camera.orbit(a, 20) for a in (0, 90)], dict(shading="lit")),
        (facet.load(meshes / "elephant.off"), [facet.Camera.orbit(45, -10, fov_y=30)], dict(shading="normals", ssaa=2)),
        (facet.Scene.default(), [facet.Camera.orbit(35, 28), facet.Camera()], dict(background="transparent")),
        (facet.Scene.from_arrays(v, f, colors=colors), [facet.Camera.look_at((0, 0, 4), (0, 0, 0))],
         dict(shading="vertex-color", passes=("color", "alpha"))),
    ]


def run_threads(work):
    """Runs each callable in a thread of its own, all started together; returns their results."""
    results = [None] * len(work)
    errors = []
    start = threading.Barrier(len(work))

    def run(i):
        try:
            start.wait()
            results[i] = work[i]()
        except Exception as e:  # reported below, in the main thread
            errors.append(e)

    threads = [threading.Thread(target=run, args=(i,)) for i in range(len(work))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    return results


def assert_same(a, b):
    assert a.keys() == b.keys()
    for k in a:
        assert np.array_equal(a[k], b[k]), k


def test_four_threads_render_what_serial_renders_give(jobs):
    serial = [facet.render(s, c, 150, 110, **o) for s, c, o in jobs]
    for _ in range(3):
        parallel = run_threads([lambda s=s, c=c, o=o: facet.render(s, c, 150, 110, threads=1, **o) for s, c, o in jobs])
        for a, b in zip(serial, parallel):
            assert_same(a, b)
    renderers = [facet.Renderer(threads=2) for _ in jobs]
    parallel = run_threads([lambda r=r, s=s, c=c, o=o: [r.render(s, c, 150, 110, **o) for _ in range(3)]
                            for r, (s, c, o) in zip(renderers, jobs)])
    for a, runs in zip(serial, parallel):
        for b in runs:
            assert_same(a, b)


def test_threads_sharing_a_renderer_take_turns(jobs):
    shared = facet.Renderer()
    serial = [facet.render(s, c, 100, 80, **o) for s, c, o in jobs]
    parallel = run_threads([lambda s=s, c=c, o=o: shared.render(s, c, 100, 80, **o) for s, c, o in jobs])
    for a, b in zip(serial, parallel):
        assert_same(a, b)


def test_the_same_scene_in_four_threads(jobs):
    scene, cameras, options = jobs[0]
    serial = facet.render(scene, cameras, 120, 90, **options)
    for result in run_threads([lambda: facet.render(scene, cameras, 120, 90, **options)] * 4):
        assert_same(serial, result)


def test_adding_to_a_scene_while_it_renders():
    v = np.array([[-1, -1, 0], [1, -1, 0], [0, 1, 0]], np.float32)
    f = np.array([[0, 1, 2]], np.uint32)
    scene = facet.Scene.from_arrays(v, f)
    camera = facet.Camera.look_at((0, 0, 30), (0, 0, 0), near=1, far=100)
    stop = threading.Event()
    first = threading.Event()
    counts = []

    # The thread renders at least once before the first mesh is added and once after the last (a
    # loop that only checked `stop` first could start after the adding ended and render nothing).
    def render():
        r = facet.Renderer(threads=2)
        while True:
            last = stop.is_set()
            r.render(scene, camera, 64, 64)
            counts.append(r.stats["triangles_in"])
            first.set()
            if last:
                break

    t = threading.Thread(target=render)
    t.start()
    try:
        assert first.wait(120), "the rendering thread did not render"
        for i in range(200):
            m = np.eye(4)
            m[:2, 3] = (i % 20) - 10, (i // 20) - 5
            scene.add_mesh(v, f, transform=m)
    finally:
        stop.set()
        t.join()
    assert len(scene) == 201
    # Each render saw the scene whole, at some point of its growth: the first before it grew, the
    # last after.
    assert counts[0] == 1 and counts[-1] == 201 and counts == sorted(counts)
