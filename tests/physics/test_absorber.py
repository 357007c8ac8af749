"""Absorbing zone (Cao et al. 2019, Eq. 16): profile and implicit damping."""

import numpy as np
import pytest

from sph.cases import builtin
from sph.engine.absorber import (
    AB_MIRROR,
    AbsorberConfig,
    absorber_params,
    damping_depth,
    sigma,
)
from sph.engine.integrator import verlet_update
from sph.schema import ConfigError

CFG = AbsorberConfig(start=90.0, length=60.0, speed=10.0)
DX = 0.4


def test_profile_is_the_hyperbolic_modave_form():
    ab = absorber_params(CFG, speed=99.0, dx=DX)  # cfg.speed wins over the default
    assert sigma(80.0, -1.0, ab) == 0.0 and sigma(90.0, -1.0, ab) == 0.0
    for x in (95.0, 120.0, 149.8):
        expect = 10.0 / 60.0 * (x - 90.0) / (150.0 - x + DX)
        assert sigma(x, 1.0, ab) == pytest.approx(expect, rel=1e-12)
        assert sigma(x, -1.0, ab) == pytest.approx(expect, rel=1e-12)
    xs = np.linspace(90.01, 150.0, 200)
    assert np.all(np.diff([sigma(x, 0.0, ab) for x in xs]) > 0)


def test_damping_depth_inverts_the_profile():
    ab = absorber_params(CFG, speed=99.0, dx=DX)
    for rate in (0.02, 0.1, 1.0):
        d = damping_depth(rate, 10.0, 60.0, DX)
        assert 0.0 < d < 60.0
        assert sigma(90.0 + d, -1.0, ab) == pytest.approx(rate, rel=1e-12)


def test_strength_scales_the_profile_speed():
    base = absorber_params(CFG, speed=99.0, dx=DX)
    strong = absorber_params(AbsorberConfig(start=90.0, length=60.0, speed=10.0, strength=2.0),
                             speed=99.0, dx=DX)
    default = absorber_params(AbsorberConfig(start=90.0, length=60.0, strength=2.0),
                              speed=9.0, dx=DX)
    for x in (95.0, 120.0, 149.8):
        assert sigma(x, 1.0, strong) == pytest.approx(2.0 * sigma(x, 1.0, base), rel=1e-12)
        assert sigma(x, 1.0, default) == pytest.approx(
            2.0 * 9.0 / 60.0 * (x - 90.0) / (150.0 - x + DX), rel=1e-12)


def test_one_sided_form_damps_only_backflow():
    ab = absorber_params(AbsorberConfig(start=90.0, length=60.0, speed=10.0,
                                        form="one_sided"), speed=1.0, dx=DX)
    assert sigma(120.0, 0.5, ab) == 0.0
    assert sigma(120.0, -0.5, ab) == pytest.approx(10.0 / 60.0 * 30.0 / (30.0 + DX),
                                                   rel=1e-12)


def test_disabled_zone_is_inert():
    ab = absorber_params(AbsorberConfig(enabled=False), speed=1.0, dx=DX)
    assert not ab.any() and sigma(120.0, -1.0, ab) == 0.0
    assert absorber_params(None, 1.0, DX)[0] == 0.0


def test_implicit_damping_of_a_uniform_flow_matches_exp_decay():
    """With no other force, dv/dt = -sigma v: the Euler-implicit update decays the speed as
    (1 + sigma dt)^-n, which tends to exp(-sigma t); here sigma dt = 1e-3."""
    n = 4
    x = np.full(n, 120.0)
    z = np.ones(n)
    vx = np.full(n, 0.5)
    vz = np.full(n, -0.25)
    zeros = np.zeros(n)
    rho = np.full(n, 1000.0)
    ab = absorber_params(CFG, speed=1.0, dx=DX)
    s = sigma(120.0, 0.5, ab)
    dt = 1e-3 / s
    steps = 2000
    expected = 1.0
    for _ in range(steps):
        x[:] = 120.0  # hold the particles (the update drifts them by dt vx first)
        expected /= 1.0 + dt * sigma(120.0 + dt * vx[0], vx[0], ab)
        verlet_update(x, z, vx, vz, rho, vx.copy(), vz.copy(), rho.copy(), zeros, zeros,
                      zeros, np.zeros(n, dtype=np.int32), dt, True, ab)
    np.testing.assert_allclose(vx, 0.5 * expected, rtol=1e-10)
    np.testing.assert_allclose(vz, -0.25 * expected, rtol=1e-10)
    assert expected == pytest.approx(np.exp(-s * dt * steps), rel=2e-3)


def test_huge_damping_stays_stable():
    """Near the end wall sigma dt can exceed 1; the implicit update never overshoots."""
    ab = absorber_params(AbsorberConfig(start=0.0, length=1.0, speed=1e4), speed=1.0, dx=1e-3)
    x = np.array([0.999])
    vx = np.array([1.0])
    vz = np.array([1.0])
    one = np.ones(1)
    zero = np.zeros(1)
    verlet_update(x, one.copy(), vx, vz, one * 1000, vx.copy(), vz.copy(), one * 1000, zero,
                  zero, zero, np.zeros(1, dtype=np.int32), 1e-3, True, ab)
    assert 0.0 < vx[0] < 1e-3
    # exactly the implicit factor 1 / (1 + sigma dt), at the drifted position, on both
    # components
    s = sigma(0.999 + 1e-3 * 1.0, 1.0, ab)
    assert vx[0] == pytest.approx(1.0 / (1.0 + 1e-3 * s), rel=1e-12)
    assert vz[0] == pytest.approx(vx[0], rel=1e-12)


def test_an_enabled_zone_must_say_where_it_lies():
    """The zone's place belongs to the case (no tank-specific default): enabling a zone
    without ``start`` is refused naming the key, before any particle is built."""
    with pytest.raises(ConfigError) as err:
        builtin("ship_decay", ["geometry.absorber.enabled=true"])
    assert err.value.key == "geometry.absorber.start"
    assert "required when geometry.absorber.enabled is true" in str(err.value)
    cfg = builtin("ship_decay", ["geometry.absorber.enabled=true", "geometry.absorber.start=80",
                                 "geometry.absorber.length=40"])
    assert (cfg.geometry.absorber.start, cfg.geometry.absorber.length) == (80.0, 40.0)


def test_damping_towards_a_stream_keeps_the_stream_and_damps_the_rest():
    """In a current tank the zone damps the velocity relative to the stream (U, 0): a
    particle moving with the stream is left alone, one 0.3 m/s faster and 0.2 m/s upward
    relaxes towards (U, 0) as (1 + sigma dt)^-n; the one-sided form damps only particles
    slower than the stream."""
    u0 = 0.8
    x = np.full(2, 120.0)
    z = np.ones(2)
    vx = np.array([u0, u0 + 0.3])
    vz = np.array([0.0, 0.2])
    zeros = np.zeros(2)
    rho = np.full(2, 1000.0)
    ab = absorber_params(CFG, speed=1.0, dx=DX, stream=u0)
    dt = 1e-3 / sigma(120.0, 0.0, ab)
    expected = 1.0
    for _ in range(500):
        x[:] = 120.0
        expected /= 1.0 + dt * sigma(120.0 + dt * vx[1], vx[1] - u0, ab)
        verlet_update(x, z, vx, vz, rho, vx.copy(), vz.copy(), rho.copy(), zeros, zeros,
                      zeros, np.zeros(2, dtype=np.int32), dt, True, ab)
    assert vx[0] == u0 and vz[0] == 0.0
    np.testing.assert_allclose(vx[1] - u0, 0.3 * expected, rtol=1e-10)
    np.testing.assert_allclose(vz[1], 0.2 * expected, rtol=1e-10)
    one = absorber_params(AbsorberConfig(start=90.0, length=60.0, speed=10.0,
                                         form="one_sided"), speed=1.0, dx=DX, stream=u0)
    assert sigma(120.0, 0.3, one) == 0.0 and sigma(120.0, -0.3, one) > 0.0


def test_mirrored_zone_damps_both_ends_alike():
    """A mirrored zone (free decay in a still 150 m tank, zones over its last and first 30 m)
    damps at x what the zone damps at 150 - x, in the one-sided form the flow towards the
    middle at either end; the middle is left alone."""
    for form in ("two_sided", "one_sided"):
        cfg = AbsorberConfig(start=120.0, length=30.0, speed=10.0, form=form, mirrored=True)
        ab = absorber_params(cfg, speed=1.0, dx=DX, middle=75.0)
        for x in (121.0, 135.0, 149.8):
            for v in (-0.5, 0.5):
                assert sigma(150.0 - x, -v, ab) == pytest.approx(sigma(x, v, ab), rel=1e-12)
        assert sigma(150.0 - 135.0, 0.5, ab) > 0.0  # towards the middle from the start end
        assert sigma(60.0, -1.0, ab) == 0.0 and sigma(90.0, -1.0, ab) == 0.0
    plain = absorber_params(AbsorberConfig(start=120.0, length=30.0, speed=10.0), 1.0, DX,
                            middle=75.0)
    assert sigma(15.0, -1.0, plain) == 0.0 and sigma(135.0, -1.0, plain) > 0.0


MIRRORED = ["numerics.dx=0.8", "geometry.absorber.enabled=true", "geometry.absorber.start=90",
            "geometry.absorber.length=30", "geometry.absorber.mirrored=true"]


def test_mirrored_zone_fits_a_still_decay_tank():
    from sph.cases import setup

    cfg = builtin("ship_decay", MIRRORED)
    ab = setup(cfg).absorber
    assert ab[AB_MIRROR] == pytest.approx(0.5 * cfg.geometry.tank_length)


@pytest.mark.parametrize("overrides, key", [
    # the flap's wave would be damped at the flap by the zone's mirror image
    (["geometry.wavemaker.theta0=0.05"], "geometry.absorber.mirrored"),
    # the two zones would overlap
    (["geometry.absorber.start=50", "geometry.absorber.length=20"],
     "geometry.absorber.start"),
    # the ship inside the zone at the start end
    (["geometry.ship_x=30"], "geometry.ship_x"),
])
def test_mirrored_zone_is_refused_where_it_does_not_fit(overrides, key):
    from sph.cases import setup

    with pytest.raises(ConfigError) as err:
        setup(builtin("ship_decay", MIRRORED + overrides))
    assert err.value.key == key


def test_mirrored_zone_is_refused_in_cases_without_a_middle():
    with pytest.raises(ConfigError) as err:
        absorber_params(AbsorberConfig(start=90.0, length=60.0, mirrored=True), 1.0, DX)
    assert err.value.key == "geometry.absorber.mirrored"
