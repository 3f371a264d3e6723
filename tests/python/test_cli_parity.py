"""The same scene, camera and options give the same bytes from Python as `facet render`'s PNG
(read back by an independent decoder, pngfile.py): every default (size, background, lights,
framing, clip planes, shading) is the command line's."""
import subprocess

import numpy as np
import pytest

import facet
from pngfile import read_png


def cli_render(facet_exe, tmp_path, model, *options):
    out = tmp_path / "cli.png"
    args = [str(facet_exe), "render"] + ([str(model)] if model else []) + ["-o", str(out)] + [str(o) for o in options]
    r = subprocess.run(args, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return read_png(out)


def same_image(png, rgba):
    """The PNG (RGB when every pixel is opaque, else RGBA) against the rendered RGBA array."""
    if png.shape[2] == 3:
        assert (rgba[..., 3] == 255).all()
        rgba = rgba[..., :3]
    assert png.shape == rgba.shape
    differing = int(np.count_nonzero((png != rgba).any(axis=2)))
    assert differing == 0, f"{differing} pixels differ"


# (Python render arguments, the equivalent command-line options)
CASES = {
    "defaults, orbit": (dict(camera=facet.Camera.orbit(30, 20)), ["--azimuth", 30, "--elevation", 20]),
    "default size and camera": (dict(camera=facet.Camera(), size=None), []),
    "look_at, lambert, ssaa, background": (
        dict(camera=facet.Camera.look_at((0.3, 0.5, 1.6), (0, 0.05, 0), up=(0, 1, 0.2), fov_y=35), shading="lambert",
             ssaa=2, background=(1, 1, 1)),
        ["--eye", "0.3,0.5,1.6", "--target", "0,0.05,0", "--up", "0,1,0.2", "--fov", 35, "--shading", "lambert",
         "--ssaa", 2, "--background", "1,1,1"]),
    "look_at without target, clip planes, normals": (
        dict(camera=facet.Camera.look_at((1.2, 0.2, 0.9), fov_y=60, near=0.8, far=1.9), shading="normals"),
        ["--eye", "1.2,0.2,0.9", "--fov", 60, "--near", 0.8, "--far", 1.9, "--shading", "normals"]),
    "transparent, flat, threads": (
        dict(camera=facet.Camera.orbit(-45, 30), background="transparent", shading="flat", threads=1),
        ["--azimuth", -45, "--elevation", 30, "--background", "transparent", "--shading", "flat", "--threads", 2]),
    "orthographic, mask": (
        dict(camera=facet.Camera.orbit(90, -10, orthographic=True), shading="mask", background=(0, 0, 0, 0.5)),
        ["--azimuth", 90, "--elevation", -10, "--ortho", "--shading", "mask", "--background", "0,0,0,0.5"]),
}


@pytest.mark.parametrize("name", CASES)
def test_loaded_model_renders_the_command_lines_bytes(bunny, facet_exe, tmp_path, name):
    args, options = CASES[name]
    args = dict(args)
    size = args.pop("size", (200, 150))
    scene = facet.load(bunny)
    if size is None:
        rgba = facet.render(scene, args.pop("camera"), **args)["color"]
    else:
        rgba = facet.render(scene, args.pop("camera"), *size, **args)["color"]
        options = options + ["--size", f"{size[0]}x{size[1]}"]
    same_image(cli_render(facet_exe, tmp_path, bunny, *options), rgba)


def test_renderer_and_a_list_of_cameras_give_the_same_bytes(bunny, facet_exe, tmp_path):
    scene = facet.load(bunny)
    renderer = facet.Renderer(threads=1)
    batch = renderer.render(scene, [facet.Camera.orbit(a, 10) for a in (0, 120)], 120, 90, ssaa=3)["color"]
    for i, a in enumerate((0, 120)):
        same_image(cli_render(facet_exe, tmp_path, bunny, "--azimuth", a, "--elevation", 10, "--size", "120x90",
                              "--ssaa", 3), batch[i])


def test_the_default_scene(facet_exe, tmp_path):
    rgba = facet.render(facet.Scene.default(), facet.Camera.orbit(20, 15), 160, 120)["color"]
    same_image(cli_render(facet_exe, tmp_path, None, "--azimuth", 20, "--elevation", 15, "--size", "160x120"), rgba)


def read_off(path):
    """vertices and faces of a plain triangle OFF file, parsed here."""
    words = [w for line in path.read_text().splitlines() for w in line.split("#")[0].split()]
    assert words[0] == "OFF"
    nv, nf = int(words[1]), int(words[2])
    vertices = np.array(words[4:4 + 3 * nv], np.float32).reshape(nv, 3)
    faces = np.array(words[4 + 3 * nv:4 + 3 * nv + 4 * nf], np.int64).reshape(nf, 4)
    assert (faces[:, 0] == 3).all()
    return vertices, faces[:, 1:]


def test_arrays_get_the_normals_the_command_line_computes(meshes, facet_exe, tmp_path):
    # The elephant as arrays (no normals in the file): facet computes creased normals as
    # `facet render` does for the file. OFF files load with a 0.6 grey material (assimp's).
    elephant = meshes / "elephant.off"
    vertices, faces = read_off(elephant)
    scene = facet.Scene.from_arrays(vertices, faces, color=(0.6, 0.6, 0.6))
    for camera, options in ((facet.Camera.orbit(30, 20), ["--azimuth", 30, "--elevation", 20]),
                            (facet.Camera.orbit(200, -30, fov_y=30), ["--azimuth", 200, "--elevation", -30, "--fov", 30])):
        rgba = facet.render(scene, camera, 180, 140)["color"]
        same_image(cli_render(facet_exe, tmp_path, elephant, "--size", "180x140", *options), rgba)


def sphere_points(n, seed):
    """n points on the unit sphere (their own normals) and a colour each."""
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(n, 3)).astype(np.float32)
    v /= np.linalg.norm(v, axis=1)[:, None]
    return v, rng.integers(0, 256, size=(n, 3), dtype=np.uint8)


def test_points_from_arrays_and_files_render_the_command_lines_bytes(facet_exe, tmp_path):
    # A coloured cloud with normals as a PLY file (written here) and as arrays with points=: both
    # give `facet render`'s bytes for each point style.
    v, c = sphere_points(2000, 26)
    ply = tmp_path / "cloud.ply"
    header = (f"ply\nformat ascii 1.0\nelement vertex {len(v)}\n" + "".join(f"property float {a}\n" for a in
              ("x", "y", "z", "nx", "ny", "nz")) + "".join(f"property uchar {a}\n" for a in ("red", "green", "blue")))
    rows = "".join("%r %r %r %r %r %r %d %d %d\n" % (*map(float, p), *map(float, p), *map(int, q)) for p, q in zip(v, c))
    ply.write_text(header + "end_header\n" + rows)
    arrays = facet.Scene.from_arrays(v, normals=v, colors=c, points=np.arange(len(v)))
    for args, options in ((dict(point_size=5, point_shape="square", ssaa=2), ["--point-size", 5, "--point-shape", "square",
                                                                              "--ssaa", 2]),
                          (dict(point_world_size=0.05, shading="lambert"), ["--point-world-size", 0.05, "--shading", "lambert"])):
        png = cli_render(facet_exe, tmp_path, ply, "--size", "160x120", "--azimuth", 30, "--elevation", 20, *options)
        for scene in (facet.load(ply), arrays):
            rgba = facet.render(scene, facet.Camera.orbit(30, 20), 160, 120, **args)["color"]
            assert np.count_nonzero((rgba[..., :3] != rgba[0, 0, :3]).any(axis=2)) > 1000  # the cloud is there
            same_image(png, rgba)


def test_lines_render_the_command_lines_bytes_and_are_counted(facet_exe, tmp_path):
    # A closed polyline as an OBJ `l` line, drawn 3 pixels wide.
    v, _ = sphere_points(40, 27)
    obj = tmp_path / "loop.obj"
    obj.write_text("".join("v %r %r %r\n" % tuple(map(float, p)) for p in v) +
                   "l " + " ".join(str(i + 1) for i in range(len(v))) + " 1\n")
    renderer = facet.Renderer(threads=2)
    rgba = renderer.render(facet.load(obj), facet.Camera.orbit(30, 20), 160, 120, line_width=3, shading="flat")["color"]
    assert renderer.stats["segments_in"] == len(v) and renderer.stats["triangles_in"] == 0
    same_image(cli_render(facet_exe, tmp_path, obj, "--size", "160x120", "--azimuth", 30, "--elevation", 20,
                          "--line-width", 3, "--shading", "flat"), rgba)
    # The same segments as arrays: wider lines cover more pixels.
    segments = np.array([[i, (i + 1) % len(v)] for i in range(len(v))])
    scene = facet.Scene.from_arrays(v, lines=segments)
    thin, wide = (np.count_nonzero(facet.render(scene, facet.Camera.orbit(30, 20), 160, 120, line_width=w,
                                                 background="transparent")["color"][..., 3] > 0)
                  for w in (1, 4))
    assert renderer.stats["segments_invalid"] == 0
    assert 0 < thin < wide


def test_anti_aliased_lines_render_the_command_lines_bytes(facet_exe, tmp_path):
    # The closed polyline above, 2 pixels wide, anti-aliased: line_aa=True and --line-aa give the same
    # bytes, and the blended edges bring shades between the line's colour and the background's.
    v, _ = sphere_points(40, 27)
    obj = tmp_path / "loop.obj"
    obj.write_text("".join("v %r %r %r\n" % tuple(map(float, p)) for p in v) +
                   "l " + " ".join(str(i + 1) for i in range(len(v))) + " 1\n")
    images = {aa: facet.render(facet.load(obj), facet.Camera.orbit(30, 20), 160, 120, line_width=2, shading="flat",
                               line_aa=aa)["color"] for aa in (False, True)}
    same_image(cli_render(facet_exe, tmp_path, obj, "--size", "160x120", "--azimuth", 30, "--elevation", 20,
                          "--line-width", 2, "--shading", "flat", "--line-aa"), images[True])
    shades = {aa: len(np.unique(images[aa].reshape(-1, 4), axis=0)) for aa in images}
    assert shades[True] > shades[False] + 20
