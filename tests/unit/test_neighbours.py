"""Tests of the cell-linked neighbour search and of the particle permutation."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from sph.engine.neighbours import CellGrid, moved_or_outside, neighbour_count
from sph.engine.particles import FLOAT_FIELDS, INT_FIELDS, WALL, Particles

# (xmin, xmax, zmin, zmax, cell): a binary-exact grid and two with inexact decimals
GRIDS = [
    (0.0, 1.0, 0.0, 0.75, 0.125),
    (-0.3, 1.1, 0.2, 0.9, 0.07),
    (2.0, 5.3, -1.0, 0.45, 0.123),
]
SEEDS = [0, 1, 2, 3]


def _uniform(rng, box, n):
    xmin, xmax, zmin, zmax, _ = box
    return rng.uniform(xmin, xmax, n), rng.uniform(zmin, zmax, n)


def _clustered(rng, box, n):
    """A few tight Gaussian clusters (many particles share cells) plus a sparse background."""
    xmin, xmax, zmin, zmax, cell = box
    n_bg = n // 5
    x = [rng.uniform(xmin, xmax, n_bg)]
    z = [rng.uniform(zmin, zmax, n_bg)]
    n_left = n - n_bg
    for k in range(4):
        m = n_left // 4 if k < 3 else n_left - 3 * (n_left // 4)
        cx, cz = rng.uniform(xmin, xmax), rng.uniform(zmin, zmax)
        # clipped a little inside: a point exactly on the bound is a case of its own
        # (see test_points_exactly_on_domain_bounds_are_inside)
        mx, mz = 1e-9 * (xmax - xmin), 1e-9 * (zmax - zmin)
        x.append(np.clip(rng.normal(cx, 0.7 * cell, m), xmin + mx, xmax - mx))
        z.append(np.clip(rng.normal(cz, 0.7 * cell, m), zmin + mz, zmax - mz))
    return np.concatenate(x), np.concatenate(z)


def _on_cell_boundaries(rng, box, n):
    """Particles whose x, z or both sit exactly on interior cell boundaries."""
    xmin, xmax, zmin, zmax, cell = box
    g = CellGrid(xmin, xmax, zmin, zmax, cell)
    # interior cell faces x0 + k cell strictly inside the box
    fx = g.x0 + cell * np.arange(2, g.ncx - 1)
    fz = g.z0 + cell * np.arange(2, g.ncz - 1)
    fx = fx[(fx > xmin) & (fx < xmax)]
    fz = fz[(fz > zmin) & (fz < zmax)]
    x, z = _uniform(rng, box, n)
    pick = rng.integers(0, 3, n)  # 0: x on a face, 1: z on a face, 2: both (a corner)
    on_x = pick != 1
    on_z = pick != 0
    x[on_x] = rng.choice(fx, on_x.sum())
    z[on_z] = rng.choice(fz, on_z.sum())
    return x, z


def _brute_force_counts(x, z, r2max):
    """O(N^2) count of j != i with |r_i - r_j|^2 < r2max, same arithmetic as the engine."""
    dx = x[:, None] - x[None, :]
    dz = z[:, None] - z[None, :]
    close = dx * dx + dz * dz < r2max
    np.fill_diagonal(close, False)
    return close.sum(axis=1)


def _check_sorted_grid(grid, n):
    order = grid.order
    assert order.shape == (n,)
    np.testing.assert_array_equal(np.sort(order), np.arange(n))  # a permutation
    cs = grid.cell_start
    assert cs.shape == (grid.ncx * grid.ncz + 1,)
    assert cs[0] == 0 and cs[-1] == n
    assert np.all(np.diff(cs) >= 0)
    # cell_of is sorted and consistent with cell_start
    assert np.all(np.diff(grid.cell_of) >= 0)
    k = np.arange(n)
    assert np.all(cs[grid.cell_of] <= k) and np.all(k < cs[grid.cell_of + 1])


def _check_counts(box, x, z, r2max):
    grid = CellGrid(*box)
    n = x.shape[0]
    n_out = grid.sort(x, z)
    assert n_out == 0
    _check_sorted_grid(grid, n)
    xs, zs = x[grid.order], z[grid.order]
    # cells agree with the positions: the sort stays stable within a cell
    expected_cell = (np.floor((zs - grid.z0) / grid.cell).astype(np.int64) * grid.ncx
                     + np.floor((xs - grid.x0) / grid.cell).astype(np.int64))
    # a particle on a cell face may round either way, never further
    assert np.all(np.abs(grid.cell_of - expected_cell) <= grid.ncx + 1)
    got = np.array([neighbour_count(xs, zs, grid.cell_of, grid.cell_start, grid.ncx, r2max, i)
                    for i in range(n)])
    want = _brute_force_counts(xs, zs, r2max)
    bad = np.flatnonzero(got != want)
    assert bad.size == 0, (f"{bad.size} particles with a wrong count, first: i = {bad[0]}, "
                           f"got {got[bad[0]]}, want {want[bad[0]]}")
    counts = np.empty_like(want)
    counts[grid.order] = want  # back to the caller's particle order
    return counts


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("box", GRIDS)
def test_counts_uniform(box, seed):
    rng = np.random.default_rng(seed)
    x, z = _uniform(rng, box, 900)
    cell = box[4]
    counts = _check_counts(box, x, z, cell * cell)
    assert counts.sum() > 0
    # a smaller search radius than the cell works as well
    _check_counts(box, x, z, (0.45 * cell) ** 2)


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("box", GRIDS)
def test_counts_clustered(box, seed):
    rng = np.random.default_rng(100 + seed)
    x, z = _clustered(rng, box, 1000)
    cell = box[4]
    counts = _check_counts(box, x, z, cell * cell)
    assert counts.max() > 50  # the clusters are really dense


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("box", GRIDS)
def test_counts_on_cell_boundaries(box, seed):
    """Particles exactly on cell faces and corners. The search radius is kept a hair below
    the cell side, so that no pair sits at a distance within rounding of the cell side (such
    a pair may be binned two cells apart; the engine's kernels vanish there anyway)."""
    rng = np.random.default_rng(200 + seed)
    x, z = _on_cell_boundaries(rng, box, 800)
    cell = box[4]
    _check_counts(box, x, z, (0.999 * cell) ** 2)
    _check_counts(box, x, z, (0.5 * cell) ** 2)


def test_counts_regular_lattice():
    """A cell-centred lattice of spacing dx with the engine's support radius 3h = 3.69 dx:
    every interior particle sees the same number of neighbours."""
    dx = 0.1
    xs = (np.arange(30) + 0.5) * dx
    zs = (np.arange(20) + 0.5) * dx
    xx, zz = np.meshgrid(xs, zs, indexing="ij")
    x, z = xx.ravel().copy(), zz.ravel().copy()
    radius = 3.0 * 1.23 * dx
    box = (0.0, 3.0, 0.0, 2.0, radius)
    counts = _check_counts(box, x, z, radius * radius)
    interior = (x > radius) & (x < 3.0 - radius) & (z > radius) & (z < 2.0 - radius)
    assert len(set(counts[interior].tolist())) == 1


def test_single_particle():
    grid = CellGrid(0.0, 1.0, 0.0, 1.0, 0.25)
    assert grid.sort(np.array([0.3]), np.array([0.6])) == 0
    _check_sorted_grid(grid, 1)
    assert neighbour_count(np.array([0.3]), np.array([0.6]), grid.cell_of, grid.cell_start,
                           grid.ncx, 0.0625, 0) == 0


def test_sort_no_particles():
    grid = CellGrid(0.0, 1.0, 0.0, 1.0, 0.25)
    assert grid.sort(np.zeros(0), np.zeros(0)) == 0
    assert grid.cell_start[-1] == 0 and grid.order.shape == (0,)


def test_grid_reused_with_changing_particle_number():
    box = GRIDS[1]
    rng = np.random.default_rng(7)
    grid = CellGrid(*box)
    for n in (50, 400, 50, 51):
        x, z = _uniform(rng, box, n)
        assert grid.sort(x, z) == 0
        _check_sorted_grid(grid, n)


# --------------------------------------------------------------------------- leaving the domain


def test_outside_particles_are_counted():
    xmin, xmax, zmin, zmax, cell = box = GRIDS[1]
    rng = np.random.default_rng(11)
    x, z = _uniform(rng, box, 300)
    bad_x = [xmin - 1e-9, xmax + 1e-9, xmin - 5 * cell, xmax + 100.0, 0.5, 0.5, -1e300, 1e300,
             xmax + 1.0]
    bad_z = [0.5, 0.5, 0.5, 0.5, zmin - 1e-9, zmax + 3 * cell, 0.5, 0.5, zmin - 1.0]
    n_bad = len(bad_x)
    xi = np.concatenate([x, bad_x])
    zi = np.concatenate([z, bad_z])
    perm = rng.permutation(xi.size)
    xi, zi = xi[perm], zi[perm]
    grid = CellGrid(*box)
    assert grid.sort(xi, zi) == n_bad
    # the outcasts are still sorted somewhere: order stays a permutation, nothing is lost
    _check_sorted_grid(grid, xi.size)
    # ...and they sit in padding cells only, never among the inside particles' cells
    cx = grid.cell_of % grid.ncx
    cz = grid.cell_of // grid.ncx
    padding = (cx == 0) | (cx == grid.ncx - 1) | (cz == 0) | (cz == grid.ncz - 1)
    assert padding.sum() == n_bad
    outside = ~((xi >= xmin) & (xi <= xmax) & (zi >= zmin) & (zi <= zmax))
    np.testing.assert_array_equal(np.sort(np.flatnonzero(outside)),
                                  np.sort(grid.order[padding]))


_NONFINITE_SCRIPT = textwrap.dedent("""
    import sys
    import numpy as np
    from sph.engine.neighbours import CellGrid

    bx, bz = float(sys.argv[1]), float(sys.argv[2])
    rng = np.random.default_rng(3)
    x = rng.uniform(0.0, 1.0, 200)
    z = rng.uniform(0.0, 1.0, 200)
    x[77], z[77] = bx, bz
    grid = CellGrid(0.0, 1.0, 0.0, 1.0, 0.25)
    n_out = grid.sort(x, z)
    assert n_out == 1, n_out
    assert np.array_equal(np.sort(grid.order), np.arange(200)), "order is no permutation"
    assert grid.cell_start[-1] == 200
    assert np.all((grid.cell_of >= 0) & (grid.cell_of < grid.ncx * grid.ncz))
    print("OK")
""")

@pytest.mark.parametrize("bx, bz", [
    pytest.param("nan", "0.5", id="x-nan"),
    pytest.param("0.5", "nan", id="z-nan"),
    pytest.param("nan", "nan", id="both-nan"),
    pytest.param("inf", "0.5", id="x-inf"),
    pytest.param("-inf", "0.5", id="x-minus-inf"),
    pytest.param("0.5", "inf", id="z-inf"),
    pytest.param("0.5", "-inf", id="z-minus-inf"),
])
def test_nonfinite_particles_are_counted(bx, bz):
    """A NaN or infinite position counts as outside, and the sort stays memory safe. Run in
    a child process: a failure here may be a crash, which must not take pytest down."""
    root = str(Path(__file__).resolve().parents[2])
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [root] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))
    proc = subprocess.run([sys.executable, "-c", _NONFINITE_SCRIPT, bx, bz], env=env,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0 and proc.stdout.strip() == "OK", (
        f"exit status {proc.returncode}: {proc.stderr[-2000:]}")


def test_inside_points_next_to_domain_bounds_are_inside():
    xmin, xmax, zmin, zmax, cell = box = GRIDS[2]
    eps = 1e-9
    x = np.array([xmin + eps, xmax - eps, 0.5 * (xmin + xmax), 0.5 * (xmin + xmax)])
    z = np.array([0.5 * (zmin + zmax), 0.5 * (zmin + zmax), zmin + eps, zmax - eps])
    assert CellGrid(*box).sort(x, z) == 0


def test_points_exactly_on_domain_bounds_are_inside():
    for xmin, xmax, zmin, zmax, cell in GRIDS:
        grid = CellGrid(xmin, xmax, zmin, zmax, cell)
        xc, zc = 0.5 * (xmin + xmax), 0.5 * (zmin + zmax)
        x = np.array([xmin, xmax, xc, xc, xmin, xmax])
        z = np.array([zc, zc, zmin, zmax, zmin, zmax])
        assert grid.sort(x, z) == 0, (xmin, xmax, zmin, zmax, cell)


# --------------------------------------------------------------------------- Particles.permute


def _random_particles(rng, n):
    parts = Particles(n)
    parts.f[:] = rng.normal(size=parts.f.shape)
    for name in ("kind", "body", "comp"):
        getattr(parts, name)[:] = rng.integers(-3, 50, n)
    return parts


@pytest.mark.parametrize("seed", SEEDS)
def test_permute_keeps_fields_with_their_particle(seed):
    rng = np.random.default_rng(seed)
    n = 257
    parts = _random_particles(rng, n)
    np.testing.assert_array_equal(parts.pid, np.arange(n))
    f0, i0 = parts.f.copy(), parts.i.copy()
    order = rng.permutation(n)
    parts.permute(order)
    assert parts.n == n
    np.testing.assert_array_equal(parts.f, f0[:, order])
    np.testing.assert_array_equal(parts.i, i0[:, order])
    np.testing.assert_array_equal(parts.pid, order)
    # the named views follow the permuted storage
    for k, name in enumerate(FLOAT_FIELDS):
        np.testing.assert_array_equal(getattr(parts, name), f0[k, order])
    for k, name in enumerate(INT_FIELDS):
        np.testing.assert_array_equal(getattr(parts, name), i0[k, order])
    # every particle keeps all its values: look each one up by its pid
    back = np.empty_like(parts.f)
    back[:, parts.pid] = parts.f
    np.testing.assert_array_equal(back, f0)
    # a second permutation composes with the first
    order2 = rng.permutation(n)
    parts.permute(order2)
    np.testing.assert_array_equal(parts.pid, order[order2])
    np.testing.assert_array_equal(parts.f, f0[:, order[order2]])
    np.testing.assert_array_equal(parts.i, i0[:, order[order2]])


def test_permute_by_cell_order_then_neighbours():
    """The engine's pattern: sort by cell, permute the particles, count on the permuted
    positions; pid maps each sorted particle back to its original index."""
    rng = np.random.default_rng(5)
    box = GRIDS[0]
    n = 600
    x, z = _clustered(rng, box, n)
    fluid = rng.uniform(size=(n - 100, 2))
    parts = Particles.from_arrays(
        np.column_stack([x[:n - 100], z[:n - 100]]), 1000.0 + fluid[:, 0], 0.01,
        np.column_stack([x[n - 100:], z[n - 100:]]), np.ones(100, dtype=np.int32),
        np.column_stack([x[n - 100:], z[n - 100:]]) + 1.0)
    kind0 = parts.kind.copy()
    rho0 = parts.rho.copy()
    grid = CellGrid(*box)
    assert grid.sort(parts.x, parts.z) == 0
    parts.permute(grid.order)
    np.testing.assert_array_equal(parts.pid, grid.order)
    np.testing.assert_array_equal(parts.x, x[parts.pid])
    np.testing.assert_array_equal(parts.z, z[parts.pid])
    np.testing.assert_array_equal(parts.kind, kind0[parts.pid])
    np.testing.assert_array_equal(parts.rho, rho0[parts.pid])
    wall = parts.kind == WALL
    np.testing.assert_array_equal(parts.bx[wall], parts.x[wall] + 1.0)
    assert np.all(parts.body[wall] == 1) and np.all(parts.body[~wall] == -1)
    r2 = box[4] ** 2
    got = [neighbour_count(parts.x, parts.z, grid.cell_of, grid.cell_start, grid.ncx, r2, i)
           for i in range(n)]
    np.testing.assert_array_equal(got, _brute_force_counts(parts.x, parts.z, r2))



def test_each_level_moves_within_its_own_skin():
    """Under variable resolution a particle's pairs are of its own level, listed at that
    level's radius: its lists hold while it has moved less than half that level's skin."""
    xs = np.zeros(2)
    zs = np.zeros(2)
    bounds = (-10.0, 10.0, -10.0, 10.0)
    hs = np.array([1.0, 0.5])
    # half skin 1 m at level 0, 0.5 m at level 1
    assert not moved_or_outside(np.array([0.8, 0.4]), zs, xs, zs, 1.0, *bounds, hs)
    assert moved_or_outside(np.array([0.8, 0.6]), zs, xs, zs, 1.0, *bounds, hs)
    assert not moved_or_outside(np.array([0.8, 0.6]), zs, xs, zs, 1.0, *bounds)
