"""Tests of the smoothing kernels: normalisation, gradient factor, support and the discrete
consistency conditions on a regular lattice."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from sph.engine.kernels import (
    DEFAULT_H_FACTOR,
    GAUSSIAN,
    KERNELS,
    SUPPORT,
    WENDLAND,
    f_r2,
    kernel_params,
    support_radius,
    w_r2,
)

# (kernel name, h / dx, support radius / h)
KERNEL_CASES = [("gaussian", 1.23, 3.0), ("wendland", 1.41, 2.0)]
# two particle spacings: the checks are scale-free, so both must pass alike
SPACINGS = [1.0, 0.02]


def _kp(name, hf, dx):
    h = hf * dx
    return h, kernel_params(name, h)


def _w(r, kp):
    return w_r2(float(r) * float(r), kp)


def _f(r, kp):
    return f_r2(float(r) * float(r), kp)


# --------------------------------------------------------------------------- parameters


@pytest.mark.parametrize("name, hf, q_support", KERNEL_CASES)
def test_defaults_and_support_radius(name, hf, q_support):
    assert DEFAULT_H_FACTOR[name] == pytest.approx(hf)
    assert SUPPORT[KERNELS[name]] == q_support
    h, kp = _kp(name, hf, 0.02)
    assert kp.dtype == np.float64 and kp.shape == (5,)
    assert kp[0] == {"gaussian": GAUSSIAN, "wendland": WENDLAND}[name]
    assert kp[1] == pytest.approx(h)
    assert support_radius(kp) == pytest.approx(q_support * h, rel=1e-14)
    assert kp[4] == pytest.approx(1.0 / h**2, rel=1e-14)


# --------------------------------------------------------------------------- (a) normalisation


@pytest.mark.parametrize("dx", SPACINGS)
@pytest.mark.parametrize("name, hf, q_support", KERNEL_CASES)
def test_integral_over_support_is_one(name, hf, q_support, dx):
    """The 2-D integral of W, in polar form 2 pi r W(r) dr over [0, R], equals 1."""
    h, kp = _kp(name, hf, dx)
    radius = support_radius(kp)
    integral, err = quad(lambda r: 2.0 * math.pi * r * _w(r, kp), 0.0, radius,
                         epsabs=1e-13, epsrel=1e-12, limit=200)
    assert err < 1e-9
    assert integral == pytest.approx(1.0, abs=1e-6)


# --------------------------------------------------------------------------- (b) gradient


@pytest.mark.parametrize("dx", SPACINGS)
@pytest.mark.parametrize("name, hf, q_support", KERNEL_CASES)
def test_gradient_factor_matches_finite_difference(name, hf, q_support, dx):
    """dW/dr = F(r) r, checked by a central difference at many radii inside the support.

    The radii stop short of the support radius: the cut-off Gaussian has a kink there (its
    slope jumps to zero), so a difference straddling R would not be a derivative, and the
    Wendland kernel vanishes like (R - r)^4 there, where any difference quotient loses its
    relative accuracy."""
    h, kp = _kp(name, hf, dx)
    radius = support_radius(kp)
    step = 1e-6 * h
    radii = np.linspace(0.05 * h, 0.995 * radius, 157)
    for r in radii:
        fd = (_w(r + step, kp) - _w(r - step, kp)) / (2.0 * step)
        analytic = _f(r, kp) * r
        assert analytic < 0.0, r / h  # both kernels decrease monotonically
        assert analytic == pytest.approx(fd, rel=1e-5), f"r/h = {r / h:.4f}"


@pytest.mark.parametrize("name, hf, q_support", KERNEL_CASES)
def test_gradient_factor_finite_at_origin(name, hf, q_support):
    """F stays finite at r = 0 (the gradient F r vanishes there)."""
    h, kp = _kp(name, hf, 0.02)
    f0 = f_r2(0.0, kp)
    assert math.isfinite(f0) and f0 < 0.0


# --------------------------------------------------------------------------- (c) support


@pytest.mark.parametrize("dx", SPACINGS)
@pytest.mark.parametrize("name, hf, q_support", KERNEL_CASES)
def test_zero_at_and_beyond_support(name, hf, q_support, dx):
    h, kp = _kp(name, hf, dx)
    radius = q_support * h
    r2_support = kp[3]
    for r2 in (r2_support, r2_support * (1 + 1e-12), radius**2 * 1.0001, (1.5 * radius) ** 2,
               (10 * radius) ** 2, 1e300):
        assert w_r2(r2, kp) == 0.0, r2
        assert f_r2(r2, kp) == 0.0, r2


@pytest.mark.parametrize("dx", SPACINGS)
@pytest.mark.parametrize("name, hf, q_support", KERNEL_CASES)
def test_non_negative_and_decreasing_inside(name, hf, q_support, dx):
    h, kp = _kp(name, hf, dx)
    radius = support_radius(kp)
    r = np.linspace(0.0, radius, 2001)[:-1]
    w = np.array([_w(v, kp) for v in r])
    assert np.all(w >= 0.0)
    assert np.all(np.diff(w) <= 0.0)
    assert w[0] > 0.0
    # approaching the support radius from inside, W tends to 0 (continuous cut-off)
    assert _w(radius * (1 - 1e-9), kp) < 1e-6 * w[0]


# --------------------------------------------------------------------------- (d) lattice sums


def _lattice_neighbourhood(dx, radius):
    """Offsets r_j - r_i of a square lattice around an interior particle i at the origin
    (the particle itself included, at offset 0)."""
    n = int(math.ceil(radius / dx)) + 1
    s = np.arange(-n, n + 1) * dx
    xx, zz = np.meshgrid(s, s, indexing="ij")
    return xx.ravel(), zz.ravel()


@pytest.mark.parametrize("dx", SPACINGS)
@pytest.mark.parametrize("name, hf, q_support", KERNEL_CASES)
def test_lattice_partition_of_unity(name, hf, q_support, dx):
    """sum_j V_j W_ij ~ 1 for an interior particle of a lattice with V_j = dx^2."""
    h, kp = _kp(name, hf, dx)
    ox, oz = _lattice_neighbourhood(dx, support_radius(kp))
    vol = dx * dx
    total = vol * sum(w_r2(float(a * a + b * b), kp) for a, b in zip(ox, oz, strict=True))
    assert total == pytest.approx(1.0, abs=0.01)


@pytest.mark.parametrize("dx", SPACINGS)
@pytest.mark.parametrize("name, hf, q_support", KERNEL_CASES)
def test_lattice_gradient_sums(name, hf, q_support, dx):
    r"""Zeroth and first moments of the discrete kernel gradient on a lattice.

    With the engine's convention :math:`\nabla_i W_{ij} = F(r_{ij})(\mathbf{r}_i - \mathbf{r}_j)`
    (here :math:`\mathbf{r}_i = 0`, so :math:`\nabla_i W_{ij} = -F\,\mathbf{s}_j` with
    :math:`\mathbf{s}_j = \mathbf{r}_j - \mathbf{r}_i`):

    * :math:`\sum_j V_j \nabla_i W_{ij} = 0` by the point symmetry of the lattice;
    * the gradient consistency condition
      :math:`\sum_j V_j (\mathbf{r}_j - \mathbf{r}_i) \otimes \nabla_i W_{ij} = +I`.

    Sign: in the continuum limit the sum is
    :math:`-\int \mathbf{s}\otimes\mathbf{s}\,W'(s)/s\,d^2s`. Since :math:`W' \le 0` the
    integrand is positive semi-definite; by isotropy it equals
    :math:`\tfrac12 I \int_0^R 2\pi s^2 (-W'(s))\,ds`, and integrating by parts
    (:math:`W(R) = 0`) gives :math:`\tfrac12 I \cdot 2\int_0^R 2\pi s W\,ds = I`. So the
    identity holds with a plus sign: :math:`\nabla_i W_{ij}` points from i towards j, the
    same direction as :math:`\mathbf{r}_j - \mathbf{r}_i`.
    """
    h, kp = _kp(name, hf, dx)
    ox, oz = _lattice_neighbourhood(dx, support_radius(kp))
    vol = dx * dx
    f = np.array([f_r2(float(a * a + b * b), kp) for a, b in zip(ox, oz, strict=True)])
    # grad_i W_ij = F (r_i - r_j) = -F * offset
    gx, gz = -f * ox, -f * oz
    grad_sum = vol * np.array([gx.sum(), gz.sum()])
    assert np.all(np.abs(grad_sum) * h < 1e-10)

    moment = vol * np.array([[np.sum(ox * gx), np.sum(ox * gz)],
                             [np.sum(oz * gx), np.sum(oz * gz)]])
    np.testing.assert_allclose(moment, np.eye(2), atol=0.02)
    # the opposite sign is clearly excluded
    assert moment[0, 0] > 0.9 and moment[1, 1] > 0.9


@pytest.mark.parametrize("name, hf, q_support", KERNEL_CASES)
def test_lattice_gradient_of_linear_field(name, hf, q_support):
    """Consequence of the two lattice sums: the SPH gradient of a linear field
    phi = a x + b z, sum_j V_j (phi_j - phi_i) grad_i W_ij, recovers (a, b) to 2 %."""
    dx = 0.05
    h, kp = _kp(name, hf, dx)
    ox, oz = _lattice_neighbourhood(dx, support_radius(kp))
    a, b = 2.5, -1.25
    f = np.array([f_r2(float(u * u + v * v), kp) for u, v in zip(ox, oz, strict=True)])
    dphi = a * ox + b * oz
    grad = dx * dx * np.array([np.sum(dphi * -f * ox), np.sum(dphi * -f * oz)])
    np.testing.assert_allclose(grad, [a, b], rtol=0.02)


def test_series_exponential_matches_the_library_one():
    """The Gaussian's exponential (:func:`sph.engine.kernels.exp_neg`) over its whole support
    (a fine grid, the ends, random points) to a relative 1e-13: the bound of its series
    and squarings (about 7e-14)."""
    from sph.engine.kernels import exp_neg

    s = np.concatenate([np.linspace(0.0, 9.0, 20001), np.arange(0, 577) / 64.0,
                        np.random.default_rng(1).uniform(0.0, 9.0, 5000)])
    got = np.array([exp_neg(v) for v in s])
    assert np.max(np.abs(got / np.exp(-s) - 1.0)) < 1e-13
