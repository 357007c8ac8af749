"""Flap wavemaker: linear theory helper and prescribed flap kinematics."""

import math

import numpy as np
import pytest
from physics_helpers import require_validation_data

from sph.bodies.wavemaker import (
    FlapConfig,
    FlapMotion,
    flap_height_to_stroke,
    flap_theta0,
    flap_wave_amplitude,
    group_velocity,
    load_flap_file,
    wavenumber,
)
from sph.engine.particles import WALL
from sph.engine.walls import fixed_kinematics, place_walls
from sph.schema import ConfigError


def test_paper_tank_values():
    """Cao et al. (2019), Sec. III B: theta0 = 0.025, omega = 1, H = 30 m -> A = 1.02 m,
    k = 0.1024 1/m, lambda = 61.4 m."""
    k = wavenumber(1.0, 30.0)
    assert k == pytest.approx(0.1024, abs=5e-5)
    assert 2 * math.pi / k == pytest.approx(61.4, abs=0.05)
    assert flap_wave_amplitude(0.025, 1.0, 30.0) == pytest.approx(1.02, abs=0.005)
    # the design card's ship wave: A = (10/21) d = 2.0 m needs about 0.049 rad
    assert flap_theta0(10 / 21 * 4.2, 1.0, 30.0) == pytest.approx(0.049, abs=0.001)


@pytest.mark.parametrize("omega, depth", [(1.0, 30.0), (0.3, 5.0), (6.0, 0.4), (2.0, 100.0)])
def test_dispersion_relation_and_round_trip(omega, depth):
    k = wavenumber(omega, depth)
    assert omega**2 == pytest.approx(9.81 * k * math.tanh(k * depth), rel=1e-12)
    th = flap_theta0(0.1, omega, depth)
    assert flap_wave_amplitude(th, omega, depth) == pytest.approx(0.1, rel=1e-12)


@pytest.mark.parametrize("omega, depth", [(1.0, 30.0), (0.3, 5.0), (0.05, 10.0), (8.0, 30.0)])
def test_group_velocity_is_d_omega_d_k_with_its_limits(omega, depth):
    k = wavenumber(omega, depth)
    dk = 1e-6 * k
    numeric = (math.sqrt(9.81 * (k + dk) * math.tanh((k + dk) * depth))
               - math.sqrt(9.81 * (k - dk) * math.tanh((k - dk) * depth))) / (2 * dk)
    assert group_velocity(omega, depth) == pytest.approx(numeric, rel=1e-6)
    if k * depth < 0.1:  # shallow water: non-dispersive, sqrt(g h)
        assert group_velocity(omega, depth) == pytest.approx(math.sqrt(9.81 * depth), rel=5e-3)
    if k * depth > 10:  # deep water: half the phase speed
        assert group_velocity(omega, depth) == pytest.approx(0.5 * omega / k, rel=1e-6)


def test_flap_transfer_function_limits():
    """Shallow water: H/S -> kh/2; deep water: H/S -> 2 (Dean & Dalrymple, Fig. 6.6)."""
    for kh in (1e-3, 1e-2):
        assert flap_height_to_stroke(kh) / (kh / 2) == pytest.approx(1.0, rel=1e-3)
    assert flap_height_to_stroke(50.0) == pytest.approx(2.0, rel=0.03)
    assert flap_height_to_stroke(500.0) == pytest.approx(2.0, rel=3e-3)
    # monotonic in between, and continuous where the large-kh form takes over
    khs = np.linspace(0.01, 30, 500)
    vals = [flap_height_to_stroke(x) for x in khs]
    assert np.all(np.diff(vals) > 0)
    assert flap_height_to_stroke(20.0 - 1e-9) == pytest.approx(flap_height_to_stroke(20.0 + 1e-9),
                                                              rel=1e-6)


@pytest.mark.parametrize("ramp", [0.0, 5.0])
def test_flap_derivatives_are_consistent(ramp):
    m = FlapMotion(FlapConfig(theta0=0.03, omega=1.3, ramp_time=ramp), depth=30.0)
    eps = 1e-5
    for t in np.linspace(0.01, 12.0, 37):
        th, dth, ddth = m.angle(t)
        assert dth == pytest.approx((m.angle(t + eps)[0] - m.angle(t - eps)[0]) / (2 * eps),
                                    abs=1e-7)
        assert ddth == pytest.approx((m.angle(t + eps)[1] - m.angle(t - eps)[1]) / (2 * eps),
                                     abs=1e-6)
    if ramp:
        assert m.angle(0.0) == (0.0, 0.0, 0.0)
    assert m.angle(ramp + 0.5)[0] == pytest.approx(0.03 * math.sin(1.3 * (ramp + 0.5)))


def test_flap_from_target_amplitude():
    m = FlapMotion(FlapConfig(amplitude=1.0235, omega=1.0), depth=30.0)
    assert m.theta0 == pytest.approx(0.025, rel=1e-3)


def test_flap_rotates_its_walls_rigidly_about_the_hinge():
    """Wall particles of group 1 keep their distance to the hinge; velocity = Omega x r;
    a positive flap angle moves the top towards +x."""
    m = FlapMotion(FlapConfig(theta0=0.05, omega=1.0), depth=1.0)
    bx = np.array([-0.05, -0.05, -0.15])
    bz = np.array([0.1, 0.9, 0.5])
    x, z = bx.copy(), bz.copy()
    vx, vz = np.zeros(3), np.zeros(3)
    kind = np.full(3, WALL, dtype=np.int32)
    body = np.ones(3, dtype=np.int32)
    kin = fixed_kinematics(2)
    t = 1.2
    kin[1] = m.kinematics(t)
    place_walls(x, z, vx, vz, bx, bz, kind, body, kin)
    np.testing.assert_allclose(np.hypot(x, z), np.hypot(bx, bz), rtol=1e-12)
    th, dth, _ = m.angle(t)
    assert th > 0 and x[1] > bx[1]  # top leans towards +x
    np.testing.assert_allclose(x, bx * math.cos(th) + bz * math.sin(th), rtol=1e-12)
    np.testing.assert_allclose(vx, dth * z, rtol=1e-12)
    np.testing.assert_allclose(vz, -dth * x, rtol=1e-12)


def test_flap_file_of_the_hadzic_experiment():
    d = require_validation_data()
    path = d / "hadzic2005" / "CaseFloatingWavesVal_Flap.dat"
    data = load_flap_file(str(path))
    m = FlapMotion(FlapConfig(file=str(path)), depth=0.4)
    k = 2345
    assert m.angle(data[k, 0])[0] == pytest.approx(math.radians(data[k, 1]), rel=1e-12)
    assert m.theta0 == pytest.approx(math.radians(np.abs(data[:, 1]).max()))


@pytest.mark.parametrize("content, words", [
    ("0 0\n0.1 1\n0.1 2\n", "increase strictly"),
    ("0 0\n0.2 1\n0.1 2\n", "increase strictly"),
    ("0 0\n0.1 x\n0.2 2\n", "two numeric columns"),
    ("0 0\n0.1 45\n0.2 2\n", "[-30, 30]"),
    ("0 0\n", "at least 3 rows"),
])
def test_bad_flap_files_are_refused(tmp_path, content, words):
    p = tmp_path / "flap.dat"
    p.write_text(content)
    with pytest.raises(ConfigError) as err:
        load_flap_file(str(p), "geometry.wavemaker.file")
    assert err.value.key == "geometry.wavemaker.file"
    assert words in str(err.value)


def test_missing_flap_file_is_refused(tmp_path):
    with pytest.raises(ConfigError, match="does not exist"):
        FlapConfig(file=str(tmp_path / "nope.dat")).check("geometry.wavemaker")
