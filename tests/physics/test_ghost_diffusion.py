"""The ghosts' density exchange (:func:`sph.engine.refinement.ghost_diffusion`): an active
particle among ghosts relaxes towards their density at the rate of the delta-SPH diffusive
term, a hydrostatic column exchanges nothing, and neither does an active neighbour or a
ghost of weight 0.

For a particle whose kernel is full of ghosts of one density, the term is
``delta h c0 * 2 * sum_g V_g (-F_ig) * (rho_g - rho_i)``. Over a full kernel
``integral (-F) dA = 2 / h**2`` (the Gaussian's ``F = -2 alpha / h**2 exp(-q**2)``,
``alpha = 1 / (pi h**2)``); on a lattice of spacing dx the sum over the neighbours is that
less the particle's own place, ``dx**2 (-F(0)) = 2 dx**2 / (pi h**4)``, so
``d rho_i / dt = 4 delta c0 / h * (1 - dx**2 / (pi h**2)) * (rho_g - rho_i)``: a time of
about ``h / (3.2 delta c0)``, 4.5 ms for the refined ship's finest level.
"""

import numpy as np
import pytest
from physics_helpers import sort_by_cells

from sph.engine.kernels import kernel_params
from sph.engine.neighbours import CellGrid, NeighbourList
from sph.engine.opening import no_opening
from sph.engine.particles import FLUID, GHOST
from sph.engine.refinement import ghost_diffusion
from sph.engine.walls import fixed_kinematics, listed_with

DX = 0.1
H = 1.23 * DX
C0 = 50.0
DELTA = 0.1
RHO0 = 1000.0
G = 9.81


def _patch(body_of_others, rho_of, gw_of_others=1.0, hs=1.0, keep=None):
    """A 21 x 21 lattice with the particle at its centre active and the others ``body``
    ``body_of_others`` (a ghost or active fluid, or a function of ``(x, z)`` giving it),
    densities ``rho_of(x, z)`` (the centre's then set by the caller), the ghosts' weights
    ``gw_of_others``, only the particles where ``keep(x, z)`` (default all); returns the
    arrays sorted by cells, the index of the centre particle and the lists."""
    n1 = 21
    g = (np.arange(n1) - n1 // 2) * DX * hs
    x, z = (a.ravel() for a in np.meshgrid(g, g))
    if keep is not None:
        x, z = x[keep(x, z)], z[keep(x, z)]
    n = x.size
    body = (np.asarray(body_of_others(x, z), np.int32) if callable(body_of_others)
            else np.full(n, body_of_others, np.int32))
    centre = np.argmin(x * x + z * z)
    body[centre] = -1
    pid = np.arange(n)
    span = 1.2 * n1 * DX * hs
    support = 3.0 * H
    grid = CellGrid(-span, span, -span, span, support * hs)
    x, z, body, pid = sort_by_cells(grid, x, z, body, pid)
    i = int(np.nonzero(pid == centre)[0][0])
    rho = rho_of(x, z)
    m = RHO0 * (DX * hs) ** 2 * np.ones(n)
    kind = np.full(n, FLUID, np.int32)
    hsa = np.full(n, hs)
    nl = NeighbourList()
    nl.build(x, z, kind, grid, support, hsa)
    nl.refresh(x, z, support, hsa)
    gw = np.where(body == GHOST, gw_of_others, 1.0)
    return x, z, rho, m, kind, body, np.zeros(n, np.int32), hsa, gw, i, nl


def _rate(x, z, rho, m, kind, body, comp, hs, gw, i, nl, gz=0.0):
    drho = np.zeros(x.size)
    near = np.zeros(x.size, np.bool_)  # the active particles with a ghost in their list
    listed_with(kind, body, nl.start, nl.inner, nl.inner_end, None, near)
    assert near[i] == np.any(body == GHOST)
    ghost_diffusion(x, z, rho, m, kind, body, comp, hs, kernel_params("gaussian", H),
                    no_opening(), fixed_kinematics(1), nl.start, nl.inner, nl.inner_end, near,
                    gw, DELTA * H * C0, 0.0, -RHO0 / C0**2 * gz, drho)
    others = np.arange(x.size) != i
    assert np.all(drho[others & (body == GHOST)] == 0.0)  # a ghost's rate is not its own
    return drho[i]


@pytest.mark.parametrize("hs", [1.0, 0.25])
def test_a_particle_among_ghosts_relaxes_at_the_diffusive_rate(hs):
    """Ghosts at 1000 kg/m3 around a particle at 1050: the lattice's closed-form rate
    ``4 delta c0 / (hs h) * (1 - dx**2 / (pi h**2)) * (rho_g - rho_i)`` (module docstring),
    at either level (the pair's smoothing length and spacing are the level's)."""
    x, z, rho, m, kind, body, comp, hsa, gw, i, nl = _patch(GHOST, lambda x, z: 0 * x + RHO0,
                                                            hs=hs)
    rho[i] = 1050.0
    want = 4.0 * DELTA * C0 / (hs * H) * (1.0 - DX**2 / (np.pi * H**2)) * (RHO0 - rho[i])
    got = _rate(x, z, rho, m, kind, body, comp, hsa, gw, i, nl)
    assert got == pytest.approx(want, rel=0.003)


def test_only_the_ghosts_among_active_neighbours_count():
    """Every other site a ghost at 1000 kg/m3, the others active at 1100: the particle at
    1050 relaxes towards the ghosts, at the rate of the same ghosts with the active
    particles taken away (to round-off), not towards the active particles' density."""
    def even(x, z):
        return (np.rint(x / DX) + np.rint(z / DX)) % 2 == 0

    mixed = _patch(lambda x, z: np.where(even(x, z), GHOST, -1),
                   lambda x, z: np.where(even(x, z), RHO0, 1100.0))
    alone = _patch(GHOST, lambda x, z: 0 * x + RHO0, keep=even)
    for case in (mixed, alone):
        case[2][case[9]] = 1050.0
    got, want = _rate(*mixed), _rate(*alone)
    assert want < 0.0
    assert got == pytest.approx(want, rel=1e-12)


def test_active_neighbours_and_weightless_ghosts_exchange_nothing():
    """The same particle among active fluid, or among ghosts of weight 0 (fitted from a
    nearly empty kernel): no term (the fluid's pairs are the list loops'; such a ghost is
    not fluid that is there)."""
    for body, w in ((-1, 1.0), (GHOST, 0.0)):
        x, z, rho, m, kind, b, comp, hsa, gw, i, nl = _patch(body, lambda x, z: 0 * x + RHO0,
                                                             gw_of_others=w)
        rho[i] = 1050.0
        assert _rate(x, z, rho, m, kind, b, comp, hsa, gw, i, nl) == 0.0


def test_a_hydrostatic_column_exchanges_nothing():
    """Ghosts and the particle at the hydrostatic density of their depth, linear in z with
    the slope rho0 g / c0**2: the term subtracts that difference, so nothing moves (to
    round-off), with the ghosts all round or only below it, where the plain difference
    would draw it towards the deeper density; ghosts below denser than hydrostatic raise
    its density. A ghost of another compartment is not in it."""
    def hydro(x, z):
        return RHO0 * (1.0 + G * (2.0 - z) / C0**2)

    scale = 4.0 * DELTA * C0 / H * (RHO0 * G * DX / C0**2)  # a spacing's hydrostatics
    # ghosts below the particle alone (a particle at a free surface, or under a hull whose
    # other side is ghosts): the hydrostatic difference counts at first order
    below = _patch(GHOST, hydro, keep=lambda x, z: z <= 0.0)
    assert abs(_rate(*below, gz=-G)) < 1e-9 * scale
    assert _rate(*below, gz=0.0) > 0.3 * scale  # the plain difference: towards the deeper
    x, z, rho, m, kind, body, comp, hsa, gw, i, nl = _patch(GHOST, hydro)
    assert abs(_rate(x, z, rho, m, kind, body, comp, hsa, gw, i, nl, gz=-G)) < 1e-9 * scale
    rho[z < z[i]] += 5.0  # denser below than hydrostatic: the particle is pulled up towards it
    assert _rate(x, z, rho, m, kind, body, comp, hsa, gw, i, nl, gz=-G) > 0.1 * scale
    comp[:] = 1
    comp[i] = 0
    assert _rate(x, z, rho, m, kind, body, comp, hsa, gw, i, nl, gz=-G) == 0.0
