"""Throughput of the engine on the dam break: particle-steps per second.

Runs the built-in dam break (1 m x 2 m column, 4 m tank) at about 20 000 and 80 000 fluid
particles for a fixed number of steps, with the Wendland C2 kernel (h = 1.41 dx, support 2h)
and the improved Gaussian (h = 1.23 dx, support 3h), after a warm-up that compiles the kernels
and lets the column start moving. Prints one line per configuration and, as its last line,
a JSON object with every result (particles counted fluid + wall; median of ``--repeat`` runs).

``--compare`` measures against references instead, each alternating with this tree's run
for ``--rounds`` rounds, one child process each (:mod:`compare`): the Wendland case at about
80 000 particles against the machine yardstick (:mod:`yardstick`, a bare numba pair loop
on 80 000 particles, the same thread count), and the Gaussian case at the same size against
commit ``--baseline`` (default 846fe50, release 0.1.0) checked out in a git worktree. The
last line then holds both rates and the median ratio of each comparison.

    python benchmarks/dam_break_throughput.py [--threads 2] [--steps 200] [--repeat 3]
    python benchmarks/dam_break_throughput.py --compare [--rounds 3] [--baseline 846fe50]
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path

from compare import interleave, run_child, summary, worktree

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
    ap.add_argument("--compare", action="store_true")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--baseline", default="846fe50")
    args = ap.parse_args()
    if args.compare:
        compare_with(args)
        return
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


def compare_with(args) -> None:
    here = Path(__file__).resolve().parent
    common = ["--threads", str(args.threads), "--steps", str(args.steps), "--warmup",
              str(args.warmup), "--repeat", "1", "--filter", args.filter, "--sizes", "80k"]

    def own(kernel):
        res = run_child(Path(__file__), common + ["--kernels", kernel])
        return res[f"{kernel}_80k"]["particle_steps_per_s"]

    results = {"threads": args.threads, "density_filter": args.filter, "steps": args.steps}
    mine, ref = interleave(args.rounds, lambda: own("wendland"), lambda: 1e6 * run_child(
        here / "yardstick.py", ["--threads", str(args.threads), "--repeat", "1"])[
            "yardstick_mps"])
    results["wendland_80k_vs_yardstick"] = summary(mine, ref)
    if args.baseline != "none":
        base = worktree(args.baseline)
        mine, ref = interleave(args.rounds, lambda: own("gaussian"), lambda: run_child(
            base / "benchmarks" / "dam_break_throughput.py", common + ["--kernels", "gaussian"],
            root=base)["gaussian_80k"]["particle_steps_per_s"])
        results["gaussian_80k_vs_" + args.baseline] = summary(mine, ref)
    for key, res in results.items():
        if isinstance(res, dict):
            print(f"{key:32s} {res['rate'] / 1e6:6.2f} against {res['reference_rate'] / 1e6:6.2f}"
                  f" M particle-steps/s: ratio {res['ratio']:.3f} (per round: "
                  f"{', '.join(f'{r:.2f}' for r in res['ratios'])})", flush=True)
    print(json.dumps(results))


if __name__ == "__main__":
    main()
