"""Validation ladder step 3: first-mode sloshing frequency against linear theory.

Rectangular tank 1 m x 1 m, fills 25/50/75 %, dx = 0.025 m (10-30 particles over the depth,
40 along the tank), started with the linear first-mode velocity field (amplitude 1 cm, a/h
<= 4 %, so nonlinear frequency shifts are below 0.1 %). Tolerance 3 %: the measured
frequency includes the weak-compressibility shift (about (omega h / c0)^2 < 0.5 %) and the
free-surface position error of half a particle spacing (about 1 % at fill 25 %). The
damping of the mode is that of the artificial viscosity, nu = alpha h c0 / 8, on a gravity
wave: 2 nu k^2.
"""

import math

import pytest
from physics_helpers import run_builtin

from sph.cases.sloshing import linear_frequency
from sph.study.analysis import artificial_viscosity_nu, oscillation_frequency, viscous_wave_damping


#: the 50 and 75 % tanks (the deeper, the longer a run) only in the slow suite, to keep the
#: default one under ten minutes on two cores; the 25 % tank checks the same in every run
@pytest.mark.parametrize("fill", [0.25, pytest.param(0.5, marks=pytest.mark.slow),
                                  pytest.param(0.75, marks=pytest.mark.slow)])
def test_rectangular_tank_first_mode_frequency(fill):
    sim = run_builtin("sloshing_rect", [
        "numerics.dx=0.025", f"geometry.fill={fill}", "run.t_end=4.0",
        "run.output_interval=0.01"])
    ds = sim.dataset()
    omega, zeta = oscillation_frequency(ds.time.values, ds.centre_of_mass_x.values)
    theory = linear_frequency(1.0, fill * 1.0, 9.81)
    assert abs(omega / theory - 1.0) < 0.03, (omega, theory)
    # the probe near the wall sees the same mode
    omega_p, _ = oscillation_frequency(ds.time.values,
                                       ds.probe_elevation.sel(probe="near_left_wall").values)
    assert abs(omega_p / theory - 1.0) < 0.03
    # a free decay at the rate the artificial viscosity gives (alpha = 0.02, nu = alpha h
    # c0 / 8, 2 nu k^2; see the test below), within the kernel truncation at the surface
    # and walls (below theory) and the damping left without viscosity (above it)
    viscous = viscous_wave_damping(artificial_viscosity_nu(0.02, sim.h, sim.c0),
                                   math.pi / 1.0) / omega
    print(f"fill {fill:.2f}: zeta = {zeta:.5f}, viscous theory {viscous:.5f}")
    assert 0.8 * viscous < zeta < 1.3 * viscous, (zeta, viscous)


def _viscous_damping(dx: float):
    """Damping ratio of the first mode (fill 50 %, 6 s) with alpha = 0 and 0.04, and the
    damping 2 nu k^2 / omega that alpha = 0.04 adds in theory."""
    zetas = {}
    for alpha in (0.0, 0.04):
        sim = run_builtin("sloshing_rect", [
            f"numerics.dx={dx}", "geometry.fill=0.5", "run.t_end=6.0",
            "run.output_interval=0.01", f"numerics.alpha={alpha}"])
        ds = sim.dataset()
        omega, zetas[alpha] = oscillation_frequency(ds.time.values, ds.centre_of_mass_x.values)
    theory = viscous_wave_damping(artificial_viscosity_nu(0.04, sim.h, sim.c0),
                                  math.pi / 1.0) / omega
    return zetas, theory


def test_artificial_viscosity_damps_the_mode_at_the_viscous_rate_coarse():
    """The test below at dx = L/20 (a quarter of its cost): the damping alpha = 0.04 adds is
    2 nu k^2 / omega, less the part lost where the viscous sum is truncated within a kernel
    support of the free surface and the walls. That truncated band is 3h / L = 0.18 of the
    tank here, twice the L/40 run's, and the deficit follows it: -4 % at L/80, -8 % at L/40,
    -14 % at L/20 (measured). So the added damping lies below theory by less than 20 %
    (the deficit's first-order growth with h leaves it below 16 %, plus the fit's spread).
    Without viscosity the mode keeps most of its energy: under a quarter of what alpha = 0.04
    adds (measured 4 %)."""
    zetas, theory = _viscous_damping(0.05)
    added = zetas[0.04] - zetas[0.0]
    assert -0.20 < added / theory - 1.0 < 0.0, (zetas, theory)
    assert 0.0 <= zetas[0.0] < 0.25 * theory, (zetas, theory)


@pytest.mark.slow
def test_artificial_viscosity_damps_the_mode_at_the_viscous_rate():
    """The artificial viscosity acts as nu = alpha h c0 / 8, and a gravity wave in a fluid
    of viscosity nu loses amplitude at 2 nu k^2 (free-slip walls and bottom, any depth):
    the damping the viscosity adds to the first mode (alpha = 0.04 against alpha = 0, fill
    50 %, dx = L/40) is compared with 2 nu k^2 / omega. Tolerance 15 %: the viscous sum is
    truncated within a kernel support (3 h = 0.09 m) of the free surface and the walls,
    where the mode's shear is largest, so the measured damping is below theory (-8 % here,
    -4 % at dx = L/80, measured); the fit runs over 6 s (5 periods, a third of the
    amplitude lost). Without the artificial viscosity the mode must keep most of its
    energy: the damping left (time integration and density re-initialisation) stays under
    a quarter of what alpha = 0.04 adds."""
    zetas, theory = _viscous_damping(0.025)
    added = zetas[0.04] - zetas[0.0]
    assert abs(added / theory - 1.0) < 0.15, (zetas, theory)
    assert 0.0 <= zetas[0.0] < 0.25 * theory, (zetas, theory)


U_TANK_TABLE_II = {0.25: 0.87, 0.5: 1.12, 0.75: 1.26}


@pytest.mark.parametrize("bilge_radius, reference", [
    (0.0, linear_frequency(16.0, 0.5 * 8.5, 9.81)), (2.0, U_TANK_TABLE_II[0.5])])
def test_u_tank_at_coarse_resolution(bilge_radius, reference):
    """The U-tank builder at dx = 0.4 m (40 particles across, 11 over the depth), fill 50 %,
    three periods: with square bilges it is a rectangular tank, whose first mode is the
    closed form (1.147 rad/s; tolerance 3 % as for the rectangular case above); with the 2-m
    bilges, Table II (measured 1.1494 and 1.1487 rad/s: at this fill the bilges hardly move
    the frequency, and Table II's 1.12 lies 2.5 % below; tolerance 5 %, as in the slow
    test)."""
    sim = run_builtin("sloshing_u", ["numerics.dx=0.4", "geometry.fill=0.5", "run.t_end=16.0",
                                     f"geometry.bilge_radius={bilge_radius}"])
    ds = sim.dataset()
    omega, _ = oscillation_frequency(ds.time.values, ds.centre_of_mass_x.values)
    tolerance = 0.03 if bilge_radius == 0.0 else 0.05
    assert abs(omega / reference - 1.0) < tolerance, (omega, reference)


@pytest.mark.slow
@pytest.mark.parametrize("fill", sorted(U_TANK_TABLE_II))
def test_u_tank_frequency_beside_table_ii(fill):
    """U-shaped cabin (B = 16 m, D = 8.5 m, bilge radius 2 m): compare with the paper's
    Table II (finite-element values). Tolerance 5 %: the paper does not state its bilge
    radius, which moves the frequency by a few per cent at low fill."""
    sim = run_builtin("sloshing_u", ["numerics.dx=0.2", f"geometry.fill={fill}",
                                     "run.t_end=40.0"])
    ds = sim.dataset()
    omega, _ = oscillation_frequency(ds.time.values, ds.centre_of_mass_x.values)
    print(f"U-tank fill {fill:.2f}: omega = {omega:.4f} rad/s, Table II "
          f"{U_TANK_TABLE_II[fill]:.2f} rad/s")
    assert abs(omega / U_TANK_TABLE_II[fill] - 1.0) < 0.05
