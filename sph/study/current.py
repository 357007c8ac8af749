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


def _basis(k, x):
    """Columns sin kx, cos kx, 1 of the linear least squares of a wave of wavenumber k."""
    return np.column_stack([np.sin(k * x), np.cos(k * x), np.ones_like(x)])


def _window(ds: xr.Dataset, window) -> tuple[np.ndarray, np.ndarray]:
    """Names and abscissae of the gauges from ``window[0]`` to ``window[1]`` theoretical
    wave lengths behind the cylinder's centre."""
    names, x = gauge_positions(ds)
    xc, lam = ds.attrs["cylinder_x"], ds.attrs["theory_wavelength"]
    sel = (x >= xc + window[0] * lam) & (x <= xc + window[1] * lam)
    return names[sel], x[sel]


def _fit_at(k, x, eta):
    basis = _basis(k, x)
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


def averaged(t: np.ndarray, t_average: float | None = None) -> np.ndarray:
    """The outputs of the time mean: the last ``t_average`` seconds, or (None) the run's
    second half, by when the wave train's front (at U / 2 from the cylinder) has passed the
    gauges' window at every Froude number of the sweep; over a run of 12 s that holds about
    one and a half of the slow swings of the wave's amplitude
    (docs/validation/current_tank.md)."""
    t_from = 0.5 * t[-1] if t_average is None else t[-1] - t_average
    return t >= t_from


#: the gauges' window in theoretical wave lengths behind the cylinder's centre: from clear
#: of the near field to where the damping zone starts (:func:`sph.cases.current.tank_for_froude`)
WINDOW = (0.5, 2.0)


def crossing_wavelength(x: np.ndarray, eta: np.ndarray) -> float:
    """Mean wave length of a surface profile from its zero crossings about its mean: the
    distance from each crossing to the next but one, averaged (nan with fewer than three
    crossings). Independent of the wave's shape (a Stokes wave's narrow crests and broad
    troughs) and of a slow change of its amplitude along x, both of which bias a sinusoid
    fitted over one or two wave lengths."""
    y = np.asarray(eta, dtype=float) - np.mean(eta)
    x = np.asarray(x, dtype=float)
    i = np.nonzero(y[:-1] * y[1:] < 0.0)[0]
    cross = x[i] + (x[i + 1] - x[i]) * y[i] / (y[i] - y[i + 1])
    if len(cross) < 3:
        return float("nan")
    return float(np.mean(cross[2:] - cross[:-2]))


def havelock_comparison(ds: xr.Dataset, window=WINDOW, t_average: float | None = None
                        ) -> dict:
    """The steady wave of a ``cylinder_in_current`` run against linear theory.

    ``window``: the gauges from ``window[0]`` to ``window[1]`` theoretical wave lengths
    behind the cylinder's centre (by default :data:`WINDOW`: the whole train between half a
    wave length, clear of the cylinder's near field, and the damping zone, which starts
    two wave lengths behind it in the built-in case and the sweep's tanks; over it linear
    theory's whole surface, :func:`sph.cases.current.havelock_surface`, reads +0.3 % in
    wave length and amplitude, over the first wave length alone +0.8 % and +1.2-1.6 %);
    ``t_average``: the time mean over the last this many seconds, by default over the run's
    second half (:func:`averaged`). Returns the fit of :func:`steady_wave`, the ratios of
    its wave length and amplitude to the theory's (``wavelength_ratio``,
    ``amplitude_ratio``) and the wave length from the zero crossings of the same mean
    surface (:func:`crossing_wavelength`, ``crossing_wavelength_ratio``)."""
    a = ds.attrs
    lam, amp = a["theory_wavelength"], a["theory_amplitude"]
    names, x = _window(ds, window)
    late = averaged(ds["time"].values, t_average)
    eta = ds["probe_elevation"].sel(probe=list(names)).values[:, late].mean(axis=1)
    fit = steady_wave(x, eta, a["theory_wavenumber"], a["cylinder_x"])
    fit.update(theory_wavelength=lam, theory_amplitude=amp, froude=a["froude"],
               wavelength_ratio=fit["wavelength"] / lam, amplitude_ratio=fit["amplitude"] / amp,
               n_gauges=len(names), x_from=float(x[0]), x_to=float(x[-1]),
               crossing_wavelength_ratio=crossing_wavelength(x, eta) / lam)
    return fit


def amplitude_history(ds: xr.Dataset, window=WINDOW) -> dict:
    """The wave's amplitude over the run: at each output, the elevation of the gauges of
    :func:`havelock_comparison`'s ``window`` fitted with the theory's wavenumber held (linear
    least squares in :math:`A\\cos\\varphi, A\\sin\\varphi, \\bar\\eta`; no time mean).
    Shows whether the wave behind the cylinder is steady, and over how long a time mean must
    run to hold whole swings of it. Returns ``time`` (s), ``amplitude_ratio`` (to the
    theory's amplitude), ``phase`` (rad) and ``mean`` (m) arrays."""
    a = ds.attrs
    names, x = _window(ds, window)
    eta = ds["probe_elevation"].sel(probe=list(names)).values  # (gauge, time)
    basis = _basis(a["theory_wavenumber"], x - a["cylinder_x"])
    (s, c, mean), *_ = np.linalg.lstsq(basis, eta, rcond=None)
    return dict(time=ds["time"].values, amplitude_ratio=np.hypot(s, c) / a["theory_amplitude"],
                phase=np.arctan2(c, s), mean=mean)
