"""facet's Python quick start (README.md, "Python"): a model file seen from four sides and a mesh
made of NumPy arrays, in one PNG, the picture in the README.

    python3 examples/python/quickstart.py MODEL OUT.png
"""
import sys

import numpy as np

import facet

model, out = sys.argv[1], sys.argv[2]

# A model file: every format `facet render` reads, the same limits and errors.
scene = facet.load(model)
cameras = [facet.Camera.orbit(azimuth, 20) for azimuth in (0, 90, 180, 270)]  # `--azimuth A --elevation 20`
views = facet.render(scene, cameras, 256, 256, ssaa=2, contact_shadow=0.6)["color"]  # (4, 256, 256, 4) uint8 RGBA

# A mesh of arrays: a wavy grid coloured by its height, with normals computed as for a file.
n = 96
x, z = np.meshgrid(np.linspace(-1, 1, n), np.linspace(-1, 1, n))
y = 0.15 * np.sin(5 * x) * np.cos(4 * z)
vertices = np.stack([x, y, z], axis=-1).reshape(-1, 3).astype(np.float32)
corner = np.arange(n * n).reshape(n, n)[:-1, :-1].ravel()
faces = np.concatenate([np.stack([corner, corner + n, corner + 1], axis=1),
                        np.stack([corner + 1, corner + n, corner + n + 1], axis=1)])
height = (vertices[:, 1] - y.min()) / np.ptp(y)
colors = np.stack([0.2 + 0.7 * height, 0.45 + 0.2 * height, 0.9 - 0.6 * height], axis=1)
wave = facet.Scene.from_arrays(vertices, faces, colors=colors)
grid = facet.render(wave, facet.Camera.orbit(30, 35), 256, 256, ssaa=2)["color"]

facet.write_png(out, np.concatenate([*views, grid], axis=1))  # one row of five images
