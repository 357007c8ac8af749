r"""Variable resolution: boxes of finer particles, split on the way in, merged on the way out.

The case file's ``numerics.refinement`` lists boxes, each of a level ``l`` from 1 to
:data:`sph.engine.config.MAX_LEVEL`; a particle of level ``l`` has the spacing
:math:`\Delta x_l = \Delta x / 2^l`, the mass :math:`m / 4^l` and the smoothing length
:math:`h_l = h / 2^l` (the particle field ``hs`` holds :math:`2^{-l}`). A box of level
``l > 1`` lies inside one of level ``l - 1``, so that the spacing changes by a ratio of two
across every level boundary.

**Pairs of different sizes** take the mean smoothing length :math:`h_{ij} = (h_i + h_j)/2`
(:func:`sph.engine.kernels.pair_scale`), in every pair loop of the engine, so that
:math:`\nabla_i W_{ij} = -\nabla_j W_{ji}` and the pressure and viscous forces of a pair stay
equal and opposite: momentum is conserved across level boundaries as within a level
(Vacondio et al. 2013, Sec. 2; Barcarolo et al. 2014, Sec. 3). The time step is global,
set by the finest level.

**Splitting** (Feldman & Bonet 2007; Barcarolo et al. 2014, the square pattern of ratio 2):
a particle whose position lies in a box of a level above its own is replaced by four
children of a quarter of its mass at :math:`\pm\Delta x_l/4` along both axes, with its
velocity, density and pressure. Mass, momentum and centre of mass are kept exactly, and a
lattice of spacing :math:`\Delta x_l` becomes one of spacing :math:`\Delta x_l/2`: the initial
refinement of a case built at ``numerics.dx`` (fluid and fixed walls alike, so that walls are
as fine as the fluid beside them) is the exact fine lattice.

**Merging** (coalescing; Vacondio et al. 2013, Sec. 3.2, in groups of four so that a merged
particle is again of the coarser level): a fluid particle of level ``l`` that lies farther
than one spacing of level ``l - 1`` outside every box of level ``l`` (the hysteresis that
keeps a particle at the boundary from splitting and merging over and over) is a candidate.
Candidates of one level and one compartment are grouped four by four, each with the three
others within :math:`1.5\,\Delta x_l` that make the most compact group (least second moment
about their centroid), in index order; a candidate that finds no three partners stays fine
until more arrive. A group becomes one particle at its centre of mass with the total mass,
the velocity of the total momentum (kept to round-off), and the density that keeps the
group's volume, :math:`\rho = \sum m_k / \sum (m_k/\rho_k)`.

The checks run when the neighbour lists are rebuilt (:mod:`sph.engine.neighbours`: no
particle has then moved more than half the lists' skin, a fraction of a fine spacing, since
the previous ones), so that splitting and merging cost nothing between rebuilds and a run
restarted from a checkpoint splits and merges exactly as the uninterrupted one.

Not done here: per-level time steps (Chiron et al. 2018) and the overlapping buffer of
Chiron et al. (2018) that interpolates the coarse and fine fields across the boundary.
"""

from __future__ import annotations

import numpy as np

from sph.engine.jit import JIT, njit
from sph.engine.particles import _FI, _II, FLUID, Particles

#: columns of the packed boxes (:func:`pack_boxes`)
BX_XMIN, BX_XMAX, BX_ZMIN, BX_ZMAX, BX_LEVEL = range(5)
#: merge candidates search their partners within this many spacings of their level
MERGE_RADIUS = 1.5
#: a particle merges only this many spacings of the coarser level outside its level's boxes
MERGE_MARGIN = 1.0


def pack_boxes(boxes) -> np.ndarray:
    """The boxes of ``numerics.refinement`` as an ``(n, 5)`` array for the numba loops."""
    out = np.zeros((len(boxes), 5))
    for k, b in enumerate(boxes):
        out[k] = (b.x[0], b.x[1], b.z[0], b.z[1], b.level)
    return out


@njit(**JIT)
def level_at(x, z, boxes, pad):
    """Finest level of the boxes containing ``(x, z)``, each grown by ``pad`` times
    ``2^(1 - level)`` (0 outside every box): with ``pad = c dx``, by ``c`` spacings of the
    level below its own."""
    best = 0
    for k in range(boxes.shape[0]):
        lev = boxes[k, BX_LEVEL]
        g = pad * 2.0 ** (1.0 - lev)
        if (boxes[k, BX_XMIN] - g <= x <= boxes[k, BX_XMAX] + g
                and boxes[k, BX_ZMIN] - g <= z <= boxes[k, BX_ZMAX] + g):
            best = max(best, int(lev))
    return best


def _levels(parts: Particles, boxes, dx, pad, fluid_only):
    """Target level of every particle (``pad``: :func:`level_at`, in spacings ``dx``) and
    its own level (:func:`levels`); walls get their own level when ``fluid_only``."""
    own = levels(parts.hs)
    return _targets(parts.x, parts.z, parts.kind, own, boxes, pad * dx, fluid_only), own


@njit(**JIT)
def _targets(x, z, kind, own, boxes, pad, fluid_only):
    target = np.empty(x.shape[0], dtype=np.int32)
    for i in range(x.shape[0]):
        if fluid_only and kind[i] != FLUID:
            target[i] = own[i]
        else:
            target[i] = level_at(x[i], z[i], boxes, pad)
    return target


def split(parts: Particles, boxes: np.ndarray, dx: float, grad_rho=(0.0, 0.0),
          fluid_only: bool = True) -> tuple[Particles, int]:
    r"""Split every particle that lies in a box of a finer level than its own, repeatedly
    until none does. Returns the new set (``parts`` itself when nothing split) and the
    number of particles split. Walls are split only when not ``fluid_only`` (the initial
    refinement). ``grad_rho``: the hydrostatic density gradient
    :math:`(\rho_0 / c_0^2)\,\mathbf{g}`; a child's density is its parent's plus this
    gradient times its offset, so that a fluid at rest stays in hydrostatic balance (a
    copied density would leave a pressure error of :math:`\rho g \Delta x_l / 4`)."""
    n_split = 0
    while True:
        target, own = _levels(parts, boxes, dx, 0.0, fluid_only)
        sel = np.nonzero(target > own)[0]
        if len(sel) == 0:
            return parts, n_split
        n_split += len(sel)
        parts = _replace(parts, sel, _children(parts, sel, dx, grad_rho))


def _children(parts: Particles, sel: np.ndarray, dx: float, grad_rho
              ) -> tuple[np.ndarray, np.ndarray]:
    """Float and integer columns of the four children of each particle ``sel``."""
    f = np.repeat(parts.f[:, sel], 4, axis=1)
    i = np.repeat(parts.i[:, sel], 4, axis=1)
    quarter = 0.25 * dx * np.repeat(parts.hs[sel], 4)
    ox = np.tile([-1.0, 1.0, -1.0, 1.0], len(sel)) * quarter
    oz = np.tile([-1.0, -1.0, 1.0, 1.0], len(sel)) * quarter
    for name, off in (("x", ox), ("z", oz), ("bx", ox), ("bz", oz), ("x_sort", ox),
                      ("z_sort", oz), ("x_inner", ox), ("z_inner", oz)):
        f[_FI[name]] += off
    fluid = i[_II["kind"]] == FLUID
    for name in ("rho", "rho_old"):
        f[_FI[name]] += np.where(fluid, grad_rho[0] * ox + grad_rho[1] * oz, 0.0)
    f[_FI["m"]] *= 0.25
    f[_FI["hs"]] *= 0.5
    f[_FI["sx"]] = 0.0
    f[_FI["sz"]] = 0.0
    # the first child keeps the parent's id, the others take new ones
    first = parts.i[_II["pid"]].max() + 1
    new = first + np.arange(3 * len(sel), dtype=np.int64).reshape(-1, 3)
    pid = i[_II["pid"]].reshape(-1, 4)
    pid[:, 1:] = new
    return f, i


def _replace(parts: Particles, remove: np.ndarray, add: tuple[np.ndarray, np.ndarray]
             ) -> Particles:
    """A new set: ``parts`` without the particles ``remove``, then the columns ``add``."""
    keep = np.ones(parts.n, dtype=bool)
    keep[remove] = False
    f, i = add
    return Particles.of_columns(np.concatenate([parts.f[:, keep], f], axis=1),
                                np.concatenate([parts.i[:, keep], i], axis=1))


@njit(**JIT)
def _groups(x, z, comp, own, cand, dx):
    """Groups of four merge candidates (indices ``cand``, in order): each with the three
    other free candidates of its level and compartment within :data:`MERGE_RADIUS`
    spacings that make the least second moment about their centroid."""
    nc = cand.shape[0]
    used = np.zeros(nc, dtype=np.bool_)
    out = np.empty((nc // 4 + 1, 4), dtype=np.int64)
    ng = 0
    near = np.empty(64, dtype=np.int64)
    for a in range(nc):
        if used[a]:
            continue
        i = cand[a]
        d = dx * 2.0 ** (-own[i])
        r2 = (MERGE_RADIUS * d) ** 2
        nn = 0
        for b in range(nc):
            j = cand[b]
            if b == a or used[b] or own[j] != own[i] or comp[j] != comp[i]:
                continue
            ddx = x[i] - x[j]
            ddz = z[i] - z[j]
            if ddx * ddx + ddz * ddz < r2 and nn < near.shape[0]:
                near[nn] = b
                nn += 1
        if nn < 3:
            continue
        best = np.inf
        pick = (0, 0, 0)
        for p in range(nn):
            for q in range(p + 1, nn):
                for r in range(q + 1, nn):
                    ks = (i, cand[near[p]], cand[near[q]], cand[near[r]])
                    cx = 0.25 * (x[ks[0]] + x[ks[1]] + x[ks[2]] + x[ks[3]])
                    cz = 0.25 * (z[ks[0]] + z[ks[1]] + z[ks[2]] + z[ks[3]])
                    mom = 0.0
                    for k in ks:
                        mom += (x[k] - cx) ** 2 + (z[k] - cz) ** 2
                    if mom < best:
                        best = mom
                        pick = (near[p], near[q], near[r])
        used[a] = True
        out[ng, 0] = i
        for c, b in enumerate(pick):
            used[b] = True
            out[ng, c + 1] = cand[b]
        ng += 1
    return out[:ng]


def merge(parts: Particles, boxes: np.ndarray, dx: float) -> tuple[Particles, int]:
    """Merge the fluid particles that lie outside the boxes of their level (beyond the
    margin), four into one. Returns the new set (``parts`` itself when nothing merged) and
    the number of merged groups."""
    target, own = _levels(parts, boxes, dx, MERGE_MARGIN, True)
    cand = np.nonzero((target < own) & (parts.kind == FLUID))[0]
    if len(cand) < 4:
        return parts, 0
    groups = _groups(parts.x, parts.z, parts.comp, own, cand, dx)
    if len(groups) == 0:
        return parts, 0
    f = parts.f[:, groups]  # (field, group, member)
    m = f[_FI["m"]]
    mass = m.sum(axis=1)
    merged = f[:, :, 0].copy()
    for name in ("x", "z", "vx", "vz", "vx_old", "vz_old", "ax", "az", "bx", "bz",
                 "x_sort", "z_sort", "x_inner", "z_inner"):
        merged[_FI[name]] = (m * f[_FI[name]]).sum(axis=1) / mass
    for name in ("rho", "rho_old"):  # the density that keeps the group's volume
        merged[_FI[name]] = mass / (m / f[_FI[name]]).sum(axis=1)
    merged[_FI["m"]] = mass
    merged[_FI["p"]] = (m * f[_FI["p"]]).sum(axis=1) / mass
    merged[_FI["drho"]] = 0.0
    merged[_FI["sx"]] = 0.0
    merged[_FI["sz"]] = 0.0
    merged[_FI["hs"]] = 2.0 * f[_FI["hs"], :, 0]
    ints = parts.i[:, groups[:, 0]].copy()
    ints[_II["pid"]] = parts.i[_II["pid"]][groups].min(axis=1)
    return _replace(parts, groups.ravel(), (merged, ints)), len(groups)


def levels(hs: np.ndarray) -> np.ndarray:
    """Refinement level of each particle from its smoothing length ratio ``hs``."""
    return np.rint(-np.log2(hs)).astype(np.int32)


def level_counts(parts: Particles, n_levels: int) -> np.ndarray:
    """Fluid particles per level ``0 .. n_levels``."""
    lev = levels(parts.hs[parts.kind == FLUID])
    return np.bincount(lev, minlength=n_levels + 1)[:n_levels + 1].astype(np.float64)
