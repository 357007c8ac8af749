"""Rigid bodies under fluid forces (Cao et al. 2019, Eqs. 9-10): kinematics and hydrostatics."""

import numpy as np
import pytest
from physics_helpers import run_builtin

from sph.bodies.rigid import DofConfig, RigidBody


def test_free_fall_is_exact_and_masks_fix_motions():
    """With zero fluid force the body falls as z = z0 - g t^2 / 2 (the Verlet scheme is exact
    for a constant acceleration), and masked DOFs never move."""
    g = 9.81
    body = RigidBody(2.0, 0.5, (1.0, 3.0), DofConfig(sway=False, heave=True, roll=False), g)
    dt, t = 1e-3, 0.0
    for step in range(1000):
        body.set_forces(5.0, 0.0, 1.0)  # sway and roll loads on fixed DOFs
        body.update(dt, euler=step % 40 == 0)
        t += dt
    assert body.q[1] == pytest.approx(3.0 - 0.5 * g * t * t, rel=1e-12)
    assert body.v[1] == pytest.approx(-g * t, rel=1e-12)
    assert body.q[0] == 1.0 and body.q[2] == 0.0
    m = body.motions()
    assert m["heave"] == pytest.approx(-0.5 * g * t * t) and m["sway"] == 0.0


def _lagged_liquid(added, liquid=6.0, mass=1.0, steps=40):
    """Accelerations of a body of ``mass`` pushed by a constant load and carrying a liquid of
    mass ``liquid`` that answers the body's acceleration one evaluation late (the explicit
    coupling), with the stabilisation's ``added`` mass in every motion."""
    body = RigidBody(mass, mass, (0.0, 0.0), DofConfig(), 0.0,
                     added_mass=(added, added, added))
    out = []
    for _ in range(steps):
        react = -liquid * body.a  # the liquid's reaction to the previous acceleration
        body.set_forces(*(7.0 + react))
        out.append(body.a.copy())
    return np.array(out)


def test_added_mass_stabilises_a_light_body_carrying_heavy_liquid():
    """A body of mass 1 holding a liquid of mass 6 under a load of 7: the coupled answer is
    an acceleration 7 / (1 + 6) = 1 in every motion. Coupled explicitly the liquid's lagged
    reaction multiplies each step's error by -6 (the added-mass instability: a 75 % loaded
    ship was thrown 3 m up in half a second); with an added mass of half, once or twice the
    liquid's the stabilised equation converges geometrically to the coupled answer (the
    error shrinks by sqrt(M_a / (M + M_a)) per step or faster), and the acceleration of a
    steady load is the plain one whatever the added mass (the term cancels when the
    acceleration stops changing)."""
    plain = _lagged_liquid(0.0)
    assert np.abs(plain[-1]).max() > 1e20
    for added in (3.0, 6.0, 12.0):
        np.testing.assert_allclose(_lagged_liquid(added, steps=800)[-1], 1.0, rtol=1e-9)
    # a steady load without a liquid: the plain acceleration F / M whatever the added mass
    body = RigidBody(2.0, 0.5, (0.0, 0.0), DofConfig(), 9.81, added_mass=(5.0, 5.0, 3.0))
    for _ in range(2000):
        body.set_forces(4.0, 30.0, 1.0)
    np.testing.assert_allclose(body.a, [2.0, 30.0 / 2.0 - 9.81, 2.0], rtol=1e-12)


def _cargo_mode(first_order: bool, wdt: float, steps=6000, dt=1.6e-3, mass=1.0, cargo=6.0,
                lagged=1.0):
    """Heave of a body of ``mass`` carrying ``cargo`` on a spring (the cargo's compression
    mode against the hull, of frequency ``wdt / dt``), plus a ``lagged`` added mass that
    answers the body's previous acceleration (the walls' pressure extrapolation), the
    stabilisation's added mass the cargo's; both advanced with the engine's Verlet scheme
    (an Euler step every 40). ``first_order``: the previous acceleration alone on the right
    (Soding's form). Returns the mode's largest amplitude over the first and the last 500
    steps."""
    k = (wdt / dt) ** 2 / (1.0 / mass + 1.0 / cargo)
    heave = DofConfig(sway=False, roll=False)
    body = RigidBody(mass, mass, (0.0, 0.0), heave, 0.0, added_mass=(0.0, cargo, 0.0))
    liquid = RigidBody(cargo, cargo, (0.0, 0.01), heave, 0.0)  # displaced by 1 cm: excited
    amp = []
    for n in range(steps):
        if first_order:
            body.a_prev[:] = body.a
        stretch = liquid.q[1] - body.q[1]
        body.set_forces(0.0, k * stretch - lagged * body.a[1], 0.0)
        liquid.set_forces(0.0, -k * stretch, 0.0)
        euler = n % 40 == 0
        liquid.update(dt, euler)
        body.update(dt, euler)
        amp.append(abs(liquid.q[1] - body.q[1]))
    return max(amp[:500]), max(amp[-500:])


@pytest.mark.parametrize("wdt", [0.02, 0.1])
def test_stabilisation_does_not_feed_the_cargo_modes(wdt):
    """The stabilisation's right-hand side with the previous acceleration alone (Soding's
    form) reads, to first order in the step, M dV/dt = f + M_a omega^2 dt V: a negative
    damping of every mode that moves the body, which in the 75 and 50 % loaded ships fed the
    cargo's compression modes (10-50 Hz) until the ship rose out of its draught
    (docs/ship.md). Model: a body of mass 1, its cargo of mass 6 on a spring, a lagged added
    mass of 1 (heavier than the body: the plain coupling is unstable), the mode at omega dt
    = 0.02 and 0.1 (in the ships, 0.15 at 15 Hz). Soding's form lets the mode grow (by 3
    and 1e12 over 6000 steps); the extrapolated acceleration the body uses damps it (to
    0.79 and 0.003 of its start): the leapfrog's own damping is all that acts on it."""
    start, end = _cargo_mode(False, wdt)
    assert end < start
    start1, end1 = _cargo_mode(True, wdt)
    assert end1 > 2.0 * start1


def test_body_state_round_trips_and_takes_an_older_state():
    """The state holds the acceleration before the last (the stabilisation's
    extrapolation); a state written before it existed (no ``a_prev``) restarts with the last
    acceleration in its place."""
    body = RigidBody(1.0, 1.0, (0.0, 0.0), DofConfig(), 9.81, added_mass=(2.0, 2.0, 2.0))
    for load in (1.0, 3.0):
        body.set_forces(load, load, load)
    state = body.get_state()
    assert not np.allclose(state["a"], state["a_prev"])
    again = RigidBody(1.0, 1.0, (0.0, 0.0), DofConfig(), 9.81, added_mass=(2.0, 2.0, 2.0))
    again.set_state(state)
    np.testing.assert_array_equal(again.a_prev, body.a_prev)
    older = {k: v for k, v in state.items() if k != "a_prev"}
    again.set_state(older)
    np.testing.assert_array_equal(again.a_prev, state["a"])


def test_roll_sign_is_positive_towards_plus_x():
    """One step from rest under constant loads: sway = fx / M dt^2 / 2, roll angle =
    -moment / I dt^2 / 2 (degrees, positive towards +x), velocities a dt; mass and inertia
    differ so that a swap of the two is seen."""
    mass, inertia, fx, moment, dt = 2.0, 5.0, 4.0, -3.0, 0.1
    body = RigidBody(mass, inertia, (0.0, 0.0), DofConfig(), 0.0)
    body.set_forces(fx, 0.0, moment)  # clockwise moment: the top moves towards +x
    body.update(dt, euler=True)
    m = body.motions()
    assert m["roll"] > 0
    assert m["roll"] == pytest.approx(np.degrees(0.5 * dt * dt * 3.0 / inertia), rel=1e-12)
    assert m["sway"] == pytest.approx(0.5 * dt * dt * fx / mass, rel=1e-12)
    assert m["heave"] == 0.0
    assert body.v[0] == pytest.approx(dt * fx / mass, rel=1e-12)
    assert body.v[2] == pytest.approx(dt * moment / inertia, rel=1e-12)


def _resting_box(tank_length: float, t_end: float = 3.0):
    """The box below released at rest in the middle of a tank ``tank_length`` long, for
    ``t_end`` seconds."""
    return run_builtin("floating_box", [
        "numerics.dx=0.02", f"run.t_end={t_end}", "run.output_interval=0.02",
        "geometry.depth=0.5", f"geometry.tank_length={tank_length}",
        "geometry.tank_height=0.8", "geometry.box_width=0.4", "geometry.box_height=0.2",
        f"geometry.box_x={tank_length / 2}", "geometry.box_density=500",
        "geometry.box_inertia=null", "geometry.absorber.enabled=false", "probes.surface=[]"])


def _assert_at_rest_on_its_draught(sim):
    ds = sim.dataset()
    draught = 0.1
    weight = 500 * 0.4 * 0.2 * 9.81
    heave = ds["heave"].values
    assert abs(heave.mean()) < 0.02 * draught
    assert np.abs(heave).max() < 0.05 * draught
    # measured: +0.25 % at t = 0 (the pressure of the initial hydrostatic field integrated
    # over a hull surface resolved by 5 particles), -0.001 % on average over the 3 s
    assert ds["body_force_z"].values[0, 0] == pytest.approx(weight, rel=5e-3)
    assert ds["body_force_z"].values[0].mean() == pytest.approx(weight, rel=2e-3)
    assert np.abs(ds["sway"].values).max() < 1e-3 * draught
    assert np.abs(ds["roll"].values).max() < 0.05


def test_floating_box_stays_at_its_hydrostatic_draught_short_tank():
    """The hydrostatic test below in a 1.6 m tank (half the particles) over 2 s, two heave
    periods of the box (about 1 s: its mass and 2D added mass against the waterplane's
    stiffness): equilibrium does not depend on the tank's length, and the walls stay 0.6 m
    (six draughts) from the box's sides. Same tolerances (measured: mean heave +0.50 % and
    largest 0.87 % of the draught, force +0.25 % at t = 0 and -0.002 % on average; over 3 s
    +0.48 %, 0.87 %, +0.25 % and -0.004 %)."""
    _assert_at_rest_on_its_draught(_resting_box(1.6, t_end=2.0))


@pytest.mark.slow
def test_floating_box_stays_at_its_hydrostatic_draught():
    """A 0.4 m x 0.2 m box of density 500 kg/m3 (draught 0.1 m), all three DOF free, released
    at its hydrostatic position in still water; dx = 0.02 m (5 particles over the draught).
    The fluid force balances the weight (to 0.5 % at t = 0, 0.2 % on average), the box stays
    within 2 % of the draught on average and 5 % at any time, and sway and roll stay at zero
    by symmetry."""
    _assert_at_rest_on_its_draught(_resting_box(3.0))


def test_strip_segments_sum_their_forces_by_length():
    """Strip theory (Cao et al. 2019, Eq. 9): the body's force per unit length is the sum of
    the segments' forces weighted by the fraction of the length each stands for; every
    segment's walls move with the body, shifted to its own tank."""
    mass, inertia = 3.0e5, 8.0e6
    body = RigidBody(mass, inertia, (10.0, 2.0), DofConfig(), 9.81,
                     segments=[(3, 2.0 / 3.0, 0.0), (4, 1.0 / 3.0, 70.0)])
    fx = np.array([0.0, 0.0, 0.0, 3.0e5, 6.0e5])  # indexed by wall group
    fz = np.array([0.0, 0.0, 0.0, 2.0e6, 5.0e6])
    mom = np.array([0.0, 0.0, 0.0, -1.0e6, 2.0e6])
    body.collect_forces(fx, fz, mom)
    np.testing.assert_allclose(body.force, [4.0e5, 3.0e6, 0.0], rtol=1e-12, atol=1e-6)
    np.testing.assert_allclose(body.segment_force, [[3.0e5, 2.0e6, -1.0e6],
                                                    [6.0e5, 5.0e6, 2.0e6]], rtol=1e-12)
    np.testing.assert_allclose(body.a, [4.0e5 / mass, 3.0e6 / mass - 9.81, 0.0], atol=1e-12)
    k0, k1 = body.segment_motion(0).kinematics(), body.segment_motion(1).kinematics()
    assert k1[0] == k0[0] + 70.0 and np.array_equal(k1[1:], k0[1:])
    with pytest.raises(ValueError, match="sum to 1"):
        RigidBody(mass, inertia, (0.0, 0.0), DofConfig(), 9.81,
                  segments=[(3, 0.5, 0.0), (4, 0.4, 70.0)])
