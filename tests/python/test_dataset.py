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
[[sensors]]
name = "lms200"
rate_hz = 5.0
[[sensors]]
name = "vlp16"
returns = "dual"
[[sensors]]
name = "sick2"
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
    assert len(failed) == 4 and all("sick2" in r and "no sensor named or of type 'sick2'" in r for r in failed)
    cells = sorted(c for c in os.listdir(serial / "out" / "cells") if not c.endswith(".json"))
    assert len(cells) == 8 and all("sick2" not in c for c in cells)
    for c in cells:
        assert (serial / "out" / "cells" / (c + ".json")).exists()
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
    killed, finished = {}, threading.Event()

    def kill_the_worker_in_the_long_cell():
        while not finished.is_set() and not killed:
            if glob.glob(str(tmp_path / "out" / "cells" / (long_cell + ".tmp*"))):
                for worker, keys in client.processing().items():
                    if any(str(k).startswith("cell-" + long_cell + "-") for k in keys):
                        pid = client.run(os.getpid, workers=[worker])[worker]
                        os.kill(pid, signal.SIGKILL)
                        killed["pid"] = pid
                        break
            time.sleep(0.01)

    try:
        killer = threading.Thread(target=kill_the_worker_in_the_long_cell)
        killer.start()
        rows = dataset.run_dataset(str(tmp_path / "grid.toml"), str(tmp_path / "out"), scheduler=cluster.scheduler_address)
        finished.set()
        killer.join()
    finally:
        client.close()
        cluster.close()
    assert killed, "the long cell's worker was never caught in the middle of the cell"
    assert [r["status"] for r in rows].count("ok") == 8
    assert not glob.glob(str(tmp_path / "out" / "cells" / "*.tmp*"))  # no partial output
    assert sorted(os.listdir(tmp_path / "out" / "cells")) == sorted(os.listdir(tmp_path / "serial" / "cells"))
    assert tree(tmp_path / "out") == tree(tmp_path / "serial")


def test_a_job_started_as_a_module_runs_on_a_schedulers_own_workers(serial, tmp_path):
    """`python3 -m smokescan.dataset --scheduler ADDR`, as the docs say for several machines: the
    workers, started apart from the job, import the cell's code by its module's name."""
    import subprocess
    import sys
    from dask.distributed import LocalCluster
    (tmp_path / "grid.toml").write_text(GRID)
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        done = subprocess.run([sys.executable, "-m", "smokescan.dataset", str(tmp_path / "grid.toml"),
                               str(tmp_path / "out"), "--scheduler", cluster.scheduler_address],
                              capture_output=True, text=True, timeout=300)
    assert done.returncode == 1, done.stderr[-2000:]  # the four failing cells
    assert tree(tmp_path / "out") == tree(serial / "out")


def test_a_resumed_job_keeps_what_is_done_and_refuses_other_settings_under_a_name(serial, tmp_path):
    import shutil
    shutil.copytree(serial / "out", tmp_path / "out")
    (tmp_path / "grid.toml").write_text(GRID)
    assert dataset.main([str(tmp_path / "grid.toml"), str(tmp_path / "out"), "--serial"]) == 1
    rows = [r.split(",") for r in open(tmp_path / "out" / "index.csv")][1:]
    done = [r for r in rows if r[11] == "done before"]
    assert len(done) == 8 and all(int(r[12]) > 0 and int(r[13]) > 0 for r in done)  # counts kept
    (tmp_path / "grid.toml").write_text(GRID.replace("rate_hz = 5.0", "rate_hz = 2.0"))
    assert dataset.main([str(tmp_path / "grid.toml"), str(tmp_path / "out"), "--serial"]) == 1
    text = open(tmp_path / "out" / "index.csv").read()
    assert text.count("with other settings (rate_hz)") == 4  # the LMS200's cells of two timelines, two seeds
    assert tree(tmp_path / "out" / "cells") == tree(serial / "out" / "cells")  # nothing replaced


def test_one_job_at_a_time_in_an_output_folder(tmp_path, capsys):
    import fcntl
    (tmp_path / "grid.toml").write_text(GRID)
    os.makedirs(tmp_path / "out")
    with open(tmp_path / "out" / ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        assert dataset.main([str(tmp_path / "grid.toml"), str(tmp_path / "out"), "--serial"]) == 2
    assert "another job is writing there" in capsys.readouterr().err
    assert sorted(os.listdir(tmp_path / "out")) == [".lock", "cells"]
    assert os.listdir(tmp_path / "out" / "cells") == []


@pytest.mark.parametrize("args,message", [
    (["--serial", "--scheduler", "tcp://127.0.0.1:1"], "--serial: runs without Dask"),
    (["--scheduler", "tcp://nowhere"], "--scheduler tcp://nowhere: cannot connect"),
    (["--workers", "0"], "--workers: must lie in 1...256"),
])
def test_bad_options_are_one_line_errors_and_nothing_is_written(tmp_path, capsys, args, message):
    (tmp_path / "grid.toml").write_text(GRID)
    assert dataset.main([str(tmp_path / "grid.toml"), str(tmp_path / "out"), *args]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(message) and "\n" not in err
    assert not (tmp_path / "out").exists()


def test_an_output_that_is_a_file_is_refused(tmp_path, capsys):
    (tmp_path / "grid.toml").write_text(GRID)
    (tmp_path / "out").write_text("mine")
    assert dataset.main([str(tmp_path / "grid.toml"), str(tmp_path / "out"), "--serial"]) == 2
    assert "exists and is not a folder" in capsys.readouterr().err
    assert (tmp_path / "out").read_text() == "mine"


ONE = 'scenes = ["plume"]\nseeds = [1]\n[[timelines]]\nname="a"\nt0=0\nt1=1\n[[sensors]]\nname="lms200"\n'


@pytest.mark.parametrize("text,message", [
    (ONE.replace("t0=0", "t0=nan"), "timelines[0].t0: must be a finite number"),
    (ONE.replace("t0=0", "t0=-1"), "timelines[0].t0: must be >= 0"),
    (ONE.replace("t1=1", "t1=-inf"), "timelines[0].t1: must be a finite number"),
    (ONE.replace("t0=0", "t0=2"), "timelines[0].t1: must not precede t0"),
    (ONE.replace("t1=1", 't1=1\nsmoke_scale="x"'), "timelines[0].smoke_scale: must be a finite number"),
    (ONE.replace("t1=1", "t1=1\nsmoke_scale=-2"), "timelines[0].smoke_scale: must be >= 0"),
    (ONE + "rate_hz = true", "sensors[0].rate_hz: must be a finite number"),
    (ONE + "rate_hz = 0", "sensors[0].rate_hz: must be > 0"),
    (ONE + "returns = 2", "sensors[0].returns: must be a string"),
    (ONE.replace('name="a"', 'name=""'), "timelines[0].name: must be a non-empty name"),
    (ONE + '[[sensors]]\nname="lms200"\nrate_hz=2', "two cells would be named plume__a__lms200__seed1"),

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
