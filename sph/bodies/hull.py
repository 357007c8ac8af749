r"""Thin-walled ship section: geometry, wall particles, compartments and hydrostatics.

The section of the paper's ship (Cao et al. 2019, Sec. IV A) is U-shaped: flat bottom,
rounded bilges of radius ``R``, vertical sides and a closed flat deck, with plating of
thickness ``t`` much thinner than the kernel support. Coordinates here are the *keel frame*
``(u, w)``: ``u`` across the ship from the centre line, ``w`` up from the outer bottom.

Thin walls: each face of the plating gets its own layers of dummy particles.
The outer face's layers run *into* the hull and belong to the sea compartment; the inner
face's layers run *out* of it and belong to the cabin. The two sets overlap in space with the
other side's fluid, and since a pair of particles interacts only when their compartments
match (or, for two fluid particles, when the segment between them passes through an open
damage opening: :mod:`sph.bodies.damage`), nothing leaks through the plating at any resolution.

The *mid-surface* (the plating's middle line) separates the compartments: its signed
distance :func:`mid_sdf` is negative inside the cabin.

Hydrostatics of the rigid section (per unit length): displaced area, centre of buoyancy,
metacentric radius, and the lost-buoyancy equilibrium of a ship with one cabin open to the
sea (:func:`flooded_draught`), used to check the flooding runs.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from sph.schema import ConfigError, spec


@dataclass(frozen=True)
class HullConfig:
    """Main dimensions of the ship section and its mass properties (every key required: the
    paper's values are the defaults of the built-in cases ``damaged_ship`` and
    ``ship_decay``, in their YAML files)."""

    breadth: float = spec(lo=0.0, lo_open=True, hi=1.0e3, unit="m", doc="B")
    depth: float = spec(lo=0.0, lo_open=True, hi=1.0e3, unit="m", doc="D, keel to deck")
    draught: float = spec(lo=0.0, lo_open=True, hi=1.0e3, unit="m",
                          doc="d, before damage (the hull mass follows from it)")
    bilge_radius: float = spec(lo=0.0, hi=1.0e3, unit="m", doc="outer bilge radius")
    plating: float = spec(lo=0.0, lo_open=True, hi=1.0e2, unit="m",
                          doc="plating thickness (bottom, sides and deck)")
    kg: float = spec(lo=0.0, hi=1.0e3, unit="m",
                     doc="height of the centre of gravity above the keel")
    gyradius: float = spec(lo=0.0, lo_open=True, hi=1.0e3, unit="m",
                           doc="roll radius of gyration about the centre of gravity")
    mass_properties: str = spec(
        choices=("loaded", "dry"),
        doc="what kg and gyradius describe (sph.bodies.cargo): loaded, the whole ship with "
            "its cargo frozen (mass: the displacement at d); dry, the hull, structure and "
            "ballast without the cargo (mass: the displacement minus the cargo)")

    def check(self, key):
        if self.draught >= self.depth:
            raise ConfigError(f"{key}.draught", f"must be in (0, {key}.depth = "
                              f"{self.depth:g}) m; got {self.draught:g}")
        half = 0.5 * self.breadth
        if self.bilge_radius >= min(half, self.depth) - self.plating:
            raise ConfigError(f"{key}.bilge_radius", f"must be in [0, "
                              f"{min(half, self.depth) - self.plating:g}) m (less than half "
                              f"the breadth and the depth, minus the plating); got "
                              f"{self.bilge_radius:g}")
        if self.plating >= 0.25 * min(self.breadth, self.depth):
            raise ConfigError(f"{key}.plating", f"must be in (0, "
                              f"{0.25 * min(self.breadth, self.depth):g}) m; got "
                              f"{self.plating:g}")
        if self.kg >= self.depth:
            raise ConfigError(f"{key}.kg", f"must be in [0, {key}.depth = {self.depth:g}) m; "
                              f"got {self.kg:g}")


def opening_bottom(hull: HullConfig) -> float:
    """Keel-frame height of a side opening's lower edge: the cabin floor (the inner face of
    the bottom plating), as the paper draws it; ``delta`` is measured from there (Cao et al.
    2019, Sec. IV A: "the height from the top of the opening to the bottom of the cabin").
    On a rounded bilge the edge cuts the bilge where its mid-surface reaches the floor's
    height."""
    return float(hull.plating)


def side_point(hull: HullConfig, w: float) -> tuple[float, float]:
    """The point ``(u, w)`` of the plating's mid-surface on the ``+u`` side at keel height
    ``w`` (on the bilge's arc below its top, on the vertical side above)."""
    hw, wb, wt, rb, rt = (float(v) for v in mid_shape(hull))
    if not wb < w <= wt:
        raise ValueError(f"w = {w:g} m is outside the side's mid-surface ({wb:g}, {wt:g}]")
    if w < wb + rb:
        return hw - rb + math.sqrt(rb * rb - (wb + rb - w) ** 2), w
    if w > wt - rt:
        return hw - rt + math.sqrt(rt * rt - (w - wt + rt) ** 2), w
    return hw, w


def opening_aperture(hull: HullConfig, w_low: float, w_high: float) -> float:
    r"""Aperture (m) of a side opening between the keel heights ``w_low`` and ``w_high``:
    the width of the gap the fluid passes through, the straight distance between the
    opening's two edges on the plating's mid-surface.

    Every particle that enters passes between the two edges, so the number of particles
    abreast in the opening is this width over dx. On a vertical side it equals the length
    of plating removed; on the bilge's arc the chord is shorter than the arc (1.43 m
    against 1.49 m for the paper's 5/21 opening at the floor), and a plating that curves
    round between the edges does not widen the passage."""
    u0, w0 = side_point(hull, w_low)
    u1, w1 = side_point(hull, w_high)
    return math.hypot(u1 - u0, w1 - w0)


def shape(hull: HullConfig, offset: float) -> np.ndarray:
    """The hull outline moved ``offset`` inwards (negative: outwards) as the parameters
    ``[half_width, w_bottom, w_top, bottom_radius, top_radius]``."""
    return np.array([0.5 * hull.breadth - offset, offset, hull.depth - offset,
                     max(hull.bilge_radius - offset, 0.0), max(-offset, 0.0)])


def mid_shape(hull: HullConfig) -> np.ndarray:
    """The plating's middle line (separates sea and cabin)."""
    return shape(hull, 0.5 * hull.plating)


def outline_points(s: np.ndarray, spacing: float, vertices: bool = False) -> np.ndarray:
    """Points along the outline ``s`` at (about) ``spacing`` apart, as ``(n, 2)`` (u, w).

    Evenly spread over the whole outline (particles), or, with ``vertices``, starting at
    every corner of the straight and curved pieces (a polygon for areas)."""
    hw, wb, wt, rb, rt = (float(v) for v in s)
    pieces = []  # (length, function of the fraction in [0, 1] -> (u, w))

    def seg(a, b):
        a, b = np.asarray(a, float), np.asarray(b, float)
        return (float(np.hypot(*(b - a))), lambda f, a=a, b=b: a + np.outer(f, b - a))

    def arc(cu, cw, r, a0):
        return (0.5 * math.pi * r, lambda f, cu=cu, cw=cw, r=r, a0=a0: np.column_stack(
            [cu + r * np.cos(a0 + 0.5 * math.pi * f), cw + r * np.sin(a0 + 0.5 * math.pi * f)]))

    # from the middle of the bottom round to it: the points are then mirror-symmetric
    # about u = 0 (as the hull is), whatever the spacing
    pieces += [seg((0.0, wb), (hw - rb, wb)), arc(hw - rb, wb + rb, rb, -0.5 * math.pi),
               seg((hw, wb + rb), (hw, wt - rt)), arc(hw - rt, wt - rt, rt, 0.0),
               seg((hw - rt, wt), (-hw + rt, wt)), arc(-hw + rt, wt - rt, rt, 0.5 * math.pi),
               seg((-hw, wt - rt), (-hw, wb + rb)), arc(-hw + rb, wb + rb, rb, math.pi),
               seg((-hw + rb, wb), (0.0, wb))]
    lengths = np.array([p[0] for p in pieces])
    total = lengths.sum()
    if vertices:  # every piece from its start point: corners exact (for areas)
        return np.concatenate([fn(np.arange(max(int(np.ceil(length / spacing)), 1))
                                  / max(int(np.ceil(length / spacing)), 1))
                               for length, fn in pieces if length > 0])
    n = max(int(round(total / spacing)), 8)
    s_along = (np.arange(n) + 0.5) * total / n
    edges = np.concatenate([[0.0], np.cumsum(lengths)])
    out = np.empty((n, 2))
    for k, (length, fn) in enumerate(pieces):
        sel = (s_along >= edges[k]) & (s_along < edges[k + 1])
        if sel.any() and length > 0:
            out[sel] = fn((s_along[sel] - edges[k]) / length)
    return out


def shell_particles(hull: HullConfig, dx: float, layers: int):
    """Dummy particles of the plating in the keel frame.

    Returns ``(points, inner)``: positions ``(n, 2)`` and a boolean per particle, True for
    the inner face's layers (cabin compartment), False for the outer face's (sea)."""
    t = hull.plating
    pts, inner = [], []
    for k in range(layers):
        o = (k + 0.5) * dx
        outer = outline_points(shape(hull, o), dx)
        inside = outline_points(shape(hull, t - o), dx)
        pts += [outer, inside]
        inner += [np.zeros(len(outer), bool), np.ones(len(inside), bool)]
    return np.concatenate(pts), np.concatenate(inner)


# ---------------------------------------------------------------------------- areas
def _polygon(s: np.ndarray, n: int = 4000) -> np.ndarray:
    return outline_points(s, 2.0 * (s[0] + s[2] - s[1]) * 2.0 / n, vertices=True)


@functools.lru_cache(maxsize=32)
def _section_polygon(hull: HullConfig, offset: float) -> np.ndarray:
    """:func:`_polygon` of the outline moved ``offset`` inwards (cached: the hydrostatic
    solvers clip the same outline at thousands of levels)."""
    poly = _polygon(shape(hull, offset))
    poly.flags.writeable = False
    return poly


def _clip_below(poly: np.ndarray, level: float) -> np.ndarray:
    """Part of a closed polygon below ``w = level`` (Sutherland-Hodgman, one half-plane): for
    each edge ``(a, b)`` in turn, ``a`` if it is below, then the crossing if the edge
    crosses the level."""
    a = poly
    b = np.roll(poly, -1, axis=0)
    ina = a[:, 1] <= level
    cross = ina != (b[:, 1] <= level)
    ac, bc = a[cross], b[cross]
    f = (level - ac[:, 1]) / (bc[:, 1] - ac[:, 1])
    out = np.empty((len(poly), 2, 2))
    out[:, 0] = a
    out[cross, 1] = ac + f[:, None] * (bc - ac)
    keep = np.column_stack([ina, cross])
    return out[keep]  # edge by edge: the vertex, then the crossing


def _area_centroid(poly: np.ndarray) -> tuple[float, float, float]:
    if len(poly) < 3:
        return 0.0, 0.0, 0.0
    u, w = poly[:, 0], poly[:, 1]
    u1, w1 = np.roll(u, -1), np.roll(w, -1)
    cross = u * w1 - u1 * w
    area = 0.5 * cross.sum()
    if abs(area) < 1e-300:
        return 0.0, 0.0, 0.0
    cu = ((u + u1) * cross).sum() / (6.0 * area)
    cw = ((w + w1) * cross).sum() / (6.0 * area)
    return abs(area), cu, cw


def _second_moments(poly: np.ndarray) -> tuple[float, float]:
    """Second moments of area of a closed polygon about its centroid,
    :math:`\\int (u - u_c)^2\\,dA` and :math:`\\int (w - w_c)^2\\,dA` (the shoelace
    sums of the moments about the origin, moved to the centroid by the parallel-axis
    theorem)."""
    area, cu, cw = _area_centroid(poly)
    if area == 0.0:
        return 0.0, 0.0
    u, w = poly[:, 0], poly[:, 1]
    u1, w1 = np.roll(u, -1), np.roll(w, -1)
    cross = u * w1 - u1 * w
    sign = 1.0 if cross.sum() > 0.0 else -1.0
    juu = sign * ((u * u + u * u1 + u1 * u1) * cross).sum() / 12.0 - area * cu * cu
    jww = sign * ((w * w + w * w1 + w1 * w1) * cross).sum() / 12.0 - area * cw * cw
    return float(juu), float(jww)


def submerged_moments(hull: HullConfig, level: float, offset: float = 0.0):
    """Area (m2), centroid height ``w`` (m) and polar second moment of area about the
    centroid :math:`\\int (u - u_c)^2 + (w - w_c)^2\\,dA` (m4) of the outline moved
    ``offset`` inwards, below ``w = level`` (upright section)."""
    poly = _clip_below(_section_polygon(hull, offset), level)
    area, _, cw = _area_centroid(poly)
    juu, jww = _second_moments(poly)
    return area, cw, juu + jww


def submerged(hull: HullConfig, level: float, offset: float = 0.0):
    """Area (m2) and centroid ``(u, w)`` of the outline moved ``offset`` inwards, below
    ``w = level`` (upright section)."""
    return _area_centroid(_clip_below(_section_polygon(hull, offset), level))


def cabin_area(hull: HullConfig) -> float:
    """V: the empty cabin's cross-section area (inside the plating), m2."""
    return submerged(hull, hull.depth, hull.plating)[0]


def hydrostatics(hull: HullConfig, rho0: float, gravity: float) -> dict:
    """Upright intact section at draught d: displacement, KB, BM, GM, and the linear roll and
    heave stiffness per unit length."""
    area, _, kb = submerged(hull, hull.draught)
    bm = hull.breadth**3 / 12.0 / area
    gm = kb + bm - hull.kg
    mass = rho0 * area
    return dict(area=area, mass=mass, kb=kb, bm=bm, gm=gm,
                roll_stiffness=mass * gravity * gm,
                heave_stiffness=rho0 * gravity * hull.breadth)


def flooded_draught(hull: HullConfig, damaged_weight: float) -> float:
    """Equilibrium draught (lost-buoyancy method) when the cabins that make up the fraction
    ``damaged_weight`` of the ship's length are open to the sea below the waterline.

    The damaged cabins keep only the buoyancy of their plating; the others must carry the
    whole mass ``rho0 A(d)``: ``A(d') - w_d A_in(d') = A(d)`` (symmetric section: no heel)."""
    target = submerged(hull, hull.draught)[0]

    def excess(d):
        return (submerged(hull, d)[0] - damaged_weight * submerged(hull, d, hull.plating)[0]
                - target)

    if excess(hull.depth) < 0.0:
        return math.inf  # sinks: the intact cabins cannot carry the ship
    return _bisect(excess, hull.draught, hull.depth)


def flooded_metacentre(hull: HullConfig, damaged_weight: float) -> dict:
    """Upright metacentre of the ship with the cabins of the fraction ``damaged_weight`` of
    its length open to the sea (lost-buoyancy method, as :func:`flooded_draught`): the
    displacement stays the intact one, A(d); the damaged cabins keep the buoyancy and the
    waterplane of their plating only. Returns the draught ``draught`` (m), ``kb``, ``bm``
    and ``km`` (m above the keel; ``bm`` = I' / A(d), I' the waterplane's second moment
    per unit length); ``km`` is inf when the ship sinks. GM after damage is ``km`` less the
    loaded ship's KG, less the cargo's free-surface correction."""
    area = submerged(hull, hull.draught)[0]
    d = flooded_draught(hull, damaged_weight)
    if math.isinf(d):
        return dict(draught=d, kb=math.inf, bm=math.inf, km=math.inf)
    a_out, _, kb_out = submerged(hull, d)
    a_in, _, kb_in = submerged(hull, d, hull.plating)
    kb = (a_out * kb_out - damaged_weight * a_in * kb_in) / area
    b_out, b_in = hull.breadth, hull.breadth - 2.0 * hull.plating
    bm = (b_out**3 - damaged_weight * b_in**3) / 12.0 / area
    return dict(draught=d, kb=kb, bm=bm, km=kb + bm)


def _bisect(fn, lo: float, hi: float, n: int = 80) -> float:
    """Root of an increasing ``fn`` in ``[lo, hi]``."""
    for _ in range(n):
        mid = 0.5 * (lo + hi)
        if fn(mid) < 0.0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def flooded_equilibrium(hull: HullConfig, damaged_weight: float,
                        tank_length: float | None = None) -> dict:
    """Upright equilibrium of the flooded ship, strip by strip, in tanks of finite length.

    In the 2-D strip model each segment floats in its own tank of length ``L``: the water
    that floods the damaged cabin leaves that tank's sea, whose level drops, and the intact
    segments' tank level rises as the ship sinks. With the keel lowered by ``s``, the intact
    tank's level rises by ``(A(d_i) - A(d)) / L`` and the damaged tank's by
    ``(A(d_d) - A_in(d_d) - A(d)) / L`` (water area conserved in each tank, the cabin level
    equal to the outside level), where ``d_i, d_d`` are the draughts below each tank's level
    and ``A, A_in`` the outer and inner (cabin) areas below a level. The keel sinks until
    ``(1 - w) A(d_i) + w (A(d_d) - A_in(d_d)) = A(d)``. ``tank_length=None`` is the open
    sea (the lost-buoyancy draught of :func:`flooded_draught`).

    Returns ``heave`` (keel displacement, m, negative down), the draughts ``d_intact``,
    ``d_damaged`` below each tank's level, the level changes ``rise_intact``,
    ``rise_damaged`` and the flood area ``flood`` (m2)."""
    area0 = submerged(hull, hull.draught)[0]
    inv_l = 0.0 if tank_length is None else 1.0 / tank_length

    def outer(level):
        return submerged(hull, level)[0]

    def inner(level):
        return submerged(hull, level, hull.plating)[0] if level > hull.plating else 0.0

    def draught_intact(s):
        # level rise r with d = d0 + s + r and r = (A(d) - A(d0)) / L
        return _bisect(lambda d: d - hull.draught - s - (outer(d) - area0) * inv_l,
                       hull.draught + s - hull.depth, hull.draught + s + hull.depth)

    def draught_damaged(s):
        return _bisect(lambda d: d - hull.draught - s
                       - (outer(d) - inner(d) - area0) * inv_l,
                       hull.draught + s - hull.depth, hull.draught + s + hull.depth)

    def excess(s):
        di, dd = draught_intact(s), draught_damaged(s)
        return ((1.0 - damaged_weight) * outer(min(di, hull.depth))
                + damaged_weight * (outer(min(dd, hull.depth)) - inner(min(dd, hull.depth)))
                - area0)

    s_max = hull.depth - hull.draught
    if excess(s_max) < 0.0:
        return dict(heave=-math.inf, d_intact=math.inf, d_damaged=math.inf,
                    rise_intact=math.nan, rise_damaged=math.nan, flood=math.nan)
    s = _bisect(excess, 0.0, s_max)
    di, dd = draught_intact(s), draught_damaged(s)
    return dict(heave=-s, d_intact=di, d_damaged=dd, rise_intact=di - hull.draught - s,
                rise_damaged=dd - hull.draught - s, flood=inner(dd))
