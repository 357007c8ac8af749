r"""Particle shifting: keeps the particle distribution regular where the flow would cluster it.

Weakly compressible SPH tracks density along particle paths. Where particles come close to
each other without the continuity equation seeing them approach, they stay packed at the
reference density and nothing pushes them apart again: a cluster forms whose particles
carry too little pressure for their number density, and once it drifts into open water it
sinks through it (its neighbours do not hold it up), reaching the tank floor at speed. Around
a thin hull this happens where a particle rounds the plating's edge at a damage opening:
the fluid on the other side of the plating comes into view (:mod:`sph.bodies.damage`) already
closer than one particle spacing.

The shifting of Sun et al. (2017, delta-plus-SPH; after Lind et al. 2012) moves every fluid
particle down the gradient of the particle concentration, each step, by

.. math::
    \delta\mathbf{r}_i = -C\,\mathrm{CFL}\,\mathrm{Ma}\,(2h)^2 \sum_j
    \left[1 + R\left(\frac{W_{ij}}{W(\Delta x)}\right)^n\right]\nabla_i W_{ij}\,V_j,
    \qquad R = 0.2,\ n = 4,

with :math:`\mathrm{Ma} = 1/c_{\text{factor}}` (the flow speed the speed of sound was sized
for) and :math:`C` the config value ``numerics.shifting`` (0 disables it). The sum runs over
the neighbours the momentum equation sees (same compartment, through an open damage
opening, wall particles included so that nobody is shifted into a wall). The kernel sum
that decides whether a particle is packed is taken in the momentum equation's pair loop
(:func:`sph.engine.fluid.interact`, one multiply-add per pair); only the packed particles, few in
a regular flow, search their neighbours again for the gradient. Near the free
surface, where the concentration gradient is that of the missing air, only the part of the
shift along the surface is kept (Lind et al. 2012): a particle is taken to be at the surface
when the divergence of the position, :math:`\nabla\cdot\mathbf{r}_i = -\sum_j V_j
\mathbf{r}_{ij}\cdot\nabla_i W_{ij}` (2 inside the fluid), is below 1.5. Shifting acts only where
the particles are packed: the shift is scaled by a gate that is zero while the kernel sum
:math:`\sum_j V_j W_{ij}` is below ``PACKED`` = 1.05 and reaches one 0.1 above it, so that
the regular flow (kernel sum one inside, less at the surface) is left exactly as the
unshifted scheme computes it. A shift is limited to a tenth of the particle spacing per
step. Velocities and densities are not corrected for the shift (first order in
:math:`\delta r`; the density is re-initialised by the MLS filter).
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from sph.engine.jit import JIT, JIT_PARALLEL, njit
from sph.engine.kernels import KP_H, KP_R2MAX, fw_scaled, w_r2
from sph.engine.opening import in_sight_near, near_opening
from sph.engine.particles import FLUID, GHOST

#: anti-clustering weight R and exponent n of Sun et al. (2017)
R_ANTI = 0.2
#: kernel sum above which a particle counts as packed (shifting starts), and the ramp over
#: which the shift reaches its full size
PACKED = 1.05
PACKED_RAMP = 0.1
#: divergence of the position below which a particle is treated as a free-surface particle
SURFACE_DIVR = 1.5

# slots of the packed shifting parameters ``shift`` (:func:`shift_params`)
SH_COEF = 0  #: shifting coefficient (0: off)
SH_W_DX = 1  #: kernel value at one particle spacing
SH_CAP = 2  #: largest shift per step (m)
SH_SIZE = 3


def shifting_coefficient(c: float, cfl: float, c_factor: float, h: float) -> float:
    r""":math:`C\,\mathrm{CFL}\,\mathrm{Ma}\,(2h)^2` with :math:`\mathrm{Ma} = 1/c_{factor}`."""
    return c * cfl / c_factor * (2.0 * h) ** 2


def shift_params(c: float, cfl: float, c_factor: float, kp, dx: float) -> np.ndarray:
    """``[coef, W(dx), cap]`` for :func:`sph.engine.fluid.interact` (``coef = 0``: no shifting);
    ``c`` is ``numerics.shifting``, the cap a tenth of the particle spacing."""
    shift = np.zeros(SH_SIZE)
    shift[SH_COEF] = shifting_coefficient(c, cfl, c_factor, kp[KP_H])
    shift[SH_W_DX] = w_r2(dx * dx, kp)
    shift[SH_CAP] = 0.1 * dx
    return shift


def shifting_active(shift: np.ndarray) -> bool:
    return shift[SH_COEF] != 0.0


@njit(inline="always", **JIT)
def _shift_pair(i, j, xi, zi, ci, x, z, kind, body, comp, hs, r2max, op, kin, near):
    """Whether particle ``j`` counts in :func:`shift_vector`'s sums, with the pair's ``dx,
    dz, r2`` and smoothing length ratio: within the support and seen by the pair rule, not
    ``i`` itself and not a ghost. ``near``: particle ``i`` is within the open opening's
    reach (:func:`sph.engine.opening.near_opening`) and takes the whole pair rule
    (:func:`sph.engine.opening.in_sight`); beyond it the rule is the compartment's alone
    (no pair it begins crosses the opening: :func:`sph.engine.opening.in_sight_near`)."""
    ok, dx, dz, r2, sij = in_sight_near(near, i, j, xi, zi, ci, x, z, kind, body, comp, hs,
                                        r2max, op, kin)
    ok = ok and j != i and not (kind[j] == FLUID and body[j] == GHOST)
    return ok, dx, dz, r2, sij


@njit(inline="always", **JIT)
def _shift_terms(j, dx, dz, r2, sij, rho, m, kp, inv_wdx):
    """Particle ``j``'s terms of :func:`shift_vector`'s sums, for a pair that counts."""
    vj = m[j] / rho[j]
    fw, w = fw_scaled(r2, kp, sij)
    q = w * inv_wdx
    q2 = q * q
    vf = vj * fw
    a = vf * (1.0 + R_ANTI * q2 * q2)
    return a * dx, a * dz, -vf * r2


@njit(inline="always", **JIT)
def _list_shift_sums(i, k0, k1, inner, xi, zi, ci, x, z, rho, m, kind, body, comp, hs, r2max,
                     op, kin, kp, inv_wdx, near, gx, gz, divr):
    """:func:`shift_vector`'s sums ``gx, gz, divr`` carried on over the candidates
    ``inner[k0:k1]`` of particle ``i`` (``inner`` None: the particles ``k0 .. k1 - 1``).
    A pair that does not count is skipped, not added as zeros: a loop whose pair function
    returned zeros for it took about twice as long, to the same sums."""
    for k in range(k0, k1):
        j = k if inner is None else inner[k]
        ok, dx, dz, r2, sij = _shift_pair(i, j, xi, zi, ci, x, z, kind, body, comp, hs,
                                          r2max, op, kin, near)
        if not ok:
            continue
        ax, az, d = _shift_terms(j, dx, dz, r2, sij, rho, m, kp, inv_wdx)
        gx += ax
        gz += az
        divr += d
    return gx, gz, divr


@njit(**JIT)
def shift_vector(i, shep, x, z, rho, m, kind, body, comp, hs, cell_of, cell_start, ncx, kp,
                 op, kin, shift, lists):
    r"""Shift of fluid particle ``i`` whose kernel sum :math:`\sum_j V_j W_{ij}` (itself
    included) is ``shep``; ``shift = [coef, W(dx), cap]``. Zero unless the particle is
    packed; then the concentration gradient and the divergence of the position are summed
    over the neighbours the momentum equation sees. ``lists``: ``(start, inner,
    inner_end)``, the particle's inner list, the candidates to sum over; None: the 3 x 3
    cells of ``cell_of`` (the reference loop), in which a fine particle tests about 25 times
    as many. Under variable resolution the pairs take
    their own smoothing lengths (``hs``, :mod:`sph.engine.refinement`) and the coefficient,
    :math:`W(\Delta x)` and the cap follow the particle's own spacing; the ghosts count
    neither in the kernel sum nor in the gradient: a ghost is fitted, not pushed, and does
    not make way for a particle shifted against it. An active particle of a family made
    coarse inside a finer box, among the ghosts of its level (the finer families' mothers,
    at their children's centres of mass), was shifted by the cap, a tenth of its spacing,
    at every step (0.04 m per step at 1.4 m/s in the refined Table I case 4), and the lists
    were rebuilt every 2-6 steps."""
    gate = min(max((shep - PACKED) / PACKED_RAMP, 0.0), 1.0)
    if gate == 0.0:
        return 0.0, 0.0
    xi = x[i]
    zi = z[i]
    ci = comp[i]
    hsi = hs[i]
    inv_wdx = hsi * hsi / shift[SH_W_DX]  # W(dx_i; h_i) = W(dx; h) / hs_i^2
    r2max = kp[KP_R2MAX]
    gx = 0.0
    gz = 0.0
    divr = 0.0
    if lists is not None:  # (start, inner, inner_end): the inner list of the particle
        start, inner, inner_end = lists
        # a loop of its own for a particle within the open opening's reach and one for
        # the others: with the choice made for every pair it took 2.4 times as long
        if near_opening(xi, zi, op, 0.0):
            gx, gz, divr = _list_shift_sums(i, start[i], inner_end[i], inner, xi, zi, ci, x,
                                            z, rho, m, kind, body, comp, hs, r2max, op, kin,
                                            kp, inv_wdx, True, gx, gz, divr)
        else:
            gx, gz, divr = _list_shift_sums(i, start[i], inner_end[i], inner, xi, zi, ci, x,
                                            z, rho, m, kind, body, comp, hs, r2max, op, kin,
                                            kp, inv_wdx, False, gx, gz, divr)
    else:  # the 3 x 3 cells (the reference loop)
        c = cell_of[i]
        for row in (c - ncx, c, c + ncx):
            gx, gz, divr = _list_shift_sums(i, cell_start[row - 1], cell_start[row + 2], None,
                                            xi, zi, ci, x, z, rho, m, kind, body, comp, hs,
                                            r2max, op, kin, kp, inv_wdx, True, gx, gz, divr)
    coef = shift[SH_COEF] * hsi * hsi
    shx = -coef * gate * gx
    shz = -coef * gate * gz
    if divr < SURFACE_DIVR:
        g2 = gx * gx + gz * gz
        if g2 > 0.0:  # keep the part along the surface (normal ~ concentration gradient)
            dot = (shx * gx + shz * gz) / g2
            shx -= dot * gx
            shz -= dot * gz
    s = math.sqrt(shx * shx + shz * shz)
    cap = shift[SH_CAP] * hsi
    if s > cap:
        shx *= cap / s
        shz *= cap / s
    return shx, shz


@njit(**JIT_PARALLEL)
def apply_shift(x, z, sx, sz, kind):
    for i in prange(x.shape[0]):
        if kind[i] == FLUID:
            x[i] += sx[i]
            z[i] += sz[i]
