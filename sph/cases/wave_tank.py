"""Numerical wave tank: flap wavemaker, absorbing zone, earth-fixed wave probes.

The paper's tank (Cao et al. 2019, Sec. III B): depth H = 30 m, length 5H, absorbing zone
over the last 2H, flap hinged at (0, 0) driven by theta(t) = 0.025 sin(1.0 t), probes WP1 at
x = H and WP2 at x = 2H (plus three reflection gauges between WP2 and the zone for the
incident/reflected wave separation). Linear theory gives A = 1.02 m, k = 0.1024 1/m,
lambda = 61.4 m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from sph.bodies.wavemaker import FlapConfig, FlapMotion, flap_wave_amplitude, wavenumber
from sph.cases.base import (
    CaseSetup,
    check_absorber_fits,
    check_probes_inside,
    flap_tank_lattice,
    load_defaults,
    make_particles,
    require_resolved,
    wall_layers,
)
from sph.engine.absorber import AbsorberConfig, absorber_params
from sph.engine.config import CaseConfig
from sph.engine.walls import tank_guard
from sph.schema import ConfigError, spec


@dataclass(frozen=True)
class Geometry:
    depth: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m", doc="water depth H")
    tank_length: float = spec(lo=0.0, lo_open=True, hi=1.0e5, unit="m",
                              doc="from the flap hinge to the end wall")
    tank_height: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m",
                              doc="height of the flap and of the end wall")
    wavemaker: FlapConfig = field(metadata=dict(doc="flap wavemaker"))
    absorber: AbsorberConfig = field(metadata=dict(doc="damping zone"))

    def check(self, key):
        if self.depth >= self.tank_height:
            raise ConfigError(f"{key}.depth", f"must be in (0, geometry.tank_height = "
                              f"{self.tank_height:g}) m; got {self.depth:g}")
        check_absorber_fits(self.absorber, self.tank_length, f"{key}.absorber")


def defaults() -> dict:
    return load_defaults("wave_tank")


def check(cfg: CaseConfig) -> None:
    g = cfg.geometry
    require_resolved("geometry.depth", g.depth, cfg.numerics.dx)
    check_probes_inside(cfg, 0.0, g.tank_length, 0.0, g.tank_height)


def theory(cfg: CaseConfig) -> dict:
    """Linear-theory wave of this tank: amplitude, wavenumber, wavelength, period."""
    g = cfg.geometry
    motion = FlapMotion(g.wavemaker, g.depth, cfg.fluid.gravity)
    k = wavenumber(g.wavemaker.omega, g.depth, cfg.fluid.gravity)
    return dict(theta0=motion.theta0, omega=g.wavemaker.omega, wavenumber=k,
                wavelength=2 * math.pi / k, period=2 * math.pi / g.wavemaker.omega,
                phase_speed=g.wavemaker.omega / k,
                amplitude=flap_wave_amplitude(motion.theta0, g.wavemaker.omega, g.depth,
                                              cfg.fluid.gravity))


def setup(cfg: CaseConfig) -> CaseSetup:
    g, dx = cfg.geometry, cfg.numerics.dx
    layers = wall_layers(cfg)
    t = layers * dx
    pts, inside, wall_mask, body = flap_tank_lattice(dx, layers, g.tank_length, g.tank_height)
    fluid_mask = inside & (pts[:, 1] < g.depth)
    walls = pts[wall_mask]
    parts = make_particles(cfg, pts[fluid_mask], walls, g.depth, g.depth, wall_body=body,
                           wall_body_xz=walls)
    th = theory(cfg)
    motion = FlapMotion(g.wavemaker, g.depth, cfg.fluid.gravity)
    swing = g.tank_height * math.sin(min(4.0 * motion.theta0, 0.5)) + dx
    bounds = (-t - swing, g.tank_length + t, -t, g.tank_height + g.depth)

    def flap_angle(p, time):
        return math.degrees(motion.angle(time)[0])

    attrs = dict(depth=g.depth, tank_length=g.tank_length, theta0=motion.theta0,
                 omega=g.wavemaker.omega, ramp_time=g.wavemaker.ramp_time,
                 flap_file=g.wavemaker.file or "", absorber=int(g.absorber.enabled),
                 absorber_start=g.absorber.start, absorber_length=g.absorber.length,
                 absorber_form=g.absorber.form, absorber_strength=g.absorber.strength,
                 theory_amplitude=th["amplitude"],
                 theory_wavenumber=th["wavenumber"], theory_wavelength=th["wavelength"])
    return CaseSetup(parts, bounds, g.depth, motions=[motion],
                     diagnostics={"flap_angle": flap_angle}, attrs=attrs,
                     absorber=absorber_params(g.absorber, th["phase_speed"], dx),
                     still_level=g.depth,
                     # the floor and the end wall (the flap is not a fixed wall)
                     tank_guard=tank_guard(-math.inf, g.tank_length, 0.0, g.tank_height, dx,
                                           layers))



