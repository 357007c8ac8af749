"""The paper's qualitative findings (Cao et al. 2019, Sec. IV-V), measured on a sweep dataset.

Each finding is a statement of the paper that can be checked on this project's runs: a few
numbers are measured from the gathered dataset (:func:`sph.study.sweeps.gather`) and compared as
the statement says. A finding whose cases are not in the sweep, or whose time window is not
covered by the runs, is reported as not determinable rather than guessed.

Measures (``T`` the wave period, ``t1`` the damage time, ``t2`` the start of the dynamic
equilibrium, ``t2_periods * T``):

- *amplitude* of a signal over a window: half the range between its 5th and 95th
  percentiles (a sine of amplitude a gives 0.988 a; single spikes do not count);
- *first peak* of Q/V: the first local maximum after ``t1`` whose prominence is at least 2 %
  of the largest Q/V (the maximum over ``[t1, t1 + 3 T]`` if there is none);
- *initial inflow rate*: the mean of dQ/dt over ``[t1, t1 + T/2]``;
- *fluctuation* of Q: ``(max - min) / max`` over ``[t2, t_end]``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from sph.study.sweeps import DEFAULT_AMPLITUDE

#: a finding comparing amplitudes "near the minimum" allows this much above the minimum
NEAR_MINIMUM = 0.10
#: the flood-volume fluctuation counts as "about 10 %" inside this band
FLUCTUATION_BAND = (0.05, 0.20)
#: "slightly larger" means a ratio inside this band
SLIGHTLY_LARGER = (1.0, 1.25)
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

    @property
    def verdict(self) -> str:
        return {True: "holds", False: "does not hold", None: "not determinable"}[self.holds]

    def as_dict(self) -> dict:
        return dict(id=self.id, statement=self.statement, paper=self.paper,
                    measured=self.measured, verdict=self.verdict)


# ------------------------------------------------------------------------------ measures
def amplitude(y) -> float:
    """Half the 5th-95th percentile range of ``y`` (NaN ignored)."""
    y = np.asarray(y, dtype=float)
    y = y[np.isfinite(y)]
    if y.size < 3:
        return float("nan")
    lo, hi = np.percentile(y, [5.0, 95.0])
    return 0.5 * float(hi - lo)


def window(t, y, start: float, end: float | None = None) -> np.ndarray:
    """Samples of ``y`` with ``start <= t <= end``."""
    t = np.asarray(t, dtype=float)
    sel = t >= start - 1e-9
    if end is not None:
        sel &= t <= end + 1e-9
    return np.asarray(y, dtype=float)[sel]


def first_peak(t, q, t1: float, period: float) -> tuple[float, float]:
    """Time and value of the first peak of ``q`` after ``t1`` (see the module docstring)."""
    from scipy.signal import find_peaks

    t = np.asarray(t, dtype=float)
    q = np.asarray(q, dtype=float)
    sel = t >= t1
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


def fluctuation(y) -> float:
    """``(max - min) / max`` of ``y``."""
    y = np.asarray(y, dtype=float)
    y = y[np.isfinite(y)]
    if y.size < 2 or np.max(y) <= 0.0:
        return float("nan")
    return float((np.max(y) - np.min(y)) / np.max(y))


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
    """A short label of a case in the paper's notation; the wave amplitude is named when it
    is not Table I's (A / d = 10/21)."""
    if case["opening"] == 0:
        base = "intact"
    else:
        minus = "-" if case["side"] == "head" else ""
        base = f"δ̄{minus} = {fraction_text(case['opening'])}"
    label = f"{base}, η = {100 * case['fill']:g} %"
    amp = float(case.get("amplitude", DEFAULT_AMPLITUDE))
    if amp == 0.0:
        label += ", still water"
    elif abs(amp - DEFAULT_AMPLITUDE) > 1e-9:
        label += f", Ā = {fraction_text(amp)}"
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
        self.cases = {str(c): dict(case=str(c), opening=float(o), side=str(s), fill=float(f),
                                   amplitude=float(a))
                      for c, o, s, f, a in zip(ds["case"].values, ds["opening"].values,
                                               ds["side"].values, ds["fill"].values,
                                               ds["amplitude"].values, strict=True)}

    def series(self, case: str, name: str, probe: str | None = None) -> np.ndarray:
        v = self.ds[name].sel(case=case)
        if probe is not None:
            v = v.sel(probe=probe)
        return v.values

    def steady(self, case: str, name: str, probe: str | None = None) -> np.ndarray:
        return window(self.t, self.series(case, name, probe), self.t2)

    def label(self, case: str) -> str:
        return case_label(self.cases[case])

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


def compute_findings(ds, groups: Mapping[str, Sequence[str]], t2_periods: float) -> list[Finding]:
    """Measure every finding on the gathered dataset ``ds``.

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
    """
    s = _Sweep(ds, t2_periods)
    out = []
    opening = [c for c in groups.get("opening", [])]
    damaged = [c for c in opening if s.cases[c]["opening"] > 0]
    intact = [c for c in opening if s.cases[c]["opening"] == 0]
    side = list(groups.get("side", []))
    fill = list(groups.get("fill", []))
    steady_note = (f"needs runs to at least t2 + T = {(t2_periods + 1):g} T "
                   f"(runs end at {s.t_end / s.period:.3g} T)")

    def missing(fid, statement, paper, need):
        out.append(Finding(fid, statement, paper, f"not in this sweep: {need}", None))

    # F1: damaged roll amplitude after t2 smaller than intact
    st, pp = ("The roll amplitude of the damaged ship after t2 is smaller than the intact "
              "ship's", "Sec. IV B, Fig. 15; Sec. V")
    if not (intact and damaged):
        missing("F1", st, pp, "an intact case and a damaged case at the reference fill")
    elif not s.steady_covered:
        out.append(Finding("F1", st, pp, steady_note, None))
    else:
        amp = {c: amplitude(s.steady(c, "roll")) for c in intact[:1] + damaged}
        holds = all(amp[c] < amp[intact[0]] for c in damaged)
        out.append(_judged("F1", st, pp, "roll amplitude after t2 (deg): " + _fmt(amp, s),
                           holds, amp.values()))

    # F2: first Q/V peak grows with opening size
    st, pp = "The first peak of Q/V grows with the opening size", "Sec. IV B, Fig. 13"
    if len(damaged) < 2:
        missing("F2", st, pp, "two or more opening sizes")
    else:
        peaks = {c: first_peak(s.t, s.series(c, "flood_ratio"), s.t1, s.period) for c in damaged}
        vals = {c: v for c, (_, v) in peaks.items()}
        text = "; ".join(f"{s.label(c)}: {v:.3g} at t/T = {tp / s.period:.2f}"
                         for c, (tp, v) in peaks.items())
        out.append(_judged("F2", st, pp, "first Q/V peak: " + text,
                           _increasing(list(vals.values())), vals.values()))

    # F3: the damaged ship settles lower than the intact one
    st, pp = ("After damage the ship heaves about a lower equilibrium than the intact ship",
              "Sec. IV B, Fig. 14; Sec. V")
    if not (intact and damaged):
        missing("F3", st, pp, "an intact case and a damaged case at the reference fill")
    elif not s.steady_covered:
        out.append(Finding("F3", st, pp, steady_note, None))
    else:
        mean = {c: float(np.nanmean(s.steady(c, "heave"))) for c in intact[:1] + damaged}
        holds = all(mean[c] < mean[intact[0]] for c in damaged)
        out.append(_judged("F3", st, pp, "mean heave after t2 (m): " + _fmt(mean, s), holds,
                           mean.values()))

    # F4: sloshing wave in the damaged cabin smaller for larger openings
    st, pp = ("The sloshing wave in the damaged cabin (W2) after t2 is lower for larger "
              "openings", "Sec. IV B, Figs. 11-12")
    if len(damaged) < 2:
        missing("F4", st, pp, "two or more opening sizes")
    elif not s.steady_covered:
        out.append(Finding("F4", st, pp, steady_note, None))
    else:
        amp = {c: amplitude(s.steady(c, "probe_elevation", "W2")) for c in damaged}
        out.append(_judged("F4", st, pp, "W2 amplitude after t2 (m): " + _fmt(amp, s),
                           _decreasing(list(amp.values())), amp.values()))

    # F5: head-wave initial inflow faster than back-wave
    heads = [c for c in side if s.cases[c]["side"] == "head" and s.cases[c]["opening"] > 0]
    backs = [c for c in side if s.cases[c]["side"] == "back" and s.cases[c]["opening"] > 0]
    st, pp = ("The initial inflow is faster with the opening facing the waves (head) than "
              "away from them (back)", "Sec. IV C, Figs. 16-17; Sec. V")
    if not (heads and backs):
        missing("F5", st, pp, "the reference opening on both sides")
    else:
        rate = {c: inflow_rate(s.t, s.series(c, "flood_volume"), s.t1, s.period)
                for c in backs[:1] + heads[:1]}
        out.append(_judged("F5", st, pp, "mean inflow rate over [t1, t1 + T/2] (m2/s): "
                           + _fmt(rate, s), rate[heads[0]] > rate[backs[0]], rate.values()))

    # F6: back-wave roll larger at dynamic equilibrium
    st, pp = ("At dynamic equilibrium the ship rolls more with the opening on the back side "
              "than facing the waves", "Sec. IV C, Fig. 18; Sec. V")
    if not (heads and backs):
        missing("F6", st, pp, "the reference opening on both sides")
    elif not s.steady_covered:
        out.append(Finding("F6", st, pp, steady_note, None))
    else:
        amp = {c: amplitude(s.steady(c, "roll")) for c in backs[:1] + heads[:1]}
        out.append(_judged("F6", st, pp, "roll amplitude after t2 (deg): " + _fmt(amp, s),
                           amp[backs[0]] > amp[heads[0]], amp.values()))

    # F7: the largest roll after damage is away from the opening
    st, pp = ("The largest roll angle after damage is towards the side opposite the opening",
              "Sec. IV C; Sec. V")
    cand = backs[:1] + heads[:1] if (heads or backs) else damaged[:1]
    if not cand:
        missing("F7", st, pp, "a damaged case")
    else:
        ext, ok = {}, True
        for c in cand:
            r = window(s.t, s.series(c, "roll"), s.t1)
            ext[c] = float(r[int(np.nanargmax(np.abs(r)))])
            # roll > 0 heels towards +x; a back opening faces +x, a head opening -x
            away = -1.0 if s.cases[c]["side"] == "back" else 1.0
            ok &= ext[c] * away > 0
        out.append(_judged("F7", st, pp, "largest roll after t1 (deg, + towards the waves' "
                           "travel): " + _fmt(ext, s), ok, ext.values()))

    # F8: near-minimum roll at fill 50 %
    st, pp = ("The roll after t2 is near its minimum at the fill ratio η = 50 %",
              "Sec. IV D, Fig. 21; Sec. V")
    half = [c for c in fill if abs(s.cases[c]["fill"] - 0.5) < 1e-6]
    if len(fill) < 3 or not half:
        missing("F8", st, pp, "η = 50 % and at least two other fill ratios")
    elif not s.steady_covered:
        out.append(Finding("F8", st, pp, steady_note, None))
    else:
        amp = {c: amplitude(s.steady(c, "roll")) for c in fill}
        low = min(amp.values())
        out.append(_judged("F8", st, pp, "roll amplitude after t2 (deg): " + _fmt(amp, s)
                           + f" (near: within {100 * NEAR_MINIMUM:g} % of the smallest)",
                           amp[half[0]] <= (1.0 + NEAR_MINIMUM) * low, amp.values()))

    # F9: flood-volume fluctuation about 10 % of its maximum
    st, pp = ("After t2 the flood volume fluctuates by about 10 % of its maximum",
              "Sec. IV B, Fig. 13")
    if not damaged:
        missing("F9", st, pp, "a damaged case at the reference fill")
    elif not s.steady_covered:
        out.append(Finding("F9", st, pp, steady_note, None))
    else:
        fl = {c: fluctuation(s.steady(c, "flood_volume")) for c in damaged}
        lo, hi = FLUCTUATION_BAND
        out.append(_judged("F9", st, pp, "(max - min) / max of Q after t2: "
                           + _fmt({c: 100 * v for c, v in fl.items()}, s, " %")
                           + f" (about 10 %: {100 * lo:g}-{100 * hi:g} %)",
                           all(lo <= v <= hi for v in fl.values()), fl.values()))

    # F10: flood-volume fluctuation decreases with fill ratio
    st, pp = ("The flood-volume fluctuation decreases as the cargo fill ratio grows",
              "Sec. IV D, Fig. 23")
    if len(fill) < 2:
        missing("F10", st, pp, "two or more fill ratios")
    elif not s.steady_covered:
        out.append(Finding("F10", st, pp, steady_note, None))
    else:
        fl = {c: fluctuation(s.steady(c, "flood_volume")) for c in fill}
        out.append(_judged("F10", st, pp, "(max - min) / max of Q after t2: "
                           + _fmt({c: 100 * v for c, v in fl.items()}, s, " %"),
                           _decreasing(list(fl.values())), fl.values()))

    # F11: sloshing in the liquid cabins smaller for larger fill ratios
    st, pp = ("The sloshing wave in the liquid cabins (W1) is lower for larger fill ratios",
              "Sec. IV D, Fig. 22")
    filled = [c for c in fill if s.cases[c]["fill"] > 0]
    if len(filled) < 2:
        missing("F11", st, pp, "two or more non-zero fill ratios")
    elif not s.steady_covered:
        out.append(Finding("F11", st, pp, steady_note, None))
    else:
        amp = {c: amplitude(s.steady(c, "probe_elevation", "W1")) for c in filled}
        out.append(_judged("F11", st, pp, "W1 amplitude after t2 (m): " + _fmt(amp, s),
                           _decreasing(list(amp.values())), amp.values()))

    # F12: heave amplitude slightly larger for the head-wave case
    st, pp = ("The wave direction changes the heave only slightly; the head-wave case "
              "heaves slightly more", "Sec. IV C, Fig. 19")
    if not (heads and backs):
        missing("F12", st, pp, "the reference opening on both sides")
    elif not s.steady_covered:
        out.append(Finding("F12", st, pp, steady_note, None))
    else:
        amp = {c: amplitude(s.steady(c, "heave")) for c in backs[:1] + heads[:1]}
        ratio = amp[heads[0]] / amp[backs[0]] if amp[backs[0]] > 0 else math.inf
        lo, hi = SLIGHTLY_LARGER
        out.append(_judged("F12", st, pp, "heave amplitude after t2 (m): " + _fmt(amp, s)
                           + f"; head / back = {ratio:.3f} (slightly larger: {lo:g}-{hi:g})",
                           lo <= ratio <= hi, amp.values()))

    # Fig. 10: the reference opening in still water and in waves of several amplitudes
    amps = [c for c in groups.get("amplitude", []) if s.cases[c]["opening"] > 0]
    still = [c for c in amps if s.cases[c]["amplitude"] == 0.0]
    waves = [c for c in amps if s.cases[c]["amplitude"] > 0.0]

    # F13: the initial inflow is slower in waves than in still water
    st, pp = ("The initial inflow is slower in waves than in still water (the wave's and the "
              "flooding water's heeling moments oppose each other)", "Sec. IV B, Fig. 10(c)")
    if not (still and waves):
        missing("F13", st, pp, "the reference opening in still water and in waves")
    else:
        rate = {c: inflow_rate(s.t, s.series(c, "flood_volume"), s.t1, s.period)
                for c in still[:1] + waves}
        out.append(_judged("F13", st, pp, "mean inflow rate over [t1, t1 + T/2] (m2/s): "
                           + _fmt(rate, s), all(rate[c] < rate[still[0]] for c in waves),
                           rate.values()))

    # F14: the same heave equilibrium whatever the wave amplitude
    st, pp = ("Whatever the wave amplitude, the damaged ship heaves about the same new "
              "equilibrium", "Sec. IV B, Fig. 10(b)")
    if len(amps) < 2:
        missing("F14", st, pp, "the reference opening at two or more wave amplitudes")
    elif not s.steady_covered:
        out.append(Finding("F14", st, pp, steady_note, None))
    else:
        mean = {c: float(np.nanmean(s.steady(c, "heave"))) for c in amps}
        sink = max(abs(v) for v in mean.values())
        spread = max(mean.values()) - min(mean.values())
        out.append(_judged("F14", st, pp, "mean heave after t2 (m): " + _fmt(mean, s)
                           + f"; spread {spread:.3g} m = {100 * spread / sink:.3g} % of the "
                           f"largest sinkage (the same: at most {100 * SAME_EQUILIBRIUM:g} %)",
                           spread <= SAME_EQUILIBRIUM * sink, mean.values()))

    # F15: the heave amplitude follows the wave amplitude
    st, pp = ("The heave amplitude after t2 is set mainly by the wave amplitude: it grows "
              "with it", "Sec. IV B, Fig. 10(b)")
    if len(amps) < 2:
        missing("F15", st, pp, "the reference opening at two or more wave amplitudes")
    elif not s.steady_covered:
        out.append(Finding("F15", st, pp, steady_note, None))
    else:
        amp = {c: amplitude(s.steady(c, "heave")) for c in amps}
        out.append(_judged("F15", st, pp, "heave amplitude after t2 (m): " + _fmt(amp, s),
                           _increasing(list(amp.values())), amp.values()))
    return out


def findings_table(findings: Sequence[Finding]) -> list[dict]:
    """Rows for a CSV or HTML table."""
    return [f.as_dict() for f in findings]


def findings_html(findings: Sequence[Finding], title: str, note: str = "") -> str:
    """A self-contained HTML page with the findings table."""
    import html

    colour = {"holds": "#d9f2d9", "does not hold": "#f8d7d7", "not determinable": "#eeeeee"}
    rows = []
    for f in findings:
        rows.append(
            "<tr>" + "".join(f"<td>{html.escape(x)}</td>" for x in
                             (f.id, f.statement, f.paper, f.measured))
            + f'<td style="background:{colour[f.verdict]}">{f.verdict}</td></tr>')
    counts = {v: sum(f.verdict == v for f in findings) for v in colour}
    summary = ", ".join(f"{n} {v}" for v, n in counts.items())
    return (
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>"
        f"{html.escape(title)}</title><style>body{{font-family:sans-serif;font-size:14px}}"
        "table{border-collapse:collapse}td,th{border:1px solid #999;padding:4px 6px;"
        "vertical-align:top}th{background:#ddd}</style></head><body>"
        f"<h2>{html.escape(title)}</h2><p>{html.escape(note)}</p><p>{summary}.</p>"
        "<table><tr><th>id</th><th>finding of the paper</th><th>where</th>"
        "<th>measured in this run</th><th>verdict</th></tr>"
        + "\n".join(rows) + "</table></body></html>\n")
