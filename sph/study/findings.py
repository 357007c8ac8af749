"""The paper's qualitative findings (Cao et al. 2019, Sec. IV-V), measured on a sweep dataset.

Each finding is a statement of the paper that can be checked on this project's runs: a few
numbers are measured from the gathered dataset (:func:`sph.study.sweeps.gather`) and compared as
the statement says. A finding whose cases are not in the sweep, or whose time window is not
covered by the runs, is reported as not determinable rather than guessed.

The findings are the table :data:`FINDINGS`: one :class:`FindingSpec` per finding (id,
statement, paper section, the group of cases it compares and what it needs of them, whether
it is measured after t2, a measure and a test), evaluated in order by
:func:`compute_findings`. A new finding is one more record.

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
from collections.abc import Callable, Mapping, Sequence
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


# ------------------------------------------------------------------------------ cases
class _Cases:
    """The cases of a sweep that the findings compare, from its groups
    (:func:`sph.study.sweeps.groups`), each list in the group's order."""

    def __init__(self, s: _Sweep, groups: Mapping[str, Sequence[str]]):
        par = s.cases
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

    def still_and_waves(self) -> list[str]:
        """The still-water case first, then every wave case."""
        return self.still[:1] + self.waves if self.still and self.waves else []

    def amplitudes(self) -> list[str]:
        return self.amps if len(self.amps) >= 2 else []


# ------------------------------------------------------------------------------ measures
# per case: sweep, case -> number
def _roll_amplitude(s: _Sweep, c: str) -> float:
    return amplitude(s.steady(c, "roll"))


def _heave_amplitude(s: _Sweep, c: str) -> float:
    return amplitude(s.steady(c, "heave"))


def _heave_mean(s: _Sweep, c: str) -> float:
    return float(np.nanmean(s.steady(c, "heave")))


def _w1_amplitude(s: _Sweep, c: str) -> float:
    return amplitude(s.steady(c, "probe_elevation", "W1"))


def _w2_amplitude(s: _Sweep, c: str) -> float:
    return amplitude(s.steady(c, "probe_elevation", "W2"))


def _inflow(s: _Sweep, c: str) -> float:
    return inflow_rate(s.t, s.series(c, "flood_volume"), s.t1, s.period)


def _fluctuation(s: _Sweep, c: str) -> float:
    return fluctuation(s.steady(c, "flood_volume"))


def _largest_roll(s: _Sweep, c: str) -> float:
    r = window(s.t, s.series(c, "roll"), s.t1)
    return float(r[int(np.nanargmax(np.abs(r)))])


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


def _first_peaks(s: _Sweep, cases: Sequence[str]):
    peaks = {c: first_peak(s.t, s.series(c, "flood_ratio"), s.t1, s.period) for c in cases}
    text = "; ".join(f"{s.label(c)}: {v:.3g} at t/T = {tp / s.period:.2f}"
                     for c, (tp, v) in peaks.items())
    return {c: v for c, (_, v) in peaks.items()}, "first Q/V peak: " + text


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
        _each(_roll_amplitude, "roll amplitude after t2 (deg)"), _first_largest),
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
        _Cases.back_and_head, True, _each(_roll_amplitude, "roll amplitude after t2 (deg)"),
        _back_larger),
    FindingSpec(
        "F7", "The largest roll angle after damage is towards the side opposite the opening",
        "Sec. IV C; Sec. V", "side (else opening)", "a damaged case",
        _Cases.sides_or_damaged, False,
        _each(_largest_roll, "largest roll after t1 (deg, + towards the waves' travel)"),
        _away_from_opening),
    FindingSpec(
        "F8", "The roll after t2 is near its minimum at the fill ratio η = 50 %",
        "Sec. IV D, Fig. 21; Sec. V", "fill", "η = 50 % and at least two other fill ratios",
        _Cases.fills_with_half, True,
        _each(_roll_amplitude, "roll amplitude after t2 (deg)",
              suffix=lambda v: f" (near: within {100 * NEAR_MINIMUM:g} % of the smallest)"),
        _half_near_minimum),
    FindingSpec(
        "F9", "After t2 the flood volume fluctuates by about 10 % of its maximum",
        "Sec. IV B, Fig. 13", "opening", "a damaged case at the reference fill",
        _Cases.any_damaged, True,
        _each(_fluctuation, "(max - min) / max of Q after t2", percent=True,
              suffix=lambda v: (f" (about 10 %: {100 * FLUCTUATION_BAND[0]:g}-"
                                f"{100 * FLUCTUATION_BAND[1]:g} %)")),
        _about_ten_percent),
    FindingSpec(
        "F10", "The flood-volume fluctuation decreases as the cargo fill ratio grows",
        "Sec. IV D, Fig. 23", "fill", "two or more fill ratios", _Cases.fills, True,
        _each(_fluctuation, "(max - min) / max of Q after t2", percent=True),
        _all_decreasing),
    FindingSpec(
        "F11", "The sloshing wave in the liquid cabins (W1) is lower for larger fill ratios",
        "Sec. IV D, Fig. 22", "fill", "two or more non-zero fill ratios", _Cases.cargo_fills,
        True, _each(_w1_amplitude, "W1 amplitude after t2 (m)"), _all_decreasing),
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
)


def compute_findings(ds, groups: Mapping[str, Sequence[str]], t2_periods: float) -> list[Finding]:
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
    """
    s = _Sweep(ds, t2_periods)
    sel = _Cases(s, groups)
    steady_note = (f"needs runs to at least t2 + T = {(t2_periods + 1):g} T "
                   f"(runs end at {s.t_end / s.period:.3g} T)")
    out = []
    for f in FINDINGS:
        cases = f.cases(sel)
        if not cases:
            out.append(Finding(f.id, f.statement, f.paper, f"not in this sweep: {f.needs}",
                               None))
        elif f.steady and not s.steady_covered:
            out.append(Finding(f.id, f.statement, f.paper, steady_note, None))
        else:
            values, measured = f.measure(s, cases)
            out.append(_judged(f.id, f.statement, f.paper, measured, f.test(values, s),
                               values.values()))
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
