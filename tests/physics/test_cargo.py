"""The loaded ship's mass properties, free-surface effect and roll-sloshing model
(sph.bodies.cargo) against closed forms."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from sph.bodies.cargo import (
    _stokes_joukowski,
    cargo_section,
    cargo_section_of_particles,
    check_mass_properties,
    mass_properties,
    roll_matrices,
    roll_modes,
)
from sph.bodies.hull import hydrostatics
from sph.cases import builtin
from sph.schema import ConfigError

HULL = builtin("damaged_ship").geometry.hull
W = 2.0 / 3.0  # the intact cabins' share of the ship's length
G = 9.81


def test_cargo_section_of_a_square_cabin_is_a_rectangle():
    """Without bilges the cargo is a rectangle b x h: area, centroid and polar moment
    A (b^2 + h^2) / 12 exactly."""
    hull = dataclasses.replace(HULL, bilge_radius=0.0)
    c = cargo_section(hull, 0.5)
    b, h = hull.breadth - 2 * hull.plating, 0.5 * hull.depth
    assert c.area == pytest.approx(b * h, rel=1e-12)
    assert c.kg == pytest.approx(hull.plating + 0.5 * h, rel=1e-12)
    assert c.inertia == pytest.approx(b * h * (b * b + h * h) / 12.0, rel=1e-9)
    assert c.breadth == pytest.approx(b) and c.depth == pytest.approx(h)
    # below the top of the bilge the surface is narrower than the cabin
    assert cargo_section(HULL, 0.1).breadth < HULL.breadth - 2 * HULL.plating


def test_loaded_ship_is_the_dry_part_plus_the_frozen_cargo():
    """`loaded`: dry part + frozen cargo give back the loaded ship's mass, KG and inertia
    Delta k^2 (first moments and the parallel-axis theorem, recomposed here)."""
    for fill, rho_c in ((0.25, 1000.0), (0.5, 1000.0), (0.75, 850.0)):
        c = cargo_section(HULL, fill)
        mp = mass_properties(HULL, 1000.0, G, W, rho_c, c)
        delta = hydrostatics(HULL, 1000.0, G)["mass"]
        assert mp.dry + mp.cargo == pytest.approx(delta, rel=1e-12)
        assert mp.cargo == pytest.approx(W * rho_c * c.area)
        kg = (mp.dry * mp.dry_kg + mp.cargo * c.kg) / delta
        assert kg == pytest.approx(HULL.kg, rel=1e-12)
        inertia = (mp.dry_inertia + mp.dry * (mp.dry_kg - kg) ** 2
                   + W * rho_c * c.inertia + mp.cargo * (c.kg - kg) ** 2)
        assert inertia == pytest.approx(delta * HULL.gyradius**2, rel=1e-12)
        assert mp.gm == pytest.approx(hydrostatics(HULL, 1000.0, G)["gm"], rel=1e-12)
    # the values of docs/ship.md at 75 % with the 850 kg/m3 oil
    assert mp.dry == pytest.approx(9.63e3, rel=2e-3)
    assert mp.dry_kg == pytest.approx(3.92, abs=0.005)
    assert mp.dry_inertia == pytest.approx(110.9e3, rel=2e-3)


def test_dry_reference_keeps_kg_and_gyradius_of_the_dry_part():
    hull = dataclasses.replace(HULL, mass_properties="dry")
    c = cargo_section(hull, 0.5)
    mp = mass_properties(hull, 1000.0, G, W, 850.0, c)
    assert mp.dry_kg == hull.kg
    assert mp.dry_inertia == pytest.approx(mp.dry * hull.gyradius**2)
    assert mp.ship_kg == pytest.approx((mp.dry * hull.kg + mp.cargo * c.kg) / mp.displacement)


def test_free_surface_correction():
    """GM_eff = GM - w (rho_c / rho) (b^3 / 12) / A(d): 3.31 m for water in the paper's
    15.8 m wide cabins, two cabins in three."""
    c = cargo_section(HULL, 0.5)
    mp = mass_properties(HULL, 1000.0, G, W, 1000.0, c)
    area = hydrostatics(HULL, 1000.0, G)["area"]
    assert mp.free_surface == pytest.approx(W * 15.8**3 / 12.0 / area, rel=1e-9)
    assert mp.free_surface == pytest.approx(3.31, abs=0.005)
    assert mp.gm_fluid == pytest.approx(mp.gm - mp.free_surface)


@pytest.mark.parametrize("hull_change, fill, rho_c, words", [
    ({}, 0.75, 1000.0, r"-0.536 % of the displacement .* allowed \(0, 917\] kg/m3"),
    ({"gyradius": 2.0}, 0.5, 1000.0, "roll inertia"),  # the frozen cargo's exceeds it
    ({"kg": 0.5}, 0.5, 1000.0, "outside the hull"),  # KG_d below the keel
    ({}, 0.9, 1000.0, r"-20.8 % .* allowed \(0, 676\] kg/m3"),
])
def test_impossible_dry_part_is_refused(hull_change, fill, rho_c, words):
    hull = dataclasses.replace(HULL, **hull_change)
    c = cargo_section(hull, fill)
    with pytest.raises(ConfigError, match=words) as err:
        check_mass_properties(hull, 1000.0, G, W, rho_c, fill, c)
    assert err.value.key == "geometry.cargo_density"


def test_particle_cargo_matches_the_exact_section():
    """The cargo as placed at dx = 0.8 m (the particles' cells) has the exact section's area,
    centroid and polar moment to within the half-spacing at its edges."""
    from sph.bodies.hull import shape
    from sph.cases.ship import _cargo_columns

    for fill in (0.25, 0.5, 0.75):
        pts, vol, _ = _cargo_columns(HULL, fill, 0.8, shape(HULL, HULL.plating))
        sph_c = cargo_section_of_particles(HULL, fill, pts[:, 0], pts[:, 1], vol)
        exact = cargo_section(HULL, fill)
        assert sph_c.area == pytest.approx(exact.area, rel=0.02)
        assert sph_c.kg == pytest.approx(exact.kg, abs=0.1)
        assert sph_c.inertia == pytest.approx(exact.inertia, rel=0.03)


def test_stokes_joukowski_inertia_of_a_square_is_lambs():
    """The liquid filling a closed square box turning about its centre has 0.1565 of the
    frozen inertia (Lamb 1932, Sec. 72); a long flat box nearly all of it."""
    j, _ = _stokes_joukowski(1.0, 1.0, 0.0, np.zeros(1))
    assert j / (4.0 * 2.0 / 3.0) == pytest.approx(0.1565, abs=2e-4)
    j, _ = _stokes_joukowski(10.0, 1.0, 0.0, np.zeros(1))
    assert j / (40.0 * 101.0 / 3.0) > 0.95


def test_roll_model_reduces_to_the_free_surface_correction_when_slow():
    """Statically (modes condensed out of the stiffness) the roll stiffness is
    Delta g GM_eff; with no cargo the frequency is sqrt(C / (I + A44))."""
    c = cargo_section(HULL, 0.5)
    mp = mass_properties(HULL, 1000.0, G, W, 1000.0, c)
    _, k = roll_matrices(mp, HULL, c, 1000.0, G, W, 1000.0, 0.0)
    static = k[0, 0] - k[0, 1:] @ np.linalg.solve(k[1:, 1:], k[1:, 0])
    # six modes (n <= 11) leave out 1e-4 of the free-surface moment (the tail of
    # sum 1/n^4); it shows 6.8 times larger on GM_eff = GM / 6.8
    assert static == pytest.approx(mp.displacement * G * mp.gm_fluid, rel=2e-3)
    empty = mass_properties(HULL, 1000.0, G, W, 1000.0, cargo_section(HULL, 0.0))
    a44 = empty.displacement * G * empty.gm / 1.06**2 - empty.displacement * HULL.gyradius**2
    out = roll_modes(empty, HULL, cargo_section(HULL, 0.0), 1000.0, G, W, 1000.0, a44)
    assert out["omega"][0] == pytest.approx(1.06, rel=1e-12)
    loaded = roll_modes(mp, HULL, c, 1000.0, G, W, 1000.0, a44)
    # two modes carry the roll: one below the sloshing frequency, one above it
    assert loaded["omega"][0] < loaded["sloshing"] < loaded["omega"][1]
    assert sum(loaded["roll_share"]) == pytest.approx(1.0)
    assert math.isfinite(loaded["quasi_static"])
