"""The paper's qualitative findings (Cao et al. 2019, Sec. IV-V), measured on a sweep dataset.

Each finding is a statement of the paper that can be checked on this project's runs: a few
numbers are measured from the gathered dataset (:func:`sph.study.sweeps.gather`) and compared as
the statement says. A finding whose cases are not in the sweep, or whose time window is not
covered by the runs or by a case whose run stopped early (it blew up), is reported as not
determinable rather than guessed.

The findings are the table :data:`FINDINGS`: one :class:`FindingSpec` per finding (id,
statement, paper section, the group of cases it compares and what it needs of them, whether
it is measured after t2, a measure and a test), evaluated in order by
:func:`compute_findings`. A new finding is one more record.

Measures (``T`` the wave period, ``t1`` the damage time, ``t2`` the start of the dynamic
equilibrium, ``t2_periods * T``):

- *running mean*: the centred mean over one wave period (undefined within half a period
  of either end of the run);
- *amplitude* of a signal over a window: half the range between the 5th and 95th
  percentiles of its oscillation about the running mean (a sine of amplitude a gives
  0.988 a; single spikes do not count; a ship still sinking or a cabin still filling adds
  nothing);
- *first peak* of Q/V: the first local maximum after ``t1`` of its running mean whose
  prominence is at least 2 % of the largest (the maximum over ``[t1, t1 + 3 T]`` if there
  is none): the same event, the end of the first inrush, for every opening, not a crest
  of the water exchanged at the wave frequency;
- *against the level*: the cabin probes W1 and W2 read the surface in the ship's frame, at
  ``u`` across it (:func:`sph.cases.ship.cabin_probe_u`), as gauges on a model's cabin
  walls do, so a level surface reads ``u tan(roll)`` there; beside W1's amplitude (F11),
  the phase (F16) and the beat (F18) the page shows, not judged, the same measure of
  ``W - u tan(roll)``, the liquid's own motion;
- *mean heel*: the mean roll over the whole periods between ``t1`` and ``t2`` (the page
  shows the intact ship's beside it, not judged: the waves' own mean heel);
- *harmonics*: the amplitudes and phases of sinusoids at given frequencies (the wave
  frequency ω, 2ω, a cabin's sloshing frequency) fitted together by least squares, with a
  straight line, to the signal after ``t2``;
- *mean frequency*: the power-weighted mean frequency of the oscillation over a window,
  between ω/2 and 3ω (a Hann-windowed periodogram on a fine grid); the *mean period* is
  2π over it;
- *initial inflow rate*: the mean of dQ/dt over ``[t1, t1 + T/2]``;
- beside the roll amplitudes (F1, F6, F8) the page shows, not judged, the amplitude about a
  straight line fitted over the window: it keeps a roll slower than the wave, which the
  running mean mostly takes out (a damaged loaded ship's low mode, near 0.4 omega);
- *fluctuation* of Q: ``(max - min) / max`` over the window after t2 (below), as the paper
  reads it; the page shows beside it the range about Q's running mean over the largest Q,
  which leaves out a cabin still filling (not judged).

Every window after t2 ends where the runs end, or sooner where the ship drifts: free in
sway, it drifts with the waves, and once a side of its hull (upright, at the waterline) is
in the absorbing zone, the zone damps the flow about it and at its opening. A finding
reads its cases up to the first moment one of their hulls lies where the zone damps at
2 % of the wave frequency (:func:`zone_entry`; the clearances are
:func:`sph.study.sweeps.zone_clearance`), and is not determinable where that comes before
the end of its window (t2 + T for a finding after t2, t2 for one between t1 and t2).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from sph.engine.stepper import MACH_LIMIT
from sph.study.sweeps import DEFAULT_AMPLITUDE, DEFAULT_OMEGA, one_wave

#: a finding comparing amplitudes "near the minimum" allows this much above the minimum
NEAR_MINIMUM = 0.10
#: a phase difference "approximately" the paper's value: within a quarter of pi, half the
#: step between the values it gives (pi, pi/2, 0), so each measured phase names one of them
PHASE_TOLERANCE = math.pi / 4
#: the phase differences between the sloshing in the damaged cabin (W2) and in the cargo
#: cabins (W1) that the paper reads at each fill ratio (Sec. IV D, Fig. 22)
PAPER_PHASES = {0.25: math.pi, 0.5: math.pi / 2, 0.75: 0.0}
#: a sloshing wave "with higher harmonics, doubling the frequency": its 2ω amplitude at
#: least this fraction of its ω amplitude (a double crest shows in the record)
SECOND_HARMONIC = 0.10
#: a beat of the wave and the sloshing frequency "detected": the cabin's free sloshing
#: amplitude at least this fraction of the forced one (the envelope then swells and
#: shrinks by 2 r / (1 + r) = 40 % or more)
BEAT = 0.25
#: a mean period or frequency counts as longer or higher than another when it exceeds it
#: by this fraction (the measure reads two equal sines over three periods, one of them
#: with a sinking trend, equal to 1e-4)
DISTINCT_FREQUENCY = 0.01
#: the flood-volume fluctuation counts as "about 10 %" inside this band
FLUCTUATION_BAND = (0.05, 0.20)
#: "slightly larger" means a ratio inside this band
SLIGHTLY_LARGER = (1.0, 1.25)
#: the density taken for the paper's liquid cargo (kg/m3): its SPH model has one fluid, of
#: reference density 1000 kg/m3, and names no other (Sec. II, IV D)
PAPER_CARGO_DENSITY = 1000.0
#: "the same" heave equilibrium: mean heaves after t2 spread by at most this fraction of the
#: largest sinkage (the spread of the mean over a window of a few periods at coarse dx)
SAME_EQUILIBRIUM = 0.10


@dataclass(frozen=True)
class Finding:
    """One finding: what the paper says, what was measured, and whether it holds."""

    id: str
    statement: str
    paper: str
    measured: str
    holds: bool | None  # None: not determinable from this sweep
    #: the verdicts on the first and the second half of the window after t2
    #: (:func:`compute_findings`); None for a finding not read after t2 or not determinable
    halves: tuple[str, str] | None = None

    @property
    def verdict(self) -> str:
        return _VERDICT[self.holds]

    @property
    def halves_text(self) -> str:
        """``"holds / does not hold"``: the verdicts on the window's halves (empty where
        the finding is not read after t2)."""
        return " / ".join(self.halves) if self.halves else ""

    def as_dict(self) -> dict:
        first, second = self.halves or ("", "")
        return dict(id=self.id, statement=self.statement, paper=self.paper,
                    measured=self.measured, verdict=self.verdict, first_half=first,
                    second_half=second)


_VERDICT = {True: "holds", False: "does not hold", None: "not determinable"}


# ------------------------------------------------------------------------------ measures
def amplitude(y) -> float:
    """Half the 5th-95th percentile range of ``y`` (NaN ignored)."""
    y = np.asarray(y, dtype=float)
    y = y[np.isfinite(y)]
    if y.size < 3:
        return float("nan")
    lo, hi = np.percentile(y, [5.0, 95.0])
    return 0.5 * float(hi - lo)


def running_mean(t, y, period: float) -> np.ndarray:
    """The centred mean of ``y`` over one ``period`` (samples evenly spaced in ``t``); NaN
    where the period reaches past either end."""
    import pandas as pd

    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    if t.size < 2:
        return np.full(y.shape, np.nan)
    n = max(int(round(period / float(np.median(np.diff(t))))), 1)
    return pd.Series(y).rolling(n, center=True, min_periods=n).mean().to_numpy()


def detrended(t, y) -> np.ndarray:
    """``y`` less the straight line fitted to it by least squares (NaN samples left out
    of the fit and kept NaN)."""
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    ok = np.isfinite(y)
    if ok.sum() < 2:
        return np.full(y.shape, np.nan)
    return y - np.polyval(np.polyfit(t[ok], y[ok], 1), t)


def oscillation(t, y, period: float) -> np.ndarray:
    """``y`` about its one-period running mean (:func:`running_mean`)."""
    return np.asarray(y, dtype=float) - running_mean(t, y, period)


def harmonics(t, y, omegas: Sequence[float]) -> np.ndarray:
    """Complex amplitudes ``a e^{i phi}`` of the sinusoids ``a sin(w t + phi)`` at the
    angular frequencies ``omegas`` fitted together with a straight line to ``y`` by least
    squares (NaN samples left out); NaN when fewer samples than unknowns. Unlike a
    periodogram it parts frequencies closer than one over the window, and unlike the
    running mean the line takes a drift out without weighting the frequencies."""
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    ok = np.isfinite(y)
    t, y = t[ok], y[ok]
    if y.size < 2 * len(omegas) + 3:
        return np.full(len(omegas), np.nan + 0j)
    cols = [np.ones_like(t), t - t.mean()]
    for w in omegas:
        cols += [np.sin(w * t), np.cos(w * t)]
    coef = np.linalg.lstsq(np.column_stack(cols), y, rcond=None)[0]
    s, c = coef[2::2], coef[3::2]  # a sin(wt + phi) = a cos(phi) sin(wt) + a sin(phi) cos(wt)
    return s + 1j * c


def spectrum_peaks(t, y, omega: float, lo: float = 0.3, hi: float = 2.2, step: float = 0.01,
                   floor: float = 0.1) -> list[tuple[float, float]]:
    """Where an oscillation sits: the local maxima, as ``(frequency / omega, amplitude)``
    from the largest down, of the amplitude of one sinusoid (and a line) fitted by
    :func:`harmonics` at each frequency of a grid from ``lo`` to ``hi`` times ``omega``
    in steps of ``step``, keeping those above ``floor`` times the largest. A record of
    length L resolves frequencies about 2 pi / L apart (0.2 omega over five periods):
    closer components merge into one peak, a peak's amplitude carries the leakage of its
    neighbours, and a strong component's side lobes (about a fifth of it) are peaks too;
    fit the peaks found together with :func:`harmonics` to part them. The grid starts at
    0.3 omega: a damaged loaded ship rolls near 0.37 omega, and below 0.3 omega five
    periods hold under one and a half cycles."""
    if not 0.0 < lo < hi or step <= 0.0:
        raise ValueError(f"spectrum_peaks: need 0 < lo < hi and step > 0, got lo={lo}, "
                         f"hi={hi}, step={step}")
    grid = np.arange(lo, hi + 0.5 * step, step)
    amp = np.array([abs(harmonics(t, y, [f * omega])[0]) for f in grid])
    if not np.isfinite(amp).any():
        return []
    top = float(np.nanmax(amp))
    found = [(float(grid[i]), float(amp[i])) for i in range(1, grid.size - 1)
             if amp[i] > amp[i - 1] and amp[i] >= amp[i + 1] and amp[i] > floor * top]
    return sorted(found, key=lambda fa: -fa[1])


def mean_frequency(t, y, omega: float) -> float:
    """Power-weighted mean angular frequency of ``y`` (evenly sampled, NaN samples at the
    ends left out) between ``omega / 2`` and ``3 omega``, from a Hann-windowed periodogram
    zero-padded to a fine grid."""
    from scipy.signal import periodogram

    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    ok = np.isfinite(y)
    if ok.sum() < 8:
        return float("nan")
    t, y = t[ok], y[ok]
    dt = float(np.median(np.diff(t)))
    f, pw = periodogram(y - y.mean(), fs=1.0 / dt, window="hann",
                        nfft=max(4096, 16 * y.size))
    w = 2.0 * math.pi * f
    band = (w >= 0.5 * omega) & (w <= 3.0 * omega)
    if not np.any(pw[band] > 0.0):
        return float("nan")
    return float(np.sum(w[band] * pw[band]) / np.sum(pw[band]))


def window(t, y, start: float, end: float | None = None) -> np.ndarray:
    """Samples of ``y`` with ``start <= t <= end``."""
    t = np.asarray(t, dtype=float)
    sel = t >= start - 1e-9
    if end is not None:
        sel &= t <= end + 1e-9
    return np.asarray(y, dtype=float)[sel]


def zone_entry(t, sway, back: float, head: float = math.inf) -> tuple[float, float]:
    """Time and sway of the first sample at which the ship has swayed ``back`` towards +x
    or ``head`` towards -x: a side of its hull then reaches an absorbing zone (``inf``,
    NaN where it never does)."""
    sway = np.asarray(sway, dtype=float)
    with np.errstate(invalid="ignore"):
        hit = np.nonzero((sway >= back) | (-sway >= head))[0]
    if not len(hit):
        return math.inf, math.nan
    return float(np.asarray(t, dtype=float)[hit[0]]), float(sway[hit[0]])


def case_zone_entry(ds, case: str) -> tuple[float, float]:
    """:func:`zone_entry` of ``case`` in a sweep dataset (its ``sway`` against its
    ``zone_clearance_back`` and ``zone_clearance_head``; none where they are missing)."""
    if "sway" not in ds.data_vars:
        return math.inf, math.nan
    clear = [float(ds[n].sel(case=case).values) if n in ds else math.inf
             for n in ("zone_clearance_back", "zone_clearance_head")]
    return zone_entry(ds["time"].values, ds["sway"].sel(case=case).values, *clear)


def first_peak(t, q, t1: float, period: float) -> tuple[float, float]:
    """Time and value of the first peak of the running mean of ``q`` after ``t1`` (see
    the module docstring)."""
    from scipy.signal import find_peaks

    t = np.asarray(t, dtype=float)
    q = running_mean(t, q, period)
    sel = (t >= t1) & np.isfinite(q)
    ts, qs = t[sel], q[sel]
    if qs.size < 3:
        return float("nan"), float("nan")
    top = float(np.nanmax(qs))
    peaks, _ = find_peaks(qs, prominence=max(0.02 * top, 1e-12))
    if len(peaks):
        k = int(peaks[0])
    else:
        early = ts <= t1 + 3.0 * period
        k = int(np.nanargmax(np.where(early, qs, -np.inf)))
    return float(ts[k]), float(qs[k])


def inflow_rate(t, q, t1: float, period: float) -> float:
    """Mean dQ/dt over ``[t1, t1 + T/2]`` (units of ``q`` per s)."""
    t = np.asarray(t, dtype=float)
    q = np.asarray(q, dtype=float)
    t_end = t1 + 0.5 * period
    if t[-1] < t_end:
        return float("nan")
    return float((np.interp(t_end, t, q) - np.interp(t1, t, q)) / (t_end - t1))


def last_sample(t, y) -> float:
    """The time of the last finite sample of ``y`` (NaN if none): where a run that stopped
    early ends in a sweep dataset."""
    ran = np.nonzero(np.isfinite(y))[0]
    return float(t[ran[-1]]) if len(ran) else float("nan")


def fluctuation(y, about=None) -> float:
    """``(max - min) / max`` of ``y``; with ``about`` (its running mean, say) the range of
    ``y - about`` over the largest ``y``: the fluctuation without a creep (NaN ignored)."""
    y = np.asarray(y, dtype=float)
    d = y if about is None else y - np.asarray(about, dtype=float)
    ok = np.isfinite(d) & np.isfinite(y)
    if ok.sum() < 2 or np.max(y[ok]) <= 0.0:
        return float("nan")
    return float((np.max(d[ok]) - np.min(d[ok])) / np.max(y[ok]))


# ------------------------------------------------------------------------------ labels
def fraction_text(x: float, max_den: int = 21) -> str:
    """``10/21`` for 0.476..., ``5/7`` for 0.714..., else the decimal."""
    if abs(x) < 1e-12:
        return "0"
    for den in range(1, max_den + 1):
        num = round(x * den)
        if num and abs(num / den - x) < 1e-6:
            return f"{num}/{den}" if den > 1 else f"{num}"
    return f"{x:.3g}"


def case_label(case: Mapping) -> str:
    """A short label of a case in the paper's notation; the wave amplitude and frequency are
    named when they are not Table I's (A / d = 10/21, omega = 1 rad/s)."""
    if case["opening"] == 0:
        base = "intact"
    else:
        minus = "-" if case["side"] == "head" else ""
        base = f"δ̄{minus} = {fraction_text(case['opening'])}"
    label = f"{base}, η = {100 * case['fill']:g} %"
    density = case.get("cargo_density")
    if case["fill"] > 0.0 and density is not None and np.isfinite(density) \
            and abs(density - PAPER_CARGO_DENSITY) > 1e-9:
        label += f" ({density:g} kg/m³ cargo)"
    amp = float(case.get("amplitude", DEFAULT_AMPLITUDE))
    if amp == 0.0:
        label += ", still water"
    elif abs(amp - DEFAULT_AMPLITUDE) > 1e-9:
        label += f", Ā = {fraction_text(amp)}"
    omega = float(case.get("omega", DEFAULT_OMEGA))
    if amp > 0.0 and abs(omega - DEFAULT_OMEGA) > 1e-9:
        label += f", ω = {omega:g} rad/s"
    return label


# ------------------------------------------------------------------------------ findings
class _Sweep:
    """Access to the per-case series of a gathered dataset."""

    def __init__(self, ds, t2_periods: float):
        self.ds = ds
        self.t = ds["time"].values
        self.period = float(ds.attrs["wave_period"])
        self.t1 = float(ds.attrs["damage_time"])
        self.t2 = t2_periods * self.period
        self.t_end = float(self.t[-1])
        #: end of the windows after t2 (:func:`compute_findings` sets it per finding)
        self.stop = self.t_end
        self.cases = {str(c): dict(case=str(c), opening=float(o), side=str(s), fill=float(f),
                                   amplitude=float(a))
                      for c, o, s, f, a in zip(ds["case"].values, ds["opening"].values,
                                               ds["side"].values, ds["fill"].values,
                                               ds["amplitude"].values, strict=True)}
        if "cargo_density" in ds.coords:
            for c, rho in zip(ds["case"].values, ds["cargo_density"].values, strict=True):
                self.cases[str(c)]["cargo_density"] = float(rho)

    def series(self, case: str, name: str, probe: str | None = None) -> np.ndarray:
        """A variable of ``case`` (at ``probe``); ``probe_level``: a cabin probe's elevation
        against the level instead of the ship (:meth:`probe_lever`)."""
        if name == "probe_level":
            roll = np.radians(self.series(case, "roll"))
            return (self.series(case, "probe_elevation", probe)
                    - self.probe_lever(case) * np.tan(roll))
        v = self.ds[name].sel(case=case)
        if probe is not None:
            v = v.sel(probe=probe)
        return v.values

    def probe_lever(self, case: str) -> float:
        """Where the cabin probes of ``case`` sit across its ship
        (:func:`sph.cases.ship.cabin_probe_u`, from the run's configuration); NaN where the
        dataset does not say."""
        import yaml

        from sph.cases.ship import cabin_probe_u

        if "case_config" not in self.ds:
            return float("nan")
        try:
            g = yaml.safe_load(str(self.ds["case_config"].sel(case=case).values))["geometry"]
            return cabin_probe_u(g["hull"]["breadth"], g["hull"]["plating"],
                                 g["damage"]["side"])
        except (TypeError, KeyError, yaml.YAMLError):
            return float("nan")

    @property
    def omega(self) -> float:
        return 2.0 * math.pi / self.period

    def steady(self, case: str, name: str, probe: str | None = None) -> np.ndarray:
        """The samples over ``[t2, stop]``."""
        return window(self.t, self.series(case, name, probe), self.t2, self.stop)

    def steady_times(self) -> np.ndarray:
        return window(self.t, self.t, self.t2, self.stop)

    def oscillation(self, case: str, name: str, probe: str | None = None,
                    start: float | None = None, end: float | None = None):
        """Times and the oscillation about the running mean over ``[start, end]``
        (default: ``[t2, stop]``)."""
        y = oscillation(self.t, self.series(case, name, probe), self.period)
        if start is None:
            start, end = self.t2, self.stop
        return window(self.t, self.t, start, end), window(self.t, y, start, end)

    def label(self, case: str) -> str:
        return case_label(self.cases[case])

    def status(self, case: str) -> str:
        """How the run of ``case`` ended (``completed`` where the dataset does not say)."""
        if "case_status" not in self.ds.data_vars:
            return "completed"
        return str(self.ds["case_status"].sel(case=case).values)

    def end(self, case: str) -> float:
        """The time of the last sample of ``case``'s run."""
        return last_sample(self.t, self.series(case, "roll"))

    def zone_entry(self, case: str) -> tuple[float, float]:
        """Time and sway of ``case``'s first sample with a side of its hull in an absorbing
        zone (:func:`zone_entry`)."""
        return case_zone_entry(self.ds, case)

    @property
    def steady_covered(self) -> bool:
        """At least one wave period of dynamic equilibrium in the runs."""
        return self.t_end >= self.t2 + self.period


def _judged(fid: str, statement: str, paper: str, measured: str, holds: bool,
            values) -> Finding:
    """A measured finding; a measure that came out NaN (e.g. a window the runs do not
    cover) decides nothing."""
    finite = all(np.isfinite(v) for v in values)
    return Finding(fid, statement, paper, measured, bool(holds) if finite else None)


def _fmt(values: Mapping[str, float], sweep: _Sweep, unit: str = "", digits: int = 3) -> str:
    return "; ".join(f"{sweep.label(c)}: {v:.{digits}g}{unit}" for c, v in values.items())


def _increasing(values: Sequence[float]) -> bool:
    return all(b > a for a, b in zip(values, values[1:], strict=False))


def _decreasing(values: Sequence[float]) -> bool:
    return all(b < a for a, b in zip(values, values[1:], strict=False))


# ------------------------------------------------------------------------------ cases
class _Cases:
    """The cases of a sweep that the findings compare, from its groups
    (:func:`sph.study.sweeps.groups`), each list in the group's order."""

    def __init__(self, s: _Sweep, groups: Mapping[str, Sequence[str]]):
        self.par = par = s.cases
        self.opening = list(groups.get("opening", []))
        self.damaged = [c for c in self.opening if par[c]["opening"] > 0]
        self.intact = [c for c in self.opening if par[c]["opening"] == 0]
        side = list(groups.get("side", []))
        self.heads = [c for c in side if par[c]["side"] == "head" and par[c]["opening"] > 0]
        self.backs = [c for c in side if par[c]["side"] == "back" and par[c]["opening"] > 0]
        self.fill = list(groups.get("fill", []))
        self.half = [c for c in self.fill if abs(par[c]["fill"] - 0.5) < 1e-6]
        self.filled = [c for c in self.fill if par[c]["fill"] > 0]
        self.amps = [c for c in groups.get("amplitude", []) if par[c]["opening"] > 0]
        self.still = [c for c in self.amps if par[c]["amplitude"] == 0.0]
        self.waves = [c for c in self.amps if par[c]["amplitude"] > 0.0]

    # selections: the cases a finding measures, or [] when the sweep lacks them
    def intact_and_damaged(self) -> list[str]:
        """The intact case first, then every damaged one."""
        return self.intact[:1] + self.damaged if self.intact and self.damaged else []

    def openings(self) -> list[str]:
        """Two or more damaged cases (opening sizes)."""
        return self.damaged if len(self.damaged) >= 2 else []

    def any_damaged(self) -> list[str]:
        return self.damaged

    def back_and_head(self) -> list[str]:
        """The back-side case, then the head-side one."""
        return self.backs[:1] + self.heads[:1] if self.heads and self.backs else []

    def sides_or_damaged(self) -> list[str]:
        """The back- and head-side cases that exist, else the first damaged case."""
        return self.backs[:1] + self.heads[:1] if (self.heads or self.backs) else self.damaged[:1]

    def fills_with_half(self) -> list[str]:
        return self.fill if len(self.fill) >= 3 and self.half else []

    def fills(self) -> list[str]:
        return self.fill if len(self.fill) >= 2 else []

    def cargo_fills(self) -> list[str]:
        return self.filled if len(self.filled) >= 2 else []

    def _at_fills(self, fills) -> list[str]:
        return [c for c in self.filled
                if any(abs(self.par[c]["fill"] - f) < 1e-6 for f in fills)]

    def phase_fills(self) -> list[str]:
        """The cases at two or more of the fill ratios whose phase the paper gives."""
        cases = self._at_fills(PAPER_PHASES)
        return cases if len(cases) >= 2 else []

    def low_fills(self) -> list[str]:
        """The cases at 25 and 50 % fill."""
        return self._at_fills((0.25, 0.5))

    def high_fill(self) -> list[str]:
        """The case at 75 % fill."""
        return self._at_fills((0.75,))

    def still_and_waves(self) -> list[str]:
        """The still-water case first, then every wave case."""
        return self.still[:1] + self.waves if self.still and self.waves else []

    def amplitudes(self) -> list[str]:
        return self.amps if len(self.amps) >= 2 else []


# ------------------------------------------------------------------------------ measures
# per case: sweep, case -> number
def _roll_amplitude(s: _Sweep, c: str) -> float:
    return amplitude(s.oscillation(c, "roll")[1])


def _roll_amplitude_line(s: _Sweep, c: str) -> float:
    """The roll's amplitude about a straight line fitted over the window after t2: a roll
    slower than the wave (a mode below omega / 2) kept, which the running mean takes out."""
    return amplitude(detrended(s.steady_times(), s.steady(c, "roll")))


def _heave_amplitude(s: _Sweep, c: str) -> float:
    return amplitude(s.oscillation(c, "heave")[1])


def _heave_mean(s: _Sweep, c: str) -> float:
    return float(np.nanmean(s.steady(c, "heave")))


def _w1_amplitude(s: _Sweep, c: str, name: str = "probe_elevation") -> float:
    return amplitude(s.oscillation(c, name, "W1")[1])


def _w1_amplitude_level(s: _Sweep, c: str) -> float:
    return _w1_amplitude(s, c, "probe_level")


def _w2_amplitude(s: _Sweep, c: str) -> float:
    return amplitude(s.oscillation(c, "probe_elevation", "W2")[1])


def _inflow(s: _Sweep, c: str) -> float:
    return inflow_rate(s.t, s.series(c, "flood_volume"), s.t1, s.period)


def _fluctuation(s: _Sweep, c: str) -> float:
    return fluctuation(s.steady(c, "flood_volume"))


def _fluctuation_about_mean(s: _Sweep, c: str) -> float:
    q = s.series(c, "flood_volume")
    return fluctuation(s.steady(c, "flood_volume"),
                       about=window(s.t, running_mean(s.t, q, s.period), s.t2, s.stop))


def _mean_heel(s: _Sweep, c: str) -> float:
    """Mean roll over the whole periods between t1 and t2."""
    k = math.floor((s.t2 - s.t1) / s.period + 1e-9)
    if k < 1 or s.t_end < s.t1 + k * s.period:
        return float("nan")
    return float(np.nanmean(window(s.t, s.series(c, "roll"), s.t1, s.t1 + k * s.period)))


def _sloshing_phase(s: _Sweep, c: str, name: str = "probe_elevation") -> float:
    """Phase difference (0 to pi) at the wave frequency between W2 and W1 after t2."""
    t = s.steady_times()
    a1 = harmonics(t, s.steady(c, name, "W1"), [s.omega])[0]
    a2 = harmonics(t, s.steady(c, name, "W2"), [s.omega])[0]
    if not (np.isfinite(a1) and np.isfinite(a2)) or a1 == 0 or a2 == 0:
        return float("nan")
    return float(abs(np.angle(a2 / a1)))


def _sloshing_phase_level(s: _Sweep, c: str) -> float:
    return _sloshing_phase(s, c, "probe_level")


def _second_harmonic(s: _Sweep, c: str) -> float:
    """W2's amplitude at 2ω over its amplitude at ω, after t2."""
    a = np.abs(harmonics(s.steady_times(), s.steady(c, "probe_elevation", "W2"),
                         [s.omega, 2.0 * s.omega]))
    return float(a[1] / a[0]) if a[0] > 0 else float("nan")


def _beat(s: _Sweep, c: str, name: str = "probe_elevation") -> float:
    """W1's amplitude at the cabin's first sloshing frequency (Table II) over its amplitude
    at ω, after t2."""
    from sph.study.validation import TABLE_II_SLOSHING

    fill = min(TABLE_II_SLOSHING, key=lambda f: abs(f - s.cases[c]["fill"]))
    a = np.abs(harmonics(s.steady_times(), s.steady(c, name, "W1"),
                         [s.omega, TABLE_II_SLOSHING[fill] * s.omega]))
    return float(a[1] / a[0]) if a[0] > 0 else float("nan")


def _beat_level(s: _Sweep, c: str) -> float:
    return _beat(s, c, "probe_level")


def _roll_frequency(s: _Sweep, c: str) -> float:
    """Mean frequency of the roll after t2, in units of ω."""
    return mean_frequency(*s.oscillation(c, "roll"), s.omega) / s.omega


def _heave_period(s: _Sweep, c: str) -> float:
    """Mean period of the heave between t1 and t2, in units of T."""
    if s.t_end < s.t2:
        return float("nan")
    return s.omega / mean_frequency(*s.oscillation(c, "heave", start=s.t1, end=s.t2),
                                    s.omega)


#: a measure: (sweep, cases) -> (values by case, the "measured" text)
Measure = Callable[[_Sweep, Sequence[str]], tuple[dict[str, float], str]]


def _each(per_case: Callable[[_Sweep, str], float], quantity: str, percent: bool = False,
          suffix: Callable[[dict[str, float]], str] | None = None) -> Measure:
    """Measure ``per_case`` on every case: ``quantity: label: value; ...`` (values in percent
    with ``percent``), then ``suffix(values)``."""

    def measure(s: _Sweep, cases: Sequence[str]):
        values = {c: per_case(s, c) for c in cases}
        shown = _fmt({c: 100 * v for c, v in values.items()}, s, " %") if percent \
            else _fmt(values, s)
        return values, f"{quantity}: {shown}" + (suffix(values) if suffix else "")

    return measure


def _beside(measure: Measure, per_case: Callable[[_Sweep, str], float], what: str,
            percent: bool = False) -> Measure:
    """``measure``, then ``per_case`` of each case shown beside it as ``what``, not judged:
    the same quantity read another way, where the two ways differ in a run."""

    def wrapped(s: _Sweep, cases: Sequence[str]):
        values, text = measure(s, cases)
        other = {c: (100 if percent else 1) * per_case(s, c) for c in cases}
        if not any(math.isfinite(v) for v in other.values()):
            return values, text
        return values, f"{text}; {what}, not judged: {_fmt(other, s, ' %' if percent else '')}"

    return wrapped


def _creep_apart(measure: Measure) -> Measure:
    """A fluctuation ``measure``, and beside it each case's fluctuation about Q's
    one-period running mean: what a cabin still filling within the window adds (the paper
    reads the plain range)."""
    return _beside(measure, _fluctuation_about_mean,
                   "about Q's one-period running mean (its creep left out)", percent=True)


def _with_intact_heel(measure: Measure) -> Measure:
    """A mean-heel ``measure``, and beside it the mean heel of the sweep's intact ship in
    the same wave over the same periods, where it has one: the waves' own mean heeling
    moment, which a damaged ship's heel carries too (not judged)."""

    def wrapped(s: _Sweep, cases: Sequence[str]):
        values, text = measure(s, cases)
        amp = {s.cases[c].get("amplitude") for c in cases}
        intact = [c for c, p in s.cases.items() if p["opening"] == 0
                  and p.get("amplitude") in amp]
        heel = _mean_heel(s, intact[0]) if intact else float("nan")
        if math.isfinite(heel):
            text += (f"; the intact ship's over the same periods, the waves' own mean heel, "
                     f"not judged: {heel:.3g}")
        return values, text

    return wrapped


#: how the page names a cabin probe's reading against the level
AGAINST_LEVEL = "against the level (W - u tan(roll), the probe's heel taken out)"


def _slow_roll_kept(measure: Measure) -> Measure:
    """A roll-amplitude ``measure`` (about the running mean), and beside it the amplitude
    about a straight line, which keeps a roll slower than the wave: a damaged loaded ship's
    low mode (below omega / 2) is mostly taken out by the one-period running mean."""
    return _beside(measure, _roll_amplitude_line,
                   "about a straight line (a roll slower than the wave kept)")


def _first_peaks(s: _Sweep, cases: Sequence[str]):
    peaks = {c: first_peak(s.t, s.series(c, "flood_ratio"), s.t1, s.period) for c in cases}
    text = "; ".join(f"{s.label(c)}: {v:.3g} at t/T = {tp / s.period:.2f}"
                     for c, (tp, v) in peaks.items())
    return ({c: v for c, (_, v) in peaks.items()},
            "first peak of the one-period mean of Q/V: " + text)


def _head_over_back(values: Mapping[str, float]) -> float:
    back, head = values.values()
    return head / back if back > 0 else math.inf


def _heave_ratio_note(values: dict[str, float]) -> str:
    lo, hi = SLIGHTLY_LARGER
    return (f"; head / back = {_head_over_back(values):.3f} (slightly larger: "
            f"{lo:g}-{hi:g})")


def _spread(values: Mapping[str, float]) -> tuple[float, float]:
    """Largest sinkage and spread of the mean heaves."""
    return (max(abs(v) for v in values.values()),
            max(values.values()) - min(values.values()))


def _spread_note(values: dict[str, float]) -> str:
    sink, spread = _spread(values)
    return (f"; spread {spread:.3g} m = {100 * spread / sink:.3g} % of the largest sinkage "
            f"(the same: at most {100 * SAME_EQUILIBRIUM:g} %)")


# ------------------------------------------------------------------------------ tests
# (values by case in the selection's order, sweep) -> whether the statement holds
def _first_largest(values, s) -> bool:
    """Every case after the first below the first."""
    first, *rest = values
    return all(values[c] < values[first] for c in rest)


def _all_increasing(values, s) -> bool:
    return _increasing(list(values.values()))


def _all_decreasing(values, s) -> bool:
    return _decreasing(list(values.values()))


def _head_larger(values, s) -> bool:
    back, head = values.values()
    return head > back


def _back_larger(values, s) -> bool:
    back, head = values.values()
    return back > head


def _away_from_opening(values, s) -> bool:
    # roll > 0 heels towards +x; a back opening faces +x, a head opening -x
    ok = True
    for c, v in values.items():
        away = -1.0 if s.cases[c]["side"] == "back" else 1.0
        ok &= v * away > 0
    return ok


def _first_shortest(values, s) -> bool:
    """Every case after the first longer than the first (:data:`DISTINCT_FREQUENCY`)."""
    first, *rest = values
    return all(values[c] > (1.0 + DISTINCT_FREQUENCY) * values[first] for c in rest)


def _back_higher(values, s) -> bool:
    back, head = values.values()
    return back > (1.0 + DISTINCT_FREQUENCY) * head


def _phases_as_paper(values, s) -> bool:
    return all(abs(v - PAPER_PHASES[min(PAPER_PHASES, key=lambda f: abs(
        f - s.cases[c]["fill"]))]) <= PHASE_TOLERANCE for c, v in values.items())


def _with_second_harmonic(values, s) -> bool:
    return all(v >= SECOND_HARMONIC for v in values.values())


def _beats(values, s) -> bool:
    return all(v >= BEAT for v in values.values())


def _half_near_minimum(values, s) -> bool:
    half = next(c for c in values if abs(s.cases[c]["fill"] - 0.5) < 1e-6)
    return values[half] <= (1.0 + NEAR_MINIMUM) * min(values.values())


def _about_ten_percent(values, s) -> bool:
    lo, hi = FLUCTUATION_BAND
    return all(lo <= v <= hi for v in values.values())


def _slightly_larger(values, s) -> bool:
    lo, hi = SLIGHTLY_LARGER
    return lo <= _head_over_back(values) <= hi


def _same_equilibrium(values, s) -> bool:
    sink, spread = _spread(values)
    return spread <= SAME_EQUILIBRIUM * sink


# ------------------------------------------------------------------------------ the table
@dataclass(frozen=True)
class FindingSpec:
    """One finding of the paper and how this project measures it.

    ``cases`` picks the cases to measure from the sweep's groups (the group named by
    ``group``); an empty pick means the sweep lacks them (``needs`` says what is missing).
    A finding measured after t2 (``steady``) needs runs to at least t2 + T. ``measure``
    returns the values by case and the "measured" text; ``test`` says whether the statement
    holds on those values (NaN values decide nothing)."""

    id: str
    statement: str
    paper: str
    group: str
    needs: str
    cases: Callable[[_Cases], list[str]]
    steady: bool
    measure: Measure
    test: Callable[[dict[str, float], _Sweep], bool]


_BOTH_SIDES = "the reference opening on both sides"
_INTACT_DAMAGED = "an intact case and a damaged case at the reference fill"
_AMPLITUDES = "the reference opening at two or more wave amplitudes"

#: the paper's findings (Sec. IV-V), in the order of the report
FINDINGS: tuple[FindingSpec, ...] = (
    FindingSpec(
        "F1", "The roll amplitude of the damaged ship after t2 is smaller than the intact "
        "ship's", "Sec. IV B, Fig. 15; Sec. V", "opening", _INTACT_DAMAGED,
        _Cases.intact_and_damaged, True,
        _slow_roll_kept(_each(_roll_amplitude, "roll amplitude after t2 (deg)")),
        _first_largest),
    FindingSpec(
        "F2", "The first peak of Q/V grows with the opening size", "Sec. IV B, Fig. 13",
        "opening", "two or more opening sizes", _Cases.openings, False, _first_peaks,
        _all_increasing),
    FindingSpec(
        "F3", "After damage the ship heaves about a lower equilibrium than the intact ship",
        "Sec. IV B, Fig. 14; Sec. V", "opening", _INTACT_DAMAGED, _Cases.intact_and_damaged,
        True, _each(_heave_mean, "mean heave after t2 (m)"), _first_largest),
    FindingSpec(
        "F4", "The sloshing wave in the damaged cabin (W2) after t2 is lower for larger "
        "openings", "Sec. IV B, Figs. 11-12", "opening", "two or more opening sizes",
        _Cases.openings, True, _each(_w2_amplitude, "W2 amplitude after t2 (m)"),
        _all_decreasing),
    FindingSpec(
        "F5", "The initial inflow is faster with the opening facing the waves (head) than "
        "away from them (back)", "Sec. IV C, Figs. 16-17; Sec. V", "side", _BOTH_SIDES,
        _Cases.back_and_head, False,
        _each(_inflow, "mean inflow rate over [t1, t1 + T/2] (m2/s)"), _head_larger),
    FindingSpec(
        "F6", "At dynamic equilibrium the ship rolls more with the opening on the back side "
        "than facing the waves", "Sec. IV C, Fig. 18; Sec. V", "side", _BOTH_SIDES,
        _Cases.back_and_head, True,
        _slow_roll_kept(_each(_roll_amplitude, "roll amplitude after t2 (deg)")),
        _back_larger),
    FindingSpec(
        "F7", "The largest roll angle after damage is towards the side opposite the opening",
        "Sec. IV C; Sec. V", "side (else opening)", "a damaged case",
        _Cases.sides_or_damaged, False,
        _with_intact_heel(_each(_mean_heel, "mean heel over the whole periods between t1 and "
                                "t2 (deg, + towards the waves' travel)")),
        _away_from_opening),
    FindingSpec(
        "F8", "The roll after t2 is near its minimum at the fill ratio η = 50 %",
        "Sec. IV D, Fig. 21; Sec. V", "fill", "η = 50 % and at least two other fill ratios",
        _Cases.fills_with_half, True,
        _slow_roll_kept(_each(_roll_amplitude, "roll amplitude after t2 (deg)", suffix=lambda v:
                              f" (near: within {100 * NEAR_MINIMUM:g} % of the smallest)")),
        _half_near_minimum),
    FindingSpec(
        "F9", "After t2 the flood volume fluctuates by about 10 % of its maximum",
        "Sec. IV B, Fig. 13", "opening", "a damaged case at the reference fill",
        _Cases.any_damaged, True,
        _creep_apart(_each(_fluctuation, "(max - min) / max of Q after t2", percent=True,
                           suffix=lambda v: (f" (about 10 %: {100 * FLUCTUATION_BAND[0]:g}-"
                                             f"{100 * FLUCTUATION_BAND[1]:g} %)"))),
        _about_ten_percent),
    FindingSpec(
        "F10", "The flood-volume fluctuation decreases as the cargo fill ratio grows",
        "Sec. IV D, Fig. 23", "fill", "two or more fill ratios", _Cases.fills, True,
        _creep_apart(_each(_fluctuation, "(max - min) / max of Q after t2", percent=True)),
        _all_decreasing),
    FindingSpec(
        "F11", "The sloshing wave in the liquid cabins (W1) is lower for larger fill ratios",
        "Sec. IV D, Fig. 22", "fill", "two or more non-zero fill ratios", _Cases.cargo_fills,
        True, _beside(_each(_w1_amplitude, "W1 amplitude after t2 (m)"), _w1_amplitude_level,
                      AGAINST_LEVEL), _all_decreasing),
    FindingSpec(
        "F12", "The wave direction changes the heave only slightly; the head-wave case "
        "heaves slightly more", "Sec. IV C, Fig. 19", "side", _BOTH_SIDES,
        _Cases.back_and_head, True,
        _each(_heave_amplitude, "heave amplitude after t2 (m)", suffix=_heave_ratio_note),
        _slightly_larger),
    # Fig. 10: the reference opening in still water and in waves of several amplitudes
    FindingSpec(
        "F13", "The initial inflow is slower in waves than in still water (the wave's and "
        "the flooding water's heeling moments oppose each other)", "Sec. IV B, Fig. 10(c)",
        "amplitude", "the reference opening in still water and in waves",
        _Cases.still_and_waves, False,
        _each(_inflow, "mean inflow rate over [t1, t1 + T/2] (m2/s)"), _first_largest),
    FindingSpec(
        "F14", "Whatever the wave amplitude, the damaged ship heaves about the same new "
        "equilibrium", "Sec. IV B, Fig. 10(b)", "amplitude", _AMPLITUDES, _Cases.amplitudes,
        True, _each(_heave_mean, "mean heave after t2 (m)", suffix=_spread_note),
        _same_equilibrium),
    FindingSpec(
        "F15", "The heave amplitude after t2 is set mainly by the wave amplitude: it grows "
        "with it", "Sec. IV B, Fig. 10(b)", "amplitude", _AMPLITUDES, _Cases.amplitudes,
        True, _each(_heave_amplitude, "heave amplitude after t2 (m)"), _all_increasing),
    FindingSpec(
        "F16", "The sloshing in the damaged cabin (W2) and in the cargo cabins (W1) differ "
        "in phase by about π at η = 25 %, π/2 at 50 % and 0 at 75 %", "Sec. IV D, Fig. 22",
        "fill", "two or more of the fill ratios 25, 50 and 75 %", _Cases.phase_fills, True,
        _beside(_each(_sloshing_phase, "phase of W2 against W1 at ω after t2 (rad)",
                      suffix=lambda v: f" (about: within π/4 = {PHASE_TOLERANCE:.3g} rad)"),
                _sloshing_phase_level, AGAINST_LEVEL),
        _phases_as_paper),
    FindingSpec(
        "F17", "At η = 25 % and 50 % the sloshing of the flood water carries the second "
        "harmonic 2ω", "Sec. IV D, Fig. 22", "fill", "the fill ratio 25 % or 50 %",
        _Cases.low_fills, True,
        _each(_second_harmonic, "W2 amplitude at 2ω over that at ω after t2",
              suffix=lambda v: f" (carries it: {SECOND_HARMONIC:g} or more)"),
        _with_second_harmonic),
    FindingSpec(
        "F18", "At η = 75 % the cargo sloshing beats at the difference of the wave and the "
        "cabin's sloshing frequencies", "Sec. IV D, Fig. 22; Table II", "fill",
        "the fill ratio 75 %", _Cases.high_fill, True,
        _beside(_each(_beat, "W1 amplitude at the sloshing frequency (Table II) over that at "
                      "ω after t2", suffix=lambda v: f" (beats: {BEAT:g} or more)"),
                _beat_level, AGAINST_LEVEL),
        _beats),
    FindingSpec(
        "F19", "At dynamic equilibrium the ship rolls at a higher frequency with the opening "
        "on the back side than facing the waves", "Sec. IV C, Fig. 18; Sec. V", "side",
        _BOTH_SIDES, _Cases.back_and_head, True,
        _each(_roll_frequency, "mean roll frequency after t2 (ω)",
              suffix=lambda v: f" (higher: by {100 * DISTINCT_FREQUENCY:g} % or more)"),
        _back_higher),
    FindingSpec(
        "F20", "Between t1 and t2 the damaged ship heaves with a longer period than the "
        "intact ship", "Sec. IV B, Fig. 14", "opening", _INTACT_DAMAGED,
        _Cases.intact_and_damaged, False,
        _each(_heave_period, "mean heave period between t1 and t2 (T)",
              suffix=lambda v: f" (longer: by {100 * DISTINCT_FREQUENCY:g} % or more)"),
        _first_shortest),
)


#: a ship whose roll passes this many degrees has capsized: the findings that compare it
#: with other cases cannot be judged
CAPSIZE_DEGREES = 90.0


def capsize_note(s: _Sweep, case: str) -> str:
    """Empty, or why ``case``'s findings cannot be judged: its roll passed
    :data:`CAPSIZE_DEGREES` (the time it first did, in wave periods, and its largest roll)."""
    roll = s.series(case, "roll")
    over = np.nonzero(np.abs(roll) >= CAPSIZE_DEGREES)[0]
    if not len(over):
        return ""
    label = case_label(s.cases[case])
    return (f"{case} ({label}) capsized: its roll passed "
            f"{CAPSIZE_DEGREES:g} degree at t/T = {s.t[over[0]] / s.period:.3g} "
            f"(largest {np.nanmax(np.abs(roll)):.0f} degree)")


def stop_note(s: _Sweep, case: str) -> str:
    """Empty, or why ``case``'s run ended before the others: the time of its last sample,
    in wave periods, and the engine's status (a blow-up names its step, time and cause)."""
    status = s.status(case)
    if status == "completed":
        return ""
    return (f"{case} ({case_label(s.cases[case])}) stopped at t/T = "
            f"{s.end(case) / s.period:.3g}: {status}")


def _stopped_too_soon(s: _Sweep, case: str, spec: FindingSpec) -> bool:
    """Whether ``case`` stopped before the end of the window that ``spec`` measures:
    ``s.stop`` for a finding after t2, t2 for one between t1 and t2 (the first peak, the
    inflow rate, the mean heel, the heave period)."""
    if s.status(case) == "completed":
        return False
    need = s.stop if spec.steady else s.t2
    return not s.end(case) >= need - 1e-9 * max(1.0, need)


def zone_note(s: _Sweep, case: str) -> str:
    """Where ``case``'s hull reached an absorbing zone, in wave periods and metres."""
    t, sway = s.zone_entry(case)
    return (f"{case} ({case_label(s.cases[case])}): its hull reached the absorbing zone at "
            f"t/T = {t / s.period:.3g} (sway {sway:+.3g} m)")


def compute_findings(ds, groups: Mapping[str, Sequence[str]], t2_periods: float,
                     halves: bool = True) -> list[Finding]:
    """Measure every finding of :data:`FINDINGS` on the gathered dataset ``ds``.

    Parameters
    ----------
    ds : xarray.Dataset
        Sweep dataset with ``case``, ``opening``, ``side``, ``fill``, ``amplitude``
        coordinates; ``roll``, ``heave``, ``flood_volume``, ``flood_ratio`` and
        ``probe_elevation`` series; global attributes ``wave_period`` and ``damage_time``.
    groups : mapping
        The paper's comparisons (:func:`sph.study.sweeps.groups`).
    t2_periods : float
        Start of the dynamic equilibrium in wave periods.

    The groups' cases are at one wave frequency (:func:`sph.study.sweeps.groups`); in a
    sweep over wave frequency the findings are measured on them alone
    (:func:`sph.study.sweeps.one_wave`). A finding is not determinable, with the reason,
    where it needs a window the runs do not cover, a case whose hull reached an absorbing
    zone before the window's end (:func:`zone_note`; the windows after t2 otherwise end
    where the first of its cases' hulls reaches one), a case that capsized
    (:func:`capsize_note`) or a case whose run stopped before the end of the window
    (``case_status``, :func:`stop_note`: a run that blew up).

    ``halves``: each finding read after t2 is also judged on each half of its window, from
    t2 to the middle between t2 and the runs' end and from there on (``Finding.halves``,
    :func:`half_verdicts`). A verdict that differs between the halves is decided by where
    the window ends more than by the ship's equilibrium: the oscillations have not settled,
    or the measure's margin is within their scatter.
    """
    found = _compute(ds, groups, t2_periods)
    if not halves:
        return found
    split = half_verdicts(ds, groups, t2_periods)
    return [f if f.holds is None else replace(f, halves=split.get(f.id)) for f in found]


def finding_cases(groups: Mapping[str, Sequence[str]]) -> list[str]:
    """Every case that some group of ``groups`` names, sorted, each once."""
    return sorted({c for g in groups.values() for c in g})


def half_verdicts(ds, groups: Mapping[str, Sequence[str]], t2_periods: float
                  ) -> dict[str, tuple[str, str]]:
    """The verdict of each finding read after t2 on the first and on the second half of the
    window after t2: the runs cut at the middle ``tm`` between t2 and their end, and t2 moved
    to ``tm`` (a finding's window also ends where a hull reaches an absorbing zone, so a
    half may be not determinable where the whole window is not). By finding id; findings
    not read after t2 are left out."""
    # the findings' cases at their one wave (a sweep over wave frequency has several)
    ds = one_wave(ds, finding_cases(groups))
    period = float(ds.attrs["wave_period"])
    end = float(ds["time"].values[-1]) / period
    mid = t2_periods + 0.5 * (end - t2_periods)
    first = _compute(ds.sel(time=slice(None, mid * period * (1 + 1e-12))), groups,
                     t2_periods)
    second = _compute(ds, groups, mid)
    steady = {f.id for f in FINDINGS if f.steady}
    return {a.id: (a.verdict, b.verdict) for a, b in zip(first, second, strict=True)
            if a.id in steady}


def _compute(ds, groups: Mapping[str, Sequence[str]], t2_periods: float) -> list[Finding]:
    """:func:`compute_findings` on one window."""
    s = _Sweep(one_wave(ds, finding_cases(groups)), t2_periods)
    sel = _Cases(s, groups)
    steady_note = (f"needs runs to at least t2 + T = {(t2_periods + 1):g} T "
                   f"(runs end at {s.t_end / s.period:.3g} T)")
    capsized = {c: note for c in s.cases if (note := capsize_note(s, c))}
    entry = {c: s.zone_entry(c)[0] for c in s.cases}
    out = []
    for f in FINDINGS:
        cases = f.cases(sel)
        # the windows after t2 end where the first of these hulls reaches a zone
        first = min(cases, key=entry.get) if cases else None
        s.stop = min(s.t_end, entry[first]) if cases else s.t_end
        need = s.t2 + s.period if f.steady else s.t2
        if not cases:
            out.append(Finding(f.id, f.statement, f.paper, f"not in this sweep: {f.needs}",
                               None))
        elif f.steady and not s.steady_covered:
            out.append(Finding(f.id, f.statement, f.paper, steady_note, None))
        elif any(c in capsized for c in cases):
            out.append(Finding(f.id, f.statement, f.paper, "; ".join(
                capsized[c] for c in cases if c in capsized), None))
        elif late := [c for c in cases if entry[c] < need - 1e-9 * need]:
            out.append(Finding(f.id, f.statement, f.paper, "; ".join(
                zone_note(s, c) for c in late) + f", before t/T = {need / s.period:.3g}",
                None))
        elif short := [c for c in cases if _stopped_too_soon(s, c, f)]:
            out.append(Finding(f.id, f.statement, f.paper, "; ".join(
                stop_note(s, c) for c in short), None))
        else:
            values, measured = f.measure(s, cases)
            if f.steady and s.stop < s.t_end:
                measured += (f" (read to t/T = {s.stop / s.period:.3g}, where the hull of "
                             f"{first} reached the absorbing zone)")
            out.append(_judged(f.id, f.statement, f.paper, measured, f.test(values, s),
                               values.values()))
    return out


def departures(ds) -> list[str]:
    """The runs of a sweep dataset that differ from the paper in a value it does not state:
    a cargo other than water (:data:`PAPER_CARGO_DENSITY`; coordinate ``cargo_density``),
    one line per run."""
    if "cargo_density" not in ds.coords:
        return []
    out = []
    for c, o, side, f, a, rho in zip(ds["case"].values, ds["opening"].values,
                                     ds["side"].values, ds["fill"].values,
                                     ds["amplitude"].values, ds["cargo_density"].values,
                                     strict=True):
        if f > 0.0 and abs(float(rho) - PAPER_CARGO_DENSITY) > 1e-9:
            label = case_label(dict(opening=float(o), side=str(side), fill=float(f),
                                    amplitude=float(a)))
            out.append(f"{c} ({label}): cargo of {float(rho):g} kg/m³, where the paper's "
                       f"one fluid is water (it gives no cargo density)")
    return out


def stopped_runs(ds, period: float) -> list[str]:
    """The runs of a sweep dataset that stopped before their end (``case_status`` other
    than ``completed``), one line per run: when (in wave periods ``period``) and why."""
    if "case_status" not in ds.data_vars:
        return []
    out = []
    for c, status in zip(ds["case"].values, ds["case_status"].values, strict=True):
        if str(status) != "completed":
            end = last_sample(ds["time"].values, ds["roll"].sel(case=c).values)
            out.append(f"{c} at t/T = {end / period:.3g}: {status}")
    return out


def fast_runs(ds, period: float) -> list[str]:
    """The runs of a sweep dataset in which some particle outran a tenth of the speed of
    sound after the damage (the limit of weak compressibility the runs warn of,
    :data:`sph.engine.stepper.MACH_LIMIT`), one line per run: the share of its samples after
    t1, when first (in wave periods ``period``) and how fast at most. Empty where the
    dataset has no ``max_velocity`` or ``speed_of_sound``."""
    c0 = float(ds.attrs.get("speed_of_sound", math.nan))
    if "max_velocity" not in ds.data_vars or not math.isfinite(c0):
        return []
    t = ds["time"].values
    after = t >= float(ds.attrs["damage_time"]) - 1e-9
    out = []
    for c in map(str, ds["case"].values):
        v = ds["max_velocity"].sel(case=c).values
        ran = after & np.isfinite(v)
        fast = ran & (v > MACH_LIMIT * c0)
        if np.any(fast):
            out.append(f"{c}: faster than c0/10 = {MACH_LIMIT * c0:.3g} m/s in "
                       f"{100 * fast.sum() / ran.sum():.2g} % of its samples after t1, first "
                       f"at t/T = {t[fast][0] / period:.3g}, at most {v[ran].max():.3g} m/s")
    return out


def particle_losses(ds) -> list[str] | None:
    """The runs of a sweep dataset that lost fluid particles out of the domain
    (``lost_particles``) or had some put back by the tank's guard (``guarded_particles``,
    :func:`sph.engine.walls.keep_in_tank`), one line per run; None where the dataset does
    not say (runs written before the counts were gathered)."""
    if "lost_particles" not in ds.data_vars:
        return None
    guarded = (ds["guarded_particles"].values if "guarded_particles" in ds.data_vars
               else np.zeros(ds.sizes["case"]))
    out = []
    for c, lost, back in zip(map(str, ds["case"].values), ds["lost_particles"].values,
                             guarded, strict=True):
        parts = [f"{int(v)} {what}" for v, what in ((lost, "lost"),
                                                    (back, "put back by the tank's guard"))
                 if np.isfinite(v) and v > 0]
        if parts:
            out.append(f"{c}: " + ", ".join(parts))
    return out


def zone_entries(ds, period: float) -> list[str]:
    """The runs of a sweep dataset whose hull reached an absorbing zone, one line per run:
    when (in wave periods ``period``) and at which sway."""
    out = []
    for c in map(str, ds["case"].values):
        t, sway = case_zone_entry(ds, c)
        if np.isfinite(t):
            out.append(f"{c} at t/T = {t / period:.3g} (sway {sway:+.3g} m)")
    return out


#: the records :func:`spectra_table` looks into: name, (variable, probe), unit
SPECTRA_RECORDS = {"roll": ("roll", None, "degree"), "heave": ("heave", None, "m"),
                   "W1": ("probe_elevation", "W1", "m"), "W2": ("probe_elevation", "W2", "m"),
                   "Q": ("flood_volume", None, "m2")}

#: the columns of :func:`spectra_table`'s rows, in the order of its CSV table
SPECTRA_COLUMNS = ("case", "record", "peak", "frequency_over_omega", "amplitude", "unit",
                   "window_start", "window_end")


def spectra_table(ds, groups: Mapping[str, Sequence[str]], t2_periods: float,
                  peaks: int = 3) -> list[dict]:
    """Where each case's records sit after t2: the ``peaks`` largest peaks of
    :func:`spectrum_peaks` of the roll, the heave, the sloshing probes W1 and W2 and the
    flood volume Q of every case the findings read (every case at the first case's wave
    where they read none), each over the window its findings read (from t2 to the end, or
    to where its hull reached the absorbing zone). A probe that does not move (W1 of a ship
    without cargo) has none. Rows for a CSV table."""
    s = _Sweep(one_wave(ds, finding_cases(groups)), t2_periods)
    rows = []
    for c in (str(c) for c in s.ds["case"].values):
        s.stop = min(s.t_end, s.zone_entry(c)[0])
        t = s.steady_times()
        for record, (name, probe, unit) in SPECTRA_RECORDS.items():
            if name not in s.ds or (probe is not None and probe not in s.ds["probe"].values):
                continue
            y = s.steady(c, name, probe)
            moves = t.size and np.isfinite(y).any() and np.nanmax(y) > np.nanmin(y)
            found = spectrum_peaks(t, y, s.omega) if moves else []
            for rank, (f, a) in enumerate(found[:peaks], start=1):
                rows.append(dict(zip(SPECTRA_COLUMNS, (c, record, rank, f, a, unit, s.t2,
                                                       min(s.stop, s.end(c))), strict=True)))
    return rows


def findings_table(findings: Sequence[Finding]) -> list[dict]:
    """Rows for a CSV or HTML table."""
    return [f.as_dict() for f in findings]


#: the heading of the column of :attr:`Finding.halves_text`
HALVES_HEADING = "first / second half of the window after t2"

_VERDICT_COLOUR = {"holds": "#d9f2d9", "does not hold": "#f8d7d7",
                   "not determinable": "#eeeeee"}


def _summary(findings: Sequence[Finding]) -> str:
    """How many findings hold, do not hold and are not determinable."""
    counts = {v: sum(f.verdict == v for f in findings) for v in _VERDICT_COLOUR}
    return ", ".join(f"{n} {v}" for v, n in counts.items())


def findings_markdown(findings: Sequence[Finding], title: str, note: str = "") -> str:
    """The findings table as Markdown, to paste into a report or a page of notes: a heading,
    the note, the counts and one row per finding (id, the paper's finding, where the paper
    states it, what the run measured, the verdict, the verdicts on the halves of the window
    after t2)."""

    def cell(text: str) -> str:
        return " ".join(str(text).split()).replace("|", "\\|")

    rows = [f"| {' | '.join(cell(x) for x in (f.id, f.statement, f.paper, f.measured))} "
            f"| {f.verdict} | {f.halves_text} |" for f in findings]
    return "\n".join([f"# {cell(title)}", "", cell(note), "", _summary(findings) + ".", "",
                      "| id | finding of the paper | where | measured in this run | verdict "
                      f"| {HALVES_HEADING} |",
                      "| --- | --- | --- | --- | --- | --- |", *rows, ""])


def findings_html(findings: Sequence[Finding], title: str, note: str = "") -> str:
    """A self-contained HTML page with the findings table."""
    import html

    rows = []
    for f in findings:
        rows.append(
            "<tr>" + "".join(f"<td>{html.escape(x)}</td>" for x in
                             (f.id, f.statement, f.paper, f.measured))
            + f'<td style="background:{_VERDICT_COLOUR[f.verdict]}">{f.verdict}</td>'
            f"<td>{html.escape(f.halves_text)}</td></tr>")
    summary = _summary(findings)
    return (
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>"
        f"{html.escape(title)}</title><style>body{{font-family:sans-serif;font-size:14px}}"
        "table{border-collapse:collapse}td,th{border:1px solid #999;padding:4px 6px;"
        "vertical-align:top}th{background:#ddd}</style></head><body>"
        f"<h2>{html.escape(title)}</h2><p>{html.escape(note)}</p><p>{summary}.</p>"
        "<table><tr><th>id</th><th>finding of the paper</th><th>where</th>"
        f"<th>measured in this run</th><th>verdict</th><th>{HALVES_HEADING}</th></tr>"
        + "\n".join(rows) + "</table></body></html>\n")
