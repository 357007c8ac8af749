"""The paper's ship in beam seas (Cao et al. 2019, Sec. IV): strip segments, cargo, damage.

Strip theory: the ship of three equal cabins is simulated as 2-D segments, each
its own wave tank with the same flap wavemaker, all carrying one rigid body (sway, heave,
roll). By symmetry two segments suffice: an intact cabin standing for two cabins' length
(weight 2/3, cargo at fill ratio eta) and the damaged middle cabin (weight 1/3, empty until
the side opening appears at ``t1``). The segments' tanks lie side by side along x, ``pitch``
metres apart, and their compartments are numbered ``2 s`` (sea) and ``2 s + 1`` (cabin).

The ship's mass is the displacement at draught d at every fill; the rigid body is the dry
part (hull, structure, ballast), the cargo is fluid. ``kg`` and ``gyradius`` describe the
loaded ship with its cargo frozen or the dry part alone (``hull.mass_properties``,
:mod:`sph.bodies.cargo`); the dry part's mass, centre of gravity and inertia follow, and the
body's reference point is the dry part's centre of gravity. A cargo of density
``cargo_density`` is simulated as water whose force on the hull is scaled by
``cargo_density / rho0`` (in a single liquid the flow does not depend on its density).

Cases: ``damaged_ship`` (the Table I runs) and ``ship_decay`` (one intact segment in still
water, released with a heel or a heave offset).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from sph.bodies.cargo import (
    MassProperties,
    cargo_section,
    cargo_section_of_particles,
    check_mass_properties,
)
from sph.bodies.damage import DamageOpening, HullGuard, fluid_volume
from sph.bodies.hull import (
    HullConfig,
    cabin_area,
    flooded_metacentre,
    hydrostatics,
    mid_shape,
    opening_aperture,
    opening_bottom,
    outline_points,
    shape,
    shell_particles,
    submerged,
)
from sph.bodies.rigid import DofConfig, RigidBody, Shifted
from sph.bodies.wavemaker import FlapConfig, FlapMotion, flap_wave_amplitude, wavenumber
from sph.cases.base import (
    CaseSetup,
    check_absorber_fits,
    check_probes_inside,
    flap_tank_lattice,
    load_defaults,
    make_particles,
    scales,
    wall_layers,
)
from sph.cases.geometry import fit_cells
from sph.engine.absorber import AbsorberConfig, absorber_params
from sph.engine.config import MAX_LEVEL, CaseConfig, RefinementBox
from sph.engine.kernels import KP_R2MAX
from sph.engine.opening import pack_opening, sdf_many, set_circle
from sph.engine.particles import FLUID
from sph.engine.probes import surface_heights
from sph.engine.walls import tank_guard
from sph.schema import ConfigError, spec

log = logging.getLogger(__name__)

SIDES = {"back": 1.0, "head": -1.0}


# The sections below declare each key's type, allowed range and meaning; their values (the
# defaults of a built-in case) are stated once, in the case's YAML (damaged_ship.yaml,
# ship_decay.yaml), which sph.cases.build_case merges under the user's file.
@dataclass(frozen=True)
class DamageConfig:
    """The side opening of the middle cabin."""

    opening: float = spec(lo=0.0, hi=1.0, doc="delta_bar = delta / d (0: intact)")
    side: str = spec(choices=tuple(SIDES),
                     doc="back: faces +x, away from the wavemaker; head: faces the waves")
    time_periods: float = spec(lo=0.0, hi=1.0e4, doc="t1 in wave periods 2 pi / omega")


@dataclass(frozen=True)
class Geometry:
    depth: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m", doc="water depth H")
    tank_length: float = spec(lo=0.0, lo_open=True, hi=1.0e5, unit="m")
    tank_height: float = spec(lo=0.0, lo_open=True, hi=1.0e4, unit="m")
    ship_x: float = spec(lo=0.0, hi=1.0e5, unit="m", doc="x of the ship's centre line")
    hull: HullConfig
    fill: float = spec(lo=0.0, hi=1.0, hi_open=True,
                       doc="cargo fill ratio eta = h_w / D of the intact cabins")
    cargo_density: float = spec(lo=1.0, hi=1.0e5, unit="kg/m3")
    intact_cabins: int = spec(lo=1, hi=100, doc="cabins the intact segment stands for")
    damaged_cabins: int = spec(lo=0, hi=100, doc="cabins the damaged segment stands for "
                               "(0: simulate the intact segment only)")
    damage: DamageConfig
    heel: float = spec(lo=-30.0, hi=30.0, unit="degree",
                       doc="initial heel, positive towards +x (free decay)")
    heave_offset: float = spec(lo=-1.0e3, hi=1.0e3, unit="m",
                               doc="initial displacement from the hydrostatic position")
    dofs: DofConfig
    wavemaker: FlapConfig
    absorber: AbsorberConfig
    refine_hull: int = spec(0, lo=0, hi=MAX_LEVEL,
                            doc="refinement level around each hull, its cabins and its "
                            "opening (0: none; dx / 2**level there; sph.engine.refinement)")
    refine_margin: float = spec(4.0, lo=0.0, hi=1.0e3, unit="m",
                                doc="the finest box reaches this far beyond the hull's "
                                "breadth, keel and deck (room for its heave and roll)")


# ------------------------------------------------------------------------------ checks
def _segments(g) -> list[dict]:
    """The simulated segments: weight, cargo, damage."""
    total = g.intact_cabins + g.damaged_cabins
    segs = [dict(name="intact", weight=g.intact_cabins / total, cargo=g.fill > 0.0,
                 damaged=False)]
    if g.damaged_cabins:
        segs.append(dict(name="damaged", weight=g.damaged_cabins / total, cargo=False,
                         damaged=g.damage.opening > 0.0))
    return segs


def masses(cfg: CaseConfig, cargo=None) -> MassProperties:
    """Mass properties of the dry part, the cargo and the loaded ship per unit length of
    ship (:mod:`sph.bodies.cargo`), for the cargo ``cargo`` (a
    :class:`~sph.bodies.cargo.CargoSection`; default: the exact section at the case's
    fill); a :class:`~sph.schema.ConfigError` if the dry part is not possible."""
    g = cfg.geometry
    if cargo is None:
        cargo = cargo_section(g.hull, g.fill)
    weight = _segments(g)[0]["weight"]
    return check_mass_properties(g.hull, cfg.fluid.rho0, cfg.fluid.gravity, weight,
                                 g.cargo_density, g.fill, cargo)


def damaged_gm(cfg: CaseConfig, m: MassProperties) -> tuple[float, float]:
    """GM of the loaded ship once its damaged cabins are open to the sea (upright,
    lost-buoyancy method, :func:`sph.bodies.hull.flooded_metacentre`), with the cargo
    frozen and corrected for the cargo's free surface (m); nan without damage, -inf if
    the intact cabins cannot carry the ship."""
    g = cfg.geometry
    segs = _segments(g)
    if len(segs) < 2 or not segs[1]["damaged"]:
        return math.nan, math.nan
    km = flooded_metacentre(g.hull, segs[1]["weight"])["km"]
    if math.isinf(km):
        return -math.inf, -math.inf
    return float(km - m.ship_kg), float(km - m.ship_kg - m.free_surface)


def cargo_area(hull: HullConfig, fill: float) -> float:
    """Cross-section area of cargo at fill ratio ``fill`` (level ``fill D`` above the cabin
    floor), m2."""
    if fill <= 0.0:
        return 0.0
    return submerged(hull, hull.plating + fill * hull.depth, hull.plating)[0]


def damage_time(cfg: CaseConfig) -> float:
    """t1 (s): when the opening appears, ``geometry.damage.time_periods`` wave periods."""
    return cfg.geometry.damage.time_periods * (2.0 * math.pi / cfg.geometry.wavemaker.omega)


def check(cfg: CaseConfig) -> None:
    g, dx = cfg.geometry, cfg.numerics.dx
    hull = g.hull
    if g.depth >= g.tank_height:
        raise ConfigError("geometry.depth", f"must be in (0, geometry.tank_height = "
                          f"{g.tank_height:g}) m; got {g.depth:g}")
    deck = g.depth - hull.draught + hull.depth + abs(g.heave_offset)
    if deck >= g.tank_height:
        raise ConfigError("geometry.tank_height", f"must exceed the deck height "
                          f"{deck:g} m (depth - draught + hull depth); got {g.tank_height:g}")
    if hull.draught >= g.depth:
        raise ConfigError("geometry.hull.draught", f"must be in (0, geometry.depth = "
                          f"{g.depth:g}) m; got {hull.draught:g}")
    half = 0.5 * hull.breadth
    lo, hi = half + 2.0 * hull.breadth / 16.0 + 4 * dx, g.tank_length - half - 4 * dx
    if g.absorber.enabled:
        # half a breadth of open water between the hull and the absorbing zone: the zone
        # damps the flow, and a drifting ship must not push its own flow into it
        hi = min(hi, g.absorber.start - 2.0 * half)
        if g.absorber.mirrored:
            if g.absorber.start < 0.5 * g.tank_length:
                raise ConfigError("geometry.absorber.start", f"must be at least the tank's "
                                  f"middle ({0.5 * g.tank_length:g} m) when mirrored is true, "
                                  f"so that the two zones do not overlap; got "
                                  f"{g.absorber.start:g}")
            lo = max(lo, g.tank_length - g.absorber.start + 2.0 * half)
    if not lo <= g.ship_x <= hi:
        raise ConfigError("geometry.ship_x", f"must be in [{lo:g}, {hi:g}] m so that the "
                          f"ship lies inside the tank, clear of the flap and at least half "
                          f"a breadth from the absorbing zone; got {g.ship_x:g}")
    if hull.plating >= dx:
        log.info("plating %.3g m is at least one particle spacing; it is resolved as thin "
                 "walls all the same", hull.plating)
    opening = g.damage.opening * hull.draught
    if g.damage.opening > 0.0 and g.damaged_cabins:
        top = hull.plating + opening
        allowed = (hull.draught - hull.plating) / hull.draught
        if opening > hull.depth - 2 * hull.plating:
            raise ConfigError("geometry.damage.opening", f"delta = opening * d = {opening:g} "
                              f"m is taller than the cabin ({hull.depth - 2 * hull.plating:g} "
                              f"m); allowed (0, {allowed:.4g})")
        if top >= hull.draught:
            raise ConfigError("geometry.damage.opening", f"the opening's top edge ({top:g} m "
                              f"above the keel) is above the waterline (draught "
                              f"{hull.draught:g} m); allowed (0, {allowed:.4g})")
        check_aperture(hull, g.damage.opening, dx, g.refine_hull)
    dx_hull = dx / 2**g.refine_hull  # the spacing at the hull (geometry.refine_hull)
    if g.fill > 0.0 and g.fill * hull.depth < dx_hull:
        raise ConfigError("geometry.fill", f"cargo height fill * D = {g.fill * hull.depth:g} m "
                          f"is below one particle spacing ({dx_hull:g} m); use 0 or a larger "
                          "fill")
    if g.fill * hull.depth >= hull.depth - 2 * hull.plating:
        raise ConfigError("geometry.fill", f"must leave room below the deck; got {g.fill:g}")
    m = masses(cfg)
    gm_d, gm_d_fluid = damaged_gm(cfg, m)
    if gm_d_fluid < 0.0:
        log.warning("once damaged the ship's GM, corrected for the cargo's free surface, is "
                    "%.3g m (lost-buoyancy method, upright; intact %.3g m, the cargo's "
                    "free-surface correction %.3g m at geometry.fill = %g, "
                    "geometry.cargo_density = %g kg/m3): it will list or capsize after the "
                    "damage (docs/ship.md)", gm_d_fluid, m.gm_fluid, m.free_surface,
                    g.fill, g.cargo_density)
    if g.refine_hull > 0:
        reach = scales(cfg).support / 2 ** (g.refine_hull - 1)
        if g.refine_margin < reach:
            log.warning("geometry.refine_margin = %g m is less than the kernel support of "
                        "the next coarser level (%.3g m): coarser fluid beside the finest "
                        "box reaches the hull's coarser layers and adds its push to the fine "
                        "fluid's, so the hull's forces count part of its pressure twice "
                        "(docs/model.md, 'Variable resolution'); allowed from %.3g m",
                        g.refine_margin, reach, reach)
    check_absorber_fits(g.absorber, g.tank_length)
    check_probes_inside(cfg, 0.0, g.tank_length, 0.0, g.tank_height)
    wm = g.wavemaker
    if g.absorber.enabled and g.absorber.mirrored and (wm.file is not None or wm.amplitude
                                                       or wm.theta0):
        raise ConfigError("geometry.absorber.mirrored", "must be false while the wavemaker "
                          "runs (its mirror image would damp the wave at the flap); a zone at "
                          "each end is for a still tank: geometry.wavemaker.theta0 = 0, no "
                          "amplitude or file")
    if g.absorber.enabled and wm.file is None and (wm.amplitude or wm.theta0):
        length = 2.0 * math.pi / wavenumber(wm.omega, g.depth, cfg.fluid.gravity)
        if g.absorber.length < 0.95 * length:
            log.warning("the absorbing zone (%g m) is %.2f lengths of the %.4g m wave: part "
                        "of the wave reflects from the end wall (a zone of one wave length "
                        "reflects 1-2 %%; sph.study.sweeps.tank_for_wave sizes the tank for "
                        "a wave)", g.absorber.length, g.absorber.length / length, length)


#: an opening narrower than this many particle spacings runs with a warning
APERTURE_WARN_SPACINGS = 4.0


def check_aperture(hull: HullConfig, opening: float, dx: float, level: int = 0) -> float:
    """Refuse an opening whose aperture (:func:`sph.bodies.hull.opening_aperture`, the gap
    between its edges) is narrower than one particle spacing, and warn below
    ``APERTURE_WARN_SPACINGS`` spacings: fewer particles abreast than that resolve the
    jet's contraction at the edges poorly, and the inflow with them. ``level``: the hull's
    refinement level (``geometry.refine_hull``), whose spacing is ``dx / 2**level``. Returns
    the aperture.
    """
    at = (f"numerics.dx = {dx:g} m" if level == 0 else
          f"the hull's spacing {dx / 2**level:g} m (numerics.dx / 2**geometry.refine_hull)")
    dx = dx / 2**level
    z0 = opening_bottom(hull)
    z1 = hull.plating + opening * hull.draught
    aperture = opening_aperture(hull, z0, z1)
    spacings = aperture / dx
    if spacings < 1.0:
        raise ConfigError("geometry.damage.opening", f"the opening {opening:.4g} (delta = "
                          f"{opening * hull.draught:.3g} m) has an aperture of {aperture:.3g} "
                          f"m, narrower than one particle spacing ({at}): use a larger "
                          f"opening or a spacing <= {aperture:.3g} m there")
    if spacings < APERTURE_WARN_SPACINGS:
        log.warning("the damage opening %.4g (delta = %.3g m) has an aperture of %.3g m, "
                    "%.3g particle spacings at %s: its inflow is under-resolved (%g or more "
                    "recommended: a spacing <= %.3g m there, or geometry.refine_hull)",
                    opening, opening * hull.draught, aperture, spacings, at,
                    APERTURE_WARN_SPACINGS, aperture / APERTURE_WARN_SPACINGS)
    return aperture


# ------------------------------------------------------------------------------ set-up
#: the body's coupling is stabilised with the cargo as added mass where the cargo outweighs
#: the dry part this many times (:mod:`sph.bodies.rigid`). Explicitly coupled, the 75 % oil
#: cargo (5.9 times its dry part) threw the ship 3 m up within 0.5 s; the 50 % water cargo
#: (2.0 times) runs stably without, and with the stabilisation its heeled decay shifted (heave
#: 0.1-0.15 m higher, the upper roll mode 0.93 rad/s against 1.20), which is not understood
#: yet: so only where it is needed (docs/ship.md)
STABILISE_RATIO = 3.0


def _pose(g, x_offset: float, kg: float):
    """Initial centre of gravity (earth) and angle (counter-clockwise) of a segment whose
    body's centre of gravity is ``kg`` above the keel."""
    hull = g.hull
    cog = np.array([g.ship_x + x_offset, g.depth - hull.draught + kg + g.heave_offset])
    return cog, -math.radians(g.heel)


def _to_earth(uw, kg, cog, theta):
    """Keel frame -> (body frame relative to the cog, earth)."""
    body = np.column_stack([uw[:, 0], uw[:, 1] - kg])
    ct, st = math.cos(theta), math.sin(theta)
    earth = np.column_stack([cog[0] + ct * body[:, 0] - st * body[:, 1],
                             cog[1] + st * body[:, 0] + ct * body[:, 1]])
    return body, earth


def cabin_probe_scale(u, kind, hs, u_probe: float, radius: float) -> float:
    """The smoothing-length ratio (``hs``) of the region a cabin probe at ``u_probe`` lies
    in: that of the finest walls within the kernel's reach ``radius`` of its line (the
    walls of a refined cabin come in every level, the finest where its box covers it); 1
    under uniform resolution or with no wall in reach."""
    near = (kind != FLUID) & (np.abs(u - u_probe) < radius)
    return float(hs[near].min()) if np.any(near) else 1.0


def cabin_probe_u(breadth: float, plating: float, side: str) -> float:
    """Where the cabin probes W1 and W2 sit across the ship (m from its centre line, + towards
    +x when upright): B/160 inside the damaged side's inner face. A level surface reads
    ``u tan(roll)`` there (roll + towards +x), the heel of the frame they read in."""
    return SIDES[side] * (0.5 * breadth - plating - breadth / 160.0)


def _to_keel(xz, kg, cog, theta):
    ct, st = math.cos(theta), math.sin(theta)
    rx, rz = xz[:, 0] - cog[0], xz[:, 1] - cog[1]
    return ct * rx + st * rz, -st * rx + ct * rz + kg


def _opening_pids(hull, shell_uw, side, z0, z1, pids):
    """Wall particles whose nearest mid-surface point lies in the opening."""
    from scipy.spatial import cKDTree

    mid = outline_points(mid_shape(hull), 0.01 * hull.plating + 1e-3)
    in_open = (side * mid[:, 0] > 0.0) & (mid[:, 1] >= z0) & (mid[:, 1] <= z1)
    _, nearest = cKDTree(mid).query(shell_uw)
    return pids[in_open[nearest]]


def _opening_circle(hull, side, z0, z1, reach, kg):
    """Centre (hull frame: ``u``, ``w - kg``) and squared reach of a circle holding the
    opening's part of the mid-surface, widened by ``reach`` (the kernel support) and a
    margin for the bisection's tolerance (:func:`sph.engine.opening.crosses_opening`)."""
    spacing = 0.01 * hull.plating + 1e-3
    mid = outline_points(mid_shape(hull), spacing)
    span = mid[(side * mid[:, 0] > 0.0) & (mid[:, 1] >= z0) & (mid[:, 1] <= z1)]
    lo, hi = span.min(axis=0), span.max(axis=0)
    centre = 0.5 * (lo + hi)
    radius = 0.5 * float(np.hypot(*(hi - lo))) + 2.0 * spacing
    return centre[0], centre[1] - kg, (radius + 1.05 * reach) ** 2


def _sea_columns(g, dx, xs, cog, theta, outer, kg):
    """Sea particles of one segment's tank: the lattice columns ``xs`` of the tank, each
    filled from the tank bottom to the still level or to the hull bottom above it; returns
    points and volumes."""
    hull = g.hull
    fine = np.linspace(0.0, g.depth, int(math.ceil(g.depth / (0.02 * dx))) + 1)
    pts, vols = [], []
    for xc in xs:
        top = g.depth
        under = False
        if abs(xc - cog[0]) < hull.breadth:
            col = np.column_stack([np.full_like(fine, xc), fine])
            d = sdf_many(*_to_keel(col, kg, cog, theta), outer)
            inside = np.nonzero(d < 0.0)[0]
            if len(inside):
                k = inside[0]
                top = fine[k - 1] + (fine[k] - fine[k - 1]) * d[k - 1] / (d[k - 1] - d[k]) \
                    if k > 0 else 0.0
                under = True
        zs, dz = fit_cells(0.0, top, dx)
        if not len(zs):
            continue
        col = np.column_stack([np.full_like(zs, xc), zs])
        # beside the hull keep half a spacing of clearance; under it the column already
        # ends half a (vertical) spacing below the plating
        d = sdf_many(*_to_keel(col, kg, cog, theta), outer)
        keep = d >= (0.25 if under else 0.5) * dx * 0.999
        pts.append(col[keep])
        vols.append(np.full(keep.sum(), dx * dz))
    return np.concatenate(pts), np.concatenate(vols)


def _cargo_columns(hull, fill, dx, inner):
    """Cargo particles in the keel frame: columns across the cabin, each filled from the
    cabin floor (or the bilge) up to the level ``plating + fill D``; returns points, volumes
    and the level."""
    level = hull.plating + fill * hull.depth
    width = hull.breadth - 2.0 * hull.plating
    us, du = fit_cells(-0.5 * width, 0.5 * width, dx)
    fine = np.linspace(hull.plating, level, int(math.ceil((level - hull.plating)
                                                           / (0.02 * dx))) + 1)
    pts, vols = [], []
    for uc in us:
        d = sdf_many(np.full_like(fine, uc), fine, inner)
        wet = np.nonzero(d < 0.0)[0]
        if not len(wet):
            continue
        k = wet[0]
        bottom = fine[k - 1] + (fine[k] - fine[k - 1]) * d[k - 1] / (d[k - 1] - d[k]) \
            if k > 0 else fine[0]
        ws, dz = fit_cells(bottom, level, dx)
        if not len(ws):
            continue
        col = np.column_stack([np.full_like(ws, uc), ws])
        keep = sdf_many(col[:, 0], col[:, 1], inner) <= -0.25 * dx * 0.999
        pts.append(col[keep])
        vols.append(np.full(keep.sum(), du * dz))
    return np.concatenate(pts), np.concatenate(vols), level


def hull_boxes(g, dx: float, pitch: float, n_seg: int
               ) -> tuple[list[RefinementBox], list[int]]:
    """Refinement boxes around each segment's hull (``geometry.refine_hull``): one of that
    level reaching ``refine_margin`` beyond the hull's breadth, keel and deck, inside one of
    each coarser level that is wider by the finer level's buffer of ghosts and one spacing
    of its own (:data:`sph.engine.refinement.BUFFER`), so that every buffer lies in the
    next coarser box. Returns the boxes and the wall group of the hull each follows
    (segment ``s``'s hull is group ``1 + n_seg + s``)."""
    from sph.engine.refinement import BUFFER

    out, groups = [], []
    hull = g.hull
    keel = g.depth - hull.draught + g.heave_offset
    for s in range(n_seg):
        xc = g.ship_x + s * pitch
        grow = g.refine_margin
        for level in range(g.refine_hull, 0, -1):
            out.append(RefinementBox(x=(xc - 0.5 * hull.breadth - grow,
                                        xc + 0.5 * hull.breadth + grow),
                                     z=(keel - grow, keel + hull.depth + grow), level=level))
            groups.append(1 + n_seg + s)
            grow += (BUFFER + 2.0) * dx * 2.0 ** -level
    return out, groups


def setup(cfg: CaseConfig) -> CaseSetup:
    g, dx = cfg.geometry, cfg.numerics.dx
    hull, rho0 = g.hull, cfg.fluid.rho0
    layers = wall_layers(cfg)
    sc = scales(cfg)
    t = layers * dx
    segs = _segments(g)
    n_seg = len(segs)
    pitch = g.tank_length + 2 * t + sc.support + 2 * dx
    flap = FlapMotion(g.wavemaker, g.depth, cfg.fluid.gravity)
    omega = g.wavemaker.omega
    period = 2.0 * math.pi / omega
    outer, inner_s = shape(hull, 0.0), shape(hull, hull.plating)
    side = SIDES[g.damage.side]
    z0 = opening_bottom(hull)
    z1 = hull.plating + g.damage.opening * hull.draught
    shell_uw, shell_inner = shell_particles(hull, dx, layers)

    # the cargo as placed (keel frame) fixes the dry part's mass, centre of gravity and
    # inertia (sph.bodies.cargo), and so the body's reference point, kg above the keel
    if segs[0]["cargo"]:
        cl, c_vol, level = _cargo_columns(hull, g.fill, dx, inner_s)
        m = masses(cfg, cargo_section_of_particles(hull, g.fill, cl[:, 0], cl[:, 1], c_vol))
    else:
        m = masses(cfg)
    kg = m.dry_kg

    fluid_xz, fluid_comp, fluid_surf, fluid_vol = [], [], [], []
    wall_xz, wall_body_xz, wall_group, wall_comp, wall_tag = [], [], [], [], []
    for s, seg in enumerate(segs):
        x_off = s * pitch
        cog, theta = _pose(g, x_off, kg)
        pts, inside, wall_mask, group = flap_tank_lattice(dx, layers, g.tank_length,
                                                          g.tank_height)
        pts = pts + np.array([x_off, 0.0])
        sea, sea_vol = _sea_columns(g, dx, np.unique(pts[inside, 0]), cog, theta, outer,
                                     kg)
        fluid_xz.append(sea)
        fluid_vol.append(sea_vol)
        fluid_comp.append(np.full(len(sea), 2 * s, np.int32))
        fluid_surf.append(np.full(len(sea), g.depth))
        walls = pts[wall_mask]
        wall_xz.append(walls)
        wall_body_xz.append(walls - np.array([x_off, 0.0]) * (group[:, None] > 0))
        wall_group.append(np.where(group > 0, 1 + s, 0).astype(np.int32))
        wall_comp.append(np.full(len(walls), 2 * s, np.int32))
        wall_tag.append(np.zeros(len(walls), np.int32))
        # hull plating: outer-face layers face the sea, inner-face layers the cabin
        body_xz, earth = _to_earth(shell_uw, kg, cog, theta)
        wall_xz.append(earth)
        wall_body_xz.append(body_xz)
        wall_group.append(np.full(len(earth), 1 + n_seg + s, np.int32))
        wall_comp.append(np.where(shell_inner, 2 * s + 1, 2 * s).astype(np.int32))
        wall_tag.append(np.full(len(earth), 1 + s, np.int32))  # hull of segment s (local tag)
        if seg["cargo"]:
            _, earth = _to_earth(cl, kg, cog, theta)
            fluid_xz.append(earth)
            fluid_vol.append(c_vol)
            fluid_comp.append(np.full(len(cl), 2 * s + 1, np.int32))
            fluid_surf.append(earth[:, 1] + (level - cl[:, 1]) * math.cos(theta))

    fluid_xz = np.concatenate(fluid_xz)
    wall_xz = np.concatenate(wall_xz)
    wall_group = np.concatenate(wall_group)
    wall_tag = np.concatenate(wall_tag)
    parts = make_particles(cfg, fluid_xz, wall_xz, np.concatenate(fluid_surf), g.depth,
                           wall_body=wall_group, wall_body_xz=np.concatenate(wall_body_xz),
                           fluid_volume=np.concatenate(fluid_vol))
    nf = len(fluid_xz)
    parts.comp[:nf] = np.concatenate(fluid_comp)
    parts.comp[nf:] = np.concatenate(wall_comp)

    # the dry part: the rigid body (the cargo is fluid)
    cog0, theta0 = _pose(g, 0.0, kg)
    # a dry part much lighter than its cargo needs the cargo's mass and frozen inertia about
    # its centre of gravity as the added mass of a stabilised coupling (sph.bodies.rigid)
    j_cargo = m.cargo_inertia + m.cargo * (m.cargo_kg - m.dry_kg) ** 2
    added = (m.cargo, m.cargo, j_cargo) if m.cargo > STABILISE_RATIO * m.dry else (0.0,) * 3
    body = RigidBody(m.dry, m.dry_inertia, cog0, g.dofs, cfg.fluid.gravity,
                     segments=[(1 + n_seg + s, seg["weight"], s * pitch)
                               for s, seg in enumerate(segs)],
                     added_mass=added)
    body.q[2] = theta0
    motions = [Shifted(flap, s * pitch) for s in range(n_seg)]
    motions += [body.segment_motion(s) for s in range(n_seg)]

    # force of the cargo on the hull scaled to its own density
    force_scale = np.ones(2 * n_seg)
    if segs[0]["cargo"]:
        force_scale[1] = g.cargo_density / rho0

    # every hull keeps its sea outside and its cabin fluid inside; the damaged segment's
    # opening (its own parameter array) lets fluid change side through it
    opening = None
    events = []
    d_seg = next((s for s, seg in enumerate(segs) if seg["damaged"]), None)
    hull_params = []
    for s in range(n_seg):
        hull_params.append(pack_opening(
            sea=2 * s, cabin=2 * s + 1, group=1 + n_seg + s, side=side, w_low=z0, w_high=z1,
            shape=mid_shape(hull), kg=kg, reach=sc.support, margin=0.5 * dx))
    if d_seg is not None:
        pid_hull = np.arange(nf, parts.n)[(wall_tag == 1 + d_seg)]
        shell_of_seg = shell_uw  # same layout in every segment
        in_opening = _opening_pids(hull, shell_of_seg, side, z0, z1, pid_hull)
        set_circle(hull_params[d_seg], _opening_circle(hull, side, z0, z1, sc.support,
                                                                kg))
        opening = DamageOpening(damage_time(cfg), hull_params[d_seg], in_opening)
        events.append(opening)
    events.append(HullGuard(hull_params))

    # diagnostics: flood volume and ratio; body-fixed probes W1 (cargo cabin), W2 (damaged)
    v_cabin = cabin_area(hull)
    diagnostics = {}
    if n_seg > 1:
        c_in = 2 * (n_seg - 1) + 1

        def flood_volume(p, time):
            return fluid_volume(p.m, p.rho, p.kind, p.comp, c_in)

        diagnostics["flood_volume"] = flood_volume
        diagnostics["flood_ratio"] = lambda p, time: flood_volume(p, time) / v_cabin
    kp = sc.kp
    radius = math.sqrt(kp[KP_R2MAX])
    u_probe = cabin_probe_u(hull.breadth, hull.plating, g.damage.side)

    def cabin_probe(s):
        def height(p):
            kin = motions[n_seg + s].kinematics()
            sel = p.comp == 2 * s + 1  # the cabin's fluid and the walls that face it
            if not np.any(p.kind[sel] == FLUID):
                return 0.0
            xz = np.column_stack([p.x[sel], p.z[sel]])
            u, w = _to_keel(xz, kg, kin[:2], kin[2])
            m, rho, kind, comp = p.m[sel], p.rho[sel], p.kind[sel], p.comp[sel]
            hs = p.hs[sel]
            scale = cabin_probe_scale(u, kind, hs, u_probe, radius)
            if scale != 1.0:
                # walls of every level line a refined cabin, and the probe lies in one
                # level's region (the stepper passes only the mass-carrying fluid): that
                # level's walls and kernel, by lengths measured in its smoothing length
                keep = (kind == FLUID) | (hs == scale)
                u, w, m = u[keep] / scale, w[keep] / scale, m[keep] / scale**2
                rho, kind, comp = rho[keep], kind[keep], comp[keep]
            out = surface_heights(u, w, m, rho, kind, comp, -1, np.array([u_probe / scale]),
                                  kp, hull.plating / scale, 0.1 * dx, True)[0]
            return 0.0 if math.isnan(out) else float(out * scale - hull.plating)
        return height

    extra = {"W1": (cabin_probe(0), g.fill * hull.depth if segs[0]["cargo"] else 0.0)}
    if n_seg > 1:
        extra["W2"] = (cabin_probe(n_seg - 1), 0.0)

    swing = g.tank_height * math.sin(min(4.0 * flap.theta0, 0.5)) + dx
    # half a spacing beyond the last wall layer: built by another sum, it can lie a
    # rounding error outside the nominal end of the tank
    bounds = (-t - swing, (n_seg - 1) * pitch + g.tank_length + t + 0.5 * dx, -t,
              g.tank_height + g.depth)
    k = wavenumber(omega, g.depth, cfg.fluid.gravity)
    hs = hydrostatics(hull, rho0, cfg.fluid.gravity)
    gm_damaged = damaged_gm(cfg, m)
    attrs = dict(depth=g.depth, tank_length=g.tank_length, ship_x=g.ship_x,
                 breadth=hull.breadth, hull_depth=hull.depth, draught=hull.draught,
                 bilge_radius=hull.bilge_radius, plating=hull.plating, kg=hull.kg,
                 gyradius=hull.gyradius, mass_properties=hull.mass_properties,
                 gm=m.gm, gm_fluid=m.gm_fluid, free_surface=m.free_surface, kb=hs["kb"],
                 bm=hs["bm"], gm_damaged=gm_damaged[0], gm_damaged_fluid=gm_damaged[1],
                 opening=g.damage.opening if g.damaged_cabins else 0.0,
                 side=g.damage.side, fill=g.fill, cargo_density=g.cargo_density,
                 damage_time=damage_time(cfg), wave_period=period,
                 theta0=flap.theta0, omega=omega, wave_amplitude=_amplitude(flap, g, cfg),
                 displacement=m.displacement, dry_mass=m.dry, dry_kg=m.dry_kg,
                 roll_inertia=m.dry_inertia, cargo_mass=m.cargo, cargo_kg=m.cargo_kg,
                 ship_kg=m.ship_kg, ship_roll_inertia=m.ship_inertia, cabin_area=v_cabin,
                 segments=n_seg,
                 segment_weights=" ".join(f"{seg['weight']:.6g}" for seg in segs),
                 segment_pitch=pitch, heel=g.heel, heave_offset=g.heave_offset,
                 opening_wall_particles=len(opening.opening_pids) if opening else 0)
    # each segment's boxes follow its hull: the ship drifts with the waves, 25-30 m over
    # the Table I runs, far beyond any margin
    boxes, box_groups = hull_boxes(g, dx, pitch, n_seg)
    setup_ = CaseSetup(parts, bounds, g.depth, motions=motions, bodies=[body], events=events,
                       refinement=boxes, refinement_groups=box_groups,
                       refinement_step=0.5 * g.refine_margin,
                       diagnostics=diagnostics, attrs=attrs,
                       absorber=absorber_params(g.absorber, omega / k, dx, pitch=pitch,
                                               middle=0.5 * g.tank_length),
                       still_level=g.depth, extra_probes=extra, opening=opening,
                       probe_comp=0, force_scale=force_scale,
                       # the floor (the end walls of several segments' tanks lie apart)
                       tank_guard=tank_guard(-math.inf, math.inf, 0.0, g.tank_height, dx,
                                             layers))
    return setup_


def _amplitude(flap, g, cfg) -> float:
    if g.wavemaker.file:
        return float("nan")
    return flap_wave_amplitude(flap.theta0, g.wavemaker.omega, g.depth, cfg.fluid.gravity)


class DamagedShip:
    """Damaged ship in beam seas, case ``damaged_ship`` (Cao et al. 2019, Table I)."""

    Geometry = Geometry
    check = staticmethod(check)
    setup = staticmethod(setup)

    @staticmethod
    def defaults() -> dict:
        return load_defaults("damaged_ship")


class ShipDecay:
    """Free heave or roll decay of the intact ship in still water, case ``ship_decay``."""

    Geometry = Geometry
    check = staticmethod(check)
    setup = staticmethod(setup)

    @staticmethod
    def defaults() -> dict:
        return load_defaults("ship_decay")
