r"""Smoothing kernels in 2D.

Two kernels are offered (config key ``numerics.kernel``):

``gaussian``
    The renormalised ("improved") Gaussian of Cao et al. (2019), Eq. (7), cut off at
    :math:`r = 3h`, with :math:`h = 1.23\,dx` by default:

    .. math:: W(r, h) = \frac{e^{-(r/h)^2} - e^{-9}}{\pi h^2 (1 - 10 e^{-9})}, \quad r \le 3h.

``wendland``
    The Wendland C2 kernel (second source paper, Sec. 2.1), support :math:`2h`:

    .. math:: W(q) = \frac{7}{4\pi h^2}\left(1 - \frac{q}{2}\right)^4 (2q + 1), \quad q = r/h \le 2.

Both are evaluated from the squared distance. The gradient is returned as a scalar factor
:math:`F(r)` with :math:`\nabla_i W_{ij} = F(r_{ij})\,(\mathbf{r}_i - \mathbf{r}_j)`, so that a pair
loop needs no square root for the Gaussian kernel.

The kernel parameters travel to the numba loops as one small float array ``kp``:
``kp = [kind, h, alpha_d, R^2, 1/h^2]`` built by :func:`kernel_params`.

Under variable resolution (:mod:`sph.engine.refinement`) every particle has its own smoothing
length :math:`h_i = s_i h` (``s_i = 2^{-l}`` at refinement level ``l``) and a pair takes the
mean :math:`h_{ij} = s_{ij} h`, :math:`s_{ij} = (s_i + s_j)/2`, so that :math:`W_{ij} = W_{ji}`
and the pair forces stay antisymmetric (momentum is conserved). The kernel of smoothing
length :math:`s h` is that of ``h`` at :math:`r/s`: :math:`W(r; sh) = W(r/s; h)/s^2` and
:math:`F(r; sh) = F(r/s; h)/s^4` (:func:`w_scaled`, :func:`f_scaled`); at ``s = 1`` they are
:func:`w_r2` and :func:`f_r2` to the last bit.
"""

from __future__ import annotations

import math

import numpy as np

from sph.engine.jit import JIT, njit

GAUSSIAN = 0
WENDLAND = 1
KERNELS = {"gaussian": GAUSSIAN, "wendland": WENDLAND}
#: support radius in units of h
SUPPORT = {GAUSSIAN: 3.0, WENDLAND: 2.0}
#: default h/dx
DEFAULT_H_FACTOR = {"gaussian": 1.23, "wendland": 1.41}

#: the Gaussian's exponential at its cut-off r = 3h
E9 = math.exp(-9.0)

# slots of the packed kernel parameters ``kp`` (:func:`kernel_params`)
KP_KIND = 0  #: GAUSSIAN or WENDLAND
KP_H = 1  #: smoothing length h
KP_ALPHA = 2  #: normalisation alpha_d
KP_R2MAX = 3  #: squared support radius
KP_INV_H2 = 4  #: 1 / h^2
KP_SIZE = 5

@njit(inline="always", **JIT)
def exp_neg(s):
    r""":math:`e^{-s}` for :math:`0 \le s \le 9` to a relative 1e-13:
    :math:`(e^{-s/64})^{64}`, the inner exponential by its 9th-order Taylor series
    (:math:`s/64 \le 0.14`, truncation below 1e-16) and the power by six squarings
    (each doubles the round-off: about 7e-14 at most over the support). Fifteen
    multiply-adds and no memory access, so that a pair loop over a neighbour list
    vectorises without gathers: the library exponential took about half the time of a
    Gaussian pair loop, and a table of :math:`e^{-k/64}` with a short series of the
    remainder (one gather per pair) about 1.13 times this one."""
    r = s * (-1.0 / 64.0)
    e = 1.0 + r * (1.0 + r * (1.0 / 2.0 + r * (1.0 / 6.0 + r * (1.0 / 24.0 + r * (
        1.0 / 120.0 + r * (1.0 / 720.0 + r * (1.0 / 5040.0 + r * (1.0 / 40320.0 + r * (
            1.0 / 362880.0)))))))))
    e = e * e
    e = e * e
    e = e * e
    e = e * e
    e = e * e
    return e * e


def kernel_params(name: str, h: float) -> np.ndarray:
    """Pack the kernel constants for the numba loops.

    Parameters
    ----------
    name : {"gaussian", "wendland"}
    h : float
        Smoothing length (m).
    """
    kind = KERNELS[name]
    if kind == GAUSSIAN:
        alpha_d = 1.0 / (math.pi * h * h * (1.0 - 10.0 * E9))
    else:
        alpha_d = 7.0 / (4.0 * math.pi * h * h)
    radius = SUPPORT[kind] * h
    kp = np.empty(KP_SIZE)
    kp[KP_KIND] = kind
    kp[KP_H] = h
    kp[KP_ALPHA] = alpha_d
    kp[KP_R2MAX] = radius * radius
    kp[KP_INV_H2] = 1.0 / (h * h)
    return kp


def support_radius(kp: np.ndarray) -> float:
    """Support radius (m) of the kernel described by ``kp``."""
    return math.sqrt(kp[KP_R2MAX])


@njit(inline="always", **JIT)
def w_r2(r2, kp):
    """Kernel value from the squared distance ``r2``; zero outside the support."""
    if r2 >= kp[KP_R2MAX]:
        return 0.0
    if kp[KP_KIND] == 0.0:
        return kp[KP_ALPHA] * (exp_neg(r2 * kp[KP_INV_H2]) - E9)
    q = math.sqrt(r2 * kp[KP_INV_H2])
    t = 1.0 - 0.5 * q
    t2 = t * t
    return kp[KP_ALPHA] * t2 * t2 * (2.0 * q + 1.0)


@njit(inline="always", **JIT)
def w_given_f(r2, fw, kp):
    """Kernel value at ``r2`` inside the support when its gradient factor ``fw`` is known
    (the Gaussian's value follows from ``fw`` without a second exponential)."""
    if kp[KP_KIND] == 0.0:
        return -0.5 * fw * kp[KP_H] * kp[KP_H] - kp[KP_ALPHA] * E9
    return w_r2(r2, kp)


@njit(inline="always", **JIT)
def f_r2(r2, kp):
    r"""Gradient factor :math:`F`, :math:`\nabla_i W_{ij} = F\,\mathbf{r}_{ij}`; 0 outside."""
    if r2 >= kp[KP_R2MAX]:
        return 0.0
    if kp[KP_KIND] == 0.0:
        return -2.0 * kp[KP_ALPHA] * kp[KP_INV_H2] * exp_neg(r2 * kp[KP_INV_H2])
    q = math.sqrt(r2 * kp[KP_INV_H2])
    t = 1.0 - 0.5 * q
    return -5.0 * kp[KP_ALPHA] * kp[KP_INV_H2] * t * t * t


@njit(inline="always", **JIT)
def pair_scale(hs, i, j):
    """Smoothing length of the pair ``(i, j)`` over the case's ``h``: the particles' own
    ratio ``hs`` when they are of one refinement level, 0 (no pair: every loop tests
    ``r2 < r2max s^2``) when they are not (:mod:`sph.engine.refinement`); 1 when ``hs`` is
    None (uniform resolution: a loop compiled for None has no trace of it)."""
    if hs is None:
        return 1.0
    return hs[i] if hs[i] == hs[j] else 0.0


@njit(inline="always", **JIT)
def w_scaled(r2, kp, s):
    """Kernel value at ``r2`` for the smoothing length ``s h``; zero outside its support."""
    inv_s2 = 1.0 / (s * s)
    return w_r2(r2 * inv_s2, kp) * inv_s2


@njit(inline="always", **JIT)
def f_scaled(r2, kp, s):
    """Gradient factor at ``r2`` for the smoothing length ``s h``; zero outside its support."""
    inv_s2 = 1.0 / (s * s)
    return f_r2(r2 * inv_s2, kp) * inv_s2 * inv_s2


@njit(inline="always", **JIT)
def fw_scaled(r2, kp, s):
    """Gradient factor and kernel value at ``r2`` inside the support of the smoothing
    length ``s h`` (one exponential for the Gaussian, :func:`w_given_f`)."""
    inv_s2 = 1.0 / (s * s)
    r2s = r2 * inv_s2
    f0 = f_r2(r2s, kp)
    return f0 * inv_s2 * inv_s2, w_given_f(r2s, f0, kp) * inv_s2
