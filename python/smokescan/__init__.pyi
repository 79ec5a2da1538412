"""Type stubs of the smokescan module (its compiled part is smokescan._smokescan)."""
from typing import Callable, Dict, List, Optional, Tuple, Any

import numpy as np
import numpy.typing as npt

__version__: str

class Error(RuntimeError):
    """A bad input or setting, with the library's one-line message (the file or option, then the problem)."""

class Scene:
    """A scene: surfaces, sensors, cameras and smoke over time (docs/scene-format.md)."""
    @property
    def source(self) -> str: ...
    @property
    def t_start_s(self) -> float: ...
    @property
    def t_end_s(self) -> float: ...
    def with_smoke_scale(self, k: float) -> "Scene":
        """A copy whose smoke is k times as dense at every time (k >= 0)."""
    @property
    def sensors(self) -> List[Tuple[str, str]]: ...
    @property
    def surfaces(self) -> List[str]: ...
    @property
    def cameras(self) -> List[str]: ...
    @property
    def volumes(self) -> List[str]: ...

def load_scene(name_or_path: str) -> Scene:
    """A built-in scene by name (builtin_scenes()) or a scene file (.toml)."""

def builtin_scenes() -> List[str]: ...

def scan(
    scene: Scene,
    sensor: str = "",
    t0: Optional[float] = None,
    t1: Optional[float] = None,
    rate_hz: float = 1.0,
    seed: int = 1,
    model: Optional[str] = None,
    sensor_file: str = "",
    penetration_power: float = 0.0,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> npt.NDArray[np.void]:
    """A 2D laser's scans (the scene's sensor by name or type; "" = the first) from t0 to t1 at
    rate_hz; without t1 up to the scene's end. One row per beam and scan, fields: time_s (f8, s), angle_rad (f8), range_m (f8, m;
    NaN for an error value), value (i8, as the sensor reports it: a range in its unit or an error
    code), beam (i4), error (bool). The same rows as `smokescan scan --out` for the same seed."""

def record_bag(
    scene: Scene,
    path: str,
    sensor: str = "",
    t0: Optional[float] = None,
    t1: Optional[float] = None,
    rate_hz: Optional[float] = None,
    seed: int = 1,
    returns: Optional[str] = None,
    model: Optional[str] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Dict[str, int]:
    """Records a scan run as a ROS 2 bag in the new folder `path` (docs/bags.md): a scene's 2D
    laser as scan() makes it, or a 3D lidar preset as scan_lidar() does. The folder appears whole
    or not at all. Returns {"messages": scans or frames, "readings": beams or points}."""

def scan_lidar(
    scene: Scene,
    sensor: str = "vlp16",
    returns: Optional[str] = None,
    rate_hz: float = 0.0,
    columns: int = 0,
    t0: Optional[float] = None,
    t1: Optional[float] = None,
    seed: int = 1,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> List[Dict[str, Any]]:
    """A 3D lidar's frames (vlp16, hdl32e, os1-128 or a preset file) on the scene's default lidar
    mount, frames starting from t0 (default: the scene's start) up to t1 (default: one frame).
    Each frame a dict: index, start_s, end_s, start_pose and end_pose (4×4, world from sensor),
    range_image (channels × columns float32, 0 = none; None for a pattern file) and points, a
    structured array without a copy: x, y, z, range_m, intensity (f4; m, calibrated reflectivity
    %), ring (u2), return_index (u1), source (u1: 0 surface, 1 smoke, 2 mirror), time_s (f4, from
    the frame's start), beam (u4)."""
