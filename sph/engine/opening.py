r"""The damage opening as the pair loops see it: the packed parameters ``op`` and the
line-of-sight tests through a hull's plating.

A ship's hull plating is thinner than the kernel support; its mid-surface (an outline of
:func:`sdf`, :func:`sph.bodies.hull.shape`) separates the sea from a cabin. Two fluid
particles of the sea and of the damaged cabin interact when the straight segment between them
crosses the mid-surface inside the open opening (:func:`passable`); a wall particle of the
damaged hull is hidden from a fluid particle when their segment crosses it there
(:func:`wall_hidden`); :func:`keep_sides` moves a fluid particle that passed through the
opening into the compartment of its new side and puts back one pressed through the plating.
The physics and its justification are in :mod:`sph.bodies.damage`.

The opening travels to the numba kernels as a float array ``op`` of ``OP_SIZE`` slots (all
zeros: no opening), packed by :func:`pack_opening`:

==================  ==========================================================
``OP_OPEN``         1 when the opening is open
``OP_SEA``          compartment id of the sea
``OP_CABIN``        compartment id of the damaged cabin
``OP_GROUP``        wall group of the damaged hull (its row of ``kin``)
``OP_SIDE``         +1 the opening faces +x ("back"), -1 it faces -x ("head")
``OP_W_LOW/HIGH``   keel-frame heights ``w`` of the opening's lower and upper edges
``OP_SHAPE`` ..     mid-surface outline (5 numbers, :func:`sph.bodies.hull.shape`)
``OP_KG``           height of the reference point (centre of gravity) above the keel
``OP_REACH``        particles within this distance of the mid-surface are checked for
                    their side
``OP_MARGIN``       a particle rounding the opening's edge within this distance of the
                    edge point changes compartment (beyond it, it was pressed through
                    the plating)
``OP_CENTRE_U/W``   centre of a circle around the opening's part of the mid-surface, in
                    the hull's frame (``u``, ``w`` minus the reference height)
``OP_REACH2``       squared reach of that circle: its radius plus the kernel support
                    (0: no quick test)
``OP_CENTRE_X/Z``   the same centre in earth coordinates at the current kinematics
                    (:func:`place_centre`, at every evaluation)
==================  ==========================================================

The circle makes the line-of-sight test cheap where it cannot succeed: a segment shorter than
the kernel support that crosses the mid-surface inside the opening has both ends within the
reach of the centre, so a pair with one end farther away is answered without the keel-frame
transform and the bisection (the test is exact: it only skips pairs that cannot cross).
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from sph.engine.jit import JIT, JIT_PARALLEL, njit
from sph.engine.kernels import pair_scale
from sph.engine.particles import FLUID

# slots of ``op`` (module docstring)
OP_OPEN = 0
OP_SEA = 1
OP_CABIN = 2
OP_GROUP = 3
OP_SIDE = 4
OP_W_LOW = 5
OP_W_HIGH = 6
OP_SHAPE = 7
OP_SHAPE_END = 12
OP_KG = 12
OP_REACH = 13
OP_MARGIN = 14
OP_CENTRE_U = 15
OP_CENTRE_W = 16
OP_REACH2 = 17
OP_CENTRE_X = 18
OP_CENTRE_Z = 19
OP_SIZE = 20


def no_opening() -> np.ndarray:
    """``op`` of a case without an opening."""
    return np.zeros(OP_SIZE)


def pack_opening(sea: int, cabin: int, group: int, side: float, w_low: float, w_high: float,
                 shape, kg: float, reach: float, margin: float,
                 circle: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> np.ndarray:
    """``op`` of a closed opening (or of an intact hull's plating, for :func:`keep_sides`);
    ``circle`` = (centre u, centre w - kg, squared reach) of the quick test."""
    op = np.zeros(OP_SIZE)
    op[OP_SEA] = sea
    op[OP_CABIN] = cabin
    op[OP_GROUP] = group
    op[OP_SIDE] = side
    op[OP_W_LOW] = w_low
    op[OP_W_HIGH] = w_high
    op[OP_SHAPE:OP_SHAPE_END] = shape
    op[OP_KG] = kg
    op[OP_REACH] = reach
    op[OP_MARGIN] = margin
    set_circle(op, circle)
    return op


def set_circle(op: np.ndarray, circle: tuple[float, float, float]) -> None:
    """Set the quick-test circle (centre u, centre w - kg, squared reach) of ``op``."""
    op[OP_CENTRE_U], op[OP_CENTRE_W], op[OP_REACH2] = circle


def set_open(op: np.ndarray, value: bool) -> None:
    op[OP_OPEN] = 1.0 if value else 0.0


def group_of(op: np.ndarray) -> int:
    """Wall group (row of ``kin``) of the hull ``op`` belongs to."""
    return int(op[OP_GROUP])


def place_centre(op: np.ndarray, k: np.ndarray) -> None:
    """Put the quick-test circle's earth centre at the hull kinematics ``k`` (a row of
    ``kin``: x, z, angle, ...)."""
    ct, st = math.cos(k[2]), math.sin(k[2])
    op[OP_CENTRE_X] = k[0] + ct * op[OP_CENTRE_U] - st * op[OP_CENTRE_W]
    op[OP_CENTRE_Z] = k[1] + st * op[OP_CENTRE_U] + ct * op[OP_CENTRE_W]


def centre(op: np.ndarray) -> np.ndarray:
    return op[OP_CENTRE_X:OP_CENTRE_Z + 1].copy()


def set_centre(op: np.ndarray, xz) -> None:
    op[OP_CENTRE_X:OP_CENTRE_Z + 1] = xz


@njit(**JIT)
def sdf(u, w, s):
    """Signed distance from ``(u, w)`` to the outline ``s`` (:func:`shape`); < 0 inside.

    A rectangle with rounded bottom corners (radius ``s[3]``) and rounded top corners
    (radius ``s[4]``)."""
    cw = 0.5 * (s[1] + s[2])
    hh = 0.5 * (s[2] - s[1])
    r = s[3] if w < cw else s[4]
    qx = abs(u) - s[0] + r
    qz = abs(w - cw) - hh + r
    ox = max(qx, 0.0)
    oz = max(qz, 0.0)
    return math.sqrt(ox * ox + oz * oz) + min(max(qx, qz), 0.0) - r


@njit(**JIT)
def sdf_many(u, w, s):
    """:func:`sdf` of every point of the arrays ``u, w``."""
    out = np.empty(u.shape[0])
    for k in range(u.shape[0]):
        out[k] = sdf(u[k], w[k], s)
    return out



#: bisection steps locating where a segment crosses the mid-surface (1/1024 of its length)
BISECTIONS = 10


@njit(**JIT)
def keel_frame(x, z, op, kin):
    """Earth ``(x, z)`` -> keel frame ``(u, w)`` of the damaged hull."""
    g = int(op[OP_GROUP])
    return _to_keel(x, z, math.cos(kin[g, 2]), math.sin(kin[g, 2]), kin, g, op[OP_KG])


@njit(inline="always", **JIT)
def _to_keel(x, z, ct, st, kin, g, kg):
    """:func:`keel_frame` with the cosine and sine of the hull's angle given."""
    rx = x - kin[g, 0]
    rz = z - kin[g, 1]
    return ct * rx + st * rz, -st * rx + ct * rz + kg


@njit(**JIT)
def crosses_opening(xi, zi, xj, zj, op, kin):
    """True when the segment between two points crosses the mid-surface inside the open
    opening."""
    if op[OP_OPEN] == 0.0:
        return False
    if op[OP_REACH2] > 0.0:
        ex = xi - op[OP_CENTRE_X]
        ez = zi - op[OP_CENTRE_Z]
        if ex * ex + ez * ez > op[OP_REACH2]:
            return False
    s = op[OP_SHAPE:OP_SHAPE_END]
    g = int(op[OP_GROUP])
    ct = math.cos(kin[g, 2])
    st = math.sin(kin[g, 2])
    ui, wi = _to_keel(xi, zi, ct, st, kin, g, op[OP_KG])
    uj, wj = _to_keel(xj, zj, ct, st, kin, g, op[OP_KG])
    # the crossing point lies between the ends: both ends on the far side of the hull, or
    # both below or both above the opening, and it cannot be inside the opening
    side = op[OP_SIDE]
    if (side * ui <= 0.0 and side * uj <= 0.0) or max(wi, wj) < op[OP_W_LOW] \
            or min(wi, wj) > op[OP_W_HIGH]:
        return False
    di = sdf(ui, wi, s)
    dj = sdf(uj, wj, s)
    if di * dj > 0.0:
        return False
    # the crossing point by bisection: the signed distance is far from linear along a
    # segment as long as the kernel support that meets the curved bilge obliquely, and a
    # linear estimate puts crossings of the bottom plating into the opening
    fa, fb = 0.0, 1.0
    for _ in range(BISECTIONS):
        f = 0.5 * (fa + fb)
        if sdf(ui + f * (uj - ui), wi + f * (wj - wi), s) * di > 0.0:
            fa = f
        else:
            fb = f
    f = 0.5 * (fa + fb)
    uc = ui + f * (uj - ui)
    wc = wi + f * (wj - wi)
    return op[OP_SIDE] * uc > 0.0 and op[OP_W_LOW] <= wc <= op[OP_W_HIGH]


@njit(inline="always", **JIT)
def opening_circle(op, pad):
    """``(cx, cz, r2)`` such that :func:`near_opening` of ``(x, z)`` with this ``pad`` is
    ``(x - cx)**2 + (z - cz)**2 <= r2``: ``r2`` is -1 while the opening is closed and
    1e300 when the quick-test circle is not set. A loop over particles takes it once."""
    if op[OP_OPEN] == 0.0:
        return 0.0, 0.0, -1.0
    if op[OP_REACH2] == 0.0:
        return 0.0, 0.0, 1.0e300
    reach = math.sqrt(op[OP_REACH2]) + pad
    return op[OP_CENTRE_X], op[OP_CENTRE_Z], reach * reach


@njit(inline="always", **JIT)
def near_opening(x, z, op, pad):
    """True when a particle at ``(x, z)`` is within ``pad`` of the reach of the open
    opening's quick-test circle (or anywhere when the circle is not set). A particle
    beyond the reach (``pad = 0``) sees only its own compartment: :func:`crosses_opening`
    is false for every pair it begins. A wall particle whose fluid neighbours begin the
    pairs is tested with ``pad`` = the kernel support."""
    cx, cz, r2 = opening_circle(op, pad)
    ex = x - cx
    ez = z - cz
    return ex * ex + ez * ez <= r2


@njit(**JIT)
def passable(xi, zi, xj, zj, ci, cj, op, kin):
    """True when fluid particles of different compartments see each other through the
    open opening (call only when ``ci != cj``)."""
    if op[OP_OPEN] == 0.0:
        return False
    a = int(op[OP_SEA])
    b = int(op[OP_CABIN])
    if not ((ci == a and cj == b) or (ci == b and cj == a)):
        return False
    return crosses_opening(xi, zi, xj, zj, op, kin)


@njit(**JIT)
def wall_hidden(xf, zf, xw, zw, bw, op, kin):
    """True when a fluid particle and a wall particle of the damaged hull (group ``bw``)
    of the same compartment lie on either side of the open opening: the wall's layers that
    reach across the plating's mid-surface belong to the other side there."""
    if op[OP_OPEN] == 0.0 or bw != int(op[OP_GROUP]):
        return False
    return crosses_opening(xf, zf, xw, zw, op, kin)


@njit(inline="always", **JIT)
def sees(xi, zi, ci, xj, zj, kj, bj, cj, op, kin):
    """The pair rule of the engine's loops: a fluid particle at ``(xi, zi)`` of compartment
    ``ci`` interacts with particle ``j`` (kind ``kj``, wall group ``bj``, compartment ``cj``)
    when ``j`` is fluid of its compartment or seen through the open opening
    (:func:`passable`), or a wall particle of its compartment not hidden by the opening
    (:func:`wall_hidden`)."""
    if kj == FLUID:
        return cj == ci or passable(xi, zi, xj, zj, ci, cj, op, kin)
    return cj == ci and not wall_hidden(xi, zi, xj, zj, bj, op, kin)


@njit(inline="always", **JIT)
def in_sight(i, j, xi, zi, ci, x, z, kind, body, comp, hs, r2max, op, kin):
    """Whether particle ``j`` counts for fluid particle ``i`` at ``(xi, zi)`` (compartment
    ``ci``): within the support of the pair's smoothing length
    (:func:`sph.engine.kernels.pair_scale`) and seen by the pair rule (:func:`sees`).
    Returns it with the pair's ``dx, dz, r2`` and smoothing length ratio ``s``."""
    dx = xi - x[j]
    dz = zi - z[j]
    r2 = dx * dx + dz * dz
    s = pair_scale(hs, i, j)
    ok = r2 < r2max * s * s and sees(xi, zi, ci, x[j], z[j], kind[j], body[j], comp[j], op,
                                     kin)
    return ok, dx, dz, r2, s


@njit(inline="always", **JIT)
def in_sight_near(near, i, j, xi, zi, ci, x, z, kind, body, comp, hs, r2max, op, kin):
    """:func:`in_sight` for a particle ``i`` within the open opening's reach (``near``:
    :func:`near_opening` of ``(xi, zi)`` with no pad, taken once per particle); beyond it the
    pair rule is the compartment's alone, the same answer without the opening's geometry
    (no pair such a particle begins crosses the opening)."""
    if near:
        return in_sight(i, j, xi, zi, ci, x, z, kind, body, comp, hs, r2max, op, kin)
    dx = xi - x[j]
    dz = zi - z[j]
    r2 = dx * dx + dz * dz
    s = pair_scale(hs, i, j)
    return r2 < r2max * s * s and comp[j] == ci, dx, dz, r2, s


@njit(**JIT)
def _normal(u, w, s):
    """Outward unit normal of the outline ``s`` at the nearest point to ``(u, w)``."""
    e = 1.0e-6 * (1.0 + s[0])
    gu = sdf(u + e, w, s) - sdf(u - e, w, s)
    gw = sdf(u, w + e, s) - sdf(u, w - e, s)
    n = math.sqrt(gu * gu + gw * gw)
    if n == 0.0:
        return 0.0, 1.0
    return gu / n, gw / n


@njit(**JIT)
def side_u(w, s):
    """``u`` of the outline ``s`` on its ``+u`` side at height ``w`` (within its bottom and
    top arcs or its vertical side)."""
    if w < s[1] + s[3]:
        r, dw = s[3], s[1] + s[3] - w
        return s[0] - r + math.sqrt(max(r * r - dw * dw, 0.0))
    if w > s[2] - s[4]:
        r, dw = s[4], w - s[2] + s[4]
        return s[0] - r + math.sqrt(max(r * r - dw * dw, 0.0))
    return s[0]


@njit(**JIT)
def in_opening_band(u, w, op):
    """True when the mid-surface point ``(u, w)`` lies in the opening or within
    ``OP_MARGIN`` of one of its edges, the distance taken from the edge point (along the
    plating, not in height: where the plating runs nearly level, as the bottom does beside
    an edge at the cabin floor, a band in height would take in the whole bottom)."""
    if op[OP_SIDE] * u <= 0.0:
        return False
    if op[OP_W_LOW] <= w <= op[OP_W_HIGH]:
        return True
    s = op[OP_SHAPE:OP_SHAPE_END]
    au = abs(u)
    m2 = op[OP_MARGIN] * op[OP_MARGIN]
    for we in (op[OP_W_LOW], op[OP_W_HIGH]):
        du = au - side_u(we, s)
        dw = w - we
        if du * du + dw * dw <= m2:
            return True
    return False


@njit(**JIT_PARALLEL)
def keep_sides(x, z, vx, vz, vx_old, vz_old, kind, comp, op, kin):
    """Keep the fluid on its side of a thin hull; let it change side through an opening.

    A fluid particle of the hull's sea (``OP_SEA``) or cabin (``OP_CABIN``) within
    ``OP_REACH`` of the plating's mid-surface that is found on the wrong side of it has
    either passed through the open opening or been pushed through the plating:

    * through the opening (the nearest mid-surface point lies in the opening or within
      ``OP_MARGIN`` of one of its edges, :func:`in_opening_band`, so that a particle
      rounding the plating's end counts):
      it takes the compartment of the side it is on;
    * through the plating: it is put back at its mirror image across the mid-surface and the
      velocity component (relative to the hull) that carried it through is removed, from
      both Verlet velocity levels. Plating thinner than the kernel support holds the fluid
      by the pressure of its wall layers alone; where a large pressure difference across it
      meets a sparse wall (at a convex bilge, beside the opening), a particle can be pressed
      through, and it must not cross.

    Ghosts of variable resolution are kept on their side too: one that turns active must
    not find itself across the plating. The stepper applies the guard again after the
    refinement has put the ghosts at their families' centres of mass (which, where a
    family parts round a bilge, may lie across the plating) and before the lists are built
    (:meth:`sph.engine.stepper.Stepper._neighbours`), so that between rebuilds a ghost is
    not moved away from where the lists were built."""
    a = int(op[OP_SEA])
    b = int(op[OP_CABIN])
    g = int(op[OP_GROUP])
    s = op[OP_SHAPE:OP_SHAPE_END]
    reach = op[OP_REACH]
    opened = op[OP_OPEN] != 0.0
    ct = math.cos(kin[g, 2])
    st = math.sin(kin[g, 2])
    for i in prange(x.shape[0]):
        ci = comp[i]
        if kind[i] != FLUID or (ci != a and ci != b):
            continue
        rx = x[i] - kin[g, 0]
        rz = z[i] - kin[g, 1]
        u = ct * rx + st * rz  # the keel frame (keel_frame), with the angle's cos and sin
        w = -st * rx + ct * rz + op[OP_KG]  # taken once
        # beyond the outline's bounding box by the reach: |sdf| >= reach, nothing to do
        if abs(u) - s[0] >= reach or s[1] - w >= reach or w - s[2] >= reach:
            continue
        d = sdf(u, w, s)
        if abs(d) >= reach or (d < 0.0) == (ci == b):
            continue
        nu, nw = _normal(u, w, s)
        if opened:
            fu = u - d * nu
            fw = w - d * nw
            if in_opening_band(fu, fw, op):
                comp[i] = b if d < 0.0 else a
                continue
        u -= 2.0 * d * nu
        w -= 2.0 * d * nw
        rx = ct * u - st * (w - op[OP_KG])
        rz = st * u + ct * (w - op[OP_KG])
        x[i] = kin[g, 0] + rx
        z[i] = kin[g, 1] + rz
        nx = ct * nu - st * nw
        nz = st * nu + ct * nw
        sign = 1.0 if ci == a else -1.0  # sea moves outwards, cabin inwards
        wx = kin[g, 3] - kin[g, 5] * rz
        wz = kin[g, 4] + kin[g, 5] * rx
        vn = ((vx[i] - wx) * nx + (vz[i] - wz) * nz) * sign
        if vn < 0.0:
            vx[i] -= sign * vn * nx
            vz[i] -= sign * vn * nz
        vn = ((vx_old[i] - wx) * nx + (vz_old[i] - wz) * nz) * sign
        if vn < 0.0:
            vx_old[i] -= sign * vn * nx
            vz_old[i] -= sign * vn * nz
