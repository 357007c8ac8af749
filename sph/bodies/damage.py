r"""Sudden side damage of a cabin: the opening, the pair rule through it, and flooding.

At ``t1`` the plating of the opening (the damaged cabin's side, from the cabin bottom up to
``delta = delta_bar d``) is taken away (Cao et al. 2019, Sec. IV A). From then on two fluid
particles of the sea and of the damaged cabin interact when the straight segment between
them crosses the plating's mid-surface inside the opening, and a fluid particle
that passes through the opening changes compartment when it crosses the mid-surface
(:func:`sph.engine.opening.keep_sides`). Every other pair across the plating stays separated.

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

The kernels' side of it (the packed parameters ``op`` and the line-of-sight tests) is
:mod:`sph.engine.opening`.
"""

from __future__ import annotations

import logging
import math

import numpy as np

from sph.engine.opening import centre, group_of, keep_sides, place_centre, set_centre, set_open
from sph.engine.particles import FLUID

log = logging.getLogger(__name__)


class HullGuard:
    """Keeps the fluid of each hull segment on its side of the plating
    (:func:`sph.engine.opening.keep_sides`);
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
        ``op`` (:func:`sph.engine.opening.pack_opening`), closed.
    opening_pids : array of int
        Original indices (``pid``) of the wall particles of the opening's plating (they stay,
        hidden across the opening; the count is reported).
    """

    #: before t1 the opening does nothing and its state is its initial one: a run may start
    #: from the state of a case that differs from it in the opening alone, or is intact
    #: (:meth:`sph.engine.stepper.Stepper.set_state` with ``seed``)
    SEEDLESS = True

    def __init__(self, time: float, params: np.ndarray, opening_pids: np.ndarray):
        self.time = float(time)
        self.params = np.asarray(params, dtype=np.float64)
        self.opening_pids = np.asarray(opening_pids, dtype=np.int64)
        self.is_open = False

    def apply(self, sim) -> None:
        """Open at ``t1`` (once); called at every evaluation, after the walls are placed
        (the compartments of the particles passing the opening are kept up to date by
        :class:`HullGuard`). Places the opening's quick-test circle at the current
        kinematics."""
        place_centre(self.params, sim.kin[group_of(self.params)])
        if not self.is_open and self.started_by(sim.t):
            self.is_open = True
            set_open(self.params, True)
            log.info("t = %.4g s (step %d): damage opening appears; the %d wall particles of "
                     "its plating are hidden across it", sim.t, sim.step,
                     len(self.opening_pids))

    @property
    def started(self) -> bool:
        """Whether the opening has appeared."""
        return self.is_open

    def started_by(self, t: float) -> bool:
        """Whether the opening has appeared by time ``t`` (as :meth:`apply` decides)."""
        return t >= self.time - 1e-12 * max(1.0, self.time)

    def describe(self) -> str:
        return f"the damage opening appears at t1 = {self.time:.6g} s"

    def get_state(self) -> dict:
        return {"is_open": np.array(int(self.is_open)), "centre": centre(self.params)}

    def set_state(self, state: dict) -> None:
        self.is_open = bool(int(state["is_open"]))
        set_open(self.params, self.is_open)
        set_centre(self.params, state["centre"])


def fluid_volume(m, rho, kind, comp, c) -> float:
    """Volume (m2 per unit length) of the fluid in compartment ``c``."""
    sel = (kind == FLUID) & (comp == c)
    return float(np.sum(m[sel] / rho[sel]))


def orifice_rate(depth_low: float, depth_high: float, gravity: float, cd: float = 0.6):
    r"""Initial inflow (m2/s per unit length) through a side opening spanning the depths
    ``depth_high < depth_low`` below the outside surface into an empty cabin:
    :math:`q = C_d\int\sqrt{2 g y}\,dy = C_d\sqrt{2g}\,\tfrac23\,(y_1^{3/2} - y_0^{3/2})`."""
    return cd * math.sqrt(2.0 * gravity) * 2.0 / 3.0 * (
        max(depth_low, 0.0) ** 1.5 - max(depth_high, 0.0) ** 1.5)
