"""facet: a software 3D renderer, from Python. NumPy arrays in, NumPy arrays out; no GPU,
no OpenGL context, no display.

    import facet
    scene = facet.load("bunny.off")                    # or facet.Scene.from_arrays(vertices, faces)
    images = facet.render(scene, facet.Camera.orbit(30, 20), 512, 512)
    images["color"]                                     # (512, 512, 4) uint8 RGBA

The same scene, camera and options give the same bytes as `facet render`'s PNG, for any
number of threads. `python3 -m facet render ...` runs the command line.
"""
from ._facet import (
    Camera,
    Environment,
    Error,
    LoadWarning,
    Renderer,
    Scene,
    __version__,
    load,
    load_isolated,
    render,
    write_png,
)

__all__ = [
    "Camera",
    "Environment",
    "Error",
    "LoadWarning",
    "Renderer",
    "Scene",
    "__version__",
    "load",
    "load_isolated",
    "render",
    "write_png",
]

for _name in ("Camera", "Environment", "Renderer", "Scene", "load", "load_isolated", "render", "write_png"):
    globals()[_name].__module__ = __name__  # help() and reprs say facet.Camera, not facet._facet.Camera
del _name
