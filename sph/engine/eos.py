r"""Tait equation of state (Cao et al. 2019, Eq. 4) and its inverse (Eq. 12).

.. math:: P = \frac{c_0^2 \rho_0}{\gamma}\left[\left(\frac{\rho}{\rho_0}\right)^\gamma - 1\right]

The pressure is evaluated once per particle and step (never inside the pair loop). The
exponent :math:`\gamma = 7` is expanded into multiplications.
"""

from __future__ import annotations

import numpy as np
from numba import prange

from sph.engine.jit import JIT, JIT_PARALLEL, njit
from sph.engine.particles import FLUID


@njit(**JIT)
def tait_pressure(rho, rho0, b_coef, gamma):
    """Pressure from density; ``b_coef = c0**2 * rho0 / gamma``."""
    x = rho / rho0
    if gamma == 7.0:
        x2 = x * x
        x4 = x2 * x2
        return b_coef * (x4 * x2 * x - 1.0)
    return b_coef * (x**gamma - 1.0)


@njit(**JIT)
def tait_density(p, rho0, b_coef, gamma):
    """Inverse Tait law (Eq. 12); the base is floored so that a strong tension stays finite."""
    base = p / b_coef + 1.0
    if base < 1.0e-3:
        base = 1.0e-3
    return rho0 * base ** (1.0 / gamma)


@njit(**JIT_PARALLEL)
def fluid_pressures(rho, kind, p, rho0, b_coef, gamma):
    """Fill ``p`` for fluid particles (``kind == FLUID``)."""
    for i in prange(rho.shape[0]):
        if kind[i] == FLUID:
            p[i] = tait_pressure(rho[i], rho0, b_coef, gamma)


def hydrostatic_density(depth_below_surface, rho0, b_coef, gamma, g):
    """Density of a fluid at rest ``depth_below_surface`` metres under a free surface."""
    p = rho0 * g * np.asarray(depth_below_surface, dtype=np.float64)
    return rho0 * (p / b_coef + 1.0) ** (1.0 / gamma)


@njit(**JIT_PARALLEL)
def cavitation_floor(rho, rho_old, kind, rho_min):
    """Raise the density of every fluid particle below ``rho_min`` to it, at both levels of
    the Verlet scheme (``numerics.pressure_floor``, :func:`tait_density` of the floor).

    Water cavitates about one atmosphere below the ambient pressure and holds no larger
    tension; the continuity equation has no such limit. In a splash that spreads, the
    densities of the refined Table I case 5 fell to 0.94 rho0 (-1.3 MPa): the tension
    paired particles and pulled them along at 40-80 m/s. With the pressure alone bounded the
    density kept falling (0.67 rho0 within 0.7 s) and a particle compressed again would
    have had to make that up before it pushed; at the floor it pushes at once."""
    for i in prange(rho.shape[0]):
        if kind[i] == FLUID:
            if rho[i] < rho_min:
                rho[i] = rho_min
            if rho_old[i] < rho_min:
                rho_old[i] = rho_min
