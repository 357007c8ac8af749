"""The damaged ship in still water: floating, sealed cargo, flooding through the opening.

A small tank (depth 15 m, 60 m long) at dx = 0.8 m keeps these runs to seconds; the hull is
the paper's (B = 16 m, D = 8.5 m, d = 4.2 m), two strip segments (intact cabin weighted 2/3,
damaged cabin 1/3). The flap does not move (theta0 = 0): still water.
"""

from __future__ import annotations

import numpy as np
import pytest
from physics_helpers import run_builtin

from sph.bodies.damage import HullGuard, orifice_rate
from sph.bodies.hull import (
    cabin_area,
    flooded_equilibrium,
    mid_shape,
    opening_aperture,
    opening_bottom,
)
from sph.cases import builtin
from sph.cases.ship import _to_keel
from sph.driver import Simulation
from sph.engine.opening import OP_GROUP, OP_KG, OP_SEA, OP_SHAPE, OP_SHAPE_END, keel_frame, sdf_many
from sph.engine.particles import GHOST
from sph.engine.stepper import SimulationError
from sph.study.analysis import decay_modes, oscillation_frequency

DX = 0.8
STILL_SMALL_TANK = [
    f"numerics.dx={DX}",
    "geometry.depth=15", "geometry.tank_length=70", "geometry.ship_x=30",
    "geometry.tank_height=30",
    "geometry.absorber.start=50", "geometry.absorber.length=20",
    "geometry.wavemaker.amplitude=null", "geometry.wavemaker.theta0=0",
    "run.output_interval=0.1",
]
#: the paper's hull, as the built-in ship cases define it
HULL = builtin("damaged_ship").geometry.hull


def _keel_coords(sim, group):
    """Keel-frame coordinates of every particle relative to the hull of wall group
    ``group``, whose body's reference point is the dry part's centre of gravity."""
    p = sim.parts
    kin = sim.kin[group]
    u, w = _to_keel(np.column_stack([p.x, p.z]), sim.setup.attrs["dry_kg"], kin[:2], kin[2])
    return u, w


def test_intact_ship_floats_at_its_draught_and_keeps_its_cargo():
    """Intact ship with cargo at eta = 0.5 released at its draught: it stays there (heave
    within 2 % of d), stays upright, the cargo keeps its level and no sea enters the hull."""
    cfg = builtin("damaged_ship", STILL_SMALL_TANK + [
        "geometry.fill=0.5", "geometry.damage.opening=0", "run.t_end=6"])
    sim = Simulation(cfg)
    p = sim.parts
    cargo0 = int(np.sum((p.kind == 0) & (p.comp == 1)))
    sim.run()
    ds = sim.dataset()
    # the start-up transient (the fluid settling against the walls) leaves a heave
    # oscillation of a few centimetres and a roll of a few tenths of a degree in this small
    # tank; the mean heave stays within 2 % of the draught
    heave = ds["heave"].values
    assert abs(np.mean(heave)) < 0.02 * HULL.draught, np.mean(heave)
    assert np.max(np.abs(heave)) < 0.03 * HULL.draught, np.max(np.abs(heave))
    assert np.max(np.abs(ds["roll"].values)) < 1.0  # degree
    # cargo level at W1 (relative to h_w = eta D) within half a particle spacing
    w1 = ds["probe_elevation"].sel(probe="W1").values
    assert np.max(np.abs(w1[5:])) < 0.5 * DX, w1
    # sealed: every cargo particle inside the inner surface, every sea particle outside
    # the outer surface of its segment's hull (signed distances in the keel frame)
    p = sim.parts
    fluid = p.kind == 0
    n_seg = 2
    for s in range(n_seg):
        u, w = _keel_coords(sim, 1 + n_seg + s)
        d_mid = sdf_many(u, w, mid_shape(HULL))
        sea = fluid & (p.comp == 2 * s)
        cabin = fluid & (p.comp == 2 * s + 1)
        assert np.all(d_mid[sea] > 0.0), "sea particle inside the hull"
        assert np.all(d_mid[cabin] < 0.0), "cargo particle outside the hull"
    assert np.sum(fluid & (p.comp == 1)) == cargo0


def test_roll_decay_frequency_beside_table_ii_small_tank():
    """The roll decay below in a tank half as deep and half as long (15 m x 60 m, a quarter
    of the particles and 0.7 of the time step count: a quarter of the cost). The section's
    added inertia and radiation damping come from the water within about a beam of the hull,
    which both tanks hold (depth 15 m = 3.6 d, walls 22 m from the sides): the frequency
    stays within the same 5 % of Table II's 1.06 rad/s (measured 1.065 rad/s, against 1.062
    in the large tank) and the damping ratio in the same weak band (measured 0.035)."""
    sim = run_builtin("ship_decay", ["numerics.dx=0.8", "run.t_end=12.0",
                                     "geometry.depth=15", "geometry.tank_length=60",
                                     "geometry.ship_x=30", "geometry.tank_height=25"])
    ds = sim.dataset()
    omega, zeta = oscillation_frequency(ds["time"].values, ds["roll"].values.ravel())
    assert omega == pytest.approx(1.06, rel=0.05), (omega, zeta)
    assert 0.02 < zeta < 0.15, (omega, zeta)
    assert sim.n_lost == 0


@pytest.mark.slow
def test_roll_decay_frequency_beside_table_ii():
    """Free roll decay of the empty intact ship (`ship_decay`: one strip segment, released at
    5 deg heel, all three DOF free) over two periods at dx = 0.8 m: the damped roll
    frequency against the paper's Table II, 1.06 rad/s, within 5 % (measured 1.062 rad/s
    here, 1.059 over 25 s at dx = 0.8 and 0.4 m). The hydrostatic frequency without added
    inertia, sqrt(g GM) / k_xx = 1.31 rad/s, is excluded: the water set in motion is felt.
    The decay is a weak one (radiation damping of the section; measured damping ratio 0.06):
    between 0.02 and 0.15."""
    sim = run_builtin("ship_decay", ["numerics.dx=0.8", "run.t_end=12.0"])
    ds = sim.dataset()
    omega, zeta = oscillation_frequency(ds["time"].values, ds["roll"].values.ravel())
    assert omega == pytest.approx(1.06, rel=0.05), (omega, zeta)
    assert 0.02 < zeta < 0.15, (omega, zeta)
    assert sim.n_lost == 0


def _flood_run(t_end):
    return run_builtin("damaged_ship", STILL_SMALL_TANK + [
        "geometry.fill=0", "geometry.damage.opening=0.9", "geometry.damage.side=back",
        "geometry.damage.time_periods=0.16", f"run.t_end={t_end}"])


def _orifice_estimate(hull, z1):
    # the opening spans its lower edge to z1 above the keel; depths below the outside still
    # level at the draught
    return orifice_rate(hull.draught - opening_bottom(hull), hull.draught - z1, 9.81)


def _cargo_speed_through_the_start(overrides, t_end=2.0):
    """Largest speed of the cargo (compartment 1: the inside of the intact segment) over the
    first ``t_end`` s of the damaged-ship case in its wave tank, and the cargo's speed at
    the end."""
    sim = Simulation(builtin("damaged_ship", [f"run.t_end={t_end}", *overrides]))
    vmax = 0.0
    while sim.t < t_end:
        sim.advance()
        p = sim.parts
        cargo = (p.kind == 0) & (p.comp == 1) & (p.body == -1)  # active: no ghosts
        v = float(np.sqrt(np.max(p.vx[cargo] ** 2 + p.vz[cargo] ** 2)))
        vmax = max(vmax, v)
    return vmax, v


@pytest.mark.parametrize("fill", [0.25, 0.5, 0.75])
def test_loaded_ship_cargo_stays_calm_through_the_flap_start(fill):
    """Table I's oil cargo in the paper's wave tank over the first 2 s (dx = 0.8 m, flap
    angle 0.060 rad: Table I's calibration at this spacing with the flap started at full
    speed, 0.058 rad with the ramp): the ship meets only the start
    of the wave (roll under 0.3 degree), so the cargo moves at a few tenths of a metre per
    second (0.21-0.23 m/s measured, the flap ramped over half a period). With the flap
    started at full speed (``ramp_time`` 0) a pressure pulse of rho c0 v, about 3 bar,
    reached the ship at 0.35 s and the cargo rattled on the cabin floor: 46, 12 and 20 m/s
    at 25, 50 and 75 % (24 m/s with water at 25 %; at linear theory's 0.049 rad, 0.5-1.3
    m/s); docs/ship.md, "The flap's start"."""
    vmax, v_end = _cargo_speed_through_the_start([
        f"geometry.fill={fill}", "geometry.cargo_density=850",
        "geometry.wavemaker.amplitude=null", "geometry.wavemaker.theta0=0.06"])
    assert vmax < 1.0, vmax
    assert v_end < 0.5, v_end


@pytest.mark.slow
def test_coarse_cargo_stays_on_the_floor_after_the_damage():
    """Table I case 6 at the coarse preset (25 % oil, 2.1 m deep: 2.7 spacings; opening
    10/21 on the back side at t1 = 19.98 s; the flap angle of the sweep in which it burst) to
    23.5 s, as the workflow runs it (about 5 min on one core). Without the wall damping the
    cargo's particles bounced off the rolling hull, its pressure rang from 21.2 s (its range
    tripling every 0.1 s) and by 22.5 s the cargo was thrown off the floor at 20-50 m/s:
    W1 read dry from 22.4 s and the run passed c0 / 10 at 22.17 s (docs/model.md, "Wall
    impacts"). With it the cargo sloshes: W1 stays wet (a dry probe reads the floor, -2.125
    m) and no particle reaches c0 / 10, the limit of weak compressibility (the flooding
    jet runs at 7-9 m/s, a 2.1 m cargo's shallow-water wave speed is 4.5 m/s)."""
    cfg = builtin("damaged_ship", [
        "geometry.fill=0.25", "geometry.cargo_density=850",
        "geometry.wavemaker.amplitude=null", "geometry.wavemaker.theta0=0.05978913236669976",
        "run.t_end=23.5", "run.output_interval=0.1"])
    assert cfg.numerics.wall_damping and cfg.numerics.pressure_floor == -1.0e5
    sim = Simulation(cfg)
    sim.run()
    ds = sim.dataset()
    late = ds["time"].values >= 21.0
    w1 = ds["probe_elevation"].sel(probe="W1").values[late]
    assert np.all(w1 > -2.0), w1
    assert float(ds["max_velocity"].values[late].max()) < 0.1 * sim.c0


def test_refined_cargo_stays_at_rest_in_a_fixed_hull():
    """The 25 % oil cargo at the `refined` preset's spacing (hull, cabins and cargo at
    0.2 m: ``refine_hull`` 2) in the small still tank, the hull held, over 0.4 s: the
    cargo stays at rest to a few tenths of a metre per second (0.2-0.3 m/s measured in the
    paper's tank). Its coarse lattice has cells 0.708 m high (3 between the floor and the
    level); with the children at +-dx/4 of their mother the fine layers met 0.108 m apart at
    the mothers' edges and 0.054 m off the floor, the floor layer's pressure rang and fell
    until the cargo burst at 0.3 s (31 m/s; docs/model.md, 'Variable resolution')."""
    vmax, _ = _cargo_speed_through_the_start(STILL_SMALL_TANK + [
        "geometry.refine_hull=2", "geometry.fill=0.25", "geometry.cargo_density=850",
        "geometry.dofs.sway=false", "geometry.dofs.heave=false", "geometry.dofs.roll=false"],
        t_end=0.4)
    assert vmax < 1.0, vmax


def _refined_still_ship():
    """The small still-water ship with its hull at dx / 2 (``refine_hull`` 1), one step
    taken."""
    sim = Simulation(builtin("damaged_ship", STILL_SMALL_TANK + [
        "geometry.refine_hull=1", "geometry.fill=0", "run.t_end=1"]))
    sim.advance()
    return sim


def test_cabin_probe_reads_the_cargo_level_in_a_refined_hull():
    """W1 in the intact ship with its hull, cabins and cargo at dx / 4 (``refine_hull`` 2,
    the `refined` preset), at rest: the cargo level within half a fine spacing, as at the
    coarse spacing. A refined cabin is lined with the walls of every level; the probe,
    filling its kernel from all of them, stood 'inside the walls' everywhere and read the
    cabins dry (W1 at the floor, W2 at 0) through the refined Table I sweep until its fix.
    W2 is dry until the opening appears."""
    for fill in (0.25, 0.5):
        sim = Simulation(builtin("damaged_ship", STILL_SMALL_TANK + [
            "geometry.refine_hull=2", f"geometry.fill={fill}", "geometry.cargo_density=850",
            "run.t_end=0.004", "run.output_interval=0.002"]))
        sim.run()
        ds = sim.dataset()
        w1 = ds["probe_elevation"].sel(probe="W1").values
        assert np.all(np.abs(w1) < 0.5 * DX / 4), (fill, w1)
        assert np.all(ds["probe_elevation"].sel(probe="W2").values == 0.0)


def _rebuild_lists(sim):
    """Refine and rebuild the neighbour lists now, as at a rebuild during a step."""
    sim._listed = None
    sim._neighbours()


def test_a_ghost_anchored_across_the_plating_is_put_back_before_the_lists_are_built():
    """Variable resolution puts a ghost at its family's centre of mass at every rebuild of
    the lists; where the family parts round the bilge that place lies inside the hull. The
    hull guard acts on it before the lists are built: the ghost is back on the sea side
    and the lists are built there (so the next step does not move it and force another
    rebuild). Put back only at the next step, such a ghost forced a rebuild at every step;
    left across the plating, up to 24 lay there in a refined Table I ship, which stopped
    1.2 s after its opening appeared (docs/findings.md)."""
    sim = _refined_still_ship()
    p = sim.parts
    guard = next(e for e in sim.setup.events if isinstance(e, HullGuard))
    op = guard.params[0]
    s = op[OP_SHAPE:OP_SHAPE_END]
    u, w = keel_frame(p.x, p.z, op, sim.kin)
    d = sdf_many(u, w, s)
    sea = (p.kind == 0) & (p.comp == int(op[OP_SEA]))
    fine = sea & (p.body != GHOST) & (p.hs < 1.0)
    i = np.nonzero(fine & (u > s[0] - s[3]) & (w < s[1] + s[3]) & (d > 0.0))[0][0]
    family = fine & (p.parent == p.parent[i])
    assert family.sum() == 4
    mother = int(np.nonzero(p.pid == p.parent[i])[0][0])
    assert p.body[mother] == GHOST
    # two children beside the side's end of the bilge, two below the bottom's end: their
    # centre of mass lies 0.5 m inside the plating (bilge radius s[3])
    r = s[3]
    du = np.array([s[0] + 0.1, s[0] + 0.1, s[0] - r, s[0] - r])
    dw = np.array([s[1] + r, s[1] + r, s[1] - 0.1, s[1] - 0.1])
    mid_u, mid_w = du.mean(), dw.mean()
    assert sdf_many(np.array([mid_u]), np.array([mid_w]), s)[0] < -0.3
    g = int(op[OP_GROUP])
    ct, st = np.cos(sim.kin[g, 2]), np.sin(sim.kin[g, 2])
    ru, rw = du, dw - op[OP_KG]
    p.x[family] = sim.kin[g, 0] + ct * ru - st * rw
    p.z[family] = sim.kin[g, 1] + st * ru + ct * rw
    mother_pid = p.pid[mother]
    _rebuild_lists(sim)
    p = sim.parts
    m = int(np.nonzero(p.pid == mother_pid)[0][0])
    um, wm = keel_frame(p.x[m:m + 1], p.z[m:m + 1], op, sim.kin)
    assert p.body[m] == GHOST
    assert sdf_many(um, wm, s)[0] > 0.0  # on the sea side
    assert (p.x_sort[m], p.z_sort[m]) == (p.x[m], p.z[m])


def test_the_fine_region_follows_the_drifting_hull():
    """The boxes of ``refine_hull`` move with their hull: the ship drifts with the waves
    (25-30 m over a Table I run at coarse), so that fixed boxes left the flooding opening
    and its jet outside the fine region within 3-4 m of drift, where families of fine
    particles spread across it fell back to a coarse level inside the cabin and the refined
    cases stopped 9 s after the damage. A box moves once its hull is half the margin (2 m)
    from where the box was placed, so that its edges stand still while the hull sways about
    its drift. Displaced 1 m by hand, the boxes stay; 2.5 m, and the lists rebuilt, the
    fluid beyond the old box's edge, inside the moved one, is active at the fine level; the
    other segment's boxes stay put."""
    sim = _refined_still_ship()
    n_seg = int(sim.setup.attrs["segments"])
    group = 1 + n_seg  # the first segment's hull
    follows = sim._box_groups == group
    assert follows.any() and not follows.all()
    box = sim.boxes[np.nonzero(follows)[0][0]].copy()
    x_edge = box[1]

    def fine_beyond_edge():
        p = sim.parts
        strip = (p.kind == 0) & (p.x > x_edge + DX) & (p.x < x_edge + 2.5 - DX)
        strip &= (p.z > box[2] + DX) & (p.z < box[3] - DX)
        assert strip.any()
        return int((strip & (p.body != GHOST) & (p.hs < 1.0)).sum())

    assert fine_beyond_edge() == 0
    sim.kin[group, 0] += 1.0
    _rebuild_lists(sim)
    assert np.array_equal(sim.boxes, sim._boxes0)
    sim.kin[group, 0] += 1.5
    _rebuild_lists(sim)
    assert sim.boxes[follows, 0:2] == pytest.approx(sim._boxes0[follows, 0:2] + 2.5)
    assert np.array_equal(sim.boxes[~follows], sim._boxes0[~follows])
    assert fine_beyond_edge() > 10


def test_a_run_with_moving_boxes_restarts_bit_for_bit():
    """The boxes a stepper's state holds are those of the last rebuild of the lists, so a
    run restarted from its state continues exactly as the uninterrupted one while its
    hull moves (released 1 m above its draught, it falls and its boxes with it; the
    margin, far below the one for physics that refine_margin's warning names, moves them
    every 5 mm)."""
    over = STILL_SMALL_TANK + ["geometry.refine_hull=1", "geometry.fill=0",
                               "geometry.heave_offset=1.0", "geometry.refine_margin=0.01",
                               "run.t_end=1"]  # boxes moved every 5 mm
    whole = Simulation(builtin("damaged_ship", over))
    for _ in range(400):
        whole.advance()
    first = Simulation(builtin("damaged_ship", over))
    for _ in range(200):
        first.advance()
    second = Simulation(builtin("damaged_ship", over))
    second.set_state(first.get_state())
    assert np.abs(first.boxes - first._boxes0).max() > 0.005  # the boxes moved
    np.testing.assert_array_equal(second.boxes, first.boxes)  # as the lists were built
    for _ in range(200):
        second.advance()
    np.testing.assert_array_equal(second.boxes, whole.boxes)
    np.testing.assert_array_equal(second.parts.f, whole.parts.f)


def test_a_fine_region_reaching_a_fixed_wall_stops_the_run():
    """Fixed walls get their fine layers at the start, within the boxes as placed then: a
    hull's box moved onto the tank floor stops the run naming the wall and the move."""
    sim = _refined_still_ship()
    sim.kin[1 + int(sim.setup.attrs["segments"]), 1] -= 8.0
    with pytest.raises(SimulationError, match="reached the fixed wall .* -8.00 m"):
        _rebuild_lists(sim)


def test_early_inflow_through_the_opening_is_of_the_orifice_order():
    """The first 1.5 s of flooding: the inflow rate is that of an orifice of the opening's
    height, q = C_d sqrt(2g) 2/3 (y1^1.5 - y0^1.5) with C_d = 0.6 (a sharp-edged slot in a
    thin plate: the jet contracts to pi / (pi + 2) = 0.61 of the opening), measured 0.90 of
    it. Bounds 0.7-1.2: the water rising in the cabin lowers the head across the opening
    (the estimate takes the cabin as empty), the ship sinking as it floods raises it, and
    the opening's edges are resolved to half a particle spacing (+-10 % of its area here)."""
    sim = _flood_run(2.6)
    ds = sim.dataset()
    t1 = ds.attrs["damage_time"]
    t = ds["time"].values
    q = ds["flood_volume"].values
    assert np.all(q[t < t1 - 1e-9] == 0.0)
    sel = (t >= t1 + 0.3) & (t <= t1 + 1.5)
    rate = np.polyfit(t[sel], q[sel], 1)[0]
    z1 = HULL.plating + 0.9 * HULL.draught
    est = _orifice_estimate(HULL, z1)
    assert 0.7 * est < rate < 1.2 * est, (rate, est)
    # the flooding water sits in the damaged cabin: every cabin particle inside the hull
    p = sim.parts
    u, w = _keel_coords(sim, 4)
    d_mid = sdf_many(u, w, mid_shape(HULL))
    cabin = (p.kind == 0) & (p.comp == 3)
    assert cabin.sum() > 0
    assert np.all(d_mid[cabin] < 0.5 * DX)


@pytest.mark.slow
def test_flooded_ship_settles_at_the_lost_buoyancy_draught():
    """Flooding to equilibrium: the mean heave over the last 20 s agrees within 3 % with the
    lost-buoyancy equilibrium of the strip model (:func:`sph.bodies.hull.flooded_equilibrium`: each
    segment in its own 70-m tank, whose level changes as the cabin takes in water), the ship
    stays upright (a flooded symmetric cabin gives no heeling moment) and the flood volume
    is the cabin's area below the damaged tank's new level. Once the cabin has filled, ship
    and flood water exchange water through the opening in a slow oscillation (period about
    20 s, heave +-0.1 m), so the mean is taken over one such period: a window a third of a
    period off that oscillation's period moves the mean by 0.1 m / pi / 3 = 0.01 m (0.7 %);
    measured 0.3 % (heave) and 0.1 % (flood volume), tolerance 3 %. No particle is lost on
    the way (with the MLS density filter, particles packed at the opening's edges sank as a
    cluster through the tank floor 40 s after the damage: docs/ship.md)."""
    sim = _flood_run(65.0)
    assert sim.n_lost == 0
    ds = sim.dataset()
    t = ds["time"].values
    late = t > t[-1] - 20.0
    eq = flooded_equilibrium(HULL, 1.0 / 3.0, tank_length=70.0)
    heave = float(np.mean(ds["heave"].values[late]))
    assert abs(heave - eq["heave"]) < 0.03 * abs(eq["heave"]), (heave, eq)
    q = float(np.mean(ds["flood_volume"].values[late]))
    assert abs(q - eq["flood"]) < 0.03 * eq["flood"], (q, eq)
    assert q < cabin_area(HULL)
    roll = float(np.mean(ds["roll"].values[late]))
    if abs(roll) >= 1.0:
        # measured -1.13 degree since the opening's lower edge moved to the cabin floor
        # (the roll swings between -2.2 and -0.2 degree with the 20-s exchange through the
        # opening; within 1 degree before); the cause is not found yet
        pytest.xfail(f"mean roll {roll:.2f} degree over the last 20 s, not upright")


#: the loaded intact ship: two cabins in three with cargo, the middle one empty; water at 25 and
#: 50 %, where the low mode rests on the smallest GM_eff, and Table I's oil at 75 %
LOADED = {0.25: 1000.0, 0.5: 1000.0, 0.75: 850.0}
#: the small tank of the loaded decay runs
DECAY_TANK = ["numerics.dx=0.8", "geometry.depth=15", "geometry.tank_length=60",
              "geometry.ship_x=30", "geometry.tank_height=25", "geometry.intact_cabins=2",
              "geometry.damaged_cabins=1", "geometry.damage.opening=0"]


@pytest.mark.slow
def test_light_loaded_ship_stays_afloat_upright_in_still_water():
    """At 75 % fill (oil) the dry part is 9.6 t/m carrying 56.6 t/m of cargo. Coupled
    explicitly, the cargo's lagged reaction overshoots the light body at every step (the
    added-mass instability): released upright in still water, in hydrostatic balance, the
    ship was thrown 3 m up and heeled 4 degree within 0.5 s. With the cargo's mass and
    inertia as the stabilising added mass (:mod:`sph.bodies.rigid`) it stays put: over 6 s
    (about a heave period) measured heave -0.080 to +0.023 m and heel below 0.6 degree, from
    the start-up of the weakly compressible sea and cargo (at the start the fluid carries the
    ship 14.6 kN/m short of its weight, 0.09 m of heave). With the stabilisation's previous
    acceleration alone on the right (Soding's form, before 2026-11-27) the cargo's
    compression modes grew and the ship rose 0.25 m by 2.4 s (docs/ship.md). Bounds: 0.15 m
    and 1 degree."""
    sim = run_builtin("ship_decay", DECAY_TANK + [
        "run.t_end=6.0", "run.output_interval=0.1", "geometry.fill=0.75",
        "geometry.cargo_density=850", "geometry.heel=0"])
    ds = sim.dataset()
    assert sim.n_lost == 0
    assert np.abs(ds["heave"].values).max() < 0.15
    assert np.abs(ds["roll"].values).max() < 1.0


#: the open decay tank: 120 m long and 15 m deep, a damping zone over the 44 m at each end
#: (a wave length of the 1.2 rad/s waves the rolling ship radiates; `mirrored`), the hull,
#: its cabins and cargo at 0.4 m (one refinement level). In the closed 60 m tank above the
#: radiated waves come back as the tank's seiches (0.58, 0.97, 1.23 rad/s ...): read as in
#: the test below, the upper mode at 50 % is 1.18 rad/s there and 1.19 in a closed 90 m
#: tank, 1.41 in this one (hull at 0.8 m; the model's 1.34; docs/ship.md).
OPEN_DECAY_TANK = ["numerics.dx=0.8", "geometry.refine_hull=1", "geometry.depth=15",
                   "geometry.tank_length=120", "geometry.ship_x=60", "geometry.tank_height=25",
                   "geometry.intact_cabins=2", "geometry.damaged_cabins=1",
                   "geometry.damage.opening=0", "geometry.absorber.enabled=true",
                   "geometry.absorber.start=76", "geometry.absorber.length=44",
                   "geometry.absorber.mirrored=true"]


def loaded_decay_modes(ds, fill, density, t_fit=30.0):
    """Measured and estimated roll modes of a loaded-ship decay record over its first
    ``t_fit`` seconds, split at the cargo's first sloshing frequency
    (:func:`sph.study.analysis.decay_modes`; the high mode radiates strongly in the open
    tank, too damped for a two-mode fit to hold it apart), and the coupled roll-sloshing
    model's (:func:`sph.bodies.cargo.roll_modes`, the sea's added inertia from the empty
    ship's 1.06 rad/s)."""

    from sph.bodies.cargo import cargo_section, mass_properties, roll_modes

    mp = mass_properties(HULL, 1000.0, 9.81, 2.0 / 3.0, density, cargo_section(HULL, fill))
    a44 = mp.displacement * 9.81 * mp.gm / 1.06**2 - mp.displacement * HULL.gyradius**2
    est = roll_modes(mp, HULL, cargo_section(HULL, fill), 1000.0, 9.81, 2.0 / 3.0, density,
                     a44)
    t, y = ds["time"].values, ds["roll"].values.ravel()
    m = decay_modes(t[t <= t_fit], y[t <= t_fit], est["sloshing"])
    return dict(m, estimate=est, gm_fluid=mp.gm_fluid)


@pytest.mark.slow
@pytest.mark.parametrize("fill", sorted(LOADED))
def test_loaded_roll_decay_against_the_roll_sloshing_estimate(fill):
    """Free roll decay of the loaded intact ship (cargo in two cabins of three: water at 25
    and 50 %, an 850 kg/m3 oil at 75 %; released at 5 deg with the cargo's surface parallel
    to the deck) in the open decay tank, 36 s (about 4 min each on one core).

    The coupled roll-sloshing model (:mod:`sph.bodies.cargo`) gives two modes that share the
    roll: one far below the cargo's first sloshing frequency, on the metacentric height the
    free-surface effect leaves (GM 3.88 m less 3.31 m for water, 2.81 m for the oil: 0.31,
    0.40, 0.60 rad/s), and one above it, ship and cargo moving against each other (1.19,
    1.34, 1.47 rad/s). Measured at 0.4 m (docs/ship.md): low 0.36, 0.45, 0.70 rad/s (+14, +14,
    +17 %), high 1.20, 1.44, 1.66 (+1, +7, +13 %). The low mode rests on GM_eff, the
    difference of two numbers of 3-4 m: 5 % less free-surface moment raises it 14 % (water)
    or 6 % (oil); the SPH's moment grows towards the model's with the spacing at the hull
    (at 25 %: +42 % at 0.8 m, +14 % at 0.4 m; at 75 %: +23, +17, +10 % at 0.8, 0.4, 0.2 m).
    The high mode depends on the sea's added inertia at its own frequency, which the model
    takes at 1.06 rad/s, and on the cabins' bilges, which its rectangle leaves out. Bounds:
    20 % on the low mode, 15 % on the high; damping ratio of the low mode between 0 and
    0.5."""
    density = LOADED[fill]
    sim = run_builtin("ship_decay", OPEN_DECAY_TANK + [
        "run.t_end=36.0", f"geometry.fill={fill}", f"geometry.cargo_density={density}"])
    assert sim.n_lost == 0
    m = loaded_decay_modes(sim.dataset(), fill, density)
    est = m["estimate"]
    assert m["low"][0] == pytest.approx(est["omega"][0], rel=0.20), m
    assert m["high"] == pytest.approx(est["omega"][1], rel=0.15), m
    assert 0.0 < m["low"][1] < 0.5, m


#: the orifice runs: still water in a short, shallow tank (3 breadths long, 4.8 m under the
#: keel), the ship held fixed, dx with at least 4 spacings across the smallest aperture
ORIFICE_DX, ORIFICE_DEPTH, ORIFICE_LENGTH = 0.35, 9.0, 48.0


def _orifice_run(opening):
    t1 = 0.16 * 2.0 * np.pi  # s (0.16 T): the start-up transient of the still tank is over
    cfg = builtin("damaged_ship", [
        f"numerics.dx={ORIFICE_DX}", f"geometry.depth={ORIFICE_DEPTH}",
        f"geometry.tank_length={ORIFICE_LENGTH}", f"geometry.ship_x={ORIFICE_LENGTH / 2}",
        f"geometry.tank_height={ORIFICE_DEPTH + 6.0}", "geometry.absorber.enabled=false",
        "geometry.wavemaker.amplitude=null", "geometry.wavemaker.theta0=0",
        "probes.surface=[]", "geometry.fill=0", f"geometry.damage.opening={opening}",
        "geometry.damage.side=back", "geometry.damage.time_periods=0.16",
        "geometry.dofs.sway=false", "geometry.dofs.heave=false", "geometry.dofs.roll=false",
        "run.output_interval=0.05", f"run.t_end={t1 + 1.0 + 1e-6}"])
    return Simulation(cfg).run()


def orifice_discharge_coefficient(sim):
    """C_d of the first second of flooding: the inflow rate (slope of the flood volume over
    t1 + 0.25 s to t1 + 1 s) over the orifice law into the empty cabin,
    Q = int_{z0}^{z1} sqrt(2 g (h_out - z)) dz, with h_out the draught lowered by the fall
    of the tank's level (the flood volume over the free surface's length, tank length minus
    breadth: 0.1-0.16 m here, which the paper's 150 m tank would make four times smaller).
    """
    ds = sim.dataset()
    t, q = ds["time"].values, ds["flood_volume"].values
    t1 = ds.attrs["damage_time"]
    sel = (t >= t1 + 0.25 - 1e-9) & (t <= t1 + 1.0 + 1e-9)
    rate = np.polyfit(t[sel], q[sel], 1)[0]
    h_out = HULL.draught - np.mean(q[sel]) / (ORIFICE_LENGTH - HULL.breadth)
    z0 = opening_bottom(HULL)
    z1 = HULL.plating + ds.attrs["opening"] * HULL.draught
    return rate / orifice_rate(h_out - z0, h_out - z1, 9.81, 1.0)


@pytest.mark.slow
@pytest.mark.parametrize("opening", [
    5 / 21,
    10 / 21,
    pytest.param(5 / 7, marks=pytest.mark.xfail(strict=True, reason=(
        "measured C_d = 0.53: the top edge is 1.1 m under the surface for a 3 m opening, "
        "and the surface draws down about 0.6 m beside the hull (docs/ship.md)"))),
])
def test_initial_inflow_follows_the_orifice_law(opening):
    """The first second of flooding through each Table I opening (still water, ship held
    fixed) against the orifice law Q = C_d int sqrt(2 g (h_out - z)) dz over the opening's
    height, C_d between 0.6 and 0.8: a sharp-edged slot contracts its jet to
    pi / (pi + 2) = 0.61, a slot with an edge the flow follows less. Measured at
    dx = 0.35 m (4.1, 6.5 and 9.1 spacings across the apertures): C_d = 0.85, 0.62, 0.53.

    An opening that reaches onto the bilge takes flow from below as well as from the side:
    its aperture (the gap between its edges, 1.43 m for the 5/21 opening) is longer than its
    height, which the law counts alone, so the upper bound is 0.8 times their ratio (the
    law over the aperture at 0.8). The 5/7 opening's top edge is 1.1 m below the surface:
    the surface draws down beside the hull and the law, which takes the undisturbed level,
    overestimates the head of its upper part (it fails the band; strict)."""
    z0, z1 = opening_bottom(HULL), HULL.plating + opening * HULL.draught
    aperture = opening_aperture(HULL, z0, z1)
    assert aperture >= 4.0 * ORIFICE_DX
    sim = _orifice_run(opening)
    assert sim.n_lost == 0
    cd = orifice_discharge_coefficient(sim)
    lo, hi = 0.6, 0.8 * aperture / (z1 - z0)
    assert lo <= cd <= hi, cd
