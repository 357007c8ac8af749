"""What a built-in case hands to the solver, and helpers shared by the cases."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from importlib import resources
from typing import Any

import numpy as np
import yaml

from sph.cases.geometry import lattice, n_wall_layers
from sph.engine.absorber import AB_SIZE
from sph.engine.config import CaseConfig
from sph.engine.eos import hydrostatic_density
from sph.engine.particles import Particles
from sph.engine.scales import Scales
from sph.schema import ConfigError


@dataclass
class CaseSetup:
    """Everything the solver needs to run a case.

    Attributes
    ----------
    particles : Particles
        Initial particles (fluid and walls) with velocities and densities set.
    bounds : tuple
        ``(xmin, xmax, zmin, zmax)`` of the domain; a particle outside has left it.
    depth : float
        Reference depth ``H`` (m) for the speed of sound ``c0 = c_factor sqrt(g H)``.
    motions : list
        Prescribed motions of the wall groups 1, 2, ... (group 0 is the fixed tank); each
        has ``kinematics(t) -> array of 9`` (see :mod:`sph.engine.walls`).
    diagnostics : dict
        Extra time series: name (registered in ``variables.yaml``) -> ``f(particles, t)``.
    attrs : dict
        Case parameters written as global attributes of the output.
    absorber : array
        Damping zone parameters (:func:`sph.engine.absorber.absorber_params`); zeros = none.
    still_level : float or None
        Height of the still free surface (probe elevations are relative to it); ``depth``
        if None.
    bodies : list
        Rigid bodies moving under fluid forces (:class:`sph.bodies.rigid.RigidBody`); their wall
        groups' entries in ``motions`` are the bodies themselves or their segment views.
    events : list
        Objects with ``apply(sim)`` called before every evaluation (e.g. a damage opening),
        and again after a refinement has moved the ghosts (so ``apply`` must give the same
        result when called twice at one time), and ``get_state()``/``set_state()`` for
        checkpoints.
    extra_probes : dict
        Further surface probes (e.g. body-fixed): name -> ``(f(particles) -> height (m),
        reference height (m))``; appended to ``surface_height`` and ``probe_elevation``
        (height minus reference).
    opening : DamageOpening or None
        The damage opening (:class:`sph.bodies.damage.DamageOpening`), also listed in ``events``.
    probe_comp : int
        Compartment of the fluid that the earth-fixed surface probes see (-1: all fluid).
    force_scale : array or None
        Factor on the fluid force on walls facing each compartment (index = compartment id);
        ones if None (a cargo of another density, :mod:`sph.cases.ship`).
    refinement : list
        Refinement boxes the case sets itself (:class:`sph.engine.config.RefinementBox`,
        e.g. around a hull), added to ``numerics.refinement``.
    refinement_groups : list
        The wall group each of ``refinement`` follows (its box moves with the group's
        reference point: a hull that sways and heaves keeps its fine region about it); 0
        for a fixed box. Empty: every box fixed.
    refinement_step : float
        A box following a group is moved once the group is this far (m, in x or z) from
        where the box was last placed for it (0: at every rebuild of the lists).
    open_boundary : OpenBoundary or None
        Inflow and outflow regions (:class:`sph.engine.openbc.OpenBoundary`), also listed
        in ``events``.
    tank_guard : array or None
        The tank's fixed walls for :func:`sph.engine.walls.keep_in_tank`
        (:func:`sph.engine.walls.tank_guard`): a fluid particle found through them is put
        back. None: no guard.
    """

    particles: Particles
    bounds: tuple
    depth: float
    motions: list = field(default_factory=list)
    diagnostics: dict[str, Callable] = field(default_factory=dict)
    attrs: dict = field(default_factory=dict)
    absorber: np.ndarray = field(default_factory=lambda: np.zeros(AB_SIZE))
    still_level: float | None = None
    bodies: list = field(default_factory=list)
    refinement: list = field(default_factory=list)
    refinement_groups: list = field(default_factory=list)
    refinement_step: float = 0.0
    events: list = field(default_factory=list)
    extra_probes: dict[str, tuple] = field(default_factory=dict)
    opening: Any = None
    probe_comp: int = -1
    force_scale: np.ndarray | None = None
    open_boundary: Any = None
    tank_guard: np.ndarray | None = None


def load_defaults(name: str) -> dict:
    """The built-in YAML of case ``name`` as a mapping."""
    text = resources.files("sph.cases").joinpath(f"{name}.yaml").read_text()
    return yaml.safe_load(text)


def example_text(name: str) -> str:
    """The built-in YAML of case ``name`` as text (what ``sph example`` prints)."""
    return resources.files("sph.cases").joinpath(f"{name}.yaml").read_text()


def scales(cfg: CaseConfig, depth: float | None = None) -> Scales:
    """dx, h, kernel support, c0 and B of a case (:class:`sph.engine.scales.Scales`; c0
    and B need the reference depth)."""
    return Scales.of(cfg.numerics, cfg.fluid, depth)


def wall_layers(cfg: CaseConfig) -> int:
    """Layers of dummy wall particles: ``numerics.wall_layers``, or enough to cover the
    kernel support (:func:`sph.cases.geometry.n_wall_layers`)."""
    return n_wall_layers(scales(cfg).support, cfg.numerics.dx, cfg.numerics.wall_layers)


def make_particles(cfg: CaseConfig, fluid_xz, wall_xz, surface_z, depth,
                   wall_body=None, wall_body_xz=None, fluid_volume=None) -> Particles:
    """Particles with hydrostatic initial density below the still level ``surface_z``.

    Fluid masses are ``rho_i dx^2`` (or ``rho_i fluid_volume``); wall masses are updated with
    the wall density (their volume stays ``dx^2``, see :func:`sph.engine.walls.wall_pressure`)."""
    b = scales(cfg, depth).b
    rho = hydrostatic_density(np.maximum(surface_z - fluid_xz[:, 1], 0.0), cfg.fluid.rho0, b,
                              cfg.fluid.gamma, cfg.fluid.gravity)
    # each particle carries the mass of its lattice cell at its initial density, so that the
    # particle volumes m/rho tile the lattice exactly (a hydrostatic column starts in SPH
    # equilibrium instead of settling with a pressure offset)
    vol = cfg.numerics.dx**2
    fvol = vol if fluid_volume is None else fluid_volume
    mass = np.concatenate([rho * fvol, np.full(len(wall_xz), cfg.fluid.rho0 * vol)])
    if wall_body is None:
        wall_body = np.zeros(len(wall_xz), dtype=np.int32)
    if wall_body_xz is None:
        wall_body_xz = wall_xz
    parts = Particles.from_arrays(fluid_xz, rho, mass, wall_xz, wall_body, wall_body_xz)
    nf = len(fluid_xz)
    parts.rho[nf:] = cfg.fluid.rho0
    return parts


def flap_tank_lattice(dx: float, layers: int, tank_length: float, tank_height: float):
    """Lattice of a tank with a flap at x = 0 (hinged at the origin) and a fixed end wall.

    Returns the points, the mask of points inside the tank (``0 < x < L``, ``z > 0``: fluid
    candidates), the mask of wall points, and the motion group of each wall point: 1 for the
    flap (``x < 0``, above the bottom), 0 for the fixed bottom and end wall."""
    t = layers * dx
    pts = lattice(-t, tank_length + t, -t, tank_height, dx)
    x, z = pts[:, 0], pts[:, 1]
    inside = (x > 0) & (x < tank_length) & (z > 0)
    walls = ~inside
    group = np.where((x[walls] < 0) & (z[walls] > 0), 1, 0).astype(np.int32)
    return pts, inside, walls, group


def check_absorber_fits(absorber, tank_length: float, key: str = "geometry.absorber") -> None:
    """An enabled damping zone must end inside the tank."""
    if absorber.enabled and absorber.start + absorber.length > tank_length + 1e-9:
        raise ConfigError(f"{key}.length", f"must be in (0, tank_length - start = "
                          f"{tank_length - absorber.start:g}] m so that the zone ends inside "
                          f"the tank; got {absorber.length:g} (start {absorber.start:g} m)")


def require_resolved(key: str, length: float, dx: float, cells: int = 4) -> None:
    """Refuse a length that the particle spacing cannot resolve."""
    if length < cells * dx:
        raise ConfigError(key, f"= {length:g} m is resolved by fewer than {cells} particle "
                          f"spacings (numerics.dx = {dx:g} m); use a smaller dx or a larger "
                          f"{key.split('.')[-1]}")


def check_probes_inside(cfg: CaseConfig, x0: float, x1: float, z0: float, z1: float) -> None:
    """Every probe must lie within the tank ``[x0, x1] x [z0, z1]``."""
    for k, pr in enumerate(cfg.probes.surface):
        if not x0 <= pr.x <= x1:
            raise ConfigError(f"probes.surface[{k}].x", f"must be inside the tank, in "
                              f"[{x0:g}, {x1:g}] m; got {pr.x:g}")
    for k, pr in enumerate(cfg.probes.pressure):
        if not x0 <= pr.x <= x1:
            raise ConfigError(f"probes.pressure[{k}].x", f"must be inside the tank, in "
                              f"[{x0:g}, {x1:g}] m; got {pr.x:g}")
        if not z0 <= pr.z <= z1:
            raise ConfigError(f"probes.pressure[{k}].z", f"must be inside the tank, in "
                              f"[{z0:g}, {z1:g}] m; got {pr.z:g}")
