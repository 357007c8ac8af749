"""Tests of the command-line interface ``sph`` (called in-process through ``main``)."""

from __future__ import annotations

import dataclasses
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml
from physics_helpers import set_options

from sph.cases import load_case
from sph.cli import main

CASE_NAMES = ["still_water", "dam_break", "sloshing_rect", "sloshing_u", "wave_tank",
              "floating_box", "ship_decay", "damaged_ship", "current_tank",
              "cylinder_in_current"]

# A still-water tank small enough to run in about a second: 10 x 5 fluid particles.
TINY_STILL_WATER = [
    "numerics.dx=0.1",
    "geometry.tank_length=1.0",
    "geometry.depth=0.5",
    "geometry.tank_height=0.8",
    "probes.pressure=[{name: b, x: 0.5, z: 0.0}]",
    "probes.surface=[{name: c, x: 0.5}]",
    "run.t_end=0.05",
]

# A tiny dam break (10 x 20 fluid particles) that is stopped by the run-time checks within
# ten steps: with c0 = 3 sqrt(g H) the hydrostatic initial density at the bottom of the
# column is about 1.09 rho0, far above the band limit 1.0001 rho0, and the Courant number
# is the largest allowed. The first check (run.check_interval = 10 steps) must fail.
TINY_BLOW_UP = [
    "numerics.dx=0.1",
    "numerics.cfl=0.5",
    "numerics.c_factor=3",
    "run.density_max=1.0001",
    "run.t_end=0.5",
]


def _stderr_lines(err):
    return [ln for ln in err.splitlines() if ln.strip()]


# --------------------------------------------------------------------------- cases / example


def test_cases_lists_every_builtin_case(capsys):
    assert main(["cases"]) == 0
    out = capsys.readouterr().out
    lines = [ln for ln in out.splitlines() if ln.strip()]
    assert len(lines) == len(CASE_NAMES)
    assert [ln.split()[0] for ln in lines] == CASE_NAMES
    for ln in lines:  # each name comes with a one-line description
        assert len(ln.split()) > 1


@pytest.mark.parametrize("name", CASE_NAMES)
def test_example_is_a_valid_case_file(name, case_file):
    cfg = load_case(case_file(name))
    assert cfg.case == name


def test_example_unknown_case(capsys):
    assert main(["example", "nope"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.startswith("error:")
    assert "nope" in captured.err and "dam_break" in captured.err


def test_usage_errors_exit_2(capsys, tmp_path):
    for argv in ([], ["frobnicate"], ["run", str(tmp_path / "x.yaml")]):  # no -o
        with pytest.raises(SystemExit) as info:
            main(argv)
        assert info.value.code == 2
    capsys.readouterr()


def test_version(capsys):
    with pytest.raises(SystemExit) as info:
        main(["--version"])
    assert info.value.code == 0
    assert "sph-flood" in capsys.readouterr().out


# --------------------------------------------------------------------------- invalid cases


@pytest.mark.parametrize("text, overrides, key", [
    ("case: still_water\nnumerics:\n  dx: -0.1\n", [], "numerics.dx"),
    ("case: still_water\nnumerics:\n  kernel: cubic\n", [], "numerics.kernel"),
    ("case: still_water\nnumerics:\n  dxx: 0.1\n", [], "numerics.dxx"),
    ("case: dam_break\n", ["geometry.column_width=5"], "geometry.column_width"),
    ("case: sloshing_rect\n", ["probes.surface=[{name: a, x: 3.0}]"], "probes.surface[0].x"),
    ("case: still_water\n", ["run.t_end.x=1"], "run.t_end"),
], ids=["negative-dx", "kernel", "typo", "column-width", "probe", "non-section"])
def test_run_invalid_case_reports_one_line(tmp_path, capsys, text, overrides, key):
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    out = tmp_path / "out" / "bad.nc"
    rc = main(["run", str(path), "-o", str(out), "--no-progress"] + set_options(overrides))
    assert rc == 2
    captured = capsys.readouterr()
    lines = _stderr_lines(captured.err)
    assert len(lines) == 1, captured.err
    assert lines[0].startswith("error:")
    assert key in lines[0]
    assert "Traceback" not in captured.err
    assert not out.exists()


def test_run_missing_case_file(tmp_path, capsys):
    rc = main(["run", str(tmp_path / "none.yaml"), "-o", str(tmp_path / "x.nc")])
    assert rc == 2
    err = capsys.readouterr().err
    assert err.startswith("error:") and "none.yaml" in err and "Traceback" not in err


def test_run_yaml_syntax_error(tmp_path, capsys):
    path = tmp_path / "broken.yaml"
    path.write_text("case: still_water\nnumerics: {dx: 0.1\nrun: [\n")
    rc = main(["run", str(path), "-o", str(tmp_path / "x.nc")])
    assert rc == 2
    err = capsys.readouterr().err
    assert err.startswith("error:") and "broken.yaml" in err and "Traceback" not in err


def test_run_output_is_a_directory(case_file, tmp_path, capsys):
    rc = main(["run", str(case_file("still_water")), "-o", str(tmp_path), "--check"]
              + set_options(TINY_STILL_WATER))
    assert rc == 2
    assert capsys.readouterr().err.startswith("error:")


# --------------------------------------------------------------------------- runs


def test_check_validates_and_writes_nothing(case_file, tmp_path, capsys):
    path = case_file("still_water")
    out = tmp_path / "results" / "still.nc"
    before = sorted(p.name for p in tmp_path.iterdir())
    rc = main(["run", str(path), "-o", str(out), "--check", "--threads", "1"]
              + set_options(TINY_STILL_WATER))
    assert rc == 0
    assert "valid" in capsys.readouterr().out
    assert not out.exists()
    new = sorted(p.name for p in tmp_path.iterdir())
    # nothing besides (possibly) the empty output folder; see the strict test below
    assert set(new) - set(before) <= {"results"}
    if out.parent.exists():
        assert list(out.parent.iterdir()) == []


def test_check_creates_no_directory(case_file, tmp_path, capsys):
    path = case_file("still_water")
    out = tmp_path / "results" / "still.nc"
    assert main(["run", str(path), "-o", str(out), "--check"] + set_options(TINY_STILL_WATER)) == 0
    capsys.readouterr()
    assert not out.parent.exists()


def test_run_tiny_still_water(case_file, tmp_path, capsys):
    path = case_file("still_water")
    out = tmp_path / "out" / "still.nc"
    rc = main(["run", str(path), "-o", str(out), "--no-progress"] + set_options(TINY_STILL_WATER))
    captured = capsys.readouterr()
    assert rc == 0, captured.err
    assert "error" not in captured.err.lower()
    assert out.exists()
    # no temporary files left next to the output
    assert [p.name for p in out.parent.iterdir()] == ["still.nc"]
    with xr.open_dataset(out) as ds:
        assert ds["time"].attrs["units"] == "s"
        assert ds["time"].dtype == np.float64  # plain seconds, not decoded as timedeltas
        t = ds["time"].values
        assert t[0] == 0.0 and np.all(np.diff(t) > 0) and t[-1] <= 0.05 + 1e-9
        assert len(t) >= 2
        assert "probe_pressure" in ds
        p = ds["probe_pressure"].values
        assert p.shape[0] == 1 and np.all(np.isfinite(p))
        assert "surface_height" in ds
        assert np.all(np.isfinite(ds["surface_height"].values))
        assert ds.attrs["status"] == "completed"
        assert ds.attrs["case"] == "still_water"
        cfg = yaml.safe_load(ds.attrs["config"])
        assert cfg["case"] == "still_water"
        assert cfg["numerics"]["dx"] == 0.1
        assert cfg["geometry"]["tank_length"] == 1.0
        assert cfg["run"]["t_end"] == 0.05
        assert cfg["probes"]["pressure"] == [{"name": "b", "x": 0.5, "z": 0.0}]


def test_run_blow_up_exits_3_and_keeps_output(case_file, tmp_path, capsys):
    path = case_file("dam_break")
    out = tmp_path / "dam.nc"
    rc = main(["run", str(path), "-o", str(out), "--no-progress"] + set_options(TINY_BLOW_UP))
    captured = capsys.readouterr()
    assert rc == 3, captured.err
    err = captured.err
    assert "Traceback" not in err
    m = re.search(r"step (\d+), t = ([0-9.eE+-]+) s: (.+)", err)
    assert m, err
    step, t = int(m.group(1)), float(m.group(2))
    assert step == 10  # the first run-time check
    assert 0.0 < t < 0.5
    assert "density" in m.group(3) and "run.density_min/max" in m.group(3)
    assert str(out) in err
    assert out.exists()
    with xr.open_dataset(out) as ds:
        assert ds.attrs["status"].startswith("failed")
        assert "step 10" in ds.attrs["status"]
        assert ds.sizes["time"] >= 1
        assert ds["time"].values[-1] <= t


def test_run_with_vtk_snapshots(case_file, tmp_path, capsys):
    path = case_file("still_water")
    out = tmp_path / "still.nc"
    vtk = tmp_path / "vtk"
    rc = main(["run", str(path), "-o", str(out), "--no-progress", "--vtk", str(vtk)]
              + set_options(TINY_STILL_WATER + ["run.vtk_interval=0.02"]))
    assert rc == 0, capsys.readouterr().err
    vtus = sorted(vtk.glob("*.vtu"))
    pvds = sorted(vtk.glob("*.pvd"))
    assert len(pvds) == 1
    # samples at t = 0, 0.02, 0.04 (t_end = 0.05)
    assert len(vtus) == 3
    root = ET.parse(pvds[0]).getroot()
    files = [ds.get("file") for ds in root.iter("DataSet")]
    times = [float(ds.get("timestep")) for ds in root.iter("DataSet")]
    assert sorted(files) == [p.name for p in vtus]
    assert times[0] == 0.0 and np.all(np.diff(times) > 0)
    with xr.open_dataset(out) as ds:
        n_particles = int(ds.attrs["n_total"])  # fluid and wall particles
    for p in vtus:
        content = p.read_bytes()  # XML header, then raw appended binary data
        assert content.startswith(b"<?xml")
        assert b'<VTKFile type="UnstructuredGrid"' in content
        assert f'NumberOfPoints="{n_particles}"'.encode() in content
        for name in (b"velocity", b"density", b"pressure"):
            assert name in content


def test_run_without_vtk_interval_writes_no_snapshots(case_file, tmp_path, capsys):
    path = case_file("still_water")
    vtk = tmp_path / "vtk"
    rc = main(["run", str(path), "-o", str(tmp_path / "s.nc"), "--no-progress", "--vtk",
               str(vtk)] + set_options(TINY_STILL_WATER + ["run.t_end=0.02"]))
    assert rc == 0, capsys.readouterr().err
    assert not vtk.exists() or not list(vtk.glob("*.vtu"))


class _FakeClock:
    def __init__(self):
        self.now = 1000.0

    def __call__(self):
        return self.now


@pytest.mark.parametrize("tty, fewest, most", [(False, 3, 6), (True, 200, 250)])
def test_progress_bar_redraws_rarely_into_a_log(monkeypatch, tty, fewest, most):
    """Two simulated minutes of a run: a log gets a line every 30 s, a terminal a redraw
    every 0.5 s; the last state (t = t_end) is always printed."""
    import io

    import tqdm.std

    from sph.driver import _progress_bar

    clock = _FakeClock()
    monkeypatch.setattr(tqdm.std, "time", clock)

    class Stream(io.StringIO):
        def isatty(self):
            return tty

    out = Stream()
    bar = _progress_bar(10.0, file=out)
    for k in range(1, 1201):  # 120 s of wall time, 0.1 s apart
        clock.now += 0.1
        bar.update_to(10.0 * k / 1200, 5.0e5)
    bar.close()
    draws = out.getvalue().count("particle-steps/s")
    assert fewest <= draws <= most  # log: 120 s / 30 s plus the first and last; tty: 2 per s
    assert "t = 10.000/10.000 s" in out.getvalue()


def _status_row(capsys, out):
    """``sph status OUT``: exit status and the table's row of ``out`` as {column: value}."""
    rc = main(["status", str(out)])
    text = capsys.readouterr().out.splitlines()
    head = re.split(r"\s{2,}", text[0].strip())
    return rc, dict(zip(head, re.split(r"\s{2,}", text[1].strip()), strict=True))


def test_status_follows_a_run_to_its_end(case_file, tmp_path, capsys):
    """A run stopped at run.max_steps: the status reads the simulated time, step and wall
    time of its newest checkpoint, which is ahead of the output's last sample, the rate
    between its two checkpoints, the largest speed and density of its samples and the
    output's word on how it ended; resumed to the end, it reads t_end and "completed"."""
    from sph.io.checkpoint import checkpoint_dir, checkpoint_files
    from sph.io.status import (
        AVERAGE_AFTER,
        SILENT_FACTOR,
        SILENT_GRACE,
        format_table,
        run_status,
    )

    path = case_file("still_water")
    out = tmp_path / "still.nc"
    base = ["run", str(path), "-o", str(out), "--no-progress", *set_options(TINY_STILL_WATER),
            "--set", "run.output_interval=0.02"]
    assert main(base + ["--set", "run.max_steps=23", "--set", "run.checkpoint_interval=0.02"]) == 0
    capsys.readouterr()
    older, ckpt = checkpoint_files(checkpoint_dir(out))
    with np.load(older) as a:
        t_old, wall_old = float(a["t"]), float(a["wall_seconds"])
    with np.load(ckpt) as a:
        t_ckpt, wall = float(a["t"]), float(a["wall_seconds"])
        speeds = a["record.series.max_velocity"]
        densities = a["record.series.density_max"]
    with xr.open_dataset(out) as ds:
        t_out, steps = float(ds["time"].values[-1]), int(ds.attrs["steps"])
    assert steps == 23 and t_out < t_ckpt < 0.05

    st = run_status(out)
    assert (st.t, st.steps, st.t_end, st.wall_seconds) == (t_ckpt, 23, 0.05, wall)
    assert st.status.startswith("stopped at run.max_steps = 23")
    assert st.fraction == pytest.approx(t_ckpt / 0.05) and st.rate == 3600 * t_ckpt / wall
    assert 0.02 <= t_old < t_ckpt and wall_old < wall
    assert st.recent_rate == pytest.approx(3600 * (t_ckpt - t_old) / (wall - wall_old), rel=1e-12)
    assert st.hours_left is None  # the run has stopped
    # the largest speed and density of the samples so far, from the newer file
    assert len(speeds) > 1 and st.max_speed == speeds.max() > 0.0
    assert st.max_density == densities.max() > 990.0
    going = dataclasses.replace(st, status="running")  # as a partial output of a live run
    assert going.hours_left == pytest.approx((0.05 - t_ckpt) / st.recent_rate)
    # a run that writes every minute (run.flush_seconds; checkpoints every 10) and has
    # written nothing for far longer is not running: the table says so, and only for a run
    # that has not ended
    assert st.write_every == 60.0
    quiet = SILENT_FACTOR * 60.0 + SILENT_GRACE
    assert going.silent(going.updated + quiet - 1.0) is None
    assert going.silent(going.updated + quiet + 1.0) == pytest.approx(quiet + 1.0)
    assert st.silent(going.updated + 1.0e5) is None
    assert "not running: nothing written for 2.0 h" in format_table(
        [going], now=going.updated + 7200.0)
    assert "not running" not in format_table([going], now=going.updated + 60.0)
    # with one checkpoint the average rate tells the time left only after AVERAGE_AFTER s
    # of computing: before, it is mostly the run's start
    one = dataclasses.replace(going, recent_rate=None)
    assert one.hours_left is None and one.rate == st.rate
    later = dataclasses.replace(one, wall_seconds=AVERAGE_AFTER)
    assert later.hours_left == pytest.approx((0.05 - t_ckpt) / later.rate)
    rc, row = _status_row(capsys, out)
    rc_folder, row_folder = _status_row(capsys, checkpoint_dir(out))  # names its run
    assert rc_folder == 0 and row_folder["t (s)"] == row["t (s)"]
    assert row_folder["output"] == row["output"] == str(out)
    assert rc == 0 and row["case"] == "still_water" and row["steps"] == "23"
    assert row["t (s)"] == f"{t_ckpt:.2f}" and row["done"] == f"{100 * t_ckpt / 0.05:.1f} %"
    assert row["status"].startswith("stopped at run.max_steps") and ckpt.name in row["status"]
    assert row["max speed (m/s)"] == f"{speeds.max():.3g}"
    assert row["max density (kg/m3)"] == f"{densities.max():.5g}"

    assert main(base) == 0  # resumes from the checkpoint to t_end
    capsys.readouterr()
    st = run_status(out)
    assert st.status == "completed" and st.t == 0.05 and st.steps > 23 and st.hours_left is None
    with xr.open_dataset(out) as ds:
        assert st.max_speed == float(ds["max_velocity"].max()) >= speeds.max()
    rc, row = _status_row(capsys, out)
    assert rc == 0 and row["done"] == "100.0 %" and row["status"] == "completed"


def test_status_sums_up_a_sweep():
    """Below the table of two or more runs, one line: how many completed, are under way
    (the wall hours left at their rates, the longest and summed), have not started, or
    ended otherwise."""
    from sph.io.status import RunStatus, summary

    def run(status, t=0.0, recent=None, wall=0.0):
        return RunStatus(Path(f"{status}.nc"), "damaged_ship", status, t, 75.4, 0, wall,
                         None, "output", recent_rate=recent)

    rows = [run("completed", 75.4, wall=3600.0), run("running", 35.4, recent=20.0),
            run("started (no output written yet)", 55.4, recent=10.0), run("not started"),
            run("blew up at step 5 (t = 1 s): density")]
    assert summary(rows) == ("5 runs: 1 completed, 2 under way (2.0 h left at the longest, "
                             "4.0 h summed, at their rates), 1 not started, 1 ended otherwise "
                             "(stopped, blew up or failed: the table says)")
    # a run under way without a rate yet (just started) is counted, not timed
    rows[1] = run("running", 1.0, wall=10.0)
    assert "(2.0 h left at the longest, 2.0 h summed for 1 of them, at their rates)" in \
        summary(rows)
    assert summary(rows[:1]) == "1 run: 1 completed, 0 under way, 0 not started"


def test_status_of_runs_not_started_and_of_other_files(tmp_path, capsys):
    """An output path with neither file is a run not started; a folder lists its outputs
    (files and checkpoint folders); a file that is not a run's output is an error naming
    it (exit status 2), the other rows still printed."""
    from sph.io.status import find_outputs

    (tmp_path / "a.nc.ckpt").mkdir()
    (tmp_path / "b.txt").write_text("not an output\n")
    (tmp_path / "c.nc").write_text("not netCDF\n")
    assert find_outputs(tmp_path) == [tmp_path / "a.nc", tmp_path / "c.nc"]

    rc, row = _status_row(capsys, tmp_path / "later.nc")
    assert rc == 0 and row["status"] == "not started" and row["t (s)"] == "0.00"

    rc = main(["status", str(tmp_path / "later.nc"), str(tmp_path / "b.txt")])
    cap = capsys.readouterr()
    assert rc == 2 and "not started" in cap.out
    [line] = _stderr_lines(cap.err)
    assert line.startswith(f"error: {tmp_path / 'b.txt'}: not a netCDF file")
    rc = main(["status", str(tmp_path)])  # a.nc: checkpoint folder, empty; c.nc: an error
    cap = capsys.readouterr()
    assert rc == 2 and "not netCDF" not in cap.out and "c.nc: not a netCDF file" in cap.err
    assert "a.nc" in cap.out and "not started" in cap.out
    empty = tmp_path / "empty"
    empty.mkdir()
    assert main(["status", str(empty)]) == 2
    assert "no outputs" in capsys.readouterr().err
