"""Throughput of the engine on the dam break: particle-steps per second.

Runs the built-in dam break (1 m x 2 m column, 4 m tank) at about 20 000 and 80 000 fluid
particles for a fixed number of steps, with the Wendland C2 kernel (h = 1.41 dx, support 2h)
and the improved Gaussian (h = 1.23 dx, support 3h), after a warm-up that compiles the kernels
and lets the column start moving. Prints one line per configuration and, as its last line,
a JSON object with every result (particles counted fluid + wall; median of ``--repeat`` runs).

    python benchmarks/dam_break_throughput.py [--threads 2] [--steps 200] [--repeat 3]
"""

from __future__ import annotations

import argparse
import json
import statistics
import time

from sph.cases import builtin
from sph.driver import Simulation

SIZES = {"20k": 0.01, "80k": 0.005}  # dx (m): 100 x 200 and 200 x 400 fluid particles
KERNELS = {"wendland": 1.41, "gaussian": 1.23}


def measure(dx: float, kernel: str, steps: int, warmup: int, threads: int,
            density_filter: str) -> tuple[int, float]:
    cfg = builtin("dam_break", [
        ("numerics.dx", dx), ("numerics.kernel", kernel),
        ("numerics.h_factor", KERNELS[kernel]), ("numerics.threads", threads),
        ("numerics.density_filter", density_filter), ("run.t_end", 10.0)])
    sim = Simulation(cfg)
    sim.evaluate()
    for _ in range(warmup):
        sim.advance()
    t0 = time.perf_counter()
    for _ in range(steps):
        sim.advance()
    wall = time.perf_counter() - t0
    return sim.parts.n, sim.parts.n * steps / wall


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--warmup", type=int, default=50)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--filter", default="mls", choices=("mls", "delta", "ddt", "none"))
    ap.add_argument("--sizes", default="20k,80k")
    ap.add_argument("--kernels", default="wendland,gaussian")
    args = ap.parse_args()
    results = {}
    for size in args.sizes.split(","):
        for kernel in args.kernels.split(","):
            rates = []
            for _ in range(args.repeat):
                n, rate = measure(SIZES[size], kernel, args.steps, args.warmup, args.threads,
                                  args.filter)
                rates.append(rate)
            med = statistics.median(rates)
            key = f"{kernel}_{size}"
            results[key] = {"particles": n, "particle_steps_per_s": round(med),
                            "runs": [round(r) for r in rates]}
            print(f"{key:14s} N = {n:6d}  {med / 1e6:6.2f} M particle-steps/s "
                  f"(runs: {', '.join(f'{r / 1e6:.2f}' for r in rates)})", flush=True)
    results["threads"] = args.threads
    results["density_filter"] = args.filter
    results["steps"] = args.steps
    print(json.dumps(results))


if __name__ == "__main__":
    main()
