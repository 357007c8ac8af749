"""A regular wave crossing a refinement box (variable resolution, docs/model.md).

A scaled copy of the paper's wave tank near its coarse preset (A / dx = 1.6, lambda / dx = 97,
ka = 0.10): depth 1 m, omega = 5 rad/s (lambda = 2.42 m), A = 0.04 m, tank 8.5 m with the
damping zone over the last wavelength. A box where a ship would sit, x in [3.5, 5.0] m from
0.4 m below the surface to above the crests, at level 1 (ratio 2) or level 2 inside a
level-1 box (ratio 4). The same run without a box is the reference.

    python benchmarks/refinement_wave.py run --levels 0 --out DIR   # 0, 1 or 2
    python benchmarks/refinement_wave.py report DIR                 # the three runs

``run`` writes ``DIR/wave_L<levels>.npz`` (the gauges' records). ``report`` separates
the incident and reflected waves on the gauges upstream of the box (Mansard & Funke), and
compares each run's first-harmonic amplitude and phase on the gauges downstream of the box
with the run without it; it prints the table and writes ``DIR/refinement_wave.json``.

What a box should change, resolution alone: the same tank at the box's dx everywhere,

    python benchmarks/refinement_wave.py run --levels 0 --dx 0.0125 --out DIR/fine

(about 8 times the coarse run), gives the wave number and the viscous decay per metre at
each dx (fits over the upstream gauges), and from them what a box of the level-1 box's
length should do to the wave downstream (``fine_reference`` in the report): the amplitude
ratio exp((decay_coarse - decay_fine) L) and the phase (k_fine - k_coarse) L, with the step
in wave number's own reflection |k_fine - k_coarse| / (k_fine + k_coarse).
"""

from __future__ import annotations

import cmath
import json
import time
from pathlib import Path

import numpy as np
from compare import run_report_main

from sph.cases import builtin
from sph.driver import Simulation
from sph.study.analysis import harmonic_fit, reflection_coefficient

DEPTH, OMEGA, AMPLITUDE, LENGTH = 1.0, 5.0, 0.04, 8.5
UPSTREAM = [1.0, 1.3, 1.6, 1.9, 2.2, 2.5, 2.8]
DOWNSTREAM = [5.4, 5.7, 6.0]
BOXES = {
    0: [],
    1: [{"x": [3.5, 5.0], "z": [0.6, 1.3], "level": 1}],
    2: [{"x": [3.2, 5.3], "z": [0.45, 1.4], "level": 1},
        {"x": [3.5, 5.0], "z": [0.6, 1.3], "level": 2}],
}
WINDOW = (7.5, 11.0)


def case(levels: int, dx: float, t_end: float, threads: int):
    lam = 2.42
    gauges = [{"name": f"x{x:.1f}", "x": x} for x in UPSTREAM + DOWNSTREAM]
    over = [("numerics.dx", dx), ("numerics.threads", threads), ("run.t_end", t_end),
            ("run.output_interval", 0.02), ("geometry.depth", DEPTH),
            ("geometry.tank_length", LENGTH), ("geometry.tank_height", 1.5),
            ("geometry.wavemaker.omega", OMEGA), ("geometry.wavemaker.theta0", None),
            ("geometry.wavemaker.amplitude", AMPLITUDE),
            ("geometry.wavemaker.ramp_time", 2.5),
            ("geometry.absorber.start", LENGTH - lam), ("geometry.absorber.length", lam),
            ("probes.surface", gauges), ("probes.pressure", [])]
    if BOXES[levels]:
        over.append(("numerics.refinement", BOXES[levels]))
    return builtin("wave_tank", over)


def run(args) -> None:
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    sim = Simulation(case(args.levels, args.dx, args.t_end, args.threads))
    t0 = time.perf_counter()
    sim.run()
    wall = time.perf_counter() - t0
    ds = sim.dataset()
    eta = ds.probe_elevation
    mass = ds.fluid_mass.values if "fluid_mass" in ds else np.zeros(0)
    np.savez(out / f"wave_L{args.levels}.npz", time=ds.time.values, eta=eta.values,
             names=np.array(eta[eta.dims[0]].values, dtype=str), mass=mass,
             wavenumber=ds.attrs["theory_wavenumber"], steps=sim.step, wall=wall)
    print(f"levels {args.levels}: {sim.step} steps, {wall:.0f} s", flush=True)


def _load(path):
    with np.load(path) as f:
        return {k: f[k] for k in f.files}


def _amplitudes(run, names, window):
    t = run["time"]
    sel = (t >= window[0]) & (t <= window[1])
    out = []
    for n in names:
        eta = run["eta"][list(run["names"]).index(n)]
        ok = sel & np.isfinite(eta)
        out.append(harmonic_fit(t[ok], eta[ok], OMEGA)[0])
    return np.array(out)


def report(args) -> None:
    d = Path(args.dir)
    runs = {lv: _load(d / f"wave_L{lv}.npz") for lv in BOXES
            if (d / f"wave_L{lv}.npz").exists()}
    k = float(runs[0]["wavenumber"])
    up = [f"x{x:.1f}" for x in UPSTREAM]
    down = [f"x{x:.1f}" for x in DOWNSTREAM]
    base_up = _amplitudes(runs[0], up, WINDOW)
    base_down = _amplitudes(runs[0], down, WINDOW)
    result = {}
    for lv, ds in runs.items():
        t = ds["time"]
        etas = np.array([ds["eta"][list(ds["names"]).index(n)] for n in up])
        refl = reflection_coefficient(t, etas, np.array(UPSTREAM), OMEGA, k, WINDOW)
        # the wave the box reflects: this run's upstream field less the reference's
        zu = _amplitudes(ds, up, WINDOW) - base_up
        sep = np.column_stack([np.exp(-1j * k * np.array(UPSTREAM)),
                               np.exp(1j * k * np.array(UPSTREAM))])
        (_, a_r), *_ = np.linalg.lstsq(sep, zu, rcond=None)
        zd = _amplitudes(ds, down, WINDOW)
        ratio = np.abs(zd) / np.abs(base_down)
        phase = np.array([cmath.phase(a / b) for a, b in zip(zd, base_down, strict=True)])
        result[lv] = dict(
            incident=float(refl["incident"]), reflection_total=float(refl["coefficient"]),
            reflection_by_box=float(abs(a_r) / refl["incident"]),
            downstream_amplitude=[float(x) for x in np.abs(zd)],
            amplitude_ratio=[float(x) for x in ratio],
            phase_difference_rad=[float(x) for x in phase],
            mass_drift=float(ds["mass"][-1] / ds["mass"][0] - 1.0) if len(ds["mass"]) else 0.0,
            steps=int(ds["steps"]), wall_seconds=float(ds["wall"]))
        r = result[lv]
        print(f"levels {lv}: incident {r['incident']:.4f} m, reflection {r['reflection_total']:.4f}"
              f", by the box {r['reflection_by_box']:.4f}; downstream amplitude / reference "
              f"{np.round(ratio, 4)}, phase {np.round(phase, 4)} rad; mass drift "
              f"{r['mass_drift']:.1e}")
    fine = d / "fine" / "wave_L0.npz"
    if fine.exists():
        result["fine_reference"] = _fine_reference(runs, _load(fine), down, base_down, result)
    (d / "refinement_wave.json").write_text(json.dumps(result, indent=1))


def _propagation(run, up):
    """Wave number (1/m) and amplitude decay per metre fitted over the upstream gauges
    ``up``."""
    a = _amplitudes(run, up, WINDOW)
    k = -np.polyfit(UPSTREAM, np.unwrap(np.angle(a)), 1)[0]
    decay = -np.polyfit(UPSTREAM, np.log(np.abs(a)), 1)[0]
    return float(k), float(decay)


def _fine_reference(runs, fine, down, coarse, result) -> dict:
    """The uniform run at the box's dx against the coarse one (``coarse``: its downstream
    amplitudes), what a box of the level-1 box's length should change downstream from that,
    and each run with a box (``result``: the report's) against the uniform fine one (module
    docstring)."""
    up = [f"x{x:.1f}" for x in UPSTREAM]
    (kc, dc), (kf, df) = _propagation(runs[0], up), _propagation(fine, up)
    length = BOXES[1][0]["x"][1] - BOXES[1][0]["x"][0]
    zf = _amplitudes(fine, down, WINDOW)
    out = dict(wavenumber_coarse=kc, wavenumber_fine=kf, decay_per_m_coarse=dc,
               decay_per_m_fine=df,
               step_reflection=abs(kf - kc) / (kf + kc),
               box_amplitude_ratio_expected=float(np.exp((dc - df) * length)),
               box_phase_expected_rad=(kf - kc) * length,
               fine_over_coarse_downstream=[float(x) for x in np.abs(zf) / np.abs(coarse)],
               fine_minus_coarse_phase_rad=[float(x) for x in np.angle(zf / coarse)],
               with_box_over_fine={str(lv): [float(x) for x in
                                            np.array(r["downstream_amplitude"]) / np.abs(zf)]
                                   for lv, r in result.items() if lv})
    print(f"uniform fine: k {kf:.4f} 1/m (coarse {kc:.4f}), decay {100 * df:.2f} %/m (coarse "
          f"{100 * dc:.2f}); the step in k reflects {100 * out['step_reflection']:.2f} %; a "
          f"box of {length:g} m should change the wave downstream by "
          f"{out['box_amplitude_ratio_expected']:.4f} in amplitude and "
          f"{out['box_phase_expected_rad']:+.4f} rad in phase; downstream fine / coarse "
          f"{np.round(out['fine_over_coarse_downstream'], 4)}")
    return out


def _run_args(parser) -> None:
    parser.add_argument("--levels", type=int, choices=sorted(BOXES), required=True)
    parser.add_argument("--dx", type=float, default=0.025)
    parser.add_argument("--t-end", type=float, default=WINDOW[1])
    parser.add_argument("--threads", type=int, default=2)


def main() -> None:
    run_report_main(__doc__, run, report, _run_args)


if __name__ == "__main__":
    main()
