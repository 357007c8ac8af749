"""Tests of the Snakemake workflow: dry runs of the default sweep, refused configurations,
lint, the toy configuration (.test/) run end to end with the report, and a workflow killed
during a case that resumes it from its checkpoint.

Each test runs snakemake in a copy of the workflow (Snakefile, config/, workflow/, .test/) in a
temporary folder, with the interpreter running the tests; the rules call the engine as `sph`
(the console script of the installed package; a stand-in calling ``python -m sph.cli`` is put
on PATH when the package is only importable).
"""

from __future__ import annotations

import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml
from physics_helpers import assert_same_series

from sph.io.checkpoint import checkpoint_files
from sph.io.output import read_dataset
from sph.schema import ConfigError
from sph.study.analysis import validation_data_dir
from sph.study.sweeps import check_documents, load_sweep, ship_overrides, validation_runs

ROOT = Path(__file__).resolve().parents[2]
N_TABLE_ONE = 8


def _env(tmp: Path) -> dict:
    env = dict(os.environ)
    path = [str(Path(sys.executable).parent)]
    if shutil.which("sph", path=os.pathsep.join(path + [env.get("PATH", "")])) is None:
        shim = tmp / "bin"
        shim.mkdir(exist_ok=True)
        (shim / "sph").write_text(f'#!/bin/sh\nexec "{sys.executable}" -m sph.cli "$@"\n')
        (shim / "sph").chmod(0o755)
        path.insert(0, str(shim))
    env["PATH"] = os.pathsep.join(path + [env.get("PATH", "")])
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT)] + [p for p in [env.get("PYTHONPATH")] if p])
    return env


def _workflow_copy(tmp: Path) -> Path:
    work = tmp / "wf"
    work.mkdir()
    shutil.copy(ROOT / "Snakefile", work)
    for d in ("config", "workflow", "profiles", ".test"):
        shutil.copytree(ROOT / d, work / d, ignore=shutil.ignore_patterns("__pycache__"))
    return work


def _snakemake(work: Path, *args, timeout=900) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "snakemake", *args], cwd=work,
                          env=_env(work.parent), capture_output=True, text=True,
                          timeout=timeout)


def _job_counts(output: str) -> dict[str, int]:
    """The `Job stats` table of a dry run: rule -> number of jobs."""
    counts = {}
    table = output.split("Job stats:")[-1]
    for line in table.splitlines():
        m = re.match(r"^([A-Za-z_]\w*)\s+(\d+)$", line.strip())
        if m and m.group(1) != "total":
            counts[m.group(1)] = int(m.group(2))
    return counts


@pytest.fixture(scope="module")
def work(tmp_path_factory):
    return _workflow_copy(tmp_path_factory.mktemp("workflow"))


def test_dry_run_lists_the_table_one_simulations(work):
    res = _snakemake(work, "-n")
    assert res.returncode == 0, res.stderr + res.stdout
    counts = _job_counts(res.stdout)
    assert counts["simulate_case"] == N_TABLE_ONE
    assert counts["case_file"] == N_TABLE_ONE
    # one wave in Table I: one wavemaker calibration, which every case file waits for, and
    # the case file of the run to t1 that cases 1-5 share (they differ in the opening alone)
    assert counts["calibrate_wavemaker"] == 1
    assert res.stdout.count("input: results/table1/calibration/A2_w1.json") == N_TABLE_ONE + 1
    assert counts["simulate_predamage"] == counts["predamage_case_file"] == 1
    shared = re.findall(r"input: results/table1/cases/(case\d)\.yaml, "
                        r"results/table1/predamage/predamage_case1\.nc\n", res.stdout)
    assert sorted(shared) == [f"case{k}" for k in range(1, 6)]
    # validation: wave tank at 3 dx, sloshing at 3 fills, roll and heave decay, box, dam break
    assert counts["simulate_validation"] == 10
    for rule in ("gather", "findings", "validation_summary", "overview_figure", "all"):
        assert counts[rule] == 1
    assert counts["ship_figure"] == 10  # Figs. 12-15, 17-19, 21-23; Fig. 10 needs amplitudes
    assert "rao_figure" not in counts  # one wave frequency: no response over frequency
    # one rule for the validation figures: Fig. 7, the wave profile, sloshing, decay, box, dam
    assert counts["validation_figure"] == 6
    for name in ("fig07_wave_tank", "fig_wave_profile", "fig_sloshing", "fig_decay",
                 "fig_floating_box", "fig_dam_break"):
        assert f"results/validation/coarse/figures/{name}.png" in res.stdout
    for k in range(1, N_TABLE_ONE + 1):
        assert f"results/table1/cases/case{k}.nc" in res.stdout
    assert not (work / "results").exists()


def test_dry_run_of_the_example_sweep(work):
    res = _snakemake(work, "-n", "--configfile", "config/sweeps/openings_fill.yaml")
    assert res.returncode == 0, res.stderr + res.stdout
    counts = _job_counts(res.stdout)
    assert counts["simulate_case"] == 13
    assert "simulate_validation" not in counts
    assert "results/openings_fill/openings_fill.nc" in res.stdout


def test_dry_run_of_the_wave_amplitude_sweep(work):
    res = _snakemake(work, "-n", "--configfile", "config/sweeps/wave_amplitude.yaml")
    assert res.returncode == 0, res.stderr + res.stdout
    counts = _job_counts(res.stdout)
    assert counts["simulate_case"] == 5
    assert counts["calibrate_wavemaker"] == 4  # one per wave; none for still water
    assert counts["ship_figure"] == 1  # only Fig. 10 compares these cases
    assert "results/wave_amplitude/figures/fig10_amplitude.png" in res.stdout


def test_dry_run_of_the_roll_rao_sweep(work):
    """The response over wave frequency: 22 ship runs (intact and damaged at 11 frequencies),
    one calibration per wave, the response figure, and the paper's figures of the two cases
    at Table I's wave."""
    res = _snakemake(work, "-n", "--configfile", "config/sweeps/roll_rao.yaml")
    assert res.returncode == 0, res.stderr + res.stdout
    counts = _job_counts(res.stdout)
    assert counts["simulate_case"] == counts["case_file"] == 22
    assert counts["calibrate_wavemaker"] == 11
    assert counts["simulate_predamage"] == 11  # each wave's intact and damaged ship share
    assert counts["rao_figure"] == 1 and counts["ship_figure"] == 4  # Figs. 12-15
    assert "simulate_validation" not in counts
    for out in ("results/roll_rao/figures/rao.png", "results/roll_rao/rao.csv",
                "results/roll_rao/calibration/A4.78447_w0.6.json",
                "results/roll_rao/calibration/A2_w1.json",
                "results/roll_rao/cases/damaged_w140.nc"):
        assert out in res.stdout, out
    assert not (work / "results").exists()


def test_dry_run_without_the_calibration(work):
    res = _snakemake(work, "-n", "--config", "calibrate_wavemaker=false")
    assert res.returncode == 0, res.stderr + res.stdout
    counts = _job_counts(res.stdout)
    assert "calibrate_wavemaker" not in counts and counts["case_file"] == N_TABLE_ONE


def test_presets_select_the_resolution(work):
    res = _snakemake(work, "-n", "--config", "preset=paper")
    assert res.returncode == 0, res.stderr + res.stdout
    assert "results/validation/paper/wave_tank/res3.nc" in res.stdout


BAD = {
    "unknown key": ({"fil": 0.5}, "fil: unknown key"),
    "fill 1.5": ({"cases": [{"case": "a", "opening": 0.5, "side": "back", "fill": 1.5}]},
                 "cases[0].fill: must be in [0, 1); got 1.5"),
    "unknown side": ({"cases": [{"case": "a", "opening": 0.5, "side": "port", "fill": 0}]},
                     "cases[0].side: unknown side 'port'"),
    "duplicate case id": ({"cases": [{"case": "a", "opening": 0.5, "side": "back", "fill": 0},
                                     {"case": "a", "opening": 0.3, "side": "back", "fill": 0}]},
                          "cases[1].case: duplicate case id 'a'"),
    "unknown column": ({"cases": [{"case": "a", "opening": 0.5, "side": "back", "fill": 0,
                                   "speed": 2}]}, "cases[0].speed: unknown key"),
    "unknown preset": ({"preset": "fine"}, "preset: unknown preset 'fine'"),
    "breaking wave": ({"cases": [{"case": "a", "opening": 0.5, "side": "back", "fill": 0,
                                  "omega": 2.0}]},
                      "cases[0].omega: the wave of amplitude A = 2 m at omega = 2 rad/s"),
    "opening above the waterline": (
        {"cases": [{"case": "a", "opening": 0.99, "side": "back", "fill": 0}]},
        "case 'a': geometry.damage.opening"),
}


def _refusal(settings: dict) -> str:
    """What the workflow's start (workflow/rules/common.smk) refuses the default
    configuration with ``settings`` on top for, without a Snakemake process: the sweep's keys
    (:func:`load_sweep`), then every run's case file (:func:`check_documents`)."""
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    config.update({"sweep": "bad", **settings})
    try:
        sweep = load_sweep(config, ROOT)
        ship = {c["case"]: ship_overrides(c, sweep) for c in sweep["cases"]}
        check_documents(ship, validation_runs(sweep, validation_data_dir()))
    except ConfigError as exc:
        return str(exc)
    return ""


@pytest.mark.parametrize("name", list(BAD))
def test_bad_sweep_is_refused_naming_the_key(name):
    settings, message = BAD[name]
    assert message in _refusal(settings)


# one refusal of each kind through Snakemake: of the sweep's keys, and of a run's case file
@pytest.mark.parametrize("name", ["fill 1.5", "opening above the waterline"])
def test_bad_sweep_is_refused_before_any_job(work, name):
    settings, message = BAD[name]
    bad = work / f"bad_{name.replace(' ', '_')}.yaml"
    bad.write_text(yaml.safe_dump(dict({"sweep": "bad"}, **settings)))
    res = _snakemake(work, "-n", "--configfile", bad.name)
    assert res.returncode != 0
    text = res.stdout + res.stderr
    assert "invalid sweep configuration" in text and message in text, text
    assert not (work / "results").exists()


def test_lint_is_clean(work):
    res = _snakemake(work, "--lint")
    assert res.returncode == 0, res.stdout + res.stderr
    assert "Congratulations, your workflow is in a good condition!" in res.stdout + res.stderr


# ------------------------------------------------------------------------------ toy run
@pytest.fixture(scope="module")
def toy(tmp_path_factory):
    """The workflow test configuration run to the end, with the report."""
    work = _workflow_copy(tmp_path_factory.mktemp("toy"))
    start = time.perf_counter()
    res = _snakemake(work, "--cores", "2", "--configfile", ".test/config.yaml")
    wall = time.perf_counter() - start
    assert res.returncode == 0, res.stdout[-6000:] + res.stderr[-6000:]
    rep = _snakemake(work, "--report", "report.html", "--configfile", ".test/config.yaml")
    assert rep.returncode == 0, rep.stdout[-3000:] + rep.stderr[-3000:]
    print(f"toy workflow: {wall:.0f} s wall")
    return work


def test_toy_workflow_writes_the_sweep_dataset(toy):
    cases = [ln.split("\t")[0] for ln in (toy / ".test" / "cases.tsv").read_text().splitlines()
             if ln and not ln.startswith(("#", "case\t"))]
    with xr.open_dataset(toy / "results" / "test" / "test.nc") as ds:
        assert list(ds["case"].values) == cases
        for name in ("opening", "side", "fill", "amplitude"):
            assert ds[name].dims == ("case",)
        for name in ("roll", "heave", "flood_ratio", "probe_elevation"):
            assert "case" in ds[name].dims and "time" in ds[name].dims
        assert ds.attrs["Conventions"] == "CF-1.10"
        assert ds["time"].attrs["units"] == "s"
        assert ds["roll"].attrs["units"] == "degree"
        assert ds.attrs["sweep"] == "test" and ds.attrs["preset"] == "toy"
    for case in cases:  # logs and benchmarks of every run
        assert (toy / "results" / "test" / "benchmarks" / "simulate" / f"{case}.tsv").is_file()
        assert "done:" in (toy / "results" / "test" / "logs" / "simulate" /
                           f"{case}.log").read_text()
    # cases 1-5 differ in the opening alone: they start from the shared run to t1, whose
    # samples they hold (sph.study.sweeps.predamage_runs)
    shared = toy / "results" / "test" / "predamage" / "predamage_case1.nc"
    seed = read_dataset(shared)
    assert seed.attrs["opening"] == 0.0 and seed["time"].values[-1] < seed.attrs["damage_time"]
    for case in ("case1", "case2", "case3", "case5"):
        log = (toy / "results" / "test" / "logs" / "simulate" / f"{case}.log").read_text()
        assert f"starting from checkpoint {shared.relative_to(toy)}.ckpt/step-" in log, log
        run = read_dataset(toy / "results" / "test" / "cases" / f"{case}.nc")
        for name in ("roll", "heave", "sway", "flood_ratio"):
            np.testing.assert_array_equal(run[name].values[:seed.sizes["time"]],
                                          seed[name].values)
    for case in ("case6", "case7"):
        assert "starting from" not in (toy / "results" / "test" / "logs" / "simulate" /
                                       f"{case}.log").read_text()
    findings = (toy / "results" / "test" / "findings.csv").read_text().splitlines()
    assert findings[0].startswith("id,statement")
    ids = [ln.split(",")[0] for ln in findings[1:]]
    assert ids == [f"F{i}" for i in range(1, 21)]  # every finding reported, once, in order
    spectra = (toy / "results" / "test" / "spectra.csv").read_text().splitlines()
    assert spectra[0] == ("case,record,peak,frequency_over_omega,amplitude,unit,window_start,"
                          "window_end")
    assert {ln.split(",")[0] for ln in spectra[1:]} <= set(cases)


def test_toy_report_shows_every_figure_and_table(toy):
    html = (toy / "report.html").read_text(errors="replace")
    figures = sorted((toy / "results" / "test" / "figures").glob("*.png"))
    figures += sorted((toy / "results" / "validation" / "toy" / "figures").glob("*.png"))
    assert len(figures) >= 15
    for fig in figures:
        assert fig.name in html, fig.name
    assert "findings.html" in html and "validation.html" in html


def test_toy_rerun_has_nothing_to_do(toy):
    res = _snakemake(toy, "-n", "--configfile", ".test/config.yaml")
    assert res.returncode == 0
    assert "Nothing to be done" in res.stdout + res.stderr


def test_changing_one_case_reruns_only_that_case(toy):
    table = toy / ".test" / "cases.tsv"
    original = table.read_text()
    changed = original.replace("case6\t10/21\tback\t0.25", "case6\t10/21\tback\t0.3")
    assert changed != original
    table.write_text(changed)
    try:
        res = _snakemake(toy, "-n", "--configfile", ".test/config.yaml")
    finally:
        table.write_text(original)
    assert res.returncode == 0, res.stdout + res.stderr
    counts = _job_counts(res.stdout)
    assert counts["case_file"] == 1 and counts["simulate_case"] == 1
    assert "results/test/cases/case6.nc" in res.stdout
    assert not re.search(r"output: results/test/cases/case[^6]\.nc", res.stdout)
    assert counts["gather"] == 1 and counts["findings"] == 1
    for rule in ("simulate_validation", "validation_case_file", "validation_summary"):
        assert rule not in counts


def _workflow_until_checkpoint(tmp_path, settings: dict, target: str):
    """A copy of the workflow whose toy sweep takes ``settings`` (case-file values),
    started in a session of its own (its pid is the session's id) on ``target`` alone, one
    core, and left running once the case has written a checkpoint. Returns the copy, the
    process, its Snakemake arguments and the checkpoint folder."""
    work = _workflow_copy(tmp_path)
    sweep = yaml.safe_load((work / ".test" / "config.yaml").read_text())
    sweep["set"] = settings
    (work / ".test" / "stop.yaml").write_text(yaml.safe_dump(sweep))
    args = [target, "--cores", "1", "--configfile", ".test/stop.yaml"]
    env = dict(_env(tmp_path), NUMBA_NUM_THREADS="1")
    wf = subprocess.Popen([sys.executable, "-m", "snakemake", *args], cwd=work, env=env,
                          start_new_session=True, stdout=subprocess.DEVNULL,
                          stderr=subprocess.DEVNULL)
    ckpt = work / (target + ".ckpt")
    try:
        end = time.monotonic() + 600
        while wf.poll() is None and not checkpoint_files(ckpt):
            assert time.monotonic() < end, "no checkpoint written"
            time.sleep(0.002)
    except BaseException:
        os.killpg(wf.pid, signal.SIGKILL)
        wf.wait()
        raise
    return work, wf, args, ckpt


@pytest.mark.slow  # 30 s; the engine's own kill-and-resume tests (test_checkpoint.py) stay
def test_killed_workflow_resumes_the_case_from_its_checkpoint(tmp_path):
    """Issue: a workflow killed during a case (SIGKILL to Snakemake and its job, as a
    pre-empted node) and run again with ``--rerun-incomplete`` resumes the case from the
    engine's checkpoint through the project's own rules; the case's log shows the resume
    time and its dataset equals an uninterrupted run's, bit for bit (the checkpoint holds
    the complete state, open damage opening included: ``tests/test_checkpoint.py``)."""
    # checkpoints every 0.5 s of simulated time; the opening appears before the first
    target = "results/test/cases/case3.nc"
    work, wf, args, ckpt = _workflow_until_checkpoint(
        tmp_path, {"run.checkpoint_interval": 0.5, "geometry.damage.time_periods": 0.05},
        target)
    try:
        os.killpg(wf.pid, signal.SIGKILL)
        wf.wait(timeout=60)
    finally:
        wf.kill()
    assert wf.returncode == -signal.SIGKILL, "the case finished before it could be killed"
    assert checkpoint_files(ckpt) and not (work / target).exists()
    assert _snakemake(work, "--unlock", *args).returncode == 0
    res = _snakemake(work, "--rerun-incomplete", *args)
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
    log = (work / "results/test/logs/simulate/case3.log").read_text()
    assert f"resuming from checkpoint {target}.ckpt/step-" in log, log
    assert " at t = 0.5" in log, log
    assert not ckpt.exists()  # a completed run removes its checkpoints
    # the uninterrupted run in a process of its own, as the workflow runs each case
    ref = tmp_path / "ref.nc"
    run = subprocess.run([sys.executable, "-m", "sph.cli", "run",
                          str(work / "results/test/cases/case3.yaml"), "-o", str(ref),
                          "--no-progress"], env=_env(tmp_path), capture_output=True, text=True)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    assert_same_series(read_dataset(work / target), read_dataset(ref))


def _processes_of_session(sid: int, *words: str) -> list[int]:
    """Pids of the processes of session ``sid`` whose command line holds every word."""
    out = []
    for d in Path("/proc").iterdir():
        if not d.name.isdigit():
            continue
        try:
            if os.getsid(int(d.name)) != sid:
                continue
            cmd = (d / "cmdline").read_bytes().split(b"\0")
        except (OSError, ProcessLookupError):
            continue
        args = [a.decode(errors="replace") for a in cmd]
        if all(any(w in a for a in args) for w in words):
            out.append(int(d.name))
    return out


@pytest.mark.skipif(not Path("/proc/self/cmdline").exists(), reason="needs /proc")
def test_a_run_stopped_by_sigterm_is_rerun_not_taken_for_done(tmp_path):
    """Issue: a case whose run is stopped gracefully (SIGTERM to the run, as a cluster's
    time limit or a kill sends it: the engine checkpoints and exits with 4) fails its job,
    and the next call reruns the case from its checkpoint. Under the profile's former
    ``keep-incomplete`` Snakemake kept the partial netCDF file and recorded it as finished:
    the next call had "nothing to be done" and the sweep would have gathered the partial
    series as the case's result."""
    target = "results/test/cases/case1.nc"
    work, wf, args, ckpt = _workflow_until_checkpoint(
        tmp_path, {"run.checkpoint_interval": 0.5}, target)
    try:
        runs = _processes_of_session(wf.pid, "run", "case1.yaml")
        assert runs, "the case finished before it could be stopped"
        for pid in runs:
            os.kill(pid, signal.SIGTERM)
        wf.wait(timeout=300)
    finally:
        if wf.poll() is None:
            os.killpg(wf.pid, signal.SIGKILL)
            wf.wait()
    assert wf.returncode != 0  # the job failed: its case was not done
    log = (work / "results/test/logs/simulate/case1.log").read_text()
    assert "interrupted by SIGTERM" in log, log
    assert checkpoint_files(ckpt)  # kept, to resume from
    assert not (work / target).exists()  # the partial series is not a result
    res = _snakemake(work, "-n", *args)
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
    assert _job_counts(res.stdout).get("simulate_case") == 1, res.stdout[-3000:]


def test_a_case_that_blows_up_keeps_what_it_wrote(tmp_path):
    """A run that blows up stops with the step, time and cause and writes its output up to
    that moment (exit status 3): that output is the case's result, marked with its status,
    so the job succeeds with a warning in its log and the sweep can be gathered
    (sph.study.sweeps.gather keeps it NaN after its end): the rule's shell turns the
    engine's exit status 3 into success, under the default profile, which Snakemake finds
    by itself."""
    work = _workflow_copy(tmp_path)
    sweep = yaml.safe_load((work / ".test" / "config.yaml").read_text())
    # the hydrostatic density at the tank floor is above this at once
    sweep["set"] = {"run.density_max": 1.0001}
    (work / ".test" / "blow.yaml").write_text(yaml.safe_dump(sweep))
    target = "results/test/cases/case1.nc"
    res = _snakemake(work, target, "--cores", "1", "--configfile", ".test/blow.yaml")
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
    assert "workflow specific profile profiles/default" in res.stdout + res.stderr
    log = (work / "results/test/logs/simulate/case1.log").read_text()
    assert "error: simulation stopped at step" in log and "left the band" in log, log
    assert "warning: the run blew up" in log, log
    ds = read_dataset(work / target)
    assert ds.sizes["time"] >= 1
    assert ds.attrs["status"].startswith("failed: simulation stopped at step")
    # done: a second call has nothing to do (it would blow up again)
    res = _snakemake(work, target, "--cores", "1", "--configfile", ".test/blow.yaml")
    assert res.returncode == 0 and "Nothing to be done" in res.stdout + res.stderr
