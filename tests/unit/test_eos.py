"""Tests of the Tait equation of state and the hydrostatic initial density."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sph.engine.eos import (
    cavitation_floor,
    fluid_pressures,
    hydrostatic_density,
    tait_density,
    tait_pressure,
)
from sph.engine.particles import FLUID, WALL

RHO0 = 1000.0
G = 9.81


def _b(c0, rho0=RHO0, gamma=7.0):
    return c0 * c0 * rho0 / gamma


# (c0 in m/s, gamma): the expanded gamma = 7 path and the generic power
EOS_CASES = [(10.0 * math.sqrt(G * 1.0), 7.0), (60.0, 7.0), (25.0, 1.4), (40.0, 3.0)]


@pytest.mark.parametrize("c0, gamma", EOS_CASES)
def test_pressure_zero_at_reference_density(c0, gamma):
    b = _b(c0, gamma=gamma)
    assert tait_pressure(RHO0, RHO0, b, gamma) == 0.0
    assert tait_density(0.0, RHO0, b, gamma) == pytest.approx(RHO0, rel=1e-15)


@pytest.mark.parametrize("c0, gamma", EOS_CASES)
def test_density_pressure_round_trip(c0, gamma):
    b = _b(c0, gamma=gamma)
    # the whole range the run-time checks allow by default (0.5 .. 1.5 rho0) and beyond
    for rho in np.linspace(0.45 * RHO0, 2.0 * RHO0, 301):
        p = tait_pressure(rho, RHO0, b, gamma)
        assert tait_density(p, RHO0, b, gamma) == pytest.approx(rho, rel=1e-12)


@pytest.mark.parametrize("c0, gamma", EOS_CASES)
def test_pressure_round_trip(c0, gamma):
    """The other way round: pressures from strong tension to strong compression."""
    b = _b(c0, gamma=gamma)
    for p in np.linspace(-0.9 * b, 20.0 * b, 201):
        rho = tait_density(p, RHO0, b, gamma)
        assert tait_pressure(rho, RHO0, b, gamma) == pytest.approx(p, rel=1e-10, abs=1e-9 * b)


@pytest.mark.parametrize("c0, gamma", EOS_CASES)
def test_pressure_matches_formula_and_is_monotone(c0, gamma):
    b = _b(c0, gamma=gamma)
    rho = np.linspace(0.5 * RHO0, 1.5 * RHO0, 101)
    p = np.array([tait_pressure(r, RHO0, b, gamma) for r in rho])
    np.testing.assert_allclose(p, b * ((rho / RHO0) ** gamma - 1.0), rtol=1e-12,
                               atol=1e-12 * b)
    assert np.all(np.diff(p) > 0.0)
    # the slope at rho0 is the speed of sound squared: dP/drho = c0^2
    d = 1e-4 * RHO0
    slope = (tait_pressure(RHO0 + d, RHO0, b, gamma)
             - tait_pressure(RHO0 - d, RHO0, b, gamma)) / (2.0 * d)
    assert slope == pytest.approx(c0 * c0, rel=1e-6)


def test_inverse_is_floored_under_strong_tension():
    """A tension beyond -b (no density can give it) stays finite and positive."""
    gamma, b = 7.0, _b(30.0)
    floor = RHO0 * 1e-3 ** (1.0 / gamma)
    for p in (-b, -2.0 * b, -1e6 * b):
        rho = tait_density(p, RHO0, b, gamma)
        assert math.isfinite(rho) and rho == pytest.approx(floor, rel=1e-12)


@pytest.mark.parametrize("c0, gamma", EOS_CASES)
def test_hydrostatic_density_gives_hydrostatic_pressure(c0, gamma):
    b = _b(c0, gamma=gamma)
    depth = np.linspace(0.0, 2.0, 41)
    rho = hydrostatic_density(depth, RHO0, b, gamma, G)
    assert rho.shape == depth.shape
    assert rho[0] == pytest.approx(RHO0, rel=1e-15)
    assert np.all(np.diff(rho) > 0.0)
    p = np.array([tait_pressure(r, RHO0, b, gamma) for r in rho])
    np.testing.assert_allclose(p, RHO0 * G * depth, rtol=1e-10, atol=1e-9)
    # scalar input works as well
    r1 = hydrostatic_density(1.3, RHO0, b, gamma, G)
    assert tait_pressure(float(r1), RHO0, b, gamma) == pytest.approx(RHO0 * G * 1.3, rel=1e-10)


def test_hydrostatic_density_with_engine_speed_of_sound():
    """With c0 = c_factor sqrt(g H) the bottom density exceeds rho0 by about 1/c_factor^2."""
    depth, c_factor, gamma = 1.0, 10.0, 7.0
    c0 = c_factor * math.sqrt(G * depth)
    rho = float(hydrostatic_density(depth, RHO0, _b(c0), gamma, G))
    assert (rho / RHO0 - 1.0) == pytest.approx(1.0 / c_factor**2, rel=0.05)


def test_fluid_pressures_fills_fluid_only():
    gamma, b = 7.0, _b(30.0)
    rho = np.linspace(0.9 * RHO0, 1.1 * RHO0, 50)
    kind = np.where(np.arange(50) % 3 == 0, WALL, FLUID).astype(np.int32)
    p = np.full(50, -123.0)
    fluid_pressures(rho, kind, p, RHO0, b, gamma)
    fl = kind == FLUID
    np.testing.assert_allclose(p[fl], b * ((rho[fl] / RHO0) ** gamma - 1.0), rtol=1e-12)
    assert np.all(p[~fl] == -123.0)


def test_cavitation_floor_raises_the_fluid_below_it_at_both_levels():
    rho = np.array([990.0, 999.0, 1001.0, 990.0])
    old = np.array([999.5, 990.0, 1001.0, 990.0])
    kind = np.array([FLUID, FLUID, FLUID, WALL], np.int32)
    cavitation_floor(rho, old, kind, 999.0)
    np.testing.assert_array_equal(rho, [999.0, 999.0, 1001.0, 990.0])
    np.testing.assert_array_equal(old, [999.5, 999.0, 1001.0, 990.0])
