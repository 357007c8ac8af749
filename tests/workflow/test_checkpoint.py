"""Checkpoints and restarts: a run stopped (max_steps, SIGINT, SIGTERM, SIGKILL) and resumed
gives the same numbers as an uninterrupted run, bit for bit; damaged or foreign checkpoints
are skipped or refused; output that cannot be written is a clear error.

Bit-identical: the checkpoint holds every particle array (both leapfrog levels and the
time derivatives of the last evaluation, in the sorted order), the wall-group kinematics
that evaluation used, the rigid-body and damage-opening states, the step counter (which
schedules the MLS and Euler steps) and the sampling schedule; resuming restores them and
does not evaluate again. Every kernel is a per-particle gather (no atomics) and the only
reductions are serial, so the thread count does not change the results either.
"""

from __future__ import annotations

import logging
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from physics_helpers import assert_same_series, set_options

from sph.cases import builtin
from sph.cli import main
from sph.driver import RunInterrupted, Simulation
from sph.io.checkpoint import (
    CheckpointError,
    CheckpointMismatch,
    NoCheckpoint,
    checkpoint_dir,
    checkpoint_files,
    find_checkpoint,
    load_checkpoint,
    restore,
    resume_or_start,
    start_from,
    write_checkpoint,
)
from sph.io.output import OutputWriteError, read_dataset
from sph.schema import ConfigError

ROOT = Path(__file__).resolve().parents[2]

#: the tiny damaged ship of the checkpoint tests
_SHIP = [
    "numerics.dx=0.25", "geometry.depth=3", "geometry.tank_length=12",
    "geometry.tank_height=5", "geometry.ship_x=6", "geometry.absorber.enabled=false",
    "geometry.hull={breadth: 3.0, depth: 2.0, draught: 1.0, bilge_radius: 0.3, "
    "plating: 0.1, kg: 0.8, gyradius: 1.0}",
    "geometry.wavemaker.amplitude=0.2", "geometry.wavemaker.omega=2.0",
    "geometry.damage.time_periods=0.05", "probes.surface=[{name: WP1, x: 3}]",
    "run.t_end=0.25", "run.output_interval=0.02",
]

# Tiny versions of the cases (a few hundred to two thousand particles, about a second each).
TINY = {
    "still_water": ("still_water", [
        "numerics.dx=0.1", "geometry.tank_length=1.0", "geometry.depth=0.5",
        "geometry.tank_height=0.8", "probes.pressure=[{name: b, x: 0.5, z: 0.0}]",
        "probes.surface=[{name: c, x: 0.5}]", "run.t_end=0.1", "run.output_interval=0.01",
    ]),
    "floating_box": ("floating_box", [
        "numerics.dx=0.025", "geometry.depth=0.3", "geometry.tank_length=1.0",
        "geometry.tank_height=0.45", "geometry.box_width=0.2", "geometry.box_height=0.1",
        "geometry.box_x=0.5", "geometry.box_inertia=null", "geometry.heave_offset=0.01",
        "geometry.absorber.enabled=false",
        "probes.surface=[{name: WP1, x: 0.25}]", "run.t_end=0.2", "run.output_interval=0.02",
    ]),
    "sloshing_delta": ("sloshing_rect", [
        "numerics.dx=0.05", "numerics.density_filter=delta", "run.t_end=0.2",
        "run.output_interval=0.02",
    ]),
    # a 3 m x 2 m hull in a 12 m tank; the opening appears at t1 = 0.157 s (step 141)
    "damaged_ship": ("damaged_ship", _SHIP),
    # the same with the wall damping: the normals' particles (listed_with) are rebuilt on resume
    "damaged_ship_damped": ("damaged_ship", [*_SHIP, "numerics.wall_damping=true"]),
    # particles created in the inflow region and removed beyond the outflow region
    "current_tank": ("current_tank", [
        "numerics.dx=0.05", "geometry.depth=0.2", "geometry.tank_length=0.5",
        "geometry.tank_height=0.4", "geometry.current.velocity=1.0",
        "geometry.absorber.enabled=true", "geometry.absorber.start=0.25",
        "geometry.absorber.length=0.25", "probes.surface=[{name: c, x: 0.25}]",
        "run.t_end=0.3", "run.output_interval=0.02",
    ]),
}


def _cfg(name, extra=()):
    case, overrides = TINY[name]
    return builtin(case, list(overrides) + list(extra))


_REFERENCE: dict[str, Simulation] = {}


def _reference(name) -> Simulation:
    """The uninterrupted run of a tiny case (computed once per session)."""
    if name not in _REFERENCE:
        _REFERENCE[name] = Simulation(_cfg(name)).run()
    return _REFERENCE[name]


def _stop_and_resume(name, tmp_path, stop_step, **resume_kw):
    """Run to ``stop_step`` with checkpoints, then resume in a fresh simulation."""
    ckpt = tmp_path / "out.nc.ckpt"
    first = Simulation(_cfg(name, [f"run.max_steps={stop_step}"]))
    first.run(tmp_path / "first.nc", checkpoint_dir=ckpt)
    assert first.step == stop_step and first.status.startswith("stopped at run.max_steps")
    second = Simulation(_cfg(name, resume_kw.get("extra", ())))
    path = resume_or_start(second, ckpt)
    assert path == ckpt / f"step-{stop_step:010d}.npz"
    assert second.step == stop_step and second.t == first.t
    second.run(tmp_path / "out.nc", checkpoint_dir=ckpt)
    return first, second


# --------------------------------------------------------------------------- bit-identical


@pytest.mark.parametrize("name", list(TINY))
def test_stop_half_way_and_resume_is_bit_identical(name, tmp_path):
    ref = _reference(name)
    _, resumed = _stop_and_resume(name, tmp_path, ref.step // 2)
    assert resumed.status == "completed" and resumed.step == ref.step
    assert np.array_equal(resumed.parts.f, ref.parts.f)
    assert np.array_equal(resumed.parts.i, ref.parts.i)
    assert_same_series(resumed.dataset(), ref.dataset())
    # and as written to disk
    assert_same_series(read_dataset(tmp_path / "out.nc"), ref.dataset())
    # a completed run deletes its checkpoints (run.keep_checkpoints = false)
    assert not (tmp_path / "out.nc.ckpt").exists()


def test_damaged_ship_resumes_before_and_after_the_opening(tmp_path):
    ref = _reference("damaged_ship")
    opening = ref.setup.opening
    # open, its plating deactivated (hidden across the hole), no particle removed
    assert opening.is_open and len(opening.opening_pids) > 0
    assert ref.parts.n == Simulation(_cfg("damaged_ship")).parts.n
    for stop in (100, 180):  # the opening appears at step 141
        d = tmp_path / str(stop)
        d.mkdir()
        first, resumed = _stop_and_resume("damaged_ship", d, stop)
        assert first.setup.opening.is_open == (stop > 141)
        assert resumed.setup.opening.is_open and resumed.setup.opening.params[0] == 1.0
        assert np.array_equal(resumed.parts.f, ref.parts.f)
        assert_same_series(resumed.dataset(), ref.dataset())


def _seed(tmp_path, name, steps, extra=()):
    """The checkpoint directory of the tiny ship with case-file values ``extra`` stopped
    after ``steps`` steps."""
    ckpt = tmp_path / f"{name}.nc.ckpt"
    Simulation(_cfg("damaged_ship", [*extra, f"run.max_steps={steps}"])).run(
        tmp_path / f"{name}.nc", checkpoint_dir=ckpt)
    return ckpt


def test_a_case_starts_from_the_state_of_another_opening_before_t1(tmp_path):
    """Before t1 the opening does nothing: the damaged ship started from the checkpoint of
    the intact ship, or of the other side's opening, at step 100 (the opening appears at
    step 141) runs to the same numbers, bit for bit, as from t = 0, and its output holds
    the seed's samples before the checkpoint."""
    ref = _reference("damaged_ship")
    for seed in (["geometry.damage.opening=0"], ["geometry.damage.side=head"]):
        ckpt = _seed(tmp_path, seed[0][16:20], 100, seed)
        sim = Simulation(_cfg("damaged_ship"))
        path = start_from(sim, ckpt)
        assert path == ckpt / "step-0000000100.npz" and sim.step == 100
        assert not sim.setup.opening.is_open
        sim.run(tmp_path / "out.nc")
        assert sim.setup.opening.is_open and sim.step == ref.step
        assert np.array_equal(sim.parts.f, ref.parts.f)
        assert np.array_equal(sim.parts.i, ref.parts.i)
        assert_same_series(read_dataset(tmp_path / "out.nc"), ref.dataset())
    # and the intact ship from the damaged one's state
    intact = Simulation(_cfg("damaged_ship", ["geometry.damage.opening=0"])).run()
    sim = Simulation(_cfg("damaged_ship", ["geometry.damage.opening=0"]))
    start_from(sim, _seed(tmp_path, "damaged", 100))
    sim.run()
    assert np.array_equal(sim.parts.f, intact.parts.f)
    assert not np.array_equal(intact.parts.f, ref.parts.f)  # the opening matters after t1


def test_a_start_from_another_case_past_t1_or_of_other_values_is_refused(tmp_path):
    sim = Simulation(_cfg("damaged_ship"))
    late = _seed(tmp_path, "late", 150, ["geometry.damage.opening=0"])  # past step 141
    with pytest.raises(CheckpointError, match="appears at t1 = 0.157"):
        start_from(sim, late)
    opened = _seed(tmp_path, "opened", 150)
    with pytest.raises(CheckpointError, match="DamageOpening had already acted"):
        start_from(Simulation(_cfg("damaged_ship", ["geometry.damage.opening=0"])), opened)
    other = _seed(tmp_path, "other", 20, ["numerics.alpha=0.05"])
    with pytest.raises(CheckpointMismatch, match="differ in geometry.damage.* alone") as info:
        start_from(Simulation(_cfg("damaged_ship")), other)
    assert info.value.keys == ["numerics.alpha"]
    with pytest.raises(NoCheckpoint, match="no checkpoint to start from"):
        start_from(sim, tmp_path / "missing")


def test_checkpoint_round_trip_restores_every_state(tmp_path):
    sim = Simulation(_cfg("floating_box", ["run.max_steps=57"])).run()
    path = write_checkpoint(sim, tmp_path)
    fresh = Simulation(_cfg("floating_box"))
    restore(fresh, load_checkpoint(path), path)
    assert np.array_equal(fresh.parts.f, sim.parts.f)
    assert np.array_equal(fresh.parts.i, sim.parts.i)
    assert np.array_equal(fresh.kin, sim.kin)
    for a, b in zip(fresh.stateful, sim.stateful, strict=True):
        sa, sb = a.get_state(), b.get_state()
        assert sa.keys() == sb.keys() and {"q", "v", "v_old", "a"} <= sa.keys()
        for key in sa:
            assert np.array_equal(sa[key], sb[key]), key
    for attr in ("t", "step", "dt", "volume0", "n_fluid", "next_output", "next_vtk",
                 "next_checkpoint", "wall_seconds", "warned_c0"):
        assert getattr(fresh, attr) == getattr(sim, attr), attr
    assert fresh.record.time == sim.record.time
    assert_same_series(fresh.dataset(), sim.dataset())
    assert fresh.restored_from == path


def test_re_evaluating_after_restore_would_not_be_identical(tmp_path):
    """Why the derivatives are stored: evaluating them again on resume uses the body's
    newer acceleration in the wall-pressure extrapolation and changes the result."""
    ref = _reference("floating_box")
    ckpt = tmp_path / "ckpt"
    Simulation(_cfg("floating_box", ["run.max_steps=300"])).run(checkpoint_dir=ckpt)
    naive = Simulation(_cfg("floating_box"))
    resume_or_start(naive, ckpt)
    naive.evaluate()
    naive.run()
    assert not np.array_equal(naive.parts.f, ref.parts.f)


def test_extend_a_finished_run_with_kept_checkpoints(tmp_path):
    ckpt = tmp_path / "ckpt"
    short = Simulation(_cfg("still_water", ["run.t_end=0.05", "run.keep_checkpoints=true"]))
    short.run(checkpoint_dir=ckpt)
    assert short.status == "completed"
    assert [p.name for p in checkpoint_files(ckpt)] == [f"step-{short.step:010d}.npz"]
    longer = Simulation(_cfg("still_water"))  # run.t_end = 0.1 may differ on resume
    assert resume_or_start(longer, ckpt) is not None
    longer.run(checkpoint_dir=ckpt)
    assert_same_series(longer.dataset(), _reference("still_water").dataset())


def test_checkpoints_by_simulated_time_keep_the_newest_two(tmp_path):
    ckpt = tmp_path / "ckpt"
    sim = Simulation(_cfg("still_water", ["run.checkpoint_interval=0.02", "run.max_steps=80"]))
    sim.run(checkpoint_dir=ckpt)
    files = checkpoint_files(ckpt)
    assert len(files) == 2  # the last by simulated time and the one at max_steps
    assert files[-1].name == "step-0000000080.npz"
    arrays = load_checkpoint(files[0])  # the first step at or after t = 0.08 s
    t, dt = float(arrays["t"]), float(arrays["dt"])
    assert 0.08 <= t < 0.08 + dt
    assert float(arrays["next_checkpoint"]) == pytest.approx(0.1)
    assert not list(ckpt.glob(".*"))  # no temporary files left


def test_vtk_snapshots_continue_after_resume(tmp_path):
    overrides = ["run.vtk_interval=0.02"]
    Simulation(_cfg("still_water", overrides)).run(vtk_dir=tmp_path / "ref")
    ckpt = tmp_path / "ckpt"
    Simulation(_cfg("still_water", overrides + ["run.max_steps=50"])).run(
        vtk_dir=tmp_path / "vtk", checkpoint_dir=ckpt)
    sim = Simulation(_cfg("still_water", overrides))
    resume_or_start(sim, ckpt)
    sim.run(vtk_dir=tmp_path / "vtk", checkpoint_dir=ckpt)
    pvd = "still_water.pvd"
    assert (tmp_path / "vtk" / pvd).read_text() == (tmp_path / "ref" / pvd).read_text()


# --------------------------------------------------------------------------- damaged files


def _two_checkpoints(tmp_path):
    ckpt = tmp_path / "out.nc.ckpt"
    Simulation(_cfg("still_water", ["run.checkpoint_interval=0.03", "run.max_steps=60"])).run(
        checkpoint_dir=ckpt)
    older, newest = checkpoint_files(ckpt)
    return ckpt, older, newest


@pytest.mark.parametrize("damage", ["truncated", "bit-flip", "empty", "not-an-archive"])
def test_damaged_checkpoint_is_skipped_for_the_previous_one(tmp_path, caplog, damage):
    ckpt, older, newest = _two_checkpoints(tmp_path)
    data = newest.read_bytes()
    if damage == "truncated":
        newest.write_bytes(data[: len(data) * 2 // 3])
    elif damage == "bit-flip":  # inside the particle data: only the checksum can tell
        newest.write_bytes(data[:1000] + bytes([data[1000] ^ 0x01]) + data[1001:])
    elif damage == "empty":
        newest.write_bytes(b"")
    else:
        newest.write_text("not a checkpoint\n")
    with pytest.raises(CheckpointError) as info:
        load_checkpoint(newest)
    assert str(newest) in str(info.value)
    with caplog.at_level(logging.WARNING, logger="sph.io.checkpoint"):
        sim = Simulation(_cfg("still_water"))
        assert resume_or_start(sim, ckpt) == older
    assert any(str(newest) in r.getMessage() and "skipping" in r.getMessage()
               for r in caplog.records)
    sim.run(checkpoint_dir=ckpt)  # the older checkpoint still leads to the same result
    assert_same_series(sim.dataset(), _reference("still_water").dataset())


def test_no_valid_checkpoint_starts_fresh_or_refuses(tmp_path, caplog):
    ckpt, older, newest = _two_checkpoints(tmp_path)
    for p in (older, newest):
        p.write_bytes(p.read_bytes()[:100])
    assert find_checkpoint(ckpt) is None
    with pytest.raises(NoCheckpoint, match="no valid checkpoint"):
        resume_or_start(Simulation(_cfg("still_water")), ckpt, "resume")
    with caplog.at_level(logging.WARNING, logger="sph.io.checkpoint"):
        sim = Simulation(_cfg("still_water"))
        assert resume_or_start(sim, ckpt) is None
    assert sim.step == 0 and sim.t == 0.0
    assert any("starting from t = 0" in r.getMessage() for r in caplog.records)


def test_checkpoint_of_another_config_is_refused_naming_the_key(tmp_path):
    ckpt, _, _ = _two_checkpoints(tmp_path)
    sim = Simulation(_cfg("still_water", ["numerics.alpha=0.05", "fluid.rho0=998"]))
    with pytest.raises(CheckpointMismatch) as info:
        resume_or_start(sim, ckpt)
    exc = info.value
    assert isinstance(exc, ConfigError)
    assert exc.keys == ["fluid.rho0", "numerics.alpha"]
    assert "numerics.alpha = 0.02 there, 0.05 here" in str(exc)
    assert "--restart" in str(exc)
    # keys that only say how long to run and what to write may change
    ok = Simulation(_cfg("still_water", ["run.t_end=0.2", "numerics.threads=1",
                                         "run.flush_seconds=5", "title=renamed"]))
    assert resume_or_start(ok, ckpt) is not None


def test_restart_mode_deletes_checkpoints(tmp_path):
    ckpt, _, _ = _two_checkpoints(tmp_path)
    sim = Simulation(_cfg("still_water"))
    assert resume_or_start(sim, ckpt, "restart") is None
    assert not ckpt.exists() and sim.step == 0


def test_stale_temporary_file_of_a_killed_writer_is_removed(tmp_path):
    ckpt, _, newest = _two_checkpoints(tmp_path)
    stale = ckpt / f".step-0000000099.npz.tmp-{os.getpid() + 1}"
    stale.write_bytes(newest.read_bytes()[:500])
    assert resume_or_start(Simulation(_cfg("still_water")), ckpt) == newest
    assert not stale.exists()


# --------------------------------------------------------------------------- signals


def _signal_at_step(monkeypatch, step, *signals):
    """Send ``signals`` to this process when the run reaches ``step`` (at a check)."""
    original = Simulation.check

    def check(self):
        original(self)
        if self.step == step:
            for sig in signals:
                os.kill(os.getpid(), sig)

    monkeypatch.setattr(Simulation, "check", check)


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_signal_writes_checkpoint_and_partial_output(tmp_path, monkeypatch, sig):
    _signal_at_step(monkeypatch, 40, sig)
    ckpt = tmp_path / "out.nc.ckpt"
    sim = Simulation(_cfg("sloshing_delta"))
    handler = signal.getsignal(sig)
    with pytest.raises(RunInterrupted) as info:
        sim.run(tmp_path / "out.nc", checkpoint_dir=ckpt)
    assert signal.getsignal(sig) == handler  # the run's handlers are removed again
    exc = info.value
    assert exc.step == 40 and exc.signal_name == sig.name
    assert exc.checkpoint == ckpt / "step-0000000040.npz" and exc.checkpoint.exists()
    ds = read_dataset(tmp_path / "out.nc")
    assert ds.attrs["status"].startswith(f"interrupted by {sig.name} at step 40")
    assert ds["time"].values[-1] <= exc.t
    monkeypatch.undo()
    resumed = Simulation(_cfg("sloshing_delta"))
    resume_or_start(resumed, ckpt)
    resumed.run(tmp_path / "out.nc", checkpoint_dir=ckpt)
    assert_same_series(read_dataset(tmp_path / "out.nc"), _reference("sloshing_delta").dataset())


def test_cli_signal_exits_4_and_second_signal_stops_at_once(tmp_path, monkeypatch, capsys,
                                                            case_file):
    path = case_file("still_water")
    out = tmp_path / "out.nc"
    argv = ["run", str(path), "-o", str(out), "--no-progress"] + set_options(TINY["still_water"][1])
    _signal_at_step(monkeypatch, 30, signal.SIGTERM)
    assert main(argv) == 4
    err = capsys.readouterr().err
    assert "interrupted by SIGTERM at step 30" in err and "run the same command again" in err
    assert checkpoint_files(checkpoint_dir(out))[-1].name == "step-0000000030.npz"
    # two signals: the second one stops at once (KeyboardInterrupt), still exit 4,
    # the checkpoint of the first interruption stays usable
    _signal_at_step(monkeypatch, 50, signal.SIGINT, signal.SIGINT)
    assert main(argv) == 4
    assert "interrupted at step 50" in capsys.readouterr().err
    assert checkpoint_files(checkpoint_dir(out))[-1].name == "step-0000000030.npz"


# --------------------------------------------------------------------------- command line


def _wait_for(predicate, timeout=600.0):
    end = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > end:
            raise AssertionError("timed out")
        time.sleep(0.002)


def _child(argv, threads=1):
    env = dict(os.environ, NUMBA_NUM_THREADS=str(threads), PYTHONPATH=str(ROOT))
    return subprocess.Popen([sys.executable, "-m", "sph.cli"] + argv, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)


LONGER = TINY["still_water"][1] + ["run.t_end=0.6", "run.checkpoint_interval=0.2"]

#: a sloshing tank with the ship cases' numerics, in which a pair loop compiled in the
#: process and one loaded from numba's cache part at round-off within the run
SHIP_NUMERICS_SLOSHING = ["numerics.density_filter=none", "numerics.shifting=1.0",
                          "numerics.wall_damping=true", "numerics.kernel=gaussian",
                          "run.t_end=0.5"]


@pytest.mark.slow
def test_a_first_run_computes_with_the_kernels_every_later_run_loads(tmp_path, case_file):
    """The first ``sph run`` of an engine on a machine (numba's cache empty) compiles its
    kernels, then starts again in a new process that loads them from the cache, so that it
    writes the same bits as every later run, a resumed one included (docs/checkpoints.md,
    "What is bit-identical"). Without the new start (``SPH_KERNELS_CACHED`` set, as the
    second process has it) the first run's last bits differ: the test can fail."""
    from sph.cli import RESTARTED_ENV

    path = case_file("sloshing_rect")

    def run(name, cache, restart=True):
        env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / cache), NUMBA_NUM_THREADS="1")
        env.pop(RESTARTED_ENV, None)
        if not restart:
            env[RESTARTED_ENV] = "1"
        out = tmp_path / f"{name}.nc"
        proc = subprocess.run([sys.executable, "-m", "sph.cli", "run", str(path), "-o",
                               str(out), "--no-progress"]
                              + set_options(SHIP_NUMERICS_SLOSHING), env=env,
                              capture_output=True, text=True)
        assert proc.returncode == 0, proc.stderr
        return read_dataset(out), proc.stderr

    first, log = run("first", "cache")
    assert "starting again with them from numba's cache" in log
    later, log = run("later", "cache")
    assert "starting again" not in log and "compiled itself" not in log
    assert_same_series(first, later)
    fresh, log = run("fresh", "other-cache", restart=False)
    assert "parallel kernels it compiled itself" in log
    assert not np.array_equal(fresh["kinetic_energy"].values, later["kinetic_energy"].values)


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM], ids=["SIGKILL", "SIGTERM"])
def test_cli_killed_process_resumes_to_the_same_result(tmp_path, case_file, caplog, capsys,
                                                       sig):
    """``sph run`` in a child process (two threads) is killed after its first checkpoint;
    the same command run again (here, one thread) resumes and ends with the same file
    contents as an uninterrupted run."""
    path = case_file("still_water")
    out = tmp_path / "killed" / "out.nc"
    argv = ["run", str(path), "-o", str(out), "--no-progress"] + set_options(LONGER)
    child = _child(argv, threads=2)
    ckpt = checkpoint_dir(out)
    try:
        _wait_for(lambda: child.poll() is not None or checkpoint_files(ckpt))
        child.send_signal(sig)
        _, err = child.communicate(timeout=600)
    finally:
        child.kill()
    if sig == signal.SIGKILL:
        assert child.returncode == -signal.SIGKILL
    else:
        assert child.returncode == 4, err.decode()
        assert b"interrupted by SIGTERM" in err
        assert read_dataset(out).attrs["status"].startswith("interrupted by SIGTERM")
    first = checkpoint_files(ckpt)[0]
    assert first.name < "step-0000000540.npz"  # stopped before the end (540 steps)
    with caplog.at_level(logging.INFO, logger="sph"):
        assert main(argv + ["--threads", "1"]) == 0, capsys.readouterr().err
    resume = [r.getMessage() for r in caplog.records if "resuming from" in r.getMessage()]
    assert len(resume) == 1 and "at t = 0.2" in resume[0] and str(ckpt) in resume[0]
    assert not ckpt.exists()
    ref_out = tmp_path / "ref" / "out.nc"
    assert main(argv[:3] + [str(ref_out)] + argv[4:]) == 0
    a, b = read_dataset(out), read_dataset(ref_out)
    assert_same_series(a, b)
    assert a.attrs["threads"] == 1 and a.attrs["status"] == "completed"


def test_cli_restart_flags(tmp_path, case_file, caplog, capsys):
    path = case_file("still_water")
    out = tmp_path / "out.nc"
    base = ["run", str(path), "-o", str(out), "--no-progress"]
    sets = set_options(TINY["still_water"][1])
    # --no-restart refuses to start from t = 0
    assert main(base + ["--no-restart"] + sets) == 2
    assert "no checkpoint to resume from" in capsys.readouterr().err
    assert main(base + sets + ["--set", "run.max_steps=40"]) == 0
    assert checkpoint_files(checkpoint_dir(out))
    # --restart and --no-restart exclude each other
    with pytest.raises(SystemExit):
        main(base + ["--restart", "--no-restart"] + sets)
    capsys.readouterr()
    with caplog.at_level(logging.INFO, logger="sph"):
        assert main(base + ["--restart"] + sets) == 0
    assert not any("resuming" in r.getMessage() for r in caplog.records)
    assert not checkpoint_dir(out).exists()
    # a checkpoint of another configuration: exit 2, one line naming the key
    assert main(base + sets + ["--set", "run.max_steps=40"]) == 0
    capsys.readouterr()
    assert main(base + sets + ["--set", "numerics.cfl=0.1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: numerics.cfl:") and len(err.strip().splitlines()) == 1
    assert main(base + ["--no-restart"] + sets) == 0  # resumes


def test_cli_start_from_another_run(tmp_path, case_file, caplog, capsys):
    path = case_file("damaged_ship")
    sets = set_options(_SHIP)
    seed = tmp_path / "seed.nc"
    assert main(["run", str(path), "-o", str(seed), "--no-progress", *sets, "--set",
                 "geometry.damage.opening=0", "--set", "run.max_steps=100"]) == 0
    base = ["run", str(path), "-o", str(tmp_path / "out.nc"), "--no-progress", *sets]
    with caplog.at_level(logging.INFO, logger="sph"):
        assert main(base + ["--start-from", str(checkpoint_dir(seed)), "--set",
                            "run.max_steps=120"]) == 0
    assert any("starting from checkpoint" in r.getMessage() and "step 100" in r.getMessage()
               for r in caplog.records)
    # with checkpoints of its own the run resumes from them
    caplog.clear()
    with caplog.at_level(logging.INFO, logger="sph"):
        assert main(base + ["--start-from", str(checkpoint_dir(seed))]) == 0
    assert any("resuming" in r.getMessage() and "step 120" in r.getMessage()
               for r in caplog.records)
    assert_same_series(read_dataset(tmp_path / "out.nc"), _reference("damaged_ship").dataset())
    # another case's values: exit 2, one line naming the key
    capsys.readouterr()
    assert main(base + ["--restart", "--start-from", str(checkpoint_dir(seed)), "--set",
                        "numerics.cfl=0.1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: cannot start from") and "numerics.cfl" in err
    assert len(err.strip().splitlines()) == 1


def test_cli_export_writes_the_series_so_far_from_a_checkpoint(tmp_path, case_file, capsys):
    """``sph export`` gives the output a run had at its checkpoint: the same series as the
    run's own output when it stopped there, and the first samples of the uninterrupted run."""
    path = case_file("still_water")
    out = tmp_path / "out.nc"
    sets = set_options(TINY["still_water"][1])
    assert main(["run", str(path), "-o", str(out), "--no-progress", *sets,
                 "--set", "run.max_steps=40"]) == 0
    part = tmp_path / "part" / "part.nc"
    assert main(["export", str(checkpoint_dir(out)), "-o", str(part)]) == 0
    exported = read_dataset(part)
    assert_same_series(exported, read_dataset(out))
    n = exported.sizes["time"]
    ref = _reference("still_water").dataset()
    assert 1 < n < ref.sizes["time"]
    assert_same_series(exported, ref.isel(time=slice(0, n)))
    assert exported.attrs["status"].startswith("exported from checkpoint")
    assert "step-0000000040.npz" in exported.attrs["status"]
    # the same from the checkpoint file
    again = tmp_path / "again.nc"
    assert main(["export", str(checkpoint_files(checkpoint_dir(out))[-1]), "-o",
                 str(again)]) == 0
    assert_same_series(read_dataset(again), exported)
    capsys.readouterr()
    # refused, one line each: the run's own output, nothing there, no valid checkpoint
    assert main(["export", str(checkpoint_dir(out)), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "the run's own output" in err and len(err.strip().splitlines()) == 1
    assert main(["export", str(tmp_path / "none.nc.ckpt"), "-o", str(again)]) == 2
    assert "no checkpoint at" in capsys.readouterr().err
    (tmp_path / "empty.nc.ckpt").mkdir()
    assert main(["export", str(tmp_path / "empty.nc.ckpt"), "-o", str(again)]) == 2
    assert "no valid checkpoint in" in capsys.readouterr().err


def test_cli_unwritable_output_directory(tmp_path, case_file, capsys, monkeypatch):
    path = case_file("still_water")
    blocker = tmp_path / "file"
    blocker.write_text("x")
    rc = main(["run", str(path), "-o", str(blocker / "out.nc"), "--no-progress"]
              + set_options(TINY["still_water"][1]))
    assert rc == 5
    err = capsys.readouterr().err
    assert err.startswith("error: cannot write to the output directory")
    assert "nothing was computed" in err
    assert blocker.read_text() == "x"


@pytest.mark.skipif(hasattr(os, "geteuid") and os.geteuid() == 0,
                    reason="root ignores directory permissions")
def test_cli_read_only_output_directory(tmp_path, case_file, capsys):
    path = case_file("still_water")
    locked = tmp_path / "locked"
    locked.mkdir()
    (locked / "old.nc").write_text("previous")
    locked.chmod(0o500)
    try:
        rc = main(["run", str(path), "-o", str(locked / "old.nc"), "--no-progress"]
                  + set_options(TINY["still_water"][1]))
    finally:
        locked.chmod(0o700)
    assert rc == 5 and "cannot write" in capsys.readouterr().err
    assert (locked / "old.nc").read_text() == "previous"


def test_cli_disk_full_keeps_previous_files_and_resumes(tmp_path, case_file, capsys,
                                                        monkeypatch):
    """A full disk at the end of a run (simulated: writing fails with ENOSPC): exit 5, the
    previous output file and the checkpoints are intact; once there is space again the
    same command resumes."""
    import errno

    path = case_file("still_water")
    out = tmp_path / "out.nc"
    argv = ["run", str(path), "-o", str(out), "--no-progress"] + set_options(
        TINY["still_water"][1] + ["run.checkpoint_interval=0.05"])
    out.write_bytes(b"previous result")

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(xr.Dataset, "to_netcdf", full)
    assert main(argv) == 5
    err = capsys.readouterr().err
    assert "disk full" in err and str(out) in err
    assert out.read_bytes() == b"previous result"
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []
    kept = checkpoint_files(checkpoint_dir(out))
    assert kept and load_checkpoint(kept[-1])
    monkeypatch.undo()
    assert main(argv) == 0
    assert_same_series(read_dataset(out), _reference("still_water").dataset())


def test_checkpoint_write_failure_keeps_previous_checkpoints(tmp_path, monkeypatch):
    import errno

    ckpt, older, newest = _two_checkpoints(tmp_path)
    before = {p.name: p.read_bytes() for p in (older, newest)}
    sim = Simulation(_cfg("still_water"))
    resume_or_start(sim, ckpt)

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(np, "savez", full)
    with pytest.raises(OutputWriteError, match="disk full"):
        write_checkpoint(sim, ckpt)
    assert {p.name: p.read_bytes() for p in ckpt.iterdir()} == before


def test_blow_up_keeps_output_and_checkpoints(tmp_path, case_file, capsys):
    """A blow-up (too large a time step) stops with step, time and cause; the output up to
    that point is readable; the checkpoints written before stay (exit 3)."""
    path = case_file("dam_break")
    out = tmp_path / "dam.nc"
    argv = ["run", str(path), "-o", str(out), "--no-progress"] + set_options([
        "numerics.dx=0.1", "numerics.cfl=0.5", "numerics.c_factor=3", "run.t_end=1.5",
        "run.density_max=1.15", "run.checkpoint_interval=0.05"])
    assert main(argv) == 3
    err = capsys.readouterr().err
    found = re.search(r"simulation stopped at step (\d+), t = ([0-9.]+) s: fluid density", err)
    assert found, err
    step, t_stop = int(found.group(1)), float(found.group(2))
    assert 0.1 < t_stop < 1.5
    ds = read_dataset(out)
    assert ds.attrs["status"].startswith(f"failed: simulation stopped at step {step}")
    assert t_stop - 0.011 < ds["time"].values[-1] <= t_stop
    kept = checkpoint_files(checkpoint_dir(out))
    assert kept and t_stop - 0.06 < float(load_checkpoint(kept[-1])["t"]) <= t_stop
    # the blow-up checks may be loosened to carry on from the last checkpoint
    t_more = round(t_stop + 0.1, 2)
    assert main(argv + ["--set", "run.density_max=1.3", "--set", f"run.t_end={t_more}"]) == 0
    assert read_dataset(out)["time"].values[-1] == pytest.approx(t_more, abs=0.011)
