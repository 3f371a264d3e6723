"""Render passes from Python (README.md, "Python"): one view of a scene with its colour, depth,
normals and instance ids, side by side in one PNG (the README's picture of the passes).

    python3 examples/python/passes.py [MODEL] OUT.png     no MODEL: the built-in default scene
"""
import sys

import numpy as np

import facet

*model, out = sys.argv[1:]
scene = facet.load(model[0]) if model else facet.Scene.default()
camera = facet.Camera.look_at((4.2, 3.4, 5.4), (0, 0.4, 0), fov_y=40).resolve(scene, 320, 240)  # OpenCV's K and [R|t]: camera.K, camera.world_to_camera
p = facet.render(scene, camera, 320, 240, passes=("color", "depth", "normal", "instance"), ssaa=2)
# p["depth"]: (240, 320) float32, distance along the viewing axis, inf on the background;
# p["normal"]: (240, 320, 3) float32 world-space unit normals; p["instance"]: (240, 320) uint32, 0 = background.

covered = p["instance"] > 0
depth = p["depth"]
near, far = depth[covered].min(), depth[covered].max()
grey = np.where(covered, 255 * (1 - 0.8 * (depth - near) / max(far - near, 1e-9)), 0)
depth_image = np.repeat(grey[..., None], 3, axis=2)
normal_image = np.where(covered[..., None], 127.5 * (p["normal"] + 1), 0)
palette = np.array([[0, 0, 0], [230, 159, 0], [86, 180, 233], [0, 158, 115], [240, 228, 66], [0, 114, 178],
                    [213, 94, 0], [204, 121, 167]])
instance_image = palette[np.where(covered, 1 + (p["instance"] - 1) % (len(palette) - 1), 0)]
panels = [p["color"][..., :3]] + [np.round(a).astype(np.uint8) for a in (depth_image, normal_image, instance_image)]
facet.write_png(out, np.concatenate(panels, axis=1))
