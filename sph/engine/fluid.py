r"""Fluid equations: continuity, momentum with gravity and artificial viscosity.

Discrete forms of Cao et al. (2019):

.. math::
    \frac{D\rho_i}{Dt} = \rho_i \sum_j \frac{m_j}{\rho_j}
    (\mathbf{v}_i - \mathbf{v}_j)\cdot\nabla_i W_{ij}
    \quad\text{(Eq. 2)}

.. math::
    \frac{D\mathbf{v}_i}{Dt} = -\sum_j m_j \frac{P_i + P_j}{\rho_i\rho_j}\nabla_i W_{ij}
    + \mathbf{g} + \mathbf{F}_v \quad\text{(Eq. 3)}

.. math::
    \mathbf{F}_v = \alpha h \sum_j m_j \frac{c_i + c_j}{\rho_i + \rho_j}
    \frac{\mathbf{v}_{ij}\cdot\mathbf{r}_{ij}}{r_{ij}^2 + (0.01h)^2}\nabla_i W_{ij}
    \quad\text{(Eq. 5, fluid--fluid pairs only: free slip at walls)}

with :math:`c_i = c_j = c_0`. Against a wall particle the fluid pressure enters as
:math:`\max(P_i, 0)` (and the wall's own extrapolated pressure is clamped at zero,
:func:`sph.engine.walls.wall_pressure`): a wall pushes and never pulls, so fluid in tension
(a vortex core reaching the tank floor under a rolling hull) cannot be drawn through the wall
layers. ``numerics.wall_tension`` chooses another rule (:mod:`sph.engine.surface`: the
second source paper's Eq. 6 clamps the pair's pressure sum for free-surface particles only);
every loop takes the pair's pressure sum as :math:`\max(a_i + P_j, f_i)` with ``(a_i, f_i)``
of :func:`sph.engine.surface.wall_pair_terms`. The optional delta-SPH diffusive term (second
source paper, Eq. 2; Antuono et al. 2010) is added to the continuity equation between fluid
particles:

.. math::
    D_i = \delta h c_0 \sum_j \psi_{ij}\cdot\nabla_i W_{ij} V_j,\qquad
    \psi_{ij} = 2(\rho_j - \rho_i)\frac{\mathbf{r}_j - \mathbf{r}_i}{r_{ij}^2}
    - \left(\langle\nabla\rho\rangle^L_i + \langle\nabla\rho\rangle^L_j\right)

with the renormalised density gradient of :func:`sph.engine.filters.renormalised_density_gradient`.
The ``ddt`` variant (Fourtakas et al. 2019) needs no gradient pass: it
subtracts the hydrostatic density difference of the pair instead,

.. math::
    \psi_{ij} = 2\left(\rho_j - \rho_i - \rho^H_{ji}\right)
    \frac{\mathbf{r}_j - \mathbf{r}_i}{r_{ij}^2},\qquad
    \rho^H_{ji} = -\frac{\rho_0}{c_0^2}\,\mathbf{g}\cdot(\mathbf{r}_i - \mathbf{r}_j)

(the Tait law linearised over a kernel support: the relative error is
:math:`\rho_0 g\,3h / B`, below 1e-3 for every case here), so that a fluid at rest in
hydrostatic balance is left exactly as it is, while noise and the density jumps of a
violent flow are diffused. Like the renormalised form, and unlike a re-initialisation, it
does not reset the density of particles packed closer than their volumes allow.

The loop is a gather over fluid particles (no writes to neighbours, no races); pairs
interact only when their compartment ids match (thin walls), or, for two fluid particles,
when the segment between them passes through an open damage opening (:mod:`sph.bodies.damage`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from sph.engine.jit import JIT, JIT_PAIR, JIT_PARALLEL_PAIR, njit
from sph.engine.kernels import (
    E9,
    KP_ALPHA,
    KP_H,
    KP_INV_H2,
    KP_KIND,
    KP_R2MAX,
    exp_neg,
    fw_scaled,
    w_r2,
)
from sph.engine.opening import in_sight, opening_circle, passable, wall_hidden
from sph.engine.particles import FLUID, GHOST
from sph.engine.shifting import PACKED, SH_COEF, shift_vector
from sph.engine.surface import wall_pair_terms


@njit(inline="always", **JIT)
def _weight(gw, body, j):
    """The weight particle ``j`` acts with: that of a ghost where the ghosts' weights ``gw``
    are given (:func:`sph.engine.refinement.ghost_fields`), 1 otherwise."""
    if gw is None:
        return 1.0
    return gw[j] if body[j] == GHOST else 1.0


@njit(inline="always", **JIT)
def _pair_general(j, dx, dz, r2, vxi, vzi, rhoi, pi, gxi, gzi, vx, vz, rho, p, m, kind, ghost,
                  grx, grz, kp, visc_coef, eps2, gx, gz, ddt_rho, use_delta, s, pwall, pfloor,
                  jw):
    """What particle ``j`` within the support adds to the sums of a fluid particle
    ``(vxi, vzi, rhoi, pi)`` at ``(dx, dz)`` from it: ``(acc_x, acc_z, div, diff, shep)``
    as :func:`_sums_general` returns them. ``s``: the pair's smoothing length over the
    case's (:func:`sph.engine.kernels.pair_scale`; 1 at uniform resolution, where every
    value is that of ``s = 1`` to the last bit); the viscosity, its regularisation ``eps2``
    and the diffusive term scale with it as with ``h``. Against a wall particle the pressure
    sum is ``max(pwall + P_j, pfloor)`` (:func:`sph.engine.surface.wall_pair_terms`).
    ``jw = (w_j, n_x, n_z)``: the weight of a ghost ``j`` (:func:`_weight`), which scales its
    mass, and the unit vector from the fluid particle towards its walls under
    ``numerics.wall_damping`` (:func:`sph.engine.walls.wall_normals`; 0 otherwise): its
    approach along it is damped by the artificial viscosity."""
    fw, w = fw_scaled(r2, kp, s)
    rhoj = rho[j]
    mj = m[j] * jw[0]
    nx, nz = jw[1], jw[2]
    vj = mj / rhoj
    dvx = vxi - vx[j]
    dvz = vzi - vz[j]
    vr = dvx * dx + dvz * dz
    diff = 0.0
    if kind[j] == FLUID:
        psum = pi + p[j]
        if ghost and psum < 0.0:  # a ghost pushes, never pulls (sph.engine.refinement)
            psum = 0.0
        coef = -mj * psum / (rhoi * rhoj)
        coef += s * visc_coef * mj / (rhoi + rhoj) * vr / (r2 + s * s * eps2)
        if ddt_rho != 0.0:
            rho_h = -ddt_rho * (gx * dx + gz * dz)
            diff = -2.0 * s * vj * fw * (rhoj - rhoi - rho_h)
        elif use_delta:
            diff = s * vj * fw * (-2.0 * (rhoj - rhoi)
                                  - ((gxi + grx[j]) * dx + (gzi + grz[j]) * dz))
    else:  # numerics.wall_tension: by default a wall pushes and never pulls
        coef = -mj * max(pwall + p[j], pfloor) / (rhoi * rhoj)
        vn = dvx * nx + dvz * nz  # numerics.wall_damping: closing in along the normal
        if vn > 0.0:
            coef += (s * visc_coef * mj / (rhoi + rhoj) * vn * (dx * nx + dz * nz)
                     / (r2 + s * s * eps2))
    return (coef * fw * dx, coef * fw * dz, vj * vr * fw, diff,
            0.0 if ghost else vj * w)


@njit(**JIT)
def _sums_general(i, x, z, vx, vz, rho, p, m, kind, body, comp, hs, cell_of, cell_start,
                  ncx, kp, visc_coef, gx, gz, ddt_rho, use_delta, grx, grz, op, kin, listed,
                  start, inner, inner_end, pwall, pfloor, gw=None, nxi=0.0, nzi=0.0):
    """Pair sums of fluid particle ``i`` with every rule: compartments, the line of sight
    through an open damage opening, hidden wall layers. Returns ``(acc_x, acc_z, div, diff,
    shep)``: the pair accelerations, the velocity divergence sum, the diffusive sum and the
    kernel sum (itself included).

    The candidates are the particle's inner list ``inner[start[i]:inner_end[i]]`` when
    ``listed`` (:class:`sph.engine.neighbours.NeighbourList`: every particle within the
    support, in cell order), else the three rows of cells around it: the same pairs in
    the same order, so the same sums to the last bit. Each pair takes its own smoothing
    length (``hs``: each particle's over the case's, :func:`_pair_general`)."""
    r2max = kp[KP_R2MAX]
    eps2 = 1.0e-4 * kp[KP_H] * kp[KP_H]
    xi = x[i]
    zi = z[i]
    vxi = vx[i]
    vzi = vz[i]
    rhoi = rho[i]
    pi = p[i]
    ci = comp[i]
    gxi = grx[i] if use_delta else 0.0
    gzi = grz[i] if use_delta else 0.0
    accx = 0.0
    accz = 0.0
    div = 0.0
    diff = 0.0
    hsi = hs[i]
    shep = m[i] / rhoi * w_r2(0.0, kp) / (hsi * hsi)
    c = cell_of[i]
    for seg in range(1 if listed else 3):
        if listed:
            lo = np.int64(start[i])
            hi = np.int64(inner_end[i])
        else:
            row = c + (seg - 1) * ncx
            lo = cell_start[row - 1]
            hi = cell_start[row + 2]
        for k in range(lo, hi):
            j = np.int64(inner[k]) if listed else k
            ok, dx, dz, r2, s = in_sight(i, j, xi, zi, ci, x, z, kind, body, comp, hs, r2max,
                                         op, kin)
            if j == i or not ok:
                continue
            t = _pair_general(j, dx, dz, r2, vxi, vzi, rhoi, pi, gxi, gzi, vx, vz, rho, p, m,
                              kind, body[j] == GHOST, grx, grz, kp, visc_coef, eps2, gx, gz,
                              ddt_rho, use_delta, s, pwall, pfloor,
                              (_weight(gw, body, j), nxi, nzi))
            accx += t[0]
            accz += t[1]
            div += t[2]
            diff += t[3]
            shep += t[4]
    return accx, accz, div, diff, shep


@njit(**JIT)
def _opening_terms(i, x, z, vx, vz, rho, p, m, kind, body, comp, kp, visc_coef, gx, gz,
                   ddt_rho, op, kin, start, inner, inner_end, s, pwall, pfloor, gw=None,
                   nxi=0.0, nzi=0.0):
    """What the damage opening changes in the sums of fluid particle ``i`` (near the open
    opening) over those of its own compartment that the list loops take
    (:func:`_list_sums`): plus the fluid of another compartment seen through the opening
    (:func:`sph.engine.opening.passable`), minus the wall layers of the damaged hull that
    the opening hides (:func:`sph.engine.opening.wall_hidden`). Added to the list sums it
    gives :func:`_sums_general`'s pairs, summed in another order."""
    r2max = kp[KP_R2MAX]
    eps2 = 1.0e-4 * kp[KP_H] * kp[KP_H]
    xi = x[i]
    zi = z[i]
    ci = comp[i]
    accx = 0.0
    accz = 0.0
    div = 0.0
    diff = 0.0
    shep = 0.0
    for k in range(start[i], inner_end[i]):
        j = inner[k]
        dx = xi - x[j]
        dz = zi - z[j]
        r2 = dx * dx + dz * dz
        if r2 >= r2max * s * s or j == i:
            continue
        if kind[j] == FLUID:
            if comp[j] == ci or not passable(xi, zi, x[j], z[j], ci, comp[j], op, kin):
                continue
            sign = 1.0
        else:
            if comp[j] != ci or not wall_hidden(xi, zi, x[j], z[j], body[j], op, kin):
                continue
            sign = -1.0
        t = _pair_general(j, dx, dz, r2, vx[i], vz[i], rho[i], p[i], 0.0, 0.0, vx, vz, rho,
                          p, m, kind, body[j] == GHOST, rho, rho, kp, visc_coef, eps2, gx, gz,
                          ddt_rho, False, s, pwall, pfloor, (_weight(gw, body, j), nxi, nzi))
        accx += sign * t[0]
        accz += sign * t[1]
        div += sign * t[2]
        diff += sign * t[3]
        shep += sign * t[4]
    return accx, accz, div, diff, shep


#: columns of the pair data (:func:`pack_pair_data`)
PK_X, PK_Z, PK_VX, PK_VZ, PK_RHO, PK_P, PK_VOL, PK_MFLUID = range(8)
PAIR_FIELDS = 8


def pair_work(n: int) -> np.ndarray:
    """A work array for the pair data of ``n`` particles (:func:`pack_pair_data`)."""
    return np.empty((n, PAIR_FIELDS))


@njit(**JIT_PARALLEL_PAIR)
def pack_pair_data(x, z, vx, vz, rho, p, m, kind, body, pk, gw=None):
    """Copy what a pair reads of its neighbour into one row per particle, 64 bytes: position,
    velocity, density, pressure, volume ``m / rho`` and the mass of a fluid particle (0 for
    a wall particle). A pair then loads one cache line instead of one from each of nine
    arrays: the list loops took about 0.88 times as long on the damaged ship. A ghost's
    volume and mass are scaled by its weight (``gw``, :func:`_weight`)."""
    for j in prange(x.shape[0]):
        pk[j, PK_X] = x[j]
        pk[j, PK_Z] = z[j]
        pk[j, PK_VX] = vx[j]
        pk[j, PK_VZ] = vz[j]
        pk[j, PK_RHO] = rho[j]
        pk[j, PK_P] = p[j]
        wj = _weight(gw, body, j)
        pk[j, PK_VOL] = wj * m[j] / rho[j]
        if kind[j] != FLUID or wj == 0.0:  # a ghost of weight 0 adds nothing
            pk[j, PK_MFLUID] = 0.0
        else:  # a ghost's mass is stored negated: it pushes and never pulls
            pk[j, PK_MFLUID] = -wj * m[j] if body[j] == GHOST else m[j]


def _list_sums(wendland: bool, diffusion: bool, ghosts: bool, damping: bool):
    """The pair sums of :func:`_sums_general` for a fluid particle that cannot see through
    a damage opening, over its inner list ``inner[k0:k1]``
    (:meth:`sph.engine.neighbours.NeighbourList.refresh`: the particles within the support
    plus a thin skin, itself included; the self pair adds its kernel value to the kernel
    sum and nothing else), with no branch: a pair beyond the support or in another
    compartment is masked (its kernel gradient and kernel value are zero, so it adds
    zeros: the sums are those over the neighbours alone, up to the grouping of the
    additions, which the compiler may split by position in the list). ``pk``: the pair
    data (:func:`pack_pair_data`); ``hx dx + hz dz`` is the hydrostatic density difference
    of the ``ddt`` diffusive term (0: none).

    One loop per kernel (``wendland``), per density filter (``diffusion`` adds the
    diffusive term; without it, MLS or no filter, ``diff`` is 0) and for variable resolution
    (``ghosts``: a ghost's mass is stored negated, and its pressure sum with the particle
    counts only when it pushes), and with or without the wall damping (``damping``: the
    particle has walls and a wall normal, ``nxi, nzi``, under ``numerics.wall_damping``).
    The choices are constants of the compiled loop, not tests in it: one loop with the
    kernel chosen per pair took about 1.5 times as long on the damaged ship, the ghosts'
    test in every loop 1.03 times, and the damping's test 1.15-1.3 times, whether it damped
    or not.
    """

    @njit(inline="always", **JIT_PAIR)
    def sums(i, k0, k1, inner, pk, comp, kp, visc_coef, hx, hz, s, pwall, pfloor, nxi, nzi):
        h2 = kp[KP_H] * kp[KP_H] * s * s
        r2max = kp[KP_R2MAX] * s * s
        eps2 = 1.0e-4 * h2
        inv_h2 = kp[KP_INV_H2] / (s * s)
        alpha = kp[KP_ALPHA] / (s * s)
        visc = visc_coef * s
        fg = -2.0 * alpha * inv_h2  # Gaussian: F = fg exp(-q^2)
        wg = alpha * E9  # Gaussian: W = -F h^2 / 2 - alpha e^-9
        fwend = -5.0 * alpha * inv_h2  # Wendland: F = fwend t^3, t = 1 - q/2
        xi = pk[i, PK_X]
        zi = pk[i, PK_Z]
        vxi = pk[i, PK_VX]
        vzi = pk[i, PK_VZ]
        rhoi = pk[i, PK_RHO]
        inv_rhoi = 1.0 / rhoi
        pi = pk[i, PK_P]
        ci = comp[i]
        accx = 0.0
        accz = 0.0
        div = 0.0
        diff = 0.0
        shep = 0.0
        for k in range(k0, k1):
            j = inner[k]
            dx = xi - pk[j, PK_X]
            dz = zi - pk[j, PK_Z]
            r2 = dx * dx + dz * dz
            pair = (r2 < r2max) & (comp[j] == ci)
            if wendland:
                q = math.sqrt(r2 * inv_h2)
                t = 1.0 - 0.5 * q
                t2 = t * t
                fw = (fwend if pair else 0.0) * t2 * t
            else:
                fw = (fg if pair else 0.0) * exp_neg(min(r2 * inv_h2, 9.0))
            pj = pk[j, PK_P]
            mj = pk[j, PK_MFLUID]
            fluid = mj != 0.0
            # numerics.wall_tension: max(pwall + pj, pfloor) against a wall particle
            psum = pi + pj if fluid else max(pwall + pj, pfloor)
            counted = pair  # in the kernel sum (shifting's gate): not a ghost
            if ghosts and mj < 0.0:  # a ghost: pushes and never pulls
                mj = -mj
                psum = max(psum, 0.0)
                counted = False
            vj = pk[j, PK_VOL]
            rhoj = pk[j, PK_RHO]
            vr = (vxi - pk[j, PK_VX]) * dx + (vzi - pk[j, PK_VZ]) * dz
            div += vj * vr * fw
            coef = -psum * vj * inv_rhoi
            if damping:  # numerics.wall_damping: a wall's approach along the normal
                vn = (vxi - pk[j, PK_VX]) * nxi + (vzi - pk[j, PK_VZ]) * nzi
                # a select, not a branch, so that the loop stays vectorised: fluid pairs
                # and walls moving away add 0, and each pair has one of the two terms
                # (walls: mj = 0), so one division serves both
                vn = 0.0 if fluid else max(vn, 0.0)
                coef += ((visc * mj * vr + visc * vj * rhoj * vn * (dx * nxi + dz * nzi))
                         / ((rhoi + rhoj) * (r2 + eps2)))
            else:
                coef += visc * mj * vr / ((rhoi + rhoj) * (r2 + eps2))  # walls: mj = 0
            accx += coef * fw * dx
            accz += coef * fw * dz
            if diffusion:
                d = -2.0 * s * vj * fw * (rhoj - rhoi - hx * dx - hz * dz)
                diff += d if fluid else 0.0
            if wendland:
                w = vj * alpha * t2 * t2 * (2.0 * q + 1.0)
            else:
                w = vj * (-0.5 * h2 * fw - wg)
            shep += w if counted else 0.0
        return accx, accz, div, diff, shep

    return sums


def _list_loop(ghosts: bool, damping: bool):
    """One call for the four list loops of :func:`_list_sums` with or without ``ghosts``
    (variable resolution) and the wall ``damping``: ``sums(gauss, diffusion, i, k0, ...)``
    picks the kernel's and the density filter's loop."""
    gauss_diff = _list_sums(wendland=False, diffusion=True, ghosts=ghosts, damping=damping)
    gauss = _list_sums(wendland=False, diffusion=False, ghosts=ghosts, damping=damping)
    wend_diff = _list_sums(wendland=True, diffusion=True, ghosts=ghosts, damping=damping)
    wend = _list_sums(wendland=True, diffusion=False, ghosts=ghosts, damping=damping)

    @njit(inline="always", **JIT_PAIR)
    def sums(gaussian, diffusion, i, k0, k1, inner, pk, comp, kp, visc_coef, hx, hz, s,
             pwall, pfloor, nxi, nzi):
        if gaussian and diffusion:
            return gauss_diff(i, k0, k1, inner, pk, comp, kp, visc_coef, hx, hz, s, pwall,
                              pfloor, nxi, nzi)
        if gaussian:
            return gauss(i, k0, k1, inner, pk, comp, kp, visc_coef, hx, hz, s, pwall, pfloor,
                         nxi, nzi)
        if diffusion:
            return wend_diff(i, k0, k1, inner, pk, comp, kp, visc_coef, hx, hz, s, pwall,
                             pfloor, nxi, nzi)
        return wend(i, k0, k1, inner, pk, comp, kp, visc_coef, hx, hz, s, pwall, pfloor, nxi,
                    nzi)

    return sums


_sums_uniform = _list_loop(ghosts=False, damping=False)
_sums_variable = _list_loop(ghosts=True, damping=False)
# numerics.wall_damping, for the particles with walls: a loop of its own (a test for the
# damping in the loop, compiled for arrays of normals, cost every particle its
# vectorisation); the variants of :func:`interact` inline them only where normals are passed
_sums_uniform_damped = _list_loop(ghosts=False, damping=True)
_sums_variable_damped = _list_loop(ghosts=True, damping=True)


def _interact_variant(gaussian: bool, diffusion: bool, variable: bool):
    """The compiled body of :func:`interact` for one kernel (``gaussian``), with or without
    the diffusive term (``diffusion``) and at uniform or variable resolution (``variable``).

    The three are constants of the compiled code: numba drops the branches on them before
    it inlines the list loops, so that each variant compiles the one list loop it runs (and
    its damped twin where wall normals are passed), not all eight; a variant without the
    diffusive term also drops the general sums. The closure holds only these three flags,
    so that numba's cache tells the variants apart by them (a closure over a compiled
    function would be keyed by that function's per-process identity and never be found
    again)."""

    @njit(**JIT_PARALLEL_PAIR)
    def interact_variant(x, z, vx, vz, rho, p, m, kind, body, comp, hs, cell_of, cell_start,
                         ncx, kp, visc_coef, gx, gz, delta_coef, ddt_rho, grx, grz, ax, az,
                         drho, op, kin, shift, sx, sz, pk, start, inner, inner_end, tension,
                         surf, gw, wnx, wnz):
        n = x.shape[0]
        pack_pair_data(x, z, vx, vz, rho, p, m, kind, body, pk, gw)
        hx = -ddt_rho * gx  # hydrostatic density difference of a pair: hx dx + hz dz
        hz = -ddt_rho * gz
        ocx, ocz, or2 = opening_circle(op, 0.0)  # near_opening, taken once
        for k in prange(n):
            # numba types a prange index as int64 here and as uint64 in the parallel loop
            # it builds: the callees below would be compiled for both
            i = np.int64(k)
            if kind[i] != FLUID or body[i] == GHOST:  # a ghost's rates are not used
                continue
            pwall, pfloor = wall_pair_terms(p[i], tension, surf, i)
            nxi = 0.0 if wnx is None else wnx[i]
            nzi = 0.0 if wnz is None else wnz[i]
            # the renormalised diffusive term (it needs grx, grz) sums every pair the
            # general way
            if diffusion and ddt_rho == 0.0:
                accx, accz, div, diff, shep = _sums_general(
                    i, x, z, vx, vz, rho, p, m, kind, body, comp, hs, cell_of, cell_start,
                    ncx, kp, visc_coef, gx, gz, ddt_rho, diffusion, grx, grz, op, kin, True,
                    start, inner, inner_end, pwall, pfloor, gw, nxi, nzi)
            else:
                k0 = start[i]
                k1 = inner_end[i]
                # every pair of a list is of the particle's own level (pair_scale)
                s = hs[i] if variable else 1.0
                # numerics.wall_damping: a particle with walls in reach takes the damped
                # loop. Numba drops a branch on "wnx is not None" before it inlines the
                # loops when wnx is None (not when it is an array: then the test stays, and
                # holds), so that a run without the damping compiles no damped loop
                damped = nxi != 0.0 or nzi != 0.0
                if wnx is not None and damped and variable:
                    accx, accz, div, diff, shep = _sums_variable_damped(
                        gaussian, diffusion, i, k0, k1, inner, pk, comp, kp, visc_coef, hx,
                        hz, s, pwall, pfloor, nxi, nzi)
                elif wnx is not None and damped:
                    accx, accz, div, diff, shep = _sums_uniform_damped(
                        gaussian, diffusion, i, k0, k1, inner, pk, comp, kp, visc_coef, hx,
                        hz, s, pwall, pfloor, nxi, nzi)
                elif variable:
                    accx, accz, div, diff, shep = _sums_variable(
                        gaussian, diffusion, i, k0, k1, inner, pk, comp, kp, visc_coef, hx,
                        hz, s, pwall, pfloor, nxi, nzi)
                else:
                    accx, accz, div, diff, shep = _sums_uniform(
                        gaussian, diffusion, i, k0, k1, inner, pk, comp, kp, visc_coef, hx,
                        hz, s, pwall, pfloor, nxi, nzi)
                if (x[i] - ocx) * (x[i] - ocx) + (z[i] - ocz) * (z[i] - ocz) <= or2:
                    t = _opening_terms(i, x, z, vx, vz, rho, p, m, kind, body, comp, kp,
                                       visc_coef, gx, gz, ddt_rho, op, kin, start, inner,
                                       inner_end, s, pwall, pfloor, gw, nxi, nzi)
                    accx += t[0]
                    accz += t[1]
                    div += t[2]
                    diff += t[3]
                    shep += t[4]
            _finish(i, accx, accz, div, diff, shep, x, z, rho, m, kind, body, comp, hs,
                    cell_of, cell_start, ncx, kp, gx, gz, delta_coef, ax, az, drho, op, kin,
                    shift, sx, sz, (start, inner, inner_end))

    return interact_variant


#: the compiled variants of :func:`interact`, by (Gaussian kernel, diffusive term, variable
#: resolution); numba compiles each on its first call
_INTERACT = {(gaussian, diffusion, variable): _interact_variant(gaussian, diffusion, variable)
             for gaussian in (False, True) for diffusion in (False, True)
             for variable in (False, True)}


def interact(x, z, vx, vz, rho, p, m, kind, body, comp, hs, cell_of, cell_start, ncx, kp,
             visc_coef, gx, gz, delta_coef, ddt_rho, grx, grz, ax, az, drho, op, kin, shift,
             sx, sz, pk, start, inner, inner_end, variable, tension, surf, gw, wnx, wnz):
    r"""Accelerations ``ax, az``, density rates ``drho`` and, when shifting is on, the
    particle shifts ``sx, sz`` (:mod:`sph.engine.shifting`) of all fluid particles.

    Under the renormalised diffusive term every fluid particle takes every pair rule at
    every particle of its inner list within the support (:func:`_sums_general`). Otherwise
    every fluid particle sums over its inner list
    ``inner[start[i]:inner_end[i]]`` (:class:`sph.engine.neighbours.NeighbourList`) with
    the kernel's own loop (:func:`_list_sums`), in the same order, the pairs of its own
    compartment; one within reach of an open damage opening adds what the opening
    changes (:func:`_opening_terms`). Under variable resolution (``variable``,
    :mod:`sph.engine.refinement`) a list holds the particle's own level only, so its loop
    takes the level's smoothing length ``hs[i] h`` for every pair.
    :func:`interact_reference` sums every particle the general way.

    Parameters
    ----------
    visc_coef : float
        :math:`2 \alpha h c_0` (zero disables viscosity).
    delta_coef : float
        :math:`\delta h c_0` (zero disables the diffusive term; then ``grx, grz`` are unused).
    ddt_rho : float
        :math:`\rho_0 / c_0^2` for the hydrostatic (``ddt``) form of the diffusive term;
        zero selects the renormalised form (``grx, grz``).
    grx, grz : arrays
        Renormalised density gradient of each particle (delta-SPH only).
    op, kin : arrays
        Damage opening (:mod:`sph.bodies.damage`) and body kinematics (:mod:`sph.engine.walls`).
    shift : array
        ``[coef, W(dx), cap]`` of :func:`sph.engine.shifting.shift_params`; ``coef = 0`` disables
        shifting and leaves ``sx, sz`` untouched. The kernel sum that decides whether a
        particle is packed is taken in this pair loop; only packed particles search their
        neighbours again for the shift (:func:`sph.engine.shifting.shift_vector`).
    pk : array
        Work array for the pair data, ``(n, PAIR_FIELDS)`` (:func:`pair_work`; filled here by
        :func:`pack_pair_data`).
    start, inner, inner_end : arrays
        The inner lists (:class:`sph.engine.neighbours.NeighbourList`).
    tension : int
        The rule of ``numerics.wall_tension`` for the pressure sum of a fluid and a wall
        particle (:data:`sph.engine.surface.WALL_TENSION`; ``CLAMP``, the key's default:
        a wall never pulls).
    surf : bool array or None
        The free-surface flags (:func:`sph.engine.surface.free_surface`) under
        ``FREE_SURFACE``; None otherwise.
    gw : array or None
        Under variable resolution, the weight each ghost acts with
        (:func:`sph.engine.refinement.ghost_fields`): its mass and volume in every pair are
        scaled by it. None: every ghost acts fully.
    wnx, wnz : arrays or None
        Under ``numerics.wall_damping``, the unit vector from each fluid particle towards
        its walls (:func:`sph.engine.walls.wall_normals`): the artificial viscosity damps
        its approach along it, the flow along the wall is left free. None: no damping.
    """
    _INTERACT[bool(kp[KP_KIND] == 0.0), bool(delta_coef != 0.0), bool(variable)](
        x, z, vx, vz, rho, p, m, kind, body, comp, hs, cell_of, cell_start, ncx, kp, visc_coef,
        gx, gz, delta_coef, ddt_rho, grx, grz, ax, az, drho, op, kin, shift, sx, sz, pk, start,
        inner, inner_end, tension, surf, gw, wnx, wnz)


@njit(**JIT)
def interact_reference(x, z, vx, vz, rho, p, m, kind, body, comp, hs, cell_of, cell_start,
                       ncx, kp, visc_coef, gx, gz, delta_coef, ddt_rho, grx, grz, ax, az, drho,
                       op, kin, shift, sx, sz, tension, surf, gw, wnx, wnz):
    """:func:`interact` with every particle summed by :func:`_sums_general` over the cells,
    one rule at a time (the test oracle of the fast loop and of the lists). Serial: an
    oracle for the tests' small patches, compiled in half the time of a parallel loop."""
    use_delta = delta_coef != 0.0
    for i in range(x.shape[0]):
        if kind[i] != FLUID:
            continue
        pwall, pfloor = wall_pair_terms(p[i], tension, surf, i)
        nxi = 0.0 if wnx is None else wnx[i]
        nzi = 0.0 if wnz is None else wnz[i]
        accx, accz, div, diff, shep = _sums_general(
            i, x, z, vx, vz, rho, p, m, kind, body, comp, hs, cell_of, cell_start, ncx, kp,
            visc_coef, gx, gz, ddt_rho, use_delta, grx, grz, op, kin, False, cell_start,
            cell_of, cell_start, pwall, pfloor, gw, nxi, nzi)
        _finish(i, accx, accz, div, diff, shep, x, z, rho, m, kind, body, comp, hs, cell_of,
                cell_start, ncx, kp, gx, gz, delta_coef, ax, az, drho, op, kin, shift, sx, sz,
                None)


@njit(inline="always", **JIT)
def _finish(i, accx, accz, div, diff, shep, x, z, rho, m, kind, body, comp, hs, cell_of,
            cell_start, ncx, kp, gx, gz, delta_coef, ax, az, drho, op, kin, shift, sx, sz,
            lists):
    ax[i] = accx + gx
    az[i] = accz + gz
    drho[i] = rho[i] * div + delta_coef * diff
    if shift[SH_COEF] != 0.0:
        if shep > PACKED:  # the gate of shift_vector is closed below PACKED
            sx[i], sz[i] = shift_vector(i, shep, x, z, rho, m, kind, body, comp, hs,
                                        cell_of, cell_start, ncx, kp, op, kin, shift, lists)
        else:
            sx[i] = 0.0
            sz[i] = 0.0
