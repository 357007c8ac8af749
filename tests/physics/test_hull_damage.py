"""Ship section geometry, hydrostatics, the pair rule through a damage opening, and the
ship cases' input checks."""

import dataclasses
import logging
import math

import numpy as np
import pytest

from sph.bodies.damage import orifice_rate
from sph.bodies.hull import (
    cabin_area,
    flooded_draught,
    flooded_equilibrium,
    flooded_metacentre,
    hydrostatics,
    mid_shape,
    opening_aperture,
    opening_bottom,
    shape,
    shell_particles,
    side_point,
    submerged,
)
from sph.cases import build_case, builtin
from sph.engine.kernels import kernel_params
from sph.engine.opening import OP_SIZE, keep_sides, passable, sdf, wall_hidden
from sph.engine.probes import surface_heights
from sph.engine.walls import fixed_kinematics
from sph.schema import ConfigError

#: the paper's hull, as the built-in ship cases define it
HULL = builtin("damaged_ship").geometry.hull


def test_section_areas_match_closed_form():
    b, d, r, t = HULL.breadth, HULL.depth, HULL.bilge_radius, HULL.plating
    corners = (2.0 - math.pi / 2.0)  # two rounded bottom corners: 2 (1 - pi/4) R^2
    assert submerged(HULL, d)[0] == pytest.approx(b * d - corners * r * r, rel=1e-5)
    assert submerged(HULL, HULL.draught)[0] == pytest.approx(
        b * HULL.draught - corners * r * r, rel=1e-5)
    assert cabin_area(HULL) == pytest.approx(
        (b - 2 * t) * (d - 2 * t) - corners * (r - t) ** 2, rel=1e-5)


def test_box_hydrostatics_closed_form():
    box = dataclasses.replace(HULL, bilge_radius=0.0, kg=3.0)
    hs = hydrostatics(box, 1000.0, 9.81)
    b, d = box.breadth, box.draught
    assert hs["kb"] == pytest.approx(d / 2, rel=1e-6)
    assert hs["bm"] == pytest.approx(b * b / (12 * d), rel=1e-6)
    assert hs["gm"] == pytest.approx(d / 2 + b * b / (12 * d) - 3.0, rel=1e-6)
    # lost buoyancy, box section: B d' - w (B - 2t)(d' - t) = B d
    w, t = 1 / 3, box.plating
    expect = (b * d - w * (b - 2 * t) * t) / (b - w * (b - 2 * t))
    assert flooded_draught(box, w) == pytest.approx(expect, rel=1e-6)
    assert flooded_draught(box, 1.0) == math.inf  # every cabin open: it sinks


def test_flooded_metacentre_box_closed_form():
    """Lost buoyancy, box section: the damaged cabins keep their plating's buoyancy
    (B d' - w (B - 2t)(d' - t)) and waterplane (B^3 - w (B - 2t)^3) / 12, the displacement
    stays B d."""
    box = dataclasses.replace(HULL, bilge_radius=0.0)
    b, d, t, w = box.breadth, box.draught, box.plating, 1 / 3
    dd = flooded_draught(box, w)
    kb = (b * dd * dd / 2 - w * (b - 2 * t) * (dd - t) * (dd + t) / 2) / (b * d)
    bm = (b**3 - w * (b - 2 * t) ** 3) / 12 / (b * d)
    got = flooded_metacentre(box, w)
    assert got["draught"] == pytest.approx(dd, rel=1e-9)
    assert got["kb"] == pytest.approx(kb, rel=1e-6)
    assert got["bm"] == pytest.approx(bm, rel=1e-6)
    assert got["km"] == pytest.approx(kb + bm, rel=1e-6)
    assert flooded_metacentre(box, 1.0)["km"] == math.inf


def test_damaged_stability_of_the_table_i_loadings(caplog):
    """The loaded ship once the middle cabin is open to the sea (lost buoyancy, upright):
    the empty ship keeps GM 3.20 m (3.88 intact); water at 25 and 50 % leaves it -0.11 m
    after the cargo's free-surface correction of 3.31 m (intact +0.57 m), so the ship lists
    or capsizes after the damage (a coarse sweep with water: a list of 23 degree at 25 %,
    capsized at 50 %, docs/ship.md), and the case warns before any run; Table I's 850 kg/m3
    oil leaves +0.39 m at every fill."""
    from sph.cases.ship import damaged_gm, masses

    def gms(*over):
        cfg = builtin("damaged_ship", list(over))
        return damaged_gm(cfg, masses(cfg))

    assert gms()[1] == pytest.approx(3.197, abs=0.005)
    with caplog.at_level(logging.WARNING, logger="sph.cases.ship"):
        caplog.clear()
        assert gms("geometry.fill=0.5", "geometry.cargo_density=1000")[1] == pytest.approx(
            -0.112, abs=0.005)
        assert "will list or capsize" in caplog.text and "geometry.fill = 0.5" in caplog.text
        caplog.clear()
        assert gms("geometry.fill=0.75", "geometry.cargo_density=850")[1] == pytest.approx(
            0.385, abs=0.005)
        assert "capsize" not in caplog.text
    assert math.isnan(gms("geometry.damage.opening=0")[0])


def test_flooded_equilibrium_in_finite_tanks_box_closed_form():
    """Box section, tanks of length L: each tank's water area is conserved, the cabin level
    equals the damaged tank's level; all relations are linear in the keel sinkage s."""
    box = dataclasses.replace(HULL, bilge_radius=0.0)
    b, d, t, w, L = box.breadth, box.draught, box.plating, 1 / 3, 70.0
    bi = b - 2 * t

    def balance(s):
        di = d + s / (1 - b / L)
        dd = (d + s + (bi * t - b * d) / L) / (1 - (b - bi) / L)
        return (1 - w) * b * di + w * (b * dd - bi * (dd - t)) - b * d, di, dd

    f0, f1 = balance(0.0)[0], balance(1.0)[0]
    s = -f0 / (f1 - f0)
    _, di, dd = balance(s)
    eq = flooded_equilibrium(box, w, tank_length=L)
    assert eq["heave"] == pytest.approx(-s, rel=1e-6)
    assert eq["d_intact"] == pytest.approx(di, rel=1e-6)
    assert eq["d_damaged"] == pytest.approx(dd, rel=1e-6)
    assert eq["flood"] == pytest.approx(bi * (dd - t), rel=1e-6)
    # the open sea is the lost-buoyancy draught; a longer tank approaches it
    sea = flooded_equilibrium(box, w)
    assert -sea["heave"] + d == pytest.approx(flooded_draught(box, w), rel=1e-9)
    far = flooded_equilibrium(box, w, tank_length=1e6)
    assert far["heave"] == pytest.approx(sea["heave"], rel=1e-4)
    assert abs(eq["heave"]) < abs(sea["heave"])  # the damaged tank's level drops


def test_sdf_sign_and_distance():
    s = shape(HULL, 0.0)
    assert sdf(0.0, 4.0, s) == pytest.approx(-4.0)  # deepest inside point: 4 m to the bottom
    assert sdf(9.0, 4.0, s) == pytest.approx(1.0)
    assert sdf(0.0, -0.5, s) == pytest.approx(0.5)
    # on the bilge: distance to the arc of radius R centred at (B/2 - R, R)
    c = np.array([8.0 - 1.5, 1.5])
    p = c + 2.0 * np.array([math.cos(-0.7), math.sin(-0.7)])
    assert sdf(p[0], p[1], s) == pytest.approx(0.5, abs=1e-12)


def test_shell_layers_lie_on_their_faces():
    dx, layers = 0.4, 4
    pts, inner = shell_particles(HULL, dx, layers)
    d_out = np.array([sdf(u, w, shape(HULL, 0.0)) for u, w in pts])
    d_in = np.array([sdf(u, w, shape(HULL, HULL.plating)) for u, w in pts])
    # outer-face layers inside the outer surface, inner-face layers outside the inner one,
    # each within `layers` spacings of its face
    assert np.all(d_out[~inner] < 0) and np.all(d_out[~inner] > -layers * dx - 1e-9)
    assert np.all(d_in[inner] > 0) and np.all(d_in[inner] < layers * dx + 1e-9)
    # particle spacing along each layer close to dx
    first = pts[~inner][: len(pts[~inner]) // layers]
    gaps = np.hypot(*np.diff(first, axis=0).T)
    assert np.median(gaps) == pytest.approx(dx, rel=0.05)


def _opening(side=1.0, z1=2.1, open_=True):
    op = np.zeros(OP_SIZE)
    op[:7] = (1.0 if open_ else 0.0, 0, 1, 0, side, HULL.plating, z1)
    op[7:12] = mid_shape(HULL)
    op[12] = 0.0  # reference point at the keel
    op[13] = 2.0
    return op, fixed_kinematics(1)


def test_pair_rule_through_the_opening():
    op, kin = _opening()
    # across the +x side inside the opening's height: sea (0) and cabin (1) see each other
    assert passable(8.3, 1.5, 7.6, 1.5, 0, 1, op, kin)
    assert passable(7.6, 1.5, 8.3, 1.5, 1, 0, op, kin)
    # across the plating above the opening, across the other side, or the bottom: blocked
    assert not passable(8.3, 3.0, 7.6, 3.0, 0, 1, op, kin)
    assert not passable(-8.3, 1.5, -7.6, 1.5, 0, 1, op, kin)
    assert not passable(2.0, -0.3, 2.0, 0.4, 0, 1, op, kin)
    # both on the same side of the plating, or compartments that the opening does not join
    assert not passable(8.3, 1.5, 8.9, 1.5, 0, 1, op, kin)
    assert not passable(8.3, 1.5, 7.6, 1.5, 0, 3, op, kin)
    # a closed opening joins nothing; a head-side opening faces -x
    assert not passable(8.3, 1.5, 7.6, 1.5, 0, 1, *_opening(open_=False))
    assert passable(-8.3, 1.5, -7.6, 1.5, 0, 1, *_opening(side=-1.0))


def test_pair_rule_follows_the_body():
    op, kin = _opening()
    op[12] = 4.0  # reference point 4 m above the keel
    kin[0, :3] = (100.0, 30.0, math.radians(10.0))  # moved and heeled 10 deg towards -x
    ct, st = math.cos(kin[0, 2]), math.sin(kin[0, 2])

    def earth(u, w):
        return 100.0 + ct * u - st * (w - 4.0), 30.0 + st * u + ct * (w - 4.0)

    assert passable(*earth(8.3, 1.5), *earth(7.6, 1.5), 0, 1, op, kin)
    assert not passable(*earth(8.3, 3.0), *earth(7.6, 3.0), 0, 1, op, kin)


def test_wall_layers_across_the_opening_are_hidden():
    op, kin = _opening()  # damaged hull = wall group 0
    # a cabin particle inside the opening and a cabin-face layer behind the removed plating
    # (outside the hull): hidden; the same layer above the opening: seen
    assert wall_hidden(7.6, 1.5, 8.35, 1.5, 0, op, kin)
    assert not wall_hidden(7.6, 3.5, 8.35, 3.5, 0, op, kin)
    # another body's walls and a closed opening: always seen
    assert not wall_hidden(7.6, 1.5, 8.35, 1.5, 1, op, kin)
    closed, _ = _opening(open_=False)
    assert not wall_hidden(7.6, 1.5, 8.35, 1.5, 0, closed, kin)


def test_opening_lower_edge_at_the_cabin_floor():
    # the paper measures delta from the cabin bottom: the lower edge is the floor's height,
    # where it cuts the bilge's mid-surface arc (radius r = 1.5 - 0.05, centre 1.5 m up)
    assert opening_bottom(HULL) == pytest.approx(HULL.plating)
    r, t = HULL.bilge_radius - 0.5 * HULL.plating, HULL.plating
    u, w = side_point(HULL, t)
    assert w == t
    assert u == pytest.approx(0.5 * HULL.breadth - HULL.bilge_radius
                              + math.sqrt(r * r - (HULL.bilge_radius - t) ** 2))
    assert side_point(HULL, 3.0) == pytest.approx((0.5 * (HULL.breadth - t), 3.0))
    with pytest.raises(ValueError):
        side_point(HULL, 0.0)  # below the bottom's mid-surface


def test_opening_aperture_is_the_gap_between_its_edges():
    t, b, rb = HULL.plating, HULL.breadth, HULL.bilge_radius
    r = rb - 0.5 * t
    u0 = 0.5 * b - rb + math.sqrt(r * r - (rb - t) ** 2)  # lower edge on the bilge
    # the 10/21 opening's top edge (2.1 m) on the vertical side: the chord from the floor
    top = t + 10 / 21 * HULL.draught
    assert opening_aperture(HULL, t, top) == pytest.approx(
        math.hypot(0.5 * (b - t) - u0, top - t))
    # the 5/21 opening ends on the arc: 1.43 m between its edges, for a 1 m height
    top = t + 5 / 21 * HULL.draught
    u1 = 0.5 * b - rb + math.sqrt(r * r - (rb - top) ** 2)
    ap = opening_aperture(HULL, t, top)
    assert ap == pytest.approx(math.hypot(u1 - u0, top - t))
    assert ap == pytest.approx(1.426, abs=1e-3)
    # shorter than the arc of plating it removes, longer than its height
    a0, a1 = math.acos((rb - t) / r), math.acos((rb - top) / r)
    assert top - t < ap < r * (a1 - a0)
    # a square bilge: the opening is a vertical slot, aperture = height
    square = dataclasses.replace(HULL, bilge_radius=0.0)
    assert opening_aperture(square, t, 2.1) == pytest.approx(2.0)


def test_probe_next_to_a_wall_reads_the_level():
    """A probe 0.1 m from a vertical wall (closer than the kernel support) reads the level
    when the wall particles complete the kernel; without them it reads low."""
    dx, level = 0.8, 4.0
    kp = kernel_params("gaussian", 1.23 * dx)
    fx, fz = np.meshgrid(-(np.arange(12) + 0.5) * dx, (np.arange(5) + 0.5) * dx)
    wx, wz = np.meshgrid((np.arange(3) + 0.5) * dx, (np.arange(14) + 0.5) * dx - 1.0)
    x = np.concatenate([fx.ravel(), wx.ravel()])
    z = np.concatenate([fz.ravel(), wz.ravel()])
    kind = np.concatenate([np.zeros(fx.size, np.int32), np.ones(wx.size, np.int32)])
    m = np.full(x.size, 1000.0 * dx * dx)
    rho = np.full(x.size, 1000.0)
    comp = np.zeros(x.size, np.int32)
    xp = np.array([-0.1])
    with_walls = surface_heights(x, z, m, rho, kind, comp, -1, xp, kp, 0.0, 0.01, True)[0]
    fluid_only = surface_heights(x, z, m, rho, kind, comp, -1, xp, kp, 0.0, 0.01, False)[0]
    assert with_walls == pytest.approx(level, abs=0.1 * dx)
    assert not fluid_only > level - 0.5 * dx  # NaN or well below the level


def _guard(op, kin, x, z, comp, vx=None, vz=None):
    n = len(x)
    x, z = np.array(x, float), np.array(z, float)
    vx = np.zeros(n) if vx is None else np.array(vx, float)
    vz = np.zeros(n) if vz is None else np.array(vz, float)
    vxo, vzo = vx.copy(), vz.copy()
    comp = np.array(comp, np.int32)
    keep_sides(x, z, vx, vz, vxo, vzo, np.zeros(n, np.int32), comp, op, kin)
    return x, z, vx, vz, vxo, vzo, comp


def _near(v):
    """Equal to ``v`` up to round-off in the mirror and keel-frame transforms."""
    return pytest.approx(v, abs=1e-9)


def test_fluid_changes_compartment_through_the_opening_only():
    op, kin = _opening()  # opening from w = 0.1 to 2.1 on the +x side, reach 2.0
    op[14] = 0.4          # a particle rounding the edge within 0.4 m of it counts
    mid = mid_shape(HULL)[0]  # u of the side's mid-surface (7.95)
    x, z, vx, vz, vxo, vzo, comp = _guard(
        op, kin,
        x=[7.7, 8.3, 7.7, 7.7, 7.7, 8.3, 0.0, -7.7],
        z=[1.5, 1.5, 2.4, 3.5, 4.5, 4.5, 1.5, 1.5],
        comp=[0, 1, 0, 0, 0, 1, 0, 0],  # all but the seventh on the wrong side
        vx=[-1.0, 1.0, -1.0, -2.0, -1.0, 3.0, 0.0, 1.0],
        vz=[0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0])
    # in the opening, or past its edge by less than the margin: the side's compartment,
    # position and velocity as they were
    assert list(comp[:3]) == [1, 0, 1]
    assert np.allclose(x[:3], [7.7, 8.3, 7.7]) and np.allclose(vx[:3], [-1.0, 1.0, -1.0])
    # pressed through the plating above the opening (and on the intact side): sent back to
    # the mirror point with the velocity across the plating removed, tangential kept
    assert list(comp[3:]) == [0, 0, 1, 0, 0]
    assert x[3] == _near(2 * mid - 7.7) and z[3] == _near(3.5)
    assert vx[3] == _near(0.0) and vz[3] == _near(0.5)
    assert vxo[3] == _near(0.0)  # the previous Verlet level too
    assert x[4] == _near(2 * mid - 7.7) and vx[4] == _near(0.0)
    assert x[5] == _near(2 * mid - 8.3) and vx[5] == _near(0.0)
    assert x[7] == _near(-(2 * mid - 7.7)) and vx[7] == _near(0.0)
    # far from the plating (the keel centre, beyond reach): left alone
    assert x[6] == 0.0 and comp[6] == 0


def test_band_beyond_the_opening_edge_is_measured_along_the_plating():
    """With the lower edge at the cabin floor the bottom plating beside it is level, within
    a band's width in height of the edge: a particle pressed through the bottom far from the
    opening is put back, not let through into the cabin; one rounding the edge within the
    margin of the edge point changes side."""
    op, kin = _opening()  # lower edge at the floor height w = 0.1 (u = 6.875), +x side
    op[14] = 0.4
    x, z, vx, vz, vxo, vzo, comp = _guard(op, kin, x=[3.0, 5.0, 6.7, 7.0],
                                          z=[0.15, 0.2, 0.2, 0.25], comp=[0, 0, 0, 0],
                                          vz=[1.0, 1.0, 1.0, 1.0])
    bottom = mid_shape(HULL)[1]
    assert list(comp) == [0, 0, 1, 1]
    assert z[0] == _near(2 * bottom - 0.15) and z[1] == _near(2 * bottom - 0.2)
    assert vz[0] == _near(0.0) and vz[1] == _near(0.0)
    assert z[2] == 0.2 and vz[2] == 1.0


def test_closed_hull_sends_back_whatever_crosses_and_respects_the_hull_velocity():
    op, kin = _opening(open_=False)
    op[14] = 0.4
    kin[0, 3] = -1.0  # hull moving towards -x at 1 m/s
    x, z, vx, vz, vxo, vzo, comp = _guard(op, kin, x=[7.7, 7.7], z=[1.5, 1.5], comp=[0, 0],
                                          vx=[-1.0, -3.0])
    assert list(comp) == [0, 0]
    assert np.allclose(x, 2 * mid_shape(HULL)[0] - 7.7)
    # moving with the hull: nothing to remove; faster into it: reduced to the hull's speed
    assert vx[0] == _near(-1.0) and vx[1] == _near(-1.0)


def test_orifice_rate():
    # a slot from the surface down to depth y: q = Cd sqrt(2g) 2/3 y^1.5
    assert orifice_rate(2.0, 0.0, 9.81, 1.0) == pytest.approx(
        math.sqrt(2 * 9.81) * 2 / 3 * 2.0**1.5)
    assert orifice_rate(2.0, 2.0, 9.81) == 0.0


# ------------------------------------------------------------------- input checks
def _case(**geometry):
    return {"case": "damaged_ship", "numerics": {"dx": 0.8}, "geometry": geometry}


@pytest.mark.parametrize("geometry, key", [
    ({"damage": {"opening": 0.99}}, "geometry.damage.opening"),  # top above the waterline
    ({"hull": {"draught": 8.0}, "damage": {"opening": 1.0}}, "geometry.damage.opening"),
    ({"damage": {"opening": 0.05}}, "geometry.damage.opening"),  # aperture 0.5 m < dx
    ({"fill": 1.0}, "geometry.fill"),
    ({"fill": -0.1}, "geometry.fill"),
    ({"fill": 0.75}, "geometry.cargo_density"),  # water outweighs the displacement
    ({"ship_x": 5.0}, "geometry.ship_x"),
    ({"ship_x": 140.0}, "geometry.ship_x"),
    ({"damage": {"side": "port"}}, "geometry.damage.side"),
    ({"hull": {"draught": 9.0}}, "geometry.hull.draught"),
    ({"hull": {"bilge_radius": 8.0}}, "geometry.hull.bilge_radius"),
    ({"depth": 45.0}, "geometry.depth"),
])
def test_bad_ship_input_is_refused(geometry, key):
    with pytest.raises(ConfigError) as err:
        build_case(_case(**geometry))
    assert err.value.key == key
    assert key in str(err.value)


def test_paper_fill_runs_with_a_lighter_cargo():
    cfg = build_case(_case(fill=0.75, cargo_density=850.0))
    assert cfg.geometry.fill == 0.75


def test_opening_narrower_than_a_spacing_is_refused_naming_its_aperture():
    # 0.1 d = 0.42 m high: 0.81 m between its edges, one spacing at dx = 0.8 m (runs),
    # not at dx = 0.85 m (refused before any particle is made)
    build_case(_case(damage={"opening": 0.1}))
    with pytest.raises(ConfigError) as err:
        build_case({**_case(damage={"opening": 0.1}), "numerics": {"dx": 0.85}})
    msg = str(err.value)
    assert err.value.key == "geometry.damage.opening"
    assert "opening 0.1 " in msg and "aperture of 0.809 m" in msg and "dx = 0.85 m" in msg


@pytest.mark.parametrize("opening, dx, warns", [
    (5 / 21, 0.8, True),    # 1.43 m aperture: 1.8 spacings
    (5 / 21, 0.35, False),  # 4.07 spacings
    (5 / 7, 0.8, True),     # 3.19 m: 3.98 spacings
    (5 / 7, 0.75, False),   # 4.25 spacings
])
def test_narrow_opening_warns_naming_its_aperture(caplog, opening, dx, warns):
    case = {**_case(damage={"opening": opening}), "numerics": {"dx": dx}}
    with caplog.at_level(logging.WARNING, logger="sph.cases.ship"):
        build_case(case)
    msgs = [r.getMessage() for r in caplog.records if "aperture" in r.getMessage()]
    assert bool(msgs) == warns, msgs
    if warns:
        ap = opening_aperture(HULL, HULL.plating, HULL.plating + opening * HULL.draught)
        assert f"opening {opening:.4g} " in msgs[0]
        assert f"aperture of {ap:.3g} m" in msgs[0] and f"dx = {dx:g} m" in msgs[0]


def test_quick_reach_test_changes_no_line_of_sight_answer():
    """The circle around the opening (``op[15:20]``) answers far pairs without the keel-frame
    transform and the bisection; it must give exactly the answers of the full test, for a
    hull that is moved and heeled, and decide most pairs near the hull by itself."""
    from types import SimpleNamespace

    from sph.bodies.damage import DamageOpening
    from sph.cases.ship import _opening_circle
    from sph.engine.opening import crosses_opening

    reach = 2.0
    z1 = 2.1
    op = np.zeros(OP_SIZE)
    op[:7] = (1.0, 0, 1, 0, 1.0, HULL.plating, z1)
    op[7:12] = mid_shape(HULL)
    op[12] = HULL.kg
    op[13] = reach
    op[15:18] = _opening_circle(HULL, 1.0, HULL.plating, z1, reach, HULL.kg)
    kin = fixed_kinematics(1)
    kin[0, :3] = (40.0, 27.0, math.radians(8.0))  # reference point moved, hull heeled
    DamageOpening(0.0, op, np.zeros(0, np.int64)).apply(SimpleNamespace(kin=kin, t=0.0, step=0))
    full = op.copy()
    full[17] = 0.0  # no quick test
    rng = np.random.default_rng(3)
    ct, st = math.cos(kin[0, 2]), math.sin(kin[0, 2])
    n, quick, crossing = 4000, 0, 0
    for _ in range(n):
        # a point within a metre of the hull's outline, and a partner within the reach
        u, w = rng.uniform(-10.0, 10.0), rng.uniform(-1.0, 10.0)
        xi = kin[0, 0] + ct * u - st * (w - HULL.kg)
        zi = kin[0, 1] + st * u + ct * (w - HULL.kg)
        a, r = rng.uniform(0.0, 2.0 * math.pi), reach * math.sqrt(rng.uniform())
        xj, zj = xi + r * math.cos(a), zi + r * math.sin(a)
        got = crosses_opening(xi, zi, xj, zj, op, kin)
        assert got == crosses_opening(xi, zi, xj, zj, full, kin)
        crossing += got
        quick += (xi - op[18]) ** 2 + (zi - op[19]) ** 2 > op[17]
    assert crossing > 20  # the sample does cross the opening
    assert quick > 0.8 * n
