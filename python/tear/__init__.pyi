"""Type hints of the `tear` package (docs/python.md)."""

import os
from typing import Any, Iterator, Literal, Mapping, Optional, Sequence, Tuple, TypedDict, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str

PathLike = Union[str, "os.PathLike[str]"]
Device = str  # "auto", "cpu", "cuda" or "cuda:N"
Space = Literal["uv", "rest-xy", "rest-xz", "rest-yz"]

class Error(Exception):
    exit_code: int

class UsageError(Error, ValueError): ...
class BadInput(Error): ...
class RuntimeFailure(Error): ...
class Interrupted(Error): ...

class Mesh:
    """A mesh on the host; its arrays are read-only views of its buffers (no copy)."""

    @property
    def node_count(self) -> int: ...
    @property
    def face_count(self) -> int: ...
    @property
    def source(self) -> str: ...
    @property
    def points(self) -> npt.NDArray[np.float32]:
        """(nodes, 3) positions, metres."""
    @property
    def faces(self) -> npt.NDArray[np.int32]:
        """(faces, 3) node indices, counter-clockwise."""
    @property
    def uvs(self) -> Optional[npt.NDArray[np.float32]]:
        """(faces, 3, 2) per-corner UVs, or None."""
    @property
    def normals(self) -> Optional[npt.NDArray[np.float32]]:
        """(faces, 3, 3) per-corner normals, or None."""
    @property
    def velocities(self) -> Optional[npt.NDArray[np.float32]]:
        """(nodes, 3) velocities, m/s, or None for a mesh read without them."""
    @property
    def ids(self) -> npt.NDArray[np.int32]:
        """(nodes,) persistent node ids (node i is id i)."""
    @property
    def origins(self) -> Optional[npt.NDArray[np.int32]]:
        """(nodes,) the face of the mesh as read each node lies in, or None."""
    @property
    def origin_weights(self) -> Optional[npt.NDArray[np.float32]]:
        """(nodes, 2) barycentric weights of the origin face's 2nd and 3rd corner, or None."""
    @property
    def torn_edges(self) -> npt.NDArray[np.int32]:
        """(edges, 2) node pairs of the borders cuts and tears made."""
    def write(self, path: PathLike, *, up_axis: Optional[str] = None, meters_per_unit: Optional[float] = None) -> None: ...
    def __dlpack__(self, **kwargs: Any) -> Any: ...
    def __dlpack_device__(self) -> Tuple[int, int]: ...

class Frame(Mesh):
    """One frame of a run: the mesh `tear run` writes for it."""

    @property
    def number(self) -> int:
        """The frame's number in outputs (start_frame + script frame - 1)."""
    @property
    def script_frame(self) -> int: ...
    @property
    def cut_count(self) -> int: ...
    @property
    def tear_events(self) -> int: ...
    @property
    def torn_length(self) -> float: ...

class FrameIterator(Iterator[Frame]):
    frame_count: int
    start_frame: int
    def __iter__(self) -> "FrameIterator": ...
    def __next__(self) -> Frame: ...
    def __len__(self) -> int: ...

class Script:
    def __init__(self, data: Union[Mapping[str, Any], str], *, name: str = "script") -> None: ...
    @classmethod
    def load(cls, path: PathLike) -> "Script": ...
    @property
    def frames(self) -> int: ...
    @property
    def snap(self) -> float: ...
    @property
    def version(self) -> int: ...
    @property
    def path(self) -> str: ...
    @property
    def cut_count(self) -> int: ...
    @property
    def simulated(self) -> bool: ...
    @property
    def fps(self) -> float: ...

class RunSummary(TypedDict):
    frames: int
    faces: int
    wall_ms: float

class CutResult(TypedDict):
    nodes_before: int
    nodes_after: int
    faces_before: int
    faces_after: int
    ms: float

def cuda_available() -> bool: ...
def read_mesh(path: PathLike, *, weld_tolerance: float = 0.0, mesh_name: Optional[str] = None, weld: bool = True,
              device: Device = "auto") -> Mesh: ...

@overload
def run(mesh: Union[Mesh, PathLike], script: Union[Script, Mapping[str, Any], PathLike], *, device: Device = "auto",
        start_frame: int = 1, frames: Optional[int] = None, output: None = None) -> FrameIterator:
    """The frames of the run, one by one, each the mesh `tear run` writes for it."""
@overload
def run(mesh: Union[Mesh, PathLike], script: Union[Script, Mapping[str, Any], PathLike], *, device: Device = "auto",
        start_frame: int = 1, frames: Optional[int] = None, output: PathLike,
        report: Optional[PathLike] = None, up_axis: Optional[str] = None, meters_per_unit: Optional[float] = None,
        checkpoint: Optional[PathLike] = None, checkpoint_every: int = 1, resume: bool = False,
        writer_threads: int = 0) -> RunSummary:
    """The whole run written to `output`, exactly as `tear run -o OUTPUT` writes it."""

class DeviceArray:
    shape: Tuple[int, int]
    dtype: str
    def __dlpack__(self, *, stream: Any = None, max_version: Any = None, dl_device: Any = None,
                   copy: Optional[bool] = None) -> Any: ...
    def __dlpack_device__(self) -> Tuple[int, int]: ...
    def __array__(self, dtype: Any = None, copy: Optional[bool] = None) -> Any: ...

class Cloth:
    def __init__(self, mesh: Union[Mesh, PathLike], *, device: Device = "auto",
                 script: Union[Script, Mapping[str, Any], PathLike, None] = None) -> None: ...
    @property
    def node_count(self) -> int: ...
    @property
    def face_count(self) -> int: ...
    @property
    def device(self) -> str: ...
    @property
    def simulated(self) -> bool: ...
    def cut(self, polyline: Sequence[Sequence[float]], *, space: Space = "rest-xy", snap: float = 0.2) -> CutResult: ...
    def step(self, frames: int = 1) -> None: ...
    def mesh(self) -> Mesh: ...
    @property
    def positions(self) -> DeviceArray: ...
    def set_positions(self, points: Any) -> None: ...
