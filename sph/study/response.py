r"""Response over wave frequency: the roll and heave response amplitude operators of a sweep.

A naval architect's first question about a ship in beam seas is how much it rolls and heaves
per unit wave over the wave frequency :math:`\omega`. For a sweep that runs the same ship in
regular waves of several frequencies (``omega`` column of the case table,
``config/sweeps/roll_rao.yaml``), per case

.. math:: \mathrm{RAO}_\phi = \frac{\phi_a}{k A}, \qquad
          \mathrm{RAO}_z = \frac{z_a}{A}, \qquad \omega^2 = g k \tanh k H,

where :math:`\phi_a` is the roll amplitude and :math:`k A` the wave slope amplitude, both in
the same angle unit (the usual roll RAO, degree per degree of wave slope), :math:`z_a` the
heave amplitude and :math:`A` the incident wave amplitude (the case table's ``amplitude``
times the draught; the wavemaker calibration brings the wave at the ship within 2 % of it,
:mod:`sph.study.calibration`). In waves much longer than the ship both tend to 1: the ship
follows the surface and its slope (Faltinsen 1990, Ch. 3); near the
roll natural frequency the roll RAO peaks at a height set by the roll damping.

The amplitudes are the findings' (:mod:`sph.study.findings`): half the 5-95 % range of the
oscillation about the one-period running mean (0.988 a for a sine of amplitude a; a ship
still sinking after the damage adds nothing), over the dynamic equilibrium from
``t2 = t2_periods T`` to the end of each run, each case with its own period T, or to where
its hull reached the absorbing zone, drifting (:func:`sph.study.findings.case_zone_entry`:
there the zone damps the ship's motion as well as the waves); a case whose hull got there
before ``t2 + T`` has no amplitudes (NaN, a gap in the figure's curve). They count
every harmonic; the table also gives the RAOs of the first harmonic alone (the linear
RAO): in the long, steep waves of a sweep at fixed slope the roll carries a second harmonic
near its natural frequency (2 omega = 1.2 rad/s at 0.6 rad/s).

The intact ship's roll natural frequency, marked on the figure, is the free roll decay's
(``ship_decay``, ``docs/validation/ship_decay.md``): 1.059 rad/s at dx = 0.8 and 0.4 m,
against the paper's 1.06 rad/s (Cao et al. 2019, Table II).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from sph.bodies.wavemaker import wavenumber
from sph.study.findings import (
    amplitude,
    case_zone_entry,
    fraction_text,
    harmonics,
    last_sample,
    oscillation,
    window,
)
from sph.study.sweeps import (
    DEFAULT_AMPLITUDE,
    DEFAULT_DEPTH,
    DEFAULT_DRAUGHT,
    DEFAULT_OMEGA,
    GRAVITY,
    OMEGA_COLUMN,
)

#: the intact ship's roll natural frequency (rad/s), measured by free roll decay
#: (docs/validation/ship_decay.md; the paper's Table II: 1.06 rad/s)
INTACT_ROLL_FREQUENCY = 1.059
#: the paper's wave slope k A: A = 2.0 m at omega = 1.0 rad/s in H = 30 m (k = 0.1024 1/m)
PAPER_STEEPNESS = wavenumber(DEFAULT_OMEGA, DEFAULT_DEPTH, GRAVITY) * DEFAULT_AMPLITUDE \
    * DEFAULT_DRAUGHT


def steepness_amplitude(omega: float, steepness: float = PAPER_STEEPNESS,
                        depth: float = DEFAULT_DEPTH, gravity: float = GRAVITY) -> float:
    """The wave amplitude A (m) of wave slope ``steepness`` = k A at frequency ``omega``
    (rad/s), k from the finite-depth dispersion relation."""
    return steepness / wavenumber(omega, depth, gravity)


def _case_value(ds, name: str, case: str, default: float) -> float:
    """A per-case variable of the sweep dataset, else its global attribute, else
    ``default``."""
    if name in ds.data_vars or name in ds.coords:
        return float(ds[name].sel(case=case))
    return float(ds.attrs.get(name, default))


def response_table(ds, t2_periods: float) -> list[dict]:
    """Roll and heave amplitudes and RAOs of every case in waves of a sweep dataset
    (:func:`sph.study.sweeps.gather`), in the order of its ``case`` dimension.

    Each row: ``case``, ``opening``, ``side``, ``fill``, ``omega`` (rad/s), ``period`` (s),
    ``amplitude`` (A, m), ``wavenumber`` (k, 1/m), ``steepness`` (k A), ``roll_amplitude``
    (degree), ``heave_amplitude`` (m), ``roll_rao`` (phi_a / (k A)), ``heave_rao``
    (z_a / A), and ``roll_rao_first``, ``heave_rao_first``: the same of the first harmonic
    alone (the sinusoid at omega fitted with a straight line after t2,
    :func:`sph.study.findings.harmonics`; the linear RAO, without the wave's and the ship's
    higher harmonics); ``zone_entry`` (t/T at which the hull reached the absorbing zone,
    ``inf`` where it never did) and ``read_to`` (t/T of the window's end: the run's end or
    the zone entry). Where the hull reached the zone before t2 + T the amplitudes and RAOs
    are NaN. Still-water cases (A = 0) are left out.
    """
    t = ds["time"].values
    draught = float(ds.attrs.get("draught", DEFAULT_DRAUGHT))
    depth = float(ds.attrs.get("depth", DEFAULT_DEPTH))
    rows = []
    for c in ds["case"].values:
        case = str(c)
        amp = float(ds["amplitude"].sel(case=case)) * draught
        if amp <= 0.0:
            continue
        omega = _case_value(ds, OMEGA_COLUMN, case, DEFAULT_OMEGA)
        period = _case_value(ds, "wave_period", case, 2.0 * math.pi / omega)
        k = wavenumber(omega, depth, GRAVITY)
        t2 = t2_periods * period
        series = {name: ds[name].sel(case=case).values for name in ("roll", "heave")}
        entry = case_zone_entry(ds, case)[0]
        end = min(entry, last_sample(t, series["roll"]))
        if end >= t2 + period:
            roll, heave = (amplitude(window(t, oscillation(t, y, period), t2, end))
                           for y in series.values())
            roll1, heave1 = (float(abs(harmonics(window(t, t, t2, end),
                                                 window(t, y, t2, end), [omega])[0]))
                             for y in series.values())
        else:
            roll = heave = roll1 = heave1 = math.nan
        rows.append(dict(
            case=case, opening=float(ds["opening"].sel(case=case)),
            side=str(ds["side"].sel(case=case).values), fill=float(ds["fill"].sel(case=case)),
            omega=omega, period=period, amplitude=amp, wavenumber=k, steepness=k * amp,
            roll_amplitude=roll, heave_amplitude=heave,
            roll_rao=math.radians(roll) / (k * amp), heave_rao=heave / amp,
            roll_rao_first=math.radians(roll1) / (k * amp), heave_rao_first=heave1 / amp,
            zone_entry=entry / period, read_to=end / period))
    return rows


def curve_label(row: Mapping) -> str:
    """The ship of a response curve: intact, or its opening (side) and fill."""
    if row["opening"] == 0:
        base = "intact"
    else:
        base = f"damaged, δ̄ = {fraction_text(row['opening'])} ({row['side']} side)"
    return base if row["fill"] == 0 else f"{base}, η = {100 * row['fill']:g} %"


def curves(rows: Sequence[Mapping]) -> dict[str, list[Mapping]]:
    """The rows of :func:`response_table` as response curves: one per ship (opening, side,
    fill; an intact ship's side does not count), sorted by omega, each with at least two
    frequencies; in the order the ships first appear."""
    out: dict[tuple, list[Mapping]] = {}
    for r in rows:
        key = (0.0, "", r["fill"]) if r["opening"] == 0 else (r["opening"], r["side"],
                                                               r["fill"])
        out.setdefault(key, []).append(r)
    return {curve_label(v[0]): sorted(v, key=lambda r: r["omega"]) for v in out.values()
            if len({round(r["omega"], 9) for r in v}) >= 2}


def varies_omega(cases: Sequence[Mapping]) -> bool:
    """Whether the checked case rows of a sweep run the ship at two or more wave
    frequencies (then the workflow draws the response figure)."""
    return len({round(float(c.get(OMEGA_COLUMN, DEFAULT_OMEGA)), 9) for c in cases
                if float(c.get("amplitude", DEFAULT_AMPLITUDE)) > 0.0}) >= 2


def write_csv(rows: Sequence[Mapping], path) -> None:
    """Write the rows of :func:`response_table` as CSV."""
    import csv

    fields = ["case", "opening", "side", "fill", "omega", "period", "amplitude", "wavenumber",
              "steepness", "roll_amplitude", "heave_amplitude", "roll_rao", "heave_rao",
              "roll_rao_first", "heave_rao_first", "zone_entry", "read_to"]
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=fields)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{r[k]:.6g}" if isinstance(r[k], float) else r[k])
                        for k in fields})

