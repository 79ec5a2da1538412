"""smokescan from Python: laser range finders, 3D lidars and cameras simulated in smoke.

    import smokescan
    scene = smokescan.load_scene("plume")
    rows = smokescan.scan(scene, sensor="lms200", t0=20, t1=21, rate_hz=5)
    rows["range_m"]          # metres, NaN where the laser reported an error code

Long calls release the GIL, report progress to `progress(done, total)` and stop on Ctrl-C
(KeyboardInterrupt). Errors are smokescan.Error with the library's one-line message.
"""
from ._report import Report
from ._smokescan import (Error, Scene, __version__, builtin_scenes, calibrate, diagnose, diagnose_lidar, fit,
                         fit_lidar, fit_plume, load_scene, omnirange, read_volume, record_bag, render, saturation,
                         scan, scan_lidar, write_volume)

__all__ = [
    "Error", "Report", "Scene", "__version__", "builtin_scenes", "calibrate", "diagnose", "diagnose_lidar", "fit",
    "fit_lidar", "fit_plume",
    "load_scene", "omnirange", "read_volume", "record_bag", "render", "saturation", "scan", "scan_lidar",
    "write_volume"
]
