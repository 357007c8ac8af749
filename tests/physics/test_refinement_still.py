"""Still water across refinement levels (slow): a tank 1 m long and 1 m deep at dx = 0.1 m
with one box of level 1 (two levels) or a box of level 2 inside it (three levels, dx down to
0.025 m), settled for 60 s. Run with
``python -m pytest -n 0 -m slow tests/physics/test_refinement_still.py`` (about 4 minutes on
one core).

What holds: the largest speed of the mass-carrying particles is below 0.5 % of sqrt(g H),
the active mass is constant to 1e-12 and the particles per level do not change. What does
not hold yet (strict xfails): the bottom pressure within 1 % of rho g H (the uniform tank
reads 1.004-1.006). With two levels it creeps from 1.007 to 1.010-1.012 between 35 and
60 s (1.0101-1.0104 at 60 s): the packing correction's doing (1.0078-1.0080 without it,
which a box through the free surface needs, docs/validation/refinement.md). With three
levels it creeps up to 1.015-1.017 by 30 s (measured 2026-11-27).
"""
import math

import numpy as np
import pytest

from sph.cases import builtin
from sph.driver import Simulation
from sph.engine.probes import point_pressures
from sph.engine.refinement import active_fluid, level_counts

DEPTH = 1.0
T_END = 60.0
#: bottom points: coarse, the level-1 boundary, level 1, the level-2 boundary, level 2
BOTTOM_X = np.array([0.15, 0.3, 0.35, 0.4, 0.5])


@pytest.fixture(scope="module", params=[2, 3])
def settled(request):
    levels = request.param
    boxes = [{"x": [0.3, 0.7], "z": [-1.0, 2.0], "level": 1},
             {"x": [0.4, 0.6], "z": [-1.0, 2.0], "level": 2}][:levels - 1]
    over = [("numerics.dx", 0.1), ("geometry.tank_length", 1.0), ("geometry.depth", DEPTH),
            ("geometry.tank_height", 1.2), ("numerics.threads", 2), ("probes.pressure", []),
            ("probes.surface", []), ("numerics.refinement", boxes)]
    sim = Simulation(builtin("still_water", over))
    sim.evaluate()
    a = active_fluid(sim.parts)
    start = dict(mass=math.fsum(sim.parts.m[a]), counts=level_counts(sim.parts, levels - 1))
    while sim.t < T_END:
        sim.advance()
    return levels, sim, start


#: why the bottom pressure is not within 1 % of rho g H yet, by the number of levels
HYDROSTATIC_XFAIL = {
    2: "with two levels the packing correction makes the bottom pressure creep to 1.010 "
       "rho g H by 60 s (docs/validation/refinement.md)",
    3: "with three levels the bottom pressure creeps up to 1.5 % above rho g H by 30 s "
       "(docs/validation/refinement.md)",
}


@pytest.mark.slow
def test_still_water_across_levels_settles_and_keeps_its_mass(settled):
    levels, sim, start = settled
    p = sim.parts
    a = active_fluid(p)
    assert abs(math.fsum(p.m[a]) / start["mass"] - 1.0) < 1e-12
    assert np.hypot(p.vx[a], p.vz[a]).max() < 0.005 * math.sqrt(9.81 * DEPTH)


@pytest.mark.slow
def test_still_water_across_levels_keeps_its_counts_per_level(settled):
    """No family changes level in still water (the hysteresis at the box edges)."""
    levels, sim, start = settled
    np.testing.assert_array_equal(level_counts(sim.parts, levels - 1), start["counts"])


@pytest.mark.slow
def test_still_water_across_levels_is_hydrostatic(settled, request):
    levels, sim, start = settled
    request.applymarker(pytest.mark.xfail(strict=True, reason=HYDROSTATIC_XFAIL[levels]))
    p = sim.parts
    a = active_fluid(p)
    q = p.take(a | (p.kind != 0))
    pres = point_pressures(q.x, q.z, q.m, q.rho, q.p, q.kind, BOTTOM_X,
                           np.zeros_like(BOTTOM_X), sim.kp, sim.gx, sim.gz)
    np.testing.assert_allclose(pres / (1000.0 * 9.81 * DEPTH), 1.0, atol=0.01)
