"""The data-set job (smokescan.dataset) on a Dask LocalCluster of two worker processes, against
the same grid run serially: the same bytes, a failing cell reported while the others finish, a
worker killed in the middle of a cell retried without a partial or duplicated output."""
import filecmp
import glob
import os
import signal
import threading
import time

import pytest

from smokescan import dataset

GRID = """
scenes = ["plume"]
seeds = [1, 2]
[[timelines]]
name = "early"
t0 = 20.0
t1 = 21.0
[[timelines]]
name = "dense"
t0 = 20.0
t1 = 21.0
smoke_scale = 3.0
[[timelines]]
name = "backwards"
t0 = 30.0
t1 = 20.0
[[sensors]]
name = "lms200"
rate_hz = 5.0
[[sensors]]
name = "vlp16"
returns = "dual"
"""


def tree(folder):
    """Every file under folder, relative, with its bytes."""
    out = {}
    for root, _, files in os.walk(folder):
        for f in files:
            p = os.path.join(root, f)
            out[os.path.relpath(p, folder)] = open(p, "rb").read()
    return out


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    d = tmp_path_factory.mktemp("serial")
    (d / "grid.toml").write_text(GRID)
    assert dataset.main([str(d / "grid.toml"), str(d / "out"), "--serial"]) == 1  # some cells fail
    return d


def test_serial_run_writes_a_bag_a_cell_and_reports_the_failing_ones(serial):
    rows = list(open(serial / "out" / "index.csv"))[1:]
    assert len(rows) == 12
    failed = [r for r in rows if ",failed," in r]
    assert len(failed) == 4 and all("backwards" in r and "--to: must not precede --from" in r for r in failed)
    cells = sorted(os.listdir(serial / "out" / "cells"))
    assert len(cells) == 8 and all("backwards" not in c for c in cells)
    for c in cells:
        assert set(os.listdir(serial / "out" / "cells" / c)) == {c + "_0.mcap", "metadata.yaml"}
    # The denser smoke is another cell's bytes; the seeds are too.
    out = serial / "out" / "cells"
    assert not filecmp.cmp(out / "plume__early__vlp16__seed1" / "plume__early__vlp16__seed1_0.mcap",
                           out / "plume__dense__vlp16__seed1" / "plume__dense__vlp16__seed1_0.mcap", shallow=False)


def test_a_local_cluster_of_two_workers_gives_the_serial_runs_bytes(serial, tmp_path):
    (tmp_path / "grid.toml").write_text(GRID)
    assert dataset.main([str(tmp_path / "grid.toml"), str(tmp_path / "out"), "--workers", "2"]) == 1
    assert tree(tmp_path / "out") == tree(serial / "out")


def test_a_worker_killed_mid_cell_is_retried_and_leaves_one_whole_output(tmp_path):
    from dask.distributed import Client, LocalCluster
    grid = GRID.replace('t1 = 21.0\n[[timelines]]\nname = "dense"', 't1 = 24.0\n[[timelines]]\nname = "dense"')
    (tmp_path / "grid.toml").write_text(grid)
    assert dataset.main([str(tmp_path / "grid.toml"), str(tmp_path / "serial"), "--serial"]) == 1
    long_cell = "plume__early__vlp16__seed1"  # 41 frames of a VLP-16 in dual return
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    client = Client(cluster)
    killed = {}

    def kill_the_worker_in_the_long_cell():
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and not killed:
            if glob.glob(str(tmp_path / "out" / "cells" / (long_cell + ".tmp*"))):
                for worker, keys in client.processing().items():
                    if "cell-" + long_cell in keys:
                        pid = client.run(os.getpid, workers=[worker])[worker]
                        os.kill(pid, signal.SIGKILL)
                        killed["pid"] = pid
                        break
            time.sleep(0.01)

    try:
        killer = threading.Thread(target=kill_the_worker_in_the_long_cell)
        killer.start()
        rows = dataset.run_dataset(str(tmp_path / "grid.toml"), str(tmp_path / "out"), scheduler=cluster.scheduler_address)
        killer.join()
    finally:
        client.close()
        cluster.close()
    assert killed, "the long cell's worker was never caught in the middle of the cell"
    assert [r["status"] for r in rows].count("ok") == 8
    assert not glob.glob(str(tmp_path / "out" / "cells" / "*.tmp*"))  # no partial output
    assert sorted(os.listdir(tmp_path / "out" / "cells")) == sorted(os.listdir(tmp_path / "serial" / "cells"))
    assert tree(tmp_path / "out") == tree(tmp_path / "serial")


@pytest.mark.parametrize("text,message", [
    ("scenes = []\nseeds = [1]\ntimelines = []\nsensors = []", "scenes: empty"),
    ('scenes = ["plume"]\nseeds = [-1]\n[[timelines]]\nname="a"\nt0=0\nt1=1\n[[sensors]]\nname="lms200"',
     "seeds: each must be a whole number"),
    ('scenes = ["plume"]\nseeds = [1]\n[[timelines]]\nname="a"\nt0=0\n[[sensors]]\nname="lms200"',
     "timelines[0].t1: missing"),
    ('scenes = ["plume"]\nseeds = [1]\n[[timelines]]\nname="a"\nt0=0\nt1=1\nspeed=2\n[[sensors]]\nname="lms200"',
     "timelines[0].speed: unknown key"),
    ('scenes = ["plume"]\nseeds = [1]\ncolour = 3', "colour: unknown key"),
    ("scenes = [", "grid.toml: "),
])
def test_a_bad_grid_is_a_one_line_error_and_nothing_is_written(tmp_path, capsys, text, message):
    (tmp_path / "grid.toml").write_text(text)
    assert dataset.main([str(tmp_path / "grid.toml"), str(tmp_path / "out"), "--serial"]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err and err.startswith(str(tmp_path / "grid.toml"))
    assert not (tmp_path / "out").exists()
