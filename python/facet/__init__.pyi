# Type stubs of the facet package (its classes and functions live in the extension module
# facet._facet; their docstrings, shown by help(), are the reference).
import os
from typing import Literal, Optional, Protocol, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = npt.ArrayLike
Colour = Sequence[float]
PassName = Literal["color", "alpha", "depth", "range", "normal", "instance", "material", "primitive", "uv"]
NormalSpace = Literal["world", "camera"]
PointShape = Literal["round", "square"]
ToneMapping = Literal["neutral", "aces", "linear"]
ShadingName = Literal["lit", "lambert", "flat", "normals", "mask", "vertex-color", "texture"]

class _MeshLike(Protocol):
    vertices: ArrayLike
    faces: ArrayLike

class Error(RuntimeError):
    """A model file could not be loaded (or another failure of facet's own)."""

    code: str

class LoadWarning(UserWarning):
    """Recoverable trouble while loading (a missing texture, invalid triangles dropped)."""

class Scene:
    def __init__(self) -> None: ...
    @staticmethod
    def from_arrays(
        vertices: Union[ArrayLike, _MeshLike],
        faces: Optional[ArrayLike] = None,
        normals: Optional[ArrayLike] = None,
        colors: Optional[ArrayLike] = None,
        uvs: Optional[ArrayLike] = None,
        texture: Optional[ArrayLike] = None,
        transform: Optional[ArrayLike] = None,
        *,
        color: Optional[Colour] = None,
        crease_angle: Optional[float] = ...,
        points: Optional[ArrayLike] = None,
        lines: Optional[ArrayLike] = None,
    ) -> Scene: ...
    def add_mesh(
        self,
        vertices: Union[ArrayLike, _MeshLike],
        faces: Optional[ArrayLike] = None,
        normals: Optional[ArrayLike] = None,
        colors: Optional[ArrayLike] = None,
        uvs: Optional[ArrayLike] = None,
        texture: Optional[ArrayLike] = None,
        transform: Optional[ArrayLike] = None,
        *,
        color: Optional[Colour] = None,
        crease_angle: Optional[float] = ...,
        points: Optional[ArrayLike] = None,
        lines: Optional[ArrayLike] = None,
    ) -> int: ...
    @staticmethod
    def default() -> Scene: ...
    def __len__(self) -> int: ...
    @property
    def triangle_count(self) -> int: ...
    @property
    def warnings(self) -> list[str]: ...
    @property
    def bounds(self) -> Optional[npt.NDArray[np.float32]]: ...

class Camera:
    def __init__(self) -> None: ...
    @staticmethod
    def orbit(
        azimuth: float = ...,
        elevation: float = ...,
        *,
        distance: Optional[float] = None,
        fov_y: float = ...,
        near: Optional[float] = None,
        far: Optional[float] = None,
        orthographic: bool = False,
    ) -> Camera: ...
    @staticmethod
    def look_at(
        eye: Sequence[float],
        target: Optional[Sequence[float]] = None,
        up: Sequence[float] = (0, 1, 0),
        fov_y: float = ...,
        *,
        near: Optional[float] = None,
        far: Optional[float] = None,
        orthographic: bool = False,
    ) -> Camera: ...
    @staticmethod
    def from_intrinsics(
        K: ArrayLike,
        width: int,
        height: int,
        world_to_camera: ArrayLike,
        *,
        near: Optional[float] = None,
        far: Optional[float] = None,
    ) -> Camera: ...
    def resolve(self, scene: Optional[Scene] = None, width: int = ..., height: int = ...) -> Camera: ...
    @property
    def K(self) -> npt.NDArray[np.float64]: ...
    @property
    def world_to_camera(self) -> npt.NDArray[np.float64]: ...
    @property
    def camera_to_world(self) -> npt.NDArray[np.float64]: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def near(self) -> Optional[float]: ...
    @property
    def far(self) -> Optional[float]: ...

class Environment:
    def __init__(self, path: Union[str, os.PathLike[str]]) -> None: ...
    @property
    def path(self) -> str: ...

EnvironmentLike = Union[Environment, str, os.PathLike[str], None]

class Renderer:
    def __init__(self, threads: Optional[int] = None) -> None: ...
    def render(
        self,
        scene: Scene,
        camera: Union[Camera, Sequence[Camera]],
        width: int = ...,
        height: int = ...,
        *,
        passes: Sequence[PassName] = ("color",),
        shading: ShadingName = "lit",
        ssaa: int = ...,
        background: Union[Colour, Literal["transparent"], None] = None,
        normal_space: NormalSpace = "world",
        out: Optional[dict[str, np.ndarray]] = None,
        point_size: float = ...,
        point_shape: PointShape = "round",
        point_world_size: Optional[float] = None,
        line_width: float = ...,
        line_aa: bool = False,
        aa: int = ...,
        environment: EnvironmentLike = None,
        exposure: float = ...,
        tone_mapping: ToneMapping = "neutral",
        contact_shadow: float = ...,
    ) -> dict[str, np.ndarray]: ...
    @property
    def threads(self) -> int: ...
    @property
    def stats(self) -> dict[str, int]: ...

def load(
    path: Union[str, os.PathLike[str]],
    *,
    crease_angle: float = ...,
    up_axis: Literal["y", "z"] = "y",
    max_triangles: int = ...,
    max_texture_size: int = ...,
    threads: Optional[int] = None,
) -> Scene: ...
def load_isolated(
    path: Union[str, os.PathLike[str]],
    *,
    timeout: float = ...,
    max_memory: Optional[int] = None,
    crease_angle: float = ...,
    up_axis: Literal["y", "z"] = "y",
    max_triangles: int = ...,
    max_texture_size: int = ...,
    threads: Optional[int] = None,
) -> Scene: ...
def render(
    scene: Scene,
    camera: Union[Camera, Sequence[Camera]],
    width: int = ...,
    height: int = ...,
    *,
    passes: Sequence[PassName] = ("color",),
    shading: ShadingName = "lit",
    ssaa: int = ...,
    background: Union[Colour, Literal["transparent"], None] = None,
    normal_space: NormalSpace = "world",
    threads: Optional[int] = None,
    point_size: float = ...,
    point_shape: PointShape = "round",
    point_world_size: Optional[float] = None,
    line_width: float = ...,
    line_aa: bool = False,
    aa: int = ...,
    environment: EnvironmentLike = None,
    exposure: float = ...,
    tone_mapping: ToneMapping = "neutral",
    contact_shadow: float = ...,
) -> dict[str, np.ndarray]: ...
def write_png(path: Union[str, os.PathLike[str]], image: npt.NDArray[np.uint8]) -> None: ...
