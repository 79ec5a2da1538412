"""The module's render, calibrate and diagnose against the command line's outputs for the same
inputs, and their promises: progress, Ctrl-C, one-line errors (run by ctest: Python.Pytest)."""
import json
import math
import os
import pathlib
import signal
import subprocess
import sys
import threading
import tomllib

import numpy as np
import pytest

import smokescan

CLI = os.environ.get("SMOKESCAN_CLI", "smokescan")


def cli(*args):
    subprocess.run([CLI, *args], check=True, stdout=subprocess.DEVNULL)


def read_png(path):
    """An 8-bit image read by Open3D (an independent reader), as an H×W×3 uint8 array."""
    code = ("import sys, numpy as np, open3d as o3d\n"
            "np.save(sys.argv[2], np.asarray(o3d.io.read_image(sys.argv[1])))\n")
    out = str(path) + ".npy"
    subprocess.run([sys.executable, "-c", code, str(path), out], check=True)
    return np.load(out)


@pytest.fixture(scope="module")
def bocas():
    return smokescan.load_scene("bocas")


def test_a_rendered_frame_is_the_command_lines(bocas, tmp_path):
    png = tmp_path / "f.png"
    cli("render", "bocas", "--time", "60", "--spp", "4", "--width", "80", "--height", "60", "--seed", "5", "--out",
        str(png))
    f = smokescan.render(bocas, time_s=60, spp=4, width=80, height=60, seed=5)
    for name in ("radiance", "variance", "display"):
        assert f[name].shape == (60, 80, 3) and f[name].dtype == np.float32
    assert f["depth_m"].shape == (60, 80) and f["object_id"].dtype == np.int32
    # The PNG holds the display frame in 8 bits: the same frame, to the quantisation's half step.
    png_pixels = read_png(png).astype(float)
    assert np.abs(f["display"] * 255 - png_pixels).max() <= 0.5 + 1e-3
    # Smoke at 60 s: the radiance is positive and finite, the display clipped to [0, 1].
    assert np.all(np.isfinite(f["radiance"])) and f["radiance"].mean() > 0
    assert f["display"].min() >= 0 and f["display"].max() <= 1
    # The ids name surfaces the scene has, each one material; depth is a distance in the room [m].
    ids, mats, depth = f["object_id"], f["material_id"], f["depth_m"]
    assert ids.min() >= 0 and ids.max() < len(bocas.surfaces)
    assert all(len(np.unique(mats[ids == i])) == 1 for i in np.unique(ids))
    assert len(np.unique(ids)) > 3 and len(np.unique(mats)) < len(np.unique(ids))  # walls share materials
    assert 0.5 < depth.min() and depth.max() < 20 and np.any(depth != np.round(depth))
    assert f["samples"] == 80 * 60 * 4
    # Same seed, same frame; another seed, another noise.
    again = smokescan.render(bocas, time_s=60, spp=4, width=80, height=60, seed=5)
    assert np.array_equal(again["radiance"], f["radiance"])
    other = smokescan.render(bocas, time_s=60, spp=4, width=80, height=60, seed=6)
    assert not np.array_equal(other["radiance"], f["radiance"])
    # The variance is that of the pixel's mean: two independent frames differ by twice it.
    spread = np.mean((other["radiance"].astype(float) - f["radiance"]) ** 2) / 2
    assert 0.5 < spread / np.mean(f["variance"]) < 2


def test_a_fixed_exposure_scales_the_display(bocas):
    f = smokescan.render(bocas, time_s=0, spp=1, width=32, height=24, exposure=0.5)
    assert f["exposure"] == 0.5
    # display = sRGB(min(1, radiance · exposure)) per channel
    lin = np.clip(f["radiance"].astype(float) * 0.5, 0, 1)
    srgb = np.where(lin <= 0.0031308, 12.92 * lin, 1.055 * lin ** (1 / 2.4) - 0.055)
    assert np.abs(srgb - f["display"]).max() < 1e-5


def test_render_reports_its_tiles_and_stops_on_ctrl_c(bocas):
    seen = []
    smokescan.render(bocas, spp=48, width=100, height=70, progress=lambda d, t: seen.append((d, t)))
    # 100 × 70 px in 16 × 16 tiles: 7 × 5 = 35, counted as they finish.
    assert len(seen) >= 3 and all(t == 35 for _, t in seen) and seen[-1] == (35, 35)
    assert any(0 < d < 35 for d, _ in seen) and all(a[0] <= b[0] for a, b in zip(seen, seen[1:]))
    # SIGINT while a long frame renders: KeyboardInterrupt soon, not the frame's end, and the
    # render's threads stopped with it (no CPU spent afterwards); the next frame is unharmed.
    import time

    reference = smokescan.render(bocas, spp=1, width=32, height=24)
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        smokescan.render(bocas, spp=4096, width=640, height=480)
    assert time.monotonic() - start < 10
    before = os.times()
    time.sleep(1.0)
    after = os.times()
    assert (after.user - before.user) + (after.system - before.system) < 0.2
    again = smokescan.render(bocas, spp=1, width=32, height=24)
    assert np.array_equal(again["radiance"], reference["radiance"])


def test_render_refuses_bad_settings_in_one_line(bocas):
    for kwargs, pattern in [({"width": -1}, r"^--width: "), ({"height": 100000}, r"^--height: "),
                            ({"exposure": 0.0}, r"^--exposure: "), ({"spp": 0}, r"^--spp: "),
                            ({"camera": "nope"}, r"nope"), ({"time_s": float("nan")}, r"^--time: ")]:
        with pytest.raises(smokescan.Error, match=pattern):
            smokescan.render(bocas, **kwargs)
    with pytest.raises(TypeError):
        smokescan.render(None)


def test_calibration_is_the_command_lines(bocas, tmp_path):
    out = tmp_path / "cal.json"
    sweep = ["--densities", "0,0.002,0.004,0.008", "--width", "64", "--height", "48", "--max-batches", "4"]
    cli("calibrate", "bocas", *sweep, "--out", str(out))
    r = smokescan.calibrate(bocas, densities=[0, 0.002, 0.004, 0.008], width=64, height=48, max_batches=4)
    mine, theirs = r.to_dict(), json.load(open(out))
    mine["render"].pop("seconds"), theirs["render"].pop("seconds")  # the time it took
    assert mine == theirs
    assert r.threshold.density == theirs["threshold"]["density"] > 0
    with pytest.raises(smokescan.Error, match=r"^--densities: "):
        smokescan.calibrate(bocas, densities=[0, 0.5])
    with pytest.raises(smokescan.Error, match=r"^--loss: "):
        smokescan.calibrate(bocas, loss="l1")


@pytest.fixture(scope="module")
def planted_run(tmp_path_factory):
    """A bocas run whose URG-04LX loses half its beams in a sector ahead (planted by a sensor file
    the diagnosis does not see), with the camera's saturation."""
    d = tmp_path_factory.mktemp("planted")
    ext = d / "ext.toml"
    ext.write_text('type = "urg04lx"\nmodel = "paper"\n[extensions]\n'
                   "[[extensions.sector]]\nfrom_deg = 20\nto_deg = 35\ndropout = 0.5\n")
    cli("scan", "bocas", "--rate", "1", "--seed", "3", "--quiet", "--sensor-file", str(ext), "--out",
        str(d / "run.log"), "--saturation-out", str(d / "sat.csv"))
    return d


def test_a_calibration_stops_on_ctrl_c_within_a_frame(bocas):
    import time

    timer = threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        smokescan.calibrate(bocas, width=640, height=480, spp=64)  # a frame takes far longer than 5 s
    assert time.monotonic() - start < 5


def test_a_calibration_from_python_is_one_diagnose_reads(bocas, planted_run, tmp_path):
    sweep = {"densities": [0, 0.002, 0.004, 0.008], "width": 64, "height": 48, "max_batches": 4}
    r = smokescan.calibrate(bocas, **sweep)
    mine = tmp_path / "mine.json"
    json.dump(r.to_dict(), open(mine, "w"))
    cli("calibrate", "bocas", "--densities", ",".join(str(d) for d in sweep["densities"]), "--width", "64",
        "--height", "48", "--max-batches", "4", "--out", str(tmp_path / "theirs.json"))
    log, sat = planted_run / "run.log", planted_run / "sat.csv"
    a = smokescan.diagnose("bocas", laser=log, saturation=sat, calibration=mine, max_findings=1)
    b = smokescan.diagnose("bocas", laser=log, saturation=sat, calibration=tmp_path / "theirs.json", max_findings=1)
    a, b = a.to_dict(), b.to_dict()
    assert a["inputs"]["calibration"] == str(mine)
    a["inputs"].pop("calibration"), b["inputs"].pop("calibration")
    assert a == b
    # The calibration is the one used: the built-in one gives another diagnosis of this run.
    builtin = smokescan.diagnose("bocas", laser=log, saturation=sat, max_findings=1).to_dict()
    builtin["inputs"].pop("calibration")
    assert builtin != a


def test_a_diagnosis_is_the_command_lines_and_finds_the_planted_sector(planted_run, tmp_path):
    log, sat = planted_run / "run.log", planted_run / "sat.csv"
    cli("diagnose", "--laser", str(log), "--saturation", str(sat), "--scene", "bocas", "--out",
        str(tmp_path / "cli"))
    rounds = []
    r = smokescan.diagnose("bocas", laser=log, saturation=str(sat), out=tmp_path / "py",
                           progress=lambda d, t: rounds.append((d, t)))
    assert r.to_dict() == json.load(open(tmp_path / "cli" / "diagnosis.json"))
    for name in ("diagnosis.json", "report.md", "sensor.toml"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    assert rounds and rounds[-1][0] == rounds[-1][1]
    assert r == smokescan.Report(json.load(open(tmp_path / "cli" / "diagnosis.json")))
    changed = r.to_dict()
    changed["findings"][0]["parameters"]["dropout"]["value"] += 1e-9
    assert r != smokescan.Report(changed)
    with pytest.raises(AttributeError):
        r.verdict = "none"
    assert r.verdict != "none"
    assert [f.cause for f in r.findings] == ["sector_dropout"]
    d = r.findings[0].parameters["dropout"]
    assert abs(d.value - 0.5) < 4 * d.std_error
    # The sector as planted (20°–35°, to the beams' 0.35° spacing), in the report and in the
    # extended sensor file diagnose wrote.
    lo, hi = (float(x) for x in r.findings[0].target.split()[1].split(".."))
    assert abs(lo - 20) < 0.75 and abs(hi - 35) < 0.75
    import tomllib

    sector = tomllib.load(open(tmp_path / "py" / "sensor.toml", "rb"))["extensions"]["sector"][0]
    assert abs(sector["from_deg"] - 20) < 0.75 and abs(sector["to_deg"] - 35) < 0.75
    assert abs(sector["dropout"] - 0.5) < 4 * d.std_error


def test_diagnose_refuses_bad_input_in_one_line_and_writes_nothing(planted_run, tmp_path):
    log = planted_run / "run.log"
    cases = [({"alpha": 0.9}, r"^--alpha: "), ({"max_findings": 0}, r"^--max-findings: "),
             ({"block_s": -1.0}, r"^--block: "), ({"smoke_shape": "bogus"}, r"bogus"),
             ({"unit": "furlong"}, r"^--unit: "), ({"model": "exact"}, r"^--model: "),
             ({"offset_s": float("inf")}, r"^--offset: ")]
    for kwargs, pattern in cases:
        with pytest.raises(smokescan.Error, match=pattern):
            smokescan.diagnose("bocas", laser=log, out=tmp_path / "never", **kwargs)
        assert not (tmp_path / "never").exists()
    with pytest.raises(smokescan.Error, match=r"^--laser: "):
        smokescan.diagnose("bocas")
    with pytest.raises(smokescan.Error, match=r"^--laser: must be a path"):
        smokescan.diagnose("bocas", laser=3)
    with pytest.raises(smokescan.Error, match=r"^--laser: holds a NUL"):
        smokescan.diagnose("bocas", laser=str(log) + "\0.bag")
    with pytest.raises(smokescan.Error, match=r"^--out: names no file"):
        smokescan.diagnose("bocas", laser=log, out="")
    with pytest.raises(smokescan.Error, match=r"^--calibration: must be a path, not None"):
        smokescan.diagnose("bocas", laser=log, calibration=None)
    (tmp_path / "taken").mkdir()
    (tmp_path / "taken" / "mine.txt").write_text("keep")
    with pytest.raises(smokescan.Error, match=r"not an empty folder"):
        smokescan.diagnose("bocas", laser=log, out=tmp_path / "taken")
    assert os.listdir(tmp_path / "taken") == ["mine.txt"]


# A point of a `scan --points` PCD (binary): x y z intensity ring return_index time source.
PCD_POINT = np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("intensity", "<f4"), ("ring", "<u2"),
                      ("return_index", "u1"), ("time", "<f4"), ("source", "u1")])


def rewrite_points(folder, change):
    """Rewrites each PCD of a `scan --points` folder with change(points) as its points: an
    independent writer of the files smokescan reads."""
    for pcd in sorted(folder.glob("*.pcd")):
        raw = pcd.read_bytes()
        head_end = raw.index(b"DATA binary\n") + len(b"DATA binary\n")
        head, points = raw[:head_end].decode(), np.frombuffer(raw[head_end:], dtype=PCD_POINT).copy()
        assert head.split("FIELDS ")[1].split("\n")[0] == " ".join(PCD_POINT.names)
        points = change(points)
        lines = [f"WIDTH {len(points)}" if l.startswith("WIDTH ") else f"POINTS {len(points)}"
                 if l.startswith("POINTS ") else l for l in head.splitlines()]
        pcd.write_bytes(("\n".join(lines) + "\n").encode() + points.tobytes())


def weaken_ring(folder, ring, keep_every):
    """Most of one ring's points gone from each frame."""
    def change(points):
        on_ring = np.flatnonzero(points["ring"] == ring)
        kept = np.ones(len(points), bool)
        kept[on_ring] = False
        kept[on_ring[::keep_every]] = True
        return points[kept]
    rewrite_points(folder, change)


def test_a_lidars_frames_are_diagnosed_as_the_command_line_does_and_a_weak_channel_is_found(tmp_path):
    frames = tmp_path / "frames"
    cli("scan", "factory_smoke", "--sensor", "vlp16", "--from", "20", "--to", "20.35", "--points", str(frames))
    weaken_ring(frames, ring=4, keep_every=3)  # two thirds of ring 4's returns gone
    cli("diagnose", "--scene", "factory_smoke", "--points", str(frames), "--sensor", "vlp16", "--out",
        str(tmp_path / "cli"))
    ticks = []
    d = smokescan.diagnose_lidar("factory_smoke", points=frames, sensor="vlp16", out=tmp_path / "py",
                                 progress=lambda done, total: ticks.append((done, total)))
    assert ticks[-1] == (4, 4)
    assert d.to_dict() == json.load(open(tmp_path / "cli" / "diagnosis.json"))
    assert (tmp_path / "py" / "report.md").read_text() == (tmp_path / "cli" / "report.md").read_text()
    assert d.verdict == "dropping_channel"
    channel = [t for t in d.tried if t["cause"] == "dropping_channel"][0]
    assert channel["ring"] == 4 and channel["named"]
    # Two thirds lost on ring 4's clear beams, none elsewhere (within the test's error).
    assert abs(channel["effect"] - 2 / 3) < 4 * channel["effect_se"] + 0.02
    assert d.rings[4]["missed"] > 0.6 * d.rings[4]["clear"]
    # The preset extended by it: ring 4 drops what gives the excess found over the other clear
    # beams' share, written as lidar.toml too, to the last digit.
    assert d.extended_preset == (tmp_path / "py" / "lidar.toml").read_text()
    preset = tomllib.loads(d.extended_preset)
    assert preset["base"] == "vlp16"
    (ring4,) = preset["extensions"]["channel"]
    assert ring4["ring"] == 4 and ring4["range_offset_m"] == 0
    assert ring4["dropout"] == pytest.approx(channel["effect"] / (1 - channel["base_rate"]), rel=1e-12)
    # Refused in one line, nothing written.
    with pytest.raises(smokescan.Error, match=r"frames\.csv: "):
        smokescan.diagnose_lidar("factory_smoke", points=tmp_path, sensor="vlp16", out=tmp_path / "never")
    with pytest.raises(smokescan.Error, match=r"^--sensor: "):
        smokescan.diagnose_lidar("factory_smoke", points=frames, sensor="", out=tmp_path / "never")
    with pytest.raises(smokescan.Error, match=r"^--alpha: "):
        smokescan.diagnose_lidar("factory_smoke", points=frames, sensor="vlp16", alpha=0.9, out=tmp_path / "never")
    assert not (tmp_path / "never").exists()
    # The same run as a ROS 2 bag of PointCloud2 frames: read in place of the folder, without poses.
    cli("scan", "factory_smoke", "--sensor", "vlp16", "--from", "20", "--to", "20.35", "--bag", str(tmp_path / "bag"))
    b = smokescan.diagnose_lidar("factory_smoke", points=tmp_path / "bag", sensor="vlp16")
    assert b.verdict == "none" and b.frames == 4 and b.pose_mismatch_m is None
    assert b.points == str(tmp_path / "bag") and b.topic == "/points"  # what was read: its only topic
    with pytest.raises(smokescan.Error, match=r"has no topic /nope"):
        smokescan.diagnose_lidar("factory_smoke", points=tmp_path / "bag", sensor="vlp16", topic="/nope")
    with pytest.raises(smokescan.Error, match=r"has no topic /nope"):
        smokescan.fit_lidar("factory_smoke", points=tmp_path / "bag", sensor="vlp16", topic="/nope")


def scale_intensities(folder, factor):
    """Every point's intensity times factor (a receiver that reads dim)."""
    def change(points):
        points["intensity"] *= factor
        return points
    rewrite_points(folder, change)


def test_a_lidars_surfaces_are_fitted_as_the_command_line_does_and_a_dim_receiver_is_read(tmp_path):
    frames = tmp_path / "frames"
    cli("scan", "factory_smoke", "--sensor", "vlp16", "--from", "20", "--to", "20.15", "--points", str(frames))
    cli("fit", "--scene", "factory_smoke", "--points", str(frames), "--sensor", "vlp16", "--out",
        str(tmp_path / "cli.toml"))
    ticks = []
    r = smokescan.fit_lidar("factory_smoke", points=frames, sensor="vlp16", out=tmp_path / "py.toml",
                            progress=lambda done, total: ticks.append((done, total)))
    assert ticks[-1] == (2, 2)
    assert r.to_dict() == json.load(open(tmp_path / "cli_report.json"))
    assert (tmp_path / "py.toml").read_text() == (tmp_path / "cli.toml").read_text() == r.extended_preset
    fitted = [s for s in r.surfaces if s["fitted"]]
    assert len(fitted) >= 6
    for s in fitted:
        assert abs(s["reflectance_factor"] - 1) < 4 * math.hypot(s["reflectance_factor_se"], s["reflectance_factor_sys"])
    preset = tomllib.loads(r.extended_preset)
    assert preset["base"] == "vlp16"
    assert {s["name"] for s in preset["extensions"]["surface"]} == {s["surface"] for s in fitted}
    # A receiver whose intensities read 20 % low: every surface reads 0.8 (within the smoke's share
    # under some echoes, which a dim receiver dims too and a dark wall would not).
    scale_intensities(frames, 0.8)
    dim = smokescan.fit_lidar("factory_smoke", points=frames, sensor="vlp16")
    for s in dim.surfaces:
        if s["fitted"]:
            assert abs(s["reflectance_factor"] - 0.8) < 0.02, s
    # Refused in one line, nothing written.
    with pytest.raises(smokescan.Error, match=r"^--sensor: "):
        smokescan.fit_lidar("factory_smoke", points=frames, sensor="", out=tmp_path / "never.toml")
    with pytest.raises(smokescan.Error, match=r"frames\.csv"):
        smokescan.fit_lidar("factory_smoke", points=tmp_path, sensor="vlp16", out=tmp_path / "never.toml")
    assert not (tmp_path / "never.toml").exists()


def volume_info(path):
    out = subprocess.run([CLI, "volume", "info", str(path)], check=True, capture_output=True, text=True).stdout
    return out


def centres(density, m):
    """World positions [m] of every voxel's centre: index_to_world applied to its indices."""
    idx = np.indices(density.shape).reshape(3, -1).T
    return idx @ m[:3, :3].T + m[:3, 3]


def test_a_vdb_grid_reads_as_its_formula():
    here = pathlib.Path(__file__).resolve().parents[2] / "volumes"
    # volumes/README.md: ρ = 1 − (r/R)² inside R = 0.2 m, voxels of 0.01 m centred on integers.
    d, m = smokescan.read_volume(here / "fog_ball_float.vdb")
    assert d.dtype == np.float32 and np.allclose(m[:3, :3], 0.01 * np.eye(3)) and np.array_equal(m[3], [0, 0, 0, 1])
    r = np.linalg.norm(centres(d, m), axis=1)
    expected = np.where(r < 0.2, 1 - (r / 0.2) ** 2, 0)
    assert np.abs(d.reshape(-1) - expected).max() < 1e-6
    assert (d > 0).sum() == 33371
    # A dense 32 × 16 × 16 block of 0.05 m voxels stored as doubles, (i + 1)/32 in column i; scaled.
    d, m = smokescan.read_volume(here / "ramp_block_double.vdb", scale=2.0)
    assert d.shape == (32, 16, 16) and np.isclose(m[0, 0], 0.05)
    assert np.allclose(d, 2 * (np.arange(32)[:, None, None] + 1) / 32.0)


def test_an_array_becomes_a_grid_that_the_library_reads(tmp_path):
    # A block of smoke at [3:7, 2:5, 1:4] in a (20, 10, 6) array of voxels of 0.02 m turned 30°
    # about z, voxel [0, 0, 0]'s centre at (1, 2, 0.5) m.
    rng = np.random.default_rng(4)
    density = np.zeros((20, 10, 6), np.float32)
    density[3:7, 2:5, 1:4] = rng.uniform(0.001, 0.01, size=(4, 3, 3))
    c, s = np.cos(np.pi / 6), np.sin(np.pi / 6)
    m = np.array([[0.02 * c, -0.02 * s, 0, 1], [0.02 * s, 0.02 * c, 0, 2], [0, 0, 0.02, 0.5], [0, 0, 0, 1]])
    path = tmp_path / "tilted.vdb"
    smokescan.write_volume(path, density, m)
    # OpenVDB's own view of the file (the command line's volume info): the voxels' index box and
    # the world box of their cubes, computed here from the corners through m.
    info = volume_info(path)
    assert "voxel 0.02 m" in info and "36 active voxels" in info and "index support [3,2,1] -> [6,4,3]" in info
    corners = np.array([[a, b, cc, 1] for a in (2.5, 6.5) for b in (1.5, 4.5) for cc in (0.5, 3.5)]) @ m.T
    lo, hi = corners[:, :3].min(axis=0), corners[:, :3].max(axis=0)
    bounds = info.split("world bounds [")[1].split("]")
    assert np.allclose([float(x) for x in bounds[0].split(",")], lo, atol=1e-3)
    assert np.allclose([float(x) for x in bounds[1].split("[")[1].split(",")], hi, atol=1e-3)
    # Read back: the block alone, its map moved to its first voxel.
    back, m_back = smokescan.read_volume(path)
    assert back.shape == (4, 3, 3) and np.array_equal(back, density[3:7, 2:5, 1:4])
    assert np.allclose(m_back[:3, :3], m[:3, :3], atol=1e-12)
    assert np.allclose(m_back[:3, 3], m[:3, :3] @ [3, 2, 1] + m[:3, 3], atol=1e-12)
    # An empty grid reads as an empty block with the map of its index origin.
    empty = tmp_path / "empty.vdb"
    smokescan.write_volume(empty, np.zeros((2, 2, 2)), m)
    d0, m0 = smokescan.read_volume(empty)
    assert d0.shape == (0, 0, 0) and np.allclose(m0, m)


def test_write_volume_refuses_what_is_not_smoke_and_writes_nothing(tmp_path):
    path = tmp_path / "bad.vdb"
    ok = np.zeros((2, 2, 2), np.float32)
    eye = np.eye(4)
    bad = [(np.full((2, 2, 2), -1.0), eye, r"^density: voxel \[0, 0, 0\] holds -1"),
           (np.full((2, 2, 2), np.nan), eye, r"^density: voxel \[0, 0, 0\]"),
           (np.zeros((2, 2)), eye, r"^density: must be a 3-D array"),
           (ok, np.diag([1, 2, 1, 1.0]), r"non-uniform"),
           (ok, np.diag([1, 1, 0, 1.0]), r"singular|not a transform"),
           (ok, np.eye(3), r"^index_to_world: must be a 4×4"),
           (ok, [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [1, 0, 0, 1]], r"not affine")]
    for density, m, pattern in bad:
        with pytest.raises(smokescan.Error, match=pattern):
            smokescan.write_volume(path, density, m)
        assert not path.exists()
    with pytest.raises(smokescan.Error, match=r"^density: must hold real numbers"):
        smokescan.write_volume(path, np.ones((2, 2, 2), bool), eye)
    # A huge array is refused by its shape, before any copy.
    with pytest.raises(smokescan.Error, match=r"^density: holds more than"):
        smokescan.write_volume(path, np.broadcast_to(np.float32(0), (1 << 29, 1, 1)), eye)
    assert not path.exists()
    # An existing file is never replaced.
    mine = tmp_path / "mine.log"
    mine.write_text("keep")
    with pytest.raises(smokescan.Error, match=r"exists"):
        smokescan.write_volume(mine, ok, eye)
    assert mine.read_text() == "keep"
    with pytest.raises(smokescan.Error, match=r"missing\.vdb"):
        smokescan.read_volume(tmp_path / "missing.vdb")
    with pytest.raises(smokescan.Error, match=r"^path: must be a path, not None"):
        smokescan.read_volume(None)
    with pytest.raises(smokescan.Error, match=r"^scale: "):
        smokescan.read_volume(tmp_path / "missing.vdb", scale=2e6)


def test_every_public_name_has_a_stub_and_a_docstring():
    import ast

    stub = ast.parse((pathlib.Path(smokescan.__file__).parent / "__init__.pyi").read_text())
    stubbed = {n.name for n in stub.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    for name in smokescan.__all__:
        if name.startswith("__"):
            continue
        assert name in stubbed, name
        assert getattr(smokescan, name).__doc__, name


def test_a_fit_is_the_command_lines_and_recovers_the_scenes_penetration_power(planted_run, tmp_path):
    # bocas's URG-04LX runs the paper model at penetration power 0.007 density·m (its sensor's
    # default; the run's sector only drops beams off the targets).
    log, sat = planted_run / "run.log", planted_run / "sat.csv"
    cli("fit", "--laser", str(log), "--saturation", str(sat), "--scene", "bocas", "--out", str(tmp_path / "c.toml"))
    r = smokescan.fit("bocas", laser=log, saturation=sat, out=tmp_path / "p.toml")
    assert r.to_dict() == json.load(open(tmp_path / "c_report.json"))
    theirs = (tmp_path / "c.toml").read_text().replace(f" (report: {tmp_path / 'c_report.json'})", "")
    assert (tmp_path / "p.toml").read_text() == theirs
    ref = [g for g in r.groups if g.name == r.reference_group][0].threshold
    p = ref.penetration_power_density_m
    assert abs(p.value - 0.007) < 4 * p.std_error
    import tomllib

    assert tomllib.load(open(tmp_path / "p.toml", "rb"))["paper"]["penetration_power"] == pytest.approx(p.value, rel=1e-12)
    # The sensor file is a new file: an existing one is refused and left alone.
    with pytest.raises(smokescan.Error, match=r"exists"):
        smokescan.fit("bocas", laser=log, saturation=sat, out=tmp_path / "p.toml")
    # No groups, no fit; a bad setting is one line.
    with pytest.raises(smokescan.Error, match=r"^fit: say which beams"):
        smokescan.fit(laser=log, saturation=sat)
    with pytest.raises(smokescan.Error, match=r"^--link: "):
        smokescan.fit("bocas", laser=log, saturation=sat, link="cloglog")
    with pytest.raises(smokescan.Error, match=r"^--bootstrap: "):
        smokescan.fit("bocas", laser=log, saturation=sat, bootstrap=5000)


def test_a_plume_fit_is_the_command_lines(tmp_path):
    log = tmp_path / "sick.log"
    cli("scan", "plume", "--sensor", "lms200", "--from", "10", "--to", "40", "--quiet", "--out", str(log))
    cli("fit-plume", "--laser", str(log), "--scene", "plume", "--bins", "4", "--out", str(tmp_path / "p.json"))
    r = smokescan.fit_plume("plume", laser=log, bins=4)
    assert r.to_dict() == json.load(open(tmp_path / "p.json"))
    assert len(r.bins) == 4 and r.to_dict() != smokescan.fit_plume("plume", laser=log).to_dict()
    # The penetration depth falls with density (docs/fitting.md: k ≈ 1.4 here), clearly.
    assert r.depth.k.value > 5 * r.depth.k.std_error
    with pytest.raises(smokescan.Error, match=r"^--bins: "):
        smokescan.fit_plume("plume", laser=log, bins=0)
    with pytest.raises(smokescan.Error, match=r"no sensor 'urg'"):
        smokescan.fit_plume("plume", laser=log, sensor="urg")


def write_png(path, pixels):
    """An 8-bit RGB PNG written by Open3D (an independent writer)."""
    code = ("import sys, numpy as np, open3d as o3d\n"
            "o3d.io.write_image(sys.argv[1], o3d.geometry.Image(np.load(sys.argv[2])))\n")
    np.save(str(path) + ".npy", pixels)
    subprocess.run([sys.executable, "-c", code, str(path), str(path) + ".npy"], check=True)
    os.remove(str(path) + ".npy")


def test_saturation_of_frames_is_hsvs_formula(tmp_path):
    # A grey frame with a 6 × 4 px patch of (255, g, g): its HSV saturation is (255 − g)/255.
    frames = tmp_path / "frames"
    frames.mkdir()
    greens = [128, 148, 168]
    # A second patch, rows 7–8, columns 0–5: 6 pixels of (g, g, 255) and 6 of (g/2, g/2, 255), so
    # its median is not its mean.
    for k, g in enumerate(greens):
        img = np.full((10, 12, 3), 40, np.uint8)
        img[2:6, 3:9] = (255, g, g)
        img[7:9, 0:3] = (g, g, 255)
        img[7:9, 3:6] = (g // 2, g // 2, 255)
        write_png(frames / f"frame_{k:03d}.png", img)
    seen = []
    d = smokescan.saturation(frames, rects=["red=3,2,6,4", "blue=0,7,6,2"], fps=10,
                             progress=lambda a, b: seen.append((a, b)))
    assert np.allclose(d["time_s"], [0, 0.1, 0.2]) and seen == [(1, 3), (2, 3), (3, 3)]
    red = np.array([(255 - g) / 255 for g in greens])
    blue = [np.array([(255 - g) / 255] * 6 + [(255 - g // 2) / 255] * 6) for g in greens]
    assert list(d["patches"]) == ["red", "blue"]
    assert np.allclose(d["patches"]["red"], red, atol=1e-7) and np.allclose(d["patch_sd"]["red"], 0, atol=1e-7)
    assert np.allclose(d["patches"]["blue"], [b.mean() for b in blue], atol=1e-7)
    assert np.allclose(d["patch_median"]["blue"], [np.median(b) for b in blue], atol=1e-7)
    assert np.allclose(d["patch_sd"]["blue"], [b.std() for b in blue], atol=1e-6)
    both = [np.concatenate([[r] * 24, b]) for r, b in zip(red, blue)]
    assert np.allclose(d["saturation"], [x.mean() for x in both], atol=1e-7)
    assert np.allclose(d["median"], [np.median(x) for x in both], atol=1e-7)
    assert np.array_equal(d["pixels"], [36, 36, 36])
    with pytest.raises(smokescan.Error, match=r"^saturation: give the target region"):
        smokescan.saturation(frames, fps=10)
    with pytest.raises(smokescan.Error, match=r"^--ids: needs --scene"):
        smokescan.saturation(frames, ids=frames)
    with pytest.raises(smokescan.Error, match=r"^--rect"):
        smokescan.saturation(frames, rects=["red=3,2"])


def test_saturation_of_rendered_frames_is_the_command_lines(tmp_path):
    fr, ids = tmp_path / "fr", tmp_path / "ids"
    fr.mkdir(), ids.mkdir()
    cli("render", "bocas", "--from", "40", "--to", "42", "--every", "1", "--out", str(fr / "f_{i}.png"), "--ids",
        str(ids / "i_{i}.exr"), "--spp", "2", "--width", "160", "--height", "120")
    cli("saturation", str(fr), "--ids", str(ids), "--scene", "bocas", "--fps", "1", "--out", str(tmp_path / "s.csv"))
    theirs = np.genfromtxt(tmp_path / "s.csv", delimiter=",", names=True)
    d = smokescan.saturation(fr, ids=ids, scene="bocas", fps=1)
    assert np.allclose(d["time_s"], theirs["time_s"], atol=1e-9)
    assert np.allclose(d["saturation"], theirs["saturation"], atol=1e-8)
    assert np.allclose(d["median"], theirs["saturation_median"], atol=1e-8)
    for name in ("blue", "yellow", "gold"):
        assert np.allclose(d["patches"][name], theirs[name], atol=1e-8)
        assert np.allclose(d["patch_sd"][name], theirs[name + "_sd"], atol=1e-8)


def read_ranges(path):
    """A range log's scans (omnirange --out, --laser-out): (time_s, angles, values in mm)."""
    rows = [line.split() for line in open(path) if not line.startswith("#")]
    return [(float(f[0]), np.array(f[1::2], float), np.array(f[2::2], np.int64)) for f in rows]


def test_the_omnicam_rangefinder_is_the_command_lines(tmp_path):
    out, laser = tmp_path / "omni.log", tmp_path / "laser.log"
    printed = subprocess.run([CLI, "omnirange", "factory", "--train", "0", "--from", "0", "--to", "2", "--spp", "4",
                              "--out", str(out), "--laser-out", str(laser)], check=True, capture_output=True,
                             text=True).stdout
    seen = []
    d = smokescan.omnirange(smokescan.load_scene("factory"), train=[0], t0=0, t1=2, spp=4,
                            progress=lambda a, b: seen.append((a, b)))
    assert seen[-1] == (4, 4)  # one training frame, three frames read
    omni, las = read_ranges(out), read_ranges(laser)
    assert np.allclose(d["time_s"], [t for t, _, _ in omni])
    for k, (t, angles, mm) in enumerate(omni):
        assert np.allclose(d["angle_rad"], angles, atol=1e-6)
        assert np.array_equal(np.round(d["range_m"][k] * 1000).astype(np.int64), mm)
    for k, (t, angles, values) in enumerate(las):
        assert np.allclose(d["laser_angle_rad"], angles, atol=1e-6)
        assert np.array_equal(d["laser_value"][k], values)
    assert seen == [(1, 4), (2, 4), (3, 4), (4, 4)]
    c = d["comparison"]
    assert f"{c['pairs']} scanline pairs" in printed and f"{c['outliers']} outliers" in printed
    assert f"mean |difference| {c['mean_abs_m']:.4f} m, {c['mean_percent']:.2f} %" in printed
    assert f"(laser - omnicam) {c['mean_signed_m']:+.4f} m" in printed and f"exposure {d['exposure']:.4g}" in printed
    # A range at the maximum is status 2, a hit lies within the ranges; the laser's ranges are its
    # values in metres, NaN where it reported an error code.
    st, rg = d["status"], d["range_m"]
    assert st.shape == rg.shape and np.all(rg[st == 2] == 3.8) and np.all((rg[st == 0] >= 0.3) & (rg[st == 0] < 3.8))
    lv, lr = d["laser_value"], d["laser_range_m"]
    # (the factory's LMS200: its error codes lie above 8100 mm, its ranges up to 8183 mm.)
    assert np.isnan(lr).any() and np.all(lv[np.isnan(lr)] > 8100)
    assert np.allclose(lr[~np.isnan(lr)] * 1000, lv[~np.isnan(lr)], atol=1e-6)
    # Below a raised minimum range, status 1 at the minimum.
    near = smokescan.omnirange(smokescan.load_scene("factory"), train=[0], t0=0, t1=0, spp=4, min_range_m=1.5)
    assert np.any(near["status"] == 1) and np.all(near["range_m"][near["status"] == 1] == 1.5)
    # The factory's floor is seen to within centimetres where both read it (the paper's Fig. 9).
    assert c["pairs"] > 300 and c["mean_abs_m"] < 0.15
    assert d["status"].dtype == np.uint8 and set(np.unique(d["status"])) <= {0, 1, 2}
    with pytest.raises(smokescan.Error, match=r"^--train: give either"):
        smokescan.omnirange(smokescan.load_scene("factory"))
    with pytest.raises(smokescan.Error, match=r"^--to: must not precede"):
        smokescan.omnirange(smokescan.load_scene("factory"), train=[0], t0=2, t1=1)
    with pytest.raises(smokescan.Error, match=r"^--rate: would keep"):
        smokescan.omnirange(smokescan.load_scene("factory"), train=[0], rate_hz=2000)


@pytest.mark.parametrize("which", ["diagnose", "fit"])
def test_a_long_fit_or_diagnosis_stops_on_ctrl_c(planted_run, tmp_path, which):
    import time

    log, sat = planted_run / "run.log", planted_run / "sat.csv"
    call = {  # both take tens of seconds
        "diagnose": lambda: smokescan.diagnose("bocas", laser=log, saturation=sat, model="physical",
                                               out=tmp_path / "never"),
        "fit": lambda: smokescan.fit("bocas", laser=log, saturation=sat, bootstrap=1000, out=tmp_path / "never"),
    }[which]
    threading.Timer(0.7, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        call()
    assert time.monotonic() - start < 5 and not (tmp_path / "never").exists()


def test_paths_and_settings_are_checked_before_any_work(planted_run, tmp_path):
    import time

    log, sat = planted_run / "run.log", planted_run / "sat.csv"
    with pytest.raises(smokescan.Error, match=r"^scene: holds a NUL"):
        smokescan.load_scene("plume\0junk")
    with pytest.raises(smokescan.Error, match=r"^--sensor-file: holds a NUL"):
        smokescan.scan(smokescan.load_scene("plume"), sensor_file="x.toml\0y", t0=20, t1=20)
    with pytest.raises(smokescan.Error, match=r"^--saturation: give the camera's saturation"):
        smokescan.fit("bocas", laser=log)
    start = time.monotonic()
    with pytest.raises(smokescan.Error, match=r"its folder does not exist"):
        smokescan.fit("bocas", laser=log, saturation=sat, bootstrap=1000, out=tmp_path / "nodir" / "x.toml")
    assert time.monotonic() - start < 1
    with pytest.raises(smokescan.Error, match=r"^--fps: "):
        smokescan.saturation(tmp_path, rects=["a=0,0,1,1"], fps=1e-300)
    # A Report is read-only all the way down: its lists are tuples.
    r = smokescan.Report({"bins": [{"n": 1}], "ok": True})
    assert isinstance(r.bins, tuple) and r.bins[0].n == 1 and r.to_dict() == {"bins": [{"n": 1}], "ok": True}
    with pytest.raises(AttributeError):
        del r.ok


def test_omnirange_stops_on_ctrl_c_within_a_frame():
    import time

    factory = smokescan.load_scene("factory")
    threading.Timer(0.7, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        smokescan.omnirange(factory, train=[0], t0=0, t1=0, spp=4096)  # minutes a frame
    assert time.monotonic() - start < 5
