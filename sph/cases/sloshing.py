r"""Free sloshing in a rectangular tank and in the U-shaped cabin section of the ship.

The liquid starts in one of two ways (``geometry.init``):

``velocity``
    flat free surface with the velocity field of the first linear standing-wave mode of a
    rectangular tank of width :math:`L` and depth :math:`h` at its zero crossing,

    .. math:: u = -a\omega\frac{\cosh k(z + h)}{\sinh kh}\sin kx,\quad
              w = a\omega\frac{\sinh k(z + h)}{\sinh kh}\cos kx,\quad k = \pi/L,

    so that the free surface follows :math:`\eta = a\sin(\omega t)\cos(kx)` (z measured from
    the still level);
``tilt``
    liquid at rest below a tilted plane free surface rising by ``amplitude`` at the left wall
    and falling by it at the right wall.

Linear theory: :math:`\omega^2 = g k \tanh(k h)`. The fluid's centre of mass
(``centre_of_mass_x``) oscillates at the first-mode frequency; see
:func:`sph.study.analysis.oscillation_frequency`.
"""

from __future__ import annotations

import math
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


def linear_frequency(length: float, depth: float, g: float = 9.81, mode: int = 1) -> float:
    """First (or ``mode``-th) natural angular frequency of a rectangular tank (rad/s)."""
    k = mode * math.pi / length
    return math.sqrt(g * k * math.tanh(k * depth))


def _centre_of_mass(p, axis):
    f = p.kind == FLUID
    arr = p.x if axis == 0 else p.z
    return float(np.sum(arr[f] * p.m[f]) / np.sum(p.m[f]))


def _sloshing_setup(cfg: CaseConfig, tank: RoundedTank, height: float, fill: float,
                    amplitude: float, init: str) -> CaseSetup:
    dx = cfg.numerics.dx
    layers = wall_layers(cfg)
    depth = fill * height
    width = tank.width
    wall_top = height
    fluid, wall = tank_particles(tank, dx, layers, wall_top, depth + amplitude + dx)
    xs = fluid[:, 0] - tank.x0
    if init == "tilt":
        level = depth + amplitude * (1.0 - 2.0 * xs / width)
    else:
        level = np.full(len(fluid), depth)
    fluid = fluid[fluid[:, 1] < level]
    xs = fluid[:, 0] - tank.x0
    parts = make_particles(cfg, fluid, wall, depth, depth)
    if init == "velocity":
        k = math.pi / width
        om = linear_frequency(width, depth, cfg.fluid.gravity)
        zz = fluid[:, 1] - tank.z0  # height above the bottom = z' + h
        nf = len(fluid)
        parts.vx[:nf] = -amplitude * om * np.cosh(k * zz) / math.sinh(k * depth) * np.sin(k * xs)
        parts.vz[:nf] = amplitude * om * np.sinh(k * zz) / math.sinh(k * depth) * np.cos(k * xs)
        parts.vx_old[:nf] = parts.vx[:nf]
        parts.vz_old[:nf] = parts.vz[:nf]
    t = layers * dx
    bounds = (tank.x0 - t, tank.x0 + width + t, tank.z0 - t, tank.z0 + 2.0 * height)
    diags = {"centre_of_mass_x": lambda p, t: _centre_of_mass(p, 0),
             "centre_of_mass_z": lambda p, t: _centre_of_mass(p, 1)}
    attrs = dict(tank_width=width, tank_height=height, fill=fill, depth=depth,
                 amplitude=amplitude, init=init,
                 linear_frequency_rect=linear_frequency(width, depth, cfg.fluid.gravity))
    return CaseSetup(parts, bounds, depth, diagnostics=diags, attrs=attrs,
                     tank_guard=tank.guard(wall_top, dx, layers))


def _check_common(cfg: CaseConfig, width: float, height: float) -> None:
    g = cfg.geometry
    depth = g.fill * height
    require_resolved("geometry.fill", depth, cfg.numerics.dx)
    if g.amplitude > 0.2 * min(depth, height - depth):
        limit = 0.2 * min(depth, height - depth)
        raise ConfigError("geometry.amplitude", f"must be in [0, {limit:g}] m "
                          "(20 % of the depth and of the freeboard) for a linear free decay; "
                          f"got {g.amplitude:g}")
    check_probes_inside(cfg, 0.0, width, 0.0, height)


class Rect:
    """Rectangular tank, case ``sloshing_rect``."""

    @dataclass(frozen=True)
    class Geometry:
        tank_length: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m")
        tank_height: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m")
        fill: float = spec(lo=0.0, lo_open=True, hi=1.0, hi_open=True,
                           doc="fill ratio: still depth / tank height")
        amplitude: float = spec(lo=0.0, hi=1.0e3, unit="m",
                                doc="initial free-surface amplitude at the walls")
        init: str = spec(choices=("velocity", "tilt"),
                         doc="first-mode velocity field or tilted free surface")

    @staticmethod
    def defaults() -> dict:
        return load_defaults("sloshing_rect")

    @staticmethod
    def check(cfg: CaseConfig) -> None:
        _check_common(cfg, cfg.geometry.tank_length, cfg.geometry.tank_height)
        require_resolved("geometry.tank_length", cfg.geometry.tank_length, cfg.numerics.dx)

    @staticmethod
    def setup(cfg: CaseConfig) -> CaseSetup:
        g = cfg.geometry
        tank = RoundedTank(0.0, 0.0, g.tank_length, g.tank_height)
        return _sloshing_setup(cfg, tank, g.tank_height, g.fill, g.amplitude, g.init)


class UTank:
    """U-shaped tank (the ship's cabin section), case ``sloshing_u``."""

    @dataclass(frozen=True)
    class Geometry:
        width: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m",
                            doc="inner breadth B")
        height: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m",
                             doc="inner depth D")
        bilge_radius: float = spec(lo=0.0, hi=1.0e4, unit="m",
                                   doc="radius of the rounded bilges")
        fill: float = spec(lo=0.0, lo_open=True, hi=1.0, hi_open=True,
                           doc="fill ratio eta: liquid height h_w = eta D")
        amplitude: float = spec(lo=0.0, hi=1.0e3, unit="m",
                                doc="initial free-surface amplitude at the walls")
        init: str = spec(choices=("velocity", "tilt"))

        def check(self, key):
            if self.bilge_radius > min(self.width / 2, self.height):
                raise ConfigError(f"{key}.bilge_radius", f"must be in [0, "
                                  f"{min(self.width / 2, self.height):g}] m (half the width "
                                  f"and at most the height); got {self.bilge_radius:g}")

    @staticmethod
    def defaults() -> dict:
        return load_defaults("sloshing_u")

    @staticmethod
    def check(cfg: CaseConfig) -> None:
        _check_common(cfg, cfg.geometry.width, cfg.geometry.height)
        require_resolved("geometry.width", cfg.geometry.width, cfg.numerics.dx)

    @staticmethod
    def setup(cfg: CaseConfig) -> CaseSetup:
        g = cfg.geometry
        tank = RoundedTank(0.0, 0.0, g.width, g.height, g.bilge_radius)
        s = _sloshing_setup(cfg, tank, g.height, g.fill, g.amplitude, g.init)
        s.attrs["bilge_radius"] = g.bilge_radius
        return s
