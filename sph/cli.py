"""Command-line interface: ``sph run``, ``sph example``, ``sph cases``.

Errors in the case file are reported as one line naming the key and the allowed range (exit
status 2); a simulation that blows up reports step, time and cause (exit status 3) after
writing what it had computed.
"""

from __future__ import annotations

import argparse
import logging
import sys
from pathlib import Path

from . import __version__
from .config import ConfigError


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

    ex = sub.add_parser("example", help="print the YAML of a built-in case")
    ex.add_argument("name", help="case name (see `sph cases`)")
    sub.add_parser("cases", help="list the built-in cases")
    return ap


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="%(levelname)s %(message)s")
    from .cases import CASES

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
        from .cases.base import example_text

        sys.stdout.write(example_text(args.name))
        return 0
    return _run(args)


def _run(args) -> int:
    from .config import load_case
    from .solver import Simulation, SimulationError

    overrides = list(args.overrides)
    if args.threads is not None:
        overrides.append(f"numerics.threads={args.threads}")
    try:
        cfg = load_case(args.case_file, overrides)
    except ConfigError as exc:
        print(f"error: invalid case {str(args.case_file)!r}: {exc}", file=sys.stderr)
        return 2
    out = args.output
    if out.exists() and out.is_dir():
        print(f"error: output path {str(out)!r} is a directory", file=sys.stderr)
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
        out.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        print(f"error: cannot create output directory {str(out.parent)!r}: {exc.strerror}",
              file=sys.stderr)
        return 2
    try:
        sim.run(out, progress=not args.no_progress, vtk_dir=args.vtk)
    except SimulationError as exc:
        t_kept = sim.record.time[-1] if sim.record.time else 0.0
        print(f"error: {exc}; output up to t = {t_kept:.6g} s "
              f"kept in {str(out)!r}", file=sys.stderr)
        return 3
    except KeyboardInterrupt:
        print(f"interrupted at step {sim.step}, t = {sim.t:.6g} s; output so far kept in "
              f"{str(out)!r}", file=sys.stderr)
        return 130
    except OSError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 4
    log.info("done: %d steps in %.1f s wall (%.3g M particle-steps/s); wrote %s", sim.step,
             sim.wall_seconds, sim.particle_steps_per_second() / 1e6, out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
