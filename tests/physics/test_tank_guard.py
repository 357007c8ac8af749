"""The tank's guard (:func:`sph.engine.walls.keep_in_tank`): a fluid particle found through
a fixed wall is put back at its mirror image with the velocity that carried it in removed;
a run whose walls hold its fluid, an impact on a wall included, is unchanged to the bit."""

import math

import numpy as np
import pytest

from sph.cases import builtin
from sph.driver import Simulation
from sph.engine.particles import FLUID, GHOST, WALL
from sph.engine.walls import keep_in_tank, tank_guard

DX = 0.1
LAYERS = 3
#: a tank 0 < x < 2, floor at z = 0, end walls up to 1.5 m
GUARD = tank_guard(0.0, 2.0, 0.0, 1.5, DX, LAYERS)


def _guarded(x, z, vx, vz, kind=None, guard=GUARD):
    x, z = np.array(x, dtype=float), np.array(z, dtype=float)
    vx, vz = np.array(vx, dtype=float), np.array(vz, dtype=float)
    vxo, vzo = vx.copy(), vz.copy()
    kind = np.full(x.shape, FLUID, dtype=np.int32) if kind is None else np.asarray(kind)
    n = keep_in_tank(x, z, vx, vz, vxo, vzo, kind, guard)
    assert np.array_equal(vx, vxo) and np.array_equal(vz, vzo)  # both leapfrog levels
    return n, x, z, vx, vz


def test_a_particle_through_the_floor_or_an_end_wall_is_mirrored_back():
    # below the floor by 0.07 m (beyond half a spacing, within the wall's 0.3 m), moving
    # down and along; beyond the left wall; beyond the right wall, moving out
    n, x, z, vx, vz = _guarded([1.0, -0.08, 2.06], [-0.07, 0.5, 0.8], [0.4, -2.0, 1.5],
                               [-3.0, 0.2, -0.1])
    assert n == 3
    np.testing.assert_allclose(x, [1.0, 0.08, 1.94], atol=1e-15)
    np.testing.assert_allclose(z, [0.07, 0.5, 0.8], atol=1e-15)
    # the velocity into the wall is removed, the rest kept
    np.testing.assert_array_equal(vx, [0.4, 0.0, 0.0])
    np.testing.assert_array_equal(vz, [0.0, 0.2, -0.1])
    # moving away from the wall already: the velocity is kept
    n, _, z, _, vz = _guarded([1.0], [-0.07], [0.0], [2.0])
    assert n == 1 and z[0] == pytest.approx(0.07) and vz[0] == 2.0
    # a corner: through the floor and an end wall at once, put back through both
    n, x, z, vx, vz = _guarded([2.13], [-0.06], [1.0], [-1.0])
    assert n == 2
    assert x[0] == pytest.approx(1.87) and z[0] == pytest.approx(0.06)
    assert vx[0] == 0.0 and vz[0] == 0.0


@pytest.mark.parametrize("where", ["in contact", "beyond the wall", "above the end wall",
                                   "a wall particle"])
def test_particles_that_are_not_through_a_wall_are_left_alone(where):
    x, z, kind = {
        # within half a spacing of the surface: a particle in contact with the wall
        "in contact": ([1.0, -0.04, 2.049], [-0.049, 0.5, 0.5], None),
        # beyond the wall's thickness: it has left the domain (removed and counted)
        "beyond the wall": ([1.0, -0.35], [-0.31, 0.5], None),
        # over the end wall's top: not through it
        "above the end wall": ([-0.2, 2.2], [1.6, 1.7], None),
        "a wall particle": ([1.0], [-0.15], [WALL]),
    }[where]
    before = (np.array(x, dtype=float), np.array(z, dtype=float))
    n, x, z, vx, vz = _guarded(x, z, np.full(len(x), -1.0), np.full(len(x), -1.0), kind)
    assert n == 0
    assert np.array_equal(x, before[0]) and np.array_equal(z, before[1])
    assert np.all(vx == -1.0) and np.all(vz == -1.0)


def test_an_open_end_has_no_wall():
    guard = tank_guard(-math.inf, 2.0, 0.0, 1.5, DX, LAYERS)  # a wavemaker at x = 0
    n, x, z, _, _ = _guarded([-0.08, -0.5], [0.5, -0.07], [-1.0, 0.0], [0.0, -1.0],
                             guard=guard)
    assert n == 1  # the floor still holds
    assert x[0] == -0.08 and z[1] == pytest.approx(0.07)


SMALL = ["numerics.dx=0.1", "geometry.tank_length=1.0", "geometry.depth=0.5",
         "geometry.tank_height=0.8", "run.t_end=0.1", "run.output_interval=0.01",
         "run.max_lost_fraction=0.1"]


def _driven_into_the_floor(guard: bool) -> tuple[Simulation, int]:
    """A still tank in which one bottom particle is found 0.07 m into the floor, moving
    down at 3 m/s: where the refinement's level changes leave one (the walls do not push
    a particle below rho0), here placed by hand."""
    sim = Simulation(builtin("still_water", SMALL))
    if not guard:
        sim.setup.tank_guard = None
    sim.evaluate()
    p = sim.parts
    fluid = np.nonzero(p.kind == FLUID)[0]
    i = fluid[np.argmin(p.z[fluid] + 1e-3 * np.abs(p.x[fluid] - 0.5))]
    pid = int(p.pid[i])
    p.z[i] = -0.07
    p.vz[i] = p.vz_old[i] = -3.0
    p.rho[i] = p.rho_old[i] = 995.0  # below rho0: the walls do not push it
    sim.evaluate()
    sim.run()
    return sim, pid


def test_a_particle_driven_into_the_floor_is_put_back_and_stays_in_the_fluid():
    sim, pid = _driven_into_the_floor(guard=True)
    p = sim.parts
    i = np.nonzero(p.pid == pid)[0]
    assert sim.n_lost == 0 and len(i) == 1
    assert sim.n_guarded >= 1 and sim.dataset().attrs["guarded_particles"] == sim.n_guarded
    assert p.z[i[0]] > 0.0  # on the fluid's side of the floor after 0.1 s
    # without the guard the walls do not hold it: 0.1 s later it is below the floor or gone
    sim, pid = _driven_into_the_floor(guard=False)
    p = sim.parts
    i = np.nonzero(p.pid == pid)[0]
    assert sim.n_lost == 1 or p.z[i[0]] < 0.0


def test_ghosts_are_fluid_to_the_guard():
    """Ghosts of variable resolution are fluid particles (``body`` = ``GHOST``): the guard,
    which reads ``kind`` alone, keeps them too (one sinking below the floor as a ghost
    feels no wall)."""
    sim = Simulation(builtin("still_water", SMALL + [
        "numerics.refinement=[{x: [0.3, 0.7], z: [-0.5, 1.0], level: 1}]"]))
    p = sim.parts
    ghosts = p.body == GHOST
    assert ghosts.any() and np.all(p.kind[ghosts] == FLUID)


def test_an_impact_on_the_walls_is_unchanged_to_the_bit():
    """A coarse dam break, its surge thrown up the far wall and falling back: the walls
    hold the fluid, the guard never acts and the run is the same with it or without."""
    over = ["numerics.dx=0.05", "geometry.tank_length=1.6", "geometry.tank_height=1.2",
            "geometry.column_width=0.4", "geometry.column_height=0.8", "run.t_end=0.9",
            "run.output_interval=0.05", "probes.pressure=[{name: wall, x: 1.6, z: 0.08}]"]
    runs = []
    for guard in (True, False):
        sim = Simulation(builtin("dam_break", over))
        if not guard:
            sim.setup.tank_guard = None
        runs.append(sim.run())
    assert runs[0].n_guarded == 0
    assert np.array_equal(runs[0].parts.f, runs[1].parts.f)
    # the surge did reach the far wall and climb it
    assert runs[0].dataset()["front_position"].max() >= 1.6 - 0.05


def test_the_count_of_guarded_particles_goes_through_a_checkpoint():
    """The count is part of the state (``STATE_SCALARS``): a stepper set from a state of
    a run that guarded a particle carries it on; a state written before the guard existed
    (no ``n_guarded`` entry) stands for none guarded."""
    sim, _ = _driven_into_the_floor(guard=True)
    assert sim.n_guarded >= 1
    state = sim.get_state()
    other, _ = _driven_into_the_floor(guard=False)
    assert other.n_guarded == 0
    other.set_state(state)
    assert other.n_guarded == sim.n_guarded
    del state["n_guarded"]
    other.set_state(state)
    assert other.n_guarded == 0
