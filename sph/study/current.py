r"""The steady wave behind a body in a current tank, measured and against linear theory.

The ``cylinder_in_current`` case (:mod:`sph.cases.current`) writes wave gauges ``G000,
G001, ...`` every ``gauge_spacing`` from the cylinder's centre. Behind the cylinder the
surface settles, behind the front of the wave train (which travels downstream at
:math:`U/2`, the group velocity relative to the body), into the steady wave of Havelock
(1926),

.. math:: \eta(x) = \bar\eta + A \sin\left(k (x - x_c) + \varphi\right),

:func:`steady_wave` fits :math:`k, A, \varphi, \bar\eta` to the time-mean elevation of the
gauges in a window of x over the last part of the run (linear least squares in
:math:`A\cos\varphi, A\sin\varphi, \bar\eta` at each trial :math:`k`, the best :math:`k`
by a bounded scalar search); :func:`havelock_comparison` sets it beside
:func:`sph.cases.current.havelock_wave`.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr
from scipy.optimize import minimize_scalar


def gauge_positions(ds: xr.Dataset) -> tuple[np.ndarray, np.ndarray]:
    """Names and abscissae (m) of the wave gauges ``G...`` of a ``cylinder_in_current`` run."""
    names = [str(n) for n in ds["probe"].values if str(n).startswith("G")]
    x = ds.attrs["gauge_x0"] + ds.attrs["gauge_spacing"] * np.array(
        [int(n[1:]) for n in names], dtype=float)
    return np.array(names), x


def _fit_at(k, x, eta):
    basis = np.column_stack([np.sin(k * x), np.cos(k * x), np.ones_like(x)])
    coef, *_ = np.linalg.lstsq(basis, eta, rcond=None)
    resid = eta - basis @ coef
    return coef, float(resid @ resid)


def steady_wave(x: np.ndarray, eta: np.ndarray, k_guess: float, x0: float = 0.0) -> dict:
    """Fit :math:`\\bar\\eta + A\\sin(k(x - x_0) + \\varphi)` to a surface profile ``eta(x)``;
    ``k`` searched within 30 % of ``k_guess``. Returns wavenumber, wavelength, amplitude,
    phase (rad), mean and the rms residual (m)."""
    xs = np.asarray(x, dtype=float) - x0
    eta = np.asarray(eta, dtype=float)
    res = minimize_scalar(lambda k: _fit_at(k, xs, eta)[1],
                          bounds=(0.7 * k_guess, 1.3 * k_guess), method="bounded",
                          options={"xatol": 1e-6 * k_guess})
    k = float(res.x)
    (s, c, mean), ss = _fit_at(k, xs, eta)
    return dict(wavenumber=k, wavelength=2 * math.pi / k, amplitude=math.hypot(s, c),
                phase=math.atan2(c, s), mean=mean, rms_residual=math.sqrt(ss / len(xs)))


def havelock_comparison(ds: xr.Dataset, window=(0.5, 1.5), t_average: float = 0.5) -> dict:
    """The steady wave of a ``cylinder_in_current`` run against linear theory.

    ``window``: the gauges from ``window[0]`` to ``window[1]`` theoretical wave lengths
    behind the cylinder's centre (by default one wave length from 0.5, which is 1.6 f at
    F = 0.7: clear of the cylinder's local disturbance, and the part of the train that
    settles first behind its front); ``t_average``: the time mean over the last this many
    seconds. Returns the fit of :func:`steady_wave` and the ratios of its wave length and
    amplitude to the theory's (``wavelength_ratio``, ``amplitude_ratio``)."""
    a = ds.attrs
    lam, amp = a["theory_wavelength"], a["theory_amplitude"]
    names, x = gauge_positions(ds)
    xc = a["cylinder_x"]
    sel = (x >= xc + window[0] * lam) & (x <= xc + window[1] * lam)
    t = ds["time"].values
    late = t >= t[-1] - t_average
    eta = ds["probe_elevation"].sel(probe=list(names[sel])).values[:, late].mean(axis=1)
    fit = steady_wave(x[sel], eta, a["theory_wavenumber"], xc)
    fit.update(theory_wavelength=lam, theory_amplitude=amp, froude=a["froude"],
               wavelength_ratio=fit["wavelength"] / lam, amplitude_ratio=fit["amplitude"] / amp,
               n_gauges=int(sel.sum()), x_from=float(x[sel][0]), x_to=float(x[sel][-1]))
    return fit
