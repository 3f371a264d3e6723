"""render()'s lit-mode and anti-aliasing options (environment, exposure, tone_mapping, aa,
contact_shadow): each gives `facet render`'s bytes with the same option, aa averages colour and
alpha only, and bad values are ValueErrors (TypeErrors for wrong types) naming the argument."""
import math

import numpy as np
import pytest

import facet
from test_cli_parity import cli_render, same_image

SIZE = (96, 72)


def write_hdr(path, width=16, height=8):
    """A small Radiance .hdr in flat (not run-length encoded) RGBE: a warm sky over a blue floor."""
    rows = []
    for y in range(height):
        for x in range(width):
            r, g, b = (3.0, 2.0, 1.0) if y < height // 2 else (0.1, 0.2, 0.8 + x / width)
            m, e = math.frexp(max(r, g, b))
            scale = m * 256.0 / max(r, g, b)
            rows.append(bytes([int(r * scale), int(g * scale), int(b * scale), e + 128]))
    path.write_bytes(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n" + f"-Y {height} +X {width}\n".encode() + b"".join(rows))
    return path


@pytest.fixture(scope="module")
def scene(bunny):
    return facet.load(bunny)


@pytest.fixture(scope="module")
def hdr(tmp_path_factory):
    return write_hdr(tmp_path_factory.mktemp("hdr") / "sky.hdr")


CAMERA = (facet.Camera.orbit(30, 20), ["--azimuth", 30, "--elevation", 20])

# (render keywords, the equivalent command-line options); "HDR" stands for the .hdr file's path.
CASES = {
    "exposure": (dict(exposure=2.5), ["--exposure", 2.5]),
    "aces": (dict(tone_mapping="aces"), ["--tone-mapping", "aces"]),
    "linear": (dict(tone_mapping="linear", exposure=0.5), ["--tone-mapping", "linear", "--exposure", 0.5]),
    "aa": (dict(aa=4), ["--aa", 4]),
    "aa and ssaa": (dict(aa=2, ssaa=2), ["--aa", 2, "--ssaa", 2]),
    "contact shadow": (dict(contact_shadow=0.8), ["--contact-shadow", 0.8]),
    "environment path": (dict(environment="HDR"), ["--environment", "HDR"]),
    "environment object": (dict(environment="ENV"), ["--environment", "HDR"]),
}


@pytest.mark.parametrize("name", CASES)
def test_each_option_gives_the_command_lines_bytes(scene, bunny, hdr, facet_exe, tmp_path, name):
    kwargs, options = CASES[name]
    swap = {"HDR": str(hdr), "ENV": facet.Environment(hdr)}
    kwargs = {k: swap.get(v, v) if isinstance(v, str) else v for k, v in kwargs.items()}
    options = [swap["HDR"] if o == "HDR" else o for o in options]
    rgba = facet.render(scene, CAMERA[0], *SIZE, **kwargs)["color"]
    plain = facet.render(scene, CAMERA[0], *SIZE)["color"]
    assert (rgba != plain).any(), f"{name} did not change the image"
    same_image(cli_render(facet_exe, tmp_path, bunny, "--size", f"{SIZE[0]}x{SIZE[1]}", *CAMERA[1], *options), rgba)


def test_an_environment_is_reused_and_a_path_is_the_same_light(scene, hdr):
    env = facet.Environment(hdr)
    assert env.path == str(hdr) and "sky.hdr" in repr(env)
    renderer = facet.Renderer(threads=1)
    a = renderer.render(scene, CAMERA[0], *SIZE, environment=env)["color"].copy()
    b = renderer.render(scene, CAMERA[0], *SIZE, environment=hdr)["color"]  # os.PathLike
    assert (a == b).all()
    assert (renderer.render(scene, CAMERA[0], *SIZE, environment=env)["color"] == a).all()


def test_aa_averages_color_and_alpha_and_leaves_the_other_passes(scene):
    passes = ("color", "alpha", "depth", "normal", "instance")
    one = facet.render(scene, CAMERA[0], *SIZE, passes=passes, background="transparent")
    four = facet.render(scene, CAMERA[0], *SIZE, passes=passes, background="transparent", aa=4)
    for p in ("depth", "normal", "instance"):
        assert one[p].tobytes() == four[p].tobytes(), p
    # Edges take fractional coverage; inside and outside the model the samples agree.
    fractional = (four["alpha"] > 0) & (four["alpha"] < 1)
    assert fractional.any() and not ((one["alpha"] > 0) & (one["alpha"] < 1)).any()
    assert (four["color"][..., 3] != one["color"][..., 3]).any()
    assert (four["alpha"] == 1).any() and (four["alpha"][one["instance"] == 0] < 1).all()


def test_the_contact_shadow_is_the_lit_modes_only(scene):
    for shading in ("lambert", "normals"):
        plain = facet.render(scene, CAMERA[0], *SIZE, shading=shading)["color"]
        assert (facet.render(scene, CAMERA[0], *SIZE, shading=shading, contact_shadow=1)["color"] == plain).all()


@pytest.mark.parametrize("kwargs, message", [
    (dict(aa=3), "aa must be 1, 2, 4 or 8, got 3"),
    (dict(aa=0), "aa must be 1, 2, 4 or 8, got 0"),
    (dict(aa=10**30), "aa must be 1, 2, 4 or 8"),
    (dict(exposure=0), "exposure must be a positive number"),
    (dict(exposure=float("nan")), "exposure must be a positive number"),
    (dict(exposure=float("inf")), "exposure must be a positive number"),
    (dict(tone_mapping="filmic"), "tone_mapping must be 'neutral', 'aces' or 'linear', got 'filmic'"),
    (dict(contact_shadow=1.5), "contact_shadow must be 0..1, got 1.5"),
    (dict(contact_shadow=-0.1), "contact_shadow must be 0..1"),
])
def test_bad_values_raise_value_errors(scene, kwargs, message):
    with pytest.raises(ValueError, match=message.replace(".", r"\.").replace("(", r"\(")):
        facet.render(scene, CAMERA[0], 8, 8, **kwargs)
    with pytest.raises(ValueError, match=message.replace(".", r"\.").replace("(", r"\(")):
        facet.Renderer(threads=1).render(scene, CAMERA[0], 8, 8, **kwargs)


@pytest.mark.parametrize("kwargs", [dict(aa=2.0), dict(aa="2"), dict(exposure="1"), dict(tone_mapping=1),
                                    dict(contact_shadow="0.5"), dict(environment=3)])
def test_wrong_types_raise_type_errors(scene, kwargs):
    with pytest.raises(TypeError):
        facet.render(scene, CAMERA[0], 8, 8, **kwargs)


def test_missing_and_bad_hdr_files_name_the_file(scene, tmp_path):
    missing = tmp_path / "nowhere.hdr"
    with pytest.raises(FileNotFoundError, match="nowhere.hdr"):
        facet.Environment(missing)
    with pytest.raises(FileNotFoundError, match="nowhere.hdr"):
        facet.render(scene, CAMERA[0], 8, 8, environment=str(missing))
    bad = tmp_path / "bad.hdr"
    bad.write_bytes(b"#?RADIANCE\nnot an image")
    with pytest.raises(facet.Error, match="bad.hdr"):
        facet.Environment(bad)
