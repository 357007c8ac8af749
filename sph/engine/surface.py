r"""Free-surface particles, and whether a wall may pull on fluid (``numerics.wall_tension``).

**Detection** (Marrone, Colagrossi, Le Touzé & Graziani 2010, J. Comput. Phys. 229, 3652,
Secs. 2.1-2.2). The renormalisation matrix of fluid particle :math:`i`,

.. math::
    \mathbf{M}_i = \sum_j (\mathbf{r}_j - \mathbf{r}_i)\otimes\nabla_i W_{ij}\,V_j,

summed over every particle it sees (fluid and wall: the wall layers complete the support
as the fluid would), is the identity inside the fluid and loses rank where the support is
cut by the free surface. Its trace is the divergence of the position that the shifting
tests (:mod:`sph.engine.shifting`, 2 inside); its smallest eigenvalue :math:`\lambda_i`
separates the particles: :math:`\lambda_i \le 0.2` (``LAMBDA_SURFACE``, a splash or a thin
film) is at the surface, :math:`\lambda_i > 0.75` (``LAMBDA_INTERIOR``) inside; in between
the particle is tested with the scan region. With the normal

.. math::
    \mathbf{n}_i = \frac{\boldsymbol\nu_i}{|\boldsymbol\nu_i|},\qquad
    \boldsymbol\nu_i = -\mathbf{M}_i^{-1}\sum_j \nabla_i W_{ij}\,V_j

(the renormalised gradient of the kernel sum, pointing out of the fluid), its tangent
:math:`\boldsymbol\tau_i` and the point :math:`T = \mathbf{r}_i + h\,\mathbf{n}_i`, the
particle is at the free surface when no fluid particle lies in the "umbrella" above it:
no fluid :math:`j` with :math:`|\mathbf{r}_j - \mathbf{r}_T| < h` at
:math:`|\mathbf{r}_j - \mathbf{r}_i| \ge \sqrt2 h`, nor with
:math:`|\mathbf{n}_i\cdot(\mathbf{r}_j - \mathbf{r}_T)| + |\boldsymbol\tau_i\cdot
(\mathbf{r}_j - \mathbf{r}_T)| < h` closer than :math:`\sqrt2 h` (their Eq. 9). Wall
particles do not fill the umbrella: fluid at a wall's waterline has wall particles above it
beside the cone, and it is at the surface all the same. Under variable resolution
(:mod:`sph.engine.refinement`) the pairs take their own smoothing lengths and the scan its
particle's own ``h``.

**Walls and tension** (the second source paper, Sec. 2.2, Eq. 6). The pressure term of a
fluid particle :math:`i` and a wall particle :math:`j` is :math:`(P_i + P_j)\nabla_i W_{ij}`;
a negative sum means the wall pulls the fluid. Three rules (config key
``numerics.wall_tension``):

``clamp`` (default)
    :math:`\max(P_i, 0) + P_j` with the wall pressure clamped at zero
    (:func:`sph.engine.walls.wall_pressure`): no wall ever pulls on any fluid particle.
``free_surface``
    Eq. 6: :math:`\max(P_i + P_j, 0)` when :math:`i` is a free-surface particle,
    :math:`P_i + P_j` otherwise: the surface separates from a wall freely, while fluid inside
    the flow, in tension, stays attached to a wall that draws away from it (as a real liquid
    does, above its vapour pressure). The wall pressure stays clamped at zero: a wall
    particle in tension pulls the fluid next to it through the wall layers (``none``
    loses particles through a flap pulled back at 1.5 g, docs/validation/wall_tension.md).
``none``
    :math:`P_i + P_j` everywhere, the wall pressure not clamped (the second source paper
    without its Eq. 6).

The same sum, with the same clamp, gives the force of the fluid on a moving body
(:func:`sph.engine.walls.wall_forces`): action and reaction stay equal. Every loop takes it
as :math:`\max(a_i + P_j, f_i)` with ``(a_i, f_i)`` from :func:`wall_pair_terms`; under
``clamp`` it is :math:`a_i = \max(P_i, 0)` and :math:`f_i = -\infty`: the sum as it was
before the option existed, to the last bit.
"""

from __future__ import annotations

import math

from numba import prange

from sph.engine.jit import JIT, JIT_PARALLEL, njit
from sph.engine.kernels import KP_H, KP_R2MAX, fw_scaled, pair_scale
from sph.engine.opening import in_sight, sees
from sph.engine.particles import FLUID

#: smallest eigenvalue of the renormalisation matrix at or below which a particle is at the
#: free surface without a scan, and above which it is inside (Marrone et al. 2010, Sec. 2.1)
LAMBDA_SURFACE = 0.2
LAMBDA_INTERIOR = 0.75

#: the rules of ``numerics.wall_tension`` (module docstring)
CLAMP = 0
FREE_SURFACE = 1
NONE = 2
WALL_TENSION = {"clamp": CLAMP, "free_surface": FREE_SURFACE, "none": NONE}


@njit(inline="always", **JIT)
def wall_pair_terms(pi, tension, surf, i):
    r"""``(a_i, f_i)`` of fluid particle ``i`` of pressure ``pi`` for its pairs with wall
    particles: the pressure term is :math:`\max(a_i + P_j, f_i)` (module docstring).
    ``surf``: the free-surface flags (:func:`free_surface`), None unless ``tension`` is
    ``FREE_SURFACE``."""
    if tension == CLAMP:
        return max(pi, 0.0), -math.inf
    if surf is not None:
        if tension == FREE_SURFACE and surf[i]:
            return pi, 0.0
    return pi, -math.inf


@njit(inline="always", **JIT)
def smallest_eigenvalue(a, b, c):
    """Smallest eigenvalue of the symmetric matrix ``[[a, b], [b, c]]``."""
    half = 0.5 * (a - c)
    return 0.5 * (a + c) - math.sqrt(half * half + b * b)


@njit(**JIT_PARALLEL)
def free_surface(x, z, m, rho, kind, body, comp, hs, kp, op, kin, start, inner, inner_end,
                 lam, surf):
    r"""Flag the free-surface fluid particles (Marrone et al. 2010; module docstring).

    Writes the smallest eigenvalue :math:`\lambda_i` of the renormalisation matrix into
    ``lam`` and the flag into ``surf`` (wall particles: 1 and False). Neighbours: the
    particle's inner list ``inner[start[i]:inner_end[i]]``
    (:class:`sph.engine.neighbours.NeighbourList`) within the support, by the pair rule of
    the momentum equation (:func:`sph.engine.opening.sees`: compartments, the damage
    opening ``op``). ``hs``: each particle's smoothing length ratio, None at uniform
    resolution."""
    r2max = kp[KP_R2MAX]
    for i in prange(x.shape[0]):
        if kind[i] != FLUID:
            lam[i] = 1.0
            surf[i] = False
            continue
        xi = x[i]
        zi = z[i]
        ci = comp[i]
        mxx = 0.0
        mxz = 0.0
        mzz = 0.0
        gx = 0.0
        gz = 0.0
        for k in range(start[i], inner_end[i]):
            j = inner[k]
            ok, dx, dz, r2, s = in_sight(i, j, xi, zi, ci, x, z, kind, body, comp, hs, r2max,
                                         op, kin)
            if j == i or not ok:
                continue
            fw, _ = fw_scaled(r2, kp, s)
            a = fw * m[j] / rho[j]  # grad_i W_ij V_j = a (r_i - r_j)
            # (r_j - r_i) (x) grad_i W_ij V_j = -a (r_i - r_j) (x) (r_i - r_j)
            mxx -= a * dx * dx
            mxz -= a * dx * dz
            mzz -= a * dz * dz
            gx += a * dx
            gz += a * dz
        li = smallest_eigenvalue(mxx, mxz, mzz)
        lam[i] = li
        if li <= LAMBDA_SURFACE:
            surf[i] = True
            continue
        if li > LAMBDA_INTERIOR:
            surf[i] = False
            continue
        det = mxx * mzz - mxz * mxz  # > li^2 > 0 here
        nx = -(mzz * gx - mxz * gz) / det
        nz = -(-mxz * gx + mxx * gz) / det
        nn = math.sqrt(nx * nx + nz * nz)
        if nn == 0.0:
            surf[i] = True
            continue
        nx /= nn
        nz /= nn
        surf[i] = not _umbrella_filled(i, xi, zi, ci, nx, nz, x, z, kind, body, comp, hs,
                                       kp, op, kin, start, inner, inner_end)


@njit(**JIT)
def _umbrella_filled(i, xi, zi, ci, nx, nz, x, z, kind, body, comp, hs, kp, op, kin, start,
                     inner, inner_end):
    """Whether a fluid particle lies in the scan region of particle ``i`` with outward
    normal ``(nx, nz)`` (Marrone et al. 2010, Eq. 9)."""
    h = kp[KP_H] * pair_scale(hs, i, i)
    h2 = h * h
    tx = xi + h * nx
    tz = zi + h * nz
    for k in range(start[i], inner_end[i]):
        j = inner[k]
        if kind[j] != FLUID or j == i:
            continue
        rx = x[j] - xi
        rz = z[j] - zi
        ux = x[j] - tx
        uz = z[j] - tz
        if rx * rx + rz * rz >= 2.0 * h2:
            inside = ux * ux + uz * uz < h2
        else:
            inside = abs(nx * ux + nz * uz) + abs(-nz * ux + nx * uz) < h
        if inside and sees(xi, zi, ci, x[j], z[j], kind[j], body[j], comp[j], op, kin):
            return True
    return False
