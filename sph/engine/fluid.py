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
layers. The optional delta-SPH diffusive term (second source paper,
Eq. 2; Antuono et al. 2010) is added to the continuity equation between fluid particles:

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

from sph.engine.jit import JIT, JIT_PAIR, JIT_PARALLEL, JIT_PARALLEL_PAIR, njit
from sph.engine.kernels import (
    E9,
    KP_ALPHA,
    KP_H,
    KP_INV_H2,
    KP_KIND,
    KP_R2MAX,
    exp_neg,
    f_r2,
    w_given_f,
    w_r2,
)
from sph.engine.neighbours import BLOCK
from sph.engine.opening import near_opening, sees
from sph.engine.particles import FLUID
from sph.engine.shifting import PACKED, SH_COEF, shift_vector


@njit(**JIT)
def _sums_general(i, x, z, vx, vz, rho, p, m, kind, body, comp, cell_of, cell_start, ncx,
                  kp, visc_coef, gx, gz, ddt_rho, use_delta, grx, grz, op, kin):
    """Pair sums of fluid particle ``i`` with every rule: compartments, the line of sight
    through an open damage opening, hidden wall layers. Returns ``(acc_x, acc_z, div, diff,
    shep)``: the pair accelerations, the velocity divergence sum, the diffusive sum and the
    kernel sum (itself included)."""
    r2max = kp[KP_R2MAX]
    eps2 = 1.0e-4 * kp[KP_H] * kp[KP_H]
    use_ddt = ddt_rho != 0.0
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
    shep = m[i] / rhoi * w_r2(0.0, kp)
    c = cell_of[i]
    for row in (c - ncx, c, c + ncx):
        for j in range(cell_start[row - 1], cell_start[row + 2]):
            dx = xi - x[j]
            dz = zi - z[j]
            r2 = dx * dx + dz * dz
            if r2 >= r2max or j == i:
                continue
            if not sees(xi, zi, ci, x[j], z[j], kind[j], body[j], comp[j], op, kin):
                continue
            fw = f_r2(r2, kp)
            rhoj = rho[j]
            vj = m[j] / rhoj
            dvx = vxi - vx[j]
            dvz = vzi - vz[j]
            vr = dvx * dx + dvz * dz
            div += vj * vr * fw
            if kind[j] == FLUID:
                coef = -m[j] * (pi + p[j]) / (rhoi * rhoj)
            else:  # a wall pushes and never pulls: fluid tension does not count
                coef = -m[j] * (max(pi, 0.0) + p[j]) / (rhoi * rhoj)
            if kind[j] == FLUID:
                coef += visc_coef * m[j] / (rhoi + rhoj) * vr / (r2 + eps2)
                if use_ddt:
                    rho_h = -ddt_rho * (gx * dx + gz * dz)
                    diff -= 2.0 * vj * fw * (rhoj - rhoi - rho_h)
                elif use_delta:
                    diff += vj * fw * (-2.0 * (rhoj - rhoi)
                                       - ((gxi + grx[j]) * dx + (gzi + grz[j]) * dz))
            accx += coef * fw * dx
            accz += coef * fw * dz
            shep += vj * w_given_f(r2, fw, kp)
    return accx, accz, div, diff, shep


@njit(inline="always", **JIT_PAIR)
def _neighbours_of(i, x, z, comp, start, index, r2max, buf):
    """The entries of particle ``i``'s Verlet list within ``sqrt(r2max)`` and of its
    compartment, into ``buf``; returns their number. Every entry is stored and the count
    advances only for a neighbour: no branch, so the one entry in four or five beyond the
    support costs no mispredicted jump."""
    xi = x[i]
    zi = z[i]
    ci = comp[i]
    nn = np.uint64(0)  # unsigned indices: no negative-index wrap-around in the loops
    for k in range(start[i], start[i + 1]):
        j = index[k]
        dx = xi - x[j]
        dz = zi - z[j]
        buf[nn] = j
        nn += np.uint64(1) if (dx * dx + dz * dz < r2max) & (comp[j] == ci) else np.uint64(0)
    return nn


@njit(inline="always", **JIT_PAIR)
def _sums_gaussian(i, buf, nn, x, z, vx, vz, rho, p, m, vol, kind, kp, visc_coef, hx, hz):
    """The pair sums of :func:`_sums_general` for a fluid particle that cannot see through
    a damage opening, over its neighbours ``buf[:nn]`` (:func:`_neighbours_of`: the
    particles of its compartment within the support, itself included; the self pair adds
    its kernel value to the kernel sum and nothing else), for the improved Gaussian kernel,
    with no branch but the fluid/wall selects. ``vol = m / rho``; ``hx dx + hz dz`` is the
    hydrostatic density difference of the ``ddt`` diffusive term (0: none)."""
    h2 = kp[KP_H] * kp[KP_H]
    eps2 = 1.0e-4 * h2
    inv_h2 = kp[KP_INV_H2]
    fg = -2.0 * kp[KP_ALPHA] * inv_h2  # F = fg exp(-q^2)
    wg = kp[KP_ALPHA] * E9  # W = -F h^2 / 2 - alpha e^-9
    xi = x[i]
    zi = z[i]
    vxi = vx[i]
    vzi = vz[i]
    rhoi = rho[i]
    inv_rhoi = 1.0 / rhoi
    pi = p[i]
    ppos = max(pi, 0.0)  # a wall pushes and never pulls
    accx = 0.0
    accz = 0.0
    div = 0.0
    diff = 0.0
    shep = 0.0
    for k in range(nn):
        j = buf[k]
        dx = xi - x[j]
        dz = zi - z[j]
        r2 = dx * dx + dz * dz
        fw = fg * exp_neg(r2 * inv_h2)
        fluid = kind[j] == FLUID
        vj = vol[j]
        rhoj = rho[j]
        vr = (vxi - vx[j]) * dx + (vzi - vz[j]) * dz
        div += vj * vr * fw
        coef = -((pi if fluid else ppos) + p[j]) * vj * inv_rhoi
        visc = visc_coef * m[j] * vr / ((rhoi + rhoj) * (r2 + eps2))
        coef += visc if fluid else 0.0
        d = -2.0 * vj * fw * (rhoj - rhoi - hx * dx - hz * dz)
        diff += d if fluid else 0.0
        accx += coef * fw * dx
        accz += coef * fw * dz
        shep += vj * (-0.5 * h2 * fw - wg)
    return accx, accz, div, diff, shep


@njit(inline="always", **JIT_PAIR)
def _sums_wendland(i, buf, nn, x, z, vx, vz, rho, p, m, vol, kind, kp, visc_coef, hx, hz):
    """:func:`_sums_gaussian` for the Wendland C2 kernel. (One loop with the kernel chosen
    inside it, for every pair, took about 1.5 times as long on the damaged ship.)"""
    h2 = kp[KP_H] * kp[KP_H]
    eps2 = 1.0e-4 * h2
    inv_h2 = kp[KP_INV_H2]
    alpha = kp[KP_ALPHA]
    fwend = -5.0 * alpha * inv_h2  # F = fwend t^3, t = 1 - q/2
    xi = x[i]
    zi = z[i]
    vxi = vx[i]
    vzi = vz[i]
    rhoi = rho[i]
    inv_rhoi = 1.0 / rhoi
    pi = p[i]
    ppos = max(pi, 0.0)
    accx = 0.0
    accz = 0.0
    div = 0.0
    diff = 0.0
    shep = 0.0
    for k in range(nn):
        j = buf[k]
        dx = xi - x[j]
        dz = zi - z[j]
        r2 = dx * dx + dz * dz
        q = math.sqrt(r2 * inv_h2)
        t = 1.0 - 0.5 * q
        t2 = t * t
        fw = fwend * t2 * t
        fluid = kind[j] == FLUID
        vj = vol[j]
        rhoj = rho[j]
        vr = (vxi - vx[j]) * dx + (vzi - vz[j]) * dz
        div += vj * vr * fw
        coef = -((pi if fluid else ppos) + p[j]) * vj * inv_rhoi
        visc = visc_coef * m[j] * vr / ((rhoi + rhoj) * (r2 + eps2))
        coef += visc if fluid else 0.0
        d = -2.0 * vj * fw * (rhoj - rhoi - hx * dx - hz * dz)
        diff += d if fluid else 0.0
        accx += coef * fw * dx
        accz += coef * fw * dz
        shep += vj * alpha * t2 * t2 * (2.0 * q + 1.0)
    return accx, accz, div, diff, shep


@njit(**JIT_PARALLEL_PAIR)
def interact(x, z, vx, vz, rho, p, m, kind, body, comp, cell_of, cell_start, ncx, kp,
             visc_coef, gx, gz, delta_coef, ddt_rho, grx, grz, ax, az, drho, op, kin, shift,
             sx, sz, vol, start, index):
    r"""Accelerations ``ax, az``, density rates ``drho`` and, when shifting is on, the
    particle shifts ``sx, sz`` (:mod:`sph.engine.shifting`) of all fluid particles.

    A fluid particle within reach of an open damage opening, or any fluid particle under
    the renormalised diffusive term, takes every pair rule at every candidate of the cells
    (:func:`_sums_general`). All others, the vast majority, sum over their Verlet list
    ``index[start[i]:start[i + 1]]`` (:class:`sph.engine.neighbours.NeighbourList`) with
    the kernel's own loop (:func:`_sums_gaussian`, :func:`_sums_wendland`), in the same
    order. :func:`interact_reference` sums every particle the general way.

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
    vol : array
        Work array for the particle volumes ``m / rho`` (filled here).
    start, index : arrays
        The Verlet lists (:class:`sph.engine.neighbours.NeighbourList`).
    """
    n = x.shape[0]
    for j in prange(n):
        vol[j] = m[j] / rho[j]
    use_delta = delta_coef != 0.0
    general = use_delta and ddt_rho == 0.0  # the renormalised term needs grx, grz
    hx = -ddt_rho * gx  # hydrostatic density difference of a pair: hx dx + hz dz
    hz = -ddt_rho * gz
    gauss = kp[KP_KIND] == 0.0
    r2max = kp[KP_R2MAX]
    longest = np.int64(0)
    for i in range(n):
        longest = max(longest, np.int64(start[i + 1] - start[i]))
    for b in prange((n + BLOCK - 1) // BLOCK):
        buf = np.empty(longest, dtype=np.uint32)  # as the lists (NeighbourList)
        for i in range(b * BLOCK, min(n, (b + 1) * BLOCK)):
            if kind[i] != FLUID:
                continue
            if general or near_opening(x[i], z[i], op, 0.0):
                accx, accz, div, diff, shep = _sums_general(
                    i, x, z, vx, vz, rho, p, m, kind, body, comp, cell_of, cell_start, ncx,
                    kp, visc_coef, gx, gz, ddt_rho, use_delta, grx, grz, op, kin)
            else:
                nn = _neighbours_of(i, x, z, comp, start, index, r2max, buf)
                if gauss:
                    accx, accz, div, diff, shep = _sums_gaussian(
                        i, buf, nn, x, z, vx, vz, rho, p, m, vol, kind, kp, visc_coef, hx, hz)
                else:
                    accx, accz, div, diff, shep = _sums_wendland(
                        i, buf, nn, x, z, vx, vz, rho, p, m, vol, kind, kp, visc_coef, hx, hz)
            _finish(i, accx, accz, div, diff, shep, x, z, rho, m, kind, body, comp, cell_of,
                    cell_start, ncx, kp, gx, gz, delta_coef, ax, az, drho, op, kin, shift, sx,
                    sz)


@njit(**JIT_PARALLEL)
def interact_reference(x, z, vx, vz, rho, p, m, kind, body, comp, cell_of, cell_start, ncx,
                       kp, visc_coef, gx, gz, delta_coef, ddt_rho, grx, grz, ax, az, drho, op,
                       kin, shift, sx, sz):
    """:func:`interact` with every particle summed by :func:`_sums_general`, one rule at a
    time (the test oracle of the fast loop)."""
    use_delta = delta_coef != 0.0
    for i in prange(x.shape[0]):
        if kind[i] != FLUID:
            continue
        accx, accz, div, diff, shep = _sums_general(
            i, x, z, vx, vz, rho, p, m, kind, body, comp, cell_of, cell_start, ncx, kp,
            visc_coef, gx, gz, ddt_rho, use_delta, grx, grz, op, kin)
        _finish(i, accx, accz, div, diff, shep, x, z, rho, m, kind, body, comp, cell_of,
                cell_start, ncx, kp, gx, gz, delta_coef, ax, az, drho, op, kin, shift, sx, sz)


@njit(inline="always", **JIT)
def _finish(i, accx, accz, div, diff, shep, x, z, rho, m, kind, body, comp, cell_of,
            cell_start, ncx, kp, gx, gz, delta_coef, ax, az, drho, op, kin, shift, sx, sz):
    ax[i] = accx + gx
    az[i] = accz + gz
    drho[i] = rho[i] * div + delta_coef * diff
    if shift[SH_COEF] != 0.0:
        if shep > PACKED:  # the gate of shift_vector is closed below PACKED
            sx[i], sz[i] = shift_vector(i, shep, x, z, rho, m, kind, body, comp, cell_of,
                                        cell_start, ncx, kp, op, kin, shift)
        else:
            sx[i] = 0.0
            sz[i] = 0.0
