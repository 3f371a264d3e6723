#!/usr/bin/env python3
"""facet's Python package against its own C++ call and against Open3D, the Python renderer a user
reaches for that installs from Debian (python3-open3d). Prints Markdown tables for
docs/BENCHMARKS.md. Run with the interpreter the package is installed in, for example the tests'
virtual environment (it sees Debian's numpy and open3d):

    build/release/tests/python/venv/bin/python bench/python_bench.py MODEL [--size 512] [--rounds 7]

  overhead  Renderer.render against the same Renderer's C++ call (_facet._time_cpp_render: the
            same camera placement, draw and image, timed in C++), in the same process; the two
            take turns, round by round, and each median is over all rounds' frames.
  images    per image, facet and Open3D's legacy Visualizer(visible=False) (its OffscreenRenderer
            fails here: "EGL Headless is not supported on this platform"): the first image after
            the mesh is loaded, then the steady state, same mesh, size and view (Open3D is given
            facet's K and [R|t]). Open3D needs an X display: Xvfb is started for it.
  whole     whole processes, load + render + save as .npy, each renderer's process started in
            turn (Open3D's against the same running Xvfb: starting Xvfb is not counted).
"""
import argparse
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np


def median_ms(values):
    return statistics.median(values) * 1e3


def overhead(model, size, rounds, frames):
    import facet
    from facet import _facet

    scene = facet.load(model)
    camera = facet.Camera.orbit(30, 20)
    rows = []
    for threads in (1, 2):
        renderer = facet.Renderer(threads=threads)
        out = {"color": np.empty((size, size, 4), np.uint8)}
        renderer.render(scene, camera, size, size)  # warm
        # Each Python call is timed around the call and, inside it, around the C++ draw
        # (Renderer._last_draw_seconds): the difference is that call's overhead, free of the
        # drift of a shared machine. The C++ call alone (_facet._time_cpp_render: the same draw
        # into memory of its own, no Python in the loop) is timed in turn with the calls.
        cpp, py, py_out, over, over_out = [], [], [], [], []
        for _ in range(rounds * frames):
            cpp += _facet._time_cpp_render(renderer, scene, camera, size, size, 1)
            start = time.perf_counter()
            renderer.render(scene, camera, size, size)
            py.append(time.perf_counter() - start)
            over.append(py[-1] - renderer._last_draw_seconds)
            start = time.perf_counter()
            renderer.render(scene, camera, size, size, out=out)
            py_out.append(time.perf_counter() - start)
            over_out.append(py_out[-1] - renderer._last_draw_seconds)
        c = median_ms(cpp)
        rows.append(f"| {threads} | {c:.3f} ms | {median_ms(py):.3f} ms ({(median_ms(py) / c - 1) * 100:+.1f}%) | "
                    f"{median_ms(py_out):.3f} ms ({(median_ms(py_out) / c - 1) * 100:+.1f}%) | "
                    f"{median_ms(over):.3f} ms ({median_ms(over) / c * 100:.1f}%) | "
                    f"{median_ms(over_out):.3f} ms ({median_ms(over_out) / c * 100:.1f}%) |")
    print(f"\n{Path(model).name} at {size}x{size}, lit, {rounds * frames} calls of each, taken in turn; medians\n")
    print("| threads | C++ call | Renderer.render | render(out=) | overhead per call | with out= |")
    print("|---:|---:|---:|---:|---:|---:|")
    print("\n".join(rows))


class Xvfb:
    """An Xvfb display for Open3D, started and stopped by this script."""

    def __enter__(self):
        for n in range(90, 120):
            if not Path(f"/tmp/.X{n}-lock").exists():
                break
        self.display = f":{n}"
        self.proc = subprocess.Popen(["Xvfb", self.display, "-screen", "0", "1280x1024x24", "-nolisten", "tcp"],
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        for _ in range(100):
            if Path(f"/tmp/.X11-unix/X{n}").exists():
                break
            time.sleep(0.05)
        return self

    def __exit__(self, *exc):
        self.proc.terminate()
        self.proc.wait()


def open3d_images(model, size, frames, K, world_to_camera, save=None):
    """Open3D's legacy Visualizer: (ms to the first image, steady ms per image)."""
    import open3d as o3d

    mesh = o3d.io.read_triangle_mesh(str(model))
    mesh.compute_vertex_normals()
    start = time.perf_counter()
    vis = o3d.visualization.Visualizer()
    if not vis.create_window(width=size, height=size, visible=False):
        raise RuntimeError("Open3D could not open its (hidden) window: no X display?")
    vis.add_geometry(mesh)
    params = vis.get_view_control().convert_to_pinhole_camera_parameters()
    params.intrinsic.set_intrinsics(size, size, K[0, 0], K[1, 1], K[0, 2], K[1, 2])
    params.extrinsic = world_to_camera
    vis.get_view_control().convert_from_pinhole_camera_parameters(params)
    image = np.asarray(vis.capture_screen_float_buffer(do_render=True))
    first = time.perf_counter() - start
    times = []
    for _ in range(frames):
        start = time.perf_counter()
        vis.poll_events()
        vis.update_renderer()
        image = np.asarray(vis.capture_screen_float_buffer(do_render=True))
        times.append(time.perf_counter() - start)
    if save:
        np.save(save, (image * 255).round().astype(np.uint8))
    vis.destroy_window()
    return first * 1e3, median_ms(times)


def facet_images(model, size, frames):
    import facet

    scene = facet.load(model)
    camera = facet.Camera.orbit(30, 20).resolve(scene, size, size)
    start = time.perf_counter()
    facet.render(scene, camera, size, size)
    first = time.perf_counter() - start
    renderer = facet.Renderer()
    renderer.render(scene, camera, size, size)
    times = []
    for _ in range(frames):
        start = time.perf_counter()
        renderer.render(scene, camera, size, size)
        times.append(time.perf_counter() - start)
    return first * 1e3, median_ms(times), camera


def images(model, size, rounds, frames):
    f_first, f_steady, o_first, o_steady = [], [], [], []
    with Xvfb() as x:
        os.environ["DISPLAY"] = x.display
        for r in range(rounds):
            a, b, camera = facet_images(model, size, frames)
            f_first.append(a), f_steady.append(b)
            # Open3D in a process of its own each round: its first image includes its window.
            code = ("import sys, numpy as np; sys.path.insert(0, sys.argv[1]); import python_bench as pb; "
                    "K = np.array(eval(sys.argv[4])); E = np.array(eval(sys.argv[5])); "
                    "print(*pb.open3d_images(sys.argv[2], int(sys.argv[3]), int(sys.argv[6]), K, E))")
            res = subprocess.run([sys.executable, "-c", code, str(Path(__file__).parent), str(model), str(size),
                                  repr(camera.K.tolist()), repr(camera.world_to_camera.tolist()), str(frames)],
                                 capture_output=True, text=True, check=True)
            a, b = map(float, res.stdout.split()[-2:])
            o_first.append(a), o_steady.append(b)
    fm = lambda v: statistics.median(v)
    print(f"\n{Path(model).name} at {size}x{size}, the same view (Open3D given facet's K and [R|t]); "
          f"medians of {rounds} rounds, steady state over {frames} images each\n")
    print("| renderer | first image | steady state per image |")
    print("|---|---:|---:|")
    print(f"| facet (Python) | {fm(f_first):.1f} ms | {fm(f_steady):.2f} ms |")
    print(f"| Open3D 0.16 Visualizer (Xvfb, llvmpipe) | {fm(o_first):.1f} ms | {fm(o_steady):.2f} ms |")
    print(f"| ratio | {fm(o_first) / fm(f_first):.1f}x | {fm(o_steady) / fm(f_steady):.1f}x |")


WHOLE = {
    "facet": ("import sys, numpy as np, facet; s = facet.load(sys.argv[1]); "
              "np.save(sys.argv[3], facet.render(s, facet.Camera.orbit(30, 20), int(sys.argv[2]), int(sys.argv[2]))['color'])"),
    "open3d": ("import sys, numpy as np, open3d as o3d; m = o3d.io.read_triangle_mesh(sys.argv[1]); m.compute_vertex_normals(); "
               "v = o3d.visualization.Visualizer(); v.create_window(width=int(sys.argv[2]), height=int(sys.argv[2]), visible=False); "
               "v.add_geometry(m); np.save(sys.argv[3], np.asarray(v.capture_screen_float_buffer(do_render=True))); v.destroy_window()"),
}


def whole(model, size, rounds):
    out = Path("/tmp") / f"python_bench_{os.getpid()}.npy"
    times = {k: [] for k in WHOLE}
    with Xvfb() as x:
        env = dict(os.environ, DISPLAY=x.display)
        for r in range(rounds):
            for name in (WHOLE if r % 2 == 0 else reversed(list(WHOLE))):
                start = time.perf_counter()
                subprocess.run([sys.executable, "-c", WHOLE[name], str(model), str(size), str(out)], env=env, check=True,
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                times[name].append(time.perf_counter() - start)
    out.unlink(missing_ok=True)
    f, o = median_ms(times["facet"]), median_ms(times["open3d"])
    print(f"\nWhole process: python3 -c 'load, render {size}x{size}, np.save', {rounds} runs each, taking turns "
          f"(Open3D against an Xvfb already running)\n")
    print("| renderer | median | min |")
    print("|---|---:|---:|")
    print(f"| facet | {f:.0f} ms | {min(times['facet']) * 1e3:.0f} ms |")
    print(f"| Open3D 0.16 | {o:.0f} ms | {min(times['open3d']) * 1e3:.0f} ms |")
    print(f"| ratio | {o / f:.1f}x | |")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("model")
    p.add_argument("--size", type=int, default=512)
    p.add_argument("--rounds", type=int, default=7)
    p.add_argument("--frames", type=int, default=20)
    p.add_argument("--only", choices=["overhead", "images", "whole"], action="append")
    a = p.parse_args()
    parts = a.only or ["overhead", "images", "whole"]
    if "overhead" in parts:
        overhead(a.model, a.size, a.rounds, a.frames)
    if "images" in parts:
        images(a.model, a.size, a.rounds, a.frames)
    if "whole" in parts:
        whole(a.model, a.size, a.rounds * 3)


if __name__ == "__main__":
    main()
