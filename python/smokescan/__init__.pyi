"""Type stubs of the smokescan module (its compiled part is smokescan._smokescan)."""
import os
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

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

PathLike = Union[str, "os.PathLike[str]"]

class Report:
    """A JSON report's object (diagnose, calibrate): its keys as attributes and items; nested
    objects are Reports. to_dict() gives the parsed JSON (NaN as None)."""
    def __getattr__(self, name: str) -> Any: ...
    def __getitem__(self, name: str) -> Any: ...
    def keys(self) -> Any: ...
    def to_dict(self) -> Dict[str, Any]: ...

def render(
    scene: Scene,
    time_s: float = 0.0,
    camera: str = "",
    width: int = 0,
    height: int = 0,
    spp: int = 16,
    seed: int = 1,
    max_depth: int = 256,
    exposure: Optional[float] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Dict[str, Any]:
    """One frame of a scene camera (default: the first; width/height 0 = the camera's) at time_s
    through the smoke, as `smokescan render` makes it. A dict: radiance and variance (H×W×3
    float32, linear [W/(m²·sr)]), display (H×W×3 float32, sRGB-encoded in [0, 1] at the exposure
    used; exposure None = auto metering), object_id and material_id (H×W int32, −1 = none),
    depth_m (H×W float32, inf = none), exposure, camera, time_s, samples, seconds.
    progress(done, total) counts 16×16-pixel tiles."""

def calibrate(
    scene: Scene,
    *,
    densities: Optional[List[float]] = None,
    spp: int = 8,
    rel_error: float = 0.03,
    max_batches: int = 16,
    width: int = 320,
    height: int = 240,
    seed: int = 1,
    camera: str = "",
    target_prefix: str = "target_",
    loss: str = "huber",
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Report:
    """`smokescan calibrate`: the density-saturation curve (the smoke paper's Fig. 7) from the
    scene's own frames, fitted with Ceres; a Report with the calibration JSON's fields
    (docs/calibration.md). json.dump(report.to_dict(), f) writes a calibration fit and diagnose read."""

def diagnose_lidar(
    scene: PathLike,
    *,
    points: PathLike,
    sensor: str,
    returns: str = "",
    columns: int = 0,
    rate_hz: float = 0.0,
    alpha: float = 0.05,
    out: Optional[PathLike] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Report:
    """`smokescan diagnose --points`: a 3D lidar's recorded frames (a folder as scan --points writes
    it) against their replay in the scene (docs/diagnosis.md, "A 3D lidar's frames"); a Report with
    diagnosis.json's fields. out= also writes diagnosis.json and report.md, whole or not at all."""

def fit_lidar(
    scene: PathLike,
    *,
    points: PathLike,
    sensor: str,
    returns: str = "",
    columns: int = 0,
    rate_hz: float = 0.0,
    out: Optional[PathLike] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Report:
    """`smokescan fit --points`: each surface's reflectance factor from a 3D lidar's recorded
    intensities against their replay in the scene, and the receiver's noise (docs/lidar.md,
    "Fitted from the intensities"); a Report with the fit report's fields. out= also writes the
    preset extended by the factors (extended_preset), whole or not at all."""

def diagnose(
    scene: PathLike,
    *,
    laser: Optional[PathLike] = None,
    bag: Optional[PathLike] = None,
    topic: str = "",
    saturation: Optional[PathLike] = None,
    calibration: PathLike = "bocas",
    patch: str = "",
    sensor: str = "",
    sensor_type: str = "urg04lx",
    sensor_file: Optional[PathLike] = None,
    model: Optional[str] = None,
    unit: str = "mm",
    lenient: bool = False,
    offset_s: Optional[float] = None,
    block_s: float = 3.0,
    smoke_shape: str = "reference",
    camera: str = "",
    target_prefix: str = "target_",
    alpha: float = 0.05,
    max_findings: int = 4,
    seed: int = 1,
    out: Optional[PathLike] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Report:
    """`smokescan diagnose`: a recorded run replayed in the scene (file or built-in name), what
    the simulation gets wrong, the cause and the extended model's held-out gain; a Report with
    diagnosis.json's fields (docs/diagnosis.md). out= also writes the command's folder
    (diagnosis.json, report.md, sensor.toml), whole or not at all."""

def read_volume(path: PathLike, grid: str = "density", scale: float = 1.0) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.float64]]:
    """A scalar grid of a .vdb file as (density, index_to_world): float32 over the box of its
    non-zero voxels; density[a, b, c] is the voxel whose centre is index_to_world @ (a, b, c, 1) [m]."""

def write_volume(path: PathLike, density: npt.ArrayLike, index_to_world: npt.ArrayLike, grid: str = "density") -> None:
    """Writes a 3-D array of densities (finite, >= 0) as an OpenVDB grid in a new .vdb file
    (atomically); index_to_world is a 4×4 affine map whose voxels are cubes."""

def fit(
    scene: Optional[PathLike] = None,
    *,
    laser: Optional[PathLike] = None,
    bag: Optional[PathLike] = None,
    topic: str = "",
    saturation: Optional[PathLike] = None,
    calibration: PathLike = "bocas",
    patch: str = "",
    sensor: str = "",
    sensor_type: str = "urg04lx",
    target_prefix: str = "target_",
    surfaces: List[str] = ...,
    surfaces_file: Optional[PathLike] = None,
    model: str = "paper",
    unit: str = "mm",
    lenient: bool = False,
    offset_s: float = 0.0,
    fixed_offset: bool = False,
    offset_window_s: float = 60.0,
    link: str = "probit",
    smooth_s: float = 2.0,
    bootstrap: int = 30,
    reference: str = "",
    image_topic: str = "",
    rects: List[str] = ...,
    polygons: List[str] = ...,
    out: Optional[PathLike] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Report:
    """`smokescan fit`: the sensor's smoke thresholds, penetration power and clock offset from a
    recorded run and the camera's saturation; a Report with the fit report's fields
    (docs/fitting.md). out= writes the fitted sensor file (a new file). No threshold fitted:
    smokescan.Error with the reason."""

def fit_plume(
    scene: PathLike,
    *,
    laser: Optional[PathLike] = None,
    bag: Optional[PathLike] = None,
    topic: str = "",
    sensor: str = "",
    unit: str = "mm",
    lenient: bool = False,
    time_offset_s: float = 0.0,
    bins: int = 8,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Report:
    """`smokescan fit-plume`: a Sick LMS200's penetration into the scene's plumes; a Report with
    the command's JSON fields."""

def saturation(
    frames: Union[PathLike, List[PathLike], None] = None,
    *,
    bag: Optional[PathLike] = None,
    topic: str = "",
    rects: List[str] = ...,
    polygons: List[str] = ...,
    ids: Optional[PathLike] = None,
    scene: Optional[PathLike] = None,
    target_prefix: str = "target_",
    timestamps: Optional[PathLike] = None,
    fps: float = 0.0,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Dict[str, Any]:
    """`smokescan saturation`: the target's HSV saturation on camera frames (files or folders,
    or bag=): time_s, saturation, median, sd, pixels (float64 arrays) and patches, patch_median,
    patch_sd (dicts of arrays by patch name)."""

def omnirange(
    scene: Scene,
    *,
    train: Optional[List[float]] = None,
    histogram: Optional[PathLike] = None,
    t0: Optional[float] = None,
    t1: Optional[float] = None,
    rate_hz: float = 1.0,
    seed: int = 1,
    spp: int = 8,
    camera: str = "",
    laser: str = "",
    threshold: float = 0.05,
    n_behind: int = 20,
    k_free: int = 2,
    scanlines: int = 360,
    min_range_m: float = 0.3,
    max_range_m: float = 3.8,
    outlier_m: float = 1.25,
    floor_z_m: float = 0.0,
    exposure: float = 0.0,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> Dict[str, Any]:
    """`smokescan omnirange`: the omni camera as a colour-based rangefinder beside the scene's
    laser. time_s (F), angle_rad (S), range_m and status (F×S), laser_angle_rad (B),
    laser_range_m and laser_value (F×B), comparison, exposure, trained_pixels."""
