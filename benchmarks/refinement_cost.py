"""Cost of the damaged ship refined around its hull against the uniform fine run.

The built-in ``damaged_ship`` case (the Table I reference: the paper's 150 m tank 30 m deep,
waves of A = 2 m, the 10/21 opening on the back side) with its damage opening open from the
start (``--damage-period``), at dx = 0.8 m with ``geometry.refine_hull = --level`` (2 by
default, the ``refined`` preset: dx = 0.2 m around each hull, its cabins and opening, the
resolution the issue asks there), and the same case at the uniform fine dx = 0.8 / 2^level
m. After
``--warmup`` steps each, the two take turns, ``--block`` steps at a time for ``--rounds``
rounds (:func:`compare.interleave`), so that the machine's changes of speed fall on both
alike. Prints, as its last line, a JSON object: the simulated seconds per wall second of
each (best and median of the rounds), their ratio (the refined run's speed-up), the
particle counts and both runs' time steps.

    python benchmarks/refinement_cost.py [--level 2] [--threads 1] [--rounds 7] [--block 100]
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np
from compare import interleave, summary

from sph.cases import builtin
from sph.driver import Simulation
from sph.engine.refinement import active_fluid


def ship(dx: float, level: int, threads: int, damage_period: float) -> Simulation:
    over = [f"numerics.dx={dx}", f"geometry.refine_hull={level}",
            f"geometry.damage.time_periods={damage_period}", f"numerics.threads={threads}"]
    sim = Simulation(builtin("damaged_ship", over))
    sim.evaluate()
    return sim


def _block(sim: Simulation, steps: int):
    def rate() -> float:
        t0, w0 = sim.t, time.perf_counter()
        for _ in range(steps):
            sim.advance()
        return (sim.t - t0) / (time.perf_counter() - w0)
    return rate


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--level", type=int, default=2, choices=(1, 2, 3))
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--block", type=int, default=100)
    ap.add_argument("--warmup", type=int, default=200)
    ap.add_argument("--damage-period", type=float, default=0.005)
    args = ap.parse_args()
    refined = ship(0.8, args.level, args.threads, args.damage_period)
    fine = ship(0.8 / 2**args.level, 0, args.threads, args.damage_period)
    for sim in (refined, fine):
        for _ in range(args.warmup):
            sim.advance()
    mine, ref = interleave(args.rounds, _block(refined, args.block), _block(fine, args.block))
    out = summary(mine, ref)
    out.update(
        unit="simulated seconds per wall second",
        refined_particles=int(refined.parts.n),
        refined_active_fluid=int(active_fluid(refined.parts).sum()),
        fine_particles=int(fine.parts.n),
        fine_fluid=int(np.sum(fine.parts.kind == 0)),
        refined_dt=refined.dt, fine_dt=fine.dt, threads=args.threads, level=args.level)
    print(f"refined {out['rate']:.4f}, uniform fine {out['reference_rate']:.4f} simulated s "
          f"per wall s: the refined run is {out['ratio']:.2f} times as fast")
    print(json.dumps(out))


if __name__ == "__main__":
    main()
