r"""Dummy-particle walls (Cao et al. 2019, Sec. II B; Adami, Hu & Adams 2012).

Walls are several layers of particles behind each solid surface. Every wall particle belongs
to a motion group ``body`` (0 = the fixed tank) and keeps its position in that group's frame.
Its pressure is extrapolated from the fluid around it with gravity and the wall's own
acceleration (Eq. 11), and its density follows from the inverse Tait law (Eq. 12):

.. math::
    P_B = \frac{\sum_f V_f W_{Bf}\left[P_f + \rho_f (\mathbf{g} - \mathbf{a}_B)\cdot
          (\mathbf{r}_B - \mathbf{r}_f)\right]}{\sum_f V_f W_{Bf}}

A wall particle without fluid in its support gets :math:`P_B = 0`. Rigid-body kinematics of
a wall particle at :math:`\mathbf{r} = \mathbf{r}_B - \mathbf{r}_c` (Eq. 13):
:math:`\mathbf{a}_B = \dot{\mathbf{V}} + \dot\Omega\times\mathbf{r}
+ \Omega\times\Omega\times\mathbf{r}`.

Body kinematics travel to numba as an array ``kin`` of shape ``(n_body, 9)`` with columns
``[xc, zc, theta, vxc, vzc, omega, axc, azc, alpha]`` (reference point, angle
counter-clockwise, and their first and second time derivatives).
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from sph.engine.eos import tait_density
from sph.engine.jit import JIT, JIT_PARALLEL, njit
from sph.engine.kernels import KP_R2MAX, f_scaled, pair_scale, w_scaled
from sph.engine.opening import OP_GROUP, in_sight_near, near_opening, opening_circle, wall_hidden
from sph.engine.particles import FLUID, GHOST, WALL
from sph.engine.surface import wall_pair_terms

KIN_COLUMNS = ("xc", "zc", "theta", "vxc", "vzc", "omega", "axc", "azc", "alpha")


def fixed_kinematics(n_body: int) -> np.ndarray:
    """Kinematics array of ``n_body`` motion groups all at rest at the origin."""
    return np.zeros((n_body, len(KIN_COLUMNS)), dtype=np.float64)


@njit(**JIT_PARALLEL)
def place_walls(x, z, vx, vz, bx, bz, kind, body, kin):
    """Positions and velocities of moving wall particles from their groups' kinematics.

    Group 0 (the fixed tank) is left untouched."""
    for i in prange(x.shape[0]):
        b = body[i]
        if kind[i] != WALL or b == 0:
            continue
        ct = math.cos(kin[b, 2])
        st = math.sin(kin[b, 2])
        rx = ct * bx[i] - st * bz[i]
        rz = st * bx[i] + ct * bz[i]
        x[i] = kin[b, 0] + rx
        z[i] = kin[b, 1] + rz
        om = kin[b, 5]
        vx[i] = kin[b, 3] - om * rz
        vz[i] = kin[b, 4] + om * rx


@njit(inline="always", **JIT)
def _sees_opening(i, b, x, z, op, support):
    """True when wall particle ``i`` of group ``b`` at ``(x, z)`` belongs to the damaged hull
    and lies within reach (plus the support) of its open opening: some fluid in its support
    may be hidden from it (:func:`sph.engine.opening.wall_hidden`)."""
    return b == int(op[OP_GROUP]) and near_opening(x, z, op, support)


@njit(inline="always", **JIT)
def _fluid_seen(i, j, xi, zi, ci, b, hide, x, z, comp, hs, r2max, op, kin):
    """Whether fluid particle ``j`` of a wall particle's list counts for the wall particle
    ``i`` at ``(xi, zi)`` (compartment ``ci``, group ``b``): within the support of the
    pair's smoothing length (:func:`sph.engine.kernels.pair_scale`), of the same
    compartment, and, when ``hide`` (:func:`_sees_opening`), not hidden by the opening.
    Returns it with the pair's ``dx, dz, r2`` and smoothing length ratio ``s``."""
    dx = xi - x[j]
    dz = zi - z[j]
    r2 = dx * dx + dz * dz
    s = pair_scale(hs, i, j)
    ok = r2 < r2max * s * s and comp[j] == ci and not (
        hide and wall_hidden(x[j], z[j], xi, zi, b, op, kin))
    return ok, dx, dz, r2, s


@njit(**JIT_PARALLEL)
def wall_pressure(x, z, rho, p, m, kind, body, comp, hs, kp, gx, gz, kin, rho0, b_coef,
                  gamma, vol0, op, start, inner, inner_end, clamp, reach):
    """Extrapolate pressure and density onto every wall particle (Eqs. 11-13).

    A wall particle keeps its volume ``vol0 hs^2`` (= dx^2 at its refinement level; walls
    are rigid), so its mass follows its density: ``m = rho vol0 hs^2``. ``hs``: each
    particle's smoothing length ratio, None at uniform resolution (1). Fluid seen through
    an open damage opening ``op`` does not count (:func:`sph.engine.opening.wall_hidden`).
    The pressure is clamped at zero (``clamp``; all but ``numerics.wall_tension: none``): a
    wall in tension would attract the fluid through itself. The fluid neighbours come from the wall
    particle's inner list ``inner[start[i]:inner_end[i]]``
    (:class:`sph.engine.neighbours.NeighbourList`); the line-of-sight test is made only for
    the damaged hull's wall particles within reach of an open opening. Under variable
    resolution only the wall particles marked in ``reach`` are done (those with an active
    fluid particle in their list, :func:`sph.engine.refinement.in_reach`: no other reads
    them before the lists are rebuilt); None: all."""
    n = x.shape[0]
    r2max = kp[KP_R2MAX]
    support = math.sqrt(r2max)
    for i in prange(n):
        if kind[i] != WALL:
            continue
        if reach is not None and not reach[i]:
            continue
        b = body[i]
        xi = x[i]
        zi = z[i]
        rx = xi - kin[b, 0]
        rz = zi - kin[b, 1]
        om2 = kin[b, 5] * kin[b, 5]
        al = kin[b, 8]
        abx = kin[b, 6] - al * rz - om2 * rx
        abz = kin[b, 7] + al * rx - om2 * rz
        ex = gx - abx
        ez = gz - abz
        ci = comp[i]
        sw = 0.0
        sp = 0.0
        hide = _sees_opening(i, b, xi, zi, op, support)
        for k in range(start[i], inner_end[i]):
            j = inner[k]
            ok, dx, dz, r2, s = _fluid_seen(i, j, xi, zi, ci, b, hide, x, z, comp, hs, r2max,
                                            op, kin)
            if not ok:
                continue
            w = w_scaled(r2, kp, s) * m[j] / rho[j]
            sw += w
            sp += w * (p[j] + rho[j] * (ex * dx + ez * dz))
        # a wall in tension would pull fluid through itself (a vortex core reaching a wall
        # takes negative pressure with it); walls push, they do not pull (unless wall_tension: none)
        pb = sp / sw if sw > 1.0e-6 else 0.0
        p[i] = max(pb, 0.0) if clamp else pb
        rho[i] = tait_density(p[i], rho0, b_coef, gamma)
        m[i] = rho[i] * vol0 * pair_scale(hs, i, i) ** 2


@njit(**JIT_PARALLEL)
def wall_forces(x, z, rho, p, m, kind, body, comp, hs, kp, kin, n_body, fx, fz, mom, pf,
                scale, op, start, inner, inner_end, tension, surf, reach):
    r"""Pressure force and moment per unit length on each motion group (Eq. 10).

    .. math:: \mathbf{f}_j = -\frac{m_j}{\rho_j}\sum_{i\in f}(P_i + P_j)\nabla_j W_{ji}
              \frac{m_i}{\rho_i}

    Per-particle values are reduced per group afterwards; the moment is taken about the
    group's reference point. Writes into ``fx, fz, mom`` (length ``n_body``); ``pf`` is an
    ``(n, 3)`` work array for the per-particle values (reused between steps); the force of
    the fluid of compartment ``c`` is multiplied by ``scale[c]``. Neighbours as in
    :func:`wall_pressure`. The pressure sum of a pair follows ``numerics.wall_tension`` as
    in the momentum equation (``tension``, ``surf``: :func:`sph.engine.fluid.interact`), so
    that the force on the body is the reaction of the force on the fluid. ``reach``: under
    variable resolution, the wall particles within reach of active fluid of their level
    (:func:`sph.engine.refinement.in_reach`), whatever region they lie in; the others,
    with no active fluid in their lists, are skipped. None: all."""
    n = x.shape[0]
    r2max = kp[KP_R2MAX]
    support = math.sqrt(r2max)
    for i in prange(n):
        if kind[i] != WALL or body[i] == 0:
            continue
        if reach is not None and not reach[i]:
            pf[i, 0] = 0.0
            pf[i, 1] = 0.0
            pf[i, 2] = 0.0
            continue
        xi = x[i]
        zi = z[i]
        ci = comp[i]
        b = body[i]
        vi = m[i] / rho[i]
        sx = 0.0
        sz = 0.0
        hide = _sees_opening(i, b, xi, zi, op, support)
        for k in range(start[i], inner_end[i]):
            j = inner[k]
            ok, dx, dz, r2, s = _fluid_seen(i, j, xi, zi, ci, b, hide, x, z, comp, hs, r2max,
                                            op, kin)
            if not ok or body[j] == GHOST:  # a ghost carries no mass (refinement)
                continue
            # the pressure sum as in the momentum equation (numerics.wall_tension)
            pwall, pfloor = wall_pair_terms(p[j], tension, surf, j)
            fw = f_scaled(r2, kp, s) * max(pwall + p[i], pfloor) * m[j] / rho[j]
            sx += fw * dx
            sz += fw * dz
        vi *= scale[ci]
        pf[i, 0] = -vi * sx
        pf[i, 1] = -vi * sz
        pf[i, 2] = (xi - kin[b, 0]) * pf[i, 1] - (zi - kin[b, 1]) * pf[i, 0]
    fx[:] = 0.0
    fz[:] = 0.0
    mom[:] = 0.0
    for i in range(n):
        if kind[i] == WALL and body[i] > 0:
            b = body[i]
            fx[b] += pf[i, 0]
            fz[b] += pf[i, 1]
            mom[b] += pf[i, 2]


@njit(**JIT_PARALLEL)
def listed_with(kind, body, start, inner, inner_end, walled, ghosted):
    """Mark the active fluid particles whose inner list
    (:meth:`sph.engine.neighbours.NeighbourList.refresh`) holds a wall particle (into
    ``walled``) and those whose list holds a ghost (into ``ghosted``; either None: not
    marked): the only ones whose wall normal (:func:`wall_normals`) or ghosts' density
    exchange (:func:`sph.engine.refinement.ghost_diffusion`) can differ from zero until the
    inner lists are refreshed. One pass over the lists for both."""
    for i in prange(kind.shape[0]):
        w = walled is None  # True: no need to look
        g = ghosted is None
        if kind[i] == FLUID and body[i] != GHOST:
            for k in range(start[i], inner_end[i]):
                j = inner[k]
                if kind[j] == WALL:
                    w = True
                elif body[j] == GHOST:
                    g = True
                if w and g:
                    break
        else:
            w = g = False
        if walled is not None:
            walled[i] = w
        if ghosted is not None:
            ghosted[i] = g


@njit(**JIT_PARALLEL)
def _wall_counts(kind, start, inner, inner_end, walled, count):
    """``count[i + 1]``: the wall particles in the inner list of each particle marked in
    ``walled`` (0 for the others)."""
    for i in prange(kind.shape[0]):
        c = 0
        if walled[i]:
            for k in range(start[i], inner_end[i]):
                if kind[inner[k]] == WALL:
                    c += 1
        count[i + 1] = c


@njit(**JIT_PARALLEL)
def _wall_fill(kind, start, inner, inner_end, walled, wall_start, wall_index):
    """Copy the wall entries of each marked particle's inner list, in their order."""
    for i in prange(kind.shape[0]):
        if walled[i]:
            c = np.int64(wall_start[i])  # (uint64 + 1 would be a float in numba)
            for k in range(start[i], inner_end[i]):
                j = inner[k]
                if kind[j] == WALL:
                    wall_index[c] = j
                    c += 1


def wall_lists(kind, start, inner, inner_end, walled, wall_start, wall_index) -> np.ndarray:
    """The wall particles of the inner list of each fluid particle marked in ``walled``
    (:func:`listed_with`), in the inner list's order, stored compressed: particle ``i``'s
    are ``wall_index[wall_start[i]:wall_start[i + 1]]`` (``wall_start``: ``n + 1`` entries,
    filled here). Made at every refresh of the inner lists, so that :func:`wall_normals`
    visits a particle's walls alone instead of its whole list (about a fifth of it beside
    a wall), summing them in the same order. Returns ``wall_index``, grown if needed."""
    wall_start[0] = 0
    _wall_counts(kind, start, inner, inner_end, walled, wall_start)
    np.cumsum(wall_start, out=wall_start)
    total = int(wall_start[-1])
    if wall_index.shape[0] < total:
        wall_index = np.empty(int(1.2 * total) + 16, dtype=inner.dtype)
    _wall_fill(kind, start, inner, inner_end, walled, wall_start, wall_index)
    return wall_index


@njit(inline="always", **JIT)
def _normal_sums(i, k0, k1, walls, xi, zi, ci, x, z, m, rho, kind, body, comp, hs, kp, r2max,
                 op, kin, near):
    """:func:`wall_normals`' sum over the wall particles ``walls[k0:k1]`` that particle
    ``i`` sees (``near``: within the open opening's reach,
    :func:`sph.engine.opening.in_sight_near`)."""
    sx = 0.0
    sz = 0.0
    for k in range(k0, k1):
        j = walls[k]
        ok, dx, dz, r2, s = in_sight_near(near, i, j, xi, zi, ci, x, z, kind, body, comp, hs,
                                          r2max, op, kin)
        if not ok:
            continue
        # grad_i W V = a (r_i - r_j) with a < 0: it points from i towards j
        a = f_scaled(r2, kp, s) * m[j] / rho[j]
        sx += a * dx
        sz += a * dz
    return sx, sz


@njit(**JIT_PARALLEL)
def wall_normals(x, z, m, rho, kind, body, comp, hs, kp, op, kin, wall_start, wall_index,
                 near, nx, nz):
    r"""The unit vector from each active fluid particle towards the walls it sees,
    :math:`\mathbf{n}_i \propto \sum_w V_w \nabla_i W_{iw}` over the wall particles of its
    inner list within the support that the pair rule lets it see
    (:func:`sph.engine.opening.sees`: its compartment, not hidden by an open damage
    opening), with their volumes ``m / rho`` (:func:`wall_pressure` sets them); ``(0, 0)``
    with no wall in reach. ``numerics.wall_damping`` damps the approach along it
    (:func:`sph.engine.fluid.interact`). Call after :func:`wall_pressure`. Only the
    particles marked in ``near`` (:func:`listed_with`) have walls to sum over: those of
    their inner lists, ``wall_index[wall_start[i]:wall_start[i + 1]]`` (:func:`wall_lists`).

    Beyond the open opening's reach (:func:`sph.engine.opening.near_opening`, and
    everywhere while it is closed) no wall is hidden, and the pair rule is the
    compartment's alone, as in the fluid's list loops: the test of :func:`in_sight` is
    made only near the opening (the same walls, in the same order)."""
    r2max = kp[KP_R2MAX]
    ocx, ocz, or2 = opening_circle(op, 0.0)  # near_opening, taken once
    for i in prange(x.shape[0]):
        nx[i] = 0.0
        nz[i] = 0.0
        if not near[i]:  # no wall in its list; nor a wall particle or a ghost
            continue
        xi = x[i]
        zi = z[i]
        ci = comp[i]
        sees_opening = (xi - ocx) * (xi - ocx) + (zi - ocz) * (zi - ocz) <= or2
        # a loop of its own within the opening's reach and one beyond it: with the choice
        # made for every pair the pass took 2.6 times as long (refined case4 at 25.75 s)
        if sees_opening:
            sx, sz = _normal_sums(i, wall_start[i], wall_start[i + 1], wall_index, xi, zi, ci,
                                  x, z, m, rho, kind, body, comp, hs, kp, r2max, op, kin, True)
        else:
            sx, sz = _normal_sums(i, wall_start[i], wall_start[i + 1], wall_index, xi, zi, ci,
                                  x, z, m, rho, kind, body, comp, hs, kp, r2max, op, kin, False)
        norm = math.sqrt(sx * sx + sz * sz)
        if norm > 0.0:
            nx[i] = sx / norm
            nz[i] = sz / norm


# --------------------------------------------------------------------------- the tank guard

#: columns of a tank guard (:func:`tank_guard`, :func:`keep_in_tank`)
TG_LEFT, TG_RIGHT, TG_FLOOR, TG_TOP, TG_DEPTH, TG_REACH = 0, 1, 2, 3, 4, 5


def tank_guard(left: float, right: float, floor: float, top: float, dx: float,
               layers: int) -> np.ndarray:
    """The guard of a tank's fixed walls for :func:`keep_in_tank`.

    ``left``, ``right``: x of the end walls' surfaces (``-inf``, ``inf`` where an end is not
    a fixed wall: a wavemaker, an open boundary, another segment's tank); ``floor``: z of
    the floor's surface; ``top``: the height up to which the end walls reach. The surfaces
    lie half a spacing in front of the first layer of wall particles. A particle counts as
    through a wall once it is half a spacing ``dx`` beyond the surface (at the first layer's
    line, where no fluid particle in contact with the wall gets), and only within the wall's
    thickness (``layers`` spacings): one beyond that has left the domain."""
    return np.array([left, right, floor, top, 0.5 * dx, layers * dx], dtype=np.float64)


@njit(**JIT)
def keep_in_tank(x, z, vx, vz, vx_old, vz_old, kind, guard) -> int:
    """Put back a fluid particle, active or ghost, found through the tank's fixed walls.

    The walls hold the fluid by the pressure of their particles alone. Where that fails (a
    particle that changes level beside the floor under variable resolution is driven into
    it while active, sinks on as a ghost, which feels no wall, and turns active below the
    floor at a density below rho0, where the walls do not push: docs/validation/
    refinement.md, "A sloshing tank") the particle would fall out of the domain. One found
    more than ``guard[TG_DEPTH]`` beyond the floor (between the end walls) or an end wall
    (below ``guard[TG_TOP]``), but within the wall's thickness, is put at its mirror image
    across the wall's surface and the velocity that carried it into the wall is removed,
    at both leapfrog levels: the hull's guard for the tank (:func:`sph.engine.opening.
    keep_sides`). A particle in contact with a wall is never that far in, so a run whose
    walls hold its fluid is unchanged to the bit. Returns how many were put back."""
    left, right, floor, top = guard[TG_LEFT], guard[TG_RIGHT], guard[TG_FLOOR], guard[TG_TOP]
    depth, reach = guard[TG_DEPTH], guard[TG_REACH]
    n = 0
    for i in range(x.shape[0]):
        if kind[i] != FLUID:
            continue
        if z[i] < top:  # the end walls first: a particle through a corner is then between them
            d = left - x[i]
            if depth < d <= reach:
                x[i] = left + d
                vx[i] = max(vx[i], 0.0)
                vx_old[i] = max(vx_old[i], 0.0)
                n += 1
            d = x[i] - right
            if depth < d <= reach:
                x[i] = right - d
                vx[i] = min(vx[i], 0.0)
                vx_old[i] = min(vx_old[i], 0.0)
                n += 1
        d = floor - z[i]
        if depth < d <= reach and left < x[i] < right:
            z[i] = floor + d
            vz[i] = max(vz[i], 0.0)
            vz_old[i] = max(vz_old[i], 0.0)
            n += 1
    return n
