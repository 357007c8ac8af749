"""Record analysis helpers of sph.study.analysis on synthetic records."""

import numpy as np
import pytest

from sph.study.analysis import decay_modes, spectral_peak


def test_spectral_peak_of_a_damped_mode():
    t = np.arange(0.0, 30.0, 0.05)
    y = 2.0 * np.exp(-0.1 * 1.3 * t) * np.cos(1.3 * t + 0.4) + 0.5
    assert spectral_peak(t, y, (0.5, 3.0)) == pytest.approx(1.3, rel=0.01)
    with pytest.raises(ValueError, match="no frequency"):
        spectral_peak(t, y, (100.0, 200.0))


@pytest.mark.parametrize("low", [0.37, 0.45, 0.6, 0.75])
def test_decay_modes_hold_a_weak_damped_mode_apart_from_a_strong_one(low):
    """A roll record like a loaded ship's decay: a strong slow mode (damping ratio 0.1, one
    to three periods in the 30 s) and a weak, strongly damped fast one (1.35 rad/s, damping
    ratio 0.15, a fifth of the amplitude) above the split at 1.0 rad/s. The slow mode within
    1 %, its damping ratio within 0.01; the fast one within 2 %. The spectrum of the record
    alone puts the fast peak at the split (0.6, 0.75) or 5 % low (0.45): the slow mode's
    spectrum buries it."""
    t = np.arange(0.0, 30.0, 0.05)
    y = (5.0 * np.exp(-0.1 * low * t) * np.cos(low * t)
         + 1.0 * np.exp(-0.15 * 1.35 * t) * np.cos(1.35 * t + 0.7) + 0.3)
    m = decay_modes(t, y, 1.0)
    assert m["low"][0] == pytest.approx(low, rel=0.01)
    assert m["low"][1] == pytest.approx(0.1, abs=0.01)
    assert m["high"] == pytest.approx(1.35, rel=0.02)
