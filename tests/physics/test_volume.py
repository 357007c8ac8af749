"""The volume correction of variable resolution (:mod:`sph.engine.volume`): the volume fraction
read on a grid counts every particle by the volume it carries, whatever its level, reads one
in the bulk of a lattice of any spacing, has no bias from disorder where the kernel sum has
one, and the correction raises the densities of a fluid packed closer than they say, lowers
those of one spread wider only where the neighbourhood is full of fluid, and leaves alone a
fluid whose densities agree with its spacing.
"""

import numpy as np
import pytest

from sph.engine.kernels import kernel_params, w_r2
from sph.engine.particles import FLUID, GHOST, WALL
from sph.engine.volume import (
    VOLUME_DEAD,
    VOLUME_DEAD_EDGE,
    VOLUME_RATE,
    VolumeCorrection,
)

RHO0 = 1000.0
DX = 0.8
#: a time step (s)
DT = 0.01
#: the grid's domain: a 16 m x 12 m tank (0-16 m, 0-12 m) and its walls' room
BOUNDS = (-3.2, 19.2, -3.2, 15.2)


class _Parts:
    """The particle fields the correction reads."""

    def __init__(self, x, z, spacing, rho=RHO0, kind=FLUID, body=-1):
        n = x.size
        self.x, self.z = x.astype(float), z.astype(float)
        self.m = np.full(n, RHO0) * np.broadcast_to(spacing, n) ** 2
        self.hs = np.broadcast_to(spacing, n) / DX
        self.rho = np.full(n, float(rho))
        self.rho_old = self.rho.copy()
        self.kind = np.full(n, kind, np.int32)
        self.body = np.full(n, body, np.int32)

    @classmethod
    def join(cls, *parts):
        out = cls(np.zeros(0), np.zeros(0), DX)
        for name in ("x", "z", "m", "hs", "rho", "rho_old", "kind", "body"):
            setattr(out, name, np.concatenate([getattr(p, name) for p in parts]))
        return out


def _lattice(x0, x1, z0, z1, spacing, **kw):
    xs = np.arange(x0 + spacing / 2, x1, spacing)
    zs = np.arange(z0 + spacing / 2, z1, spacing)
    x, z = np.meshgrid(xs, zs)
    return _Parts(x.ravel(), z.ravel(), spacing, **kw)


def _nodes(frac, x0, x1, z0, z1):
    """The grid's nodes with x in [x0, x1] and z in [z0, z1] (m)."""
    i = np.round(np.array([x0, x1]) / DX - 0.5).astype(int) + 4
    k = np.round(np.array([z0, z1]) / DX - 0.5).astype(int) + 4
    return frac[i[0]:i[1] + 1, k[0]:k[1] + 1]


def test_the_deposit_keeps_every_particles_volume_and_skips_ghosts_and_walls():
    rng = np.random.default_rng(3)
    p = _Parts(rng.uniform(2, 14, 500), rng.uniform(2, 10, 500), DX)
    p.rho = 1000.0 + rng.uniform(0, 20, 500)
    p.body[:50] = GHOST
    p.kind[50:100] = WALL
    vc = VolumeCorrection(BOUNDS, DX)
    grid = np.zeros(vc.shape)
    from sph.engine.volume import deposit
    deposit(p.x, p.z, p.rho, p.m, p.hs, p.kind, p.body, vc.x0, vc.z0, DX, grid)
    counted = slice(100, None)
    assert grid.sum() == pytest.approx(np.sum(p.m[counted] / p.rho[counted]), rel=1e-12)


@pytest.mark.parametrize("spacing", [0.8, 0.4, 0.2])
def test_a_lattice_of_any_level_reads_one_in_its_bulk(spacing):
    p = _lattice(0, 16, 0, 12, spacing)
    frac, full = VolumeCorrection(BOUNDS, DX).fraction(p)
    np.testing.assert_allclose(_nodes(frac, 4.4, 11.6, 4.4, 7.6), 1.0, atol=1e-9)
    assert _nodes(full, 4.4, 11.6, 4.4, 7.6).all()


def test_two_levels_side_by_side_read_one_across_their_interface():
    """Coarse fluid left of x = 8 m, fine (0.2 m) right of it: each counts by the volume it
    carries over its own square, so the fraction reads one across the interface. (Spread
    as points by cloud-in-cell weights, the coarse particles' volumes read 2.3 % off at
    the interface.)"""
    p = _Parts.join(_lattice(0, 8, 0, 12, 0.8), _lattice(8, 16, 0, 12, 0.2))
    frac, _ = VolumeCorrection(BOUNDS, DX).fraction(p)
    np.testing.assert_allclose(_nodes(frac, 4.4, 11.6, 4.4, 7.6), 1.0, atol=1e-9)


def test_disorder_biases_the_kernel_sum_but_not_the_grid_fraction():
    """Particles displaced at random by up to a quarter spacing, over 40 draws: the mean
    kernel sum of their own volumes rises above one by the kernel's convexity (about
    0.01 here), the mean grid fraction stays at one within its standard error (each
    particle's volume spreads over the nodes by weights that sum to one wherever it is)."""
    rng = np.random.default_rng(1)
    kp = kernel_params("gaussian", 1.23 * DX)
    vc = VolumeCorrection(BOUNDS, DX)
    fr, phis = [], []
    for _ in range(40):
        p = _lattice(0, 16, 0, 12, DX)
        p.x += rng.uniform(-0.25, 0.25, p.x.size) * DX
        p.z += rng.uniform(-0.25, 0.25, p.x.size) * DX
        frac, _ = vc.fraction(p)
        fr.append(_nodes(frac, 4.4, 11.6, 4.4, 7.6).mean())
        sel = np.nonzero((p.x > 5) & (p.x < 11) & (p.z > 4) & (p.z < 8))[0]
        r2 = (p.x[sel, None] - p.x[None]) ** 2 + (p.z[sel, None] - p.z[None]) ** 2
        w = np.vectorize(lambda q: w_r2(q, kp))(r2)
        phis.append(np.mean(w @ (p.m / p.rho)))
    phis, fr = np.array(phis), np.array(fr)
    assert phis.mean() - 1.0 > 0.005, phis.mean()
    assert abs(fr.mean() - 1.0) < 3.0 * fr.std() / np.sqrt(fr.size) + 1e-4, fr.mean()


def test_a_fluid_whose_densities_agree_with_its_spacing_is_left_as_it_is():
    """Water 8 m deep with a free surface, on a lattice: nothing changes, at the surface
    (half-full cells) or in the bulk."""
    p = _lattice(0, 16, 0, 8, DX)
    f = VolumeCorrection(BOUNDS, DX).apply(p, DT)
    assert np.all(f == 1.0) and np.all(p.rho == RHO0)


def test_a_packed_fluid_takes_denser_and_a_spread_one_looser_densities_in_its_bulk():
    """Water 10 m deep, its densities 6 % below what its spacing gives (packed): the bulk's rise
    at VOLUME_RATE by the excess over the dead band, rho_old with them; 6 % above (spread): the
    bulk's fall the same way, the surface's are left as they are."""
    vc = VolumeCorrection(BOUNDS, DX)
    for rho, sign in ((RHO0 / 1.06, 1.0), (RHO0 * 1.06, -1.0)):
        p = _lattice(0, 16, 0, 10, DX, rho=rho)
        f = vc.apply(p, DT).copy()
        bulk = (p.x > 5) & (p.x < 11) & (p.z > 4.5) & (p.z < 5.5)
        frac = RHO0 / rho
        want = 1.0 + VOLUME_RATE * DT * (frac - 1.0 - sign * VOLUME_DEAD)
        # beyond the smoothing's reach (4 cells) from the surface and the bottom
        np.testing.assert_allclose(f[bulk], want, rtol=1e-9)
        np.testing.assert_allclose(p.rho_old, p.rho)
        top = p.z > 9.5
        if sign < 0:  # spread at the surface reads as the air above: left alone
            assert np.all(f[top] == 1.0)
        else:  # packed at the surface: the excess over the edge's band is taken
            assert np.all(f[top] <= 1.0 + VOLUME_RATE * DT * (frac - 1.0 - VOLUME_DEAD_EDGE)
                          + 1e-12)
