r"""Rigid bodies moving under fluid forces: 3 DOF in 2D (sway, heave, roll).

Cao et al. (2019), Eqs. (9)-(10): the fluid force per unit length on a body is the reaction of
the fluid--wall pressure terms summed over its wall particles
(:func:`sph.engine.walls.wall_forces`); with strip theory the total force and moment are the
per-unit-length values of each segment times the segment's length. A body here carries its
mass and roll inertia *per unit length* of the simulated strip, so that

.. math:: M\dot{\mathbf{V}} = \mathbf{f} + M\mathbf{g},\qquad I\dot\Omega = m_f,

with :math:`\mathbf{f}, m_f` the force and moment per unit length about the centre of
gravity. Each DOF can be fixed with a mask.

**A light body carrying heavy liquid** (a ship at 75 % fill: a dry part of 9.6 t/m holding
56.6 t/m of cargo) is unstable when coupled explicitly: the liquid's reaction to the body's
acceleration arrives a step late and is larger than the body's own inertia, so each step
overshoots the last (the added-mass instability of partitioned fluid-structure coupling,
Causin, Gerbeau & Nobile 2005, Comput. Methods Appl. Mech. Engrg. 194). Upright in still
water such a ship was thrown 3 m up within half a second. The body therefore takes an
added mass :math:`M_a` per motion (``added_mass``) on both sides of its equation (Soding
2001, Ship Technol. Res. 48), with the acceleration of the two previous evaluations
extrapolated to the present one on the right:

.. math:: (M + M_a)\,\dot V^{n} = f^{n} + M g + M_a \left(2\dot V^{n-1} - \dot V^{n-2}\right),

which is :math:`M \dot V = f + M g` whenever the acceleration changes linearly over two
steps, and stable when :math:`M_a` is at least about a quarter of the liquid's lagged
reaction. ``added_mass`` 0 (the default) is the plain equation.

Why the extrapolation: with the previous acceleration alone on the right (Soding's form),
the body's equation reads :math:`M\dot V = f + Mg - M_a\,\Delta t\,\ddot V` to first order
in the step: a force :math:`M_a \omega^2 \Delta t\, V` in phase with the velocity, a
negative damping of every mode of frequency :math:`\omega` that moves the body. With the
cargo's mass as :math:`M_a` it fed the compression modes of the cargo against the hull
(10-50 Hz in the 75 and 50 % loaded ships at dx = 0.8 m): they grew within 1-3 s, the
walls (which push and never pull) rectified them, and the upright ship rose 0.12 m (50 %)
and 0.25 m (75 %) above its draught in still water. The extrapolated acceleration leaves a
term of order :math:`(\omega\Delta t)^2` instead, and the same modes decay
(``tests/physics/test_bodies.py`` shows both on a body, its cargo on a spring and a lagged
added mass; docs/ship.md the ship runs).

The angle ``theta`` is counter-clockwise in the x-z plane; the output ``roll`` is
:math:`-\theta` in degrees (positive when the body heels towards +x).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sph.schema import spec


@dataclass(frozen=True)
class DofConfig:
    """Which motions are free."""

    sway: bool = spec(True, doc="horizontal motion free")
    heave: bool = spec(True, doc="vertical motion free")
    roll: bool = spec(True, doc="rotation free")


class RigidBody:
    """State of one rigid body (wall groups moving under fluid forces).

    Parameters
    ----------
    mass, inertia : float
        Mass (kg/m) and roll inertia about the centre of gravity (kg m) per unit length.
    cog : pair of float
        Initial centre of gravity (m) in the frame of the first segment.
    dofs : DofConfig
        Free motions.
    gravity : float
        g (m/s2).
    segments : sequence of (group, weight, x_offset)
        The wall groups that carry this body (one per strip segment), the fraction of the
        body's length each stands for (weights sum to 1: strip theory, Cao et al. Eq. 9) and
        the x offset of that segment's tank. A single 2-D body: ``[(group, 1.0, 0.0)]``.
    added_mass : triple of float
        Added mass in sway and heave (kg/m) and added inertia in roll (kg m) of the
        stabilisation of a light body (module docstring); zero: none.
    """

    free = True

    def __init__(self, mass: float, inertia: float, cog, dofs: DofConfig, gravity: float,
                 segments=((1, 1.0, 0.0),), added_mass=(0.0, 0.0, 0.0)):
        self.mass = float(mass)
        self.inertia = float(inertia)
        #: added mass (kg/m) in sway and heave and added inertia (kg m) in roll of the
        #: stabilisation (module docstring)
        self.added = np.array(added_mass, dtype=np.float64)
        self.g = float(gravity)
        self.mask = np.array([dofs.sway, dofs.heave, dofs.roll], dtype=np.float64)
        self.segments = [(int(g), float(w), float(x)) for g, w, x in segments]
        total = sum(w for _, w, _ in self.segments)
        if abs(total - 1.0) > 1e-12:
            raise ValueError(f"segment weights must sum to 1; got {total:g}")
        self.q0 = np.array([cog[0], cog[1], 0.0])
        self.q = self.q0.copy()
        self.v = np.zeros(3)
        self.v_old = np.zeros(3)
        self.a = np.zeros(3)
        #: the acceleration of the evaluation before the last (the stabilisation's
        #: extrapolation, module docstring)
        self.a_prev = np.zeros(3)
        self.force = np.zeros(3)  # fluid fx, fz (N/m) and moment (N) about the cog
        #: force and moment per unit length on each segment (last evaluation)
        self.segment_force = np.zeros((len(self.segments), 3))

    def segment_motion(self, k: int) -> Shifted:
        """Kinematics source of segment ``k``'s wall group."""
        return Shifted(self, self.segments[k][2])

    def kinematics(self, t: float = 0.0) -> np.ndarray:
        """Row of :data:`sph.engine.walls.KIN_COLUMNS` for the wall particles of this body."""
        return np.concatenate([self.q, self.v, self.a])

    def collect_forces(self, fx, fz, mom) -> None:
        """Weighted sum of the per-group forces (arrays indexed by wall group) -> accelerations."""
        for k, (g, _, _) in enumerate(self.segments):
            self.segment_force[k] = (fx[g], fz[g], mom[g])
        w = np.array([s[1] for s in self.segments])
        total = w @ self.segment_force
        self.set_forces(*total)

    def set_forces(self, fx: float, fz: float, moment: float) -> None:
        """Fluid force and moment per unit length -> accelerations (masked)."""
        self.force[:] = (fx, fz, moment)
        if not self.added.any():
            self.a[:] = self.mask * np.array([fx / self.mass, fz / self.mass - self.g,
                                              moment / self.inertia])
            return
        inertia = np.array([self.mass, self.mass, self.inertia])
        predicted = 2.0 * self.a - self.a_prev
        load = np.array([fx, fz - self.mass * self.g, moment]) + self.added * predicted
        self.a_prev[:] = self.a
        self.a[:] = self.mask * load / (inertia + self.added)

    def update(self, dt: float, euler: bool) -> None:
        """Advance with the fluid's Verlet step (see :mod:`sph.engine.integrator`)."""
        self.q += dt * self.v + 0.5 * dt * dt * self.a
        new_v = (self.v if euler else self.v_old) + (1.0 if euler else 2.0) * dt * self.a
        self.v_old[:] = self.v
        self.v[:] = new_v * self.mask

    def get_state(self) -> dict:
        """Everything :meth:`update`, :meth:`kinematics` and the output depend on (for
        checkpoints): position, velocity at both leapfrog levels, the acceleration of the
        last evaluation (it feeds the wall-pressure extrapolation), the one before it (the
        stabilisation's extrapolation) and the fluid forces."""
        return {"q": self.q.copy(), "v": self.v.copy(), "v_old": self.v_old.copy(),
                "a": self.a.copy(), "a_prev": self.a_prev.copy(), "force": self.force.copy(),
                "segment_force": self.segment_force.copy()}

    def set_state(self, state: dict) -> None:
        # a checkpoint written before the stabilisation's extrapolation has no ``a_prev``:
        # the last acceleration stands for it (Soding's form for the first step)
        state = {"a_prev": state["a"], **state}
        for key in ("q", "v", "v_old", "a", "a_prev", "force", "segment_force"):
            target = getattr(self, key)
            value = np.asarray(state[key], dtype=np.float64)
            if value.shape != target.shape:
                raise ValueError(f"body state {key!r} has shape {value.shape}, expected "
                                 f"{target.shape}")
            target[:] = value

    def motions(self) -> dict:
        """Sway (m), heave (m) and roll (degree, positive towards +x) from the start."""
        return {"sway": float(self.q[0] - self.q0[0]), "heave": float(self.q[1] - self.q0[1]),
                "roll": float(-np.degrees(self.q[2]))}


class Shifted:
    """The kinematics of another motion, translated by ``x_offset`` along x (the copy of a
    body or a flap in another strip segment's tank)."""

    def __init__(self, motion, x_offset: float):
        self.motion = motion
        self.x_offset = float(x_offset)

    def kinematics(self, t: float = 0.0) -> np.ndarray:
        k = np.array(self.motion.kinematics(t), dtype=np.float64)
        k[0] += self.x_offset
        return k
