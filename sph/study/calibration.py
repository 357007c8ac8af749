"""Wavemaker calibration at the ship's position.

Linear flap theory gives the flap angle for a wave of amplitude A, but the wave the ship
meets is smaller: the artificial viscosity damps it on the way from the flap, and the wave
grows less than linearly with the flap angle (at the coarse preset a 2 m wave arrives at
2H = 60 m 15 % low). As in a model basin, the wavemaker is calibrated at the
model's position instead: a wave-tank run with the ship case's numerics, tank and absorbing
zone and no ship (:func:`tank_document`) measures the incident amplitude where the ship's
centre line will be, over the periods the ship meets the wave before and after the damage
(:func:`incident_amplitude`); the next flap angle is interpolated between the runs that
bracket the target amplitude, or extrapolated from the last two, or after the first run
scaled by the ratio of the target to the measured amplitude (:func:`next_angle`), and the
run repeated until the two agree within :data:`TOLERANCE` (:func:`calibrate`). The ship
cases then run with the calibrated angle (:func:`calibrated_document`).
"""

from __future__ import annotations

import copy
import dataclasses
import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from sph.cases.ship import damage_time

#: the incident amplitude at the ship is the target within this fraction
TOLERANCE = 0.02
#: wave-tank runs at most; a calibration that has not converged by then stops with an error
MAX_RUNS = 5
#: the measuring window: from the damage time t1 for this many wave periods (the ship meets
#: fully developed waves from t1 on, Cao et al. 2019, Sec. IV A)
WINDOW_PERIODS = 3.0
#: name of the surface probe at the ship's centre line
PROBE = "ship"


class CalibrationError(RuntimeError):
    """The calibration did not converge."""


def tank_document(ship_doc: Mapping[str, Any]) -> dict:
    """The wave-tank case file of a ship case file: the ship's numerics, fluid, tank,
    absorbing zone and wavemaker (its angle from linear theory for the ship's amplitude),
    no ship, one surface probe at the ship's centre line, run to the end of the measuring
    window."""
    from sph.bodies.wavemaker import FlapMotion
    from sph.cases import build_case

    cfg = build_case(copy.deepcopy(dict(ship_doc)))
    g = cfg.geometry
    if g.wavemaker.file is not None:
        raise ValueError("a wavemaker driven by a file is not calibrated")
    period = 2.0 * math.pi / g.wavemaker.omega
    wavemaker = dataclasses.asdict(g.wavemaker)
    wavemaker.update(theta0=FlapMotion(g.wavemaker, g.depth, cfg.fluid.gravity).theta0,
                     amplitude=None)
    return {
        "case": "wave_tank",
        "title": f"Wavemaker calibration for: {cfg.title}",
        "numerics": dataclasses.asdict(cfg.numerics),
        "fluid": dataclasses.asdict(cfg.fluid),
        "run": {"t_end": round(damage_time(cfg) + WINDOW_PERIODS * period, 9),
                "output_interval": cfg.run.output_interval},
        "geometry": {"depth": g.depth, "tank_length": g.tank_length,
                     "tank_height": g.tank_height, "wavemaker": wavemaker,
                     "absorber": dataclasses.asdict(g.absorber)},
        "probes": {"surface": [{"name": PROBE, "x": g.ship_x}]},
    }


def incident_amplitude(t, eta, start: float, omega: float) -> float:
    """Amplitude of the wave-frequency component of the surface elevation ``eta`` from
    ``start`` on (a sinusoid fitted with a straight line by least squares,
    :func:`sph.study.findings.harmonics`)."""
    from sph.study.findings import harmonics, window

    t = np.asarray(t, dtype=float)
    return float(abs(harmonics(window(t, t, start), window(t, eta, start), [omega])[0]))


def run_tank(doc: Mapping[str, Any]) -> tuple[np.ndarray, np.ndarray]:
    """Run a wave-tank case file in this process; times and the elevation at the ship's
    probe."""
    from sph.cases import build_case
    from sph.driver import Simulation

    sim = Simulation(build_case(copy.deepcopy(dict(doc))))
    sim.run()
    ds = sim.dataset()
    return ds["time"].values, ds["probe_elevation"].sel(probe=PROBE).values


def calibrate(ship_doc: Mapping[str, Any],
              run: Callable[[Mapping[str, Any]], tuple] = run_tank) -> dict:
    """Calibrate the flap angle of a ship case file (see the module docstring).

    Returns ``theta0`` (rad), the ``target`` amplitude (m) and the ``runs``: the angle and
    the measured amplitude of each wave-tank run, the last within :data:`TOLERANCE`.

    Raises
    ------
    CalibrationError
        When :data:`MAX_RUNS` runs do not bring the amplitude within the tolerance.
    """
    from sph.cases import build_case

    cfg = build_case(copy.deepcopy(dict(ship_doc)))
    target = target_amplitude(cfg)
    omega = cfg.geometry.wavemaker.omega
    doc = tank_document(ship_doc)
    runs = []
    for _ in range(MAX_RUNS):
        theta0 = doc["geometry"]["wavemaker"]["theta0"]
        t, eta = run(doc)
        measured = incident_amplitude(t, eta, damage_time(cfg), omega)
        runs.append({"theta0": theta0, "amplitude": measured})
        if not measured >= 0.1 * target:  # NaN included
            raise CalibrationError(f"no wave at x = {cfg.geometry.ship_x:g} m with flap "
                                   f"angle {theta0:.5g} rad: incident amplitude "
                                   f"{measured:.3g} m, below a tenth of the target "
                                   f"{target:.4g} m")
        if abs(measured / target - 1.0) <= TOLERANCE:
            return {"theta0": theta0, "target": target, "runs": runs,
                    "tolerance": TOLERANCE, "x": cfg.geometry.ship_x}
        doc["geometry"]["wavemaker"]["theta0"] = next_angle(runs, target)
    tried = ", ".join(f"{r['theta0']:.6g} rad -> {r['amplitude']:.4g} m" for r in runs)
    raise CalibrationError(f"incident amplitude {runs[-1]['amplitude']:.4g} m after "
                           f"{MAX_RUNS} runs, target {target:.4g} m +- {100 * TOLERANCE:g} % "
                           f"({tried})")


def next_angle(runs, target: float) -> float:
    """The flap angle of the next wave-tank run from the ``runs`` so far (dicts with
    ``theta0`` and ``amplitude``): linear interpolation between the closest runs below and
    above the target amplitude where both exist, else the secant through the last two
    runs; where that has no rising slope or leaves [1/2, 2] times the last angle (the
    measured amplitudes scatter by a per cent or two), and after the first run, the last
    angle scaled by target / measured.

    The amplitude at the ship is not proportional to the angle: at the coarse preset it rose
    1.5-1.7 times as fast in relative terms near 2 m (0.05801 -> 1.922 m, 0.06038 ->
    2.060 m), so that the proportional step alone overshot each time and oscillated about
    the target (1.92, 2.06, 1.96 m) without reaching it in four runs.
    """
    last = runs[-1]
    below = [r for r in runs if r["amplitude"] < target]
    above = [r for r in runs if r["amplitude"] > target]
    if below and above:
        pair = (min(below, key=lambda r: target - r["amplitude"]),
                min(above, key=lambda r: r["amplitude"] - target))
    else:
        pair = tuple(runs[-2:])
    if len(pair) == 2:
        (t0, a0), (t1, a1) = ((r["theta0"], r["amplitude"]) for r in pair)
        if t1 != t0 and (a1 - a0) / (t1 - t0) > 0.0:
            theta = t1 + (target - a1) * (t1 - t0) / (a1 - a0)
            if 0.5 * last["theta0"] <= theta <= 2.0 * last["theta0"]:
                return float(theta)
    return float(last["theta0"] * target / last["amplitude"])


def target_amplitude(cfg) -> float:
    """The wave amplitude (m) a ship case asks for: its ``wavemaker.amplitude``, or the
    linear-theory amplitude of its ``theta0``."""
    from sph.bodies.wavemaker import flap_wave_amplitude

    w = cfg.geometry.wavemaker
    if w.amplitude is not None:
        return float(w.amplitude)
    return flap_wave_amplitude(w.theta0, w.omega, cfg.geometry.depth, cfg.fluid.gravity)


def calibrated_document(ship_doc: Mapping[str, Any], result: Mapping[str, Any]) -> dict:
    """The ship case file with the calibrated flap angle in place of its amplitude."""
    doc = copy.deepcopy(dict(ship_doc))
    wm = doc.setdefault("geometry", {}).setdefault("wavemaker", {})
    wm["theta0"] = float(result["theta0"])
    wm["amplitude"] = None
    return doc
