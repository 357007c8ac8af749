r"""Sudden side damage of a cabin: the opening, the pair rule through it, and flooding.

At ``t1`` the plating of the opening (the damaged cabin's side, from the cabin bottom up to
``delta = delta_bar d``) is taken away (Cao et al. 2019, Sec. IV A). From then on two fluid
particles of the sea and of the damaged cabin interact when the straight segment between
them crosses the plating's mid-surface inside the opening, and a fluid particle
that passes through the opening changes compartment when it crosses the mid-surface
(:func:`keep_sides`). Every other pair across the plating stays separated.

The plating is thinner than the kernel support, and each face's wall layers lie behind its
face, across the mid-surface. A fluid particle sees a wall particle of the damaged hull only
along a line of sight through plating: when the segment between them crosses the mid-surface
inside the opening, the wall particle is hidden (:func:`wall_hidden`). The opening's own wall
particles are therefore deactivated, not removed: hidden from everything that looks at them
through the hole, they still stand behind the plating for a particle just beyond the
opening's edge whose line of sight to them crosses the remaining plating. Removing them
instead leaves such a particle without support in the wedge behind the plating's end; under
the hydrostatic head at the lower edge the truncated kernel then pumps particles along the
plating and energy into the sea, until the run blows up (measured: the sea's kinetic energy
grew by about 45 kJ/s per metre of ship after the cabin had filled, and a particle went
through the tank floor 13-26 s after the damage at dx = 0.8 m, with and without the hull
guard and shifting).

The opening travels to the numba kernels as a float array ``op`` (all zeros: no opening):

====  =====================================================================
0     1 when the opening is open
1, 2  compartment ids of the sea and of the damaged cabin
3     wall group of the damaged hull (its row of ``kin``)
4     side: +1 the opening faces +x ("back"), -1 it faces -x ("head")
5, 6  keel-frame heights ``w`` of the opening's lower and upper edges
7-11  mid-surface outline (:func:`sph.hull.shape`)
12    height of the reference point (centre of gravity) above the keel
13    reach: particles within this distance of the mid-surface are checked for their side
14    margin: a particle rounding the opening's edge within this distance of it changes
      compartment (beyond it, a particle on the wrong side was pressed through the plating)
15,16 centre of a circle around the opening's part of the mid-surface, in the hull's frame
      (``u``, ``w`` minus the reference height)
17    squared reach of that circle: its radius plus the kernel support (0: no quick test)
18,19 the same centre in earth coordinates at the current kinematics (updated by
      :class:`DamageOpening` at every evaluation)
====  =====================================================================

The circle makes the line-of-sight test cheap where it cannot succeed: a segment shorter than
the kernel support that crosses the mid-surface inside the opening has both ends within the
reach of the centre, so a pair with one end farther away is answered without the keel-frame
transform and the bisection (the test is exact: it only skips pairs that cannot cross).
"""

from __future__ import annotations

import logging
import math

import numpy as np
from numba import prange

from .hull import sdf
from .jit import JIT, JIT_PARALLEL, njit

log = logging.getLogger(__name__)

OP_SIZE = 20
#: bisection steps locating where a segment crosses the mid-surface (1/1024 of its length)
BISECTIONS = 10


def no_opening() -> np.ndarray:
    return np.zeros(OP_SIZE)


@njit(**JIT)
def keel_frame(x, z, op, kin):
    """Earth ``(x, z)`` -> keel frame ``(u, w)`` of the damaged hull."""
    g = int(op[3])
    ct = math.cos(kin[g, 2])
    st = math.sin(kin[g, 2])
    rx = x - kin[g, 0]
    rz = z - kin[g, 1]
    return ct * rx + st * rz, -st * rx + ct * rz + op[12]


@njit(**JIT)
def crosses_opening(xi, zi, xj, zj, op, kin):
    """True when the segment between two points crosses the mid-surface inside the open
    opening."""
    if op[0] == 0.0:
        return False
    if op[17] > 0.0:
        ex = xi - op[18]
        ez = zi - op[19]
        if ex * ex + ez * ez > op[17]:
            return False
    s = op[7:12]
    ui, wi = keel_frame(xi, zi, op, kin)
    uj, wj = keel_frame(xj, zj, op, kin)
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
    return op[4] * uc > 0.0 and op[5] <= wc <= op[6]


@njit(**JIT)
def passable(xi, zi, xj, zj, ci, cj, op, kin):
    """True when fluid particles of different compartments see each other through the
    open opening (call only when ``ci != cj``)."""
    if op[0] == 0.0:
        return False
    a = int(op[1])
    b = int(op[2])
    if not ((ci == a and cj == b) or (ci == b and cj == a)):
        return False
    return crosses_opening(xi, zi, xj, zj, op, kin)


@njit(**JIT)
def wall_hidden(xf, zf, xw, zw, bw, op, kin):
    """True when a fluid particle and a wall particle of the damaged hull (group ``bw``)
    of the same compartment lie on either side of the open opening: the wall's layers that
    reach across the plating's mid-surface belong to the other side there."""
    if op[0] == 0.0 or bw != int(op[3]):
        return False
    return crosses_opening(xf, zf, xw, zw, op, kin)


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


@njit(**JIT_PARALLEL)
def keep_sides(x, z, vx, vz, vx_old, vz_old, kind, comp, op, kin):
    """Keep the fluid on its side of a thin hull; let it change side through an opening.

    A fluid particle of the hull's sea (``op[1]``) or cabin (``op[2]``) within ``reach``
    (``op[13]``) of the plating's mid-surface that is found on the wrong side of it has
    either passed through the open opening or been pushed through the plating:

    * through the opening (the nearest mid-surface point lies on the opening's side within
      ``op[14]`` of its height range, so that a particle rounding the plating's end counts):
      it takes the compartment of the side it is on;
    * through the plating: it is put back at its mirror image across the mid-surface and the
      velocity component (relative to the hull) that carried it through is removed, from
      both Verlet velocity levels. Plating thinner than the kernel support holds the fluid
      by the pressure of its wall layers alone; where a large pressure difference across it
      meets a sparse wall (at a convex bilge, beside the opening), a particle can be pressed
      through, and it must not cross."""
    a = int(op[1])
    b = int(op[2])
    g = int(op[3])
    s = op[7:12]
    reach = op[13]
    margin = op[14]
    is_open = op[0] != 0.0
    ct = math.cos(kin[g, 2])
    st = math.sin(kin[g, 2])
    for i in prange(x.shape[0]):
        ci = comp[i]
        if kind[i] != 0 or (ci != a and ci != b):
            continue
        u, w = keel_frame(x[i], z[i], op, kin)
        d = sdf(u, w, s)
        if abs(d) >= reach or (d < 0.0) == (ci == b):
            continue
        nu, nw = _normal(u, w, s)
        if is_open:
            fu = u - d * nu
            fw = w - d * nw
            if op[4] * fu > 0.0 and op[5] - margin <= fw <= op[6] + margin:
                comp[i] = b if d < 0.0 else a
                continue
        u -= 2.0 * d * nu
        w -= 2.0 * d * nw
        rx = ct * u - st * (w - op[12])
        rz = st * u + ct * (w - op[12])
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


class HullGuard:
    """Keeps the fluid of each hull segment on its side of the plating (:func:`keep_sides`);
    applied at every evaluation, after the walls are placed and any opening has appeared.

    Parameters
    ----------
    params : list of arrays
        One ``op`` array per hull (the damaged hull's is the opening's own array, so that the
        opening counts once it is open)."""

    def __init__(self, params):
        self.params = list(params)

    def apply(self, sim) -> None:
        p = sim.parts
        for op in self.params:
            keep_sides(p.x, p.z, p.vx, p.vz, p.vx_old, p.vz_old, p.kind, p.comp, op, sim.kin)

    def get_state(self) -> dict:
        return {}

    def set_state(self, state: dict) -> None:
        pass


class DamageOpening:
    """The opening event of one damaged hull.

    Parameters
    ----------
    time : float
        ``t1`` (s); ``math.inf`` for an intact ship.
    params : array
        ``op`` (see the module docstring) with ``op[0] = 0``.
    opening_pids : array of int
        Original indices (``pid``) of the wall particles of the opening's plating (they stay,
        hidden across the opening; the count is reported).
    """

    def __init__(self, time: float, params: np.ndarray, opening_pids: np.ndarray):
        self.time = float(time)
        self.params = np.asarray(params, dtype=np.float64)
        self.opening_pids = np.asarray(opening_pids, dtype=np.int64)
        self.is_open = False

    def apply(self, sim) -> None:
        """Open at ``t1`` (once); called at every evaluation, after the walls are placed
        (the compartments of the particles passing the opening are kept up to date by
        :class:`HullGuard`). Places the opening's centre (``op[18:20]``) at the current
        kinematics."""
        op = self.params
        k = sim.kin[int(op[3])]
        ct, st = math.cos(k[2]), math.sin(k[2])
        op[18] = k[0] + ct * op[15] - st * op[16]
        op[19] = k[1] + st * op[15] + ct * op[16]
        if not self.is_open and sim.t >= self.time - 1e-12 * max(1.0, self.time):
            self.is_open = True
            self.params[0] = 1.0
            log.info("t = %.4g s (step %d): damage opening appears; the %d wall particles of "
                     "its plating are hidden across it", sim.t, sim.step,
                     len(self.opening_pids))

    def get_state(self) -> dict:
        return {"is_open": np.array(int(self.is_open)), "centre": self.params[18:20].copy()}

    def set_state(self, state: dict) -> None:
        self.is_open = bool(int(state["is_open"]))
        self.params[0] = 1.0 if self.is_open else 0.0
        self.params[18:20] = state["centre"]


def fluid_volume(m, rho, kind, comp, c) -> float:
    """Volume (m2 per unit length) of the fluid in compartment ``c``."""
    sel = (kind == 0) & (comp == c)
    return float(np.sum(m[sel] / rho[sel]))


def orifice_rate(depth_low: float, depth_high: float, gravity: float, cd: float = 0.6):
    r"""Initial inflow (m2/s per unit length) through a side opening spanning the depths
    ``depth_high < depth_low`` below the outside surface into an empty cabin:
    :math:`q = C_d\int\sqrt{2 g y}\,dy = C_d\sqrt{2g}\,\tfrac23\,(y_1^{3/2} - y_0^{3/2})`."""
    return cd * math.sqrt(2.0 * gravity) * 2.0 / 3.0 * (
        max(depth_low, 0.0) ** 1.5 - max(depth_high, 0.0) ** 1.5)
