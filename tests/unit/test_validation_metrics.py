"""Comparison metrics of a simulated series with a measured one (:mod:`sph.study.validation`):
amplitude ratio, lag and correlation recover known values from synthetic signals, on the
irregular sampling of a digitised record; the table of validation targets is complete."""

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from sph.cases import CASES
from sph.study.sweeps import PRESET_SECTION_KEYS
from sph.study.validation import (
    HADZIC_MAP,
    TARGETS,
    Target,
    dominant_period,
    floating_box_errors,
    series_errors,
)

SCRIPTS = Path(__file__).resolve().parents[2] / "workflow" / "scripts"

OMEGA = 2.0 * math.pi / 0.8  # a wave group's dominant period, 0.8 s


def _measured(seed=0, n=300, span=(5.0, 9.0)):
    rng = np.random.default_rng(seed)
    te = np.sort(rng.uniform(*span, n))  # digitised: irregular sampling
    envelope = np.exp(-(((te - 7.0) / 1.2) ** 2))
    return te, envelope * np.sin(OMEGA * te)


def _simulated(gain, lag, t=None):
    t = np.arange(0.0, 10.0, 0.01) if t is None else t
    return t, gain * np.exp(-(((t - lag - 7.0) / 1.2) ** 2)) * np.sin(OMEGA * (t - lag))


@pytest.mark.parametrize("gain,lag", [(1.0, 0.0), (0.8, 0.06), (1.3, -0.1)])
def test_series_errors_recover_gain_and_lag(gain, lag):
    te, ye = _measured()
    t, y = _simulated(gain, lag)
    e = series_errors(t, y, te, ye, max_lag=0.3)
    # gain: the RMS ratio of two records of the same group shifted by under 2 % of its width
    assert e["amplitude_ratio"] == pytest.approx(gain, rel=0.02)
    assert e["lag"] == pytest.approx(lag, abs=0.01)  # the search grid: half the sampling
    assert e["correlation"] > 0.995
    if gain == 1.0 and lag == 0.0:
        # only the linear interpolation between the irregular samples (13 ms apart on
        # average, omega^2 dt^2 / 8 ~ 1e-3 of the amplitude, more across the wider gaps)
        assert e["nrms"] < 0.01


def test_an_inverted_series_does_not_correlate_within_a_quarter_period():
    te, ye = _measured()
    t, y = _simulated(-1.0, 0.0)
    e = series_errors(t, y, te, ye, max_lag=0.2)  # quarter period 0.2 s
    assert e["correlation"] < 0.2
    assert e["nrms"] > 0.5  # the difference is twice the signal


def test_series_errors_refuse_a_too_short_overlap():
    te, ye = _measured(span=(5.0, 5.4))
    t, y = _simulated(1.0, 0.0)
    with pytest.raises(ValueError, match="overlap"):
        series_errors(t, y, te, ye, max_lag=0.3)


def test_dominant_period_of_a_wave_group():
    t, y = _simulated(1.0, 0.0)
    # a Gaussian envelope of 1.2 s widens the peak; the spectrum's bin is 0.1 Hz
    assert dominant_period(t, y) == pytest.approx(0.8, rel=0.05)
    assert math.isnan(dominant_period(t, np.ones_like(t)))


def test_floating_box_errors_of_the_experiment_against_itself():
    exp = {"WaveProbe_N1": np.column_stack(_measured()),
           "WP_Heave": np.column_stack(_measured(seed=1)),
           "WP_Roll": np.column_stack(_measured(span=(6.0, 6.5)))}  # too short: left out
    t = np.arange(0.0, 10.0, 0.01)
    _, y = _simulated(1.0, 0.0, t)
    ds = xr.Dataset({"probe_elevation": (("probe", "time"), np.vstack([y, 0 * y])),
                     "heave": ("time", y), "roll": ("time", y)},
                    coords={"time": t, "probe": ["WP1", "WP2"]})
    out = floating_box_errors(ds, exp)
    assert set(out) == {"WaveProbe_N1", "WP_Heave"}
    for e in out.values():
        assert e["amplitude_ratio"] == pytest.approx(1.0, rel=0.01)
        assert abs(e["lag"]) <= 0.01 and e["correlation"] > 0.999
    assert set(HADZIC_MAP) >= set(out)


def test_every_validation_target_has_every_field_and_a_unique_id():
    assert list(TARGETS) == ["wave_tank", "sloshing", "decay", "floating_box", "dam_break",
                            "cylinder"]
    figures = []
    for key, t in TARGETS.items():
        assert t.id == key
        for field in dataclasses.fields(Target):
            value = getattr(t, field.name)
            assert value is not None and value != "" and value != (), (key, field.name)
        assert t.case in CASES and t.id in PRESET_SECTION_KEYS
        assert callable(t.runs) and callable(t.metric)
        for name, script in t.figures:
            assert (SCRIPTS / f"{script}.py").is_file(), script
            figures.append(name)
    assert len(set(figures)) == len(figures)  # one file name per figure
