"""Still water in a rectangular tank: hydrostatic pressure and no spurious motion."""

from __future__ import annotations

from dataclasses import dataclass

from sph.cases.base import (
    CaseSetup,
    check_probes_inside,
    load_defaults,
    make_particles,
    require_resolved,
    wall_layers,
)
from sph.cases.geometry import RoundedTank, tank_particles
from sph.engine.config import CaseConfig
from sph.schema import ConfigError, spec


@dataclass(frozen=True)
class Geometry:
    tank_length: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m",
                              doc="inner length of the tank")
    depth: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m", doc="water depth")
    tank_height: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m",
                              doc="height of the side walls")

    def check(self, key):
        if self.depth > self.tank_height:
            raise ConfigError(f"{key}.depth", f"must be in (0, geometry.tank_height = "
                              f"{self.tank_height:g}] m; got {self.depth:g}")


def defaults() -> dict:
    return load_defaults("still_water")


def check(cfg: CaseConfig) -> None:
    g = cfg.geometry
    require_resolved("geometry.depth", g.depth, cfg.numerics.dx)
    require_resolved("geometry.tank_length", g.tank_length, cfg.numerics.dx)
    check_probes_inside(cfg, 0.0, g.tank_length, 0.0, g.tank_height)


def setup(cfg: CaseConfig) -> CaseSetup:
    g, dx = cfg.geometry, cfg.numerics.dx
    layers = wall_layers(cfg)
    tank = RoundedTank(0.0, 0.0, g.tank_length, g.tank_height)
    fluid, wall = tank_particles(tank, dx, layers, g.tank_height, g.depth)
    parts = make_particles(cfg, fluid, wall, g.depth, g.depth)
    t = layers * dx
    bounds = (-t, g.tank_length + t, -t, g.tank_height + 0.5 * g.tank_height)
    return CaseSetup(parts, bounds, g.depth,
                     attrs=dict(tank_length=g.tank_length, depth=g.depth),
                     tank_guard=tank.guard(g.tank_height, dx, layers))
