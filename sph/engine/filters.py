r"""Density filters: first-order MLS re-initialisation and the delta-SPH density gradient.

``mls`` (Cao et al. 2019, Eq. 8; Colagrossi & Landrini 2003): every ``mls_interval`` steps

.. math:: \rho_i = \sum_j m_j W^{MLS}_{ij},\qquad
          W^{MLS}_{ij} = \left[\beta_0 + \beta_1 (x_i - x_j) + \beta_2 (z_i - z_j)\right] W_{ij},

with :math:`\boldsymbol\beta_i = \mathbf{A}_i^{-1}(1, 0, 0)^T` and
:math:`\mathbf{A}_i = \sum_j W_{ij}\tilde{\mathbf{A}}_{ij} V_j`,
:math:`\tilde{\mathbf{A}}_{ij} = \mathbf{p}_{ij}\mathbf{p}_{ij}^T`, :math:`\mathbf{p}_{ij} =
(1, x_i - x_j, z_i - z_j)`. The sum runs over fluid and wall particles of the same
compartment, and fluid particles seen through an open damage opening (:mod:`sph.bodies.damage`);
wall densities carry the extrapolated hydrostatic pressure. Where
:math:`\mathbf{A}_i` is ill-conditioned (isolated particles) the zeroth-order Shepard
filter is used instead. A linear density field is reproduced exactly.

``delta`` (second source paper, Eq. 2): the renormalised density gradient

.. math:: \langle\nabla\rho\rangle^L_i = \mathbf{L}_i\sum_j (\rho_j - \rho_i)\nabla_i W_{ij} V_j,
          \qquad \mathbf{L}_i = \left[\sum_j (\mathbf{r}_j - \mathbf{r}_i)\otimes
          \nabla_i W_{ij} V_j\right]^{-1}

over fluid neighbours, used by the diffusive term in :func:`sph.engine.fluid.interact`.
"""

from __future__ import annotations

from numba import prange

from sph.engine.jit import JIT, JIT_PARALLEL, njit
from sph.engine.kernels import KP_R2MAX, f_scaled, pair_scale, w_scaled
from sph.engine.opening import in_sight, passable
from sph.engine.particles import FLUID


@njit(inline="always", **JIT)
def mls_solve(a11, a12, a13, a22, a23, a33):
    r"""The first row of the inverse of the symmetric first-order MLS moment matrix
    :math:`A = \sum_j \mathbf{b}_j\mathbf{b}_j^T W_j V_j`, :math:`\mathbf{b} = (1, dx,
    dz)`, as cofactors over the determinant: ``c11, c12, c13, det``; the fit of a field
    with moments ``f0, f1, f2`` is ``(c11 f0 + c12 f1 + c13 f2) / det``. ``regular``:
    false where :math:`A` is near singular (the caller then takes the Shepard mean)."""
    c11 = a22 * a33 - a23 * a23
    c12 = -(a12 * a33 - a13 * a23)
    c13 = a12 * a23 - a13 * a22
    det = a11 * c11 + a12 * c12 + a13 * c13
    return c11, c12, c13, det, det > 1.0e-3 * a11 * a22 * a33 and det > 0.0


@njit(**JIT_PARALLEL)
def mls_density(x, z, rho, m, kind, body, comp, hs, cell_of, cell_start, ncx, kp, out, op,
                kin):
    """First-order MLS density of every fluid particle into ``out`` (walls copied); each
    pair takes its own smoothing length (``hs``, :func:`sph.engine.kernels.pair_scale`)."""
    n = x.shape[0]
    r2max = kp[KP_R2MAX]
    for i in prange(n):
        if kind[i] != FLUID:
            out[i] = rho[i]
            continue
        xi = x[i]
        zi = z[i]
        ci = comp[i]
        a11 = a12 = a13 = a22 = a23 = a33 = 0.0
        s0 = s1 = s2 = 0.0
        c = cell_of[i]
        for row in (c - ncx, c, c + ncx):
            for j in range(cell_start[row - 1], cell_start[row + 2]):
                ok, dx, dz, r2, s = in_sight(i, j, xi, zi, ci, x, z, kind, body, comp, hs,
                                             r2max, op, kin)
                if not ok:
                    continue
                w = w_scaled(r2, kp, s)
                mw = m[j] * w
                vw = mw / rho[j]
                a11 += vw
                a12 += vw * dx
                a13 += vw * dz
                a22 += vw * dx * dx
                a23 += vw * dx * dz
                a33 += vw * dz * dz
                s0 += mw
                s1 += mw * dx
                s2 += mw * dz
        c11, c12, c13, det, regular = mls_solve(a11, a12, a13, a22, a23, a33)
        if regular:
            out[i] = (c11 * s0 + c12 * s1 + c13 * s2) / det
        elif a11 > 0.0:
            out[i] = s0 / a11
        else:
            out[i] = rho[i]


@njit(**JIT_PARALLEL)
def renormalised_density_gradient(x, z, rho, m, kind, comp, hs, cell_of, cell_start, ncx, kp,
                                  grx, grz, op, kin):
    """Renormalised density gradient of every fluid particle (zero where L is singular);
    smoothing length per pair as in :func:`mls_density`."""
    n = x.shape[0]
    r2max = kp[KP_R2MAX]
    for i in prange(n):
        grx[i] = 0.0
        grz[i] = 0.0
        if kind[i] != FLUID:
            continue
        xi = x[i]
        zi = z[i]
        rhoi = rho[i]
        ci = comp[i]
        mxx = mxz = mzz = 0.0
        gx = gz = 0.0
        c = cell_of[i]
        for row in (c - ncx, c, c + ncx):
            for j in range(cell_start[row - 1], cell_start[row + 2]):
                if kind[j] != FLUID or j == i:
                    continue
                dx = xi - x[j]
                dz = zi - z[j]
                r2 = dx * dx + dz * dz
                s = pair_scale(hs, i, j)
                if r2 >= r2max * s * s:
                    continue
                if comp[j] != ci and not passable(xi, zi, x[j], z[j], ci, comp[j], op, kin):
                    continue
                fv = f_scaled(r2, kp, s) * m[j] / rho[j]
                mxx -= fv * dx * dx
                mxz -= fv * dx * dz
                mzz -= fv * dz * dz
                d = (rho[j] - rhoi) * fv
                gx += d * dx
                gz += d * dz
        det = mxx * mzz - mxz * mxz
        if det > 1.0e-3:
            grx[i] = (mzz * gx - mxz * gz) / det
            grz[i] = (-mxz * gx + mxx * gz) / det
