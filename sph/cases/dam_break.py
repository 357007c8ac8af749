"""Dam break: a water column collapsing in a tank (Koshizuka & Oka 1996 set-up).

The column ``column_width`` x ``column_height`` stands against the left wall of a tank of
length ``tank_length``; the surge front position (``front_position``, measured from the left
wall: the rightmost fluid particle plus half a spacing) is recorded every output step.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

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
from sph.engine.particles import FLUID
from sph.schema import ConfigError, spec


@dataclass(frozen=True)
class Geometry:
    tank_length: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m")
    tank_height: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m")
    column_width: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m")
    column_height: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m")

    def check(self, key):
        if self.column_width >= self.tank_length:
            raise ConfigError(f"{key}.column_width", f"must be in (0, geometry.tank_length = "
                              f"{self.tank_length:g}) m; got {self.column_width:g}")
        if self.column_height > self.tank_height:
            raise ConfigError(f"{key}.column_height", f"must be in (0, geometry.tank_height "
                              f"= {self.tank_height:g}] m; got {self.column_height:g}")


def defaults() -> dict:
    return load_defaults("dam_break")


def check(cfg: CaseConfig) -> None:
    g = cfg.geometry
    require_resolved("geometry.column_width", g.column_width, cfg.numerics.dx)
    require_resolved("geometry.column_height", g.column_height, cfg.numerics.dx)
    check_probes_inside(cfg, 0.0, g.tank_length, 0.0, g.tank_height)


def setup(cfg: CaseConfig) -> CaseSetup:
    g, dx = cfg.geometry, cfg.numerics.dx
    layers = wall_layers(cfg)
    tank = RoundedTank(0.0, 0.0, g.tank_length, g.tank_height)
    fluid, wall = tank_particles(tank, dx, layers, g.tank_height, g.column_height)
    fluid = fluid[fluid[:, 0] < g.column_width]
    parts = make_particles(cfg, fluid, wall, g.column_height, g.column_height)
    t = layers * dx
    bounds = (-t, g.tank_length + t, -t, g.tank_height + g.column_height)

    def front(p, t):
        return float(np.max(p.x[p.kind == FLUID])) + 0.5 * dx

    return CaseSetup(parts, bounds, g.column_height, diagnostics={"front_position": front},
                     attrs=dict(tank_length=g.tank_length, column_width=g.column_width,
                                column_height=g.column_height),
                     tank_guard=tank.guard(g.tank_height, dx, layers))
