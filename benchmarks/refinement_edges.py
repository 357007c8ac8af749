"""Where the refined ship's fluid holds its kinetic energy once calm, and where the volume
correction puts energy in, by distance to the refinement box's edge.

The still-water flooding of ``benchmarks/refinement_flooding.py`` (mode ``refined``, or a
uniform mode read against the refined case's boxes as placed at the start), with the active
fluid binned by its signed distance to the nearest box's boundary (negative inside, the
Euclidean distance outside a corner) in bands of one coarse spacing, 0.8 m:

- the kinetic energy of each band, averaged over records every 0.5 s from ``--t-from``
  (the fine run's kinetic energy is 39-45 kJ once calm, the refined run's 155 kJ:
  docs/validation/refinement.md, "The damaged ship refined around its hull");
- the elastic energy the volume correction (:mod:`sph.engine.volume`) puts into each band
  over the run, to first order sum m p / rho^2 d rho over its passes (each pass changes a
  density by less than 1e-3 of itself).

    python benchmarks/refinement_edges.py run --mode refined --out DIR [--t-end 36]
    python benchmarks/refinement_edges.py report DIR

``run`` writes ``DIR/edges_<mode>.json``. A refined run to 36 s takes about 20 minutes on
one core. A diagnostic, not a check: the volume correction's pass is wrapped for the run.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
from compare import run_report_main
from refinement_flooding import MODES, case

from sph.driver import Simulation
from sph.engine.refinement import BX_XMAX, BX_XMIN, BX_ZMAX, BX_ZMIN, active_fluid

#: band edges of the signed distance to the box's boundary (m): one coarse spacing wide
EDGES = np.arange(-6.0, 6.01, 0.8)
#: seconds between the kinetic energy's records
RECORD = 0.5


def edge_distance(x: np.ndarray, z: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """Signed distance of each point to the boundary of the nearest box (negative inside)."""
    out = np.full(x.shape, np.inf)
    for b in boxes:  # (a tank per hull segment, a box in each)
        gx = np.maximum(b[BX_XMIN] - x, x - b[BX_XMAX])
        gz = np.maximum(b[BX_ZMIN] - z, z - b[BX_ZMAX])
        d = np.where((gx > 0) & (gz > 0), np.hypot(gx, gz), np.maximum(gx, gz))
        out = np.minimum(out, d)
    return out


def run(args) -> None:
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    sim = Simulation(case(args.mode, args.t_end, 1))
    # a uniform run is read against the refined case's boxes where they start
    boxes0 = sim.boxes.copy() if sim.variable else Simulation(case("refined", 1.0, 1)).boxes
    ke = np.zeros(len(EDGES) + 1)
    vol = np.zeros(len(EDGES) + 1)
    if sim.volume is not None:
        inner = sim.volume.apply

        def wrapped(parts, dt):
            r0 = parts.rho.copy()
            result = inner(parts, dt)
            a = active_fluid(parts) & (parts.rho != r0)
            de = parts.m[a] * parts.p[a] / parts.rho[a] ** 2 * (parts.rho[a] - r0[a])
            band = np.searchsorted(EDGES, edge_distance(parts.x[a], parts.z[a], sim.boxes))
            vol[:] += np.bincount(band, weights=de, minlength=len(vol))
            return result

        sim.volume.apply = wrapped
    sim.evaluate()
    n_rec, nxt, t0 = 0, args.t_from, time.perf_counter()
    while sim.t < args.t_end:
        sim.advance()
        if sim.t >= nxt:
            p = sim.parts
            a = active_fluid(p)
            band = np.searchsorted(EDGES, edge_distance(
                p.x[a], p.z[a], sim.boxes if sim.variable else boxes0))
            ke += np.bincount(band, weights=0.5 * p.m[a] * (p.vx[a] ** 2 + p.vz[a] ** 2),
                              minlength=len(ke))
            n_rec += 1
            nxt += RECORD
    result = dict(mode=args.mode, t_from=args.t_from, t_end=float(sim.t), edges=EDGES.tolist(),
                  kinetic_energy=(ke / max(n_rec, 1)).tolist(), volume_input=vol.tolist(),
                  records=n_rec, wall_seconds=time.perf_counter() - t0)
    (out / f"edges_{args.mode}.json").write_text(json.dumps(result))
    print(f"{args.mode}: to t = {sim.t:.2f} s, {result['wall_seconds']:.0f} s")


def report(args) -> None:
    for f in sorted(Path(args.dir).glob("edges_*.json")):
        r = json.loads(f.read_text())
        e = r["edges"]
        names = ([f"< {e[0]:+.1f}"]
                 + [f"{a:+.1f} to {b:+.1f}" for a, b in zip(e[:-1], e[1:], strict=True)]
                 + [f"> {e[-1]:+.1f}"])
        ke, vol = np.array(r["kinetic_energy"]), np.array(r["volume_input"])
        print(f"{r['mode']}: mean kinetic energy from {r['t_from']:g} s {ke.sum() / 1e3:.1f} kJ,"
              f" volume correction's input to {r['t_end']:.1f} s {vol.sum() / 1e6:.2f} MJ")
        for name, k, v in zip(names, ke, vol, strict=True):
            print(f"  {name:>14} m: {k / 1e3:7.1f} kJ  {v / 1e3:9.1f} kJ")


def _run_args(parser) -> None:
    parser.add_argument("--mode", choices=sorted(MODES), required=True)
    parser.add_argument("--t-end", type=float, default=36.0)
    parser.add_argument("--t-from", type=float, default=20.0,
                        help="seconds from which the kinetic energy is read (calm: t1 + 19)")


def main() -> None:
    run_report_main(__doc__, run, report, _run_args)


if __name__ == "__main__":
    main()
