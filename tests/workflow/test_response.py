"""Tests of the response over wave frequency (sph.study.response) and its figure
(workflow/scripts/fig_rao.py) on synthetic sweep datasets."""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest
import xarray as xr

from sph.bodies.wavemaker import wavenumber
from sph.study import response
from sph.study import sweeps as study

OMEGAS = (0.6, 0.8, 1.0, 1.2)
DRAUGHT, DEPTH = 4.2, 30.0


def _resonance(omega, natural, zeta):
    """The response of a linear oscillator to a unit forcing slope: 1 in long waves."""
    r = omega / natural
    return 1.0 / math.hypot(1.0 - r * r, 2.0 * zeta * r)


def _roll_rao(case, omega):
    return _resonance(omega, 1.059, 0.10) if case.startswith("intact") else \
        _resonance(omega, 0.95, 0.15)


def _heave_rao(case, omega):
    return _resonance(omega, 1.01, 0.4) if case.startswith("intact") else \
        _resonance(omega, 0.9, 0.4)


def _dataset(still=True):
    """A sweep over wave frequency at the paper's slope kA: each run 12 of its own periods
    (NaN after its end on the common axis), its roll and heave sines of the RAOs above,
    the damaged ship listing and sinking after t1 = 3.18 T (a trend the amplitudes must
    not read); with a still-water case, which has no RAO."""
    rows = []
    for name, opening in (("intact", 0.0), ("damaged", 10 / 21)):
        for w in OMEGAS:
            amp = response.steepness_amplitude(w) / DRAUGHT
            rows.append(dict(case=f"{name}_w{round(100 * w):03d}", opening=opening,
                             side="back", fill=0.0, omega=w, amplitude=amp))
    if still:
        rows.append(dict(case="still", opening=10 / 21, side="back", fill=0.0, omega=1.0,
                         amplitude=0.0))
    dt = 0.05
    t = np.arange(0.0, 12 * 2 * math.pi / min(OMEGAS) + 1e-9, dt)
    roll, heave, periods, t1s = [], [], [], []
    for r in rows:
        w, period = r["omega"], 2 * math.pi / r["omega"]
        t1 = 3.18 * period
        a = r["amplitude"] * DRAUGHT
        k = wavenumber(w, DEPTH)
        phi = math.degrees(k * a) * _roll_rao(r["case"], w) if a else 0.0
        z = a * _heave_rao(r["case"], w)
        settle = np.clip(t - t1, 0.0, None) / (0.5 * period)
        damaged = r["opening"] > 0
        roll.append(phi * np.sin(w * t + 0.4) - (3.0 if damaged else 0.0)
                    * (1 - np.exp(-settle)))
        heave.append(z * np.sin(w * t) - (0.8 if damaged else 0.0) * (1 - np.exp(-settle)))
        for series in (roll[-1], heave[-1]):
            series[t > 12 * period + 1e-9] = np.nan
        periods.append(period)
        t1s.append(t1)
    ds = xr.Dataset(
        {"roll": (("case", "time"), np.array(roll)),
         "heave": (("case", "time"), np.array(heave)),
         "wave_period": ("case", periods), "damage_time": ("case", t1s)},
        coords=dict(time=t, case=[r["case"] for r in rows],
                    **{k: ("case", [r[k] for r in rows])
                       for k in ("opening", "side", "fill", "amplitude", "omega")}),
        attrs=dict(draught=DRAUGHT, depth=DEPTH, sweep="rao", preset="synthetic", dx=0.8))
    return ds


def test_paper_wave_slope():
    assert response.PAPER_STEEPNESS == pytest.approx(0.2048, abs=1e-4)
    assert response.steepness_amplitude(1.0) == pytest.approx(2.0, rel=1e-12)
    # a 147 m wave at 0.6 rad/s carries the same slope with A = 4.78 m
    assert response.steepness_amplitude(0.6) == pytest.approx(4.784, abs=1e-3)


def test_response_table_recovers_the_raos():
    """The RAOs of the synthetic runs within 2 %: the amplitude measure reads 0.988 of a
    sine (half the 5-95 % range), and the running mean leaves < 0.5 % of the settling."""
    rows = response.response_table(_dataset(), 7.0)
    assert [r["case"] for r in rows] == [c for c in _dataset()["case"].values if c != "still"]
    for r in rows:
        assert r["steepness"] == pytest.approx(response.PAPER_STEEPNESS, rel=1e-9)
        assert r["period"] == pytest.approx(2 * math.pi / r["omega"])
        assert r["roll_rao"] == pytest.approx(_roll_rao(r["case"], r["omega"]), rel=0.02)
        assert r["heave_rao"] == pytest.approx(_heave_rao(r["case"], r["omega"]), rel=0.02)
        assert r["roll_rao"] == pytest.approx(
            math.radians(r["roll_amplitude"]) / r["steepness"], rel=1e-12)


def test_first_harmonic_rao_leaves_out_a_second_harmonic():
    """A roll with a second harmonic of 40 % (a steep long wave exciting the roll near its
    natural frequency at 2 omega): the amplitude measure counts it, the first-harmonic RAO
    does not (a least-squares sine, exact to the sampling)."""
    ds = _dataset(still=False)
    t = ds["time"].values
    roll = ds["roll"].values.copy()
    first = roll[0].copy()
    roll[0] = first + 0.4 * np.nanmax(np.abs(first[t > 7 * 2 * math.pi / 0.6])) \
        * np.sin(2 * 0.6 * t)
    ds["roll"] = (("case", "time"), roll)
    r = response.response_table(ds, 7.0)[0]
    assert r["case"] == "intact_w060"
    assert r["roll_rao_first"] == pytest.approx(_roll_rao("intact", 0.6), rel=0.005)
    assert r["roll_rao"] > 1.1 * r["roll_rao_first"]  # 1.15 at these phases
    assert r["heave_rao_first"] == pytest.approx(_heave_rao("intact", 0.6), rel=0.005)


def test_response_table_uses_each_case_own_period_and_window():
    """With one common period (that of 1 rad/s) the 0.6 rad/s run's window and running
    mean would be wrong: the measure must take each case's own."""
    ds = _dataset(still=False)
    wrong = ds.drop_vars(["wave_period", "damage_time", "omega"])
    wrong.attrs["wave_period"] = 2 * math.pi
    rows = response.response_table(wrong, 7.0)
    w060 = next(r for r in rows if r["case"] == "damaged_w060")
    assert abs(w060["roll_rao"] / _roll_rao("damaged", 0.6) - 1.0) > 0.02


def test_curves_are_one_per_ship_sorted_by_omega():
    rows = response.response_table(_dataset(), 7.0)
    lines = response.curves(rows[::-1])
    assert list(lines) == ["damaged, δ̄ = 10/21 (back side)", "intact"]
    for curve in lines.values():
        assert [r["omega"] for r in curve] == list(OMEGAS)
    assert response.curves(rows[:1]) == {}  # one frequency is no curve
    assert response.varies_omega(study.check_cases(
        [dict(case="a", opening=0, side="back", fill=0),
         dict(case="b", opening=0, side="back", fill=0, omega=0.8)]))
    assert not response.varies_omega(study.check_cases(
        [dict(case="a", opening=0, side="back", fill=0),
         dict(case="b", opening=0, side="back", fill=0, omega=0.8, amplitude=0)]))


def test_rao_figure_draws_each_ship_against_omega(tmp_path, figure_script):
    """workflow/scripts/fig_rao.py: two panels (roll / kA, heave / A), one line per ship
    through its RAOs, the intact roll natural frequency marked; the table as CSV."""
    load, drawn = figure_script
    fig_rao = load("fig_rao")
    nc = tmp_path / "rao.nc"
    _dataset().to_netcdf(nc)
    fig_rao.main(tmp_path / "rao.png", tmp_path / "rao.csv", nc, 7.0)
    assert (tmp_path / "rao.png").stat().st_size > 10_000
    roll_ax, heave_ax = drawn["axes"]
    assert roll_ax.get_ylabel().startswith("roll amplitude / wave slope kA")
    assert heave_ax.get_ylabel() == "heave amplitude / wave amplitude A"
    assert heave_ax.get_xlabel() == "wave frequency ω (rad/s)"
    for ax, rao in ((roll_ax, _roll_rao), (heave_ax, _heave_rao)):
        lines = {ln.get_label(): ln for ln in ax.get_lines()}
        intact = lines["intact"]
        np.testing.assert_allclose(intact.get_xdata(), OMEGAS)
        np.testing.assert_allclose(intact.get_ydata(), [rao("intact", w) for w in OMEGAS],
                                   rtol=0.02)
        marks = [ln for name, ln in lines.items() if "natural frequency" in name]
        assert len(marks) == 1 and list(marks[0].get_xdata()) == [1.059, 1.059]
        np.testing.assert_allclose(lines["intact, first harmonic"].get_ydata(),
                                   [rao("intact", w) for w in OMEGAS], rtol=0.01)
    legend = [t.get_text() for t in roll_ax.get_legend().get_texts()]
    assert legend[:4] == ["intact", "intact, first harmonic", "damaged, δ̄ = 10/21 (back side)",
                          "damaged, δ̄ = 10/21 (back side), first harmonic"]
    with open(tmp_path / "rao.csv") as fh:
        table = list(csv.DictReader(fh))
    assert len(table) == 2 * len(OMEGAS)
    assert float(table[0]["roll_rao"]) == pytest.approx(_roll_rao("intact", 0.6), rel=0.02)


def test_amplitudes_stop_where_the_hull_reaches_the_absorbing_zone(tmp_path, figure_script):
    """A run whose hull drifts into the absorbing zone comes to roll a third as much within
    about a period (the zone damps the ship as well as the waves): read to its entry, the
    RAO is the free one (within 2 %, as the whole runs above); read to the end the
    first-harmonic RAO would be 20 % or more low, the range one (which the two free
    periods before the entry dominate) 5 %. A hull in the zone before
    t2 + T gives no amplitudes; the figure's note names both."""
    ds = _dataset(still=False)
    t = ds["time"].values
    cases = list(ds["case"].values)
    cut, lost = cases.index("intact_w080"), cases.index("intact_w120")
    period = 2 * math.pi / 0.8
    entry = 9.0 * period
    roll = ds["roll"].values.copy()
    fade = np.exp(-np.clip(t - entry, 0.0, None) / period)
    roll[cut] = roll[cut] * (1.0 + 2.0 * fade) / 3.0
    sway = np.zeros_like(roll)
    sway[cut] = 4.0 * t / entry  # reaches the 4 m clearance at t = entry
    sway[lost] = 4.0 * t / (7.5 * 2 * math.pi / 1.2)
    ds["roll"] = (("case", "time"), roll)
    ds["sway"] = (("case", "time"), sway)
    ds["zone_clearance_back"] = ("case", np.full(len(cases), 4.0))
    ds["zone_clearance_head"] = ("case", np.full(len(cases), math.inf))
    rows = {r["case"]: r for r in response.response_table(ds, 7.0)}
    r = rows["intact_w080"]
    assert r["zone_entry"] == pytest.approx(9.0, abs=0.01)
    assert r["read_to"] == r["zone_entry"]
    assert r["roll_rao"] == pytest.approx(_roll_rao("intact", 0.8), rel=0.02)
    assert r["roll_rao_first"] == pytest.approx(_roll_rao("intact", 0.8), rel=0.02)
    whole = response.response_table(ds.drop_vars("sway"), 7.0)
    w080 = next(w for w in whole if w["case"] == "intact_w080")
    assert w080["roll_rao_first"] < 0.8 * _roll_rao("intact", 0.8)
    assert w080["roll_rao"] < 0.95 * _roll_rao("intact", 0.8)
    assert math.isnan(rows["intact_w120"]["roll_rao"])
    assert math.isnan(rows["intact_w120"]["heave_rao_first"])
    assert rows["intact_w100"]["zone_entry"] == math.inf
    assert rows["intact_w100"]["read_to"] == pytest.approx(12.0, abs=0.01)
    load, drawn = figure_script
    fig_rao = load("fig_rao")
    note = fig_rao.zone_note(list(rows.values()))
    assert "intact_w080 9 T" in note and "no amplitude: intact_w120" in note
    assert fig_rao.zone_note(whole) == ""
    ds.to_netcdf(tmp_path / "rao.nc")
    lines = fig_rao.main(tmp_path / "rao.png", tmp_path / "rao.csv", tmp_path / "rao.nc")
    assert drawn["texts"][-1] == note
    assert np.isnan([r["roll_rao"] for r in lines["intact"]]).sum() == 1  # a gap
    with open(tmp_path / "rao.csv") as fh:
        table = {r["case"]: r for r in csv.DictReader(fh)}
    assert table["intact_w120"]["roll_rao"] == "nan"
    assert float(table["intact_w080"]["read_to"]) == pytest.approx(9.0, abs=0.01)
