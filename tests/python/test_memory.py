"""1,000 renders in a loop keep the process's resident memory stable: measured from
/proc/self/statm after a warm-up, the growth over the loop stays under a bound far below what
one leaked image per render would add (1,000 x 64 KiB and more)."""
import gc
import os

import numpy as np
import pytest

import facet

PAGE = os.sysconf("SC_PAGE_SIZE")
BOUND = 8 << 20  # bytes of growth allowed over the 1,000 renders (a leaked image each: 62 MiB and more)


def resident() -> int:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * PAGE


@pytest.fixture(scope="module")
def scene(meshes):
    return facet.load(meshes / "elephant.off")


def growth(render_once, n=1000, warmup=50):
    for _ in range(warmup):
        render_once()
    gc.collect()
    before = resident()
    for _ in range(n):
        render_once()
    gc.collect()
    return resident() - before


def test_a_renderer_in_a_loop(scene):
    renderer = facet.Renderer(threads=2)
    camera = facet.Camera.orbit(30, 20)
    grew = growth(lambda: renderer.render(scene, camera, 128, 128, passes=("color", "alpha")))
    print(f"Renderer.render x1000: resident memory grew {grew / 1024:.0f} KiB")
    assert grew < BOUND


def test_render_in_a_loop(scene):
    # A Renderer, its threads and a supersampled target made and freed by every call.
    cameras = [facet.Camera.orbit(10, 10)]
    grew = growth(lambda: facet.render(scene, cameras, 128, 128, threads=2, ssaa=2))
    print(f"facet.render x1000: resident memory grew {grew / 1024:.0f} KiB")
    assert grew < BOUND


def test_out_arrays_and_new_scenes_in_a_loop(scene):
    renderer = facet.Renderer(threads=1)
    out = {"color": np.empty((128, 128, 4), np.uint8)}
    v = np.random.default_rng(1).uniform(-1, 1, (3000, 3)).astype(np.float32)
    f = np.arange(3000).reshape(1000, 3)

    def once():
        s = facet.Scene.from_arrays(v, f, crease_angle=None)
        renderer.render(s, facet.Camera(), 128, 128, out=out)
        renderer.render(scene, facet.Camera(), 128, 128, out=out)

    grew = growth(once)
    print(f"Scene.from_arrays + 2 renders into out= x1000: resident memory grew {grew / 1024:.0f} KiB")
    assert grew < BOUND
