"""The hydrostatic form of the delta-SPH diffusive term (``numerics.density_filter: ddt``,
:func:`sph.engine.fluid.interact`; Fourtakas et al. 2019).

A block of fluid at rest on a square lattice under gravity. The term must (1) vanish for the
hydrostatic density field, so that a tank at rest stays at rest (the plain Molteni-Colagrossi
form does not: it diffuses the hydrostatic stratification away); (2) conserve mass, the sum
of V_i D_i over all particles being zero (each pair's terms cancel); (3) dissipate a
perturbation of that field: sum of V_i (rho_i - rho_H,i) D_i below zero.
"""

import math

import numpy as np
from physics_helpers import fluid_pair_loop, sort_by_cells

from sph.engine.kernels import kernel_params
from sph.engine.neighbours import CellGrid

DX = 0.1
RHO0 = 1000.0
G = 9.81
N = 24
H = N * DX
C0 = 10.0 * math.sqrt(G * H)


def _rates(rho_field, ddt=True):
    """Density rates of the diffusive term alone (fluid at rest, no pressure) for the
    density ``rho_field(z)`` on the lattice; returns z, rho, volumes, rates."""
    xs, zs = np.meshgrid((np.arange(N) + 0.5) * DX, (np.arange(N) + 0.5) * DX)
    x, z = xs.ravel().copy(), zs.ravel().copy()
    n = len(x)
    kp = kernel_params("gaussian", 1.23 * DX)
    grid = CellGrid(-1.0, 4.0, -1.0, 4.0, math.sqrt(kp[3]))
    x, z = sort_by_cells(grid, x, z)
    rho = rho_field(z)
    m = np.full(n, RHO0 * DX * DX)
    zero = np.zeros(n)
    _, _, drho, _, _ = fluid_pair_loop(x, z, zero, zero, rho, m, grid, kp, gz=-G,
                                       delta_coef=0.1 * kp[1] * C0,
                                       ddt_rho=RHO0 / C0**2 if ddt else 0.0)
    return z, rho, m / rho, drho


def _hydrostatic(z):
    # the Tait law linearised over the column, as the term assumes
    return RHO0 * (1.0 + G * (H - z) / C0**2)


def test_hydrostatic_density_field_is_left_alone():
    _, _, _, drho = _rates(_hydrostatic)
    # each pair's term is zero to round-off; compare with the rate the plain form gives
    _, _, _, plain = _rates(_hydrostatic, ddt=False)
    assert np.max(np.abs(plain)) > 1.0  # kg/m3/s: the plain form smears the stratification
    assert np.max(np.abs(drho)) < 1e-9 * np.max(np.abs(plain))


def test_diffusion_conserves_mass_and_damps_a_perturbation():
    rng = np.random.default_rng(7)
    noise = {}

    def field(z):
        noise["d"] = rng.normal(0.0, 0.5, z.shape)  # kg/m3
        return _hydrostatic(z) + noise["d"]

    z, rho, vol, drho = _rates(field)
    total = np.sum(vol * drho)
    assert abs(total) < 1e-9 * np.sum(vol * np.abs(drho))
    assert np.sum(vol * noise["d"] * drho) < 0.0
    # the perturbation decays at every scale the kernel sees: the rate anticorrelates with it
    assert np.corrcoef(noise["d"], drho)[0, 1] < -0.5
