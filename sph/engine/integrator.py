r"""Time integration: the two-level Verlet (leapfrog) scheme with one force evaluation per step.

After Monaghan (1989) as used in DualSPHysics (Crespo et al. 2015): with derivatives
:math:`\mathbf{a}^n, \dot\rho^n` evaluated at :math:`(\mathbf{x}^n, \mathbf{v}^n, \rho^n)`,

.. math::
    \mathbf{x}^{n+1} = \mathbf{x}^n + \Delta t\,\mathbf{v}^n + \tfrac12\Delta t^2\mathbf{a}^n,\quad
    \mathbf{v}^{n+1} = \mathbf{v}^{n-1} + 2\Delta t\,\mathbf{a}^n,\quad
    \rho^{n+1} = \rho^{n-1} + 2\Delta t\,\dot\rho^n .

This is centred in time (second order, neutrally stable for oscillations). Every
``euler_interval`` steps the leapfrog levels are re-coupled by one forward step
(:math:`\mathbf{v}^{n+1} = \mathbf{v}^n + \Delta t\,\mathbf{a}^n`), which removes the
scheme's computational mode; with the MLS filter this step coincides with the
re-initialisation so that both levels carry the filtered density.

The time step combines the acoustic, force and viscous limits:

.. math:: \Delta t = C\,\min\left(\frac{h}{c_0 + |\mathbf{v}|_{max}},
          \sqrt{\frac{h}{|\mathbf{a}|_{max}}}, \frac{h}{\alpha c_0}\right).
"""

from __future__ import annotations

import math

from numba import prange

from sph.engine.absorber import AB_FORM, AB_STREAM, sigma
from sph.engine.jit import JIT, JIT_PARALLEL, njit
from sph.engine.particles import FLUID


@njit(**JIT)
def max_speed_accel(vx, vz, ax, az, kind):
    """Largest fluid speed and acceleration magnitude."""
    v2 = 0.0
    a2 = 0.0
    for i in range(vx.shape[0]):
        if kind[i] != FLUID:
            continue
        s = vx[i] * vx[i] + vz[i] * vz[i]
        if s > v2:
            v2 = s
        s = ax[i] * ax[i] + az[i] * az[i]
        if s > a2:
            a2 = s
    return math.sqrt(v2), math.sqrt(a2)


def time_step(cfl: float, h: float, c0: float, alpha: float, vmax: float, amax: float) -> float:
    """Stable time step from the acoustic CFL, force and viscous conditions."""
    dt = h / (c0 + vmax)
    if amax > 0.0:
        dt = min(dt, math.sqrt(h / amax))
    if alpha > 0.0:
        dt = min(dt, h / (alpha * c0))
    return cfl * dt


@njit(**JIT_PARALLEL)
def verlet_update(x, z, vx, vz, rho, vx_old, vz_old, rho_old, ax, az, drho, kind, dt, euler,
                  ab):
    """Advance fluid particles one step (see module docstring); walls are left alone.

    ``ab`` describes the absorbing zone (:mod:`sph.engine.absorber`); its damping of the
    velocity relative to the stream ``(ab[AB_STREAM], 0)`` is applied implicitly to the new
    velocity."""
    half_dt2 = 0.5 * dt * dt
    dt_eff = dt if euler else 2.0 * dt
    for i in prange(x.shape[0]):
        if kind[i] != FLUID:
            continue
        x[i] += dt * vx[i] + half_dt2 * ax[i]
        z[i] += dt * vz[i] + half_dt2 * az[i]
        if euler:
            nvx = vx[i] + dt * ax[i]
            nvz = vz[i] + dt * az[i]
            nrho = rho[i] + dt * drho[i]
        else:
            nvx = vx_old[i] + 2.0 * dt * ax[i]
            nvz = vz_old[i] + 2.0 * dt * az[i]
            nrho = rho_old[i] + 2.0 * dt * drho[i]
        if ab[AB_FORM] != 0.0:
            u0 = ab[AB_STREAM]
            s = sigma(x[i], nvx - u0, ab)
            if s != 0.0:  # inside the zone
                fac = 1.0 / (1.0 + dt_eff * s)
                nvx = u0 + (nvx - u0) * fac
                nvz *= fac
        vx_old[i] = vx[i]
        vz_old[i] = vz[i]
        rho_old[i] = rho[i]
        vx[i] = nvx
        vz[i] = nvz
        rho[i] = nrho
