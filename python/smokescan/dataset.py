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
    label = "lms200_5hz"                    # optional: the cells' name for it (default: name)
    rate_hz = 5.0                           # optional: scans (frames) a second
    returns = "dual"                        # optional, a lidar's return mode
    model = "physical"                      # optional, a 2D laser's model

OUT gets cells/CELL/ (one bag per cell: metadata.yaml and CELL_0.mcap, written whole or not at
all), cells/CELL.json (the cell's settings and counts, once its bag is whole) and index.csv (one
row per cell: its settings, status ok, done before, failed or not run, messages, readings and
the error). A cell's output depends only on its settings and seed: the same grid gives the same
bytes, serial or on any number of workers. A cell whose bag and settings are already there is not
run again (a job can be resumed; other settings under the same name are a failed cell); a worker
killed mid-cell leaves a temporary folder (CELL.tmpXXXXXX), which the cell's next attempt
removes. One job at a time in an OUT (a lock). The exit status is 1 when a cell failed or did
not run, 2 for a bad grid, OUT or scheduler (one line; nothing written), 130 on Ctrl-C (the index
then says which cells ran).
"""
import argparse
import contextlib
import csv
import fcntl
import functools
import glob
import hashlib
import io
import json
import math
import os
import re
import shutil
import sys
import tomllib

import smokescan

INDEX_FIELDS = ["cell", "scene", "timeline", "t0", "t1", "smoke_scale", "sensor", "rate_hz", "returns", "model",
                "seed", "status", "messages", "readings", "error"]
SETTINGS = ["scene", "timeline", "t0", "t1", "smoke_scale", "sensor", "rate_hz", "returns", "model", "seed"]
MAX_CELLS = 100_000
WORKERS_WAIT_S = 60


class GridError(Exception):
    """A grid, OUT or scheduler the job cannot use: its message is one line naming it."""


def _name_part(text):
    return re.sub(r"[^A-Za-z0-9+-]+", "_", text).strip("_") or "x"


def _table(path, item, where, keys):
    """A [[timelines]] or [[sensors]] entry: a table of known keys."""
    if not isinstance(item, dict):
        raise GridError(f"{path}: {where}: must be a table")
    for key in item:
        if key not in keys:
            raise GridError(f"{path}: {where}.{key}: unknown key ({', '.join(keys)})")
    return item


def _value(path, table, key, where, kind, default=None, required=False):
    """table[key] checked: kind "name" (a non-empty string), "number" (finite), "text"."""
    if key not in table:
        if required:
            raise GridError(f"{path}: {where}{key}: missing")
        return default
    v = table[key]
    if kind == "number":
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise GridError(f"{path}: {where}{key}: must be a finite number")
        return float(v)
    if not isinstance(v, str) or (kind == "name" and not v.strip()):
        raise GridError(f"{path}: {where}{key}: must be a " + ("non-empty name" if kind == "name" else "string"))
    return v


def _list(path, grid, key):
    if key not in grid:
        raise GridError(f"{path}: {key}: missing")
    if not isinstance(grid[key], list):
        raise GridError(f"{path}: {key}: must be a list")
    if not grid[key]:
        raise GridError(f"{path}: {key}: empty")
    return grid[key]


def read_grid(path):
    """The grid's cells, in order (scene, timeline, sensor, seed), each a dict of settings."""
    try:
        with open(path, "rb") as f:
            grid = tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError) as e:
        raise GridError(f"{path}: {e}") from None
    here = os.path.dirname(os.path.abspath(path))
    for key in grid:
        if key not in ("scenes", "seeds", "timelines", "sensors"):
            raise GridError(f"{path}: {key}: unknown key (scenes, seeds, timelines, sensors)")
    scenes, seeds = _list(path, grid, "scenes"), _list(path, grid, "seeds")
    timelines, sensors = _list(path, grid, "timelines"), _list(path, grid, "sensors")
    for s in scenes:
        if not isinstance(s, str) or not s.strip():
            raise GridError(f"{path}: scenes: each must be a scene name or file")
    for s in seeds:
        if not isinstance(s, int) or isinstance(s, bool) or not 0 <= s < 2 ** 64:
            raise GridError(f"{path}: seeds: each must be a whole number from 0 to 18446744073709551615")
    cells_wanted = len(scenes) * len(seeds) * len(timelines) * len(sensors)
    if cells_wanted > MAX_CELLS:
        raise GridError(f"{path}: the grid has {cells_wanted} cells (at most {MAX_CELLS})")
    spans = []
    for i, t in enumerate(timelines):
        where = f"timelines[{i}]"
        t = _table(path, t, where, ("name", "t0", "t1", "smoke_scale"))
        where += "."
        span = dict(timeline=_value(path, t, "name", where, "name", required=True),
                    t0=_value(path, t, "t0", where, "number", required=True),
                    t1=_value(path, t, "t1", where, "number", required=True),
                    smoke_scale=_value(path, t, "smoke_scale", where, "number", 1.0))
        if span["t0"] < 0:
            raise GridError(f"{path}: {where}t0: must be >= 0 (a bag's stamps start at 0)")
        if span["t1"] < span["t0"]:
            raise GridError(f"{path}: {where}t1: must not precede t0")
        if span["smoke_scale"] < 0:
            raise GridError(f"{path}: {where}smoke_scale: must be >= 0")
        spans.append(span)
    kinds = []
    for i, s in enumerate(sensors):
        where = f"sensors[{i}]"
        s = _table(path, s, where, ("name", "label", "rate_hz", "returns", "model"))
        where += "."
        kind = dict(sensor=_value(path, s, "name", where, "name", required=True),
                    rate_hz=_value(path, s, "rate_hz", where, "number"),
                    returns=_value(path, s, "returns", where, "text"), model=_value(path, s, "model", where, "text"))
        if kind["rate_hz"] is not None and not kind["rate_hz"] > 0:
            raise GridError(f"{path}: {where}rate_hz: must be > 0")
        kind["label"] = _value(path, s, "label", where, "name", kind["sensor"])
        kinds.append(kind)
    cells, ids = [], {}
    for scene in scenes:
        scene_path = scene if scene in smokescan.builtin_scenes() else os.path.join(here, scene)
        stem = os.path.splitext(os.path.basename(scene))[0]
        for span in spans:
            for kind in kinds:
                for seed in seeds:
                    cell = "__".join(_name_part(x) for x in (stem, span["timeline"], kind["label"], f"seed{seed}"))
                    if len(cell) > 200:
                        raise GridError(f"{path}: the cell name {cell[:40]}... is over 200 bytes (shorter names)")
                    if cell in ids:
                        raise GridError(f"{path}: two cells would be named {cell}: give scenes different file names, "
                                        "and timelines, sensors (label) and seeds different values")
                    ids[cell] = True
                    c = dict(cell=cell, scene=scene, seed=seed, **span, **kind)
                    c["scene_path"] = scene_path
                    cells.append(c)
    return cells


@functools.lru_cache(maxsize=8)
def _scene(path, smoke_scale):
    scene = smokescan.load_scene(path)
    return scene if smoke_scale == 1.0 else scene.with_smoke_scale(smoke_scale)


def _write_whole(path, text):
    """A small file written whole: a temporary beside it renamed into place."""
    tmp = path + ".part"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def run_cell(cell, out):
    """One cell: its bag in OUT/cells/CELL, whole or not at all, then CELL.json (its settings and
    counts). Returns the cell's index row."""
    row = dict(cell, status="ok", messages=0, readings=0, error="")
    folder = os.path.join(out, "cells", cell["cell"])
    record = folder + ".json"
    settings = {k: cell[k] for k in SETTINGS}
    if os.path.exists(record) and os.path.exists(os.path.join(folder, "metadata.yaml")):
        with open(record) as f:
            before = json.load(f)
        if before.get("settings") != settings:
            changed = [k for k in SETTINGS if before.get("settings", {}).get(k) != settings[k]]
            row.update(status="failed", error=f"{folder} holds this cell with other settings ({', '.join(changed)}); "
                                              "remove it or write to another OUT")
            return row
        row.update(status="done before", messages=before["messages"], readings=before["readings"])
        return row
    for stale in glob.glob(glob.escape(folder) + ".tmp*"):  # a killed attempt's temporary
        shutil.rmtree(stale, ignore_errors=True)
    if os.path.isdir(folder):  # a bag whose settings were never recorded (killed in between): again
        shutil.rmtree(folder)
    try:
        scene = _scene(cell["scene_path"], cell["smoke_scale"])
        done = smokescan.record_bag(scene, folder, sensor=cell["sensor"], t0=cell["t0"], t1=cell["t1"],
                                    rate_hz=cell["rate_hz"], seed=cell["seed"], returns=cell["returns"],
                                    model=cell["model"])
    except Exception as e:  # a cell's failure is its row's, never the job's
        row.update(status="failed", error=str(e).replace("\n", " ") if isinstance(e, smokescan.Error)
                   else f"{type(e).__name__}: {e}".replace("\n", " "))
        return row
    row.update(done)
    _write_whole(record, json.dumps(dict(settings=settings, **done), sort_keys=True) + "\n")
    return row


def write_index(out, rows):
    """index.csv, written whole (a temporary renamed into place)."""
    text = io.StringIO()
    w = csv.DictWriter(text, fieldnames=INDEX_FIELDS, lineterminator="\n", extrasaction="ignore")
    w.writeheader()
    for r in rows:
        w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in INDEX_FIELDS})
    _write_whole(os.path.join(out, "index.csv"), text.getvalue())


def _task_key(cell, out):
    """Unique to this OUT and these settings: two jobs on one scheduler never share a result."""
    digest = hashlib.sha1(json.dumps([os.path.abspath(out), cell], sort_keys=True).encode()).hexdigest()[:16]
    return f"cell-{cell['cell']}-{digest}"


def _connect(scheduler, workers):
    """A Dask client: to the scheduler's address, or to a new LocalCluster. One-line errors."""
    from dask.distributed import Client, LocalCluster
    if scheduler:
        try:
            client = Client(scheduler, timeout="20s")
        except (OSError, ValueError, TypeError) as e:
            raise GridError(f"--scheduler {scheduler}: cannot connect ({e})".replace("\n", " ")) from None
        try:
            client.wait_for_workers(1, timeout=WORKERS_WAIT_S)
        except Exception:
            client.close()
            raise GridError(f"--scheduler {scheduler}: no worker joined within {WORKERS_WAIT_S} s") from None
        return client, None
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None)
    return Client(cluster), cluster


@contextlib.contextmanager
def _locked(out):
    """OUT made (or taken) for this job alone."""
    if not out:
        raise GridError("OUT: must name a folder")
    if os.path.exists(out) and not os.path.isdir(out):
        raise GridError(f"{out}: exists and is not a folder")
    try:
        os.makedirs(os.path.join(out, "cells"), exist_ok=True)
        lock = open(os.path.join(out, ".lock"), "w")
    except OSError as e:
        raise GridError(f"{out}: cannot write ({e.strerror})") from None
    try:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        lock.close()
        raise GridError(f"{out}: another job is writing there") from None
    try:
        yield
    finally:
        lock.close()


def run_dataset(grid_path, out, scheduler=None, workers=2, serial=False, report=None):
    """Runs every cell of the grid into OUT; returns the index rows (in the grid's order). The
    index is written however the job ends (a cell not run says so)."""
    from smokescan.dataset import run_cell as task  # by its module's name, also under `python3 -m`: workers import it
    cells = read_grid(grid_path)
    if serial and scheduler:
        raise GridError("--serial: runs without Dask; it takes no --scheduler")
    report = report or (lambda row, done, total: None)
    rows = [None] * len(cells)
    client, cluster = (None, None) if serial else _connect(scheduler, workers)
    try:
        with _locked(out):
            try:
                if serial:
                    for i, c in enumerate(cells):
                        rows[i] = task(c, out)
                        report(rows[i], i + 1, len(cells))
                else:
                    from dask.distributed import as_completed
                    futures = client.map(task, cells, out=os.path.abspath(out), key=[_task_key(c, out) for c in cells],
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
                write_index(out, [r or dict(c, status="not run", messages="", readings="", error="")
                                  for r, c in zip(rows, cells)])
    finally:
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
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
    except KeyboardInterrupt:
        print(f"interrupted: {a.out}/index.csv says which cells ran", file=sys.stderr)
        return 130
    bad = sum(r["status"] == "failed" for r in rows)
    print(f"wrote {a.out}: {len(rows) - bad} of {len(rows)} cells, index.csv")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
