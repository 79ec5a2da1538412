"""smokescan's data-set job on Dask: a grid of scenes x smoke timelines x seeds x sensors, one
ROS 2 bag per cell (smokescan.record_bag) and an index of the cells.

    python3 -m smokescan.dataset GRID.toml OUT [--scheduler ADDRESS] [--workers N] [--serial]

Each cell is one Dask task calling the module. Without --scheduler the job starts a LocalCluster
of N worker processes (default 2, one thread each); with it, it runs on that scheduler's workers,
which must import the same smokescan and see OUT at the same path (docs/python.md). --serial runs
the cells one after another in this process, without Dask.

GRID.toml (docs/python.md):

    scenes = ["plume", "rooms/lab.toml"]   # built-in names or scene files (relative to GRID.toml)
    seeds = [1, 2, 3]
    [[timelines]]                           # a span of the scene's own smoke, k times as dense
    name = "early"
    t0 = 20.0
    t1 = 30.0
    smoke_scale = 1.0                       # optional (1)
    [[sensors]]
    name = "lms200"                         # a scene's 2D laser (name or type) or a lidar preset
    rate_hz = 5.0                           # optional: scans (frames) a second
    returns = "dual"                        # optional, a lidar's return mode
    model = "physical"                      # optional, a 2D laser's model

OUT gets cells/CELL/ (one bag per cell: metadata.yaml and CELL_0.mcap, written whole or not at
all) and index.csv (one row per cell: its settings, status ok or failed, messages, readings and
the error). A cell's output depends only on its settings and seed: the same grid gives the same
bytes, serial or on any number of workers. A cell whose bag is already there is not run again
(a job can be resumed); a worker killed mid-cell leaves a temporary folder (CELL.tmpXXXXXX),
which the cell's next attempt removes. The exit status is 1 when a cell failed, 2 for a bad grid.
"""
import argparse
import csv
import functools
import glob
import io
import os
import re
import shutil
import sys
import tomllib

import smokescan

INDEX_FIELDS = ["cell", "scene", "timeline", "t0", "t1", "smoke_scale", "sensor", "rate_hz", "returns", "model",
                "seed", "status", "messages", "readings", "error"]
MAX_CELLS = 100_000


class GridError(Exception):
    """A grid file that cannot be run: its message names the file and the key."""


def _name_part(text):
    return re.sub(r"[^A-Za-z0-9.+-]+", "_", text).strip("_") or "x"


def read_grid(path):
    """The grid's cells, in order (scene, timeline, sensor, seed), each a dict of settings."""
    try:
        with open(path, "rb") as f:
            grid = tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError) as e:
        raise GridError(f"{path}: {e}") from None
    here = os.path.dirname(os.path.abspath(path))

    def need(table, key, kind, where):
        if key not in table:
            raise GridError(f"{path}: {where}{key}: missing")
        value = table[key]
        if not isinstance(value, kind) or isinstance(value, bool):
            raise GridError(f"{path}: {where}{key}: must be {kind.__name__ if isinstance(kind, type) else 'a number'}")
        return value

    known = {"scenes", "seeds", "timelines", "sensors"}
    for key in grid:
        if key not in known:
            raise GridError(f"{path}: {key}: unknown key (scenes, seeds, timelines, sensors)")
    scenes = need(grid, "scenes", list, "")
    seeds = need(grid, "seeds", list, "")
    timelines = need(grid, "timelines", list, "")
    sensors = need(grid, "sensors", list, "")
    for key, items in (("scenes", scenes), ("seeds", seeds), ("timelines", timelines), ("sensors", sensors)):
        if not items:
            raise GridError(f"{path}: {key}: empty")
    for s in scenes:
        if not isinstance(s, str) or not s:
            raise GridError(f"{path}: scenes: each must be a scene name or file")
    for s in seeds:
        if not isinstance(s, int) or isinstance(s, bool) or not 0 <= s < 2 ** 64:
            raise GridError(f"{path}: seeds: each must be a whole number from 0 to 18446744073709551615")
    cells_wanted = len(scenes) * len(seeds) * len(timelines) * len(sensors)
    if cells_wanted > MAX_CELLS:
        raise GridError(f"{path}: the grid has {cells_wanted} cells (at most {MAX_CELLS})")
    names = set()
    spans = []
    for i, t in enumerate(timelines):
        where = f"timelines[{i}]."
        if not isinstance(t, dict):
            raise GridError(f"{path}: timelines[{i}]: must be a table")
        for key in t:
            if key not in ("name", "t0", "t1", "smoke_scale"):
                raise GridError(f"{path}: {where}{key}: unknown key (name, t0, t1, smoke_scale)")
        name = need(t, "name", str, where)
        if name in names:
            raise GridError(f"{path}: {where}name: '{name}' twice")
        names.add(name)
        spans.append((name, float(need(t, "t0", (int, float), where)), float(need(t, "t1", (int, float), where)),
                      float(t.get("smoke_scale", 1.0))))
    kinds = []
    for i, s in enumerate(sensors):
        where = f"sensors[{i}]."
        if not isinstance(s, dict):
            raise GridError(f"{path}: sensors[{i}]: must be a table")
        for key in s:
            if key not in ("name", "rate_hz", "returns", "model"):
                raise GridError(f"{path}: {where}{key}: unknown key (name, rate_hz, returns, model)")
        kinds.append({"sensor": need(s, "name", str, where), "rate_hz": s.get("rate_hz"),
                      "returns": s.get("returns"), "model": s.get("model")})
    cells, ids = [], set()
    for scene in scenes:
        scene_path = scene if scene in smokescan.builtin_scenes() else os.path.join(here, scene)
        stem = os.path.splitext(os.path.basename(scene))[0]
        for name, t0, t1, k in spans:
            for kind in kinds:
                for seed in seeds:
                    cell = "__".join(_name_part(x) for x in (stem, name, kind["sensor"], f"seed{seed}"))
                    if cell in ids:
                        raise GridError(f"{path}: two cells would be named {cell} (scenes with the same file name?)")
                    ids.add(cell)
                    cells.append(dict(cell=cell, scene=scene_path, timeline=name, t0=t0, t1=t1, smoke_scale=k,
                                      seed=seed, **kind))
    return cells


@functools.lru_cache(maxsize=8)
def _scene(path, smoke_scale):
    scene = smokescan.load_scene(path)
    return scene if smoke_scale == 1.0 else scene.with_smoke_scale(smoke_scale)


def run_cell(cell, out):
    """One cell: its bag in OUT/cells/CELL, whole or not at all. Returns the cell's index row."""
    row = dict(cell, status="ok", messages=0, readings=0, error="")
    folder = os.path.join(out, "cells", cell["cell"])
    if os.path.exists(os.path.join(folder, "metadata.yaml")):  # done by an earlier attempt or run
        row["status"] = "done before"
        return row
    for stale in glob.glob(glob.escape(folder) + ".tmp*"):  # a killed attempt's temporary
        shutil.rmtree(stale, ignore_errors=True)
    if os.path.isdir(folder) and not os.listdir(folder):
        os.rmdir(folder)
    try:
        scene = _scene(cell["scene"], cell["smoke_scale"])
        done = smokescan.record_bag(scene, folder, sensor=cell["sensor"], t0=cell["t0"], t1=cell["t1"],
                                    rate_hz=cell["rate_hz"], seed=cell["seed"], returns=cell["returns"],
                                    model=cell["model"])
        row.update(done)
    except smokescan.Error as e:
        row.update(status="failed", error=str(e))
    return row


def write_index(out, rows):
    """index.csv, written whole (a temporary renamed into place)."""
    text = io.StringIO()
    w = csv.DictWriter(text, fieldnames=INDEX_FIELDS, lineterminator="\n", extrasaction="ignore")
    w.writeheader()
    for r in rows:
        w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in INDEX_FIELDS})
    tmp = os.path.join(out, ".index.csv.tmp")
    with open(tmp, "w") as f:
        f.write(text.getvalue())
    os.replace(tmp, os.path.join(out, "index.csv"))


def run_dataset(grid_path, out, scheduler=None, workers=2, serial=False, report=None):
    """Runs every cell of the grid into OUT; returns the index rows (in the grid's order)."""
    cells = read_grid(grid_path)
    os.makedirs(os.path.join(out, "cells"), exist_ok=True)
    report = report or (lambda row, done, total: None)
    rows = [None] * len(cells)
    if serial:
        for i, c in enumerate(cells):
            rows[i] = run_cell(c, out)
            report(rows[i], i + 1, len(cells))
    else:
        from dask.distributed import Client, LocalCluster, as_completed
        cluster = None
        if scheduler:
            client = Client(scheduler)
        else:
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None)
            client = Client(cluster)
        try:
            futures = client.map(run_cell, cells, out=os.path.abspath(out), key=["cell-" + c["cell"] for c in cells],
                                 pure=False)
            where = {f.key: i for i, f in enumerate(futures)}
            for n, f in enumerate(as_completed(futures), 1):
                i = where[f.key]
                try:
                    rows[i] = f.result()
                except Exception as e:  # the task itself failed (e.g. its workers kept dying)
                    rows[i] = dict(cells[i], status="failed", messages=0, readings=0,
                                   error=f"{type(e).__name__}: {e}".replace("\n", " "))
                report(rows[i], n, len(cells))
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
    write_index(out, rows)
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python3 -m smokescan.dataset", description=__doc__.split("\n\n")[0])
    ap.add_argument("grid", help="the grid (TOML)")
    ap.add_argument("out", help="the output folder (cells/ and index.csv)")
    ap.add_argument("--scheduler", help="a Dask scheduler's address (default: a LocalCluster)")
    ap.add_argument("--workers", type=int, default=2, help="the LocalCluster's worker processes (default 2)")
    ap.add_argument("--serial", action="store_true", help="run the cells here, one after another, without Dask")
    a = ap.parse_args(argv)
    if not 1 <= a.workers <= 256:
        print(f"--workers: must lie in 1...256, got {a.workers}", file=sys.stderr)
        return 2

    def report(row, done, total):
        print(f"[{done}/{total}] {row['cell']}: {row['status']}"
              + (f" ({row['error']})" if row["error"] else ""), file=sys.stderr)

    try:
        rows = run_dataset(a.grid, a.out, a.scheduler, a.workers, a.serial, report)
    except GridError as e:
        print(str(e), file=sys.stderr)
        return 2
    failed = sum(r["status"] == "failed" for r in rows)
    print(f"wrote {a.out}: {len(rows) - failed} of {len(rows)} cells, index.csv")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
