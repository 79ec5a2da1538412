"""The module's render, calibrate and diagnose against the command line's outputs for the same
inputs, and their promises: progress, Ctrl-C, one-line errors (run by ctest: Python.Pytest)."""
import json
import os
import pathlib
import signal
import subprocess
import sys
import threading

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
    # The ids name surfaces the scene has; depth is where a surface was hit.
    ids = f["object_id"]
    assert ids.max() < len(bocas.surfaces) and np.all(np.isfinite(f["depth_m"][ids >= 0]))
    # Same seed, same frame; another seed, another noise.
    again = smokescan.render(bocas, time_s=60, spp=4, width=80, height=60, seed=5)
    assert np.array_equal(again["radiance"], f["radiance"])
    other = smokescan.render(bocas, time_s=60, spp=4, width=80, height=60, seed=6)
    assert not np.array_equal(other["radiance"], f["radiance"])


def test_a_fixed_exposure_scales_the_display(bocas):
    f = smokescan.render(bocas, time_s=0, spp=1, width=32, height=24, exposure=0.5)
    assert f["exposure"] == 0.5
    # display = sRGB(min(1, radiance · exposure)) per channel
    lin = np.clip(f["radiance"].astype(float) * 0.5, 0, 1)
    srgb = np.where(lin <= 0.0031308, 12.92 * lin, 1.055 * lin ** (1 / 2.4) - 0.055)
    assert np.abs(srgb - f["display"]).max() < 1e-5


def test_render_reports_its_tiles_and_stops_on_ctrl_c(bocas):
    seen = []
    smokescan.render(bocas, spp=2, width=96, height=64, progress=lambda d, t: seen.append((d, t)))
    assert seen and seen[-1] == (24, 24) and all(a[0] <= b[0] for a, b in zip(seen, seen[1:]))
    # SIGINT while a long frame renders: KeyboardInterrupt soon, not the frame's end.
    import time

    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        smokescan.render(bocas, spp=4096, width=640, height=480)
    assert time.monotonic() - start < 10


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
    # The report written as JSON is a calibration diagnose and fit read.
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
    assert r.verdict != "none"
    assert [f.cause for f in r.findings] == ["sector_dropout"]
    d = r.findings[0].parameters["dropout"]
    assert abs(d.value - 0.5) < 4 * d.std_error


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
    (tmp_path / "taken").mkdir()
    (tmp_path / "taken" / "mine.txt").write_text("keep")
    with pytest.raises(smokescan.Error, match=r"not an empty folder"):
        smokescan.diagnose("bocas", laser=log, out=tmp_path / "taken")
    assert os.listdir(tmp_path / "taken") == ["mine.txt"]


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
    # A tilted block: voxels of 0.02 m turned 30° about z, its first voxel's centre at (1, 2, 0.5).
    rng = np.random.default_rng(4)
    density = rng.uniform(0, 0.01, size=(20, 10, 6)).astype(np.float32)
    density[density < 0.002] = 0
    c, s = np.cos(np.pi / 6), np.sin(np.pi / 6)
    m = np.array([[0.02 * c, -0.02 * s, 0, 1], [0.02 * s, 0.02 * c, 0, 2], [0, 0, 0.02, 0.5], [0, 0, 0, 1]])
    path = tmp_path / "tilted.vdb"
    smokescan.write_volume(path, density, m)
    info = volume_info(path)
    assert "voxel 0.02 m" in info and f"{int((density > 0).sum())} active voxels" in info
    back, m_back = smokescan.read_volume(path)
    # The box of the non-zero voxels: trimmed where a face held only zeros, the map moved with it.
    nz = np.argwhere(density > 0)
    lo, hi = nz.min(axis=0), nz.max(axis=0) + 1
    assert np.array_equal(back, density[lo[0]:hi[0], lo[1]:hi[1], lo[2]:hi[2]])
    assert np.allclose(m_back[:3, :3], m[:3, :3], atol=1e-12)
    assert np.allclose(m_back[:3, 3], m[:3, :3] @ lo + m[:3, 3], atol=1e-12)


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
    with pytest.raises(smokescan.Error, match=r"missing\.vdb"):
        smokescan.read_volume(tmp_path / "missing.vdb")


def test_every_public_name_has_a_stub_and_a_docstring():
    import ast

    stub = ast.parse((pathlib.Path(smokescan.__file__).parent / "__init__.pyi").read_text())
    stubbed = {n.name for n in stub.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    for name in smokescan.__all__:
        if name.startswith("__"):
            continue
        assert name in stubbed, name
        assert getattr(smokescan, name).__doc__, name
