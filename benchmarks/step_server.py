"""A damaged-ship simulation that steps on request: the child process of a lockstep comparison
(:func:`compare.lockstep`).

Builds the built-in ``damaged_ship`` case with the engine found first on ``PYTHONPATH``
(this tree, or another commit checked out under ``.bench/``), warms up, prints ``ready``,
then for each line read from standard input advances ``--block`` steps and prints the
seconds they took; it stops at end of input.

    PYTHONPATH=TREE python benchmarks/step_server.py [--dx 0.8] [--threads 1] [--block 20]
        [--set KEY=VALUE ...]

``--set`` (repeatable) adds a case-file value (dotted key, YAML value), e.g.
``--set geometry.refine_hull=2 --set numerics.wall_damping=true`` for the ship of the
workflow's ``refined`` preset.
"""

from __future__ import annotations

import argparse
import sys
import time


def parse_sets(items) -> list[tuple[str, object]]:
    """``KEY=VALUE`` strings (``--set``) as (dotted key, YAML-parsed value) pairs."""
    import yaml

    out = []
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key:
            raise SystemExit(f"--set {item!r}: expected KEY=VALUE")
        out.append((key, yaml.safe_load(value)))
    return out


def damaged_ship(dx: float, damage_period: float, threads: int, shifting: float,
                 extra=()):
    """The built-in damaged ship with these values and the case-file values ``extra``
    (``(dotted key, value)`` pairs); works with this tree's package and with the
    single-package layout of release 0.1.0 (commit 846fe50)."""
    over = [("numerics.dx", dx), ("numerics.threads", threads),
            ("numerics.shifting", shifting), ("geometry.damage.time_periods", damage_period),
            *extra]
    try:
        from sph.cases import builtin
        from sph.driver import Simulation
    except ImportError:  # release 0.1.0
        from sph.config import apply_overrides, build_case

        from sph import solver
        from sph.cases.base import load_defaults
        return solver.Simulation(build_case(apply_overrides(load_defaults("damaged_ship"),
                                                            over)))
    return Simulation(builtin("damaged_ship", over))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dx", type=float, default=0.8)
    ap.add_argument("--damage-period", type=float, default=0.005)
    ap.add_argument("--shifting", type=float, default=1.0)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--warmup", type=int, default=20)
    ap.add_argument("--block", type=int, default=20)
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = ap.parse_args()
    sim = damaged_ship(args.dx, args.damage_period, args.threads, args.shifting,
                       parse_sets(args.set))
    sim.evaluate()
    for _ in range(args.warmup):
        sim.advance()
    print("ready", sim.parts.n, flush=True)
    for _ in sys.stdin:
        t0 = time.perf_counter()
        for _ in range(args.block):
            sim.advance()
        print(time.perf_counter() - t0, flush=True)


if __name__ == "__main__":
    main()
