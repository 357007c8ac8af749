"""Large first-mode sloshing across a refinement box: does the fluid keep its volume?

A rectangular tank 24 m long with water 12 m deep (the ship tank's depth; the ship cases'
numerics: dx = 0.8 m, no density filter, shifting, wall damping, the tension floor) sloshes
in its first mode from a flat surface with the linear mode's velocity field (amplitude
2 m at the walls, period 5.8 s). Beneath the surface the water moves about 1 m to and fro
and 0.7 m up and down, so families of particles cross the edges of a refinement box and
change level twice a period. Modes:

- ``coarse``, ``fine``: uniform dx = 0.8 m and 0.4 m, the references;
- ``deep``: a level-1 box x in [8, 16] m, z in [3, 8] m, under the surface;
- ``surface``: a level-1 box x in [8, 16] m through the free surface, as a ship's box,
  and through the floor;
- ``lifted``: the same box 2 m off the floor, so that its edges meet no wall (a ship's box
  does not reach the tank's walls either).

    python benchmarks/refinement_sloshing.py run --mode deep --out DIR [--t-end 60]
        [--hysteresis 0.5] [--rise 3] [--jitter 0.25] [--density-filter none] [--max-lost 0.02]
    python benchmarks/refinement_sloshing.py report DIR

A refined run takes one to one and a half minutes on one core, the fine one about a minute,
the coarse one 9 s (60 s simulated, beside a second run). ``run`` records every 0.05 s the
kinetic energy KE and the potential energy PE of the fluid that carries the mass (ghosts
excluded) and writes ``DIR/slosh_<mode>[_h<H>][_rise<R>][_j<A>][_<filter>][_lost<F>].json``;
``--hysteresis`` sets :data:`sph.engine.refinement.HYSTERESIS` (the coarse spacings past a
box's edge at which a family changes level) for the run, ``--rise``
:data:`sph.engine.refinement.RISE` (the spacings of the box's level inside its edge at
which a family rises to it). ``--jitter A``: every
``JITTER_EVERY`` s, a share ``JITTER_SHARE`` of the mass-carrying particles beneath the
surface and away from the walls, drawn at random (a fixed seed), is displaced by up to A
of its spacing in x and z: the disorder a change of level leaves in the lattice, put into
a run without one. A run stopped by the engine (a particle leaving the tank) keeps its
record up to then; ``--max-lost F`` lets a share F of the fluid particles leave first
(``run.max_lost_fraction``; the engine's default lets none of this tank's 450 go), so that
the energy can be read past the first loss.

What must hold: the mechanical energy E = KE + PE - PE(0) (PE(0): the fluid at rest with a
flat surface, which it is at t = 0) only decays, by the viscosity, and never falls below
zero: below zero the fluid fills less room than its densities say. ``report`` prints, per
6 s window, E against E(0); the fluid's mean surface at the end (the mean over 2 m columns
of the highest particle; the first mode cancels in it); and writes
``DIR/refinement_sloshing.json``. The refined runs take the volume correction of variable
resolution (:mod:`sph.engine.volume`); the numbers before and after it are in
docs/validation/refinement.md, "A sloshing tank".
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
from compare import run_report_main

import sph.engine.refinement as refinement
from sph.cases import builtin
from sph.driver import Simulation
from sph.engine.refinement import active_fluid
from sph.engine.stepper import SimulationError

LENGTH, DEPTH, AMPLITUDE, DX = 24.0, 12.0, 2.0, 0.8
BOXES = {"coarse": [], "fine": [],
         "deep": [{"x": [8.0, 16.0], "z": [3.0, 8.0], "level": 1}],
         "surface": [{"x": [8.0, 16.0], "z": [-2.0, 20.0], "level": 1}],
         "lifted": [{"x": [8.0, 16.0], "z": [2.0, 20.0], "level": 1}]}
#: seconds between records, and the report's window
RECORD, WINDOW = 0.05, 6.0
#: ``--jitter``: seconds between the displacements, and the share of particles displaced
JITTER_EVERY, JITTER_SHARE = 0.5, 0.05


def case(mode: str, t_end: float, threads: int, density_filter: str = "none",
         max_lost: float | None = None):
    over = [("numerics.dx", DX / 2 if mode == "fine" else DX),
            ("geometry.tank_length", LENGTH), ("geometry.tank_height", 2 * DEPTH),
            ("geometry.fill", 0.5), ("geometry.amplitude", AMPLITUDE),
            ("numerics.density_filter", density_filter), ("numerics.shifting", 1.0),
            ("numerics.pressure_floor", -1.0e5), ("numerics.wall_damping", True),
            ("numerics.threads", threads), ("probes.surface", []), ("run.t_end", t_end),
            ("numerics.refinement", BOXES[mode])]
    if max_lost is not None:
        over.append(("run.max_lost_fraction", max_lost))
    return builtin("sloshing_rect", over)


def _surface(p) -> float:
    """Mean over 2 m columns of the highest mass-carrying particle (m)."""
    a = active_fluid(p)
    x, z = p.x[a], p.z[a]
    return float(np.mean([z[(x >= c) & (x < c + 2.0)].max()
                          for c in np.arange(0.0, LENGTH, 2.0)]))


def _jitter(p, dx: float, amplitude: float, rng) -> None:
    """Displace ``JITTER_SHARE`` of the mass-carrying particles 1.5 m or more inside the
    walls and 3 m or more beneath the still surface by up to ``amplitude`` spacings."""
    a = np.nonzero(active_fluid(p) & (p.z > 1.5) & (p.z < DEPTH - 3.0) & (p.x > 1.5)
                   & (p.x < LENGTH - 1.5))[0]
    k = rng.choice(a, max(1, int(JITTER_SHARE * len(a))), replace=False)
    reach = amplitude * dx * p.hs[k]
    p.x[k] += rng.uniform(-1.0, 1.0, len(k)) * reach
    p.z[k] += rng.uniform(-1.0, 1.0, len(k)) * reach


def mechanical_energy(p) -> tuple[float, float]:
    """Kinetic and potential energy (J per metre of width) of the fluid that carries the
    mass (ghosts excluded)."""
    a = active_fluid(p)
    return (0.5 * float(np.sum(p.m[a] * (p.vx[a] ** 2 + p.vz[a] ** 2))),
            9.81 * float(np.sum(p.m[a] * p.z[a])))


def simulate(sim, t_end: float, jitter: float | None = None) -> dict:
    """Run ``sim`` to ``t_end``, recording (t, KE, PE) of the mass-carrying fluid every
    ``RECORD`` s (``jitter``: the ``--jitter`` displacements); a run the engine stops keeps
    its record up to then. Returns ``record``, ``status`` and the mean surface at the start
    and the end (``surface_start``, ``surface_end``)."""
    sim.evaluate()
    rng = np.random.default_rng(1)
    rec, status, nxt, shake = [], "completed", 0.0, JITTER_EVERY
    surface0 = _surface(sim.parts)
    while sim.t < t_end:
        if sim.t >= nxt - 1e-9:
            rec.append((sim.t, *mechanical_energy(sim.parts)))
            nxt += RECORD
        if jitter and sim.t >= shake:
            _jitter(sim.parts, sim.cfg.numerics.dx, jitter, rng)
            shake += JITTER_EVERY
        try:
            sim.advance()
        except SimulationError as e:
            status = str(e)
            break
    return dict(record=rec, status=status, surface_start=surface0,
                surface_end=_surface(sim.parts))


def run(args) -> None:
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    name = "_".join([args.mode] + [f"{k}{v:g}" if isinstance(v, float) else f"{k}{v}"
                                   for k, v in (("h", args.hysteresis), ("rise", args.rise),
                                                ("j", args.jitter),
                                                ("", args.density_filter),
                                                ("lost", args.max_lost))
                                   if v not in (None, "none")])
    if args.hysteresis is not None:
        refinement.HYSTERESIS = args.hysteresis  # read at every rebuild of the lists
    if args.rise is not None:
        refinement.RISE = args.rise
    sim = Simulation(case(args.mode, args.t_end, args.threads, args.density_filter,
                          args.max_lost))
    t0 = time.perf_counter()
    rec = simulate(sim, args.t_end, args.jitter)
    p = sim.parts
    result = dict(mode=args.mode, hysteresis=refinement.HYSTERESIS, jitter=args.jitter,
                  density_filter=args.density_filter,
                  wall_seconds=time.perf_counter() - t0, steps=sim.step,
                  mass=float(np.sum(p.m[active_fluid(p)])), **rec)
    (out / f"slosh_{name}.json").write_text(json.dumps(result))
    print(f"{name}: {sim.step} steps to t = {sim.t:.2f} s, {result['wall_seconds']:.0f} s; "
          f"{rec['status']}")


def measures(r: dict) -> dict:
    """Windows' mean E / E(0), the lowest window mean of E (J) and the surface's change."""
    t, ke, pe = np.array(r["record"]).T
    e = ke + pe - pe[0]
    starts = np.arange(0.0, t[-1] - WINDOW + 1e-9, WINDOW)
    windows = [float(e[(t >= a) & (t < a + WINDOW)].mean() / e[0]) for a in starts]
    return dict(t_end=float(t[-1]), e_windows=windows,
                e_min=float(min(windows) * e[0]) if windows else float("nan"),
                surface_change=r["surface_end"] - r["surface_start"])


def report(args) -> None:
    d = Path(args.dir)
    result = {}
    for f in sorted(d.glob("slosh_*.json")):
        r = json.loads(f.read_text())
        m = measures(r)
        result[f.stem[6:]] = dict(status=r["status"], wall_seconds=r["wall_seconds"], **m)
        print(f"{f.stem[6:]:>12}: to {m['t_end']:.1f} s, E/E(0) by {WINDOW:g} s windows "
              + " ".join(f"{v:+.2f}" for v in m["e_windows"])
              + f"; surface {m['surface_change']:+.2f} m; {r['wall_seconds']:.0f} s"
              + ("" if r["status"] == "completed" else f"; stopped: {r['status'][:90]}"))
    (d / "refinement_sloshing.json").write_text(json.dumps(result, indent=1))


def _run_args(parser) -> None:
    parser.add_argument("--mode", choices=sorted(BOXES), required=True)
    parser.add_argument("--t-end", type=float, default=60.0)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--hysteresis", type=float, default=None,
                        help="sph.engine.refinement.HYSTERESIS for this run (coarse spacings)")
    parser.add_argument("--rise", type=float, default=None,
                        help="sph.engine.refinement.RISE for this run (spacings of the "
                             "box's level inside its edge at which a family rises)")
    parser.add_argument("--jitter", type=float, default=None,
                        help="displace particles at random by up to this many spacings")
    parser.add_argument("--density-filter", default="none",
                        choices=("none", "mls", "delta", "ddt"))
    parser.add_argument("--max-lost", type=float, default=None,
                        help="run.max_lost_fraction: the share of fluid particles that may "
                             "leave the tank before the run stops")


def main() -> None:
    run_report_main(__doc__, run, report, _run_args)


if __name__ == "__main__":
    main()
