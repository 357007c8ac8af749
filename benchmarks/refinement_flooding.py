"""Still-water flooding of the damaged ship refined around its hull against uniform runs.

The still-water flooding case of ``tests/physics/test_ship.py`` (a 70 m tank 15 m deep, the
ship at x = 30 m, the 0.9 opening on the back side opening at t1 = 0.16 wave periods =
1.0 s, no waves, empty cabins) at a uniform dx = 0.8 m (``coarse``), a uniform 0.4 m
(``fine``), the same at a Courant number of 0.19 instead of 0.2 (``fine_cfl``) and 0.8 m
with ``geometry.refine_hull = 1`` (``refined``: 0.4 m around the hull, ``--margin`` metres
beyond it).

    python benchmarks/refinement_flooding.py run --mode refined --out DIR [--t-end 30]
        [--rise R]
    python benchmarks/refinement_flooding.py report DIR

``report`` compares the flooded fraction of the cabin Q / V (``flood_ratio``), the heave
and the heel with the fine run at every output time after t1, prints the largest
differences and writes ``DIR/refinement_flooding.json``. The ``fine_cfl`` line is the floor
of such a comparison: two fine runs a round-off path apart part by that much.

Three measures need no reference run, so they hold however far a run's flooding has parted
from the fine one's by round-off: once the cabin has filled (from t1 + ``SETTLED`` s), in
windows of ``WINDOW`` s,

- **draught**: the largest gap between the mean heave and the lost-buoyancy heave of the
  mean flood water, -w Q / B (Q the cabin's water per unit length, ``flood_volume``; w the
  damaged segment's share of the ship's length; B the breadth): a ship in still water
  floats at it whatever its water does, within how fast it follows (the uniform runs to
  0.05 m);
- **force noise**: the median over the windows of the standard deviation of the hull's
  vertical force less its one-second running mean: the pressure waves the hull feels,
  which a weakly compressible flow carries and its viscosity damps;
- **kinetic energy**: the largest window mean of the fluid's kinetic energy from t1 +
  ``CALM`` s, once the inrush has died down: in still water it only falls or is handed
  back and forth with the ship's slow motion.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
import xarray as xr
from compare import run_report_main

import sph.engine.refinement as refinement
from sph.cases import builtin
from sph.driver import Simulation
from sph.study.findings import oscillation

#: dx, refinement level around the hull, Courant number; ``fine_cfl`` is the fine run at a
#: Courant number 5 % lower: the spread between the two is how closely a run can be compared
#: with the fine one at all (the flooding jet and the heel it drives are sensitive)
MODES = {"coarse": (0.8, 0, 0.2), "fine": (0.4, 0, 0.2), "fine_cfl": (0.4, 0, 0.19),
         "refined": (0.8, 1, 0.2)}
#: seconds after t1 from which the cabin counts as filled, and the measures' window (s)
SETTLED, WINDOW = 8.0, 4.0
#: seconds after t1 from which the fluid's kinetic energy is read (module docstring)
CALM = 20.0


def case(mode: str, t_end: float, threads: int, margin: float = 4.0):
    dx, level, cfl = MODES[mode]
    return builtin("damaged_ship", [
        f"numerics.dx={dx}", f"numerics.cfl={cfl}", f"geometry.refine_hull={level}",
        f"geometry.refine_margin={margin}", "geometry.depth=15",
        "geometry.tank_length=70", "geometry.ship_x=30", "geometry.tank_height=30",
        "geometry.absorber.start=50", "geometry.absorber.length=20",
        "geometry.wavemaker.amplitude=null", "geometry.wavemaker.theta0=0",
        "run.output_interval=0.1", "geometry.fill=0", "geometry.damage.opening=0.9",
        "geometry.damage.side=back", "geometry.damage.time_periods=0.16",
        f"run.t_end={t_end}", f"numerics.threads={threads}"])


def run(args) -> None:
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.rise is not None:
        refinement.RISE = args.rise  # read at every rebuild of the lists
    sim = Simulation(case(args.mode, args.t_end, args.threads, args.margin))
    t0 = time.perf_counter()
    sim.run(out / f"flood_{args.mode}.nc")
    print(f"{args.mode}: {sim.step} steps, {time.perf_counter() - t0:.0f} s, "
          f"{sim.n_lost} particles lost")


def _series(ds):
    return (ds["time"].values, ds["flood_ratio"].values, ds["heave"].values,
            ds["roll"].values)


def reference_free_measures(ds) -> tuple[float, float, float]:
    """The largest gap (m) between a window's mean heave and the lost-buoyancy heave of its
    mean flood water and the median force noise (N), over the windows after the cabin has
    filled, and the largest window mean of the kinetic energy (J) from t1 + ``CALM``
    (module docstring)."""
    t = ds["time"].values
    heave, q = ds["heave"].values, ds["flood_volume"].values
    fz = ds["body_force_z"].values.reshape(-1, t.size).sum(axis=0)
    w = float(str(ds.attrs["segment_weights"]).split()[-1])
    noise = oscillation(t, fz, 1.0)  # NaN within half a second of either end
    ke = ds["kinetic_energy"].values
    gaps, sds, kes = [], [], []
    t1 = ds.attrs["damage_time"]
    for a in np.arange(t1 + SETTLED, t[-1] - WINDOW + 1e-9, WINDOW):
        m = (t >= a) & (t < a + WINDOW)
        gaps.append(abs(heave[m].mean() + w * q[m].mean() / ds.attrs["breadth"]))
        sds.append(np.nanstd(noise[m]))
        if a >= t1 + CALM:
            kes.append(ke[m].mean())
    nan = float("nan")
    return (float(max(gaps)) if gaps else nan, float(np.median(sds)) if sds else nan,
            float(max(kes)) if kes else nan)


def report(args) -> None:
    d = Path(args.dir)
    runs = {m: xr.open_dataset(d / f"flood_{m}.nc") for m in MODES
            if (d / f"flood_{m}.nc").exists()}
    tf, qf, hf, rf = _series(runs["fine"])
    t1 = runs["fine"].attrs["damage_time"]
    result = {}
    for mode, ds in runs.items():
        t, q, heave, roll = _series(ds)
        n = min(len(t), len(tf))
        after = tf[:n] > t1
        dq = np.abs(q[:n] - qf[:n])[after]
        result[mode] = dict(
            t_end=float(t[n - 1]), status=ds.attrs.get("status", ""),
            wall_seconds=float(ds.attrs.get("wall_clock_seconds", 0.0)),
            q_final=float(q[n - 1]), q_fine_final=float(qf[n - 1]),
            dq_max=float(dq.max()),
            dq_rel_max_after_half=float(np.max(dq[qf[:n][after] > 0.5 * qf[n - 1]]
                                               / qf[:n][after][qf[:n][after] > 0.5 * qf[n - 1]])),
            heave_diff_max=float(np.max(np.abs(heave[:n] - hf[:n])[after])),
            heel_diff_max_deg=float(np.max(np.abs(roll[:n] - rf[:n])[after])))
        r = result[mode]
        r.update(zip(("draught_gap_max", "force_noise", "kinetic_energy_max"),
                     reference_free_measures(ds), strict=True))
        print(f"{mode}: to t = {r['t_end']:.1f} s ({r['status']}), Q/V {r['q_final']:.3f} "
              f"(fine {r['q_fine_final']:.3f}), largest |dQ/V| {r['dq_max']:.3f}, relative "
              f"{r['dq_rel_max_after_half']:.3f} once half full; heave {r['heave_diff_max']:.3f} m;"
              f" heel {r['heel_diff_max_deg']:.2f} degree; draught {r['draught_gap_max']:.3f} m"
              f" off its lost-buoyancy heave at most; force noise {r['force_noise'] / 1e3:.1f} kN;"
              f" kinetic energy up to {r['kinetic_energy_max'] / 1e3:.0f} kJ once calm;"
              f" {r['wall_seconds']:.0f} s")
    (d / "refinement_flooding.json").write_text(json.dumps(result, indent=1))


def _run_args(parser) -> None:
    parser.add_argument("--mode", choices=sorted(MODES), required=True)
    parser.add_argument("--t-end", type=float, default=30.0)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--margin", type=float, default=4.0,
                        help="geometry.refine_margin of the refined run (m)")
    parser.add_argument("--rise", type=float, default=None,
                        help="sph.engine.refinement.RISE for this run (spacings of the "
                             "box's level inside its edge at which a family rises)")


def main() -> None:
    run_report_main(__doc__, run, report, _run_args)


if __name__ == "__main__":
    main()
