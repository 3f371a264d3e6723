"""The README's Python quick start (examples/python/quickstart.py) runs and writes the picture the
README shows: five 256x256 views in a row, each with a model in it. write_png's file reads back
with the pixels it was given."""
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import facet
from pngfile import read_png

QUICKSTART = Path(__file__).resolve().parents[2] / "examples" / "python" / "quickstart.py"


def test_the_quick_start_writes_its_picture(bunny, tmp_path):
    out = tmp_path / "quickstart.png"
    r = subprocess.run([sys.executable, str(QUICKSTART), str(bunny), str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    image = read_png(out)
    assert image.shape == (256, 5 * 256, 3)
    background = image[0, 0]
    for i in range(5):
        panel = image[:, i * 256:(i + 1) * 256]
        covered = (panel != background).any(axis=2).mean()
        assert 0.05 < covered < 0.95, i


def test_write_png_round_trips(tmp_path):
    rng = np.random.default_rng(5)
    rgba = rng.integers(0, 256, (17, 23, 4), dtype=np.uint8)
    facet.write_png(tmp_path / "a.png", rgba)
    assert np.array_equal(read_png(tmp_path / "a.png"), rgba)
    rgb = rgba[..., :3]  # not contiguous: converted
    facet.write_png(str(tmp_path / "b.png"), rgb)
    assert np.array_equal(read_png(tmp_path / "b.png"), rgb)
    with pytest.raises(ValueError, match="uint8 array of shape"):
        facet.write_png(tmp_path / "c.png", rgba.astype(np.float32))
    with pytest.raises(facet.Error, match="no_such_dir"):
        facet.write_png(tmp_path / "no_such_dir" / "d.png", rgba)
    assert not (tmp_path / "c.png").exists()


def test_the_passes_example_writes_four_panels(tmp_path):
    # The default scene: colour, depth, normals and instance ids of one view, side by side.
    out = tmp_path / "passes.png"
    example = QUICKSTART.parent / "passes.py"
    r = subprocess.run([sys.executable, str(example), str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    image = read_png(out)
    assert image.shape == (240, 4 * 320, 3)
    colour, depth, normal, instance = (image[:, i * 320:(i + 1) * 320] for i in range(4))
    covered = (instance != 0).any(axis=2)
    assert 0.05 < covered.mean() < 0.95
    # Each pass panel is black exactly where no object is.
    for panel in (depth, normal):
        assert not panel[~covered].any() and panel[covered].any(axis=1).mean() > 0.99
    assert len(np.unique(instance[covered].reshape(-1, 3), axis=0)) >= 2  # several objects
