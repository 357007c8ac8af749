"""Validation ladder step 4: the numerical wave tank against linear wavemaker theory.

Fast tests check the post-processing on synthetic records, the refusal of bad input and a
short coarse run; the ``slow`` tests run the paper's tank (Cao et al. 2019, Sec. III B) and
compare with linear theory (A = 1.02 m, T = 2 pi s). Tolerances: amplitude 10 % at
dx = 0.4 A (a wave height is resolved by 5 particles; SPH dissipation over two wavelengths
and the weakly-compressible surface both lower it) and 5 % at dx = 0.2 A (the dissipation,
like the artificial viscosity alpha h c0, scales with h), period 1 % (set by the flap),
reflection below 5 % with the absorbing zone, and the incident wave extrapolated back to the
flap within 3 % of theory. Both resolutions are judged over the same window, 40-60 s: the
wave reflected by the zone reaches WP2 after about 30 s and WP1 after about 40 s, and the
two probes, half a wavelength apart, both sit near nodes of the partial standing wave it
makes (docs/validation/wave_tank.md: with a probe every 3 m at dx = 1 A and 0.6 A the incident wave
is within 1 % of theory at the flap, decays at the artificial viscosity's rate, and the
zone reflects 1.9 % with strength 1, 0.8-0.9 % with the built-in case's strength 2). A
dx = 0.4 A run is 3.2 G particle-steps (30 457 particles, 105 300 steps), a dx = 0.2 A run
about 25 G (117 000 particles, 210 000 steps): at the 1.0 to 3.2 M particle-steps/s of two
threads on the 2-core machines measured so far, 20 to 50 minutes and 2.2 to 7 hours;
results are in docs/validation/wave_tank.md. The built-in case uses alpha = 0.01, half the
paper's value: the artificial viscosity's decay (2 nu k^2 / c_g per metre, nu = alpha h
c0 / 8) took 2.6 % of WP2's 5 % at 0.2 A with 0.02. Measured over 40-60 s: with
alpha = 0.01, WP1 / WP2 -1.2 / -4.6 % at 0.4 A and -1.3 / -4.0 % at 0.2 A (every assertion
holds); with 0.02, -2.5 / -6.8 % at 0.4 A and -1.7 / -5.1 % at 0.2 A (0.1 point outside
5 %). Beyond
the viscous decay, the wave at the flap is 1.8 % low at 0.2 A (1 % of it nonlinear), and it
loses about 2 % more by 84 m at every dx (docs/validation/wave_tank.md, "The error
budget, and what is still open").
"""

import math

import numpy as np
import pytest
from physics_helpers import run_builtin

from sph.bodies.wavemaker import flap_wave_amplitude, group_velocity
from sph.cases import builtin
from sph.schema import ConfigError
from sph.study.analysis import (
    flap_wave_record,
    harmonic_fit,
    reflection_coefficient,
    viscous_wave_damping,
    wave_statistics,
)
from sph.study.validation import wave_separation

OMEGA, K = 1.0, 0.10237595312395345


def test_wave_statistics_on_a_synthetic_record():
    t = np.arange(0, 60, 0.1)
    eta = 0.05 + 1.02 * np.sin(OMEGA * t + 0.3) + 0.03 * np.sin(2 * OMEGA * t)
    s = wave_statistics(t, eta, OMEGA, (20.0, 60.0))
    assert s["amplitude"] == pytest.approx(1.02, rel=1e-3)
    assert s["mean"] == pytest.approx(0.05, abs=2e-3)
    assert s["period"] == pytest.approx(2 * math.pi, rel=1e-3)


@pytest.mark.parametrize("kr", [0.0, 0.04, 0.3])
def test_reflection_separation_on_synthetic_waves(kr):
    t = np.arange(0, 80, 0.1)
    xs = np.array([30.0, 60.0, 66.0, 72.0, 81.0])
    a_i, phase = 1.0, 0.7
    etas = [a_i * np.cos(OMEGA * t - K * x + phase) + kr * a_i * np.cos(OMEGA * t + K * x + 2.1)
            for x in xs]
    r = reflection_coefficient(t, etas, xs, OMEGA, K, (10.0, 80.0))
    assert r["incident"] == pytest.approx(a_i, rel=1e-6)
    assert r["coefficient"] == pytest.approx(kr, abs=1e-6)


@pytest.mark.parametrize("kr", [0.0, 0.03])
def test_reflection_separation_with_a_decaying_incident_wave(kr):
    # a wave losing 0.13 % per metre (the artificial viscosity at dx = 0.6 A) plus a
    # reflected wave growing towards the reflector: the fit with the decay recovers both
    # and the amplitude at the flap; without it, the decay is misread as reflection
    t = np.arange(0, 80, 0.1)
    beta, a_i, x_end = 1.3e-3, 1.0, 90.0
    xs = np.arange(18.0, 88.0, 6.0)
    a_r = kr * a_i * math.exp(-2 * beta * x_end)  # reflected amplitude at x = 0
    etas = [a_i * math.exp(-beta * x) * np.cos(OMEGA * t - K * x + 0.4)
            + a_r * math.exp(beta * x) * np.cos(OMEGA * t + K * x + 1.3) for x in xs]
    r = reflection_coefficient(t, etas, xs, OMEGA, K, (10.0, 80.0), decay=beta)
    assert r["incident"] == pytest.approx(a_i, rel=1e-6)
    assert r["coefficient"] == pytest.approx(kr * math.exp(-2 * beta * (x_end - xs.max())),
                                             abs=1e-6)
    assert r["residual"] < 1e-6
    blind = reflection_coefficient(t, etas, xs, OMEGA, K, (10.0, 80.0))
    assert blind["residual"] > 1e-3
    assert blind["incident"] < 0.95 * a_i


def _envelope(t, eta, centre, omega=OMEGA):
    """First-harmonic amplitude over the period centred on ``centre``."""
    sel = np.abs(t - centre) < math.pi / omega
    return abs(harmonic_fit(t[sel], eta[sel], omega)[0])


def test_signalling_solution_settles_to_flap_theory_with_the_phase_of_a_progressive_wave():
    # a long sine started abruptly: once the front has passed, the record is the steady
    # linear wave eta = A cos(omega t - k x) of the flap transfer function
    t = np.arange(0.0, 120.0, 0.05)
    a = flap_wave_amplitude(0.025, OMEGA, 30.0)
    eta = flap_wave_record(t, 0.025 * np.sin(OMEGA * t), 60.0, 30.0)
    late = t > 70.0
    z, mean = harmonic_fit(t[late], eta[late], OMEGA)
    assert abs(z) == pytest.approx(a, rel=2e-3)
    assert abs(np.angle(z * np.exp(1j * K * 60.0))) < math.radians(1.0)
    assert abs(mean) < 2e-3 * a


def test_signalling_solution_decays_at_the_viscous_rate():
    t = np.arange(0.0, 120.0, 0.05)
    k, depth, nu, x = K, 30.0, 0.2, 60.0
    cg = group_velocity(OMEGA, depth)
    eta = flap_wave_record(t, 0.025 * np.sin(OMEGA * t), x, depth, nu=nu)
    late = t > 70.0
    expected = flap_wave_amplitude(0.025, OMEGA, depth) * math.exp(
        -viscous_wave_damping(nu, k) / cg * x)
    assert abs(harmonic_fit(t[late], eta[late], OMEGA)[0]) == pytest.approx(expected, rel=2e-3)


def test_signalling_front_is_the_fresnel_front_at_the_group_velocity():
    # far from the flap a suddenly started wave train arrives with the envelope of a step
    # spread by dispersion (Fresnel integral): half the steady amplitude at t = x / c_g,
    # then the first overshoot, 1.17 times the steady amplitude (the Cornu spiral)
    t = np.arange(0.0, 120.0, 0.05)
    depth, x = 30.0, 300.0
    cg = group_velocity(OMEGA, depth)
    a = flap_wave_amplitude(0.025, OMEGA, depth)
    eta = flap_wave_record(t, 0.025 * np.sin(OMEGA * t), x, depth)
    assert _envelope(t, eta, x / cg) / a == pytest.approx(0.5, abs=0.05)
    peak = max(_envelope(t, eta, c) for c in np.arange(x / cg, x / cg + 30.0, 0.5)) / a
    assert peak == pytest.approx(1.17, abs=0.05)
    assert _envelope(t, eta, x / cg - 15.0) / a < 0.2


def test_signalling_solution_refuses_uneven_sampling():
    t = np.array([0.0, 0.1, 0.3, 0.4, 0.5])
    with pytest.raises(ValueError, match="uniformly"):
        flap_wave_record(t, np.zeros_like(t), 30.0, 30.0)


def _wave_tank(overrides):
    return builtin("wave_tank", overrides)


@pytest.mark.parametrize("overrides, key, words", [
    (["geometry.depth=-30"], "geometry.depth", "in (0"),
    (["geometry.depth=45"], "geometry.depth", "tank_height"),
    (["geometry.absorber.length=80"], "geometry.absorber.length", "(0, tank_length - start"),
    (["geometry.absorber.start=200"], "geometry.absorber.length", "inside the tank"),
    (["probes.surface=[{name: far, x: 170.0}]"], "probes.surface[0].x", "inside the tank"),
    (["probes.surface=[{name: behind, x: -5.0}]"], "probes.surface[0].x", "inside the tank"),
    (["geometry.wavemaker.theta0=0.025", "geometry.wavemaker.amplitude=1.0"],
     "geometry.wavemaker.amplitude", "either theta0 or amplitude"),
    (["geometry.wavemaker.omega=0"], "geometry.wavemaker.omega", "in (0"),
    (["geometry.absorber.form=sideways"], "geometry.absorber.form", "one of"),
    (["geometry.wavemaker.file=/nonexistent/flap.dat"], "geometry.wavemaker.file",
     "does not exist"),
    (["geometry.absorber.damping=3"], "geometry.absorber.damping", "unknown key"),
])
def test_bad_wave_tank_input_is_refused(overrides, key, words):
    with pytest.raises(ConfigError) as err:
        _wave_tank(overrides)
    assert err.value.key == key
    assert words in str(err.value)


def test_non_monotonic_flap_file_is_refused(tmp_path):
    p = tmp_path / "flap.dat"
    p.write_text("0 0\n0.1 0.5\n0.05 1.0\n0.2 0.0\n")
    with pytest.raises(ConfigError) as err:
        _wave_tank(["geometry.wavemaker.theta0=null", f"geometry.wavemaker.file={p}"])
    assert err.value.key == "geometry.wavemaker.file"
    assert "row 3" in str(err.value)


def _flap_run(extra=()):
    return run_builtin("wave_tank", ["numerics.dx=1.0", "run.t_end=30.0",
                                     "run.output_interval=0.05",
                                     "probes.surface=[{name: near, x: 3.0}, {name: WP1, x: 30.0}]",
                                     *extra])


def _assert_flap_drives_the_water(sim, amplitude_tolerance):
    ds = sim.dataset()
    t = ds.time.values
    np.testing.assert_allclose(ds.flap_angle.values, np.degrees(0.025 * np.sin(t)), atol=1e-12)
    eta = ds.probe_elevation.sel(probe="near").values
    assert eta[np.argmin(abs(t - 1.8))] > 0.2
    assert eta[np.argmin(abs(t - 4.9))] < -0.2
    assert abs(ds.volume_error.values).max() < 0.01
    # the run records the zone's effective c: strength 2 x the phase speed omega / k
    assert ds.attrs["absorber_speed"] == pytest.approx(2.0 * OMEGA / K, rel=1e-9)
    s = wave_statistics(t, ds.probe_elevation.sel(probe="WP1").values, OMEGA, (15.0, 30.0))
    theory = ds.attrs["theory_amplitude"]
    assert abs(s["amplitude"] / theory - 1.0) < amplitude_tolerance, (s, theory)
    assert abs(s["period"] / (2 * math.pi / OMEGA) - 1.0) < 0.01, s


def test_flap_drives_the_water_next_to_it_short_tank():
    """The test below in a tank half as long (75 m, the absorbing zone over its last 30 m:
    half the particles). The flap and the water next to it behave the same (measured
    +0.27 / -0.22 m there, against the 0.2 m bounds); at WP1 the period holds to 1 %
    (measured +0.08 %) and the amplitude to 10 % (measured +5.0 %: a zone half a wavelength
    long reflects more, and the reflected part that reaches WP1 before 30 s adds to the
    incident wave)."""
    _assert_flap_drives_the_water(_flap_run(["geometry.tank_length=75",
                                             "geometry.absorber.start=45",
                                             "geometry.absorber.length=30"]), 0.10)


@pytest.mark.slow
def test_flap_drives_the_water_next_to_it():
    """Coarse (dx = 1 m = 1 A) and short (30 s): the flap angle is recorded as theta0
    sin(omega t) in degrees; the water next to the flap rises while the flap leans forward
    (t ~ pi/2) and falls while it leans back (t ~ 3 pi/2); and once the front has passed
    WP1 (x = 30 m, 15-30 s) the wave there has the linear-theory amplitude within 10 % and
    period within 1 % (measured -1.7 % and -0.2 % with the case's alpha = 0.01, -4.9 % with
    0.02; the artificial viscosity alone takes 3 % over those 30 m at this resolution with
    0.01, docs/validation/wave_tank.md)."""
    _assert_flap_drives_the_water(_flap_run(), 0.10)


def _paper_tank(absorber: bool, dx: float = 0.4):
    sim = run_builtin("wave_tank", [f"numerics.dx={dx}", "run.t_end=60.0",
                                    f"geometry.absorber.enabled={str(absorber).lower()}"])
    return sim.dataset()


WINDOW = (40.0, 60.0)


@pytest.mark.slow
@pytest.mark.parametrize("dx, tolerance", [(0.4, 0.10), (0.2, 0.05)], ids=["0.4A", "0.2A"])
def test_paper_tank_amplitude_period_and_reflection(dx, tolerance):
    ds = _paper_tank(True, dx)
    a_theory = float(ds.attrs["theory_amplitude"])
    for probe in ("WP1", "WP2"):
        s = wave_statistics(ds.time.values, ds.probe_elevation.sel(probe=probe).values, OMEGA,
                            WINDOW)
        print(f"dx = {dx} m, {probe}: A = {s['amplitude']:.3f} m (theory {a_theory:.3f}), "
              f"T = {s['period']:.3f} s")
        assert abs(s["amplitude"] / a_theory - 1) < tolerance
        assert abs(s["period"] / (2 * math.pi) - 1) < 0.01
    r = wave_separation(ds, WINDOW)
    print(f"reflection with the zone: {r['coefficient']:.3f}; incident amplitude at the "
          f"flap {r['incident']:.3f} m (residual {r['residual']:.3f})")
    assert r["coefficient"] < 0.05
    # the flap makes the linear-theory wave: extrapolated back to the flap with the decay
    # of the artificial viscosity, the incident wave is within 3 % of theory (second-order
    # corrections to the first harmonic are (ka)^2 = 1 %; the fit's residual about 2 %)
    assert abs(r["incident"] / a_theory - 1) < 0.03


@pytest.mark.slow
def test_without_the_zone_the_end_wall_reflects():
    ds = _paper_tank(False)
    r = wave_separation(ds, WINDOW)
    print(f"reflection without the zone: {r['coefficient']:.3f}")
    assert r["coefficient"] > 0.2
