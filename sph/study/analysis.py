"""Post-processing used by the tests and the workflow: frequencies, fronts, validation data."""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from sph.bodies.wavemaker import flap_height_to_stroke, group_velocity, wavenumber


def validation_data_dir() -> Path:
    """Folder of the external experimental series.

    ``SPH_VALIDATION_DATA`` if set, else ``data/validation/`` of the repository (one folder
    per source, each with a README giving the citation, provenance and format).
    """
    env = os.environ.get("SPH_VALIDATION_DATA")
    if env:
        return Path(env)
    return Path(__file__).resolve().parents[2] / "data" / "validation"


def read_two_column(path: str | Path, skip: int = 2) -> np.ndarray:
    """Read a whitespace-separated two-column series after ``skip`` header lines."""
    rows = []
    with open(path, encoding="latin-1") as fh:
        for k, line in enumerate(fh):
            if k < skip:
                continue
            parts = line.split()
            if len(parts) >= 2:
                rows.append((float(parts[0]), float(parts[1])))
    return np.array(rows)


def koshizuka_front() -> np.ndarray:
    """Koshizuka & Oka (1996) dam-break front: columns time (s), front x (m)."""
    return read_two_column(validation_data_dir() / "koshizuka1996" /
                           "EXP_X-DamTipPosition_Koshizuka_Oka1996.txt")


def ritter_front(t, x0: float, depth: float, g: float = 9.81):
    """Shallow-water (Ritter) bound on the dam-break front: ``x0 + 2 sqrt(g H) t``."""
    return x0 + 2.0 * math.sqrt(g * depth) * np.asarray(t)


def zero_crossing_period(t, y) -> float:
    """Mean period from the upward zero crossings of ``y - mean(y)`` (linear interpolation)."""
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float) - np.mean(y)
    k = np.nonzero((y[:-1] < 0.0) & (y[1:] >= 0.0))[0]
    if len(k) < 2:
        raise ValueError("fewer than two upward zero crossings: record too short")
    tc = t[k] - y[k] * (t[k + 1] - t[k]) / (y[k + 1] - y[k])
    return float((tc[-1] - tc[0]) / (len(tc) - 1))


def multistart_fit(model, t, y, starts, **kwargs):
    """The parameters of ``model`` fitted to ``(t, y)`` by :func:`scipy.optimize.curve_fit`
    from each start in ``starts`` (keyword arguments passed on), those of least squared
    residual; None when no start converges."""
    from scipy.optimize import curve_fit

    best = None
    for p0 in starts:
        try:
            popt, _ = curve_fit(model, t, y, p0=p0, **kwargs)
        except RuntimeError:
            continue
        res = float(np.sum((model(t, *popt) - y) ** 2))
        if best is None or res < best[0]:
            best = (res, popt)
    return None if best is None else best[1]


def oscillation_frequency(t, y, t_start: float = 0.0) -> tuple[float, float]:
    """Angular frequency (rad/s) and damping ratio of a decaying oscillation.

    Fits :math:`y = c + a e^{-\\zeta\\omega t}\\sin(\\omega_d t + \\varphi)` (scipy
    least squares) to the samples after ``t_start``, starting from the zero-crossing period.
    Returns the damped frequency :math:`\\omega_d` and :math:`\\zeta`.
    """
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    sel = t >= t_start
    t, y = t[sel] - t[sel][0], y[sel]
    w0 = 2.0 * math.pi / zero_crossing_period(t, y)
    c0 = float(np.mean(y))
    a0 = float(np.max(np.abs(y - c0)))

    def model(tt, c, a, w, zeta, phi):
        return c + a * np.exp(-zeta * w * tt) * np.sin(w * tt + phi)

    popt = multistart_fit(model, t, y, [[c0, a0, w0, 0.01, phi0] for phi0 in
                                        np.linspace(0, 2 * math.pi, 8, endpoint=False)],
                          maxfev=5000)
    if popt is None:
        return w0, float("nan")
    return abs(float(popt[2])), float(popt[3])


def spectral_peak(t, y, band: tuple[float, float], pad: int = 16) -> float:
    """Angular frequency (rad/s) of the largest peak of the spectrum of ``y`` (uniformly
    sampled at ``t``, mean removed, Hann window, zero-padded ``pad`` times) within ``band``
    (rad/s). For a damped mode that a multi-mode fit cannot hold apart from a stronger one:
    its peak stays where the mode is while its width grows with its damping."""
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    v = (y - y.mean()) * np.hanning(y.size)
    n = pad * y.size
    spec = np.abs(np.fft.rfft(v, n))
    omega = 2.0 * math.pi * np.fft.rfftfreq(n, (t[-1] - t[0]) / (t.size - 1))
    sel = (omega >= band[0]) & (omega <= band[1])
    if not sel.any():
        raise ValueError(f"no frequency of the record in {band} rad/s")
    return float(omega[sel][np.argmax(spec[sel])])


def decay_modes(t, y, split: float) -> dict:
    """The two modes of a free decay that a frequency ``split`` (rad/s) holds apart, such as
    a loaded ship's roll (a slow mode on the metacentric height that the cargo's free surface
    leaves, and a fast one of ship and cargo moving against each other, above the cargo's
    sloshing frequency ``split``). The slow mode, which carries most of the motion, by a
    damped fit :math:`c + a e^{-\\zeta\\omega t}\\cos(\\omega t + \\varphi)` below ``split``;
    the fast one as the peak of the spectrum of what that fit leaves, between ``split`` and
    three times it (a strongly damped mode that a two-mode fit cannot hold apart; the slow
    mode's own spectrum would bury its peak). Returns ``low`` (omega, damping ratio) and
    ``high`` (omega)."""
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    t = t - t[0]

    def mode(tt, c, a, w, z, p):
        return c + a * np.exp(-z * w * tt) * np.cos(w * tt + p)

    w0 = spectral_peak(t, y, (0.0, split))
    p = multistart_fit(mode, t, y, [[float(y.mean()), 0.5 * float(np.ptp(y)), w0, 0.1, ph]
                                    for ph in np.linspace(0.0, 2.0 * math.pi, 6, endpoint=False)],
                       bounds=([-np.inf, 0.0, 0.0, 0.0, -np.inf],
                               [np.inf, np.inf, split, 1.0, np.inf]), maxfev=20000)
    if p is None:
        raise ValueError("no damped mode fits the record below the split")
    return dict(low=(float(p[2]), float(p[3])),
                high=spectral_peak(t, y - mode(t, *p), (split, 3.0 * split)))


def harmonic_fit(t, y, omega: float) -> tuple[complex, float]:
    """Least-squares fit ``y = c + Re(Z exp(i omega t))``; returns the complex amplitude Z
    and the mean c."""
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    m = np.column_stack([np.ones_like(t), np.cos(omega * t), np.sin(omega * t)])
    (c, a, b), *_ = np.linalg.lstsq(m, y, rcond=None)
    return complex(a, -b), float(c)


def wave_statistics(t, eta, omega: float, window: tuple[float, float]) -> dict:
    """Steady amplitude and period of a regular wave record inside ``window`` (s).

    Returns ``amplitude`` (first-harmonic amplitude, m), ``height`` (mean crest-to-trough
    half range, m), ``period`` (mean zero-up-crossing period, s) and ``mean`` (m).
    """
    t = np.asarray(t, dtype=float)
    eta = np.asarray(eta, dtype=float)
    sel = (t >= window[0]) & (t <= window[1]) & np.isfinite(eta)
    if sel.sum() < 8:
        raise ValueError(f"window {window} holds fewer than 8 samples")
    z, c = harmonic_fit(t[sel], eta[sel], omega)
    return dict(amplitude=abs(z), mean=c, period=zero_crossing_period(t[sel], eta[sel]),
                height=0.5 * float(np.ptp(eta[sel])))


def reflection_coefficient(t, etas, xs, omega: float, k: float,
                           window: tuple[float, float], decay: float = 0.0) -> dict:
    """Separate incident and reflected regular waves from several probes (Mansard & Funke
    1980, least squares over the probes).

    Each probe record is reduced to its complex amplitude :math:`Z_p` at ``omega``; then
    :math:`Z_p = a_I e^{-i k x_p - \beta x_p} + a_R e^{i k x_p + \beta x_p}` is solved for
    :math:`a_I, a_R` in the least-squares sense, where :math:`\beta` = ``decay`` (1/m) is
    the spatial decay rate of a progressive wave (e.g. :func:`viscous_wave_damping` over the
    group velocity for the artificial viscosity of a run): without it, the steady fall of
    the amplitude along the tank is read as part reflection. Needs two probes not separated
    by a multiple of half a wavelength (more, spread over a wavelength, make it robust).

    Returns ``incident`` (amplitude extrapolated to x = 0, m), ``reflected`` (m, at x = 0),
    ``coefficient`` = reflected / incident at the probe farthest along x (where the two
    waves are closest to the reflector; with ``decay`` = 0 the same everywhere) and
    ``residual``: the RMS misfit of the probes' complex amplitudes over ``incident``;
    ``a_incident``, ``a_reflected``: the complex amplitudes at x = 0.
    """
    t = np.asarray(t, dtype=float)
    sel = (t >= window[0]) & (t <= window[1])
    xs = np.asarray(xs, dtype=float)
    z = np.array([harmonic_fit(t[sel], np.asarray(e)[sel], omega)[0] for e in etas])
    a = np.column_stack([np.exp(-1j * k * xs - decay * xs), np.exp(1j * k * xs + decay * xs)])
    (ai, ar), *_ = np.linalg.lstsq(a, z, rcond=None)
    x_ref = float(xs.max())
    coefficient = abs(ar) / abs(ai) * math.exp(2.0 * decay * x_ref)
    residual = float(np.sqrt(np.mean(np.abs(a @ np.array([ai, ar]) - z) ** 2)) / abs(ai))
    return dict(incident=abs(ai), reflected=abs(ar), coefficient=coefficient,
                residual=residual, a_incident=complex(ai), a_reflected=complex(ar))


def artificial_viscosity_nu(alpha: float, h: float, c0: float) -> float:
    """Kinematic viscosity (m2/s) equivalent to the artificial viscosity of
    :mod:`sph.engine.fluid` in 2D: :math:`\\nu = \\alpha h c_0 / 8` (Monaghan 2005, Sec. 4.5; the
    continuum limit of the pair sum uses only the kernel's normalisation, so it holds for
    every kernel with the same ``h``)."""
    return alpha * h * c0 / 8.0


def viscous_wave_damping(nu: float, k: float) -> float:
    """Amplitude decay rate (1/s) of a linear gravity wave of wavenumber ``k`` in a fluid
    of kinematic viscosity ``nu`` with free-slip walls and bottom: :math:`2 \\nu k^2`
    (Lamb 1932, Sec. 348). The potential flow's dissipation :math:`2\\mu\\int e_{ij}
    e_{ij}\\,dV` over its energy gives :math:`4\\nu k^2` for the energy at any depth, for
    progressive and standing waves alike. Divided by the group velocity it is the spatial
    decay rate (1/m) of a progressive wave."""
    return 2.0 * nu * k * k


def flap_wave_record(t, angle, x: float, depth: float, g: float = 9.81,
                     nu: float = 0.0) -> np.ndarray:
    r"""Linear free-surface elevation (m) at ``x`` (m from the hinge) made by a bottom-hinged
    flap that moves through ``angle`` (rad, sampled at the uniform times ``t`` starting from
    rest at ``t[0]``): the wavemaker signalling problem, start-up transient included.

    The stroke at the still-water level :math:`X(t) = h\tan\theta(t)` is split into
    frequencies; each travels as a progressive wave with the flap transfer function of
    :func:`sph.bodies.wavemaker.flap_height_to_stroke` (Dean & Dalrymple: :math:`\eta` leads the
    stroke by a quarter period) and the phase :math:`e^{-ik(\omega)x}` of the dispersion
    relation, so the front of a suddenly started wave train arrives near :math:`x/c_g` with
    the Fresnel-type envelope of linear theory. Evanescent modes are left out (at
    :math:`x = h` they are below 5 % of their size at the flap). With ``nu`` > 0 each
    frequency also loses amplitude at the spatial rate :math:`2\nu k^2 / c_g`
    (:func:`viscous_wave_damping`), the decay that a viscosity, or the artificial viscosity
    of :func:`artificial_viscosity_nu`, gives a progressive wave.

    The record is zero-padded to 16 times its length (at least 4096 s), so that nothing
    wraps round into ``t``. The flap is taken to stop at ``t[-1]``; because the sum of
    progressive waves is not strictly causal near the flap (the evanescent modes left out
    would cancel the difference), that stop shows in the last seconds of the result, by a
    few per cent at x = 0.2 h. Continue the motion past the times of interest
    (:func:`sph.study.validation.linear_wave_record` adds 60 s).
    """

    t = np.asarray(t, dtype=float)
    angle = np.asarray(angle, dtype=float)
    if t.ndim != 1 or t.shape != angle.shape or t.size < 4:
        raise ValueError("t and angle must be 1-D arrays of the same length (4 or more)")
    step = np.diff(t)
    dt = float(step.mean())
    if dt <= 0.0 or np.abs(step - dt).max() > 1.0e-3 * dt:
        raise ValueError("t must be uniformly sampled and increasing")
    n = 1 << int(math.ceil(math.log2(max(16 * t.size, 4096.0 / dt))))
    stroke = np.zeros(n)
    stroke[: t.size] = depth * np.tan(angle)
    spec = np.fft.rfft(stroke)
    omega = 2.0 * np.pi * np.fft.rfftfreq(n, dt)
    gain = np.zeros(omega.size, dtype=complex)
    for i in range(1, omega.size):
        k = wavenumber(omega[i], depth, g)
        decay = 0.0
        if nu > 0.0:
            decay = viscous_wave_damping(nu, k) / group_velocity(omega[i], depth, g) * x
            if decay > 700.0:
                continue
        gain[i] = 1j * flap_height_to_stroke(k * depth) * np.exp(-1j * k * x - decay)
    return np.fft.irfft(spec * gain, n)[: t.size]
