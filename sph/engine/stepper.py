"""The physics stepper: one case's particles advanced step by step, with run-time checks
and sampled diagnostics.

Plain Python that drives the numba kernels of the engine. One step:

1. place moving walls at time ``t`` (:func:`sph.engine.walls.place_walls`),
2. when a particle has moved half the skin since the last sort (or left the domain): sort
   particles by cell and rebuild the Verlet lists (:mod:`sph.engine.neighbours`); remove
   the particles that left the domain, or stop,
3. pressures: Tait EOS for the fluid, extrapolation for the walls,
4. derivatives (:func:`sph.engine.fluid.interact`; delta-SPH gradient first if selected),
5. MLS re-initialisation when due, then the Verlet update (:mod:`sph.engine.integrator`).

The stepper knows nothing of files, signals or schedules: the run driver
(:class:`sph.driver.Simulation`) loops it, writes its output and checkpoints. Its whole
state goes in and out through :meth:`Stepper.get_state` and :meth:`Stepper.set_state`.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field

import numpy as np

from sph.engine.config import CaseConfig, ConfigError
from sph.engine.eos import cavitation_floor, fluid_pressures, tait_density
from sph.engine.filters import mls_density, renormalised_density_gradient
from sph.engine.fluid import interact, pair_work
from sph.engine.integrator import max_speed_accel, time_step, verlet_update
from sph.engine.jit import set_threads
from sph.engine.neighbours import (
    INNER_SKIN,
    SKIN,
    CellGrid,
    NeighbourList,
    moved_or_outside,
)
from sph.engine.opening import no_opening
from sph.engine.particles import FLOAT_FIELDS, FLUID, GHOST, INT_FIELDS, WALL, Particles
from sph.engine.probes import point_pressures, surface_heights
from sph.engine.refinement import (
    BUFFER,
    PACK_BULK,
    PACK_RELAX,
    active_fluid,
    assign,
    ghost_diffusion,
    ghost_fields,
    ghost_sources,
    in_reach,
    level_counts,
    levels_at,
    pack_boxes,
    packing_density,
    packing_fraction,
    spawn,
    wall_contact,
)
from sph.engine.scales import Scales
from sph.engine.shifting import apply_shift, shift_params, shifting_active
from sph.engine.surface import FREE_SURFACE, NONE, WALL_TENSION, free_surface
from sph.engine.volume import VOLUME_STRIDE, VolumeCorrection
from sph.engine.walls import (
    fixed_kinematics,
    keep_in_tank,
    listed_with,
    place_walls,
    wall_forces,
    wall_lists,
    wall_normals,
    wall_pressure,
)

log = logging.getLogger(__name__)


class SimulationError(RuntimeError):
    """A run that blew up; names the step, the simulated time and the cause."""

    def __init__(self, step: int, t: float, cause: str):
        self.step, self.t, self.cause = step, t, cause
        super().__init__(f"simulation stopped at step {step}, t = {t:.6g} s: {cause}")


@dataclass
class Record:
    """Time series buffers filled at every output sample."""

    time: list = field(default_factory=list)
    series: dict = field(default_factory=dict)
    surface: list = field(default_factory=list)
    pressure: list = field(default_factory=list)

    def add(self, t: float, values: dict, surface, pressure) -> None:
        self.time.append(t)
        for k, v in values.items():
            self.series.setdefault(k, []).append(v)
        self.surface.append(surface)
        self.pressure.append(pressure)

    def restore(self, state: dict) -> None:
        """Take the ``record.*`` entries of a state (:meth:`Stepper.get_state`)."""
        time = state["record.time"]
        n = len(time)
        self.time = time.tolist()
        self.surface = list(state["record.surface"]) if n else []
        self.pressure = list(state["record.pressure"]) if n else []
        self.series = {}
        for key, value in state.items():
            if key.startswith("record.series."):
                name = key[len("record.series."):]
                self.series[name] = value.tolist() if value.ndim == 1 else list(value)


class StateMismatch(ValueError):
    """A state (:meth:`Stepper.set_state`) that does not fit this stepper."""


#: the largest speed over c0 at which the flow stays weakly compressible (density errors of
#: the order of its square, 1 %); a run warns once past it
MACH_LIMIT = 0.1

#: scalar state entries of a stepper: name -> type
STATE_SCALARS = {"t": float, "step": int, "dt": float, "volume0": float, "n_fluid": int,
                 "n_lost": int, "warned_c0": bool, "n_spawned": int, "n_removed": int,
                 "n_guarded": int}
#: scalar entries that states written by earlier versions lack, with the value they stand for
#: there (``n_guarded``: before the tank's guard, no particle was guarded)
STATE_SCALAR_DEFAULTS = {"n_guarded": 0}


class Stepper:
    """The physics of one prepared case: evaluate, advance, check, sample.

    Parameters
    ----------
    cfg : CaseConfig
        Validated configuration.
    setup : CaseSetup
        Particles and case data (:class:`sph.cases.base.CaseSetup`, built by the case's
        ``setup``, :func:`sph.cases.setup`).
    """

    def __init__(self, cfg: CaseConfig, setup):
        self.cfg = cfg
        self.threads = set_threads(cfg.numerics.threads)
        self.setup = setup
        num, fl = cfg.numerics, cfg.fluid
        #: dx, h, kernel parameters, support radius, c0 and B, derived once
        self.scales = Scales.of(num, fl, self.setup.depth)
        self.parts = self.setup.particles
        #: cells and Verlet lists reach the kernel support plus a skin (SKIN of it), so that
        #: they stay valid until a particle has moved half the skin
        self.list_radius = self.scales.support * (1.0 + SKIN)
        #: the inner lists of the fluid pair loop, refreshed from the Verlet lists when a
        #: particle has moved half their thinner skin (INNER_SKIN)
        self.inner_radius = self.scales.support * (1.0 + INNER_SKIN)
        self.grid = CellGrid(*self.setup.bounds, self.list_radius)
        self.gx, self.gz = 0.0, -fl.gravity
        #: refinement boxes (:mod:`sph.engine.refinement`); none: uniform resolution
        self._box_list = list(num.refinement) + list(self.setup.refinement)
        self.boxes = pack_boxes(self._box_list)
        #: the boxes as placed (the bodies at their initial places), the wall group each
        #: follows (0: fixed) and those groups' initial kinematics (:meth:`_move_boxes`)
        self._boxes0 = self.boxes.copy()
        groups = list(self.setup.refinement_groups) or [0] * len(self.setup.refinement)
        self._box_groups = np.array([0] * len(num.refinement) + groups, dtype=np.int64)
        self._kin0 = fixed_kinematics(1 + len(self.setup.motions))
        for k, motion in enumerate(self.setup.motions, start=1):
            self._kin0[k] = motion.kinematics(0.0)
        self.variable = len(self.boxes) > 0
        if self.variable:
            log.warning("numerics.refinement: variable resolution is experimental "
                        "(docs/model.md, 'Variable resolution')")
            self._refine_initial()
        #: the finest level's smoothing length ratio: the time step and the lists' skins
        self.max_level = max((b.level for b in self._box_list), default=0)
        self.hs_min = 2.0 ** -self.max_level
        #: under variable resolution, the volume correction on a grid of the coarsest
        #: spacing (sph.engine.volume)
        self.volume = (VolumeCorrection(self.setup.bounds, num.dx) if self.variable
                       else None)
        #: children made and ghosts removed (:mod:`sph.engine.refinement`) so far
        self.n_spawned = 0
        self.n_removed = 0
        self.nlist = NeighbourList()
        self._listed = None  # the particle set the lists were built for
        self.kin = fixed_kinematics(1 + len(self.setup.motions))
        #: rigid bodies that move under fluid forces (each spans one or more wall groups)
        self.bodies = list(self.setup.bodies)
        nb = len(self.kin)
        self._fx, self._fz, self._mom = np.zeros(nb), np.zeros(nb), np.zeros(nb)
        self.visc_coef = 2.0 * num.alpha * self.h * self.c0
        self.delta_coef = (num.delta * self.h * self.c0
                           if num.density_filter in ("delta", "ddt") else 0.0)
        #: rho0 / c0^2: the hydrostatic form of the diffusive term (0: renormalised form)
        self.ddt_rho = (fl.rho0 / self.c0**2 if num.density_filter == "ddt" else 0.0)
        #: variable resolution with no density filter: the diffusive term over the pairs
        #: with ghosts alone, in the hydrostatic form (sph.engine.refinement.ghost_diffusion)
        self._ghost_exchange = self.variable and num.density_filter == "none"
        self._ghost_coef = num.delta * self.h * self.c0
        #: its hydrostatic density difference of a pair, ``hx dx + hz dz``
        self._ghost_h = (-fl.rho0 / self.c0**2 * self.gx, -fl.rho0 / self.c0**2 * self.gz)
        #: particle shifting ``[coef, W(dx), cap]`` (:mod:`sph.engine.shifting`; coef 0: off)
        self.shift = shift_params(num.shifting, num.cfl, num.c_factor, self.kp, num.dx)
        #: the pressure sum of fluid and wall particles (:mod:`sph.engine.surface`); the
        #: free-surface flags are computed only when the rule needs them
        self.tension = WALL_TENSION[num.wall_tension]
        #: the density of numerics.pressure_floor (0: none; sph.engine.eos.cavitation_floor)
        self._rho_floor = (0.0 if num.pressure_floor is None else
                           tait_density(num.pressure_floor, fl.rho0, self.b, fl.gamma))
        #: damage opening parameters for the kernels (:mod:`sph.engine.opening`)
        self.op = (self.setup.opening.params if self.setup.opening is not None
                   else no_opening())
        self.force_scale = (self.setup.force_scale if self.setup.force_scale is not None
                            else np.ones(int(self.parts.comp.max()) + 1))
        self._allocate_work()
        #: objects whose state a checkpoint must hold besides the particles: each has
        #: ``get_state() -> dict`` (numpy arrays and scalars) and ``set_state(dict)``
        self.stateful = list(self.bodies) + list(self.setup.events)
        #: inflow and outflow regions (:mod:`sph.engine.openbc`; also in ``setup.events``)
        self.open_boundary = self.setup.open_boundary
        self.t = 0.0
        self.step = 0
        self.dt = 0.0
        self.n_fluid = int(np.sum(active_fluid(self.parts)))
        #: fluid particles that left the domain and were removed (:meth:`_exclude`)
        self.n_lost = 0
        #: times a fluid particle found through the tank's fixed walls was put back
        #: (:meth:`_guard_tank`)
        self.n_guarded = 0
        fmask = active_fluid(self.parts)
        self.volume0 = float(np.sum(self.parts.m[fmask] / self.parts.rho[fmask]))
        self.record = Record()
        self.warned_c0 = False
        probes = cfg.probes
        self._surf_x = np.array([p.x for p in probes.surface], dtype=np.float64)
        self._pres_x = np.array([p.x for p in probes.pressure], dtype=np.float64)
        self._pres_z = np.array([p.z for p in probes.pressure], dtype=np.float64)
        self._zfloor = self.setup.bounds[2]

    # the scales the kernels need, as :attr:`scales` derives them
    @property
    def h(self) -> float:
        return self.scales.h

    @property
    def kp(self) -> np.ndarray:
        return self.scales.kp

    @property
    def c0(self) -> float:
        return self.scales.c0

    @property
    def b(self) -> float:
        return self.scales.b

    def _wall_reach(self):
        """The wall particles the wall loops do, None (all) at uniform resolution. Under
        refinement (:meth:`_mark_ghosts`) those within reach of active fluid
        (:func:`sph.engine.refinement.in_reach`), for the pressure and for the forces on
        bodies alike: a body takes the reaction of every push its wall particles give the
        active fluid, whatever level's region they lie in. A family active at a coarser
        level inside a finer box (:func:`sph.engine.refinement.assign`) pushes on the
        hull's coarse layers, and its fine children, ghosts, push on nothing: left out,
        its share of the hull's pressure was lost (docs/validation/refinement.md)."""
        return self._reach if self.variable else None

    def _hs(self, parts):
        """The smoothing length ratios the wall and list loops take: None at uniform
        resolution, so that they are compiled without them."""
        return parts.hs if self.variable else None

    def _refine_initial(self) -> None:
        """Give the fluid and the walls inside the refinement boxes children down to their
        level (:func:`spawn`, :func:`assign`); a box must overlap the domain, and one whose
        edge meets a fixed wall of the tank is warned of (:func:`wall_contact`)."""
        xmin, xmax, zmin, zmax = self.setup.bounds
        p = self.parts
        dx, guard = self.cfg.numerics.dx, self.setup.tank_guard
        n_cfg = len(self.cfg.numerics.refinement)
        for k, b in enumerate(self._box_list):
            key = (f"numerics.refinement[{k}]" if k < n_cfg
                   else "the case's refinement (geometry.refine_hull)")
            if b.x[1] <= xmin or b.x[0] >= xmax or b.z[1] <= zmin or b.z[0] >= zmax:
                raise ConfigError(key, f"the box x = {list(b.x)}, z = {list(b.z)} m lies "
                                  f"outside the domain x in [{xmin:g}, {xmax:g}], z in "
                                  f"[{zmin:g}, {zmax:g}] m")
            contact = wall_contact((*b.x, *b.z), guard, dx) if guard is not None else None
            if contact is not None:
                log.warning("%s: the box's %s edge meets the tank's %s at x = %.2f, z = %.2f "
                            "m; a family that changes level beside a wall is not held by it, "
                            "and a flow across such an edge packs and gains energy there "
                            "(docs/validation/refinement.md, 'A sloshing tank'): keep the "
                            "edges the flow crosses a few spacings off the walls", key,
                            *contact)
        parts, _ = spawn(p, self.boxes, dx, self._grad_rho(), fluid_only=False)
        self.parts, _ = assign(parts, self.boxes, dx, hysteresis=False)

    def _grad_rho(self) -> tuple[float, float]:
        """The hydrostatic density gradient (rho0 / c0^2) g (:func:`spawn`)."""
        k = self.cfg.fluid.rho0 / self.c0**2
        return k * self.gx, k * self.gz

    def _refine(self) -> None:
        """Give children to the fluid particles that reached a finer box's buffer, mark
        every fluid particle active or a ghost, remove the ghosts beyond their buffer
        (:mod:`sph.engine.refinement`)."""
        dx = self.cfg.numerics.dx
        self._move_boxes()
        parts, n_new = spawn(self.parts, self.boxes, dx, self._grad_rho())
        parts, n_gone = assign(parts, self.boxes, dx)
        if parts is not self.parts:
            self.n_spawned += n_new
            self.n_removed += n_gone
            self.parts = parts
            self._allocate_work()

    def _move_boxes(self) -> None:
        """Move each box that follows a wall group by that group's displacement since the
        start (translation only: a box is wide enough for the hull's roll), so that a
        drifting hull keeps its fine region about it. Checked at every rebuild of the
        lists; a box is moved only once its group is ``setup.refinement_step`` or more
        (in x or z) from where the box was last placed for it, so that its edges stand
        still while the hull oscillates about its drift (edges swept back and forth split
        and merge the families on them every wave period). The boxes as placed are part of
        the state (:meth:`get_state`)."""
        g = self._box_groups
        if not g.any():
            return
        shift = self.kin[g, :2] - self._kin0[g, :2]
        placed = np.column_stack([self.boxes[:, 0] - self._boxes0[:, 0],
                                  self.boxes[:, 2] - self._boxes0[:, 2]])
        step = self.setup.refinement_step
        move = (g > 0) & np.any(np.abs(shift - placed) >= step, axis=1)
        if not move.any():
            return
        self.boxes[move, 0:2] = self._boxes0[move, 0:2] + shift[move, 0:1]
        self.boxes[move, 2:4] = self._boxes0[move, 2:4] + shift[move, 1:2]
        # fixed walls got their fine layers at the start, within the boxes as placed then:
        # a moving box must not take in any other
        p, pad = self.parts, BUFFER * self.cfg.numerics.dx
        fixed = np.nonzero((p.kind == WALL) & (p.body == 0))[0]
        for b in np.nonzero(move)[0]:
            now = levels_at(p.x[fixed], p.z[fixed], self.boxes[b:b + 1], pad)
            then = levels_at(p.x[fixed], p.z[fixed], self._boxes0[b:b + 1], pad)
            if np.any(now > then):
                k = fixed[np.argmax(now > then)]
                raise SimulationError(self.step, self.t, (
                    f"the level-{int(self.boxes[b, 4])} refinement box following wall group "
                    f"{int(g[b])} reached the fixed wall at x = {p.x[k]:.2f} m, z = "
                    f"{p.z[k]:.2f} m, which has no layers of that level (the group moved "
                    f"{shift[b, 0]:+.2f} m, {shift[b, 1]:+.2f} m); place the body farther "
                    f"from the walls"))

    def _allocate_work(self) -> None:
        """Per-particle work arrays; call again when the number of particles changes."""
        n = self.parts.n
        self._pf = np.zeros((n, 3)) if self.bodies else None
        self._grx = np.zeros(n)
        self._grz = np.zeros(n)
        self._rho_buf = np.zeros(n)
        self._pk = pair_work(n)
        # the weight each ghost acts with, fitted with it (ghost_fields)
        self._gw = np.ones(n) if self.variable else None
        # each fluid particle's packing fraction and the density factor it took (_pack)
        self._phi = np.zeros(n) if self.variable else None
        self._rho_sum = np.zeros(n) if self.variable else None
        self._pack_f = np.ones(n) if self.variable else None
        # numerics.wall_damping: each fluid particle's direction towards its walls
        damp = self.cfg.numerics.wall_damping
        self._wnx = np.zeros(n) if damp else None
        self._wnz = np.zeros(n) if damp else None
        # the fluid particles with a wall in their inner list (listed_with), at each refresh
        self._walled = np.zeros(n, dtype=np.bool_) if damp else None
        # and the walls of their inner lists (wall_lists), for the wall normals
        self._wall_start = (np.zeros(n + 1, dtype=NeighbourList.DTYPE_START) if damp
                            else None)
        self._wall_index = np.zeros(0, dtype=NeighbourList.DTYPE_INDEX)
        # with the ghosts' density exchange, those with a ghost in it
        self._ghosted = np.zeros(n, dtype=np.bool_) if self._ghost_exchange else None
        need = self.tension == FREE_SURFACE
        self._lam = np.ones(n) if need else None
        self._surf = np.zeros(n, dtype=np.bool_) if need else None

    # ------------------------------------------------------------------ physics
    def _kinematics(self, t: float) -> None:
        for k, motion in enumerate(self.setup.motions, start=1):
            self.kin[k] = motion.kinematics(t)

    def evaluate(self) -> None:
        """Place walls, sort, and compute pressures and time derivatives at ``self.t``."""
        p = self.parts
        if self.setup.motions:
            self._kinematics(self.t)
            place_walls(p.x, p.z, p.vx, p.vz, p.bx, p.bz, p.kind, p.body, self.kin)
        for event in self.setup.events:
            event.apply(self)  # may replace self.parts
        self._guard_tank()
        self._neighbours()
        p = self.parts
        g = self.grid
        fl = self.cfg.fluid
        if self.variable:
            ghost_fields(p.x, p.z, p.vx, p.vz, p.rho, p.vx_old, p.vz_old, p.rho_old, p.m,
                         p.kind, p.body, p.comp, p.hs, *self._sources, self.kp, self.op,
                         self.kin, self._reach, self._rebuilt, self._grad_rho(), self._gw)
        if self._rho_floor:
            cavitation_floor(p.rho, p.rho_old, p.kind, self._rho_floor)
        fluid_pressures(p.rho, p.kind, p.p, fl.rho0, self.b, fl.gamma)
        hs = self._hs(p)
        wall_pressure(p.x, p.z, p.rho, p.p, p.m, p.kind, p.body, p.comp, hs, self.kp, self.gx,
                      self.gz, self.kin, fl.rho0, self.b, fl.gamma, self.cfg.numerics.dx**2,
                      self.op, self.nlist.start, self.nlist.inner, self.nlist.inner_end,
                      self.tension != NONE, self._wall_reach())
        if self._wnx is not None:
            wall_normals(p.x, p.z, p.m, p.rho, p.kind, p.body, p.comp, hs, self.kp, self.op,
                         self.kin, self._wall_start, self._wall_index, self._walled, self._wnx,
                         self._wnz)
        if self._surf is not None:
            free_surface(p.x, p.z, p.m, p.rho, p.kind, p.body, p.comp, hs, self.kp, self.op,
                         self.kin, self.nlist.start, self.nlist.inner, self.nlist.inner_end,
                         self._lam, self._surf)
        if self.delta_coef and not self.ddt_rho:
            renormalised_density_gradient(p.x, p.z, p.rho, p.m, p.kind, p.comp, p.hs,
                                          g.cell_of, g.cell_start, g.ncx, self.kp, self._grx,
                                          self._grz, self.op, self.kin)
        interact(p.x, p.z, p.vx, p.vz, p.rho, p.p, p.m, p.kind, p.body, p.comp, p.hs,
                 g.cell_of, g.cell_start, g.ncx, self.kp, self.visc_coef, self.gx, self.gz,
                 self.delta_coef, self.ddt_rho, self._grx, self._grz, p.ax, p.az, p.drho,
                 self.op, self.kin, self.shift, p.sx, p.sz, self._pk, self.nlist.start,
                 self.nlist.inner, self.nlist.inner_end, self.variable, self.tension,
                 self._surf, self._gw, self._wnx, self._wnz)
        if self._ghosted is not None:
            # the ghosts' density exchange (under the other filters the ghosts are in it)
            ghost_diffusion(p.x, p.z, p.rho, p.m, p.kind, p.body, p.comp, p.hs, self.kp,
                            self.op, self.kin, self.nlist.start, self.nlist.inner,
                            self.nlist.inner_end, self._ghosted, self._gw, self._ghost_coef,
                            *self._ghost_h, p.drho)
        if self.open_boundary is not None:
            self.open_boundary.freeze(p)
        if self.variable:  # a ghost moves with its interpolated velocity
            ghost = p.body == GHOST
            for a in (p.ax, p.az, p.drho, p.sx, p.sz):
                a[ghost] = 0.0
        if self.bodies:
            wall_forces(p.x, p.z, p.rho, p.p, p.m, p.kind, p.body, p.comp, hs, self.kp,
                        self.kin, len(self.kin), self._fx, self._fz, self._mom, self._pf,
                        self.force_scale, self.op, self.nlist.start, self.nlist.inner,
                        self.nlist.inner_end, self.tension, self._surf,
                        self._wall_reach())
            for body in self.bodies:
                body.collect_forces(self._fx, self._fz, self._mom)

    def _neighbours(self) -> None:
        """Sort by cell and rebuild the Verlet lists when a particle has moved half the skin
        since the last sort, left the domain, or the particle set changed; refresh the inner
        lists when a particle has moved half their skin."""
        p, g, nl = self.parts, self.grid, self.nlist
        # each level's skin scales with its h, as its lists do (moved_or_outside)
        half_skin = 0.5 * (self.list_radius - self.scales.support)
        hs = self._hs(p)
        self._rebuilt = False
        if self._listed is p and not moved_or_outside(p.x, p.z, p.x_sort, p.z_sort,
                                                      half_skin * half_skin, *g.bounds, hs):
            half_inner = 0.5 * (self.inner_radius - self.scales.support)
            if moved_or_outside(p.x, p.z, p.x_inner, p.z_inner, half_inner * half_inner,
                                *g.bounds, hs):
                self._refresh_inner()
            return
        if self.variable:
            self._refine()
            p = self.parts
            # the refinement put the ghosts at their families' centres of mass: the events
            # act again (the hull guard puts one found across the plating back on its
            # side, the tank's guard one found through its floor), so that the lists are
            # built at the places the particles keep
            for event in self.setup.events:
                event.apply(self)
            self._guard_tank()
        if self.open_boundary is not None:
            self.parts = self.open_boundary.rebuild(p)
            if self.parts is not p:
                p = self.parts
                self._allocate_work()
        if g.sort(p.x, p.z):
            self._exclude()
            p = self.parts
            g.sort(p.x, p.z)
        p.permute(g.order)
        p.x_sort[:] = p.x
        p.z_sort[:] = p.z
        nl.build(p.x, p.z, p.kind, g, self.list_radius, self._hs(p))
        self._refresh_inner()
        self._listed = p
        self._mark_ghosts()
        if self.variable:
            self._pack()
        self._rebuilt = True

    def _pack(self) -> None:
        """Under variable resolution, bring the density of the active fluid in the bulk
        towards the one its particles' spacing gives (:func:`packing_density`), at every
        rebuild of the lists.

        The continuity equation keeps a particle's density in step with its neighbours'
        spacing only while they move smoothly. The refinement moves particles in jumps: a
        ghost goes to its family's centre of mass, a family turns active at another level
        where its ghosts were, a brood of ghost children is made afresh. Each jump packs
        some active particles closer (or looser) than their densities say, and nothing
        undoes it: such fluid is heavier than its pressure holds, sinks, and weakens the
        pressure gradient it lies in. In the refined Table I runs the packing fraction
        (:func:`packing_fraction`) of the active fluid beside the hull grew from 1.000 at t1
        to a median of 1.07-1.13 twenty seconds later, the level-0 fluid below the hull to
        1.07 down to the tank's floor, and the intact ship sank 0.8 m below its
        uniform-resolution draught (docs/findings.md)."""
        p, nl = self.parts, self.nlist
        packing_fraction(p.x, p.z, p.rho, p.m, p.kind, p.comp, p.body, p.hs, self.kp, self.op,
                         self.kin, nl.start, nl.index, self._phi, self._rho_sum)
        packing_density(p.x, p.z, p.rho, p.rho_old, p.kind, p.comp, p.body, p.hs, self.kp,
                        self.op, self.kin, nl.start, nl.index, self._phi, self._rho_sum,
                        PACK_BULK, PACK_RELAX, self._pack_f)

    def _seed_pairs(self, state: dict[str, np.ndarray]) -> list[tuple[int, object]]:
        """``(index in the seed state, object)`` of the stateful objects that take a seed
        state's (:meth:`set_state` with ``seed``): those that are not ``SEEDLESS``, matched
        in order by type."""
        if "stateful.types" not in state:
            raise StateMismatch("the state names no object types (written by an earlier "
                                "version): it can only resume its own run")
        types = str(state["stateful.types"]).split()
        started = state["stateful.started"]
        t = float(state["t"])
        if np.any(started):
            k = int(np.argmax(started))
            raise StateMismatch(f"its {types[k]} had already acted at t = {t:.6g} s")
        own = [obj for obj in self.stateful if not getattr(obj, "SEEDLESS", False)]
        for obj in self.stateful:
            if getattr(obj, "SEEDLESS", False) and obj.started_by(t):
                raise StateMismatch(f"it is at t = {t:.6g} s, not before this case's "
                                    f"{type(obj).__name__} acts ({obj.describe()})")
        theirs = [k for k, free in enumerate(state["stateful.seedless"]) if not free]
        if [types[k] for k in theirs] != [type(obj).__name__ for obj in own]:
            mine = " ".join(type(o).__name__ for o in self.stateful)
            raise StateMismatch(f"its objects ({' '.join(types) or 'none'}) are not this "
                                f"case's ({mine or 'none'}) apart from events that have not "
                                "acted")
        return list(zip(theirs, own, strict=True))

    def _mark_ghosts(self) -> None:
        """The ghosts and walls within reach of active particles (:func:`in_reach`) and the
        particles each ghost is fitted from (:func:`ghost_sources`), at the positions the
        lists were built at."""
        if not self.variable:
            return
        p = self.parts
        self._reach = np.zeros(p.n, dtype=np.bool_)
        in_reach(self.nlist.start, self.nlist.index, p.kind, p.body, self._reach)
        self._sources = ghost_sources(p.x_sort, p.z_sort, p.kind, p.body, p.hs, self.grid,
                                      self.list_radius)

    def _refresh_inner(self) -> None:
        p = self.parts
        p.x_inner[:] = p.x
        p.z_inner[:] = p.z
        self.nlist.refresh(p.x, p.z, self.inner_radius, self._hs(p))
        self._mark_listed()

    def _mark_listed(self) -> None:
        """Under ``numerics.wall_damping``, the fluid particles whose inner list holds a
        wall, and with the ghosts' density exchange those whose list holds a ghost
        (:func:`listed_with`): the wall normals and the exchange are summed for them alone."""
        if self._walled is not None or self._ghosted is not None:
            nl = self.nlist
            listed_with(self.parts.kind, self.parts.body, nl.start, nl.inner, nl.inner_end,
                        self._walled, self._ghosted)
        if self._walled is not None:
            self._wall_index = wall_lists(self.parts.kind, nl.start, nl.inner, nl.inner_end,
                                          self._walled, self._wall_start, self._wall_index)

    def _guard_tank(self) -> None:
        """Put back the fluid particles found through the tank's fixed walls
        (:func:`sph.engine.walls.keep_in_tank`, the case's ``tank_guard``), and say so
        the first time and as their count passes each power of ten."""
        guard = self.setup.tank_guard
        if guard is None:
            return
        p = self.parts
        n = keep_in_tank(p.x, p.z, p.vx, p.vz, p.vx_old, p.vz_old, p.kind, guard)
        if n:
            before = self.n_guarded
            self.n_guarded += n
            if before == 0 or len(str(self.n_guarded)) > len(str(before)):
                log.warning("t = %.6g s (step %d): %d fluid particle(s) found through the "
                            "tank's fixed walls put back (%d so far): the walls did not hold "
                            "them", self.t, self.step, n, self.n_guarded)

    def _exclude(self) -> None:
        """Remove the fluid particles that left the domain, within the budget
        ``run.max_lost_fraction`` of the initial fluid particles (as SPH codes exclude
        particles that escape through a wall); stop the run for a NaN position, a wall
        particle outside the domain or a spent budget."""
        p, g = self.parts, self.grid
        xmin, xmax, zmin, zmax = g.bounds
        inside = (p.x >= xmin) & (p.x <= xmax) & (p.z >= zmin) & (p.z <= zmax)
        out = ~inside
        where = (f"the domain x in [{xmin:g}, {xmax:g}], z in [{zmin:g}, {zmax:g}] m")
        if not np.all(np.isfinite(p.x[out]) & np.isfinite(p.z[out])) \
                or np.any(p.kind[out] != FLUID):
            raise SimulationError(self.step, self.t, f"{int(out.sum())} particle(s) left "
                                  f"{where} (or are NaN)")
        lost = out & active_fluid(p)  # a ghost is removed without a word
        n_out = int(lost.sum())
        budget = int(self.cfg.run.max_lost_fraction * self.n_fluid)
        if self.n_lost + n_out > budget:
            raise SimulationError(self.step, self.t, f"{n_out} fluid particle(s) left {where}"
                                  f", {self.n_lost + n_out} in all, more than "
                                  f"run.max_lost_fraction allows ({budget})")
        k = np.nonzero(lost)[0]
        if n_out:
            log.warning("t = %.5g s (step %d): %d fluid particle(s) left %s at (x, z) = %s m, "
                        "speed %s m/s; removed (%d of %d allowed)", self.t, self.step, n_out,
                        where, ", ".join(f"({p.x[i]:.3g}, {p.z[i]:.3g})" for i in k[:5]),
                        ", ".join(f"{math.hypot(p.vx[i], p.vz[i]):.3g}" for i in k[:5]),
                        self.n_lost + n_out, budget)
        self.n_lost += n_out
        self.parts = p.take(inside)
        self._allocate_work()

    def advance(self) -> None:
        """One time step (derivatives at the current level must be up to date)."""
        p, num = self.parts, self.cfg.numerics
        vmax, amax = max_speed_accel(p.vx, p.vz, p.ax, p.az, p.kind)
        self.dt = time_step(num.cfl, self.h * self.hs_min, self.c0, num.alpha, vmax, amax)
        if not self.warned_c0 and vmax > MACH_LIMIT * self.c0:
            self.warned_c0 = True
            log.warning("t = %.4g s: max velocity %.3g m/s exceeds c0/10 = %.3g m/s; "
                        "compressibility errors grow (raise numerics.c_factor)",
                        self.t, vmax, MACH_LIMIT * self.c0)
        s = self.step + 1
        mls_due = num.density_filter == "mls" and s % num.mls_interval == 0
        euler = mls_due or s % num.euler_interval == 0 or self.step == 0
        g = self.grid
        if mls_due:
            mls_density(p.x, p.z, p.rho, p.m, p.kind, p.body, p.comp, p.hs, g.cell_of,
                        g.cell_start, g.ncx, self.kp, self._rho_buf, self.op, self.kin)
            p.rho[:] = self._rho_buf
        verlet_update(p.x, p.z, p.vx, p.vz, p.rho, p.vx_old, p.vz_old, p.rho_old, p.ax, p.az,
                      p.drho, p.kind, self.dt, euler, self.setup.absorber)
        if shifting_active(self.shift):
            apply_shift(p.x, p.z, p.sx, p.sz, p.kind)
        for body in self.bodies:
            body.update(self.dt, euler)
        if self.volume is not None and s % VOLUME_STRIDE == 0:
            self.volume.apply(p, VOLUME_STRIDE * self.dt)
        self.t += self.dt
        self.step = s
        self.evaluate()

    # ------------------------------------------------------------------ checks
    def check(self) -> None:
        """Stop with a :class:`SimulationError` on NaN/inf (any fluid particle) or the density
        of an active fluid particle (not a ghost) out of band."""
        p, run, rho0 = self.parts, self.cfg.run, self.cfg.fluid.rho0
        f = p.kind == FLUID
        for name in ("x", "z", "vx", "vz", "rho", "ax", "az"):
            arr = getattr(p, name)[f]
            if not np.all(np.isfinite(arr)):
                bad = int(np.sum(~np.isfinite(arr)))
                raise SimulationError(self.step, self.t, f"{bad} fluid particle(s) have a "
                                      f"non-finite {name}")
        # the band is the mass-carrying fluid's: a ghost's density is fitted from it
        rho = p.rho[f & (p.body != GHOST)]
        lo, hi = float(rho.min()), float(rho.max())
        if lo < run.density_min * rho0 or hi > run.density_max * rho0:
            raise SimulationError(self.step, self.t, f"fluid density {lo:.5g}..{hi:.5g} "
                                  f"kg/m3 left the band [{run.density_min * rho0:g}, "
                                  f"{run.density_max * rho0:g}] (run.density_min/max)")
        if self.dt and self.dt < 1e-6 * self.h / self.c0:
            raise SimulationError(self.step, self.t, f"time step collapsed to {self.dt:.3g} s")

    # ------------------------------------------------------------------ output
    def sample(self) -> None:
        """Append the current state to the time series."""
        p, fl = self.parts, self.cfg.fluid
        f = active_fluid(p)
        m, vx, vz, rho = p.m[f], p.vx[f], p.vz[f], p.rho[f]
        speed2 = vx * vx + vz * vz
        values = {
            "n_particles": float(f.sum()),
            "dt": self.dt,
            "kinetic_energy": float(0.5 * np.sum(m * speed2)),
            "potential_energy": float(fl.gravity * np.sum(m * p.z[f])),
            "volume_error": float(np.sum(m / rho) / self.volume0 - 1.0),
            "max_velocity": float(np.sqrt(speed2.max())),
            "density_min": float(rho.min()),
            "density_max": float(rho.max()),
        }
        if self.variable:
            values["fluid_mass"] = float(np.sum(m))
            values["n_particles_level"] = level_counts(p, self.max_level)
        if self.bodies:
            values.update(self.bodies[0].motions())
            forces = np.array([b.force for b in self.bodies])
            values["body_force_x"] = forces[:, 0]
            values["body_force_z"] = forces[:, 1]
            values["body_moment"] = forces[:, 2]
        if self.variable:  # the probes and diagnostics see the mass-carrying fluid
            p = p.take(f | (p.kind != FLUID))
        for name, fn in self.setup.diagnostics.items():
            values[name] = fn(p, self.t)
        surf = surface_heights(p.x, p.z, p.m, p.rho, p.kind, p.comp, self.setup.probe_comp,
                               self._surf_x, self.kp,
                               self._zfloor, 0.1 * self.cfg.numerics.dx)
        pres = point_pressures(p.x, p.z, p.m, p.rho, p.p, p.kind, self._pres_x, self._pres_z,
                               self.kp, self.gx, self.gz)
        if self.setup.extra_probes:
            surf = np.concatenate([surf, [fn(p) for fn, _ in self.setup.extra_probes.values()]])
        self.record.add(self.t, values, surf, pres)

    # ------------------------------------------------------------------ state
    def get_state(self) -> dict[str, np.ndarray]:
        """The complete state as named numpy arrays: particles (every field, in the sorted
        order of the last evaluation, with its derivatives), wall kinematics, the scalars
        of :data:`STATE_SCALARS`, the sampled time series (``record.*``) and the state of
        every stateful object (``stateful.K.*``: rigid bodies, the damage opening).
        :meth:`set_state` of a stepper built from the same configuration continues bit for
        bit."""
        out: dict[str, np.ndarray] = {
            "particles.fields": np.array(" ".join(FLOAT_FIELDS) + " | " + " ".join(INT_FIELDS)),
            "particles.f": self.parts.f,
            "particles.i": self.parts.i,
            "kin": self.kin,
            "boxes": self.boxes,  # as placed at the last rebuild (:meth:`_move_boxes`)
        }
        for name, tp in STATE_SCALARS.items():
            out[name] = np.array(tp(getattr(self, name)))
        rec = self.record
        n = len(rec.time)
        out["record.time"] = np.asarray(rec.time, dtype=np.float64)
        for name in ("surface", "pressure"):  # (sample, probe); probes may be none
            out[f"record.{name}"] = (np.asarray(getattr(rec, name), dtype=np.float64) if n
                                     else np.zeros((0, 0)))
        for key, values in rec.series.items():
            out[f"record.series.{key}"] = np.asarray(values, dtype=np.float64)
        out["stateful.count"] = np.array(len(self.stateful))
        # what each object is, so that another case can start from this state
        # (:meth:`set_state` with ``seed``)
        out["stateful.types"] = np.array(" ".join(type(o).__name__ for o in self.stateful))
        seedless = [bool(getattr(o, "SEEDLESS", False)) for o in self.stateful]
        out["stateful.seedless"] = np.array(seedless, dtype=np.bool_)
        out["stateful.started"] = np.array([f and o.started for f, o in
                                            zip(seedless, self.stateful, strict=True)],
                                           dtype=np.bool_)
        for k, obj in enumerate(self.stateful):
            for key, value in obj.get_state().items():
                out[f"stateful.{k}.{key}"] = np.asarray(value)
        return out

    def set_state(self, state: dict[str, np.ndarray], seed: bool = False) -> None:
        """Put a state of :meth:`get_state` into this stepper (built from the same
        configuration); the derivatives come with it, so no evaluation is needed before the
        next :meth:`advance`.

        ``seed``: the state is another case's, one that differs from this one only in
        objects whose state before their event is their initial one (class attribute
        ``SEEDLESS``: the damage opening, which does nothing before t1), taken before any
        such object of either case has acted (``started``, ``started_by(t)``). Those
        objects keep their own state, the others take the seed's in order. The state the
        particles reach before the event is the same whatever the event, so this case
        continues as from t = 0 (``sph run --start-from``).

        Raises
        ------
        StateMismatch
            If the state does not fit (other particle fields, wall groups or objects, or
            particles not in cell order; with ``seed``, an event already passed).
        """
        fields = str(state["particles.fields"])
        if fields != " ".join(FLOAT_FIELDS) + " | " + " ".join(INT_FIELDS):
            raise StateMismatch(f"other particle fields ({fields})")
        f, i = state["particles.f"], state["particles.i"]
        if f.shape[0] != len(FLOAT_FIELDS) or i.shape != (len(INT_FIELDS), f.shape[1]):
            raise StateMismatch(f"particle arrays of shapes {f.shape}, {i.shape} do not fit")
        if state["kin"].shape != self.kin.shape:
            raise StateMismatch(f"{state['kin'].shape[0]} wall groups, this case has "
                                f"{self.kin.shape[0]}")
        pairs = self._seed_pairs(state) if seed else list(enumerate(self.stateful))
        if not seed and int(state["stateful.count"]) != len(self.stateful):
            raise StateMismatch(f"{int(state['stateful.count'])} stateful objects, this case "
                                f"has {len(self.stateful)}")
        parts = Particles(f.shape[1])
        parts.f[:] = f
        parts.i[:] = i
        self.parts = parts
        self._allocate_work()
        self.kin[:] = state["kin"]
        if "boxes" in state:  # (states written before the boxes moved have fixed ones)
            if state["boxes"].shape != self.boxes.shape:
                raise StateMismatch(f"{state['boxes'].shape[0]} refinement boxes, this case "
                                    f"has {self.boxes.shape[0]}")
            self.boxes[:] = state["boxes"]
        for name, tp in STATE_SCALARS.items():
            if name not in state and name in STATE_SCALAR_DEFAULTS:
                setattr(self, name, STATE_SCALAR_DEFAULTS[name])
            else:
                setattr(self, name, tp(state[name][()]))
        for k, obj in pairs:
            prefix = f"stateful.{k}."
            try:
                obj.set_state({key[len(prefix):]: value for key, value in state.items()
                               if key.startswith(prefix)})
            except (KeyError, ValueError) as exc:
                raise StateMismatch(f"state of {type(obj).__name__} does not fit: {exc}"
                                    ) from exc
        self.record.restore(state)
        # the cells and Verlet lists of the restored particles, as they were built: from the
        # positions of the last sort (the counting sort is stable, so sorting by them again
        # leaves the order as it is)
        n_out = self.grid.sort(parts.x_sort, parts.z_sort)
        if n_out or not np.array_equal(self.grid.order, np.arange(parts.n)):
            raise StateMismatch("particles are not in cell order")
        hs = self._hs(parts)
        self.nlist.build(parts.x_sort, parts.z_sort, parts.kind, self.grid, self.list_radius,
                         hs)
        self.nlist.refresh(parts.x_inner, parts.z_inner, self.inner_radius, hs)
        self._mark_listed()
        self._listed = parts
        self._mark_ghosts()
