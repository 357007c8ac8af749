"""Cost of the damaged ship refined around its hull against the uniform fine run.

The still-water flooding case of ``tests/physics/test_ship.py`` (a 70 m tank 15 m deep, the
ship at x = 30 m, the 0.9 opening on the back side opening at 0.16 wave periods, no waves)
at dx = 0.8 m with a level-1 box around the hull (x in [19, 41] m, z in [8, 22] m: dx =
0.4 m there), and the same case at a uniform 0.4 m. After ``--warmup`` steps each, the two
take turns, ``--block`` steps at a time for ``--rounds`` rounds
(:func:`compare.interleave`), so that the machine's changes of speed fall on both alike.
Prints, as its last line, a JSON object: the simulated seconds per wall second of each
(best and median of the rounds), their ratio (the refined run's speed-up), the particle
counts and both runs' time steps.

    python benchmarks/refinement_cost.py [--threads 1] [--rounds 7] [--block 200]
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

#: the refinement around the hull: it holds the hull's heave and roll with the buffer
BOX = {"x": [19.0, 41.0], "z": [8.0, 22.0], "level": 1}


def flooding(dx: float, refined: bool, threads: int) -> Simulation:
    over = [f"numerics.dx={dx}", "geometry.depth=15", "geometry.tank_length=70",
            "geometry.ship_x=30", "geometry.tank_height=30", "geometry.absorber.start=50",
            "geometry.absorber.length=20", "geometry.wavemaker.amplitude=null",
            "geometry.wavemaker.theta0=0", "geometry.fill=0", "geometry.damage.opening=0.9",
            "geometry.damage.side=back", "geometry.damage.time_periods=0.16",
            f"numerics.threads={threads}"]
    if refined:
        over.append(("numerics.refinement", [BOX]))
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
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--block", type=int, default=200)
    ap.add_argument("--warmup", type=int, default=300)
    args = ap.parse_args()
    refined = flooding(0.8, True, args.threads)
    fine = flooding(0.4, False, args.threads)
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
        refined_dt=refined.dt, fine_dt=fine.dt, threads=args.threads)
    print(f"refined {out['rate']:.4f}, uniform fine {out['reference_rate']:.4f} simulated s "
          f"per wall s: the refined run is {out['ratio']:.2f} times as fast")
    print(json.dumps(out))


if __name__ == "__main__":
    main()
