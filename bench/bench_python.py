"""The Python module's overhead: the same runs through Python and through the C++ library
(build/smokescan_bench_pipeline) in the same session, medians of 5. Usage, from the repository:
    PYTHONPATH=build/python /usr/bin/python3 bench/bench_python.py [build]"""
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import smokescan
from smokescan import dataset


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build"
    reps = 5
    scene = smokescan.load_scene("plume")

    def median_s(f):
        t = []
        for _ in range(reps):
            t0 = time.perf_counter()
            f()
            t.append(time.perf_counter() - t0)
        return statistics.median(t)

    def laser():
        return smokescan.scan(scene, "lms200", t0=20, t1=30, rate_hz=10)

    def lidar():
        return smokescan.scan_lidar(scene, "vlp16", returns="dual", t0=20, t1=21)

    rows = len(laser())
    points = sum(len(f["points"]) for f in lidar())
    py = {"laser": median_s(laser), "lidar": median_s(lidar)}
    out = subprocess.run([f"{build}/smokescan_bench_pipeline", str(reps)], check=True, capture_output=True, text=True)
    cpp = {k: float(v) for k, v in (line.split() for line in out.stdout.splitlines())}
    print("| run | through Python [s] | through the C++ library [s] | overhead |")
    print("|---|---|---|---|")
    what = {"laser": f"LMS200, 101 scans ({rows} rows)", "lidar": f"VLP-16 dual, 11 frames ({points} points)"}
    for k in ("laser", "lidar"):
        print(f"| {what[k]} | {py[k]:.4f} | {cpp[k]:.4f} | {100 * (py[k] / cpp[k] - 1):+.1f} % |")

    # The data-set job's throughput: the same grid (2 scenes' spans x 2 sensors x 4 seeds = 16 cells)
    # serially, on a LocalCluster of 1 worker and of 2.
    grid = """
scenes = ["plume"]
seeds = [1, 2, 3, 4]
[[timelines]]
name = "early"
t0 = 20.0
t1 = 22.0
[[timelines]]
name = "dense"
t0 = 20.0
t1 = 22.0
smoke_scale = 3.0
[[sensors]]
name = "lms200"
rate_hz = 10.0
[[sensors]]
name = "vlp16"
returns = "dual"
"""
    print("\n| data-set job, 16 cells | s | cells/s |\n|---|---|---|")
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "grid.toml")
        open(path, "w").write(grid)
        for what, kw in (("serial (no Dask)", dict(serial=True)), ("LocalCluster, 1 worker", dict(workers=1)),
                         ("LocalCluster, 2 workers", dict(workers=2))):
            out = os.path.join(d, "out")
            t0 = time.perf_counter()
            rows = dataset.run_dataset(path, out, **kw)
            s = time.perf_counter() - t0
            assert all(r["status"] == "ok" for r in rows)
            shutil.rmtree(out)
            print(f"| {what} | {s:.2f} | {len(rows) / s:.2f} |")


if __name__ == "__main__":  # the cluster's worker processes import this file
    main()
