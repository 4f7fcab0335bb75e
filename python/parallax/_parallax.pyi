# Type stubs of the compiled module parallax._parallax (python/src/*.cpp).
from os import PathLike
from typing import Any, Callable, Iterator, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

Triple = Tuple[float, float, float]

class InputError(ValueError): ...

class Vlr:
    @property
    def user_id(self) -> str: ...
    @property
    def record_id(self) -> int: ...
    @property
    def description(self) -> str: ...
    @property
    def extended(self) -> bool: ...
    @property
    def data(self) -> bytes: ...
    @property
    def data_size(self) -> int: ...

class PointCloud:
    def __len__(self) -> int: ...
    @property
    def count(self) -> int: ...
    @property
    def columns(self) -> list[str]: ...
    def keys(self) -> list[str]: ...
    def __contains__(self, name: str) -> bool: ...
    def __getitem__(self, name: str) -> npt.NDArray[np.generic]: ...
    def __setitem__(self, name: str, value: npt.ArrayLike) -> None: ...
    def raw(self, name: str) -> npt.NDArray[np.generic]: ...
    def to_dict(self) -> dict[str, npt.NDArray[np.generic]]: ...
    @property
    def scale(self) -> Triple: ...
    @property
    def offset(self) -> Triple: ...
    @property
    def bounds(self) -> Tuple[Triple, Triple]: ...
    @property
    def path(self) -> Optional[str]: ...
    @property
    def format(self) -> Optional[str]: ...
    @property
    def crs_wkt(self) -> Optional[str]: ...
    @property
    def crs(self) -> str: ...
    @property
    def point_format(self) -> Optional[int]: ...
    @property
    def las_version(self) -> Optional[str]: ...
    @property
    def vlrs(self) -> list[Vlr]: ...

class ChunkReader(Iterator[PointCloud]):
    def __iter__(self) -> ChunkReader: ...
    def __next__(self) -> PointCloud: ...
    @property
    def point_count(self) -> int: ...
    @property
    def scale(self) -> Triple: ...
    @property
    def offset(self) -> Triple: ...

def read(
    path: str,
    columns: Optional[Sequence[str]] = None,
    *,
    text_columns: Sequence[str] = (),
    parallel: bool = True,
    classes: Optional[Sequence[int]] = None,
    returns: Optional[Sequence[Union[str, int]]] = None,
    intensity: Optional[Tuple[float, float]] = None,
    elevation: Optional[Tuple[float, float]] = None,
    gps_time: Optional[Tuple[float, float]] = None,
    clip_box: Optional[Sequence[float]] = None,
    clip_polygon: Optional[Sequence[Tuple[float, float]]] = None,
    clip_mode: str = "inside",
    progress: Optional[Callable[[int, Optional[int]], object]] = None,
) -> PointCloud: ...
def read_header(path: str) -> dict[str, object]: ...
def read_chunks(
    path: str, *, points: int = 1000000, text_columns: Sequence[str] = ()
) -> ChunkReader: ...
def write(
    path: Union[str, PathLike[str]],
    points: Union[PointCloud, Mapping[str, npt.ArrayLike]],
    *,
    ascii: bool = False,
    las_version: Optional[str] = None,
    point_format: int = -1,
    laz_chunk_points: int = 50000,
    pcd_data: str = "binary",
    properties: Sequence[str] = (),
    scale: Optional[Triple] = None,
    offset: Optional[Triple] = None,
) -> None: ...

class OctreeNode:
    @property
    def name(self) -> str: ...
    @property
    def level(self) -> int: ...
    @property
    def bounds(self) -> Tuple[Triple, Triple]: ...
    @property
    def spacing(self) -> float: ...
    @property
    def point_count(self) -> int: ...
    @property
    def child_mask(self) -> int: ...

class Octree:
    def __len__(self) -> int: ...
    @property
    def path(self) -> str: ...
    @property
    def format(self) -> str: ...
    @property
    def point_count(self) -> int: ...
    @property
    def bounds(self) -> Tuple[Triple, Triple]: ...
    @property
    def cube(self) -> Tuple[Triple, Triple]: ...
    @property
    def spacing(self) -> float: ...
    @property
    def scale(self) -> Triple: ...
    @property
    def offset(self) -> Triple: ...
    @property
    def attributes(self) -> list[str]: ...
    def nodes(self) -> list[OctreeNode]: ...
    @property
    def level_point_counts(self) -> list[int]: ...
    @property
    def levels(self) -> int: ...
    def query(
        self,
        *,
        box: Optional[Sequence[float]] = None,
        polygon: Optional[Sequence[Tuple[float, float]]] = None,
        level: Optional[int] = None,
        spacing: Optional[float] = None,
        classes: Optional[Sequence[int]] = None,
        returns: Optional[Sequence[Union[str, int]]] = None,
        intensity: Optional[Tuple[float, float]] = None,
        elevation: Optional[Tuple[float, float]] = None,
        gps_time: Optional[Tuple[float, float]] = None,
        clip_mode: str = "inside",
        progress: Optional[Callable[[int, int], object]] = None,
        report: Optional[dict[str, int]] = None,
    ) -> PointCloud: ...

def open_octree(path: str) -> Octree: ...
def network_stats() -> dict[str, int]: ...

# render and pick take `parallax render`'s options as keyword arguments, with _ for -, and its
# defaults: width=1280, height=720, eye, target, up, fov, ortho, camera, stereo, eye_separation,
# convergence, swap_eyes, color, color_ramp, color_range, point_size, size_mode, shape,
# world_size, adaptive_scale, uniform_color, background, lighting, edl, edl_strength,
# edl_radius, msaa, rasterizer, hq, classes, returns, intensity, elevation, gps_time, clip_box,
# clip_polygon (a polygon file), clip_mode, preview, budget, min_node_size, cache_dir, no_cache,
# memory; pick also radius.
def render(
    source: Union[str, PathLike[str], PointCloud],
    *,
    width: int = 1280,
    height: int = 720,
    **options: Any,
) -> npt.NDArray[np.uint8]: ...
def pick(
    source: Union[str, PathLike[str], PointCloud],
    pixel: Tuple[int, int],
    *,
    width: int = 1280,
    height: int = 720,
    radius: int = 3,
    **options: Any,
) -> dict[str, Any]: ...

# convert and process run the commands in this process; keyword arguments are their options with
# _ for - (True for a switch), e.g. format="potree", sampling="random", point_format=7,
# clip_box=(...), memory=2048; process's steps run in the order given.
PathArg = Union[str, PathLike[str]]

def convert(
    src: Union[PathArg, Sequence[PathArg]],
    dst: PathArg,
    *,
    progress: Optional[Callable[..., object]] = None,
    **options: Any,
) -> None: ...
def process(
    src: Union[PathArg, Sequence[PathArg]],
    dst: PathArg,
    *,
    steps: Union[Sequence[Tuple[str, Any]], Mapping[str, Any]] = (),
    progress: Optional[Callable[..., object]] = None,
    **options: Any,
) -> None: ...
