"""Type stub of the mgelastic module (python/*.cpp): shapes and units in docs/python.md."""

from os import PathLike
from typing import Any, Callable, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

class Error(RuntimeError):
    """An error of the library; the message is what the `mgelastic` CLI prints after 'error: '."""

class SceneError(Error, ValueError):
    """An invalid scene: the message names the file and the JSON pointer of the bad value."""

def rotation(axis: Sequence[float], degrees: float) -> npt.NDArray[np.float64]:
    """The 3x3 matrix of a rotation by `degrees` about `axis`."""

class Scene:
    """A validated scene (docs/scene-format.md), defaults filled in."""
    @staticmethod
    def load(path: Union[str, PathLike[str]]) -> Scene: ...
    @staticmethod
    def from_dict(document: dict[str, Any], name: str = "<dict>",
                  directory: Union[str, PathLike[str]] = ".") -> Scene: ...
    def to_dict(self) -> dict[str, Any]: ...
    @property
    def file(self) -> str: ...
    @property
    def directory(self) -> str: ...
    @property
    def engine(self) -> str: ...
    @property
    def frames(self) -> int: ...
    @property
    def dt(self) -> float: ...
    @property
    def quasistatic(self) -> bool: ...
    @property
    def constraints(self) -> int: ...

class StepStats:
    cycles: int
    relative_residual: float
    quasi_linear_reduction: float
    quasi_linear_residual: float
    converged: bool
    stalled: bool
    seconds: float

class FrameStats:
    frame: int
    time: float
    steps: int
    cycles: int
    worst_residual: float
    converged: bool
    solve_seconds: float
    rotate_seconds: float
    assemble_seconds: float
    step_stats: list[StepStats]

class Simulation:
    """A simulation of one scene; frame k shows time (k + 1) dt. Field arrays are read-only
    live views refreshed after every step."""
    def __init__(self, scene: Scene, threads: int = 0) -> None: ...
    @staticmethod
    def resume(scene: Scene, path: Union[str, PathLike[str]], threads: int = 0) -> Simulation: ...
    def step(self) -> FrameStats: ...
    def advance_to(self, time: float) -> None: ...
    def run(self, frames: Optional[int] = None,
            callback: Optional[Callable[[Simulation, FrameStats], Optional[bool]]] = None) -> None: ...
    def save(self, path: Union[str, PathLike[str]]) -> None: ...
    def set_region_pose(self, region: int, translate: Sequence[float] = (0.0, 0.0, 0.0),
                        rotate: Optional[npt.ArrayLike] = None) -> None: ...
    def set_traction(self, index: int, traction: Sequence[float]) -> None:
        """loads.tractions[index] applies `traction` (Pa) from the next step on."""
    def set_pressure(self, index: int, pressure: float) -> None:
        """loads.pressures[index] applies `pressure` (Pa, inward) from the next step on."""
    def set_force(self, index: int, force: Sequence[float]) -> None:
        """loads.forces[index] applies the total `force` (N) from the next step on."""
    def displacement(self) -> npt.NDArray[np.float64]:
        """grid: (nx+1, ny+1, nz+1, 3); tet: (N, 3); m."""
    def velocity(self) -> npt.NDArray[np.float64]:
        """as displacement, m/s."""
    def pressure(self) -> npt.NDArray[np.float64]:
        """grid only: (nx, ny, nz), Pa."""
    def von_mises(self) -> npt.NDArray[np.float64]:
        """grid: (nx, ny, nz); tet: (T,); Pa."""
    def cell_types(self) -> npt.NDArray[np.uint8]:
        """grid only: (nx, ny, nz)."""
    def positions(self) -> npt.NDArray[np.float64]:
        """tet only: (N, 3), m."""
    def surface(self) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int32]]:
        """(vertices (V, 3) m, triangles (T, 3))."""
    @property
    def stats(self) -> FrameStats: ...
    @property
    def frame(self) -> int: ...
    @property
    def frames(self) -> int: ...
    @property
    def time(self) -> float: ...
    @property
    def engine(self) -> str: ...
    @property
    def scene(self) -> Scene: ...
    @property
    def cells(self) -> Tuple[int, int, int]: ...
    @property
    def spacing(self) -> float: ...
    @property
    def origin(self) -> npt.NDArray[np.float64]: ...
