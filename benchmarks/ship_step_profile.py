"""Where a damaged-ship time step goes: seconds per engine stage and particle-steps per second.

Builds the built-in ``damaged_ship`` case (coarse dx = 0.8 m unless ``--dx``: two strip
segments, 13 976 fluid + 3 290 wall particles, the cost unit of a Table I case of the
workflow) with the damage opening already open (``--damage-period``, in wave periods, 0.005
by default: the line-of-sight tests at the opening run from the start), warms up, then times
``--steps`` steps with every stage of :meth:`sph.driver.Simulation.evaluate` and
``advance`` wrapped in a timer. Prints the stages by time and, as its last line, a JSON
object (median rate over ``--repeat`` runs, and the stage times of the last one).

With ``--baseline COMMIT`` (default: 846fe50, release 0.1.0; ``none`` to skip) this tree
and that commit, checked out in a git worktree, each run the same ship in a child process
(:mod:`step_server`) and take turns, ``--block`` steps at a time for ``--blocks`` blocks
each (:func:`compare.lockstep`), so that the machine's changes of speed fall on both alike;
the last line holds the ratio of their summed times (the speed-up over the baseline), the
median of the per-block ratios, both median block rates, and the stage table of one more
run of this tree.

    python benchmarks/ship_step_profile.py [--threads 1] [--steps 300] [--repeat 3]
        [--baseline 846fe50 | none] [--blocks 60] [--block 20] [--set KEY=VALUE ...]

``--checkpoint CASE.yaml CKPT.npz`` times a late state instead: the case file and one of
its checkpoints (``OUT.nc.ckpt/step-*.npz`` of a workflow run), at ``--threads``; no
baseline (the checkpoint's configuration ties it to this tree's case format). The calm
start the built-in ship gives misses what a flooded, sloshing state costs.

``--set`` (repeatable; :func:`step_server.parse_sets`) adds case-file values to the ship of
both sides, e.g. the workflow's ``refined`` ship: ``--set geometry.refine_hull=2 --set
numerics.wall_damping=true --set numerics.pressure_floor=-100000.0`` (YAML reads ``-1e5``,
without a point, as text).
"""

from __future__ import annotations

import argparse
import collections
import json
import statistics
import time
from pathlib import Path

from compare import ROOT, lockstep, run_child, worktree
from step_server import damaged_ship, parse_sets

from sph.engine import stepper as solver
from sph.engine.neighbours import CellGrid, NeighbourList
from sph.engine.particles import Particles

#: engine stages called from the solver module (numba kernels)
STAGES = ("fluid_pressures", "wall_pressure", "interact", "wall_forces", "mls_density",
          "renormalised_density_gradient", "verlet_update", "apply_shift", "place_walls",
          "max_speed_accel", "wall_normals", "listed_with", "ghost_fields", "ghost_diffusion",
          "cavitation_floor", "packing_fraction", "packing_density", "wall_lists",
          "moved_or_outside", "keep_in_tank")
#: methods of the simulation that hold no timed stage: the refinement's spawning and
#: merging, the ghosts' sources
METHODS = ("_refine", "_mark_ghosts")


def _timed(fn, name, timers):
    def wrapper(*args, **kwargs):
        t0 = time.perf_counter()
        out = fn(*args, **kwargs)
        timers[name] += time.perf_counter() - t0
        return out
    return wrapper


def from_checkpoint(case_file: str, checkpoint: str, threads: int):
    """A simulation restored from ``checkpoint``, a checkpoint of the run of ``case_file``,
    with ``threads`` numba threads."""
    from sph.cases import load_case
    from sph.driver import Simulation
    from sph.io.checkpoint import load_checkpoint, restore

    sim = Simulation(load_case(case_file, [f"numerics.threads={threads}"]))
    restore(sim, load_checkpoint(checkpoint), checkpoint)
    return sim


def measure(dx: float, damage_period: float, steps: int, warmup: int, threads: int,
            shifting: float, extra=(), checkpoint=None) -> tuple[int, float, dict]:
    timers: dict[str, float] = collections.defaultdict(float)
    originals = {name: getattr(solver, name) for name in STAGES if hasattr(solver, name)}
    sort, permute = CellGrid.sort, Particles.permute
    build, refresh = NeighbourList.build, NeighbourList.refresh
    try:
        for name, fn in originals.items():
            setattr(solver, name, _timed(fn, name, timers))
        CellGrid.sort = _timed(sort, "cell sort", timers)
        Particles.permute = _timed(permute, "permute", timers)
        NeighbourList.build = _timed(build, "list build", timers)
        NeighbourList.refresh = _timed(refresh, "inner list refresh", timers)
        sim = (damaged_ship(dx, damage_period, threads, shifting, extra) if checkpoint is None
               else from_checkpoint(*checkpoint, threads))
        for event in sim.setup.events:
            event.apply = _timed(event.apply, type(event).__name__, timers)
        for body in sim.bodies:
            body.update = _timed(body.update, "rigid body", timers)
        for name in METHODS:
            setattr(sim, name, _timed(getattr(sim, name), name.strip("_"), timers))
        sim.evaluate()
        for _ in range(warmup):
            sim.advance()
        timers.clear()
        t0 = time.perf_counter()
        for _ in range(steps):
            sim.advance()
        wall = time.perf_counter() - t0
    finally:
        for name, fn in originals.items():
            setattr(solver, name, fn)
        CellGrid.sort, Particles.permute = sort, permute
        NeighbourList.build, NeighbourList.refresh = build, refresh
    stages = dict(sorted(timers.items(), key=lambda kv: -kv[1]))
    stages["other"] = wall - sum(timers.values())
    return sim.parts.n, sim.parts.n * steps / wall, {k: v / wall for k, v in stages.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--dx", type=float, default=0.8)
    ap.add_argument("--damage-period", type=float, default=0.005)
    ap.add_argument("--shifting", type=float, default=1.0)
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--warmup", type=int, default=20)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--baseline", default="846fe50")
    ap.add_argument("--blocks", type=int, default=60)
    ap.add_argument("--block", type=int, default=20)
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--checkpoint", nargs=2, default=None, metavar=("CASE", "CKPT"),
                    help="time the state of a checkpoint CKPT of the run of case file CASE")
    args = ap.parse_args()
    default_baseline = args.baseline in ("none", ap.get_default("baseline"))
    if args.checkpoint is not None and (args.set or not default_baseline):
        ap.error("--checkpoint takes neither --set nor --baseline (the case file fixes the ship)")
    if args.baseline != "none" and args.checkpoint is None:
        compare_with(args)
        return
    rates = []
    for _ in range(args.repeat):
        n, rate, shares = measure(args.dx, args.damage_period, args.steps, args.warmup,
                                  args.threads, args.shifting, parse_sets(args.set),
                                  args.checkpoint)
        rates.append(rate)
    for name, share in shares.items():
        print(f"{name:32s} {100 * share:5.1f} %")
    med = statistics.median(rates)
    what = (f"checkpoint {args.checkpoint[1]}" if args.checkpoint else
            f"damaged_ship dx = {args.dx:g} m")
    print(f"{what}  N = {n}  {med / 1e6:.2f} M particle-steps/s, {1e3 * n / med:.1f} ms/step "
          f"(runs: {', '.join(f'{r / 1e6:.2f}' for r in rates)}; {args.threads} thread(s))")
    print(json.dumps({"particles": n, "particle_steps_per_s": round(med), "runs":
                      [round(r) for r in rates], "threads": args.threads, "dx": args.dx,
                      "shifting": args.shifting, "stage_shares": {k: round(v, 4) for k, v
                                                                   in shares.items()}}))


def compare_with(args) -> None:
    """This tree against ``args.baseline`` in lockstep (:func:`compare.lockstep`), then one
    run of this tree for the stage table."""
    base = worktree(args.baseline)
    common = ["--threads", str(args.threads), "--dx", str(args.dx), "--damage-period",
              str(args.damage_period), "--shifting", str(args.shifting), "--warmup",
              str(args.warmup)] + [f"--set={item}" for item in args.set]
    out = lockstep(Path(__file__).with_name("step_server.py"),
                   common + ["--block", str(args.block)], ROOT, base, args.blocks)
    last = run_child(Path(__file__), common + ["--steps", str(args.steps), "--repeat", "1",
                                               "--baseline", "none"])
    n = last["particles"]
    rate = n * args.block / statistics.median(out["seconds"])
    ref_rate = n * args.block / statistics.median(out["reference_seconds"])
    for name, share in last["stage_shares"].items():
        print(f"{name:32s} {100 * share:5.1f} %")
    print(f"damaged_ship dx = {args.dx:g} m  N = {n}  {args.threads} thread(s), "
          f"{args.blocks} blocks of {args.block} steps each, taking turns: this tree "
          f"{rate / 1e6:.3f}, {args.baseline} {ref_rate / 1e6:.3f} M particle-steps/s "
          f"(median block); ratio {out['ratio']:.2f} (summed times; median of the "
          f"per-block ratios {out['median_ratio']:.2f})")
    print(json.dumps({"particles": n, "threads": args.threads, "dx": args.dx,
                      "particle_steps_per_s": round(rate), "baseline": args.baseline,
                      "baseline_particle_steps_per_s": round(ref_rate),
                      "ratio": out["ratio"], "median_ratio": out["median_ratio"],
                      "blocks": args.blocks, "block": args.block, "set": args.set,
                      "stage_shares": last["stage_shares"]}))


if __name__ == "__main__":
    main()
