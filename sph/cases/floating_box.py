"""A freely floating box in a wave tank (the set-up of Hadžić et al. 2005, Cao et al. 2019
Sec. III A): flap wavemaker at x = 0, absorbing zone at the far end, a solid box of given
density floating at its hydrostatic draught with sway, heave and roll free.

With ``wavemaker.theta0 = 0`` the tank is still and the box must stay at its hydrostatic
draught ``d = (rho_box / rho0) * box_height`` (``heave_offset`` starts it displaced, for a
heave free decay). The wavemaker may be driven by the experiment's flap file.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sph.bodies.rigid import DofConfig, RigidBody
from sph.bodies.wavemaker import FlapConfig, FlapMotion, wavenumber
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
from sph.cases.geometry import fit_cells
from sph.engine.absorber import AbsorberConfig, absorber_params
from sph.engine.config import CaseConfig
from sph.engine.walls import tank_guard
from sph.schema import ConfigError, spec


@dataclass(frozen=True)
class Geometry:
    depth: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m")
    tank_length: float = spec(lo=0.0, lo_open=True, hi=1.0e5, unit="m")
    tank_height: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m")
    box_width: float = spec(lo=0.0, lo_open=True, hi=1.0e3, unit="m")
    box_height: float = spec(lo=0.0, lo_open=True, hi=1.0e3, unit="m")
    box_x: float = spec(lo=0.0, hi=1.0e5, unit="m", doc="x of the box centre")
    box_density: float = spec(lo=1.0, hi=1.0e5, unit="kg/m3",
                              doc="below rho0 for the box to float")
    box_inertia: float | None = spec(lo=0.0, lo_open=True, hi=1.0e9, unit="kg m",
                                     doc="roll inertia per unit length about the centre of "
                                     "gravity; null: homogeneous box m (w^2 + h^2) / 12")
    heave_offset: float = spec(lo=-1.0e3, hi=1.0e3, unit="m",
                               doc="initial displacement from the hydrostatic position")
    dofs: DofConfig
    wavemaker: FlapConfig
    absorber: AbsorberConfig


def defaults() -> dict:
    return load_defaults("floating_box")


def check(cfg: CaseConfig) -> None:
    g = cfg.geometry
    dx = cfg.numerics.dx
    require_resolved("geometry.box_height", g.box_height, dx, cells=3)
    require_resolved("geometry.box_width", g.box_width, dx, cells=3)
    if g.box_density >= cfg.fluid.rho0:
        raise ConfigError("geometry.box_density", f"must be in [1, fluid.rho0 = "
                          f"{cfg.fluid.rho0:g}) kg/m3 for the box to float; got "
                          f"{g.box_density:g}")
    half = 0.5 * g.box_width
    if not (dx * 4 + half <= g.box_x <= g.tank_length - half - 4 * dx):
        raise ConfigError("geometry.box_x", f"must be in [{half + 4 * dx:g}, "
                          f"{g.tank_length - half - 4 * dx:g}] m so that the box lies inside "
                          f"the tank; got {g.box_x:g}")
    if g.depth >= g.tank_height:
        raise ConfigError("geometry.depth", f"must be in (0, geometry.tank_height = "
                          f"{g.tank_height:g}) m; got {g.depth:g}")
    check_absorber_fits(g.absorber, g.tank_length)
    check_probes_inside(cfg, 0.0, g.tank_length, 0.0, g.tank_height)


def setup(cfg: CaseConfig) -> CaseSetup:
    g, dx = cfg.geometry, cfg.numerics.dx
    rho0 = cfg.fluid.rho0
    layers = wall_layers(cfg)
    t = layers * dx
    draught = g.box_density / rho0 * g.box_height
    bottom = g.depth - draught + g.heave_offset
    cog = np.array([g.box_x, bottom + 0.5 * g.box_height])
    # tank and flap on the tank lattice; the fluid in three blocks of columns fitted exactly
    # to the box's faces (left of it, under it, right of it) and the box a lattice fitted
    # to its own faces, both symmetric about the box's centre: a box that does not fall on
    # the tank lattice would otherwise start with a fluid gap wider on one side than on the
    # other and a particle centroid off its centre of gravity, and heel at release
    pts, inside, tank_mask, body = flap_tank_lattice(dx, layers, g.tank_length, g.tank_height)
    xl, xr = g.box_x - 0.5 * g.box_width, g.box_x + 0.5 * g.box_width
    fluid, vols = [], []
    for lo, hi, top in ((0.0, xl, g.depth), (xl, xr, min(bottom, g.depth)),
                        (xr, g.tank_length, g.depth)):
        xs, sx = fit_cells(lo, hi, dx)
        zs, sz = fit_cells(0.0, top, dx)
        xx, zz = np.meshgrid(xs, zs, indexing="ij")
        fluid.append(np.column_stack([xx.ravel(), zz.ravel()]))
        vols.append(np.full(xx.size, sx * sz))
    fluid, vols = np.concatenate(fluid), np.concatenate(vols)
    bx, _ = fit_cells(-0.5 * g.box_width, 0.5 * g.box_width, dx)
    bz, _ = fit_cells(-0.5 * g.box_height, 0.5 * g.box_height, dx)
    xx, zz = np.meshgrid(bx, bz, indexing="ij")
    box = np.column_stack([xx.ravel(), zz.ravel()])
    walls = np.concatenate([pts[tank_mask], box + cog])
    body_xz = np.concatenate([pts[tank_mask], box])
    body = np.concatenate([body, np.full(len(box), 2, dtype=np.int32)])
    parts = make_particles(cfg, fluid, walls, g.depth, g.depth, wall_body=body,
                           wall_body_xz=body_xz, fluid_volume=vols)
    mass = g.box_density * g.box_width * g.box_height
    inertia = g.box_inertia or mass * (g.box_width**2 + g.box_height**2) / 12.0
    flap = FlapMotion(g.wavemaker, g.depth, cfg.fluid.gravity)
    box_body = RigidBody(mass, inertia, cog, g.dofs, cfg.fluid.gravity,
                         segments=[(2, 1.0, 0.0)])
    swing = g.tank_height * math.sin(min(4.0 * flap.theta0, 0.5)) + dx
    bounds = (-t - swing, g.tank_length + t, -t, g.tank_height + g.depth)
    k = wavenumber(g.wavemaker.omega, g.depth, cfg.fluid.gravity)
    attrs = dict(depth=g.depth, tank_length=g.tank_length, box_width=g.box_width,
                 box_height=g.box_height, box_x=g.box_x, box_density=g.box_density,
                 box_mass=mass, box_inertia=inertia, draught=draught,
                 heave_offset=g.heave_offset, theta0=flap.theta0, omega=g.wavemaker.omega,
                 flap_file=g.wavemaker.file or "")
    return CaseSetup(parts, bounds, g.depth, motions=[flap, box_body], bodies=[box_body],
                     attrs=attrs,
                     diagnostics={"flap_angle": lambda p, time: math.degrees(
                         flap.angle(time)[0])},
                     absorber=absorber_params(g.absorber, g.wavemaker.omega / k, dx),
                     still_level=g.depth,
                     tank_guard=tank_guard(-math.inf, g.tank_length, 0.0, g.tank_height, dx,
                                           layers))
