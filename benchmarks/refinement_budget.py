"""Where the sloshing tank's energy goes under variable resolution: a budget by stage.

The run of ``benchmarks/refinement_sloshing.py`` (mode ``surface`` or ``deep``), with each
stage of a step that can change the mechanical energy E = KE + PE of the mass-carrying
fluid wrapped and its change summed:

- ``update``: the leapfrog update (:func:`sph.engine.integrator.verlet_update`): the work of
  every force but gravity;
- ``shift``: the particle shifting (:func:`sph.engine.shifting.apply_shift`), which moves
  particles at constant velocity;
- ``levels``: the changes of level at each rebuild of the lists (spawn, assign);
- ``ghosts``: the pressure work of the ghosts on the active particles, summed over their
  pairs at every step as the pair loops take it (pushes only, each ghost's weight
  included), dt times sum_i m_i v_i . a_i;
- ``volume``, ``packing``: the elastic energy sum m e(rho) of the active fluid (the Tait
  equation's, e = integral of p / rho^2 d rho from rho0) that the volume correction
  (:mod:`sph.engine.volume`) and the packing correction
  (:func:`sph.engine.refinement.packing_density`) put in by changing densities;

and the volume correction's input summed by metre of x, by metre of z, and by the share of
the volume fraction read at the particle that its own level's fluid gives (1 where only
its level is near; between 0.1 and 0.9 where the levels mix, at a box's edge), and each
family that falls back to level 0 counted with the distance from its level-0 particle to
the nearest coarse active particle already there. A diagnostic, not a check: the wrappers
replace the stepper's module functions for the run.

    python benchmarks/refinement_budget.py run --mode surface --out DIR [--t-end 60] [--rise R]
    python benchmarks/refinement_budget.py report DIR

``run`` writes ``DIR/budget_<mode>[_rise<R>].json`` (the budget every 0.5 s, in joules);
``report`` prints each in units of E(0). A run takes about 1.5 minutes on one core. The
numbers of 2026-11-30 are in docs/validation/refinement.md ("A rise hysteresis").
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
from compare import run_report_main
from numba import njit
from refinement_sloshing import BOXES, DEPTH, LENGTH, case, mechanical_energy
from scipy import ndimage
from scipy.spatial import cKDTree

import sph.engine.refinement as refinement
import sph.engine.stepper as stepper
from sph.driver import Simulation
from sph.engine.kernels import KP_R2MAX, f_scaled
from sph.engine.particles import FLUID, GHOST
from sph.engine.refinement import active_fluid, levels

#: seconds between records
RECORD = 0.5
#: the budget's terms, in the order of the records
TERMS = ("update", "shift", "levels", "ghosts", "volume", "packing")
#: bins of the share of the volume fraction at a particle given by its own level's fluid
OWN_SHARE = (0.0, 0.1, 0.5, 0.9, 0.98, 1.0 + 1e-9)


@njit(cache=True)
def ghost_power(x, z, vx, vz, rho, p, m, kind, body, hs, gw, start, index, kp):
    """sum_i m_i v_i . a_i over the active fluid particles, a_i the pressure force of the
    ghosts of their level alone (their pressure sum counted only where positive, the
    ghost's mass scaled by its weight ``gw``), over the lists ``start``, ``index``."""
    r2max = kp[KP_R2MAX]
    power = 0.0
    for i in range(x.shape[0]):
        if kind[i] != FLUID or body[i] == GHOST:
            continue
        ax = 0.0
        az = 0.0
        for k in range(start[i], start[i + 1]):
            j = index[k]
            if kind[j] != FLUID or body[j] != GHOST or hs[j] != hs[i]:
                continue
            dx = x[i] - x[j]
            dz = z[i] - z[j]
            r2 = dx * dx + dz * dz
            if r2 == 0.0 or r2 >= r2max * hs[i] * hs[i]:
                continue
            c = (-m[j] * gw[j] * max(p[i] + p[j], 0.0) / (rho[i] * rho[j])
                 * f_scaled(r2, kp, hs[i]))
            ax += c * dx
            az += c * dz
        power += m[i] * (vx[i] * ax + vz[i] * az)
    return power


class Budget:
    """The wrappers around ``sim``'s stages and the sums they keep."""

    def __init__(self, sim):
        self.sim = sim
        fl = sim.cfg.fluid
        self.b, self.gamma, self.rho0 = sim.b, fl.gamma, fl.rho0
        self.sums = dict.fromkeys(TERMS, 0.0)
        self.volume_by_x = np.zeros(int(np.ceil(LENGTH)))
        self.volume_by_z = np.zeros(int(np.ceil(2 * DEPTH)))
        self.volume_by_share = np.zeros(len(OWN_SHARE) - 1)
        self.falls: list[tuple[float, float, float]] = []  # (t, x, nearest / dx)
        self._wrap_module("verlet_update", "update", self.total)
        self._wrap_module("apply_shift", "shift", self.total)
        self._wrap_module("packing_density", "packing", self.elastic)
        self._wrap_volume()
        self._wrap_levels()

    def mechanical(self) -> tuple[float, float]:
        return mechanical_energy(self.sim.parts)

    def total(self) -> float:
        """KE + PE of the mass-carrying fluid."""
        return sum(self.mechanical())

    def _elastic_each(self) -> np.ndarray:
        p = self.sim.parts
        r, b, g, r0 = p.rho, self.b, self.gamma, self.rho0
        e = b * ((r ** (g - 1) / r0 ** g) / (g - 1) + 1.0 / r) - b * (1.0 / (r0 * (g - 1))
                                                                       + 1.0 / r0)
        return np.where(active_fluid(p), p.m * e, 0.0)

    def elastic(self) -> float:
        return float(self._elastic_each().sum())

    def _wrap_module(self, name: str, term: str, measure) -> None:
        """Replace the stepper's function ``name`` by one that adds the change of
        ``measure()`` across each call to the term ``term``."""
        inner = getattr(stepper, name)

        def wrapped(*args):
            e0 = measure()
            inner(*args)
            self.sums[term] += measure() - e0

        setattr(stepper, name, wrapped)

    def _level_fractions(self, parts) -> list[np.ndarray]:
        """The volume correction's smoothed fraction (:mod:`sph.engine.volume`) of each
        level's active fluid alone, read at every particle."""
        vc, lev = self.sim.volume, levels(parts.hs)
        at = [(parts.x - vc.x0) / vc.spacing - 0.5, (parts.z - vc.z0) / vc.spacing - 0.5]
        return [ndimage.map_coordinates(vc.fraction(parts, lev == k)[0], at, order=1,
                                        mode="nearest") for k in range(int(lev.max()) + 1)]

    def _wrap_volume(self) -> None:
        inner = self.sim.volume.apply

        def wrapped(parts, dt):
            e0 = self._elastic_each()
            out = inner(parts, dt)
            de = self._elastic_each() - e0
            self.sums["volume"] += float(de.sum())
            for where, sums in ((parts.x, self.volume_by_x), (parts.z, self.volume_by_z)):
                bins = np.clip(where, 0.0, len(sums) - 1e-9).astype(int)
                sums += np.bincount(bins, weights=de, minlength=len(sums))
            on = de != 0.0
            if on.any():
                frac = self._level_fractions(parts)
                own = np.choose(levels(parts.hs), frac, mode="clip")
                share = own[on] / np.maximum(sum(f[on] for f in frac), 1e-12)
                self.volume_by_share += np.histogram(share, bins=OWN_SHARE,
                                                     weights=de[on])[0]
            return out

        self.sim.volume.apply = wrapped

    def _wrap_levels(self) -> None:
        sim = self.sim
        inner = sim._refine
        dx = sim.cfg.numerics.dx

        def wrapped():
            p = sim.parts
            before = p.pid[active_fluid(p) & (levels(p.hs) == 0)]
            e0 = self.total()
            inner()
            self.sums["levels"] += self.total() - e0
            p = sim.parts
            now = np.nonzero(active_fluid(p) & (levels(p.hs) == 0))[0]
            fresh = np.isin(p.pid[now], before, invert=True)
            new, old = now[fresh], now[~fresh]
            if len(new) and len(old):
                d, _ = cKDTree(np.column_stack([p.x[old], p.z[old]])).query(
                    np.column_stack([p.x[new], p.z[new]]))
                self.falls += [(sim.t, float(x), float(r / dx))
                               for x, r in zip(p.x[new], d, strict=True)]

        sim._refine = wrapped

    def step_ghosts(self) -> None:
        sim, p = self.sim, self.sim.parts
        self.sums["ghosts"] += sim.dt * ghost_power(
            p.x, p.z, p.vx, p.vz, p.rho, p.p, p.m, p.kind, p.body, p.hs, sim._gw,
            sim.nlist.start, sim.nlist.index, sim.kp)


def run(args) -> None:
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.rise is not None:
        refinement.RISE = args.rise
    sim = Simulation(case(args.mode, args.t_end, 1))
    budget = Budget(sim)
    sim.evaluate()
    ke0, pe0 = budget.mechanical()
    el0 = budget.elastic()
    records, nxt, t0 = [], 0.0, time.perf_counter()
    while sim.t < args.t_end:
        budget.step_ghosts()
        if sim.t >= nxt - 1e-9:
            ke, pe = budget.mechanical()
            records.append([sim.t, ke + pe - pe0, budget.elastic() - el0,
                            *(budget.sums[k] for k in TERMS)])
            nxt += RECORD
        sim.advance()
    name = args.mode + ("" if args.rise is None else f"_rise{args.rise:g}")
    result = dict(mode=args.mode, rise=args.rise, e0=ke0, columns=["t", "E", "elastic",
                                                                   *TERMS],
                  records=records, volume_by_x=budget.volume_by_x.tolist(),
                  volume_by_z=budget.volume_by_z.tolist(),
                  volume_by_own_share=budget.volume_by_share.tolist(),
                  falls=budget.falls, wall_seconds=time.perf_counter() - t0)
    (out / f"budget_{name}.json").write_text(json.dumps(result))
    print(f"{name}: to t = {sim.t:.2f} s, {result['wall_seconds']:.0f} s")


def report(args) -> None:
    for f in sorted(Path(args.dir).glob("budget_*.json")):
        r = json.loads(f.read_text())
        rec = np.array(r["records"])
        e0 = rec[0, 1]
        last = rec[-1] / e0
        print(f"{f.stem[7:]}: at t = {rec[-1, 0]:.1f} s, in E(0): E {last[1]:+.2f}, elastic "
              f"{last[2]:+.2f}; " + ", ".join(f"{k} {v:+.2f}" for k, v in
                                              zip(TERMS, last[3:], strict=True)))
        vx = np.array(r["volume_by_x"]) / e0
        print("  volume correction by metre of x: " + " ".join(f"{v:.2f}" for v in vx))
        if "volume_by_z" in r:
            vz = np.array(r["volume_by_z"]) / e0
            print("  by metre of z, from the floor: " + " ".join(f"{v:.2f}" for v in vz))
            vs = np.array(r["volume_by_own_share"]) / e0
            print("  by the share of the fraction at the particle its own level gives: " +
                  ", ".join(f"{a:g}-{min(b, 1):g} {v:+.2f}" for a, b, v in
                            zip(OWN_SHARE[:-1], OWN_SHARE[1:], vs, strict=True)))
        falls = np.array(r["falls"])
        if len(falls):
            near = falls[:, 2]
            print(f"  {len(falls)} falls to level 0; nearest coarse particle, in coarse "
                  f"spacings: median {np.median(near):.2f}, below 0.7 {np.mean(near < 0.7):.0%}"
                  f", 1st percentile {np.percentile(near, 1):.2f}")


def _run_args(parser) -> None:
    parser.add_argument("--mode", choices=sorted(m for m in BOXES if BOXES[m]),
                        required=True)
    parser.add_argument("--t-end", type=float, default=60.0)
    parser.add_argument("--rise", type=float, default=None,
                        help="sph.engine.refinement.RISE for this run")


def main() -> None:
    run_report_main(__doc__, run, report, _run_args)


if __name__ == "__main__":
    main()
