"""The engine's fast pair loops against their references on a damaged ship with its opening
open.

:func:`sph.engine.fluid.interact` sums most fluid particles over a branch-free gathered
neighbour list with a loop per kernel, and keeps the general loop (every pair rule at every
candidate) for particles within reach of the opening; :func:`interact_reference` sums every
particle the general way and is the oracle here. :func:`sph.engine.walls.wall_pressure`
and :func:`sph.engine.walls.wall_forces` are checked against brute-force sums over all
particles. In float64 the two orders of
summation agree to round-off: the tolerance is 1e-10 of the largest value of each field.
(The shifts of packed particles are checked branch by branch in ``test_pair_loop``.)
"""

import numpy as np
import pytest
from physics_helpers import NO_EXTRAS

from sph.cases import builtin
from sph.driver import Simulation
from sph.engine.eos import tait_density
from sph.engine.fluid import interact, interact_reference, pair_work
from sph.engine.kernels import f_r2, w_r2
from sph.engine.opening import near_opening, wall_hidden
from sph.engine.particles import FLUID, WALL
from sph.engine.shifting import shift_params
from sph.engine.surface import CLAMP
from sph.engine.walls import wall_forces, wall_pressure

RTOL = 1e-10


def _flooding_ship(kernel):
    over = [("numerics.dx", 0.8), ("numerics.threads", 2),
            ("geometry.damage.time_periods", 0.001)]
    if kernel == "wendland":
        over += [("numerics.kernel", "wendland"), ("numerics.h_factor", 1.41)]
    sim = Simulation(builtin("damaged_ship", over))
    sim.evaluate()
    for _ in range(40):
        sim.advance()
    assert sim.op[0] == 1.0, "the opening should be open"
    return sim


@pytest.fixture(scope="module", params=["gaussian", "wendland"])
def ship(request):
    return _flooding_ship(request.param)


def _derivatives(fn, sim, delta, ddt, shifting, extra=()):
    p, g = sim.parts, sim.grid
    n = p.n
    out = [np.zeros(n) for _ in range(5)]
    rng = np.random.default_rng(3)
    grx, grz = rng.normal(0, 20.0, n), rng.normal(0, 20.0, n)
    shift = shift_params(shifting, 0.2, 10.0, sim.kp, sim.cfg.numerics.dx)
    fn(p.x, p.z, p.vx, p.vz, p.rho, p.p, p.m, p.kind, p.body, p.comp, p.hs, g.cell_of,
       g.cell_start, g.ncx, sim.kp, sim.visc_coef, sim.gx, sim.gz, delta * sim.h * sim.c0,
       (1000.0 / sim.c0**2) if ddt else 0.0, grx, grz, *out[:3], sim.op, sim.kin, shift,
       *out[3:], *extra)
    return out


@pytest.mark.parametrize("delta, ddt, shifting", [(0.0, False, 0.0), (0.1, True, 1.0),
                                                   (0.1, False, 4.0)])
def test_fast_pair_loop_matches_the_reference(ship, delta, ddt, shifting):
    p = ship.parts
    fluid = p.kind == FLUID
    near = sum(near_opening(p.x[i], p.z[i], ship.op, 0.0) for i in np.nonzero(fluid)[0])
    assert 0 < near < 0.05 * fluid.sum(), near  # both paths are taken
    got = _derivatives(interact, ship, delta, ddt, shifting,
                      (pair_work(p.n), ship.nlist.start, ship.nlist.inner,
                       ship.nlist.inner_end, False, *NO_EXTRAS))
    want = _derivatives(interact_reference, ship, delta, ddt, shifting, NO_EXTRAS)
    for name, a, b in zip(("ax", "az", "drho", "sx", "sz"), got, want, strict=True):
        scale = np.abs(b[fluid]).max()
        if name in ("ax", "az", "drho"):
            assert scale > 0.0, name
        np.testing.assert_allclose(a[fluid], b[fluid], rtol=0, atol=RTOL * scale,
                                   err_msg=name)


def test_wall_pressure_matches_a_sum_over_all_particles(ship):
    """Eq. 11 with the wall's acceleration, fluid of the wall's compartment only, fluid
    behind the open opening hidden: summed here over every particle of the ship."""
    p = ship.parts
    fl = ship.cfg.fluid
    rho, pres, m = p.rho.copy(), p.p.copy(), p.m.copy()
    # the stepper's arguments at uniform resolution (no smoothing length ratios, every wall
    # particle), so that the stepper's compiled loop is tested
    wall_pressure(p.x, p.z, rho, pres, m, p.kind, p.body, p.comp, None, ship.kp, ship.gx,
                  ship.gz, ship.kin, fl.rho0, ship.b, fl.gamma, ship.cfg.numerics.dx**2,
                  ship.op, ship.nlist.start, ship.nlist.inner, ship.nlist.inner_end, True, None)
    fluid = np.nonzero(p.kind == FLUID)[0]
    r2max = ship.kp[3]
    hidden_seen = 0
    for i in np.nonzero(p.kind == WALL)[0]:
        b = p.body[i]
        k = ship.kin[b]
        rx, rz = p.x[i] - k[0], p.z[i] - k[1]
        abx = k[6] - k[8] * rz - k[5] ** 2 * rx
        abz = k[7] + k[8] * rx - k[5] ** 2 * rz
        dx, dz = p.x[i] - p.x[fluid], p.z[i] - p.z[fluid]
        r2 = dx * dx + dz * dz
        sel = np.nonzero((r2 < r2max) & (p.comp[fluid] == p.comp[i]))[0]
        keep = [s for s in sel if not wall_hidden(p.x[fluid[s]], p.z[fluid[s]], p.x[i],
                                                  p.z[i], b, ship.op, ship.kin)]
        hidden_seen += len(sel) - len(keep)
        j = fluid[keep]
        w = np.array([w_r2(v, ship.kp) for v in r2[keep]]) * p.m[j] / p.rho[j]
        sw = w.sum()
        sp = (w * (p.p[j] + p.rho[j] * ((ship.gx - abx) * dx[keep]
                                        + (ship.gz - abz) * dz[keep]))).sum()
        want = max(sp / sw, 0.0) if sw > 1e-6 else 0.0
        assert pres[i] == pytest.approx(want, rel=1e-10, abs=1e-10 * fl.rho0 * 9.81), i
        assert rho[i] == pytest.approx(tait_density(want, fl.rho0, ship.b, fl.gamma),
                                       rel=1e-12)
    assert hidden_seen > 0  # the opening hides some fluid from the hull's wall layers


def test_wall_forces_match_a_sum_over_all_particles(ship):
    """Eq. 10 per wall particle of the hull: pressure of both ends (fluid tension counts as
    zero), fluid behind the open opening hidden, summed over every particle."""
    p = ship.parts
    nb = len(ship.kin)
    fx, fz, mom = np.zeros(nb), np.zeros(nb), np.zeros(nb)
    pf = np.zeros((p.n, 3))
    scale = np.ones(int(p.comp.max()) + 1)
    wall_forces(p.x, p.z, p.rho, p.p, p.m, p.kind, p.body, p.comp, None, ship.kp, ship.kin, nb,
                fx, fz, mom, pf, scale, ship.op, ship.nlist.start, ship.nlist.inner,
                ship.nlist.inner_end, CLAMP, None, None)
    fluid = np.nonzero(p.kind == FLUID)[0]
    hull = np.nonzero((p.kind == WALL) & (p.body > 0))[0]
    assert len(hull) > 0
    want = np.zeros((len(hull), 2))
    for row, i in enumerate(hull):
        dx, dz = p.x[i] - p.x[fluid], p.z[i] - p.z[fluid]
        r2 = dx * dx + dz * dz
        sel = [s for s in np.nonzero((r2 < ship.kp[3]) & (p.comp[fluid] == p.comp[i]))[0]
               if not wall_hidden(p.x[fluid[s]], p.z[fluid[s]], p.x[i], p.z[i], p.body[i],
                                  ship.op, ship.kin)]
        j = fluid[sel]
        fw = np.array([f_r2(v, ship.kp) for v in r2[sel]]) * (
            p.p[i] + np.maximum(p.p[j], 0.0)) * p.m[j] / p.rho[j]
        want[row] = -p.m[i] / p.rho[i] * np.array([(fw * dx[sel]).sum(),
                                                   (fw * dz[sel]).sum()])
    scale_f = np.abs(want).max()
    assert scale_f > 0.0
    np.testing.assert_allclose(pf[hull, :2], want, rtol=0, atol=RTOL * scale_f)


def _pairs_within(x, z, start, index, end, r2max):
    """Per particle, the number of entries ``index[start[i]:end[i]]`` within the support."""
    n = len(x)
    first = start[:-1].astype(np.int64)
    lens = end.astype(np.int64) - first
    owner = np.repeat(np.arange(n), lens)
    k = np.arange(lens.sum()) + np.repeat(first - (np.cumsum(lens) - lens), lens)
    j = index[k]
    r2 = (x[owner] - x[j]) ** 2 + (z[owner] - z[j]) ** 2
    return np.bincount(owner[r2 < r2max], minlength=n)


STEPS = 300


@pytest.mark.parametrize("kernel", ["gaussian", "wendland"])
def test_inner_lists_hold_every_pair_within_the_support_at_every_step(kernel):
    """The pair loops go over the inner lists, refreshed only when a particle has
    moved half their thin skin: at every step of a flooding ship, each particle's inner
    list (a subsequence of its Verlet list) must hold every particle of its Verlet list
    within the support (checked every fourth step), and the lists must have been refreshed
    in between."""
    sim = _flooding_ship(kernel)
    nl = sim.nlist
    refreshed = 0
    for step in range(STEPS):
        before = sim.parts.x_inner.copy()
        sim.advance()
        p = sim.parts
        refreshed += not np.array_equal(before, p.x_inner)
        if step % 4:  # a pair missed stays missed until the next refresh
            continue
        full = _pairs_within(p.x, p.z, nl.start, nl.index, nl.start[1:], sim.kp[3])
        inner = _pairs_within(p.x, p.z, nl.start, nl.inner, nl.inner_end, sim.kp[3])
        np.testing.assert_array_equal(inner, full)
        assert np.all(nl.inner_end <= nl.start[1:])
    assert 0 < refreshed < STEPS, refreshed
