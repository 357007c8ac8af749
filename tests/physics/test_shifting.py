"""Particle shifting (:mod:`sph.engine.shifting`): packed particles are spread, regular ones and the
free surface are left alone.

A block of fluid on a square lattice (spacing dx) with a packed patch in its middle (extra
particles at half the spacing, all at the reference density): the kernel sum of the patch is
well above one, which pressure cannot see. Shifting must move the patch's particles away from
its centre, leave the regular lattice and the free surface where they are, and, applied
repeatedly, bring the largest kernel sum down to the packing threshold.
"""

import math

import numpy as np
import pytest
from physics_helpers import fluid_pair_loop, sort_by_cells

from sph.engine.kernels import kernel_params, w_r2
from sph.engine.neighbours import CellGrid
from sph.engine.shifting import PACKED, apply_shift, shift_params, shifting_coefficient

DX = 0.1
RHO0 = 1000.0


def _block(n=24, packed=True):
    xs, zs = np.meshgrid((np.arange(n) + 0.5) * DX, (np.arange(n) + 0.5) * DX)
    pts = np.column_stack([xs.ravel(), zs.ravel()])
    if packed:  # a 4 x 4 patch of extra particles in the middle, half a spacing off
        c = 0.5 * n * DX
        px, pz = np.meshgrid(c + (np.arange(4) - 1.5) * DX, c + (np.arange(4) - 1.5) * DX)
        pts = np.vstack([pts, np.column_stack([px.ravel(), pz.ravel()]) + 0.5 * DX])
    return pts


class _State:
    def __init__(self, pts):
        n = len(pts)
        self.x, self.z = pts[:, 0].copy(), pts[:, 1].copy()
        self.rho = np.full(n, RHO0)
        self.m = np.full(n, RHO0 * DX * DX)
        self.kind = np.zeros(n, np.int32)  # all fluid
        self.kp = kernel_params("gaussian", 1.23 * DX)
        r = math.sqrt(self.kp[3])
        self.grid = CellGrid(-1.0, 4.0, -1.0, 4.0, r)
        self.shift_params = shift_params(1.0, 0.2, 10.0, self.kp, DX)

    def shift(self):
        self.x, self.z, self.rho, self.m = sort_by_cells(self.grid, self.x, self.z, self.rho,
                                                         self.m)
        zero = np.zeros(len(self.x))
        # the shift is summed in the pair loop of the momentum equation (at rest, no pressure)
        _, _, _, sx, sz = fluid_pair_loop(self.x, self.z, zero, zero, self.rho, self.m,
                                          self.grid, self.kp, shift=self.shift_params)
        return sx, sz

    def kernel_sums(self):
        d2 = (self.x[:, None] - self.x[None, :]) ** 2 + (self.z[:, None] - self.z[None, :]) ** 2
        w = np.vectorize(lambda r2: w_r2(r2, self.kp))(d2)
        return (w * (self.m / self.rho)[None, :]).sum(axis=1)


def test_regular_lattice_and_free_surface_are_not_shifted():
    s = _State(_block(packed=False))
    sx, sz = s.shift()
    # a regular block (inside: kernel sum one; at its edges, a free surface: below one)
    assert np.max(np.hypot(sx, sz)) == 0.0


def test_packed_patch_spreads_from_its_centre_and_not_through_the_surface():
    s = _State(_block())
    c = 0.5 * 24 * DX + 0.5 * DX
    sums = s.kernel_sums()
    assert sums.max() > 1.3  # the patch is packed well beyond the threshold
    sx, sz = s.shift()
    mag = np.hypot(sx, sz)
    r = np.hypot(s.x - c, s.z - c)
    moved = mag > 1e-9
    assert moved.any()
    # particles that move lie near the patch, and move away from its centre
    assert np.all(r[moved] < 5 * DX)
    away = (sx * (s.x - c) + sz * (s.z - c))[moved & (r > 0.5 * DX)]
    assert np.all(away > 0.0)
    # never more than the per-step cap
    assert mag.max() <= 0.1 * DX * (1 + 1e-12)


def test_repeated_shifting_unpacks_the_patch():
    s = _State(_block())
    before = s.kernel_sums().max()
    for _ in range(400):
        sx, sz = s.shift()
        apply_shift(s.x, s.z, sx, sz, s.kind)
    after = s.kernel_sums()
    assert before > 1.3
    # down to the threshold (plus the ramp it is reached over), and the block's outline
    # (its free surface) is where it was within a fifth of a spacing
    assert after.max() < PACKED + 0.1, after.max()
    assert s.x.min() > 0.5 * DX - 0.2 * DX and s.z.max() < 24 * DX - 0.5 * DX + 0.2 * DX


def test_shifting_coefficient_scales_with_h_squared():
    assert shifting_coefficient(1.0, 0.2, 10.0, 2.0) == pytest.approx(
        4.0 * shifting_coefficient(1.0, 0.2, 10.0, 1.0))
    assert shifting_coefficient(0.0, 0.2, 10.0, 1.0) == 0.0


def test_kernel_value_from_its_gradient_factor():
    """The shift's kernel values come from the momentum equation's gradient factor."""
    from sph.engine.kernels import f_r2, w_given_f
    for name in ("gaussian", "wendland"):
        kp = kernel_params(name, 1.3 * DX)
        for r2 in np.linspace(0.0, kp[3], 50, endpoint=False):
            assert w_given_f(r2, f_r2(r2, kp), kp) == pytest.approx(w_r2(r2, kp), rel=1e-12,
                                                                    abs=1e-12 * kp[2])
