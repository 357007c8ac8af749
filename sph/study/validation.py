"""Validation-ladder metrics measured on the workflow's validation runs.

Each function takes the runs of one target (opened netCDF datasets) and returns rows
``target, run, quantity, measured, reference, unit, error, source``: ``error`` is the relative
difference ``measured / reference - 1`` where a reference value exists, or a normalised RMS
difference for a time series compared with an experiment.

The targets that the workflow runs are the table :data:`TARGETS`: one :class:`Target` per
target (id, what it compares, the reference, its runs, its metric, the tolerance the
project's tests ask, its figures). The workflow's rules, ``sph.study.sweeps`` and
``workflow/scripts/validation_summary.py`` read it; a new target is one more record (and its
preset section, ``sph.study.sweeps.PRESET_SECTION_KEYS``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from sph.bodies.wavemaker import FlapMotion, group_velocity
from sph.cases import build_case
from sph.engine.config import Numerics
from sph.schema import ConfigError
from sph.study.analysis import (
    artificial_viscosity_nu,
    flap_wave_record,
    koshizuka_front,
    oscillation_frequency,
    reflection_coefficient,
    validation_data_dir,
    viscous_wave_damping,
    wave_statistics,
)

#: Table II of Cao et al. (2019): first sloshing frequency of the U-shaped cabin, rad/s
TABLE_II_SLOSHING = {0.25: 0.87, 0.5: 1.12, 0.75: 1.26}
#: Table II: roll and heave natural frequencies of the ship, rad/s (omega_w = 1.0 rad/s)
TABLE_II_ROLL = 1.06
TABLE_II_HEAVE = 1.28


def frequency(t, y) -> tuple[float, float]:
    """:func:`sph.study.analysis.oscillation_frequency`, or NaN when the record is too short."""
    try:
        return oscillation_frequency(t, y)
    except ValueError:
        return float("nan"), float("nan")


def steady_wave(t, eta, omega: float, window) -> dict:
    """:func:`sph.study.analysis.wave_statistics`, or NaN values when the window is too short."""
    try:
        return wave_statistics(t, eta, omega, tuple(window))
    except ValueError:
        nan = float("nan")
        return dict(amplitude=nan, mean=nan, period=nan, height=nan)


def _row(target, run, quantity, measured, reference, unit, source, error=None) -> dict:
    if error is None and reference not in (None, 0) and np.isfinite(measured):
        error = measured / reference - 1.0
    return dict(target=target, run=run, quantity=quantity, measured=float(measured),
                reference=float("nan") if reference is None else float(reference), unit=unit,
                error=float("nan") if error is None else float(error), source=source)


def wave_tank(runs: Mapping[str, object], window: Sequence[float]) -> list[dict]:
    """Steady amplitude and period at WP1 and WP2 against linear flap theory, per run; the
    reflection coefficient of the absorbing zone from all probes of the finest run."""
    rows = []
    finest = None
    for run, ds in runs.items():
        t = ds["time"].values
        omega = float(ds.attrs["omega"])
        a = float(ds.attrs["theory_amplitude"])
        dx = float(ds.attrs["dx"])
        for probe in ("WP1", "WP2"):
            if probe not in ds["probe"].values:
                continue
            eta = ds["probe_elevation"].sel(probe=probe).values
            st = steady_wave(t, eta, omega, window)
            label = f"{run} (dx = {dx:g} m = {dx / a:.2f} A)"
            rows.append(_row("wave_tank", label, f"amplitude at {probe}", st["amplitude"], a,
                             "m", "linear flap theory"))
            rows.append(_row("wave_tank", label, f"period at {probe}", st["period"],
                             2 * math.pi / omega, "s", "wavemaker period"))
        if finest is None or dx < float(finest.attrs["dx"]):
            finest = ds
    if finest is not None and finest["probe"].size >= 3:
        sep = wave_separation(finest, window)
        if sep is not None:
            label = f"dx = {float(finest.attrs['dx']):g} m"
            rows.append(_row("wave_tank", label, "reflection coefficient", sep["coefficient"],
                             None, "1", "absorbing zone (small is good)"))
            rows.append(_row("wave_tank", label, "incident amplitude at the flap",
                             sep["incident"], float(finest.attrs["theory_amplitude"]), "m",
                             "linear flap theory (probe array, artificial-viscosity decay)"))
    return rows


#: probes nearer the flap than this many depths sit in its near field (evanescent modes, which
#: decay as exp(-pi x / h), still 15 % of their size at the flap there) and are left out of the
#: incident/reflected fit
NEAR_FIELD_DEPTHS = 0.6


def wave_separation(ds, window: Sequence[float]) -> dict | None:
    r"""Incident and reflected waves of a ``wave_tank`` run from its surface probes
    (:func:`sph.study.analysis.reflection_coefficient`), with the spatial decay that the run's
    artificial viscosity gives the incident wave. Only probes between 0.6 depths from the
    flap (where the evanescent modes of the flap, which decay as :math:`e^{-\pi x/h}`,
    are down to 15 % of their size at the flap) and the start of the absorbing zone (where
    the zone, not the viscosity, takes the wave's energy) count. None if fewer than three
    probes qualify or a probe's x is unknown."""
    names = list(ds["probe"].values)
    positions = probe_positions(ds)
    xs = [positions.get(p) for p in names]
    if any(x is None for x in xs):
        return None
    x_max = float(ds.attrs["absorber_start"]) if int(ds.attrs["absorber"]) else math.inf
    x_min = NEAR_FIELD_DEPTHS * float(ds.attrs["depth"])
    keep = [i for i, x in enumerate(xs) if x_min <= x <= x_max]
    if len(keep) < 3:
        return None
    names = [names[i] for i in keep]
    xs = [xs[i] for i in keep]
    etas = [ds["probe_elevation"].sel(probe=p).values for p in names]
    return reflection_coefficient(ds["time"].values, etas, xs, float(ds.attrs["omega"]),
                                  float(ds.attrs["theory_wavenumber"]), tuple(window),
                                  decay=run_wave_decay(ds))


def probe_positions(ds) -> dict[str, float]:
    """x (m) of each surface probe of a run, by name, from the run's configuration."""
    surface = (_run_config(ds).get("probes") or {}).get("surface") or []
    return {str(p["name"]): float(p["x"]) for p in surface if "name" in p and "x" in p}


def _run_config(ds) -> dict:
    import yaml

    return yaml.safe_load(ds.attrs.get("config", "")) or {}


def _run_gravity(ds) -> float:
    return float((_run_config(ds).get("fluid") or {}).get("gravity", 9.81))


def run_wave_decay(ds) -> float:
    """Spatial amplitude decay rate (1/m) that the artificial viscosity of a ``wave_tank``
    run gives its progressive wave: :func:`sph.study.analysis.viscous_wave_damping` with
    :func:`run_viscosity`, over the group velocity."""
    omega = float(ds.attrs["omega"])
    return viscous_wave_damping(run_viscosity(ds), float(ds.attrs["theory_wavenumber"])) / (
        group_velocity(omega, float(ds.attrs["depth"]), _run_gravity(ds)))


def run_viscosity(ds) -> float:
    """Kinematic viscosity (m2/s) that the artificial viscosity of a run amounts to,
    :func:`sph.study.analysis.artificial_viscosity_nu` with the run's alpha, h and c0."""

    alpha = (_run_config(ds).get("numerics") or {}).get("alpha", Numerics.alpha)
    return artificial_viscosity_nu(float(alpha), float(ds.attrs["smoothing_length"]),
                                   float(ds.attrs["speed_of_sound"]))


def _flap_angles(ds, t) -> np.ndarray:
    """Flap angle (rad) at the times ``t``: from the run's flap configuration where it can
    be rebuilt (so it extends past the run's end), else the recorded ``flap_angle``."""

    try:
        cfg = build_case(_run_config(ds))
        motion = FlapMotion(cfg.geometry.wavemaker, cfg.geometry.depth, cfg.fluid.gravity)
    except (ConfigError, OSError, AttributeError, KeyError, TypeError, ValueError):
        return np.radians(np.interp(t, ds["time"].values, ds["flap_angle"].values))
    return np.array([motion.angle(ti)[0] for ti in t])


def linear_wave_record(ds, probe: str, nu: float = 0.0, dt: float = 0.05,
                       pad: float = 60.0):
    """Linear theory at a probe of a ``wave_tank`` run, start-up transient included:
    :func:`sph.study.analysis.flap_wave_record` driven by the run's flap motion, on a uniform grid
    of step ``dt`` from 0 to the run's end. ``nu`` > 0 adds the viscous decay of each
    frequency (:func:`run_viscosity` gives the run's own). The flap motion is continued
    ``pad`` seconds past the run's end (from the run's configuration; where that cannot be
    rebuilt, the recorded ``flap_angle`` is used and held), because the progressive-wave
    solution, which leaves out the evanescent modes, feels a sudden stop of the flap a few
    seconds before it happens. Returns ``(t, eta)``."""
    x = probe_positions(ds).get(probe)
    if x is None:
        raise ValueError(f"probe {probe!r} has no x in the run's configuration")
    g = _run_gravity(ds)
    t_end = float(ds["time"].values[-1])
    t = np.arange(0.0, t_end + pad + 0.5 * dt, dt)
    eta = flap_wave_record(t, _flap_angles(ds, t), x, float(ds.attrs["depth"]), g=g, nu=nu)
    keep = t <= t_end + 0.5 * dt
    return t[keep], eta[keep]


def sloshing(runs: Mapping[str, object]) -> list[dict]:
    """First sloshing frequency of the U-shaped cabin against Table II."""
    rows = []
    for run, ds in runs.items():
        fill = float(ds.attrs["fill"])
        omega, _ = frequency(ds["time"].values, ds["centre_of_mass_x"].values)
        ref = TABLE_II_SLOSHING.get(round(fill, 6))
        rows.append(_row("sloshing", f"{run} (fill {100 * fill:g} %, dx = "
                         f"{float(ds.attrs['dx']):g} m)", "first sloshing frequency", omega,
                         ref, "rad/s", "Table II" if ref else "no reference"))
    return rows


def decay(runs: Mapping[str, object]) -> list[dict]:
    """Roll and heave natural frequencies of the intact ship against Table II."""
    rows = []
    for run, ds in runs.items():
        name, ref = ("roll", TABLE_II_ROLL) if run == "roll" else ("heave", TABLE_II_HEAVE)
        omega, zeta = frequency(ds["time"].values, ds[name].values)
        label = f"{run} (dx = {float(ds.attrs['dx']):g} m)"
        rows.append(_row("decay", label, f"{name} natural frequency", omega, ref, "rad/s",
                         "Table II"))
        rows.append(_row("decay", label, f"{name} damping ratio", zeta, None, "1",
                         "fitted decay"))
    return rows


def hadzic_series(path: str | Path | None = None,
                  project_signs: bool = True) -> dict[str, np.ndarray]:
    """The Hadzic et al. (2005) series: name -> array of (time, value) rows.

    Names: ``WaveProbe_N1``, ``WaveProbe_N2`` (m), ``WP_Heave`` (m), ``WP_Roll`` (degree),
    ``WP_Sway`` (m). With ``project_signs`` the roll is given in this project's convention
    (positive when the top of the body moves towards +x, the direction of wave travel): the
    file counts it the other way (the simulated roll correlates with the measured one at the
    lag of heave and sway only after the sign change; ``docs/validation/floating_box.md``).
    """
    if path is None:
        path = validation_data_dir() / "hadzic2005" / "EXP_FloatingWavesVal_Hadzic_et_al_2005.txt"
    with open(path, encoding="latin-1") as fh:
        lines = fh.read().splitlines()
    header = lines[1].split("\t")
    names = [header[k] for k in range(1, len(header), 2)]
    cols: dict[str, list] = {n: [] for n in names}
    for line in lines[2:]:
        parts = line.split("\t")
        for k, n in enumerate(names):
            try:
                t, v = float(parts[2 * k]), float(parts[2 * k + 1])
            except (IndexError, ValueError):
                continue
            cols[n].append((t, v))
    out = {n: np.array(v) for n, v in cols.items()}
    if project_signs and len(out.get("WP_Roll", ())):
        out["WP_Roll"][:, 1] *= -1.0
    return out


#: experiment series -> (variable, probe, unit)
HADZIC_MAP = {"WaveProbe_N1": ("probe_elevation", "WP1", "m"),
              "WaveProbe_N2": ("probe_elevation", "WP2", "m"),
              "WP_Heave": ("heave", None, "m"), "WP_Roll": ("roll", None, "degree"),
              "WP_Sway": ("sway", None, "m")}


def simulated(ds, variable: str, probe: str | None):
    if variable not in ds:
        return None
    v = ds[variable]
    if probe is not None:
        if probe not in ds["probe"].values:
            return None
        v = v.sel(probe=probe)
    return v.values


def series_errors(t, y, te, ye, max_lag: float, dt: float | None = None) -> dict:
    """Amplitude, phase and shape errors of a simulated series ``(t, y)`` against a measured
    one ``(te, ye)`` (irregularly sampled, as digitised series are).

    Both are interpolated onto a uniform grid over the measured span (clipped to the run);
    the simulated series is then shifted by the lag in ``[-max_lag, max_lag]`` that
    maximises the correlation. Returns

    ``amplitude_ratio``
        RMS of the simulated series about its mean over the same of the measured one;
    ``lag``
        the best shift in s, positive when the simulation lags the measurement;
    ``correlation``
        Pearson correlation at that lag (1: same shape);
    ``rms``, ``nrms``
        RMS difference without shift, and the same over the measured half range.
    """
    t, y, te, ye = (np.asarray(a, float) for a in (t, y, te, ye))
    lo, hi = max(te[0], t[0]), min(te[-1], t[-1])
    if hi - lo <= 2.0 * max_lag:
        raise ValueError(f"the series overlap over {max(hi - lo, 0.0):.3g} s, less than "
                         f"twice the largest lag {max_lag:g} s")
    if dt is None:
        dt = min(float(np.median(np.diff(te))), float(np.median(np.diff(t)))) / 2.0
    grid = np.arange(lo, hi + 0.5 * dt, dt)
    e = np.interp(grid, te, ye)
    rms = float(np.sqrt(np.mean((np.interp(grid, t, y) - e) ** 2)))
    ec = e - e.mean()
    best_c, best_lag = -np.inf, 0.0
    for lag in np.arange(-max_lag, max_lag + 0.5 * dt, dt):
        s = np.interp(grid + lag, t, y)
        sc = s - s.mean()
        den = float(np.sqrt(np.sum(sc * sc) * np.sum(ec * ec)))
        c = float(np.sum(sc * ec)) / den if den > 0.0 else -np.inf
        if c > best_c:
            best_c, best_lag = c, float(lag)
    s = np.interp(grid, t, y)
    amp = float(np.std(s) / np.std(e)) if np.std(e) > 0.0 else float("nan")
    scale = 0.5 * float(np.ptp(e)) or 1.0
    return dict(amplitude_ratio=amp, lag=best_lag, correlation=best_c, rms=rms,
                nrms=rms / scale)


def dominant_period(t, y) -> float:
    """Period (s) of the largest peak of the amplitude spectrum of ``y`` (mean removed,
    resampled uniformly); ``nan`` for a constant series."""
    t, y = np.asarray(t, float), np.asarray(y, float)
    dt = float(np.median(np.diff(t)))
    grid = np.arange(t[0], t[-1], dt)
    v = np.interp(grid, t, y)
    v = (v - v.mean()) * np.hanning(len(v))
    spec = np.abs(np.fft.rfft(v))
    f = np.fft.rfftfreq(len(v), dt)
    if len(spec) < 2 or not np.any(spec[1:] > 0.0):
        return float("nan")
    return float(1.0 / f[1 + int(np.argmax(spec[1:]))])


#: largest lag searched when matching the floating box's series with the experiment: half
#: the wave group's dominant period (about 0.75 s), so that no lag jumps a whole wave
BOX_MAX_LAG = 0.35


def floating_box_errors(ds, exp: Mapping[str, np.ndarray],
                        max_lag: float = BOX_MAX_LAG) -> dict[str, dict]:
    """:func:`series_errors` of each series of a floating box run against the experiment
    (:func:`hadzic_series` names); series absent from either side, or overlapping the run
    over less than ``4 max_lag``, are left out."""
    out = {}
    t = ds["time"].values
    for name, (variable, probe, _unit) in HADZIC_MAP.items():
        y = simulated(ds, variable, probe)
        data = exp.get(name)
        if y is None or data is None or len(data) < 5:
            continue
        sel = (data[:, 0] >= t[0]) & (data[:, 0] <= t[-1])
        if sel.sum() < 5 or data[sel, 0][-1] - data[sel, 0][0] < 4.0 * max_lag:
            continue
        out[name] = series_errors(t, y, data[sel, 0], data[sel, 1], max_lag)
    return out


def floating_box(runs: Mapping[str, object], exp: Mapping[str, np.ndarray]) -> list[dict]:
    """Per run and series: amplitude ratio, lag (s), correlation and normalised RMS
    difference against the experiment (:func:`floating_box_errors`)."""
    rows = []
    for run, ds in runs.items():
        label = f"{run} (dx = {float(ds.attrs['dx']):g} m)"
        src = "Hadzic et al. (2005)"
        for name, e in floating_box_errors(ds, exp).items():
            unit = HADZIC_MAP[name][2]
            rows.append(_row("floating_box", label, f"{name} amplitude ratio",
                             e["amplitude_ratio"], 1.0, "1", src))
            rows.append(_row("floating_box", label, f"{name} lag", e["lag"], None, "s", src))
            rows.append(_row("floating_box", label, f"{name} correlation", e["correlation"],
                             None, "1", src))
            rows.append(_row("floating_box", label, f"{name} RMS difference", e["rms"], None,
                             unit, src, error=e["nrms"]))
    return rows


def dam_break(runs: Mapping[str, object], t_max: float = 0.6) -> list[dict]:
    """Surge-front lead over Koshizuka & Oka (1996) up to ``t_max``: RMS and largest."""
    exp = koshizuka_front()
    exp = exp[exp[:, 0] <= t_max]
    rows = []
    for run, ds in runs.items():
        t = ds["time"].values
        sel = exp[:, 0] <= t[-1]
        if sel.sum() < 2:
            continue
        rel = np.interp(exp[sel, 0], t, ds["front_position"].values) / exp[sel, 1] - 1.0
        label = f"{run} (dx = {float(ds.attrs['dx']):g} m)"
        rows.append(_row("dam_break", label, "front lead, RMS", float(np.sqrt(np.mean(rel**2))),
                         None, "1", "Koshizuka & Oka (1996)",
                         error=float(np.sqrt(np.mean(rel**2)))))
        k = int(np.argmax(np.abs(rel)))
        rows.append(_row("dam_break", label, f"front lead, largest (t = {exp[sel][k, 0]:.2f} s)",
                         float(rel[k]), None, "1", "Koshizuka & Oka (1996)",
                         error=float(rel[k])))
    return rows


def cylinder(runs: Mapping[str, object]) -> list[dict]:
    """The steady wave behind the submerged cylinder against Havelock's linear theory:
    wave length and amplitude per run (:func:`sph.study.current.havelock_comparison`)."""
    from sph.study.current import havelock_comparison

    rows = []
    for run, ds in runs.items():
        fit = havelock_comparison(ds)
        label = f"{run} (F = {fit['froude']:.3f}, dx = {float(ds.attrs['dx']):g} m)"
        src = "Havelock (1926), Lamb Sec. 247"
        rows.append(_row("cylinder", label, "wave length", fit["wavelength"],
                         fit["theory_wavelength"], "m", src))
        rows.append(_row("cylinder", label, "wave amplitude", fit["amplitude"],
                         fit["theory_amplitude"], "m", src))
    return rows


# ------------------------------------------------------------------------------ the targets
# Runs of a target: (the preset's section of the target, its numbers parsed, as
# sph.study.sweeps.validation_runs passes it; the folder of the experimental series) ->
# run id -> case-file values (dotted keys).
def _common(sec: Mapping) -> dict:
    """Case-file values of every run of a target: the preset section's ``set``, ``dx``,
    ``t_end`` and ``output_interval``."""
    over = dict(sec.get("set") or {})
    over["numerics.dx"] = sec["dx"] if "dx" in sec else None
    over["run.t_end"] = sec["t_end"]
    if "output_interval" in sec:
        over["run.output_interval"] = sec["output_interval"]
    return over


#: numerics a wave tank does not take from the ship case: its spacing is the run's, and
#: threads and refinement boxes belong to the ship's runs
_NOT_SHIP_NUMERICS = ("dx", "threads", "refinement")


def ship_numerics() -> dict:
    """Case-file values (dotted keys) that give a wave tank the numerics and the absorbing
    zone of the built-in ``damaged_ship`` case: kernel, density filter and diffusion,
    artificial viscosity, sound speed, shifting, wall treatment; the absorbing zone's form,
    speed and strength (its place is the same in both tanks). The built-in ``wave_tank``
    case has its own, tuned for the wave alone (half the viscosity, twice the absorber's
    strength); the validation ladder measures the wave the ship's model makes."""
    from dataclasses import asdict

    from sph.cases import CASES
    from sph.schema import build

    ship = CASES["damaged_ship"]
    doc = ship.defaults()  # the sections alone: the ship's checks are not the tank's
    num = build(Numerics, doc.get("numerics"), "numerics")
    absorber = build(ship.Geometry, doc.get("geometry"), "geometry").absorber
    out = {f"numerics.{k}": v for k, v in asdict(num).items() if k not in _NOT_SHIP_NUMERICS}
    for k in ("form", "speed", "strength"):
        out[f"geometry.absorber.{k}"] = getattr(absorber, k)
    return out


def _wave_tank_runs(sec: Mapping, data_dir: Path) -> dict[str, dict]:
    """``res1``, ``res2``, ...: the wave of amplitude ``amplitude`` at dx = f A for each f of
    ``dx_over_amplitude``, coarsest first, with the ship's numerics (:func:`ship_numerics`;
    the section's ``set`` overrides them)."""
    amp = sec["amplitude"]
    factors = sorted(sec["dx_over_amplitude"], reverse=True)
    runs = {}
    for i, f in enumerate(factors, start=1):
        over = {**ship_numerics(), **_common(sec)}
        over["numerics.dx"] = round(f * amp, 9)
        over["geometry.wavemaker.amplitude"] = amp
        over["geometry.wavemaker.theta0"] = None
        runs[f"res{i}"] = over
    return runs


def _sloshing_runs(sec: Mapping, data_dir: Path) -> dict[str, dict]:
    """``fillNN``: one run per fill ratio of ``fills`` (NN in percent)."""
    runs = {}
    for fill in sec["fills"]:
        over = _common(sec)
        over["geometry.fill"] = fill
        runs[f"fill{round(100 * fill):02d}"] = over
    return runs


def _decay_runs(sec: Mapping, data_dir: Path) -> dict[str, dict]:
    """``roll``: released with the initial ``heel``; ``heave``: roll locked, released with
    ``heave_offset``."""
    roll = _common(sec)
    roll.update({"geometry.heel": sec["heel"], "geometry.heave_offset": 0.0})
    heave = _common(sec)
    heave.update({"geometry.heel": 0.0, "geometry.dofs.roll": False,
                  "geometry.heave_offset": sec["heave_offset"]})
    return {"roll": roll, "heave": heave}


def _floating_box_runs(sec: Mapping, data_dir: Path) -> dict[str, dict]:
    """``box``: driven by the experiment's flap signal from ``data_dir``."""
    over = _common(sec)
    over["geometry.wavemaker.file"] = str(Path(data_dir) / "hadzic2005" /
                                          "CaseFloatingWavesVal_Flap.dat")
    over["geometry.wavemaker.file_sign"] = -1  # the file's angles count the other way
    return {"box": over}


def _dam_break_runs(sec: Mapping, data_dir: Path) -> dict[str, dict]:
    """``front``: the built-in column."""
    return {"front": _common(sec)}


def _cylinder_runs(sec: Mapping, data_dir: Path) -> dict[str, dict]:
    """``F0632``, ...: one run per Froude number of ``froude``, each in a tank sized for its
    wave (:func:`sph.cases.current.tank_for_froude`)."""
    from sph.cases.current import tank_for_froude

    runs = {}
    for fr in sec["froude"]:
        over = _common(sec)
        over["geometry.froude"] = fr
        over.update(tank_for_froude(fr, over["numerics.dx"]))
        runs[f"F{round(1000 * fr):04d}"] = over
    return runs


# metrics of a target in one signature: (datasets by run, steady window (s), data folder)
def _wave_tank_metric(sets, window, data_dir) -> list[dict]:
    return wave_tank(sets, window)


def _sloshing_metric(sets, window, data_dir) -> list[dict]:
    return sloshing(sets)


def _decay_metric(sets, window, data_dir) -> list[dict]:
    return decay(sets)


def _floating_box_metric(sets, window, data_dir) -> list[dict]:
    exp = hadzic_series(Path(data_dir) / "hadzic2005" /
                        "EXP_FloatingWavesVal_Hadzic_et_al_2005.txt")
    return floating_box(sets, exp)


def _dam_break_metric(sets, window, data_dir) -> list[dict]:
    return dam_break(sets)


def _cylinder_metric(sets, window, data_dir) -> list[dict]:
    return cylinder(sets)


@dataclass(frozen=True)
class Target:
    """One target of the validation ladder that the workflow runs.

    ``runs(section, data_dir)`` gives the case-file values (dotted keys) of each run of the
    target from the preset's section of the same name (``config/presets.yaml``, numbers
    parsed), all runs of the built-in ``case``; ``metric(datasets by run, window,
    data_dir)`` measures them as rows (see the module docstring); ``figures`` are the
    workflow's figures of the target, ``(file name, script in workflow/scripts/)``.
    ``tolerance`` is what the project's validation tests ask of this comparison
    (``docs/validation/``), at the resolution stated there: the workflow reports the errors
    at its preset and judges nothing."""

    id: str
    compares: str
    reference: str
    case: str
    runs: Callable[[Mapping, Path], dict[str, dict]]
    metric: Callable[[Mapping[str, Any], Sequence[float], str | Path], list[dict]]
    tolerance: str
    figures: tuple[tuple[str, str], ...]


#: the validation targets of the workflow, by id, in the order they are listed and run
TARGETS: dict[str, Target] = {t.id: t for t in (
    Target(
        id="wave_tank",
        compares="steady wave amplitude and period at WP1 and WP2 at three resolutions, "
                 "with the ship's numerics and absorbing zone; reflection of the absorbing "
                 "zone and incident amplitude at the flap",
        reference="linear flap theory (Cao et al. 2019, Sec. III B, Fig. 7)",
        case="wave_tank", runs=_wave_tank_runs, metric=_wave_tank_metric,
        tolerance="amplitude 10 % (5 % at dx = 0.2 A), period 1 %, reflection below 5 %",
        figures=(("fig07_wave_tank", "fig_wave_tank"),
                 ("fig_wave_profile", "fig_wave_profile"))),
    Target(
        id="sloshing",
        compares="first sloshing frequency of the U-shaped cabin at the fills of Table II",
        reference="Cao et al. (2019), Table II",
        case="sloshing_u", runs=_sloshing_runs, metric=_sloshing_metric,
        tolerance="5 % of Table II (dx = 0.2 m)",
        figures=(("fig_sloshing", "fig_sloshing"),)),
    Target(
        id="decay",
        compares="roll and heave natural frequencies (and damping) of the intact ship",
        reference="Cao et al. (2019), Table II",
        case="ship_decay", runs=_decay_runs, metric=_decay_metric,
        tolerance="roll 5 % of Table II; heave none (a 2-D section, docs/validation/"
                  "ship_decay.md)",
        figures=(("fig_decay", "fig_decay"),)),
    Target(
        id="floating_box",
        compares="wave probes, heave, roll and sway of the box in the experiment's wave "
                 "group: amplitude ratio, lag, correlation, RMS difference",
        reference="Hadzic et al. (2005), data/validation/hadzic2005",
        case="floating_box", runs=_floating_box_runs, metric=_floating_box_metric,
        tolerance="WP1 amplitude ratio 0.85-1.15, r > 0.93; heave 0.8-1.2, roll 0.7-1.3, "
                  "r > 0.8 (dx = 0.016 m)",
        figures=(("fig_floating_box", "fig_floating_box"),)),
    Target(
        id="dam_break",
        compares="surge-front lead over the experiment up to t = 0.6 s",
        reference="Koshizuka & Oka (1996), data/validation/koshizuka1996",
        case="dam_break", runs=_dam_break_runs, metric=_dam_break_metric,
        tolerance="front lead RMS 15 %, largest 16 % (dx = 0.025 m)",
        figures=(("fig_dam_break", "fig_dam_break"),)),
    Target(
        id="cylinder",
        compares="wave length and amplitude of the steady wave behind a submerged cylinder "
                 "in a current, over the Froude number",
        reference="Havelock (1926); Lamb (1932), Sec. 247",
        case="cylinder_in_current", runs=_cylinder_runs, metric=_cylinder_metric,
        tolerance="none yet: docs/validation/current_tank.md",
        figures=(("fig_cylinder_froude", "fig_cylinder_froude"),)),
)}
