"""Large sloshing across a refinement box (slow): the fluid must keep its volume.

First-mode sloshing, 2 m at the walls, in a tank 24 m long with water 12 m deep, at the
ship cases' numerics (dx = 0.8 m, no density filter, shifting, wall damping), with a level-1
box x in [8, 16] m, z in [3, 8] m under the surface (``benchmarks/refinement_sloshing.py``,
mode ``deep``). Beneath the surface the water moves about 1 m to and fro, so particles cross
the box's edges every period. The mechanical energy E = KE + PE - PE(0) of the mass-carrying
fluid (flat and at rest at PE(0)) must only decay and stay positive: below zero the fluid
fills less room than its densities say (it packs), and its surface falls.

What holds: with the families' hysteresis about the box edges (``HYSTERESIS``) at 2 coarse
spacings, wider than the water's excursion, no family changes level and the run decays as
the uniform coarse one does (E / E(0) within 0.05 of it; 0.31 against 0.35 over 48-54 s
in the benchmark).
What does not hold yet (strict xfail, measured 2026-11-30): at the default hysteresis the
families that cross change level twice a period, and the fluid packs: E falls below zero
from 24-30 s (-5.7 E(0) by 42-48 s) and the surface ends 0.8 m low at 60 s
(docs/validation/refinement.md, "A sloshing tank"). Run with
``python -m pytest -n 0 -m slow tests/physics/test_refinement_sloshing.py`` (about 3
minutes on one core).
"""
import numpy as np
import pytest

import sph.engine.refinement as refinement
from sph.cases import builtin
from sph.driver import Simulation
from sph.engine.refinement import active_fluid

T_END, WINDOW = 42.0, 6.0
BOX = [{"x": [8.0, 16.0], "z": [3.0, 8.0], "level": 1}]


def _energy_windows(refined: bool):
    """Window means of E / E(0) and the change of the mean surface (m)."""
    over = [("numerics.dx", 0.8), ("geometry.tank_length", 24.0),
            ("geometry.tank_height", 24.0), ("geometry.fill", 0.5),
            ("geometry.amplitude", 2.0), ("numerics.density_filter", "none"),
            ("numerics.shifting", 1.0), ("numerics.pressure_floor", -1.0e5),
            ("numerics.wall_damping", True), ("numerics.threads", 1),
            ("probes.surface", []), ("numerics.refinement", BOX if refined else [])]
    sim = Simulation(builtin("sloshing_rect", over))
    sim.evaluate()

    def state():
        p = sim.parts
        a = active_fluid(p)
        x, z = p.x[a], p.z[a]
        top = np.mean([z[(x >= c) & (x < c + 2.0)].max() for c in range(0, 24, 2)])
        return (sim.t, 0.5 * np.sum(p.m[a] * (p.vx[a] ** 2 + p.vz[a] ** 2)),
                9.81 * np.sum(p.m[a] * z), top)

    rec = [state()]
    while sim.t < T_END:
        sim.advance()
        if sim.step % 50 == 0:
            rec.append(state())
    t, ke, pe, top = np.array(rec).T
    e = ke + pe - pe[0]
    wins = [e[(t >= a) & (t < a + WINDOW)].mean() / e[0]
            for a in np.arange(0.0, T_END - WINDOW + 1e-9, WINDOW)]
    return np.array(wins), top[-1] - top[0]


@pytest.fixture(scope="module")
def coarse():
    return _energy_windows(refined=False)


@pytest.fixture
def hysteresis(monkeypatch, request):
    monkeypatch.setattr(refinement, "HYSTERESIS", request.param)
    return request.param


@pytest.mark.slow
@pytest.mark.parametrize("hysteresis", [
    2.0, pytest.param(refinement.HYSTERESIS, marks=pytest.mark.xfail(
        strict=True, reason="families changing level in a flow pack the fluid "
        "(docs/validation/refinement.md)"))], indirect=True)
def test_sloshing_across_a_box_keeps_its_volume(coarse, hysteresis):
    wins, surface = _energy_windows(refined=True)
    assert wins.min() > 0.0, f"E / E(0) by windows {np.round(wins, 2)}"
    # the top particle of 2 m columns at dx = 0.8 m: the uniform runs end within 0.1 m
    assert abs(surface) < 0.15
    # the coarse spacing's viscous decay dominates; a box of finer fluid may only slow it
    np.testing.assert_allclose(wins, coarse[0], atol=0.05)
