"""Variable resolution (:mod:`sph.engine.refinement`): children make the fine lattice and
the active particles keep the mass, momentum and centre of mass; ghosts beyond their buffer
go; a ghost's fields are exact for a linear field; the levels do not interact; a case refined
everywhere is the case at half the spacing; a still tank with a level boundary settles as
the uniform one; bad boxes are refused before any compute.
"""

import logging
import math
import re

import numpy as np
import pytest
from physics_helpers import sort_by_cells

import sph.engine.refinement as refinement
from sph.cases import builtin
from sph.driver import Simulation, SimulationError
from sph.engine.fluid import interact, interact_reference, pair_work
from sph.engine.kernels import kernel_params
from sph.engine.neighbours import CellGrid, NeighbourList
from sph.engine.opening import no_opening
from sph.engine.particles import FLUID, GHOST, Particles
from sph.engine.refinement import (
    BUFFER,
    SPREAD,
    STRAY,
    _cell_span,
    _IdIndex,
    active_fluid,
    assign,
    ghost_fields,
    ghost_sources,
    ghost_weight,
    level_counts,
    levels,
    pack_boxes,
    spawn,
)
from sph.engine.shifting import shift_params
from sph.engine.surface import CLAMP
from sph.engine.walls import fixed_kinematics, listed_with, wall_forces
from sph.schema import ConfigError

DX = 0.1


class _Box:
    def __init__(self, x, z, level):
        self.x, self.z, self.level = x, z, level


def _lattice(nx, nz, dx=DX, x0=0.0, rng=None):
    """Fluid particles on a lattice of spacing ``dx``, random velocities and densities."""
    rng = rng or np.random.default_rng(1)
    x, z = np.meshgrid(x0 + (np.arange(nx) + 0.5) * dx, (np.arange(nz) + 0.5) * dx)
    n = x.size
    p = Particles(n)
    p.x[:], p.z[:] = x.ravel(), z.ravel()
    p.rho[:] = 1000.0 + rng.normal(0.0, 2.0, n)
    p.rho_old[:] = p.rho
    p.m[:] = p.rho * dx * dx
    p.vx[:], p.vz[:] = rng.normal(0.0, 1.0, n), rng.normal(0.0, 1.0, n)
    p.vx_old[:], p.vz_old[:] = p.vx, p.vz
    p.body[:] = -1
    return p


def _totals(p):
    f = p.kind == FLUID
    m = p.m[f]
    return (math.fsum(m), (m * p.vx[f]).sum(), (m * p.vz[f]).sum(), (m * p.x[f]).sum(),
            (m * p.z[f]).sum())


def _refined(p, boxes, grad_rho=(0.0, 0.0)):
    """The initial refinement, as the stepper's."""
    q, n_new = spawn(p, boxes, DX, grad_rho)
    q, _ = assign(q, boxes, DX, hysteresis=False)
    return q, n_new


def test_children_make_the_fine_lattice_and_the_active_mass_is_kept():
    """The particles within a box's buffer get four children each; the mothers inside the
    box and the children outside it become ghosts. The active particles then hold the
    mass, momentum and centre of mass of the coarse set (a quarter of a mass is exact)."""
    p = _lattice(20, 6)
    boxes = pack_boxes([_Box((0.8, 1.2), (-1.0, 2.0), 1)])
    before = _totals(p)
    q, n_new = _refined(p, boxes)
    # the buffer reaches BUFFER fine spacings beyond the box: coarse columns 0.55 .. 1.45
    pad = BUFFER * DX / 2
    mothers = np.abs(p.x - 1.0) < 0.2 + pad
    assert n_new == 4 * mothers.sum()
    a = active_fluid(q)
    after = _totals(q.take(a))
    assert after[0] == before[0]
    for u, v in zip(after[1:], before[1:], strict=True):
        assert u == pytest.approx(v, rel=1e-14, abs=1e-12 * before[0])
    lev = levels(q.hs)
    inside = (q.x > 0.8) & (q.x < 1.2)
    assert np.all(a == (inside == (lev == 1)))  # coarse active outside, fine inside
    assert np.all(q.body[~a] == GHOST)
    # the children of a lattice of spacing dx are the lattice of spacing dx / 2
    fine = lev == 1
    fx = np.sort(np.unique(np.round(q.x[fine] / (DX / 2) - 0.5, 9)))
    np.testing.assert_allclose(fx, np.arange(10, 30))
    fz = np.sort(np.unique(np.round(q.z[fine] / (DX / 2) - 0.5, 9)))
    np.testing.assert_allclose(fz, np.arange(12))
    assert len(np.unique(q.pid)) == q.n  # ids stay unique
    np.testing.assert_array_equal(level_counts(q, 1), [16 * 6, 4 * 6 * 4])
    # a mother with children gets no second set
    again, n_again = spawn(q, boxes, DX)
    assert n_again == 0 and again is q
    # a family is active at one level, whichever of its members crosses the box's edge:
    # the active mass stays the same when every particle moves about
    rng = np.random.default_rng(4)
    for _ in range(5):
        q.x[:] += rng.uniform(-0.3, 0.3, q.n) * DX
        q.z[:] += rng.uniform(-0.3, 0.3, q.n) * DX
        q, _ = assign(q, boxes, DX)
        assert math.fsum(q.m[active_fluid(q)]) == before[0]


def test_children_tile_a_stretched_cell():
    """A case that fits whole cells between a floor and a level stretches them vertically
    (a 25 % cargo at dx = 0.8 m: cells 0.708 m high). The children of a column of cells dx
    wide and 1.2 dx high are the fine lattice of dx / 2 by 0.6 dx, evenly spaced across
    their mothers' edges; at +-dx / 4 they made layers 0.2 dx apart where two mothers met
    (0.1 dx of spacing and 0.35 dx of offset from the floor in the 25 % cargo)."""
    p = _lattice(4, 5)
    stretch = 1.2
    p.z[:] *= stretch
    p.m[:] *= stretch
    q, _ = _refined(p, pack_boxes([_Box((-1.0, 1.0), (-1.0, 1.0), 1)]))
    fine = levels(q.hs) == 1
    fz = np.sort(np.unique(np.round(q.z[fine], 9)))
    np.testing.assert_allclose(fz, (np.arange(10) + 0.5) * 0.5 * stretch * DX, rtol=1e-12)
    fx = np.sort(np.unique(np.round(q.x[fine], 9)))
    np.testing.assert_allclose(fx, (np.arange(8) + 0.5) * 0.5 * DX, rtol=1e-12)
    # each child holds a quarter of its mother's mass over a quarter of her cell
    np.testing.assert_allclose(q.m[fine] / q.rho[fine], 0.25 * stretch * DX * DX, rtol=1e-12)


def test_children_keep_a_fluid_at_rest_hydrostatic():
    """A child's density is its parent's plus the hydrostatic gradient times its offset."""
    p = _lattice(4, 4)
    p.vx[:] = p.vz[:] = 0.0
    k = 1000.0 / 30.0**2
    q, _ = _refined(p, pack_boxes([_Box((-1.0, 1.0), (-1.0, 1.0), 1)]), (0.0, -9.81 * k))
    # children of one parent: the lower ones denser by rho0 g (dx / 2) / c0^2
    kids = np.nonzero(levels(q.hs) == 1)[0]
    kids = kids[np.argsort(np.hypot(q.x[kids] - p.x[0], q.z[kids] - p.z[0]))[:4]]
    dz = q.z[kids] - p.z[0]
    np.testing.assert_allclose(q.rho[kids] - p.rho[0], -9.81 * k * dz, rtol=1e-9, atol=1e-12)


def test_ghosts_beyond_the_buffer_are_removed_and_mothers_take_the_mass_back():
    p = _lattice(8, 4)
    q, _ = _refined(p, pack_boxes([_Box((0.2, 0.6), (-1.0, 2.0), 1)]))
    gone = pack_boxes([_Box((5.0, 6.0), (-1.0, 2.0), 1)])  # the box moved away
    back, n_gone = assign(q, gone, DX)
    assert n_gone == (levels(q.hs) == 1).sum()
    assert back.n == p.n and np.all(active_fluid(back))
    assert _totals(back)[0] == _totals(p)[0]


def _family_momentum(q, pid):
    """Mass and momentum (both leapfrog levels) of the active particles of the family of
    level-0 particle ``pid`` (two levels)."""
    kids = q.parent == pid
    fam = (active_fluid(q)) & ((q.pid == pid) | kids)
    m = q.m[fam]
    return np.array([math.fsum(m), *(math.fsum(m * getattr(q, c)[fam])
                                     for c in ("vx", "vz", "vx_old", "vz_old"))])


@pytest.mark.parametrize("rise", [None, 3.0])
def test_a_family_crossing_into_a_box_hands_its_momentum_to_its_children(monkeypatch, rise):
    """A coarse particle entering a box: its children, ghosts until then with velocities
    fitted from the flow around them, turn active with a common change of velocity that
    gives them its momentum exactly, at both leapfrog levels (the issue's "momentum
    conserved to round-off in every split and merge"); not before its level-0 particle is
    ``RISE`` fine spacings inside the box (3: a family half of that inside, three times the
    hysteresis, stays coarse)."""
    monkeypatch.setattr(refinement, "RISE", rise)
    p = _lattice(12, 4)
    boxes = pack_boxes([_Box((0.6, 1.2), (-1.0, 2.0), 1)])
    q, _ = _refined(p, boxes)
    # a coarse particle just left of the box, with children as ghosts in the buffer
    i = np.nonzero((levels(q.hs) == 0) & (q.x > 0.5) & (q.x < 0.6) & active_fluid(q))[0][0]
    pid = q.pid[i]
    kids = q.parent == pid
    assert kids.sum() == 4 and np.all(q.body[kids] == GHOST)
    rng = np.random.default_rng(7)
    for c in ("vx", "vz", "vx_old", "vz_old"):  # as fitted: unrelated to the mother's
        getattr(q, c)[kids] = rng.normal(0.0, 1.0, 4)
    before = _family_momentum(q, pid)
    rise = DX / 2 * (refinement.HYSTERESIS if refinement.RISE is None else refinement.RISE)
    step = 0.6 + 0.5 * rise - q.x[i]  # into the box, by half the rise: no change yet
    q.x[i] += step
    q.x[kids] += step
    q, _ = assign(q, boxes, DX)
    assert active_fluid(q)[i] and not active_fluid(q)[kids].any()
    q.x[i] += rise  # past the rise
    q.x[kids] += rise
    q, _ = assign(q, boxes, DX)
    kids = q.parent == pid
    assert np.all(active_fluid(q)[kids]) and q.body[q.pid == pid][0] == GHOST
    after = _family_momentum(q, pid)
    assert after[0] == before[0]
    np.testing.assert_allclose(after[1:], before[1:], rtol=0, atol=1e-14 * before[0])
    # the children keep their differences of velocity (their fitted shear)
    assert np.ptp(q.vx[kids]) > 0.5


def test_a_family_with_a_child_astray_merges_into_its_mother():
    """A child carried out of its box's lattice (a flooding jet parts a family) would be an
    active fine particle with no fine neighbours or walls around it: its family turns
    active at the coarse level, its mother at the family's centre of mass with its mass
    and momentum, and its children turn ghosts."""
    p = _lattice(12, 4)
    boxes = pack_boxes([_Box((0.4, 0.8), (-1.0, 2.0), 1)])
    q, _ = _refined(p, boxes)
    i = np.nonzero((levels(q.hs) == 0) & (np.abs(q.x - 0.6) < 0.05) & (q.z > 0.2))[0][0]
    pid = q.pid[i]
    kids = np.nonzero(q.parent == pid)[0]
    assert np.all(active_fluid(q)[kids]) and q.body[i] == GHOST
    before = _family_momentum(q, pid)
    # one child far out, past the box's lattice but within its mother's buffer
    x0 = q.x[kids[0]]
    q.x[kids[0]] = 0.8 + STRAY * DX / 2 + 0.03
    centre = np.array([np.sum(q.m[kids] * q.x[kids]), np.sum(q.m[kids] * q.z[kids])])
    centre /= np.sum(q.m[kids])
    q, _ = assign(q, boxes, DX)
    i = np.nonzero(q.pid == pid)[0][0]
    kids = q.parent == pid
    assert active_fluid(q)[i] and np.all(q.body[kids] == GHOST)
    np.testing.assert_allclose([q.x[i], q.z[i]], centre, rtol=0, atol=1e-15)
    after = _family_momentum(q, pid)
    assert after[0] == before[0]
    np.testing.assert_allclose(after[1:], before[1:], rtol=0, atol=1e-14 * before[0])
    # its neighbours' families are untouched: fine inside the box
    inside = (q.x > 0.45) & (q.x < 0.75) & (q.pid != pid) & (q.parent != pid)
    assert np.all(active_fluid(q)[inside] == (levels(q.hs)[inside] == 1))
    # the child back beside its siblings: the family turns fine again, momentum kept
    kids = np.nonzero(q.parent == pid)[0]
    q.x[kids[0]] = x0
    q, _ = assign(q, boxes, DX)
    assert np.all(active_fluid(q)[q.parent == pid])
    np.testing.assert_allclose(_family_momentum(q, pid)[1:], before[1:], rtol=0,
                               atol=1e-14 * before[0])


def test_a_brood_of_ghosts_spread_from_its_mother_is_made_afresh():
    """A coarse particle in the buffer, active, its four children ghosts: when one of them
    has been carried more than SPREAD of its mother's spacings from her (children of
    the sea carried into a flooded cabin), the brood is removed, the mother's mass and
    momentum untouched, and the next refinement gives her four children tiling her cell
    again; a brood within reach stays, and an active brood, which carries the family's
    mass, is never removed however far it spreads."""
    p = _lattice(12, 4)
    boxes = pack_boxes([_Box((0.6, 1.2), (-1.0, 2.0), 1)])
    q, _ = _refined(p, boxes)
    i = np.nonzero((levels(q.hs) == 0) & (q.x > 0.5) & (q.x < 0.6) & active_fluid(q))[0][0]
    pid = q.pid[i]
    kids = np.nonzero(q.parent == pid)[0]
    assert len(kids) == 4 and np.all(q.body[kids] == GHOST)
    home = np.c_[q.x[kids], q.z[kids]] - [q.x[i], q.z[i]]
    assert np.hypot(*home.T).max() < 0.36 * DX
    def carried(q):  # the active particles' mass, momentum and first moments
        a = active_fluid(q)
        return [math.fsum(q.m[a] * c) for c in (1.0, q.vx[a], q.vz[a], q.x[a], q.z[a])]

    totals = carried(q)
    # within reach: kept
    q.x[kids[0]] = q.x[i] + 0.99 * SPREAD * DX
    q, n_gone = assign(q, boxes, DX)
    assert n_gone == 0 and (q.parent == pid).sum() == 4
    # one child beyond reach: the brood goes, and nothing else
    kids = np.nonzero(q.parent == pid)[0]
    q.x[kids[0]] = q.x[np.nonzero(q.pid == pid)[0][0]] + 1.01 * SPREAD * DX
    q, n_gone = assign(q, boxes, DX)
    assert n_gone == 4 and not np.any(q.parent == pid)
    assert carried(q) == totals  # ghosts carry none of the mass and momentum
    # the next refinement: a new brood tiling her cell
    q, n_new = spawn(q, boxes, DX)
    q, _ = assign(q, boxes, DX)
    assert n_new == 4
    i = np.nonzero(q.pid == pid)[0][0]
    kids = np.nonzero(q.parent == pid)[0]
    np.testing.assert_allclose(np.c_[q.x[kids], q.z[kids]] - [q.x[i], q.z[i]], home,
                               rtol=0, atol=1e-12)
    assert active_fluid(q)[i] and np.all(q.body[kids] == GHOST)
    # an active brood (a family inside the box) spread as far: kept, active
    j = np.nonzero((levels(q.hs) == 0) & (np.abs(q.x - 0.9) < 0.05) & (q.z < 0.2))[0][0]
    brood = np.nonzero(q.parent == q.pid[j])[0]
    assert np.all(active_fluid(q)[brood])
    q.z[brood[0]] += 1.01 * SPREAD * DX
    q, n_gone = assign(q, boxes, DX)
    assert n_gone == 0 and np.all(active_fluid(q)[q.parent == q.pid[j]])


def test_ghost_fields_are_exact_for_a_linear_field():
    """The first-order fit of a ghost's density and velocity from the active particles of
    every level reproduces a linear field to round-off, next to the box and inside it,
    where the kernel is full; near the lattice's edges (a free surface) the Shepard mean
    stays within the field's range over the kernel, and is exact for a fluid at rest."""
    p = _lattice(24, 16)
    boxes = pack_boxes([_Box((0.85, 1.55), (0.5, 1.1), 1)])
    q, _ = _refined(p, boxes)
    rng = np.random.default_rng(3)
    q.x[:] += rng.normal(0.0, 0.05 * DX, q.n) * levels(q.hs)  # disorder the fine level
    kp = kernel_params("gaussian", 1.23 * DX)
    support = 3.0 * kp[1]
    grid = CellGrid(-0.5, 2.9, -0.5, 2.1, support * 1.15)
    x, z, m, hs, body = sort_by_cells(grid, q.x, q.z, q.m, q.hs, q.body)
    n = len(x)
    lin = {"rho": (1000.0, 3.0, -9.0), "vx": (0.5, -2.0, 1.0), "vz": (-0.1, 0.7, 0.3)}
    fields = {k: c[0] + c[1] * x + c[2] * z for k, c in lin.items()}
    ghost = body == GHOST
    full = ghost & (x > support) & (x < 2.4 - support) & (z > support) & (z < 1.6 - support)
    assert full.sum() > 100 and (ghost & ~full).sum() > 50
    work = {k: np.where(ghost, rng.normal(0.0, 1.0, n), v) for k, v in fields.items()}
    old = {k: np.zeros(n) for k in fields}
    kind = np.zeros(n, np.int32)
    ghost_fields(x, z, work["vx"], work["vz"], work["rho"], old["vx"], old["vz"], old["rho"],
                 m, kind, body, kind, hs,
                 *ghost_sources(x, z, kind, body, hs, grid, support * 1.15), kp,
                 no_opening(), fixed_kinematics(1), np.zeros(n, np.bool_), True, (0.0, 0.0),
                 np.ones(n))
    for k, v in fields.items():
        np.testing.assert_allclose(work[k][full], v[full], rtol=0,
                                   atol=1e-9 * np.abs(v).max(), err_msg=k)
        slope = math.hypot(lin[k][1], lin[k][2])
        assert np.all(np.abs(work[k] - v)[ghost] <= slope * support), k
        np.testing.assert_array_equal(old[k][ghost], work[k][ghost])
    # a fluid at rest: the Shepard mean near the edges carries each source's density along
    # the hydrostatic gradient, so that every ghost, at a free surface too, is exact
    hydro = 1000.0 - 9.0 * z
    rho = np.where(ghost, 0.0, hydro)
    ghost_fields(x, z, np.zeros(n), np.zeros(n), rho, np.zeros(n), np.zeros(n), np.zeros(n),
                 m, kind, body, kind, hs,
                 *ghost_sources(x, z, kind, body, hs, grid, support * 1.15), kp,
                 no_opening(), fixed_kinematics(1), np.zeros(n, np.bool_), True, (0.0, -9.0),
                 np.ones(n))
    fitted = ghost & (rho != 0.0)
    assert (fitted & ~full).sum() > 50
    np.testing.assert_allclose(rho[fitted], hydro[fitted], rtol=0, atol=1e-9 * 1000.0)


def _pair_loops(x, z, vx, vz, rho, pres, m, body, hs, grid, kp, visc=0.0, shift=None,
                gw=None):
    """One call of the list loops (:func:`interact`) and one of the general loop
    (:func:`interact_reference`) on fluid particles sorted by ``grid``: each returns
    ``ax, az, drho, sx, sz``. ``gw``: the ghosts' weights (None: every ghost acts fully,
    passed as weights of 1 as the stepper does, so that its compiled loop is tested)."""
    n = len(x)
    gw = np.ones(n) if gw is None else gw
    kind = np.zeros(n, np.int32)
    support = 3.0 * kp[1]
    nlist = NeighbourList()
    nlist.build(x, z, kind, grid, support, hs)
    nlist.refresh(x, z, support, hs)
    shift = np.zeros(3) if shift is None else shift
    out = []
    for general in (False, True):
        res = [np.zeros(n) for _ in range(5)]
        args = (x, z, vx, vz, rho, pres, m, kind, body, kind, hs, grid.cell_of,
                grid.cell_start, grid.ncx, kp, visc, 0.0, 0.0, 0.0, 0.0, x, x, *res[:3],
                no_opening(), fixed_kinematics(1), shift, *res[3:])
        if general:
            interact_reference(*args, CLAMP, None, gw, None, None)
        else:
            interact(*args, pair_work(n), nlist.start, nlist.inner, nlist.inner_end, True,
                     CLAMP, None, gw, None, None)
        out.append(res)
    return out


def test_ghost_sources_are_every_active_particle_in_its_own_reach_in_index_order():
    """Each ghost's sources (:func:`ghost_sources`, searched in cells of each level's own
    radius) are exactly the active particles ``j`` within the list radius times ``hs[j]``,
    in ascending index, the order the coarse cells gave and :func:`ghost_fields` sums in;
    ghosts beyond a level's particles (outside its cells) included."""
    rng = np.random.default_rng(7)
    n = 3000
    x = rng.uniform(0.0, 6.0, n)
    z = rng.uniform(0.0, 3.0, n)
    hs = 2.0 ** -rng.integers(0, 3, n)
    body = np.where(rng.random(n) < 0.3, GHOST, -1).astype(np.int32)
    kind = np.where(rng.random(n) < 0.1, 1, FLUID).astype(np.int32)  # some walls
    fine = hs < 1.0  # the finer levels' particles crowd the left
    x[fine] *= 0.5
    radius = 0.9
    grid = CellGrid(0.0, 6.0, 0.0, 3.0, radius)
    x, z, hs, body, kind = sort_by_cells(grid, x, z, hs, body, kind)
    start, index = ghost_sources(x, z, kind, body, hs, grid, radius)
    active = (kind == FLUID) & (body != GHOST)
    ghosts = np.nonzero((kind == FLUID) & (body == GHOST))[0]
    found = 0
    for i in range(n):
        got = index[start[i]:start[i + 1]]
        if i not in ghosts:
            assert len(got) == 0
            continue
        want = np.nonzero(active & ((x - x[i]) ** 2 + (z - z[i]) ** 2
                                    < (radius * hs) ** 2))[0]
        np.testing.assert_array_equal(got, want, err_msg=f"ghost {i}")
        found += len(want)
    assert found > 5 * len(ghosts)  # not an empty comparison
    assert len(set(levels(hs[index]))) == 3


def test_a_point_beyond_a_level_s_cells_searches_none_of_them():
    """The cells about a point (:func:`_cell_span`): the 3 x 3 about one inside, clipped at
    an edge, and none for a point more than a cell beyond the interior on any side (a
    ghost far from a level's particles: its columns would have run past the last row's
    cells, reading outside the cell table)."""
    grid = CellGrid(0.0, 2.0, 0.0, 1.0, 0.5)  # interior columns 1-5, rows 1-3
    span = (grid.x0 + grid.cell, grid.z0 + grid.cell, 1.0 / grid.cell, grid.ncx, grid.ncz)
    assert _cell_span(0.7, 0.2, *span) == (1, 3, 1, 2)
    assert _cell_span(1.99, 0.99, *span) == (3, 5, 1, 3)
    assert _cell_span(2.6, 0.5, *span) == (5, 5, 1, 3)  # within a cell of the edge
    for x, z in ((3.1, 0.5), (-1.1, 0.5), (1.0, 2.1), (1.0, -0.6), (50.0, 50.0)):
        c0, c1, r0, r1 = _cell_span(x, z, *span)
        assert c0 > c1 and r0 > r1, (x, z)


def test_levels_do_not_interact():
    """The active particles of a level feel only their own level: the accelerations of the
    fine particles do not change when the coarse ghosts inside their box change."""
    p = _lattice(16, 8, rng=np.random.default_rng(5))
    q, _ = _refined(p, pack_boxes([_Box((0.55, 1.05), (-1.0, 2.0), 1)]))
    kp = kernel_params("gaussian", 1.23 * DX)
    support = 3.0 * kp[1]
    grid = CellGrid(-0.5, 2.1, -0.5, 1.3, support)
    x, z, vx, vz, rho, m, hs, body = sort_by_cells(grid, q.x, q.z, q.vx, q.vz, q.rho, q.m,
                                                   q.hs, q.body)
    visc = 2 * 0.02 * kp[1] * 30.0

    def loops(rho):
        return _pair_loops(x, z, vx, vz, rho, 30.0**2 * (rho - 1000.0), m, body, hs, grid,
                           kp, visc)

    listed, ref = loops(rho)
    before = listed[:3]
    # the list loops, each at its particle's own level, are the general loop's sums
    active = body != GHOST
    for u, v in zip(before, ref[:3], strict=True):
        np.testing.assert_allclose(u[active], v[active], rtol=1e-12,
                                   atol=1e-12 * np.abs(v).max())
    coarse_ghost = (body == GHOST) & (levels(hs) == 0)
    assert coarse_ghost.sum() > 0
    after = loops(np.where(coarse_ghost, rho + 5.0, rho))[0][:3]
    fine = (levels(hs) == 1) & (body != GHOST)
    for u, v in zip(before, after, strict=True):
        np.testing.assert_array_equal(u[fine], v[fine])
        assert np.any(u[~fine] != v[~fine])  # the coarse particles do feel them



def test_a_ghost_pushes_and_never_pulls():
    """A ghost acts on an active particle and feels nothing back, so a pull between them is
    not balanced: in a splash in tension (measured in the refined Table I case 5 at 21.2 s,
    -1.3 MPa) the ghosts ahead of a fine particle, fitted to its own velocity, pulled it
    along to 57 m/s. The pressure sum of an active particle and a ghost counts only when it
    pushes, as against a wall; an active neighbour in the same place does pull."""
    kp = kernel_params("gaussian", 1.23 * DX)
    support = 3.0 * kp[1]
    grid = CellGrid(-0.5, 0.5, -0.5, 0.5, support)
    n = 2
    hs = np.ones(n)
    m = np.full(n, 1000.0 * DX * DX)
    rho = np.full(n, 990.0)
    zero = np.zeros(n)

    def accel_x(pressure, neighbour):
        x, z = np.array([0.0, 0.5 * DX]), np.zeros(n)
        body = np.array([-1, neighbour], np.int32)
        x, z, b = sort_by_cells(grid, x, z, body)
        listed, ref = _pair_loops(x, z, zero, zero, rho, np.full(n, pressure), m, b, hs, grid,
                                  kp)
        out = [res[0][b == -1][0] for res in (listed, ref)]
        assert out[0] == pytest.approx(out[1], rel=1e-12, abs=1e-12)
        return out[0]

    # the neighbour lies at +x: a pull is a positive acceleration, a push a negative one
    assert accel_x(-2.0e5, -1) > 1.0  # two active particles in tension attract
    assert accel_x(-2.0e5, GHOST) == 0.0
    push = accel_x(2.0e5, -1)
    assert push < -1.0 and accel_x(2.0e5, GHOST) == pytest.approx(push, rel=1e-12)


def test_a_ghost_in_spray_does_not_act():
    """A ghost fitted from a nearly empty kernel is not fluid that is there. In a spray its
    only source may be the particle it acts on: fitted to that particle's own density and
    velocity, it follows it and pushes it on, and feels nothing back (in the refined Table I
    case 5, cabin particles beside ghosts filled 0.02-0.13 ran up to 100 m/s and the run
    stopped). A ghost acts with the weight of the share of its kernel its sources fill
    (:func:`ghost_weight`): not at all below 0.1, fully from 0.3, so that in the bulk and at a
    flat free surface (about 0.5) nothing changes."""
    kp = kernel_params("gaussian", 1.23 * DX)
    h = kp[1]
    support = 3.0 * h
    assert ghost_weight(0.05) == 0.0 and ghost_weight(0.2) == pytest.approx(0.5)
    assert ghost_weight(0.3) == 1.0 and ghost_weight(0.5) == 1.0

    def fitted(x, z, body, rho):
        """Fit the ghosts (``ghost_fields``) of particles sorted by a grid; returns the
        sorted set, its fields and the ghosts' weights."""
        grid = CellGrid(x.min() - 0.5, x.max() + 0.5, z.min() - 0.5, z.max() + 0.5, support)
        x, z, body, rho = sort_by_cells(grid, x, z, body, rho)
        n = len(x)
        kind, hs, m = np.zeros(n, np.int32), np.ones(n), np.full(n, 1000.0 * DX * DX)
        vx, vz = np.where(body == GHOST, 0.0, 3.0), np.zeros(n)
        gw = np.full(n, -1.0)
        ghost_fields(x, z, vx, vz, rho, vx.copy(), vz.copy(), rho.copy(), m, kind, body, kind,
                     hs, *ghost_sources(x, z, kind, body, hs, grid, support), kp,
                     no_opening(), fixed_kinematics(1), np.zeros(n, np.bool_), True,
                     (0.0, 0.0), gw)
        return grid, x, z, vx, vz, body, rho, m, hs, gw

    # a lone particle at 1060 kg/m3 and a ghost 1.4 h ahead of it: the ghost's only source
    grid, x, z, vx, vz, body, rho, m, hs, gw = fitted(
        np.array([0.0, 1.4 * h]), np.zeros(2), np.array([-1, GHOST], np.int32),
        np.array([1060.0, 0.0]))
    g, a = body == GHOST, body != GHOST
    assert rho[g][0] == pytest.approx(1060.0) and vx[g][0] == pytest.approx(3.0)
    assert gw[g][0] == 0.0
    pres = 30.0**2 * (rho - 1000.0)
    for weights, pushed in ((None, True), (gw, False)):
        for res in _pair_loops(x, z, vx, vz, rho, pres, m, body, hs, grid, kp, gw=weights):
            ax = res[0][a][0]
            assert (ax < -10.0) if pushed else (ax == 0.0), (weights, ax)

    # a lattice with a free surface on top, and ghosts among its particles: every ghost,
    # in the bulk and at the surface, acts fully
    xs, zs = np.meshgrid((np.arange(16) + 0.5) * DX, (np.arange(8) + 0.5) * DX)
    gx0 = (np.arange(2, 14) + 0.0) * DX
    x0 = np.concatenate([xs.ravel(), gx0, gx0])
    z0 = np.concatenate([zs.ravel(), np.full(12, 4.0 * DX), np.full(12, 8.0 * DX)])
    body0 = np.where(np.arange(len(x0)) < xs.size, -1, GHOST).astype(np.int32)
    rho0 = np.where(body0 == GHOST, 0.0, 1000.0 + 0.9 * (0.8 - z0))
    grid, x, z, vx, vz, body, rho, m, hs, gw = fitted(x0, z0, body0, rho0)
    assert np.all(gw[body == GHOST] == 1.0)
    pres = 30.0**2 * (rho - 1000.0)
    full = _pair_loops(x, z, vx, vz, rho, pres, m, body, hs, grid, kp, 0.1, gw=gw)
    plain = _pair_loops(x, z, vx, vz, rho, pres, m, body, hs, grid, kp, 0.1)
    for u, v in zip(full, plain, strict=True):
        for p, q in zip(u, v, strict=True):
            np.testing.assert_array_equal(p, q)


def test_ghosts_neither_pack_nor_steer_the_shifting():
    """Particle shifting spreads packed active particles; a ghost is fitted, not pushed, and
    does not make way, so it counts neither in the kernel sum that gates the shift nor in
    its gradient. A family made coarse inside a finer box sits among the ghosts of its
    level (the finer families' mothers): counted, they had it shifted by the cap, a tenth of
    its spacing, at every step (the refined Table I case 4 rebuilt its lists every 2-6
    steps). A lattice with a packed 4 x 4 patch in its middle: patch active, the lattice
    around it is shifted; patch of ghosts, nothing moves."""
    n = 16
    xs, zs = np.meshgrid((np.arange(n) + 0.5) * DX, (np.arange(n) + 0.5) * DX)
    c = 0.5 * n * DX
    px, pz = np.meshgrid(c + (np.arange(4) - 1.5) * DX, c + (np.arange(4) - 1.5) * DX)
    x0 = np.concatenate([xs.ravel(), px.ravel() + 0.5 * DX])
    z0 = np.concatenate([zs.ravel(), pz.ravel() + 0.5 * DX])
    patch0 = np.arange(len(x0)) >= n * n
    kp = kernel_params("gaussian", 1.23 * DX)
    support = 3.0 * kp[1]
    grid = CellGrid(-0.5, 2.1, -0.5, 2.1, support)
    shift = shift_params(1.0, 0.2, 10.0, kp, DX)

    def shifts(patch_body):
        body0 = np.where(patch0, patch_body, -1).astype(np.int32)
        x, z, body = sort_by_cells(grid, x0, z0, body0)
        n_all = len(x)
        rho = np.full(n_all, 1000.0)
        zero = np.zeros(n_all)
        listed, _ = _pair_loops(x, z, zero, zero, rho, zero, rho * DX * DX, body,
                                np.ones(n_all), grid, kp, shift=shift)
        return np.hypot(listed[3], listed[4])[body == -1]

    assert shifts(-1).max() > 0.01 * DX  # active and packed: spread
    assert shifts(GHOST).max() == 0.0

def _still(dx, boxes=None, density_filter="mls"):
    over = [("numerics.dx", dx), ("geometry.depth", 0.6), ("geometry.tank_length", 1.0),
            ("geometry.tank_height", 0.8), ("numerics.threads", 2),
            ("probes.pressure", []), ("probes.surface", []),
            ("numerics.density_filter", density_filter)]
    if boxes is not None:
        over.append(("numerics.refinement", boxes))
    sim = Simulation(builtin("still_water", over))
    sim.evaluate()
    return sim


def test_a_case_refined_everywhere_is_the_case_at_half_the_spacing():
    """Split at the start from dx = 0.1, every particle (fluid and walls) is at level 1 on the
    lattice of dx = 0.05. Given the same masses and densities (a child carries a quarter of
    its parent's mass, the uniform run the mass of its own cell: they differ by the
    hydrostatic density over half a spacing, 4e-4 here), the pair loops with a smoothing
    length per particle give the uniform run's derivatives to round-off, and the time step
    is the finest level's."""
    coarse = _still(0.1, [{"x": [-1.0, 2.0], "z": [-1.0, 2.0], "level": 1}])
    fine = _still(0.05)
    assert coarse.variable and not fine.variable
    a, b = coarse.parts, fine.parts
    fa = np.nonzero(active_fluid(a))[0]
    fb = np.nonzero(b.kind == FLUID)[0]
    assert len(fa) == len(fb)
    ia = fa[np.lexsort((np.round(a.z[fa], 9), np.round(a.x[fa], 9)))]
    ib = fb[np.lexsort((np.round(b.z[fb], 9), np.round(b.x[fb], 9)))]
    np.testing.assert_allclose(a.x[ia], b.x[ib], atol=1e-12)
    np.testing.assert_allclose(a.z[ia], b.z[ib], atol=1e-12)
    np.testing.assert_allclose(a.m[ia], b.m[ib], rtol=1e-3)
    b.m[ib] = a.m[ia]
    b.rho[ib] = a.rho[ia]
    rng = np.random.default_rng(2)
    for name in ("vx", "vz"):
        getattr(a, name)[ia] = getattr(b, name)[ib] = rng.normal(0.0, 0.1, len(ia))
    coarse.evaluate()
    fine.evaluate()
    for name in ("ax", "az", "drho"):
        u, v = getattr(a, name)[ia], getattr(b, name)[ib]
        scale = np.abs(v).max()
        assert scale > 0
        np.testing.assert_allclose(u, v, rtol=0, atol=1e-9 * scale, err_msg=name)
    coarse.advance()
    fine.advance()
    assert coarse.dt == pytest.approx(fine.dt, rel=1e-12)


@pytest.mark.parametrize("boxes, key, words", [
    ([{"x": [0.2, 0.4], "z": [0.0, 0.5], "level": 2}], "numerics.refinement[0]",
     "inside a box of level 1"),
    ([{"x": [0.4, 0.2], "z": [0.0, 0.5], "level": 1}], "numerics.refinement[0].x",
     "min < max"),
    ([{"x": [0.2, 0.4], "z": [0.0, 0.5], "level": 4}], "numerics.refinement[0].level",
     "3"),
    ([{"x": [5.0, 6.0], "z": [0.0, 0.5], "level": 1}], "numerics.refinement[0]",
     "outside the domain"),
])
def test_bad_refinement_boxes_are_refused(boxes, key, words):
    with pytest.raises(ConfigError) as err:
        _still(0.1, boxes)
    assert err.value.key == key
    assert words in str(err.value)


def test_a_moving_wall_in_a_box_is_refined_whole():
    """A box that reaches part of the wavemaker's flap gives the whole flap its fine layers
    (it may swing out of the box), in the flap's own frame, while the fixed walls get them
    only within the box's buffer."""
    over = [("numerics.dx", 0.4), ("numerics.refinement",
                                   [{"x": [-1.0, 3.0], "z": [-2.0, 10.0], "level": 1}])]
    sim = Simulation(builtin("wave_tank", over))
    p = sim.parts
    lev = levels(p.hs)
    flap = (p.kind != FLUID) & (p.body == 1)
    assert (lev[flap] == 1).sum() == 4 * (lev[flap] == 0).sum() > 0
    assert p.z[flap & (lev == 1)].max() > 30.0  # far above the box
    fixed = (p.kind != FLUID) & (p.body == 0) & (lev == 1)
    assert fixed.sum() > 0 and p.x[fixed].max() < 3.0 + BUFFER * 0.2 + 1e-9
    # the children sit at +-dx / 4 from their parent in the flap's frame
    kids = np.nonzero(flap & (lev == 1))[0]
    mother, _ = _IdIndex(p.pid).find(p.parent[kids])
    np.testing.assert_allclose(np.abs(p.bx[kids] - p.bx[mother]), 0.1, atol=1e-12)
    np.testing.assert_allclose(np.abs(p.bz[kids] - p.bz[mother]), 0.1, atol=1e-12)


@pytest.mark.parametrize("density_filter", ["mls", "none"])
def test_restart_with_refinement_continues_bit_for_bit(density_filter):
    """Splits and merges happen at list rebuilds, from the state alone: a run stopped and
    restarted from its state continues exactly as the uninterrupted one. The water starts
    moving at 1.5 m/s towards +x, so that it crosses the box's edges. With no density
    filter the ghosts' density exchange runs over the particles marked at each refresh of
    the inner lists, which a restart marks again."""
    box = [{"x": [0.35, 0.65], "z": [-1.0, 2.0], "level": 1}]

    def moving():
        sim = _still(0.1, box, density_filter)
        fluid = sim.parts.kind == FLUID
        sim.parts.vx[fluid] = sim.parts.vx_old[fluid] = 1.5
        sim.evaluate()
        return sim

    whole = moving()
    for _ in range(400):
        whole.advance()
    first = moving()
    for _ in range(200):
        first.advance()
    second = _still(0.1, box, density_filter)
    second.set_state(first.get_state())
    if density_filter == "none":  # the restored lists' marks, made again
        fresh = np.zeros(second.parts.n, np.bool_)
        nl = second.nlist
        listed_with(second.parts.kind, second.parts.body, nl.start, nl.inner, nl.inner_end,
                    None, fresh)
        assert fresh.any() and np.array_equal(second._ghosted, fresh)
    for _ in range(200):
        second.advance()
    assert whole.n_spawned + whole.n_removed > 0  # the level boundary moved particles across
    assert (second.n_spawned, second.n_removed) == (whole.n_spawned, whole.n_removed)
    np.testing.assert_array_equal(second.parts.f, whole.parts.f)
    np.testing.assert_array_equal(second.parts.i, whole.parts.i)


#: the damaged ship in a 70 m tank 15 m deep, refined at level 1 around its hull
SHIP_SMALL = ["numerics.dx=0.8", "geometry.depth=15", "geometry.tank_length=70",
              "geometry.ship_x=30", "geometry.tank_height=30", "geometry.absorber.start=50",
              "geometry.absorber.length=20", "geometry.refine_hull=1", "numerics.threads=2"]


def test_the_ship_refined_around_its_hull():
    """``geometry.refine_hull`` puts each hull with its cabins and opening in a box of that
    level: the hull's wall groups get their fine layers whole, the fluid in the cabins and
    around the hull is active at the fine level, the flap far away stays coarse, and the
    active mass is kept over the first steps."""
    sim = Simulation(builtin("damaged_ship", SHIP_SMALL + ["geometry.fill=0.5"]))
    sim.evaluate()
    p = sim.parts
    lev = levels(p.hs)
    groups = np.unique(p.body[(p.kind != FLUID) & (p.body > 0)])
    refined = [b for b in groups if np.any((p.body == b) & (lev == 1))]
    pitch = sim.setup.attrs["segment_pitch"]
    hulls = [b for b in groups if abs(np.median(p.x[p.body == b]) % pitch - 30.0) < 10.0]
    assert refined == hulls and len(hulls) == 2  # both hull segments, not the flaps
    for b in refined:
        wall = (p.kind != FLUID) & (p.body == b)
        assert (wall & (lev == 1)).sum() == 4 * (wall & (lev == 0)).sum()
    a = active_fluid(p)
    cabins = a & (p.comp % 2 == 1)  # each segment's sea is 2 s, its cabin 2 s + 1
    assert cabins.sum() > 0 and np.all(lev[cabins] == 1)
    near = a & (np.abs(p.x % pitch - 30.0) < 8.0) & (p.z > 9.0) & (p.comp % 2 == 0)
    assert near.sum() > 0 and np.all(lev[near] == 1)
    assert np.all(lev[a & (np.abs(p.x % pitch - 30.0) > 20.0)] == 0)
    mass = math.fsum(p.m[a])
    for _ in range(30):
        sim.advance()
    a = active_fluid(sim.parts)
    assert math.fsum(sim.parts.m[a]) == pytest.approx(mass, rel=1e-13)
    assert np.all(np.isfinite(sim.parts.ax[a]))


def test_a_family_turned_coarse_beside_the_hull_keeps_its_push_on_the_hull():
    """Action and reaction across levels: a family active at the coarse level inside the
    hull's box (one that strayed, :func:`assign`) pushes on the hull's coarse layers, and
    its fine children, ghosts, push on nothing. The hull must take that push: with the
    water at rest, turning the 22 families under the intact hull's keel coarse leaves the
    hull's vertical force within 2 % (0.5 % measured: the coarse kernel spreads the same
    hydrostatic pressure over the keel; leaving the coarse layers' reaction out lost 58 %
    of it), and the force is that of every wall particle of the hull."""
    sim = Simulation(builtin("damaged_ship", SHIP_SMALL + [
        "geometry.fill=0", "geometry.wavemaker.amplitude=null",
        "geometry.wavemaker.theta0=0"]))
    sim.evaluate()
    sim.evaluate()  # as the one after the change: the lists built, the ghosts fitted
    body = sim.bodies[0]
    hull = [g for g, _, _ in body.segments]
    before = body.segment_force.copy()
    p = sim.parts
    lev = levels(p.hs)
    g = hull[0]
    xc = sim.kin[g][0]
    keel = sim.cfg.geometry.depth - sim.cfg.geometry.hull.draught
    under = (active_fluid(p) & (lev == 1) & (p.comp == 0) & (np.abs(p.x - xc) < 4.0)
             & (p.z < keel) & (p.z > keel - 1.2))
    families = np.unique(p.parent[under])
    assert len(families) > 15
    for pid in families:  # as assign turns a family coarse, the water at rest
        p.body[p.pid == pid] = -1
        p.body[p.parent == pid] = GHOST
    sim._mark_ghosts()
    sim.evaluate()
    after = body.segment_force.copy()
    assert after[0, 1] == pytest.approx(before[0, 1], rel=0.02)
    assert after[1, 1] == pytest.approx(before[1, 1], rel=1e-3)  # the other segment
    fx, fz, mom = (np.zeros(len(sim.kin)) for _ in range(3))
    wall_forces(p.x, p.z, p.rho, p.p, p.m, p.kind, p.body, p.comp, p.hs, sim.kp, sim.kin,
                len(sim.kin), fx, fz, mom, sim._pf, sim.force_scale, sim.op,
                sim.nlist.start, sim.nlist.inner, sim.nlist.inner_end, sim.tension,
                sim._surf, None)
    np.testing.assert_allclose(np.c_[fx[hull], fz[hull], mom[hull]], after, rtol=1e-12,
                               atol=1e-9 * abs(after[0, 1]))


@pytest.mark.parametrize("level, margin, warns", [
    (1, 2.9, True), (1, 3.0, False),    # the coarse support at dx = 0.8 m: 2.95 m
    (2, 1.45, True), (2, 1.5, False),   # level 1's: 1.48 m
])
def test_a_box_margin_within_the_coarser_support_is_warned_about(caplog, level, margin,
                                                                 warns):
    """A hull closer to its finest box's edge than the next coarser level's kernel support
    is reached by that level's fluid outside the box, whose push on the hull's coarser
    layers the hull takes besides the fine fluid's: the case warns, naming the key and
    the smallest margin without it."""
    with caplog.at_level(logging.WARNING, logger="sph.cases.ship"):
        builtin("damaged_ship", [f"geometry.refine_hull={level}",
                                 f"geometry.refine_margin={margin}"])
    msgs = [r.getMessage() for r in caplog.records if "refine_margin" in r.getMessage()]
    assert bool(msgs) == warns, msgs
    if warns:
        assert f"allowed from {2.952 / 2 ** (level - 1):.3g} m" in msgs[0]


@pytest.mark.parametrize("x, z, edge, at", [
    ((0.35, 0.65), (-1.0, 2.0), "left edge meets the tank's floor", (0.35, 0.0)),
    ((-0.15, 1.15), (0.25, 0.45), "bottom edge meets the tank's left end wall", (0.0, 0.25)),
    ((0.35, 0.65), (0.1, 2.0), "left edge meets the tank's floor", (0.35, 0.0)),
    ((0.05, 0.65), (0.3, 2.0), "left edge meets the tank's left end wall", (0.05, 0.3)),
    ((0.35, 0.65), (0.25, 2.0), None, None),      # 2.5 spacings off the floor
    ((-0.15, 1.15), (-0.15, 2.0), None, None),    # its edges inside the walls or above them
])
def test_a_box_edge_that_meets_a_tank_wall_is_warned_about(caplog, x, z, edge, at):
    """A box whose edge crosses a wall of the tank, or runs along it within 1.5 spacings
    (the sloshing benchmark's box through the floor, which gains energy there:
    docs/validation/refinement.md), is warned of, naming the key, the edge, the wall and
    the place; a box whose edges stay farther off the walls, or lie inside them or above
    them, is not."""
    with caplog.at_level(logging.WARNING, logger="sph.engine.stepper"):
        _still(0.1, [{"x": list(x), "z": list(z), "level": 1}])
    msgs = [r.getMessage() for r in caplog.records if "meets the tank's" in r.getMessage()]
    if edge is None:
        assert msgs == []
    else:
        assert len(msgs) == 1
        assert msgs[0].startswith(f"numerics.refinement[0]: the box's {edge} at ")
        place = re.findall(r"x = ([-\d.]+), z = ([-\d.]+)", msgs[0])[0]
        np.testing.assert_allclose([float(v) for v in place], at, atol=1e-9)


def test_the_density_band_is_checked_over_the_active_fluid():
    """``run.density_min/max`` stop a run on the density of a mass-carrying particle, not on
    a ghost's, which is fitted from them (an MLS fit may overshoot): a ghost far out of the
    band passes the check, an active particle there stops the run, naming the band."""
    sim = _still(0.1, [{"x": [0.35, 0.65], "z": [-1.0, 2.0], "level": 1}])
    p = sim.parts
    ghost = np.nonzero((p.kind == FLUID) & (p.body == GHOST))[0][0]
    active = np.nonzero(active_fluid(p))[0][0]
    rho0 = sim.cfg.fluid.rho0
    sim.check()
    p.rho[ghost] = 1.6 * rho0  # above the default density_max of 1.5
    sim.check()
    p.rho[ghost] = 0.4 * rho0  # below density_min
    sim.check()
    p.rho[active] = 1.6 * rho0
    with pytest.raises(SimulationError, match="left the band"):
        sim.check()
