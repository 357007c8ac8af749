"""Run orchestration: the time loop, run-time checks, diagnostics and output.

Plain Python that drives the numba kernels of the physics modules. One step:

1. place moving walls at time ``t`` (:func:`sph.walls.place_walls`),
2. sort particles by cell (:mod:`sph.neighbours`); stop if any left the domain,
3. pressures: Tait EOS for the fluid, extrapolation for the walls,
4. derivatives (:func:`sph.fluid.interact`; delta-SPH gradient first if selected),
5. MLS re-initialisation when due, then the Verlet update (:mod:`sph.integrator`).
"""

from __future__ import annotations

import logging
import math
import signal
import sys
import threading
import time as wallclock
from dataclasses import dataclass, field

import numpy as np

from . import __version__
from .cases import CASES
from .cases.base import CaseSetup, b_coef
from .config import CaseConfig
from .damage import no_opening
from .eos import fluid_pressures
from .filters import mls_density, renormalised_density_gradient
from .fluid import interact
from .integrator import max_speed_accel, time_step, verlet_update
from .jit import set_threads
from .kernels import kernel_params, support_radius
from .neighbours import CellGrid
from .particles import FLUID
from .probes import point_pressures, surface_heights
from .shifting import apply_shift, shift_params
from .walls import fixed_kinematics, place_walls, wall_forces, wall_pressure

log = logging.getLogger(__name__)


class SimulationError(RuntimeError):
    """A run that blew up; names the step, the simulated time and the cause."""

    def __init__(self, step: int, t: float, cause: str):
        self.step, self.t, self.cause = step, t, cause
        super().__init__(f"simulation stopped at step {step}, t = {t:.6g} s: {cause}")


class RunInterrupted(RuntimeError):
    """A run stopped by SIGINT or SIGTERM between two steps; ``checkpoint`` is the file
    written to resume it (None when the run had no checkpoint directory)."""

    def __init__(self, step: int, t: float, signal_name: str, checkpoint=None):
        self.step, self.t, self.signal_name, self.checkpoint = step, t, signal_name, checkpoint
        where = f"; checkpoint {str(checkpoint)!r}" if checkpoint is not None else ""
        super().__init__(f"interrupted by {signal_name} at step {step}, t = {t:.6g} s{where}")


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


class Simulation:
    """A prepared run of one case.

    Parameters
    ----------
    cfg : CaseConfig
        Validated configuration.
    setup : CaseSetup, optional
        Particles and case data; built from ``cfg`` by the case's ``setup`` if omitted.
    """

    def __init__(self, cfg: CaseConfig, setup: CaseSetup | None = None):
        self.cfg = cfg
        self.threads = set_threads(cfg.numerics.threads)
        self.setup = setup if setup is not None else CASES[cfg.case].setup(cfg)
        num, fl = cfg.numerics, cfg.fluid
        self.h = num.h
        self.kp = kernel_params(num.kernel, self.h)
        self.c0, self.b = b_coef(cfg, self.setup.depth)
        self.parts = self.setup.particles
        self.grid = CellGrid(*self.setup.bounds, support_radius(self.kp))
        self.gx, self.gz = 0.0, -fl.gravity
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
        #: particle shifting ``[coef, W(dx), cap]`` (:mod:`sph.shifting`; coef 0: off)
        self.shift = shift_params(num.shifting, num.cfl, num.c_factor, self.kp, num.dx)
        #: damage opening parameters for the kernels (:mod:`sph.damage`)
        self.op = (self.setup.opening.params if self.setup.opening is not None
                   else no_opening())
        self.force_scale = (self.setup.force_scale if self.setup.force_scale is not None
                            else np.ones(int(self.parts.comp.max()) + 1))
        self._allocate_work()
        #: objects whose state a checkpoint must hold besides the particles: each has
        #: ``get_state() -> dict`` (numpy arrays and scalars) and ``set_state(dict)``
        self.stateful = list(self.bodies) + list(self.setup.events)
        self.t = 0.0
        self.step = 0
        self.dt = 0.0
        self.n_fluid = int(np.sum(self.parts.kind == FLUID))
        #: fluid particles that left the domain and were removed (:meth:`_exclude`)
        self.n_lost = 0
        fmask = self.parts.kind == FLUID
        self.volume0 = float(np.sum(self.parts.m[fmask] / self.parts.rho[fmask]))
        self.record = Record()
        self._warned_c0 = False
        probes = cfg.probes
        self._surf_x = np.array([p.x for p in probes.surface], dtype=np.float64)
        self._pres_x = np.array([p.x for p in probes.pressure], dtype=np.float64)
        self._pres_z = np.array([p.z for p in probes.pressure], dtype=np.float64)
        self._zfloor = self.setup.bounds[2]
        self.wall_seconds = 0.0
        self.status = "not started"
        #: simulated times of the next output sample, snapshot and checkpoint
        self.next_output = self.next_vtk = 0.0
        self.next_checkpoint = cfg.run.checkpoint_interval
        #: the checkpoint this run resumed from (:func:`sph.checkpoint.restore`)
        self.restored_from = None

    def _allocate_work(self) -> None:
        """Per-particle work arrays; call again when the number of particles changes."""
        n = self.parts.n
        self._pf = np.zeros((n, 3)) if self.bodies else None
        self._grx = np.zeros(n)
        self._grz = np.zeros(n)
        self._rho_buf = np.zeros(n)

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
        p = self.parts
        g = self.grid
        n_out = g.sort(p.x, p.z)
        if n_out:
            self._exclude()
            p = self.parts
            g.sort(p.x, p.z)
        p.permute(g.order)
        fl = self.cfg.fluid
        fluid_pressures(p.rho, p.kind, p.p, fl.rho0, self.b, fl.gamma)
        wall_pressure(p.x, p.z, p.rho, p.p, p.m, p.kind, p.body, p.comp, g.cell_of,
                      g.cell_start, g.ncx, self.kp, self.gx, self.gz, self.kin, fl.rho0,
                      self.b, fl.gamma, self.cfg.numerics.dx**2, self.op)
        if self.delta_coef and not self.ddt_rho:
            renormalised_density_gradient(p.x, p.z, p.rho, p.m, p.kind, p.comp, g.cell_of,
                                          g.cell_start, g.ncx, self.kp, self._grx, self._grz,
                                          self.op, self.kin)
        interact(p.x, p.z, p.vx, p.vz, p.rho, p.p, p.m, p.kind, p.body, p.comp, g.cell_of,
                 g.cell_start, g.ncx, self.kp, self.visc_coef, self.gx, self.gz,
                 self.delta_coef, self.ddt_rho, self._grx, self._grz, p.ax, p.az, p.drho,
                 self.op, self.kin, self.shift, p.sx, p.sz)
        if self.bodies:
            wall_forces(p.x, p.z, p.rho, p.p, p.m, p.kind, p.body, p.comp, g.cell_of,
                        g.cell_start, g.ncx, self.kp, self.kin, len(self.kin), self._fx,
                        self._fz, self._mom, self._pf, self.force_scale, self.op)
            for body in self.bodies:
                body.collect_forces(self._fx, self._fz, self._mom)

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
        n_out = int(out.sum())
        budget = int(self.cfg.run.max_lost_fraction * self.n_fluid)
        if self.n_lost + n_out > budget:
            raise SimulationError(self.step, self.t, f"{n_out} fluid particle(s) left {where}"
                                  f", {self.n_lost + n_out} in all, more than "
                                  f"run.max_lost_fraction allows ({budget})")
        k = np.nonzero(out)[0]
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
        self.dt = time_step(num.cfl, self.h, self.c0, num.alpha, vmax, amax)
        if not self._warned_c0 and 10.0 * vmax > self.c0:
            self._warned_c0 = True
            log.warning("t = %.4g s: max velocity %.3g m/s exceeds c0/10 = %.3g m/s; "
                        "compressibility errors grow (raise numerics.c_factor)",
                        self.t, vmax, self.c0 / 10.0)
        s = self.step + 1
        mls_due = num.density_filter == "mls" and s % num.mls_interval == 0
        euler = mls_due or s % num.euler_interval == 0 or self.step == 0
        g = self.grid
        if mls_due:
            mls_density(p.x, p.z, p.rho, p.m, p.kind, p.body, p.comp, g.cell_of, g.cell_start,
                        g.ncx, self.kp, self._rho_buf, self.op, self.kin)
            p.rho[:] = self._rho_buf
        verlet_update(p.x, p.z, p.vx, p.vz, p.rho, p.vx_old, p.vz_old, p.rho_old, p.ax, p.az,
                      p.drho, p.kind, self.dt, euler, self.setup.absorber)
        if self.shift[0]:
            apply_shift(p.x, p.z, p.sx, p.sz, p.kind)
        for body in self.bodies:
            body.update(self.dt, euler)
        self.t += self.dt
        self.step = s
        self.evaluate()

    # ------------------------------------------------------------------ checks
    def check(self) -> None:
        """Stop with a :class:`SimulationError` on NaN/inf or a density out of band."""
        p, run, rho0 = self.parts, self.cfg.run, self.cfg.fluid.rho0
        f = p.kind == FLUID
        for name in ("x", "z", "vx", "vz", "rho", "ax", "az"):
            arr = getattr(p, name)[f]
            if not np.all(np.isfinite(arr)):
                bad = int(np.sum(~np.isfinite(arr)))
                raise SimulationError(self.step, self.t, f"{bad} fluid particle(s) have a "
                                      f"non-finite {name}")
        rho = p.rho[f]
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
        f = p.kind == FLUID
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
        if self.bodies:
            values.update(self.bodies[0].motions())
            forces = np.array([b.force for b in self.bodies])
            values["body_force_x"] = forces[:, 0]
            values["body_force_z"] = forces[:, 1]
            values["body_moment"] = forces[:, 2]
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

    def dataset(self):
        """The run so far as a CF-annotated :class:`xarray.Dataset`."""
        from .output import build_dataset

        rec = self.record
        series = {k: np.asarray(v) for k, v in rec.series.items()}
        for name in ("body_force_x", "body_force_z", "body_moment"):
            if name in series:  # (time, body) -> (body, time)
                series[name] = series[name].T
        probes = {}
        names = [pr.name for pr in self.cfg.probes.surface] + list(self.setup.extra_probes)
        if names:
            surf = np.asarray(rec.surface).T.reshape(len(names), -1)
            still = self.setup.depth if self.setup.still_level is None else self.setup.still_level
            ref = np.array([still] * len(self._surf_x)
                           + [r for _, r in self.setup.extra_probes.values()])
            probes["surface_height"] = (names, surf)
            probes["probe_elevation"] = (names, surf - ref[:, None])
        if len(self._pres_x):
            names = [pr.name for pr in self.cfg.probes.pressure]
            probes["probe_pressure"] = (names, np.asarray(rec.pressure).T)
        attrs = dict(self.setup.attrs)
        attrs.update(case=self.cfg.case, title=self.cfg.title, status=self.status,
                     steps=self.step, wall_clock_seconds=round(self.wall_seconds, 3),
                     threads=self.threads, n_fluid=self.n_fluid, n_total=self.parts.n,
                     lost_particles=self.n_lost,
                     speed_of_sound=self.c0, smoothing_length=self.h,
                     kernel=self.cfg.numerics.kernel,
                     density_filter=self.cfg.numerics.density_filter, dx=self.cfg.numerics.dx,
                     particle_steps_per_second=round(self.particle_steps_per_second(), 1))
        if self.setup.absorber[0] != 0.0:  # the zone's effective c (speed x strength), m/s
            attrs.update(absorber_speed=float(self.setup.absorber[3]))
        return build_dataset(rec.time, series, probes=probes or None, attrs=attrs,
                             config_yaml=self.cfg.to_yaml())

    def summary(self) -> str:
        """One line describing the prepared run."""
        num = self.cfg.numerics
        return (f"{self.cfg.case}: {self.n_fluid} fluid + {self.parts.n - self.n_fluid} wall "
                f"particles, dx = {num.dx:g} m, h = {self.h:g} m, c0 = {self.c0:.4g} m/s, "
                f"{self.threads} thread(s), sph-flood {__version__}")

    def particle_steps_per_second(self) -> float:
        return self.parts.n * self.step / self.wall_seconds if self.wall_seconds else 0.0

    def write(self, path) -> None:
        from .output import write_netcdf_atomic

        write_netcdf_atomic(self.dataset(), path)

    # ------------------------------------------------------------------ driver
    def run(self, out_path=None, *, progress: bool = False, vtk_dir=None,
            checkpoint_dir=None) -> Simulation:
        """Run to ``run.t_end`` (or ``run.max_steps``), writing ``out_path`` atomically.

        The partial output is rewritten every ``run.flush_seconds`` of wall time; on a
        blow-up or an interrupt the data up to that moment is written (global attribute
        ``status`` says what happened) and the exception propagates.

        With ``checkpoint_dir`` (see :mod:`sph.checkpoint`) a checkpoint is written every
        ``run.checkpoint_interval`` of simulated time and every
        ``run.checkpoint_wall_seconds`` of wall time, when the run stops at
        ``run.max_steps`` before ``t_end``, and on SIGINT or SIGTERM. A completed run
        deletes its checkpoints unless ``run.keep_checkpoints`` is set (then it writes a
        last one). A simulation restored from a checkpoint continues where it was.

        Raises
        ------
        SimulationError
            The run blew up (NaN, a particle left the domain, density out of band).
        RunInterrupted
            SIGINT or SIGTERM arrived (in the main thread); the run stopped after the step
            in progress, with a checkpoint when it has a checkpoint directory. A second
            signal raises KeyboardInterrupt at once.
        sph.output.OutputWriteError
            The output or a checkpoint could not be written.
        """
        run = self.cfg.run
        bar = _progress_bar(run.t_end) if progress else None
        vtk = None
        if vtk_dir is not None and run.vtk_interval > 0:
            from .output import VTKWriter

            resume_after = self.t if self.restored_from is not None else None
            vtk = VTKWriter(vtk_dir, self.cfg.case, resume_after=resume_after)
        t_wall0 = wallclock.perf_counter() - self.wall_seconds
        last_flush = last_ckpt = wallclock.perf_counter()
        eps = 1e-12 * run.t_end
        self.status = "running"
        pending = None
        try:
            with _StopSignals() as stop:
                if self.step == 0 and self.restored_from is None:
                    self.evaluate()
                while True:
                    if self.t >= self.next_output - eps:
                        self.sample()
                        self.next_output += run.output_interval
                    if vtk is not None and self.t >= self.next_vtk - eps:
                        self._write_vtk(vtk)
                        self.next_vtk += run.vtk_interval
                    if self.t >= run.t_end - eps:
                        self.status = "completed"
                        break
                    if run.max_steps and self.step >= run.max_steps:
                        self.status = (f"stopped at run.max_steps = {run.max_steps}, "
                                       f"t = {self.t:.6g} s")
                        break
                    self.advance()
                    if self.step % run.check_interval == 0:
                        self.check()
                    now = wallclock.perf_counter()
                    self.wall_seconds = now - t_wall0
                    if bar is not None:
                        bar.update_to(self.t, self.particle_steps_per_second())
                    if checkpoint_dir is not None and self._checkpoint_due(now - last_ckpt,
                                                                           eps):
                        self.checkpoint(checkpoint_dir)
                        last_ckpt = wallclock.perf_counter()
                    if out_path is not None and now - last_flush > run.flush_seconds:
                        self.write(out_path)
                        last_flush = now
                    if stop.signal_name is not None:
                        path = (self.checkpoint(checkpoint_dir) if checkpoint_dir is not None
                                else None)
                        raise RunInterrupted(self.step, self.t, stop.signal_name, path)
                # a signal from here on is ignored: the run is done
                if checkpoint_dir is not None and (self.status != "completed"
                                                   or run.keep_checkpoints):
                    self.checkpoint(checkpoint_dir)
                if out_path is not None and self.record.time:
                    self.wall_seconds = wallclock.perf_counter() - t_wall0
                    self.write(out_path)
                    out_path = None  # written: nothing left to do below
                if checkpoint_dir is not None and self.status == "completed" and not (
                        run.keep_checkpoints):
                    from .checkpoint import remove_checkpoints

                    remove_checkpoints(checkpoint_dir)  # only once the output is safe
        except SimulationError as exc:
            self.status = f"failed: {exc}"
            pending = exc
            raise
        except RunInterrupted as exc:
            self.status = str(exc)
            pending = exc
            raise
        except KeyboardInterrupt as exc:
            self.status = f"interrupted at step {self.step}, t = {self.t:.6g} s"
            pending = exc
            raise
        except BaseException as exc:
            pending = exc
            raise
        finally:
            self.wall_seconds = wallclock.perf_counter() - t_wall0
            if bar is not None:
                bar.close()
            if vtk is not None:
                vtk.close()
            if out_path is not None and self.record.time:
                try:
                    self.write(out_path)
                except OSError as exc:
                    if pending is None:
                        raise
                    log.error("%s", exc)  # keep the error that stopped the run
        return self

    def _checkpoint_due(self, wall_since: float, eps: float) -> bool:
        """Whether a checkpoint is due after this step (advances the simulated-time
        schedule)."""
        run = self.cfg.run
        due = bool(run.checkpoint_wall_seconds) and wall_since >= run.checkpoint_wall_seconds
        if run.checkpoint_interval > 0 and self.t >= self.next_checkpoint - eps:
            due = True
            while self.next_checkpoint <= self.t + eps:
                self.next_checkpoint += run.checkpoint_interval
        return due

    def checkpoint(self, directory):
        """Write a checkpoint of the current state (:func:`sph.checkpoint.write_checkpoint`)
        into ``directory``; returns its path."""
        from .checkpoint import write_checkpoint

        return write_checkpoint(self, directory)

    def _write_vtk(self, vtk) -> None:
        p = self.parts
        vtk.write(self.t, p.x, p.z, {
            "velocity": np.column_stack([p.vx, p.vz]), "density": p.rho, "pressure": p.p,
            "kind": p.kind.astype(np.int32), "id": p.pid.astype(np.int32)})


class _StopSignals:
    """Within the block, SIGINT and SIGTERM only set :attr:`signal_name` (the run stops
    cleanly after the step in progress); a second signal raises KeyboardInterrupt. Does
    nothing outside the main thread, where Python cannot install handlers."""

    def __init__(self):
        self.signal_name = None
        self._previous = {}

    def __enter__(self):
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGINT, signal.SIGTERM):
                self._previous[sig] = signal.signal(sig, self._handle)
        return self

    def _handle(self, signum, frame):
        if self.signal_name is not None:
            raise KeyboardInterrupt
        self.signal_name = signal.Signals(signum).name
        log.warning("received %s: stopping after this step (send it again to stop at once)",
                    self.signal_name)

    def __exit__(self, *exc_info):
        for sig, handler in self._previous.items():
            signal.signal(sig, handler)
        return False


def _progress_bar(t_end: float, file=None):
    """A tqdm bar over simulated time, with the particle-steps rate. On a terminal it is
    redrawn twice a second; written to a file (a run in the background with its output
    redirected to a log) it prints a line every 30 s, so a day-long run leaves a log of a
    few thousand lines rather than megabytes of redraws."""
    from tqdm import tqdm

    stream = sys.stderr if file is None else file
    interval = 0.5 if getattr(stream, "isatty", lambda: False)() else 30.0

    class Bar(tqdm):
        def update_to(self, t, rate):
            if self._time() - self.last_print_t < interval and t < t_end:
                return
            self.set_postfix_str(f"{rate / 1e6:.2f} M particle-steps/s", refresh=False)
            self.update(min(t, t_end) - self.n)

    return Bar(total=t_end, unit="s", unit_scale=False, file=stream, mininterval=interval,
               bar_format="{l_bar}{bar}| t = {n:.3f}/{total:.3f} s [{elapsed}<{remaining}"
               "{postfix}]")
