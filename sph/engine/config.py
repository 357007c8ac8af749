"""Typed, validated, frozen sections of a case configuration.

A case file is a YAML mapping with the sections ``case``, ``title``, ``numerics``, ``fluid``,
``run``, ``geometry`` (its keys depend on the case, :mod:`sph.cases`) and ``probes``. Every
key is declared below with its type, default, allowed range and meaning
(:func:`sph.schema.spec`); unknown keys, wrong types and out-of-range values raise
:class:`~sph.schema.ConfigError` naming the key and the allowed range, before any particle
is created.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import yaml

from sph.engine.kernels import DEFAULT_H_FACTOR
from sph.schema import ConfigError, spec

# --------------------------------------------------------------------------- sections


#: most refinement levels (each halves the particle spacing)
MAX_LEVEL = 3


@dataclass(frozen=True)
class RefinementBox:
    """A box of finer particles (:mod:`sph.engine.refinement`): spacing ``dx / 2**level``."""

    x: list[float] = spec(lo=-1.0e6, hi=1.0e6, unit="m", doc="[xmin, xmax] of the box")
    z: list[float] = spec(lo=-1.0e6, hi=1.0e6, unit="m", doc="[zmin, zmax] of the box")
    level: int = spec(1, lo=1, hi=MAX_LEVEL, doc="refinement level: spacing dx / 2**level")

    def check(self, key):
        for name in ("x", "z"):
            lim = getattr(self, name)
            if len(lim) != 2 or not lim[0] < lim[1]:
                raise ConfigError(f"{key}.{name}", f"must be [min, max] with min < max; got "
                                  f"{list(lim)}")


@dataclass(frozen=True)
class Numerics:
    """Discretisation and numerical model."""

    dx: float = spec(lo=0.0, lo_open=True, hi=100.0, unit="m", doc="initial particle spacing")
    kernel: str = spec("gaussian", choices=("gaussian", "wendland"),
                       doc="smoothing kernel: improved Gaussian (3h support) or Wendland C2 (2h)")
    h_factor: float | None = spec(None, lo=1.0, hi=2.0,
                                  doc="h/dx; default 1.23 (gaussian) or 1.41 (wendland)")
    density_filter: str = spec("mls", choices=("mls", "delta", "ddt", "none"),
                               doc="MLS re-initialisation, delta-SPH diffusion with the "
                                   "renormalised density gradient (delta) or with the "
                                   "hydrostatic density difference subtracted (ddt), or none "
                                   "(under variable resolution the ghosts still exchange "
                                   "density with the active particles, delta)")
    mls_interval: int = spec(20, lo=1, hi=10000, doc="steps between MLS re-initialisations")
    delta: float = spec(0.1, lo=0.0, hi=1.0,
                        doc="delta-SPH coefficient (delta and ddt; with none, the ghosts' "
                            "density exchange of variable resolution)")
    alpha: float = spec(0.02, lo=0.0, hi=1.0, doc="artificial viscosity coefficient")
    c_factor: float = spec(10.0, lo=3.0, hi=200.0,
                           doc="speed of sound c0 = c_factor * sqrt(g * depth)")
    cfl: float = spec(0.2, lo=0.0, lo_open=True, hi=0.5, doc="Courant number")
    euler_interval: int = spec(40, lo=2, hi=10000,
                               doc="steps between Euler re-couplings of the Verlet scheme")
    shifting: float = spec(0.0, lo=0.0, hi=10.0,
                           doc="particle shifting coefficient C (Sun et al. 2017); 0 = off")
    wall_tension: str = spec("clamp", choices=("clamp", "free_surface", "none"),
                             doc="pressure sum of a fluid and a wall particle: clamp (a "
                                 "wall never pulls), free_surface (clamped at zero for "
                                 "free-surface fluid only, the second source paper's Eq. 6) "
                                 "or none (sph.engine.surface)")
    pressure_floor: float | None = spec(
        None, lo=-1.0e8, hi=0.0, unit="Pa",
        doc="lowest fluid pressure (gauge); null = none. -1.0e5: water cavitates about one "
            "atmosphere below the ambient pressure, and SPH fluid held in a larger tension "
            "clumps and jets (docs/model.md)")
    wall_damping: bool = spec(
        False, doc="damp the fluid's approach to a wall along the wall's normal with the "
                   "artificial viscosity (the flow along it stays free-slip): a lone particle "
                   "then strikes a wall inelastically, as a drop does, and is not pumped up "
                   "by a moving wall (docs/model.md)")
    wall_layers: int = spec(0, lo=0, hi=20,
                            doc="layers of dummy particles; 0 = enough to cover the support")
    threads: int = spec(0, lo=0, hi=1024, doc="numba threads; 0 = NUMBA_NUM_THREADS")
    refinement: list[RefinementBox] = spec(
        [], doc="boxes of finer particles, each level halving dx (sph.engine.refinement); "
                "a box of level l > 1 lies inside one of level l - 1")

    @property
    def h(self) -> float:
        return self.dx * (self.h_factor or DEFAULT_H_FACTOR[self.kernel])

    def check(self, key):
        boxes = self.refinement
        for k, b in enumerate(boxes):
            if b.level == 1:
                continue
            parents = [a for a in boxes if a.level == b.level - 1 and a.x[0] <= b.x[0]
                       and b.x[1] <= a.x[1] and a.z[0] <= b.z[0] and b.z[1] <= a.z[1]]
            if not parents:
                raise ConfigError(f"{key}.refinement[{k}]", f"a box of level {b.level} must "
                                  f"lie inside a box of level {b.level - 1}; got x = "
                                  f"{list(b.x)}, z = {list(b.z)}")


@dataclass(frozen=True)
class Fluid:
    """Liquid properties and gravity."""

    rho0: float = spec(1000.0, lo=1.0, hi=1.0e5, unit="kg/m3", doc="reference density")
    gamma: float = spec(7.0, lo=1.0, hi=10.0, doc="Tait exponent")
    gravity: float = spec(9.81, lo=0.0, hi=100.0, unit="m/s2", doc="gravity (acts along -z)")


@dataclass(frozen=True)
class Run:
    """Duration, output and run-time checks."""

    t_end: float = spec(lo=0.0, lo_open=True, hi=1.0e6, unit="s", doc="simulated duration")
    output_interval: float = spec(0.01, lo=0.0, lo_open=True, hi=1.0e6, unit="s",
                                  doc="time between output samples")
    vtk_interval: float = spec(0.0, lo=0.0, hi=1.0e6, unit="s",
                               doc="time between ParaView snapshots; 0 = none")
    max_steps: int = spec(0, lo=0, hi=10**12, doc="stop after this many steps; 0 = no limit")
    check_interval: int = spec(10, lo=1, hi=100000, doc="steps between blow-up checks")
    density_min: float = spec(0.5, lo=0.0, lo_open=True, hi=1.0, hi_open=True,
                              doc="blow-up if an active fluid density falls below this times "
                                  "rho0 (ghosts of variable resolution are fitted, not "
                                  "checked)")
    density_max: float = spec(1.5, lo=1.0, lo_open=True, hi=10.0,
                              doc="blow-up if an active fluid density exceeds this times rho0")
    max_lost_fraction: float = spec(0.001, lo=0.0, hi=0.1,
                                    doc="fraction of the fluid particles that may leave the "
                                        "domain (removed and counted, with a warning) before "
                                        "the run stops as blown up; 0 = stop at the first")
    flush_seconds: float = spec(60.0, lo=0.0, lo_open=True, hi=1.0e6, unit="s",
                                doc="wall time between rewrites of the partial output")
    checkpoint_interval: float = spec(0.0, lo=0.0, hi=1.0e6, unit="s",
                                      doc="simulated time between checkpoints; 0 = none by "
                                      "simulated time")
    checkpoint_wall_seconds: float = spec(600.0, lo=0.0, hi=1.0e7, unit="s",
                                          doc="wall time between checkpoints; 0 = none by "
                                          "wall time")
    keep_checkpoints: bool = spec(False, doc="keep the checkpoints (and write a last one) "
                                  "after a successful finish, e.g. to extend the run later "
                                  "with a larger t_end; by default they are deleted")

    def check(self, key):
        if self.output_interval > self.t_end:
            raise ConfigError(f"{key}.output_interval",
                              f"must be in (0, run.t_end = {self.t_end:g}] s; "
                              f"got {self.output_interval:g}")


@dataclass(frozen=True)
class SurfaceProbe:
    """Earth-fixed free-surface elevation probe."""

    name: str = spec(doc="probe name")
    x: float = spec(lo=-1.0e6, hi=1.0e6, unit="m", doc="abscissa")


@dataclass(frozen=True)
class PressureProbe:
    """Earth-fixed pressure probe on a wall."""

    name: str = spec(doc="probe name")
    x: float = spec(lo=-1.0e6, hi=1.0e6, unit="m", doc="abscissa")
    z: float = spec(lo=-1.0e6, hi=1.0e6, unit="m", doc="height")


@dataclass(frozen=True)
class Probes:
    surface: list[SurfaceProbe] = spec([], doc="free-surface elevation probes")
    pressure: list[PressureProbe] = spec([], doc="wall pressure probes")

    def check(self, key):
        names = [p.name for p in self.surface] + [p.name for p in self.pressure]
        for n in names:
            if names.count(n) > 1:
                raise ConfigError(f"{key}", f"probe name {n!r} is used twice; names must be "
                                  "unique")


@dataclass(frozen=True)
class CaseConfig:
    """A whole case: which built-in geometry, and every parameter of the run."""

    case: str
    title: str
    numerics: Numerics
    fluid: Fluid
    run: Run
    geometry: Any
    probes: Probes

    def to_dict(self) -> dict:
        return _to_plain(self)

    def to_yaml(self) -> str:
        return yaml.safe_dump(self.to_dict(), sort_keys=False)


def _to_plain(obj):
    if dataclasses.is_dataclass(obj):
        return {f.name: _to_plain(getattr(obj, f.name)) for f in dataclasses.fields(obj)}
    if isinstance(obj, (list, tuple)):
        return [_to_plain(v) for v in obj]
    return obj
