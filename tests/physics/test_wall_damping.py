"""``numerics.wall_damping``: the artificial viscosity on a fluid particle's approach to a
wall along the wall's normal, the flow along the wall left free.

Walls are free-slip and push by their extrapolated pressure, so a lone particle striking a
wall bounces elastically, and off a wall that moves towards it, faster than it came: in the
refined Table I case 5 single particles in the damaged cabin's upper corner, between the
rolling hull's plating and its deck, were pumped up to 50 m/s. A drop strikes a wall
inelastically. The damping takes the fluid-fluid viscosity's form with the relative
velocity's component along the normal, when the particle closes in: a particle over a flat
floor falling onto it is slowed, one rising from it or sliding along it is not.
"""

import numpy as np
import pytest
from physics_helpers import sort_by_cells, verlet_lists

from sph.engine.fluid import interact, interact_reference, pair_work
from sph.engine.kernels import kernel_params
from sph.engine.neighbours import CellGrid
from sph.engine.opening import no_opening
from sph.engine.particles import FLUID, WALL
from sph.engine.surface import CLAMP
from sph.engine.walls import fixed_kinematics, listed_with, wall_lists, wall_normals

DX = 0.1
C0 = 30.0


@pytest.fixture(scope="module")
def floor():
    """A flat floor of three wall layers (top layer at z = -DX / 2) and one fluid particle
    a spacing above its top layer, sorted by cells; the walls at rest, at rho0, unloaded."""
    xs = np.arange(-10, 11) * DX
    wx, wz = np.meshgrid(xs, -(np.arange(3) + 0.5) * DX)
    x = np.concatenate([wx.ravel(), [0.013]])
    z = np.concatenate([wz.ravel(), [0.5 * DX]])
    kind = np.where(np.arange(len(x)) < wx.size, WALL, FLUID).astype(np.int32)
    kp = kernel_params("gaussian", 1.23 * DX)
    grid = CellGrid(-1.2, 1.2, -0.5, 0.8, 3.0 * kp[1])
    x, z, kind = sort_by_cells(grid, x, z, kind)
    n = len(x)
    lists = verlet_lists(x, z, kind, grid)
    return dict(x=x, z=z, kind=kind, kp=kp, grid=grid, lists=lists, n=n,
                body=np.zeros(n, np.int32), comp=np.zeros(n, np.int32),
                rho=np.full(n, 1000.0), p=np.zeros(n), m=np.full(n, 1000.0 * DX * DX),
                fluid=int(np.nonzero(kind == FLUID)[0][0]))


def _normals(f):
    nx, nz = np.zeros(f["n"]), np.zeros(f["n"])
    near = np.zeros(f["n"], dtype=np.bool_)
    listed_with(f["kind"], f["body"], *f["lists"], near, None)
    assert near[f["fluid"]] and near.sum() == 1  # the fluid particle, which has walls
    wall_start = np.zeros(f["n"] + 1, dtype=np.uint64)
    walls = wall_lists(f["kind"], *f["lists"], near, wall_start, np.zeros(0, np.uint32))
    # the walls of the fluid particle's inner list, in its order
    start, inner, inner_end = f["lists"]
    i = f["fluid"]
    own = inner[start[i]:inner_end[i]]
    np.testing.assert_array_equal(walls[wall_start[i]:wall_start[i + 1]],
                                  own[f["kind"][own] == WALL])
    assert wall_start[-1] == wall_start[i + 1] - wall_start[i] > 0
    wall_normals(f["x"], f["z"], f["m"], f["rho"], f["kind"], f["body"], f["comp"], None,
                 f["kp"], no_opening(), fixed_kinematics(1), wall_start, walls, near, nx, nz)
    return nx, nz


def _accel(f, velocity, damping, reference=False):
    """Acceleration of the fluid particle moving at ``velocity`` over the resting floor."""
    n = f["n"]
    vx, vz = np.zeros(n), np.zeros(n)
    i = f["fluid"]
    vx[i], vz[i] = velocity
    wn = _normals(f) if damping else (None, None)
    out = [np.zeros(n) for _ in range(5)]
    args = (f["x"], f["z"], vx, vz, f["rho"], f["p"], f["m"], f["kind"], f["body"], f["comp"],
            np.ones(n), f["grid"].cell_of, f["grid"].cell_start, f["grid"].ncx, f["kp"],
            2.0 * 0.02 * f["kp"][1] * C0, 0.0, 0.0, 0.0, 0.0, f["x"], f["x"], *out[:3],
            no_opening(), fixed_kinematics(1), np.zeros(3), *out[3:])
    if reference:
        interact_reference(*args, CLAMP, None, None, *wn)
    else:
        interact(*args, pair_work(n), *f["lists"], False, CLAMP, None, None, *wn)
    return np.array([out[0][i], out[1][i]])


def test_the_normal_points_at_the_floor(floor):
    nx, nz = _normals(floor)
    i = floor["fluid"]
    assert nx[i] == pytest.approx(0.0, abs=0.05) and nz[i] < -0.99
    assert np.all(nx[floor["kind"] == WALL] == 0.0)


def test_only_the_approach_is_damped(floor):
    plain = _accel(floor, (0.0, -2.0), False)
    damped = _accel(floor, (0.0, -2.0), True)
    # falling onto the floor: slowed, by the viscosity's order a c0 v / h
    assert damped[1] - plain[1] > 0.05 * 0.02 * C0 * 2.0 / DX
    # rising from it: not at all
    np.testing.assert_array_equal(_accel(floor, (0.0, 2.0), True),
                                  _accel(floor, (0.0, 2.0), False))
    # sliding along it: the lattice's normal leans by about 1e-4 off the particle's row
    np.testing.assert_allclose(_accel(floor, (2.0, 0.0), True), _accel(floor, (2.0, 0.0), False),
                               rtol=0, atol=1e-3 * (damped[1] - plain[1]))


def test_list_loop_and_general_loop_agree(floor):
    for velocity in ((0.7, -2.0), (-1.5, -0.3)):
        got = _accel(floor, velocity, True)
        want = _accel(floor, velocity, True, reference=True)
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12 * np.abs(want).max())


@pytest.mark.slow
def test_free_sloshing_is_unchanged():
    """Free sloshing in the U-shaped cabin at the refined cabins' spacing (0.2 m) with the
    ship's numerics: the flow along the walls is left free, so the damping changes neither
    the first sloshing frequency nor its decay. Measured 2026-11-28 at the fills of Table
    II: frequency 0.8764 / 1.1468 / 1.2789 rad/s without and 0.8766 / 1.1468 / 1.2789 with
    it, damping ratio 0.0069 / 0.0047 / 0.0052 both (the frequencies within 0.7-2.4 % of
    Table II's 0.87 / 1.12 / 1.26). The tolerances are far above those differences and far
    below what a viscosity on the whole relative velocity at the walls would add."""
    from sph.cases import builtin
    from sph.driver import Simulation
    from sph.study.validation import frequency, ship_numerics

    over = {k: v for k, v in ship_numerics().items() if not k.startswith("geometry.")}
    over.update({"numerics.dx": 0.2, "numerics.threads": 1, "geometry.fill": 0.5,
                 "numerics.pressure_floor": -100000.0, "run.t_end": 30.0,
                 "run.output_interval": 0.05})
    out = {}
    for damping in (False, True):
        cfg = builtin("sloshing_u", list({**over, "numerics.wall_damping": damping}.items()))
        ds = Simulation(cfg).run().dataset()
        out[damping] = frequency(ds["time"].values, ds["centre_of_mass_x"].values)
    (w0, z0), (w1, z1) = out[False], out[True]
    assert w1 == pytest.approx(w0, rel=0.005)
    assert z1 == pytest.approx(z0, rel=0.15)
    assert 0.0 < z0 < 0.02  # a free decay, lightly damped
