"""The Python module against the command line and its own promises (run by ctest: Python.Pytest,
with PYTHONPATH at the built module and SMOKESCAN_CLI the built command)."""
import os
import signal
import subprocess
import threading

import numpy as np
import pytest

import smokescan

CLI = os.environ.get("SMOKESCAN_CLI", "smokescan")


def cli(*args):
    subprocess.run([CLI, *args], check=True, stdout=subprocess.DEVNULL)


def read_log(path):
    """The laser log's scans: (time_s, angles, values in mm)."""
    out = []
    for line in open(path):
        if line.startswith("#"):
            continue
        f = line.split()
        out.append((float(f[0]), np.array(f[1::2], float), np.array(f[2::2], np.int64)))
    return out


def read_pcd(path):
    """A binary PCD's points as a structured array, by its own header (an independent reader)."""
    data = open(path, "rb").read()
    fields = sizes = types = None
    pos = 0
    while True:
        end = data.index(b"\n", pos)
        words = data[pos:end].decode().split()
        pos = end + 1
        if words[0] == "FIELDS":
            fields = words[1:]
        elif words[0] == "SIZE":
            sizes = [int(w) for w in words[1:]]
        elif words[0] == "TYPE":
            types = words[1:]
        elif words[0] == "DATA":
            assert words[1] == "binary"
            break
    kind = {"F": "f", "U": "u", "I": "i"}
    dtype = np.dtype([(f, f"<{kind[t]}{s}") for f, s, t in zip(fields, sizes, types)])
    return np.frombuffer(data[pos:], dtype=dtype)


@pytest.fixture(scope="module")
def plume():
    return smokescan.load_scene("plume")


def test_a_scene_is_loaded_and_looked_at(plume):
    assert "plume" in smokescan.builtin_scenes()
    assert plume.source == "builtin:plume"
    assert plume.sensors == [("sick", "lms200"), ("hokuyo", "urg04lx")]
    assert len(plume.surfaces) > 0 and len(plume.volumes) == 6
    assert plume.t_end_s > plume.t_start_s
    with pytest.raises(smokescan.Error, match=r"^no-such\.toml: "):
        smokescan.load_scene("no-such.toml")


@pytest.mark.parametrize("sensor,model", [("lms200", "paper"), ("urg04lx", "physical")])
def test_scans_are_the_command_lines_for_the_same_seed(plume, tmp_path, sensor, model):
    log = tmp_path / "scan.log"
    cli("scan", "plume", "--sensor", sensor, "--model", model, "--from", "20", "--to", "22", "--rate", "5",
        "--seed", "7", "--out", str(log), "--quiet")
    rows = smokescan.scan(plume, sensor=sensor, model=model, t0=20, t1=22, rate_hz=5, seed=7)
    scans = read_log(log)
    n = len(scans[0][1])
    assert rows.shape == (len(scans) * n,)
    for k, (t, angles, values_mm) in enumerate(scans):
        r = rows[k * n:(k + 1) * n]
        assert np.all(r["time_s"] == pytest.approx(t, abs=5e-4))
        assert np.all(r["beam"] == np.arange(n))
        np.testing.assert_allclose(r["angle_rad"], angles, atol=5e-7)
        np.testing.assert_array_equal(r["value"], values_mm)  # both sensors report millimetres here
    # Errors are codes, their range NaN; the rest are ranges in metres.
    err = rows["error"]
    assert np.all(np.isnan(rows["range_m"][err]))
    np.testing.assert_allclose(rows["range_m"][~err], rows["value"][~err] * 1e-3)
    if model == "physical":
        assert err.any() and (~err).any()  # the smoke at 20 s makes the URG err on some beams


def quaternion_matrix(w, x, y, z):
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def test_lidar_frames_are_the_command_lines_points_and_poses(tmp_path):
    """On a robot that moves (the maze): points field by field as the CLI's PCD files, each
    frame's times and start and end poses as its frames.csv, the range image as the first
    returns' ranges."""
    maze = smokescan.load_scene("maze")
    cli("scan", "maze", "--sensor", "vlp16", "--returns", "dual", "--from", "2", "--to", "2.1", "--seed", "3",
        "--points", str(tmp_path / "pts"))
    frames = smokescan.scan_lidar(maze, "vlp16", returns="dual", t0=2, t1=2.1, seed=3)
    index = np.genfromtxt(tmp_path / "pts" / "frames.csv", delimiter=",", names=True, dtype=None, encoding=None)
    assert len(frames) == len(index) == 2
    for k, (f, row) in enumerate(zip(frames, index)):
        assert f["index"] == k
        assert f["start_s"] == row["start_s"] and f["end_s"] == pytest.approx(row["end_s"], abs=1e-12)
        for which in ("start", "end"):
            pose = f[which + "_pose"]
            t = [row[f"{which}_{a}_m"] for a in "xyz"]
            q = [row[f"{which}_q{a}"] for a in "wxyz"]
            np.testing.assert_allclose(pose[:3, 3], t, atol=1e-12)
            np.testing.assert_allclose(pose[:3, :3], quaternion_matrix(*q), atol=1e-12)
            np.testing.assert_array_equal(pose[3], [0, 0, 0, 1])
        assert not np.allclose(f["start_pose"], f["end_pose"])  # the robot moved during the frame
        p = f["points"]
        theirs = read_pcd(tmp_path / "pts" / f"{k:06d}.pcd")
        assert len(theirs) == len(p) > 1000
        for name in ("x", "y", "z", "intensity", "ring", "return_index", "source"):
            np.testing.assert_array_equal(p[name], theirs[name], err_msg=name)
        np.testing.assert_array_equal(p["time_s"], theirs["time"])
        np.testing.assert_allclose(np.sqrt(p["x"] ** 2 + p["y"] ** 2 + p["z"] ** 2), p["range_m"], rtol=1e-5)
        image, first = f["range_image"], p[p["return_index"] == 0]
        assert image.shape == (16, 1808)
        np.testing.assert_array_equal(image[first["ring"], first["beam"] // 16], first["range_m"])
        assert (image > 0).sum() == len(first)


def test_lidar_points_are_the_librarys_own_memory(plume):
    """numpy holds the points the library made (a capsule owns them), and they stay valid after
    every other reference to the frame is gone."""
    import gc
    frames = smokescan.scan_lidar(plume, "vlp16", t0=20, seed=3)
    p = frames[0]["points"]
    assert not p.flags.owndata and type(p.base).__name__ == "PyCapsule"
    copy = p.copy()
    del frames
    gc.collect()
    for _ in range(3):
        smokescan.scan_lidar(plume, "vlp16", t0=20, seed=4)  # reuse the freed memory
    assert p.tobytes() == copy.tobytes()


def test_the_same_seed_gives_the_same_arrays_and_another_does_not(plume):
    a = smokescan.scan(plume, sensor="urg04lx", t0=20, t1=21, rate_hz=4, seed=5)
    b = smokescan.scan(plume, sensor="urg04lx", t0=20, t1=21, rate_hz=4, seed=5)
    c = smokescan.scan(plume, sensor="urg04lx", t0=20, t1=21, rate_hz=4, seed=6)
    assert a.tobytes() == b.tobytes()
    assert a.tobytes() != c.tobytes()


@pytest.mark.parametrize("call,message", [
    (lambda s: smokescan.scan(s, sensor="nope"), r"no sensor named or of type 'nope'"),
    (lambda s: smokescan.scan(s, model="magic"), r"^--model: unknown sensor model 'magic' \(paper, physical\)"),
    (lambda s: smokescan.scan(s, t0=float("nan"), t1=1), r"^--from: must be a finite number"),
    (lambda s: smokescan.scan(s, t0=0, t1=float("inf")), r"^--to: must be a finite number"),
    (lambda s: smokescan.scan(s, penetration_power=-1), r"^--penetration-power: "),
    (lambda s: smokescan.scan(s, seed=-1), r"^--seed: is not a seed"),
    (lambda s: smokescan.scan(s, seed=2 ** 64), r"^--seed: is not a seed"),
    (lambda s: smokescan.scan_lidar(s, t0=float("inf")), r"^--from: must be a finite number"),
    (lambda s: smokescan.scan_lidar(s, rate_hz=-10), r"^--rate: "),
    (lambda s: smokescan.scan_lidar(s, columns=-5), r"^--columns: "),
    (lambda s: smokescan.scan_lidar(s, columns=2 ** 40), r"^--columns: "),
    (lambda s: smokescan.scan(s, t0=30, t1=20), r"^--to: must not precede --from"),
    (lambda s: smokescan.scan(s, rate_hz=-1), r"^--rate: "),
    (lambda s: smokescan.scan(s, t0=0, t1=150, rate_hz=1000), r"^--to: .* \(at most 50000000"),
    (lambda s: smokescan.scan_lidar(s, "vlp17"), r"vlp17"),
    (lambda s: smokescan.scan_lidar(s, returns="bogus"), r"^--returns: unknown return mode 'bogus'"),
    (lambda s: smokescan.scan_lidar(s, returns=""), r"^--returns: unknown return mode ''"),
    (lambda s: smokescan.scan_lidar(s, "os1-128", returns="dual", t0=0, t1=100), r"^--to: .* points in memory"),
    (lambda s: smokescan.scan_lidar(s, columns=7), r"column"),
])
def test_bad_settings_are_one_line_errors(plume, call, message):
    with pytest.raises(smokescan.Error, match=message) as e:
        call(plume)
    assert "\n" not in str(e.value)
    assert isinstance(e.value, RuntimeError)


def test_wrong_types_are_type_errors(plume):
    for call in (lambda: smokescan.scan(None), lambda: smokescan.scan_lidar(None),
                 lambda: smokescan.record_bag(None, "x"), lambda: smokescan.scan(plume, progress=3)):
        with pytest.raises(TypeError):
            call()


def test_progress_is_reported_and_a_callbacks_exception_stops_the_run(plume):
    seen = []
    smokescan.scan_lidar(plume, "vlp16", t0=20, t1=20.3, progress=lambda done, total: seen.append((done, total)))
    assert seen == [(1, 4), (2, 4), (3, 4), (4, 4)]

    calls = []

    def fail(done, total):
        calls.append(done)
        raise ValueError("stop at %d" % done)

    with pytest.raises(ValueError, match="stop at 1"):
        smokescan.scan(plume, t0=0, t1=10, progress=fail)
    assert calls == [1]


def test_ctrl_c_interrupts_a_long_call(plume):
    """Ctrl-C while the library works: the call stops before its next scan. The progress callable
    is a builtin (no Python runs in it, so only the library's own check can see the signal)."""
    done, sent = {}, {}

    def ctrl_c():
        sent["at"] = done.get("n", 0)
        os.kill(os.getpid(), signal.SIGINT)

    timer = threading.Timer(0.3, ctrl_c)
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        smokescan.scan(plume, t0=0, t1=149.9, rate_hz=10, progress=lambda d, t, set=done.__setitem__: set("n", d))
    timer.join()
    assert done["n"] <= sent["at"] + 1 and done["n"] < 1500, (done, sent)


def test_a_call_lets_other_threads_run(plume):
    """While a call works in one thread, the main thread runs Python: it ticks hundreds of times
    (a call that held the GIL would let it tick only before and after)."""
    worker = threading.Thread(target=lambda: smokescan.scan_lidar(plume, "vlp16", t0=20, t1=20.5, seed=1))
    import time
    ticks = 0
    worker.start()
    while worker.is_alive():
        ticks += 1
        time.sleep(0.001)
    worker.join()
    assert ticks >= 30, ticks


def test_two_threads_scan_at_once(plume):
    """Two threads' calls at once each get what a lone call gets."""
    alone = smokescan.scan_lidar(plume, "vlp16", t0=20, t1=20.5, seed=11)
    results = {}
    start = threading.Barrier(2)

    def work(name):
        start.wait()
        results[name] = smokescan.scan_lidar(plume, "vlp16", t0=20, t1=20.5, seed=11)

    threads = [threading.Thread(target=work, args=(n,)) for n in "ab"]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for name in "ab":
        assert len(results[name]) == len(alone) == 6
        for f, g in zip(results[name], alone):
            assert f["points"].tobytes() == g["points"].tobytes()


def readme_block(fence, after):
    """The first code block fenced `fence` after the line `after` in README.md."""
    text = open(os.path.join(os.path.dirname(__file__), "..", "..", "README.md")).read()
    rest = text[text.index(after):]
    start = rest.index("```" + fence + "\n") + len(fence) + 4
    return rest[start:rest.index("```", start)]


def test_the_readmes_python_section_runs_as_written(tmp_path):
    """Its first block installs the module into a prefix (here a fresh one), its second runs
    there with Debian's python3, and prints a line a scan."""
    build = os.path.dirname(os.path.dirname(smokescan.__file__))  # build/python
    setup = readme_block("sh", "## Python").replace("build", os.path.dirname(build))
    env = dict(os.environ, HOME=str(tmp_path))
    env.pop("PYTHONPATH", None)
    example = readme_block("python", "## Python")
    script = setup + '\n/usr/bin/python3 - <<"EOF"\n' + example + "EOF\n"
    out = subprocess.run(["bash", "-euo", "pipefail", "-c", script], env=env, check=True, capture_output=True,
                         text=True, cwd=tmp_path).stdout
    lines = out.strip().splitlines()
    assert len(lines) == 11 and all("361 beams, nearest" in line for line in lines), out
    assert (tmp_path / ".local" / "lib" / "python3" / "dist-packages" / "smokescan" / "__init__.pyi").exists()
