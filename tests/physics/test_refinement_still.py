"""Still water across refinement levels (slow): a tank 1 m long and 1 m deep at dx = 0.1 m
with one box of level 1 (two levels) or a box of level 2 inside it (three levels, dx down to
0.025 m), settled for 60 s. The pressure at the bottom under every level and at the level
boundaries is that of the uniform coarse tank, within 1 % of rho g H; the largest speed of
the mass-carrying particles is below 0.5 % of sqrt(g H); the active mass is constant to
1e-12 and the particles per level do not drift (no family changes level in still water).
Run with ``python -m pytest -m slow tests/physics/test_refinement_still.py``."""

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


def _tank(levels):
    boxes = [{"x": [0.3, 0.7], "z": [-1.0, 2.0], "level": 1},
             {"x": [0.4, 0.6], "z": [-1.0, 2.0], "level": 2}][:levels - 1]
    over = [("numerics.dx", 0.1), ("geometry.tank_length", 1.0), ("geometry.depth", DEPTH),
            ("geometry.tank_height", 1.2), ("numerics.threads", 2), ("probes.pressure", []),
            ("probes.surface", []), ("numerics.refinement", boxes)]
    sim = Simulation(builtin("still_water", over))
    sim.evaluate()
    return sim


@pytest.mark.slow
@pytest.mark.parametrize("levels", [2, 3])
def test_still_water_across_levels_stays_hydrostatic(levels):
    sim = _tank(levels)
    a = active_fluid(sim.parts)
    mass0 = math.fsum(sim.parts.m[a])
    counts0 = level_counts(sim.parts, levels - 1)
    while sim.t < T_END:
        sim.advance()
    p = sim.parts
    a = active_fluid(p)
    assert abs(math.fsum(p.m[a]) / mass0 - 1.0) < 1e-12
    np.testing.assert_array_equal(level_counts(p, levels - 1), counts0)
    assert sim.n_removed == 0
    speed = np.hypot(p.vx[a], p.vz[a]).max()
    assert speed < 0.005 * math.sqrt(9.81 * DEPTH)
    q = p.take(a | (p.kind != 0))
    pres = point_pressures(q.x, q.z, q.m, q.rho, q.p, q.kind, BOTTOM_X,
                           np.zeros_like(BOTTOM_X), sim.kp, sim.gx, sim.gz)
    np.testing.assert_allclose(pres / (1000.0 * 9.81 * DEPTH), 1.0, atol=0.01)
