"""Command-line interface: ``sph run``, ``sph example``, ``sph cases``, ``sph status``,
``sph export``.

``sph run CASE.yaml -o OUT.nc`` keeps checkpoints in ``OUT.nc.ckpt/`` (see
:mod:`sph.io.checkpoint`) and by default resumes from the newest valid one: running the same
command again after a kill, a pre-emption or a full disk continues the run. ``--restart``
deletes the checkpoints and starts from t = 0; ``--no-restart`` never starts from t = 0 (it
fails when there is nothing to resume).

``--start-from CKPT`` starts, instead of from t = 0, from another run's checkpoint (a file,
or a checkpoint directory: its newest) whose case differs from this one only in
``geometry.damage`` (the opening, its side, or none: an intact ship), taken before the
opening of either appears: before t1 the opening does nothing, so the run continues as if
it had run from t = 0, to the bit, and its output holds the other run's samples up to
there. The cases of a sweep that differ in the opening alone share their run to t1 this
way (the workflow's ``predamage`` runs). A run that has checkpoints of its own resumes from
them instead.

``sph export CKPT -o PART.nc`` writes the output of a run up to one of its checkpoints (a
checkpoint file, or a checkpoint directory: its newest), built from the checkpoint's own
configuration, its ``status`` saying where the series ends: the run so far of a run that is
still running, or was stopped, killed or interrupted by a workflow that deleted its partial
output. It refuses the run's own output path, which ``sph run`` writes. Exit 2 when there is
no valid checkpoint there, 5 when the file cannot be written.

Exit status of ``sph run``:

== ==================================================================================
0  done (or stopped at ``run.max_steps``; running again with a larger limit resumes)
2  invalid case file or command line, a checkpoint of another configuration,
   ``--no-restart`` with nothing to resume, or a ``--start-from`` checkpoint that does not
   fit (another case, or past the opening); one line names the key and the allowed range
3  the simulation blew up; the message names step, time and cause, and the output up
   to that moment is written
4  interrupted by SIGINT or SIGTERM; a checkpoint and the output so far are written,
   and running the same command again resumes
5  the output or a checkpoint cannot be written (unwritable directory, disk full);
   earlier files are left intact
== ==================================================================================
"""

from __future__ import annotations

import argparse
import logging
import os
import sys
import warnings
from pathlib import Path

import yaml

from sph import __version__
from sph.cases import CASES, build_case, example_text, load_case
from sph.driver import RunInterrupted, Simulation, SimulationError
from sph.engine.jit import compiled_here
from sph.io.checkpoint import (
    CheckpointError,
    checkpoint_dir,
    output_of,
    read_source,
    restore,
    resume_or_start,
    start_from,
)
from sph.io.status import StatusError, find_outputs, format_table, run_status, summary
from sph.schema import ConfigError


def _parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="sph", description="numba WCSPH engine of sph-flood")
    ap.add_argument("--version", action="version", version=f"sph-flood {__version__}")
    sub = ap.add_subparsers(dest="command", required=True)

    run = sub.add_parser("run", help="run one case file and write a netCDF file")
    run.add_argument("case_file", type=Path, help="case YAML (start from `sph example NAME`)")
    run.add_argument("-o", "--output", type=Path, required=True, help="output netCDF path")
    run.add_argument("--set", dest="overrides", action="append", default=[],
                     metavar="KEY=VALUE", help="override a case value, e.g. numerics.dx=0.01")
    run.add_argument("--vtk", type=Path, default=None, metavar="DIR",
                     help="write ParaView snapshots every run.vtk_interval into DIR")
    run.add_argument("--threads", type=int, default=None, help="numba threads (overrides "
                     "numerics.threads)")
    run.add_argument("--no-progress", action="store_true", help="no progress bar")
    run.add_argument("--check", action="store_true",
                     help="validate the case file and build the particles, then stop")
    again = run.add_mutually_exclusive_group()
    again.add_argument("--restart", dest="resume", action="store_const", const="restart",
                       default="auto", help="delete the checkpoints of OUTPUT and start "
                       "from t = 0 (default: resume from the newest valid checkpoint)")
    again.add_argument("--no-restart", dest="resume", action="store_const", const="resume",
                       help="never start from t = 0: resume from the newest valid "
                       "checkpoint, fail (exit 2) if there is none")

    run.add_argument("--start-from", type=Path, default=None, metavar="CKPT",
                     help="start from another run's checkpoint (file or checkpoint "
                     "directory) of a case that differs from this one in geometry.damage "
                     "alone, taken before the opening appears (instead of from t = 0; a "
                     "run with checkpoints of its own resumes from them)")

    ex = sub.add_parser("example", help="print the YAML of a built-in case")
    ex.add_argument("name", help="case name (see `sph cases`)")
    sub.add_parser("cases", help="list the built-in cases")
    st = sub.add_parser("status", help="how far runs have got: simulated time, share of "
                        "run.t_end, wall time, rate (from their outputs and checkpoints)")
    st.add_argument("outputs", type=Path, nargs="+", metavar="OUTPUT",
                    help="a run's output path (OUT.nc; it need not exist yet) or a folder "
                    "of them (every *.nc and *.nc.ckpt in it)")
    exp = sub.add_parser("export", help="write a run's output so far from one of its "
                         "checkpoints (a run stopped, killed or still running)")
    exp.add_argument("checkpoint", type=Path, metavar="CKPT",
                     help="a checkpoint file, or a run's checkpoint directory (OUT.nc.ckpt: "
                     "its newest valid checkpoint)")
    exp.add_argument("-o", "--output", type=Path, required=True,
                     help="netCDF path to write (another path than the run's own output)")
    return ap


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="%(levelname)s %(message)s")
    if args.command == "cases":
        for name, mod in CASES.items():
            doc = (sys.modules[mod.__module__].__doc__ if isinstance(mod, type) else
                   mod.__doc__) or ""
            print(f"{name:16s} {doc.strip().splitlines()[0] if doc.strip() else ''}")
        return 0
    if args.command == "example":
        if args.name not in CASES:
            print(f"error: unknown case {args.name!r}; built-in cases: "
                  f"{', '.join(CASES)}", file=sys.stderr)
            return 2
        sys.stdout.write(example_text(args.name))
        return 0
    if args.command == "status":
        return _status(args.outputs)
    if args.command == "export":
        return _export(args.checkpoint, args.output)
    try:
        return _run(args, own_process=argv is None)
    except KeyboardInterrupt:  # before the time loop (while building the particles)
        print("interrupted before the run started", file=sys.stderr)
        return 4


#: set in the environment of a ``sph run`` that starts again with the kernels the first
#: process compiled (:func:`_compile_kernels`): it does not start again a second time
RESTARTED_ENV = "SPH_KERNELS_CACHED"


def _compile_kernels(cfg) -> list[str]:
    """Compile, or load from numba's cache, the kernels the case ``cfg`` runs, and return
    those this process compiled itself (:func:`sph.engine.jit.compiled_here`).

    A throw-away simulation of the case (its messages silenced: the run's own gives them)
    takes a step, a sample and a check at t = 0 and again at the time of its last timed
    event (the damage opening at t1), so that the kernels a run first needs later come from
    the cache too."""
    logging.disable(logging.WARNING)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            warm = Simulation(cfg)
            times = [e.time for e in warm.setup.events if isinstance(
                getattr(e, "time", None), float)]
            for t in [None] + ([max(times)] if times else []):
                try:
                    if t is not None:
                        warm.t = t
                    warm.evaluate()
                    warm.advance()
                    warm.sample()
                    warm.check()
                except Exception:  # noqa: BLE001 - the run meets it again and reports it
                    pass
    finally:
        logging.disable(logging.NOTSET)
    return compiled_here()


def _run(args, own_process: bool = False) -> int:

    overrides = list(args.overrides)
    if args.threads is not None:
        overrides.append(f"numerics.threads={args.threads}")
    try:
        cfg = load_case(args.case_file, overrides)
    except ConfigError as exc:
        print(f"error: invalid case {str(args.case_file)!r}: {exc}", file=sys.stderr)
        return 2
    out = args.output
    if _is_directory(out):
        return 2
    try:
        sim = Simulation(cfg)
    except ConfigError as exc:
        print(f"error: invalid case {str(args.case_file)!r}: {exc}", file=sys.stderr)
        return 2
    log = logging.getLogger("sph")
    log.info("%s", sim.summary())
    if args.check:
        print("case is valid")
        return 0
    try:
        _check_writable(out.parent)
    except OSError as exc:
        print(f"error: cannot write to the output directory {str(out.parent)!r}: "
              f"{exc.strerror or exc}; nothing was computed", file=sys.stderr)
        return 5
    if own_process:  # (loading the kernels here also keeps it out of the run's timing)
        fresh = _compile_kernels(cfg)
        if fresh and not os.environ.get(RESTARTED_ENV):
            # the kernels a process compiles itself differ from those loaded from the cache
            # at round-off (docs/checkpoints.md): run with the cached ones, as every later
            # run and every resumed one will
            log.info("compiled %d kernels (first run of this engine here); starting again "
                     "with them from numba's cache", len(fresh))
            os.environ[RESTARTED_ENV] = "1"
            sys.stdout.flush()
            sys.stderr.flush()
            exe = sys.argv[0]  # the `sph` script: the same command line for `ps` and `pgrep`
            if os.access(exe, os.X_OK) and not exe.endswith(".py"):
                os.execv(exe, [exe, *sys.argv[1:]])
            os.execv(sys.executable, [sys.executable, "-m", "sph.cli", *sys.argv[1:]])
    ckpt = checkpoint_dir(out)
    try:
        resumed = resume_or_start(sim, ckpt, args.resume)
    except ConfigError as exc:  # another configuration, or nothing to resume
        print(f"error: {exc}", file=sys.stderr)
        return 2
    seed = None
    if resumed is None and args.start_from is not None:
        try:
            seed = start_from(sim, args.start_from)
        except (ConfigError, CheckpointError) as exc:  # another case, or past the opening
            print(f"error: cannot start from {str(args.start_from)!r}: {exc}",
                  file=sys.stderr)
            return 2
    if resumed is not None:
        log.info("resuming from checkpoint %s at t = %.6g s (step %d)", resumed, sim.t,
                 sim.step)
    elif seed is not None:
        log.info("starting from checkpoint %s of another run at t = %.6g s (step %d)", seed,
                 sim.t, sim.step)
    try:
        sim.run(out, progress=not args.no_progress, vtk_dir=args.vtk, checkpoint_dir=ckpt)
    except SimulationError as exc:
        t_kept = sim.record.time[-1] if sim.record.time else 0.0
        print(f"error: {exc}; output up to t = {t_kept:.6g} s "
              f"kept in {str(out)!r}", file=sys.stderr)
        return 3
    except RunInterrupted as exc:
        print(f"{exc}; output so far in {str(out)!r}; run the same command again to resume",
              file=sys.stderr)
        return 4
    except KeyboardInterrupt:
        print(f"interrupted at step {sim.step}, t = {sim.t:.6g} s; output so far in "
              f"{str(out)!r}; running the same command again resumes from the last "
              "checkpoint, if any", file=sys.stderr)
        return 4
    except OSError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 5
    late = compiled_here(parallel=True) if own_process else []
    if late:
        log.warning("this run computed with parallel kernels it compiled itself (%s): a "
                    "rerun, which loads them from numba's cache, can differ from it at "
                    "round-off (docs/checkpoints.md)", ", ".join(sorted(set(late))))
    if sim.status != "completed":
        log.info("%s; run again with a larger run.max_steps (or 0) to continue", sim.status)
    log.info("done: %d steps in %.1f s wall (%.3g M particle-steps/s); wrote %s", sim.step,
             sim.wall_seconds, sim.particle_steps_per_second() / 1e6, out)
    return 0


def _status(paths: list[Path]) -> int:
    rows, failed = [], False
    for path in paths:
        if path.name.endswith(".nc.ckpt"):  # a checkpoint folder stands for its output
            outputs = [output_of(path)]
        elif path.is_dir() and not path.name.endswith(".nc"):
            outputs = find_outputs(path)
        else:
            outputs = [path]
        if not outputs:
            print(f"error: no outputs (*.nc, *.nc.ckpt) in {str(path)!r}", file=sys.stderr)
            failed = True
        for out in outputs:
            try:
                rows.append(run_status(out))
            except StatusError as exc:
                print(f"error: {exc}", file=sys.stderr)
                failed = True
    if rows:
        print(format_table(rows))
        if len(rows) > 1:
            print(summary(rows))
    return 2 if failed else 0


def _export(source: Path, out: Path) -> int:
    """``sph export``: the output of a run up to one of its checkpoints. The case is the
    checkpoint's own configuration; the output's ``status`` says where the series ends."""
    try:
        path, arrays = read_source(source)
        cfg = build_case(yaml.safe_load(str(arrays["config"])))
    except (ConfigError, CheckpointError) as exc:
        print(f"error: cannot export {str(source)!r}: {exc}", file=sys.stderr)
        return 2
    if _is_directory(out):
        return 2
    own = output_of(path.parent)
    if out.resolve() == own.resolve():
        print(f"error: {str(out)!r} is the run's own output, which `sph run` writes (and "
              "which a workflow would take for the finished run); export to another path",
              file=sys.stderr)
        return 2
    sim = Simulation(cfg)
    try:
        restore(sim, arrays, path)
    except (ConfigError, CheckpointError) as exc:
        print(f"error: cannot export {str(source)!r}: {exc}", file=sys.stderr)
        return 2
    sim.status = (f"exported from checkpoint {str(path)!r} at t = {sim.t:.6g} s "
                  f"(step {sim.step}) of a run to {cfg.run.t_end:g} s")
    try:
        _check_writable(out.parent)
        sim.write(out)
    except OSError as exc:
        print(f"error: cannot write {str(out)!r}: {exc.strerror or exc}", file=sys.stderr)
        return 5
    logging.getLogger("sph").info("wrote %s: %d samples to t = %.6g s (step %d)", out,
                                  len(sim.record.time), sim.t, sim.step)
    return 0


def _is_directory(out: Path) -> bool:
    """Whether the output path ``out`` is a directory (and say so)."""
    if out.exists() and out.is_dir():
        print(f"error: output path {str(out)!r} is a directory", file=sys.stderr)
        return True
    return False


def _check_writable(directory: Path) -> None:
    """Create ``directory`` if needed and write (then delete) a small file in it, so that
    an unwritable directory or a full disk is reported before any computing."""
    directory.mkdir(parents=True, exist_ok=True)
    probe = directory / f".sph-write-test-{os.getpid()}"
    try:
        with open(probe, "wb") as fh:
            fh.write(b"\0" * 4096)
            fh.flush()
            os.fsync(fh.fileno())
    finally:
        probe.unlink(missing_ok=True)


if __name__ == "__main__":
    sys.exit(main())
