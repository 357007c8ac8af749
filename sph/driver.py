"""The run driver: a case's stepper looped to the end, with output, checkpoints, ParaView
snapshots and clean stops on signals.

:class:`Simulation` is the physics stepper (:class:`sph.engine.stepper.Stepper`) plus the
run's schedule: samples every ``run.output_interval``, the partial output rewritten every
``run.flush_seconds`` of wall time, checkpoints (:mod:`sph.io.checkpoint`), snapshots
(:class:`sph.io.output.VTKWriter`), and SIGINT/SIGTERM handled between two steps.
"""

from __future__ import annotations

import logging
import signal
import sys
import threading
import time as wallclock

import numpy as np
from tqdm import tqdm

from sph import __version__
from sph.cases import setup as case_setup
from sph.engine.absorber import absorber_active, absorber_speed
from sph.engine.config import CaseConfig
from sph.engine.particles import GHOST
from sph.engine.refinement import levels
from sph.engine.stepper import SimulationError, Stepper
from sph.io.checkpoint import remove_checkpoints, write_checkpoint
from sph.io.output import VTKWriter, build_dataset, write_netcdf_atomic

__all__ = ["RunInterrupted", "Simulation", "SimulationError"]

log = logging.getLogger(__name__)


class RunInterrupted(RuntimeError):
    """A run stopped by SIGINT or SIGTERM between two steps; ``checkpoint`` is the file
    written to resume it (None when the run had no checkpoint directory)."""

    def __init__(self, step: int, t: float, signal_name: str, checkpoint=None):
        self.step, self.t, self.signal_name, self.checkpoint = step, t, signal_name, checkpoint
        where = f"; checkpoint {str(checkpoint)!r}" if checkpoint is not None else ""
        super().__init__(f"interrupted by {signal_name} at step {step}, t = {t:.6g} s{where}")


#: scalar state entries of the driver's schedule: name -> type
SCHEDULE_SCALARS = {"wall_seconds": float, "next_output": float, "next_vtk": float,
                    "next_checkpoint": float}


class Simulation(Stepper):
    """A prepared run of one case.

    Parameters
    ----------
    cfg : CaseConfig
        Validated configuration.
    setup : CaseSetup, optional
        Particles and case data; built from ``cfg`` by the case's ``setup`` if omitted.
    """

    def __init__(self, cfg: CaseConfig, setup=None):
        super().__init__(cfg, setup if setup is not None else case_setup(cfg))
        self.wall_seconds = 0.0
        self.status = "not started"
        #: simulated times of the next output sample, snapshot and checkpoint
        self.next_output = self.next_vtk = 0.0
        self.next_checkpoint = cfg.run.checkpoint_interval
        #: the checkpoint this run resumed from (:func:`sph.io.checkpoint.restore`)
        self.restored_from = None

    def get_state(self) -> dict[str, np.ndarray]:
        """The stepper's state (:meth:`Stepper.get_state`) and the run's schedule."""
        out = super().get_state()
        for name, tp in SCHEDULE_SCALARS.items():
            out[name] = np.array(tp(getattr(self, name)))
        return out

    def set_state(self, state: dict[str, np.ndarray], seed: bool = False) -> None:
        super().set_state(state, seed)
        for name, tp in SCHEDULE_SCALARS.items():
            setattr(self, name, tp(state[name][()]))

    def dataset(self):
        """The run so far as a CF-annotated :class:`xarray.Dataset`."""
        rec = self.record
        series = {k: np.asarray(v) for k, v in rec.series.items()}
        for name in ("body_force_x", "body_force_z", "body_moment", "n_particles_level"):
            if name in series:  # (time, body) -> (body, time); the same per level
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
                     lost_particles=self.n_lost, guarded_particles=self.n_guarded,
                     speed_of_sound=self.c0, smoothing_length=self.h,
                     kernel=self.cfg.numerics.kernel,
                     density_filter=self.cfg.numerics.density_filter, dx=self.cfg.numerics.dx,
                     particle_steps_per_second=round(self.particle_steps_per_second(), 1))
        if absorber_active(self.setup.absorber):  # the zone's effective c, m/s
            attrs.update(absorber_speed=absorber_speed(self.setup.absorber))
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
        write_netcdf_atomic(self.dataset(), path)

    # ------------------------------------------------------------------ driver
    def run(self, out_path=None, *, progress: bool = False, vtk_dir=None,
            checkpoint_dir=None) -> Simulation:
        """Run to ``run.t_end`` (or ``run.max_steps``), writing ``out_path`` atomically.

        The partial output is rewritten every ``run.flush_seconds`` of wall time; on a
        blow-up or an interrupt the data up to that moment is written (global attribute
        ``status`` says what happened) and the exception propagates.

        With ``checkpoint_dir`` (see :mod:`sph.io.checkpoint`) a checkpoint is written every
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
        sph.io.output.OutputWriteError
            The output or a checkpoint could not be written.
        """
        run = self.cfg.run
        bar = _progress_bar(run.t_end) if progress else None
        vtk = None
        if vtk_dir is not None and run.vtk_interval > 0:
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
        """Write a checkpoint of the current state (:func:`sph.io.checkpoint.write_checkpoint`)
        into ``directory``; returns its path."""
        return write_checkpoint(self, directory)

    def _write_vtk(self, vtk) -> None:
        p = self.parts
        vtk.write(self.t, p.x, p.z, {
            "velocity": np.column_stack([p.vx, p.vz]), "density": p.rho, "pressure": p.p,
            "kind": p.kind.astype(np.int32), "id": p.pid.astype(np.int32),
            "level": levels(p.hs), "ghost": (p.body == GHOST).astype(np.int32)})


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
