"""The still-water flooding benchmark's measures that need no reference run
(``benchmarks/refinement_flooding.py``: draught against the lost-buoyancy heave, force
noise), on synthetic records with known answers."""
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
from refinement_flooding import reference_free_measures  # noqa: E402

B, W, T1 = 16.0, 1.0 / 3.0, 1.0


def record(offset=0.0, noise=0.0, growth=0.0, seed=1):
    """60 s at 0.1 s: flood water swinging slowly about 75 m2, the ship at its
    lost-buoyancy heave (plus ``offset`` from 30 s on), a hull force of 650 kN with white
    noise of standard deviation ``noise`` and a slow swing a running mean keeps."""
    t = np.arange(0.0, 60.0 + 1e-9, 0.1)
    q = 75.0 + 5.0 * np.sin(2 * np.pi * t / 16.0)
    heave = -W * q / B + np.where(t >= 30.0, offset, 0.0)
    rng = np.random.default_rng(seed)
    fz = 650e3 + 20e3 * np.sin(2 * np.pi * t / 16.0) + noise * rng.standard_normal(t.size)
    ke = 400e3 * np.exp(-t / 4.0) + 20e3 * np.exp(growth * np.clip(t - 30.0, 0.0, None))
    return xr.Dataset(
        {"heave": ("time", heave), "flood_volume": ("time", q), "kinetic_energy": ("time", ke),
         "body_force_z": (("body", "time"), fz[None, :])},
        coords={"time": t},
        attrs={"segment_weights": f"{1 - W:.6g} {W:.6g}", "breadth": B, "damage_time": T1})


def test_a_ship_at_its_lost_buoyancy_heave_reads_no_gap_and_no_noise():
    gap, noise, ke = reference_free_measures(record())
    assert gap < 1e-3  # only the rounding of the weights in the attributes
    assert noise < 0.5e3  # a 16 s swing is not noise (its residual after a 1 s mean)
    # from t1 + 20 s the inrush's energy is gone: the 20 kJ left, and its decaying tail
    assert ke == pytest.approx(20e3 + 400e3 * np.exp(-21.0 / 4.0), rel=0.05)


def test_a_ship_sunk_below_it_and_a_noisy_force_read_their_offset_and_noise():
    gap, noise, ke = reference_free_measures(record(offset=-0.4, noise=50e3, growth=0.1))
    assert gap == pytest.approx(0.4, abs=0.01)
    # white noise less its 1 s (10-sample) running mean keeps sqrt(1 - 1/10) of its spread
    assert noise == pytest.approx(50e3 * np.sqrt(0.9), rel=0.15)
    # energy growing from 30 s: the last whole window (53-57 s) ends 27 s after it began
    assert ke > 20e3 * np.exp(0.1 * 23.0)
