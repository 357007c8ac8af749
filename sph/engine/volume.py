r"""The volume correction under variable resolution: the fluid fills the room its densities
say, read on a grid.

Weakly compressible SPH keeps a particle's density in step with its neighbours' spacing
through the continuity equation, whose rate is that of the kernel sum
:math:`\sum_j m_j W_{ij}`. The kernel is convex over the ring of nearest neighbours, so a
disordered arrangement reads a larger kernel sum than an ordered one of the same volume.
A jump that moves a particle without changing any density (the refinement's: a family
turning active at another level where its ghosts were, a ghost going to its family's
centre of mass, a brood of ghost children made afresh) adds disorder the densities do not
carry; the pressure then orders the particles again, and the continuity equation takes the
disorder's share off their densities as it goes. Each jump leaves the fluid a little more
closely packed than its densities say, it is heavier than its pressure holds and sinks, and
the loss grows with every jump: a sloshing tank refined in a box under its surface lost
7 % of its depth in a minute (``benchmarks/refinement_sloshing.py``,
docs/validation/refinement.md). The same tank at one resolution, with particles displaced
at random, packs the same way.

The per-level packing correction (:func:`sph.engine.refinement.packing_density`) brings
each particle's density towards its own level's kernel sum; that sum carries the
disorder's bias (the defect itself) and reads each level's lattice, ghosts included, where
the fluid is the union of the levels' active particles. The measure here is neither. Every
:data:`VOLUME_STRIDE` steps the volumes :math:`m_i/\rho_i` of the active fluid of all
levels are spread onto a grid of the coarsest spacing: each node takes a particle's volume
times the node's bilinear hat (two cells wide) averaged over the particle's own square
(side: its level's spacing). The squares of a lattice, and of two lattices meeting at a
level's edge, tile the plane and the hats sum to one, so the nodes read exactly one in the
bulk of a fluid whose densities agree with its spacing, at any level and across levels;
the weights sum to one wherever a particle is, so disorder adds scatter but no bias. The
fraction is divided by the cells' area and smoothed by a Gaussian of :data:`VOLUME_SIGMA`
cells.

Where the smoothed fraction :math:`f` at a particle (bilinear) passes :math:`1 + d`, the
particle's density (``rho_old`` with it) rises at the rate :data:`VOLUME_RATE`,
:math:`\rho \leftarrow \rho\,[1 + r\,\Delta t\,(f - 1 - d)]`, so that packed fluid takes the
pressure that spreads it again over a fraction of a second, many acoustic crossings of a
cell. Where :math:`f < 1 - d` the density falls in the same way, but only in the bulk:
where the smoothed fraction is at least :data:`VOLUME_FULL` at every node within
:data:`VOLUME_REACH` cells (the smoothing's reach). Near a free surface, a wall or a hull's
dry compartment a node reads low because part of its cell is empty (and wall particles
are not counted: a hull's plating is layers of particles closer than the fluid's spacing),
so there only an excess is taken; the smoothing mixes in empty cells and can only lower a
reading there. The dead band :math:`d` (:data:`VOLUME_DEAD`; :data:`VOLUME_DEAD_EDGE`
outside the bulk) is the scatter the smoothed fraction reads in an ordered flow. Ghosts
carry no mass and are not counted.

The correction runs under variable resolution only: a uniform run has no jumps, and its
scheme is the one validated against the benchmarks of docs/validation.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import ndimage

from sph.engine.jit import JIT, njit
from sph.engine.particles import FLUID, GHOST

#: rate (1/s) at which a density takes the fraction's excess over the dead band: the
#: mismatch relaxes over 1 / VOLUME_RATE s, many acoustic crossings of a cell
VOLUME_RATE = 6.0
#: steps between corrections (each takes the rate over that many steps): a pass costs
#: 7.5 % of a refined ship step (docs/performance.md)
VOLUME_STRIDE = 4
#: dead band of the fraction in a full neighbourhood: the smoothed reading's scatter in an
#: ordered flow (0.999-1.001 at the 1st-99th percentile in the sloshing tank at 3 s)
VOLUME_DEAD = 0.01
#: dead band elsewhere, where only an excess is taken
VOLUME_DEAD_EDGE = 0.01
#: width of the smoothing Gaussian, in cells
VOLUME_SIGMA = 1.0
#: a node's neighbourhood is full where every node within ``VOLUME_REACH`` (the smoothing's
#: reach) reads at least ``VOLUME_FULL`` after smoothing
VOLUME_FULL = 0.9
VOLUME_REACH = 3


@njit(inline="always", **JIT)
def _hat_integral(u):
    """Integral of the hat max(0, 1 - |v|) from -infinity to ``u``."""
    if u <= -1.0:
        return 0.0
    if u <= 0.0:
        return 0.5 * (u + 1.0) * (u + 1.0)
    if u < 1.0:
        return 1.0 - 0.5 * (1.0 - u) * (1.0 - u)
    return 1.0


@njit(inline="always", **JIT)
def _weights(c, half, x0, inv):
    """First node and the weights of up to three nodes along one axis: the hat of each
    node (width two cells) averaged over the particle's extent ``c +- half``."""
    a = (c - half - x0) * inv - 0.5
    b = (c + half - x0) * inv - 0.5
    i0 = int(math.floor(a))
    scale = 1.0 / (b - a)
    w0 = scale * (_hat_integral(b - i0) - _hat_integral(a - i0))
    w1 = scale * (_hat_integral(b - i0 - 1) - _hat_integral(a - i0 - 1))
    w2 = scale * (_hat_integral(b - i0 - 2) - _hat_integral(a - i0 - 2))
    return i0, w0, w1, w2


@njit(**JIT)
def deposit(x, z, rho, m, hs, kind, body, x0, z0, spacing, grid):
    """Add the volume ``m / rho`` of every active fluid particle (not a ghost) to ``grid``.
    Node ``(i, k)`` sits at ``(x0 + (i + 1/2) spacing, z0 + (k + 1/2) spacing)`` and takes the
    particle's volume times its hat (bilinear, two cells wide) averaged over the particle's
    square, of side its own spacing ``spacing * hs`` (the grid's spacing is the coarsest
    level's): the squares of a lattice, or of two lattices meeting at an interface, tile
    the plane, so that the nodes read exactly one wherever they do. A particle with a node
    outside the grid is left out."""
    nx, nz = grid.shape
    inv = 1.0 / spacing
    for n in range(x.shape[0]):
        if kind[n] != FLUID or body[n] == GHOST:
            continue
        half = 0.5 * spacing * hs[n]
        i0, a0, a1, a2 = _weights(x[n], half, x0, inv)
        k0, b0, b1, b2 = _weights(z[n], half, z0, inv)
        if i0 < 0 or k0 < 0 or i0 + 2 >= nx or k0 + 2 >= nz:
            continue
        v = m[n] / rho[n]
        for di, wa in ((0, a0), (1, a1), (2, a2)):
            if wa == 0.0:
                continue
            for dk, wb in ((0, b0), (1, b1), (2, b2)):
                grid[i0 + di, k0 + dk] += v * wa * wb


@njit(**JIT)
def correct(x, z, rho, rho_old, kind, body, x0, z0, spacing, frac, full, relax, dead,
            dead_edge, factor):
    """Scale the density of each active fluid particle by the fraction ``frac`` read at it
    (bilinear; the nearest node's ``full``), as the module says; ``factor[n]``: the factor
    applied (1 where none)."""
    nx, nz = frac.shape
    inv = 1.0 / spacing
    for n in range(x.shape[0]):
        factor[n] = 1.0
        if kind[n] != FLUID or body[n] == GHOST:
            continue
        u = (x[n] - x0) * inv - 0.5
        w = (z[n] - z0) * inv - 0.5
        i = int(math.floor(u))
        k = int(math.floor(w))
        if i < 0 or k < 0 or i + 1 >= nx or k + 1 >= nz:
            continue
        fu = u - i
        fw = w - k
        f = ((1.0 - fu) * (1.0 - fw) * frac[i, k] + fu * (1.0 - fw) * frac[i + 1, k]
             + (1.0 - fu) * fw * frac[i, k + 1] + fu * fw * frac[i + 1, k + 1])
        if full[i + int(fu >= 0.5), k + int(fw >= 0.5)]:
            e = f - 1.0
            e = e - dead if e > dead else (e + dead if e < -dead else 0.0)
        else:
            e = f - 1.0 - dead_edge if f > 1.0 + dead_edge else 0.0
        if e != 0.0:
            s = 1.0 + relax * e
            rho[n] *= s
            rho_old[n] *= s
            factor[n] = s


class VolumeCorrection:
    """The grid over ``bounds = (xmin, xmax, zmin, zmax)`` at ``spacing`` (the coarsest
    level's particle spacing) and the correction of the module's docstring."""

    def __init__(self, bounds, spacing: float):
        xmin, xmax, zmin, zmax = bounds
        self.spacing = float(spacing)
        self.x0, self.z0 = float(xmin), float(zmin)
        self.shape = (int(math.ceil((xmax - xmin) / spacing)) + 1,
                      int(math.ceil((zmax - zmin) / spacing)) + 1)
        self._factor = np.empty(0)

    def fraction(self, parts, select=None) -> tuple[np.ndarray, np.ndarray]:
        """The smoothed volume fraction on the grid's nodes and whether each node's
        neighbourhood is full (module docstring); ``select``: a mask of the particles to
        count (all active fluid where None), as a diagnostic of one level's share."""
        kind = parts.kind if select is None else np.where(select, parts.kind, -1).astype(
            parts.kind.dtype)
        grid = np.zeros(self.shape)
        deposit(parts.x, parts.z, parts.rho, parts.m, parts.hs, kind, parts.body,
                self.x0, self.z0, self.spacing, grid)
        grid /= self.spacing * self.spacing
        frac = ndimage.gaussian_filter(grid, VOLUME_SIGMA, mode="constant", cval=0.0)
        full = ndimage.minimum_filter(frac, size=2 * VOLUME_REACH + 1, mode="constant",
                                      cval=0.0) >= VOLUME_FULL
        return frac, full

    def apply(self, parts, dt: float) -> np.ndarray:
        """Correct the densities of ``parts`` over a step of ``dt`` s; returns the factor
        each density took (1 where none)."""
        if self._factor.shape[0] != parts.x.shape[0]:
            self._factor = np.empty(parts.x.shape[0])
        frac, full = self.fraction(parts)
        correct(parts.x, parts.z, parts.rho, parts.rho_old, parts.kind, parts.body,
                self.x0, self.z0, self.spacing, frac, full, VOLUME_RATE * dt, VOLUME_DEAD,
                VOLUME_DEAD_EDGE, self._factor)
        return self._factor
