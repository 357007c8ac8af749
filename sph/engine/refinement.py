r"""Variable resolution: boxes of finer particles coupled to the coarser ones through
overlapping buffers of ghost particles (adaptive particle refinement).

The case file's ``numerics.refinement`` lists boxes, each of a level ``l`` from 1 to
:data:`sph.engine.config.MAX_LEVEL`; a particle of level ``l`` has the spacing
:math:`\Delta x_l = \Delta x / 2^l`, the mass :math:`m / 4^l` and the smoothing length
:math:`h_l = h / 2^l` (the particle field ``hs`` holds :math:`2^{-l}`). A box of level
``l > 1`` lies inside one of level ``l - 1``, so that the spacing changes by a ratio of two
across every level boundary.

**Each level sees only its own size** (Barcarolo et al. 2014; Chiron et al. 2018, J. Comput.
Phys. 354, Secs. 2-3). Pairs of different levels do not interact
(:func:`sph.engine.kernels.pair_scale` is zero for them), so every kernel sum is taken
over a lattice of one spacing, as at uniform resolution. A first attempt let pairs of
different sizes interact with the mean smoothing length (Vacondio et al. 2013): the
zeroth-order consistency :math:`h\,|\sum_j V_j \nabla W_{ij}|` of the lattice, zero in a
uniform one, reached 0.22 at the boundary, a spurious force of several m/s^2 at 1 m depth,
and a still tank did not settle. Here the fluid of level ``l`` is *active* (it carries the
mass and is integrated) inside the region of level ``l`` (its boxes less those of a finer
level) and a *ghost* around it:

- inside a finer box, where the coarser particles are kept as ghosts (the inactive mother
  particles of Chiron et al.), so that an active coarse particle near the boundary finds
  a complete coarse lattice within its support;
- in a buffer around its own boxes, :data:`BUFFER` spacings wide (the kernel support and
  the lists' skin, plus one spacing), where the fine ghosts (passive children) complete
  the fine lattice of the active fine particles near the boundary.

A ghost's density and velocity are interpolated every step from the active particles
around it, of every level, by a first-order moving least squares fit with each source's
own kernel (:func:`ghost_fields`: exact for a linear field, so a fluid at rest keeps its
hydrostatic pressure across a boundary); its pressure follows from the equation of state.
A ghost moves with its interpolated velocity; it exerts pressure and viscous forces on the
active particles of its level, and nothing acts back on it. So it pushes and never pulls
(:mod:`sph.engine.fluid`: their pressure sum counts only when positive, as against a wall):
a pull is not balanced, and in a splash in tension the ghosts ahead of a fine particle,
fitted to its own velocity, pulled it along to 57 m/s (refined Table I case 5). Ghosts are
kept out of the mass, the energies, the probes and the forces on bodies (the particle field
``body`` of a ghost is :data:`sph.engine.particles.GHOST`).

**Families** (:func:`spawn`, :func:`assign`): a particle of level ``l`` inside the
buffered box of a finer level gets four children of a quarter of its mass tiling its cell
(the square pattern of Feldman & Bonet 2007; Barcarolo et al. 2014): at
:math:`\pm\Delta x_l/4` across and a quarter of its cell's height, its volume over
:math:`\Delta x_l`, up and down (:func:`_children`), with its velocity and its density
corrected hydrostatically; it
keeps existing, and its children keep its id in the field ``parent``. Its children are
removed when it leaves that buffered box (and theirs with them). A level-0 particle and its
descendants are one family, and the family is active at one level only: the level of the
region its level-0 particle lies in, with a hysteresis, and a coarser one while its
particles of that level have strayed from their lattice (:func:`_family_levels`); its
other levels are ghosts. A family changing level hands its momentum to the particles that
turn active (:func:`assign`). The mass held by the
active particles is then the initial mass exactly, whatever crosses a level boundary (a
rule by each particle's own position, as Chiron et al. use, lets fine ghosts drift into a
box without the coarse mass leaving it: a still tank gained 2 % of its mass in 10 s). A
family spreads a little while it lives: its ghosts move with the flow interpolated at
their own places, so a level boundary is sharp to within that spread, and each level's
lattice stays complete across it, its ghosts filling the other side.
Walls are built the same way at the initial refinement: their coarse layers are kept
and fine ones added, for a fixed wall within the buffered box, for a moving wall group
(a hull, a flap) over the whole group if any of it is within reach, so that the walls of
every level are as fine as the fluid beside them wherever the body moves. A wall's
children split its layers into layers of half the spacing over the same band.

The changes are made when the neighbour lists are rebuilt (:mod:`sph.engine.neighbours`: no
particle has then moved more than half the lists' skin, a fraction of a fine spacing, since
the previous ones), so that they cost nothing between rebuilds and a run restarted from a
checkpoint continues exactly as the uninterrupted one. The time step is global, set by the
finest level; per-level time steps (Chiron et al. 2018, Sec. 4) are not done.
"""

from __future__ import annotations

import numpy as np
from numba import prange

from sph.engine.config import MAX_LEVEL
from sph.engine.filters import mls_solve
from sph.engine.jit import JIT, JIT_PARALLEL, njit
from sph.engine.kernels import KP_R2MAX, f_scaled, w_scaled
from sph.engine.neighbours import CellGrid, _pack_lists
from sph.engine.opening import in_sight, in_sight_near, opening_circle, sees
from sph.engine.particles import _FI, _II, FLUID, GHOST, Particles
from sph.engine.walls import TG_FLOOR, TG_LEFT, TG_RIGHT, TG_TOP

#: the packing correction (:func:`packing_density`, at every rebuild of the lists): a
#: particle is in the bulk where its packing fraction and that of every active fluid
#: particle in its support is at least this (1.5 h below a flat free surface: about 0.98)
PACK_BULK = 0.98
#: and its density moves this share of the way to its summation density
PACK_RELAX = 0.2
#: of a relative mismatch beyond this, only this much is taken at a rebuild
PACK_STEP = 0.005
#: a mismatch beyond this is not taken: the particle sits against a cluster of ghosts (a
#: ghost feels no force, so their spacing is not one the fluid can take)
PACK_RANGE = 0.1
#: columns of the packed boxes (:func:`pack_boxes`)
BX_XMIN, BX_XMAX, BX_ZMIN, BX_ZMAX, BX_LEVEL = range(5)
#: a ghost's fields are a first-order fit where the active particles fill at least this
#: much of its kernel (sum of V W), the Shepard mean elsewhere (:func:`ghost_fields`)
MLS_SUPPORT = 0.8
#: a ghost acts on the active particles with the weight ``(a - SPARSE) / (FULL - SPARSE)``,
#: clipped to [0, 1], of the share ``a`` of its kernel its sources fill
#: (:func:`ghost_weight`): fully where they fill 0.3 of it or more (a ghost at a flat free
#: surface: about 0.5), not at all below 0.1 (spray: one or two particles, and the only
#: one may be the particle the ghost acts on)
GHOST_SPARSE = 0.1
GHOST_FULL = 0.3
#: width of the buffer of ghosts around a box, in its level's spacings: the kernel
#: support (3 h = 3.7 spacings for the Gaussian) with the lists' skin, plus one spacing
BUFFER = 5.5
#: a family stays active at a level while its particles of that level lie within this many
#: of their spacings of their level's boxes (:func:`_family_levels`): the kernel support
#: (3.7 spacings) then stays within the buffer of that level's lattice
STRAY = 1.8
#: a family changes level once its level-0 particle is this many spacings of the box's
#: level past the box's edge (:func:`_family_levels`)
HYSTERESIS = 0.5
#: a family rises to a finer level only once its level-0 particle is this many spacings of
#: the box's level inside the box's edge (None: :data:`HYSTERESIS`)
RISE = None
#: a brood of ghost children (its family active at a coarser level) is made afresh once one
#: of them is farther than this many of its mother's spacings from her (:func:`assign`):
#: born within 0.36 of them, it then no longer tiles her cell. In the refined Table I run
#: 1.4 % of the level-2 ghost children were that far at t1 (the largest 5.2); 20 s after
#: the damage 28 % were, the farthest 79 m away: children of families in the sea carried
#: into the flooded cabin, fitted from its spray, pushed it to 60 m/s (case 5 stopped at
#: 41.1 s with a density of 1569 kg/m3)
SPREAD = 2.0


def pack_boxes(boxes) -> np.ndarray:
    """The boxes of ``numerics.refinement`` as an ``(n, 5)`` array for the numba loops."""
    out = np.zeros((len(boxes), 5))
    for k, b in enumerate(boxes):
        out[k] = (b.x[0], b.x[1], b.z[0], b.z[1], b.level)
    return out


@njit(**JIT)
def level_at(x, z, boxes, pad):
    """Finest level of the boxes containing ``(x, z)``, each grown by ``pad`` spacings of
    its own level, ``pad dx 2^-level`` with ``pad`` in metres at level 0 (0 outside every
    box)."""
    best = 0
    for k in range(boxes.shape[0]):
        lev = boxes[k, BX_LEVEL]
        g = pad * 2.0 ** (-lev)
        if (boxes[k, BX_XMIN] - g <= x <= boxes[k, BX_XMAX] + g
                and boxes[k, BX_ZMIN] - g <= z <= boxes[k, BX_ZMAX] + g):
            best = max(best, int(lev))
    return best


@njit(**JIT)
def levels_at(x, z, boxes, pad):
    """Level of the region (``pad = 0``) or of the buffered box (``pad``) at each point."""
    out = np.empty(x.shape[0], dtype=np.int32)
    for i in range(x.shape[0]):
        out[i] = level_at(x[i], z[i], boxes, pad)
    return out


def spawn(parts: Particles, boxes: np.ndarray, dx: float, grad_rho=(0.0, 0.0),
          fluid_only: bool = True) -> tuple[Particles, int]:
    r"""Give four children to every particle of level ``l`` that lies in the buffered box
    of a finer level and has none, level by level. Returns the new set (``parts`` itself
    when none was made) and the number of children made. Walls get children only when not
    ``fluid_only`` (the initial refinement). ``grad_rho``: the hydrostatic density gradient
    :math:`(\rho_0 / c_0^2)\,\mathbf{g}`; a child's density is its parent's plus this
    gradient times its offset, so that a fluid at rest stays in hydrostatic balance (a
    copied density would leave a pressure error of :math:`\rho g \Delta x_l / 4`)."""
    n_new = 0
    for lev in range(int(boxes[:, BX_LEVEL].max())):
        own = levels(parts.hs)
        cand = (own == lev) & (levels_at(parts.x, parts.z, boxes, BUFFER * dx) > lev)
        if fluid_only:
            cand &= parts.kind == FLUID
        else:  # a moving wall group is refined whole if any of it is in reach
            moving = (parts.kind != FLUID) & (parts.body > 0)
            touched = np.unique(parts.body[cand & moving])
            cand |= (own == lev) & moving & np.isin(parts.body, touched)
        cand &= ~np.isin(parts.pid, parts.parent[own == lev + 1])
        idx = np.nonzero(cand)[0]
        if len(idx):
            n_new += 4 * len(idx)
            f, i = _children(parts, idx, dx, grad_rho)
            parts = Particles.of_columns(np.concatenate([parts.f, f], axis=1),
                                         np.concatenate([parts.i, i], axis=1))
    return parts, n_new


def _children(parts: Particles, sel: np.ndarray, dx: float, grad_rho
              ) -> tuple[np.ndarray, np.ndarray]:
    """Float and integer columns of the four children of each particle ``sel``."""
    f = np.repeat(parts.f[:, sel], 4, axis=1)
    i = np.repeat(parts.i[:, sel], 4, axis=1)
    spacing = dx * np.repeat(parts.hs[sel], 4)
    fluid = i[_II["kind"]] == FLUID
    # the children tile their mother's cell: a level's spacing wide (the cases' lattices are
    # columns of it) and as high as her volume makes it, since a case that fits whole cells
    # between a floor and a level stretches them vertically (a 25 % cargo at dx = 0.8 m:
    # 3 cells of 0.708 m); children at +-spacing/4 left layers 0.54 fine spacings apart
    # where two mothers met, and the cargo rang until it burst (docs/model.md)
    height = np.where(fluid, np.repeat(parts.m[sel] / parts.rho[sel], 4) / spacing, spacing)
    ox = np.tile([-1.0, 1.0, -1.0, 1.0], len(sel)) * 0.25 * spacing
    oz = np.tile([-1.0, -1.0, 1.0, 1.0], len(sel)) * 0.25 * height
    for name, off in (("x", ox), ("z", oz), ("bx", ox), ("bz", oz), ("x_sort", ox),
                      ("z_sort", oz), ("x_inner", ox), ("z_inner", oz)):
        f[_FI[name]] += off
    for name in ("rho", "rho_old"):
        f[_FI[name]] += np.where(fluid, grad_rho[0] * ox + grad_rho[1] * oz, 0.0)
    f[_FI["m"]] *= 0.25
    f[_FI["hs"]] *= 0.5
    f[_FI["sx"]] = 0.0
    f[_FI["sz"]] = 0.0
    i[_II["parent"]] = i[_II["pid"]]
    i[_II["pid"]] = parts.i[_II["pid"]].max() + 1 + np.arange(4 * len(sel))
    return f, i


class _IdIndex:
    """The particles' ids sorted once (a stable argsort), for :meth:`find` to look up many
    sets of ids: :func:`assign` looks up mothers and ancestors level by level, and an
    argsort of every id for each lookup was about a quarter of its time."""

    def __init__(self, pid: np.ndarray):
        self.order = np.argsort(pid, kind="stable")
        self.sorted = pid[self.order]

    def find(self, wanted: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Index of the particle of each id ``wanted`` and whether it exists."""
        k = np.minimum(np.searchsorted(self.sorted, wanted), len(self.sorted) - 1)
        return self.order[k], self.sorted[k] == wanted


def _anchor(parts: Particles, fluid: np.ndarray, own: np.ndarray, ids: _IdIndex) -> None:
    """Move every ghost that has active descendants to their centre of mass, so that a
    family's level-0 particle, whose place decides the family's level, stays with the
    particles that carry its mass: moved by the flow interpolated at its own place, it
    drifted from them where they split (a flooding jet), and a fine particle far from its
    family's box, with no fine neighbours or walls, fell through the tank floor."""
    acc = np.zeros((parts.n, 3))
    act = fluid & (parts.body != GHOST)
    acc[act, 0] = parts.m[act]
    acc[act, 1] = parts.m[act] * parts.x[act]
    acc[act, 2] = parts.m[act] * parts.z[act]
    for lev in range(int(own.max()) if parts.n else 0, 0, -1):
        kids = np.nonzero(fluid & (own == lev) & (acc[:, 0] > 0.0))[0]
        mother, found = ids.find(parts.parent[kids])
        np.add.at(acc, mother[found], acc[kids[found]])
    moved = fluid & (parts.body == GHOST) & (acc[:, 0] > 0.0)
    parts.x[moved] = acc[moved, 1] / acc[moved, 0]
    parts.z[moved] = acc[moved, 2] / acc[moved, 0]


def _roots(parts: Particles, fluid: np.ndarray, own: np.ndarray, ids: _IdIndex
           ) -> np.ndarray:
    """Index of the level-0 ancestor of every fluid particle (itself for the others);
    ``ids``: the particles' ids (:class:`_IdIndex`)."""
    root = np.arange(parts.n)
    for _ in range(int(own.max()) if parts.n else 0):
        up = np.nonzero(fluid & (parts.parent[root] >= 0))[0]
        if len(up) == 0:
            break
        root[up], _ = ids.find(parts.parent[root[up]])
    return root


#: the columns a family's momentum is kept in, at both leapfrog levels
_MOMENTUM = ("vx", "vz", "vx_old", "vz_old")


def _family_sums(parts: Particles, members: np.ndarray, root: np.ndarray) -> np.ndarray:
    """Mass and momentum (:data:`_MOMENTUM`) of the particles ``members`` summed per family
    (indexed by the family's level-0 particle): shape ``(5, n)``."""
    r = root[members]
    m = parts.m[members]
    out = np.empty((len(_MOMENTUM) + 1, parts.n))
    out[0] = np.bincount(r, m, minlength=parts.n)
    for k, name in enumerate(_MOMENTUM, start=1):
        out[k] = np.bincount(r, m * getattr(parts, name)[members], minlength=parts.n)
    return out


def _family_levels(parts: Particles, fluid: np.ndarray, own: np.ndarray, root: np.ndarray,
                   before: np.ndarray, boxes: np.ndarray, dx: float, hysteresis: bool
                   ) -> np.ndarray:
    """The level each family is active at, per family (indexed by its level-0 particle):
    the level of the region its level-0 particle lies in, with a hysteresis of
    :data:`HYSTERESIS` spacings of the boxes' levels about their edges (a family keeps its
    level ``before`` until its level-0 particle is that far past an edge: in still water
    the surface particles beside a boundary settle back and forth across it; :data:`RISE`
    spacings inside an edge for a rise, where it is set), lowered
    while the family's particles of that level are not all there (a mother out of their
    buffered box lost its children) or one of them strayed more than :data:`STRAY` of its
    spacings out of its level's boxes, where its kernel would reach past the lattice of its
    level."""
    n = parts.n
    r = np.nonzero(fluid & (own == 0))[0]  # the families' level-0 particles
    rise = HYSTERESIS if RISE is None else RISE
    inner = levels_at(parts.x[r], parts.z[r], boxes, -rise * dx)
    outer = levels_at(parts.x[r], parts.z[r], boxes, HYSTERESIS * dx)
    out = np.zeros(n, dtype=np.int32)
    out[r] = levels_at(parts.x[r], parts.z[r], boxes, 0.0)
    if hysteresis:
        keep = before[r] <= MAX_LEVEL
        out[r[keep]] = np.clip(before[r[keep]], inner[keep], outer[keep])
    near = levels_at(parts.x, parts.z, boxes, STRAY * dx)
    for lev in range(int(own.max()) if n else 0, 0, -1):
        at = fluid & (own == lev)
        count = np.bincount(root[at], minlength=n)
        strays = np.bincount(root[at & (near < lev)], minlength=n)
        bad = (count != 4 ** lev) | (strays > 0)
        out[(out == lev) & bad] = lev - 1
    return out


def assign(parts: Particles, boxes: np.ndarray, dx: float, hysteresis: bool = True
           ) -> tuple[Particles, int]:
    """Remove the children of the fluid particles that left the buffered boxes of their
    children's level, the broods of ghost children of which one has spread more than
    :data:`SPREAD` of its mother's spacings from her (their family active at a coarser
    level; :func:`spawn` makes her a new one), and the children of removed ones; move
    every ghost with active descendants to their centre of mass (:func:`_anchor`), then
    mark every fluid particle active or a ghost (field ``body``): a family (a particle of
    level 0 and its descendants) is active at one level (:func:`_family_levels`) and a
    ghost at every other. A family whose level changes hands its momentum over: the
    particles that turn active take a common velocity change that gives them the momentum
    the family's active particles had (before any removal), so that mass and momentum are
    kept to round-off in every split and merge, and the centre of mass too in a merge.
    ``hysteresis``: false at the initial refinement, where every family takes its region's
    level. Returns the set (``parts`` itself when none was removed) and the number
    removed."""
    fluid = parts.kind == FLUID
    own = levels(parts.hs)
    ids = _IdIndex(parts.pid)
    root = _roots(parts, fluid, own, ids)
    # the family's active particles now: those of its coarsest level marked active (the
    # children just made are copies of their mother, marks included)
    marked = fluid & (parts.body != GHOST)
    before = np.full(parts.n, np.iinfo(np.int32).max, dtype=np.int32)
    np.minimum.at(before, root[marked], own[marked])
    held = _family_sums(parts, marked & (own == before[root]), root)
    gone = np.zeros(parts.n, dtype=bool)
    reach = levels_at(parts.x, parts.z, boxes, BUFFER * dx)
    for lev in range(1, int(own.max()) + 1):
        kids = np.nonzero(fluid & (own == lev))[0]
        mother, found = ids.find(parts.parent[kids])
        gone[kids] = ~found | gone[mother] | (reach[mother] < lev)
        # ghost children spread from their mother: the whole brood goes, and the mother
        # gets a new one at the next refinement (spawn)
        spread = found & (before[root[kids]] < lev) & (
            np.hypot(parts.x[kids] - parts.x[mother], parts.z[kids] - parts.z[mother])
            > SPREAD * dx * 2.0 ** (1 - lev))
        if spread.any():
            gone[kids] |= found & np.isin(mother, mother[spread])
    n_gone = int(gone.sum())
    if n_gone:
        keep = ~gone
        new_index = np.cumsum(keep) - 1  # level-0 particles are never removed
        parts = parts.take(keep)
        fluid, own, before = fluid[keep], own[keep], before[keep]
        root = new_index[root[keep]]
        held = held[:, keep]
        ids = _IdIndex(parts.pid)
    _anchor(parts, fluid, own, ids)
    after = _family_levels(parts, fluid, own, root, before, boxes, dx, hysteresis)
    active = fluid & (own == after[root])
    parts.body[fluid] = np.where(active[fluid], -1, GHOST)
    changed = active & (before[root] != after[root]) & (held[0, root] > 0.0)
    if changed.any():
        now = _family_sums(parts, changed, root)
        r = root[changed]
        for k, name in enumerate(_MOMENTUM, start=1):
            col = getattr(parts, name)
            col[changed] += (held[k, r] - now[k, r]) / now[0, r]
    return parts, n_gone


@njit(**JIT_PARALLEL)
def in_reach(start, index, kind, body, out):
    """Mark the ghosts and the wall particles that an active fluid particle of their level
    may reach before the lists are rebuilt (one in their Verlet list: the lists hold one
    level). Only these act on the fluid: a ghost's density and velocity are fitted at every
    step (:func:`ghost_fields`), a wall particle's pressure is extrapolated and its force
    taken (:func:`sph.engine.walls.wall_pressure`, :func:`sph.engine.walls.wall_forces`).
    The others, deep in a finer box or far out in a buffer (a coarse hull inside its box),
    need a ghost's velocity only to move along."""
    for i in prange(out.shape[0]):
        out[i] = False
        if kind[i] == FLUID and body[i] != GHOST:
            continue
        for k in range(start[i], start[i + 1]):
            j = index[k]
            if kind[j] == FLUID and body[j] != GHOST:
                out[i] = True
                break


@njit(inline="always", **JIT)
def _source(i, j, x, z, kind, body, hs, r2list):
    """Whether active fluid particle ``j`` lies within its own kernel's list radius of
    ghost ``i``."""
    if kind[j] != FLUID or body[j] == GHOST:
        return False
    dx = x[i] - x[j]
    dz = z[i] - z[j]
    return dx * dx + dz * dz < r2list * hs[j] * hs[j]


@njit(inline="always", **JIT)
def _cell_span(x, z, x0, z0, inv_cell, ncx, ncz):
    """The columns and rows of the cells about ``(x, z)`` in a
    :class:`~sph.engine.neighbours.CellGrid` whose domain starts at ``(x0, z0)``: ``(first
    column, last column, first row, last row)``, clipped to the interior (a point outside
    it sees the cells at its edge). The cell of a point inside is the grid's own (the same
    rounding as its sort). A point more than a cell beyond the interior gets an empty span
    (no rows): its first column would lie beyond the row's cells."""
    ix = int(np.floor((x - x0) * inv_cell + 1.0))
    iz = int(np.floor((z - z0) * inv_cell + 1.0))
    c0, c1 = max(ix - 1, 1), min(ix + 1, ncx - 2)
    r0, r1 = max(iz - 1, 1), min(iz + 1, ncz - 2)
    if c0 > c1 or r0 > r1:
        return 1, 0, 1, 0
    return c0, c1, r0, r1


@njit(**JIT_PARALLEL)
def _source_room(x, z, kind, body, cell_start, x0, z0, inv_cell, ncx, ncz, room):
    """Add to ``room[i]`` the candidates of each ghost ``i`` among the active particles of
    one level, binned in cells of their list radius: the particles of the cells about it
    (:func:`_cell_span`), the most sources it can have there."""
    for i in prange(x.shape[0]):
        if kind[i] != FLUID or body[i] != GHOST:
            continue
        c0, c1, r0, r1 = _cell_span(x[i], z[i], x0, z0, inv_cell, ncx, ncz)
        cnt = 0
        for row in range(r0, r1 + 1):
            cnt += cell_start[row * ncx + c1 + 1] - cell_start[row * ncx + c0]
        room[i] += cnt


@njit(**JIT_PARALLEL)
def _fill_sources(x, z, kind, body, hs, perm, cell_start, x0, z0, inv_cell, ncx, ncz, r2list,
                  cursor, index):
    """Append each ghost's sources of one level (the active particles within their own
    kernel's list radius of it) at ``index[cursor[i]:]``, advancing ``cursor[i]``."""
    for i in prange(x.shape[0]):
        if kind[i] != FLUID or body[i] != GHOST:
            continue
        c0, c1, r0, r1 = _cell_span(x[i], z[i], x0, z0, inv_cell, ncx, ncz)
        k = cursor[i]
        for row in range(r0, r1 + 1):
            for m in range(cell_start[row * ncx + c0], cell_start[row * ncx + c1 + 1]):
                j = perm[m]
                if _source(i, j, x, z, kind, body, hs, r2list):
                    index[k] = j
                    k += 1
        cursor[i] = k


@njit(**JIT_PARALLEL)
def _sort_sources(start, index):
    """Sort each ghost's sources ``index[start[i]:start[i + 1]]``. By insertion: a ghost has
    some 50-90, in runs already in order (one per level and row of cells): on the refined
    Table I case4 at 25.7 s this took 7 ms a rebuild instead of a quicksort's 12 ms."""
    for i in prange(start.shape[0] - 1):
        a = start[i]
        for k in range(a + 1, start[i + 1]):
            v = index[k]
            m = k - 1
            while m >= a and index[m] > v:
                index[m + 1] = index[m]
                m -= 1
            index[m + 1] = v


def ghost_sources(x, z, kind, body, hs, grid, radius) -> tuple[np.ndarray, np.ndarray]:
    """For each ghost, the active fluid particles within ``radius`` (the lists' radius)
    times their own smoothing length ratio, in index order (the cell order of ``grid``,
    which the particles are sorted by): ``index[start[i]:start[i + 1]]``. Built with the
    Verlet lists and valid as long as they are; :func:`ghost_fields` visits these instead
    of the cells.

    The active particles of each level are binned in cells of their own list radius, as
    the lists are (:func:`sph.engine.neighbours.NeighbourList.build`): in the cells of
    ``grid`` (the coarsest level's) a ghost of a box's finest level tested 16 times the
    candidates it needs, and in the refined Table I case 4 at 33 s this search took 138 ms
    at each rebuild of the lists, 10 % of the run. A particle outside ``grid``'s domain is
    no source."""
    n = x.shape[0]
    xmin, xmax, zmin, zmax = grid.bounds
    active = ((kind == FLUID) & (body != GHOST) & (x >= xmin) & (x <= xmax) & (z >= zmin)
              & (z <= zmax))
    level = levels(hs)
    r2 = radius * radius
    # one pass over the candidates: each ghost's sources are written into room for all its
    # candidates, then packed (a count, then a fill: 27 ms a call against 21 on the refined
    # Table I case 2 at 45 s, the least of 15 calls each)
    room = np.zeros(n + 1, dtype=np.int64)
    bins = []
    for lev in np.unique(level[active]):
        sel = np.nonzero(active & (level == lev))[0]
        xs, zs = x[sel], z[sel]
        cells = CellGrid(xs.min(), xs.max(), zs.min(), zs.max(), radius * 2.0 ** -lev)
        cells.sort(xs, zs)
        lx0, _, lz0, _ = cells.bounds  # the level's own, not the domain's
        bins.append((sel[cells.order], cells.cell_start, lx0, lz0, 1.0 / cells.cell,
                     cells.ncx, cells.ncz))
        _source_room(x, z, kind, body, *bins[-1][1:], room[1:])
    np.cumsum(room, out=room)
    scratch = np.empty(int(room[n]), dtype=np.int64)
    cursor = room[:-1].copy()
    for b in bins:
        _fill_sources(x, z, kind, body, hs, *b, r2, cursor, scratch)
    start = np.zeros(n + 1, dtype=np.int64)
    start[1:] = np.cumsum(cursor - room[:-1])
    index = np.empty(int(start[n]), dtype=np.int64)
    _pack_lists(start, room, scratch, index)
    _sort_sources(start, index)
    return start, index


@njit(inline="always", **JIT)
def ghost_weight(a):
    """The weight a ghost acts with on the active particles (:data:`GHOST_SPARSE`,
    :data:`GHOST_FULL`), from the share ``a`` of its kernel its sources fill."""
    return min(max((a - GHOST_SPARSE) / (GHOST_FULL - GHOST_SPARSE), 0.0), 1.0)


@njit(**JIT_PARALLEL)
def ghost_fields(x, z, vx, vz, rho, vx_old, vz_old, rho_old, m, kind, body, comp, hs,
                 src_start, src_index, kp, op, kin, reach, every, grad_rho, gw):
    r"""Density and velocity of every ghost (:data:`sph.engine.particles.GHOST`) from the
    active fluid particles around it, of every level, each with its own kernel: the
    first-order moving least squares fit

    .. math:: f_g = \sum_j f_j\,\beta_g\cdot(1, x_g - x_j, z_g - z_j)\,W_j(\mathbf{x}_g)\,V_j,
              \qquad \beta_g = A_g^{-1}\mathbf{e}_1,\quad
              A_g = \sum_j \mathbf{b}_j\mathbf{b}_j^T W_j V_j

    (as the density filter, :func:`sph.engine.filters.mls_density`), exact for a linear
    field; the Shepard mean where :math:`A_g` is near singular or the kernel is less than
    :data:`MLS_SUPPORT` full (at a free surface or a splash a linear fit extrapolates, and
    a ghost given a wild velocity would carry it when its family turns active there), with
    each source's density carried to the ghost along the hydrostatic gradient ``grad_rho``
    (:math:`(\rho_0 / c_0^2)\,\mathbf{g}`): the sources of a ghost at a free surface lie
    below it on the whole, and their plain mean gave it the density of a depth of about
    a smoothing length; its pressure pushed the active particles beside it up and out, and
    the fine particles at a box's edge rose out of a still tank's surface. Both
    leapfrog levels take the fitted values; a ghost with no active particle in reach keeps
    its own. Only the ghosts marked in ``reach`` (:func:`in_reach`) are fitted,
    unless ``every`` (the steps the lists are rebuilt at: the others move with the velocity
    of their last fit in between). The candidates are the ghost's sources
    ``src_index[src_start[i]:src_start[i + 1]]`` (:func:`ghost_sources`).

    ``gw`` (output, or None): the weight each fitted ghost acts with on the active particles
    (:func:`ghost_weight`; the pair loops scale its mass by it,
    :func:`sph.engine.fluid.interact`). A ghost fitted from a nearly empty kernel is not
    fluid that is there: in a spray its only source may be the particle it acts on, and
    fitted to that particle's own pressure and velocity it travelled with it and pushed it
    on (a ghost feels nothing back). In the refined Table I case 5, cabin particles with no
    active neighbour of their level, beside ghosts filled 0.02-0.13, ran up to 100 m/s
    from 31 s and the run stopped at 39 s (a density of 1516 kg/m3)."""
    r2max = kp[KP_R2MAX]
    ocx, ocz, or2 = opening_circle(op, 0.0)  # near_opening, taken once
    for i in prange(x.shape[0]):
        if kind[i] != FLUID or body[i] != GHOST or not (every or reach[i]):
            continue
        xi = x[i]
        zi = z[i]
        ci = comp[i]
        # beyond the open opening's reach (and everywhere while it is closed) a ghost sees
        # the fluid of its compartment alone, as in the list loops: the pair rule is
        # taken only near the opening
        sees_opening = (xi - ocx) * (xi - ocx) + (zi - ocz) * (zi - ocz) <= or2
        a11 = a12 = a13 = a22 = a23 = a33 = 0.0
        r0 = r1 = r2_ = u0 = u1 = u2 = w0 = w1 = w2 = 0.0
        for k in range(src_start[i], src_start[i + 1]):
            j = src_index[k]
            dx = xi - x[j]
            dz = zi - z[j]
            r2 = dx * dx + dz * dz
            s = hs[j]
            if r2 >= r2max * s * s:
                continue
            if sees_opening:
                if not sees(xi, zi, ci, x[j], z[j], kind[j], body[j], comp[j], op, kin):
                    continue
            elif comp[j] != ci:
                continue
            vw = w_scaled(r2, kp, s) * m[j] / rho[j]
            a11 += vw
            a12 += vw * dx
            a13 += vw * dz
            a22 += vw * dx * dx
            a23 += vw * dx * dz
            a33 += vw * dz * dz
            r0 += vw * rho[j]
            r1 += vw * rho[j] * dx
            r2_ += vw * rho[j] * dz
            u0 += vw * vx[j]
            u1 += vw * vx[j] * dx
            u2 += vw * vx[j] * dz
            w0 += vw * vz[j]
            w1 += vw * vz[j] * dx
            w2 += vw * vz[j] * dz
        if gw is not None:
            gw[i] = ghost_weight(a11)
        if a11 <= 0.0:
            continue
        c11, c12, c13, det, regular = mls_solve(a11, a12, a13, a22, a23, a33)
        if a11 > MLS_SUPPORT and regular:
            rho[i] = (c11 * r0 + c12 * r1 + c13 * r2_) / det
            vx[i] = (c11 * u0 + c12 * u1 + c13 * u2) / det
            vz[i] = (c11 * w0 + c12 * w1 + c13 * w2) / det
        else:
            rho[i] = (r0 + grad_rho[0] * a12 + grad_rho[1] * a13) / a11
            vx[i] = u0 / a11
            vz[i] = w0 / a11
        rho_old[i] = rho[i]
        vx_old[i] = vx[i]
        vz_old[i] = vz[i]


@njit(inline="always", **JIT)
def _ghost_diffusion_sum(i, k0, k1, inner, xi, zi, ci, rhoi, x, z, rho, m, kind, body, comp,
                         hs, kp, r2max, op, kin, gw, hx, hz, near):
    """:func:`ghost_diffusion`'s sum over the ghosts of ``inner[k0:k1]`` that particle ``i``
    sees (``near``: within the open opening's reach,
    :func:`sph.engine.opening.in_sight_near`)."""
    d = 0.0
    for k in range(k0, k1):
        j = inner[k]
        if body[j] != GHOST or kind[j] != FLUID:
            continue
        ok, dx, dz, r2, s = in_sight_near(near, i, j, xi, zi, ci, x, z, kind, body, comp, hs,
                                          r2max, op, kin)
        if not ok:
            continue
        vj = (1.0 if gw is None else gw[j]) * m[j] / rho[j]
        d += -2.0 * s * vj * f_scaled(r2, kp, s) * (rho[j] - rhoi - hx * dx - hz * dz)
    return d


@njit(**JIT_PARALLEL)
def ghost_diffusion(x, z, rho, m, kind, body, comp, hs, kp, op, kin, start, inner, inner_end,
                    near, gw, coef, hx, hz, drho):
    r"""Add to ``drho`` of each active fluid particle the diffusive term of delta-SPH with
    the hydrostatic density difference subtracted (as ``numerics.density_filter: ddt``,
    :func:`sph.engine.fluid.interact`) over its pairs with ghosts alone,

    .. math:: \dot\rho_i \mathrel{+}= \delta h c_0 \sum_{g} 2\,s\,V_g\,
              (\rho_g - \rho_i - \rho^H_{ig})\,F_{ig},

    ``coef`` = :math:`\delta h c_0`, ``hx dx + hz dz`` the hydrostatic difference
    :math:`\rho^H` (:math:`-(\rho_0 / c_0^2)\,\mathbf{g}\cdot\mathbf{r}_{ig}`), each ghost's
    volume scaled by its weight ``gw`` (:func:`ghost_weight`). For the runs with no density
    filter (``numerics.density_filter: none``, the ship cases'): under ``mls`` the
    re-initialisation fits an active particle's density from its ghosts too, and under
    ``delta`` and ``ddt`` the ghosts are in the diffusive term.

    A ghost holds the density its sources give it (:func:`ghost_fields`) and feels no
    force, so an active particle whose kernel holds ghosts more than fluid of its own level
    cannot relax a compression by pushing its neighbours apart: with no diffusive term its
    density stays wherever an impact left it. In the refined Table I case 2 such particles
    under the hull carried 1.06-1.31 rho0 (up to 2.4e7 Pa) and were thrown at 40-115 m/s
    (the ship's roll-over there is not their doing: with the term it heels as far); in
    case 7 particles with no active neighbour of their level among 31 ghosts held 1.09
    rho0. With the term each relaxes towards the density its
    ghosts carry, on the acoustic time of a smoothing length over delta; a particle among
    fluid of its own level is left as it was, and a ghost fitted from a nearly empty
    kernel (weight 0) exchanges nothing. Only the particles marked in ``near`` (those with a
    ghost in their inner list, :func:`sph.engine.walls.listed_with`) have pairs to sum."""
    r2max = kp[KP_R2MAX]
    ocx, ocz, or2 = opening_circle(op, 0.0)  # near_opening, taken once
    for i in prange(x.shape[0]):
        if not near[i]:  # no ghost in its list; nor a wall particle or a ghost
            continue
        xi = x[i]
        zi = z[i]
        ci = comp[i]
        if (xi - ocx) * (xi - ocx) + (zi - ocz) * (zi - ocz) <= or2:
            d = _ghost_diffusion_sum(i, start[i], inner_end[i], inner, xi, zi, ci, rho[i], x,
                                     z, rho, m, kind, body, comp, hs, kp, r2max, op, kin, gw,
                                     hx, hz, True)
        else:
            d = _ghost_diffusion_sum(i, start[i], inner_end[i], inner, xi, zi, ci, rho[i], x,
                                     z, rho, m, kind, body, comp, hs, kp, r2max, op, kin, gw,
                                     hx, hz, False)
        drho[i] += coef * d


@njit(**JIT_PARALLEL)
def packing_fraction(x, z, rho, m, kind, comp, body, hs, kp, op, kin, start, index, phi,
                     rho_sum):
    r"""The share of space its own level's fluid fills in its kernel and the summation
    density,

    .. math:: \phi_i = \sum_j \frac{m_j}{\rho_j} W_{ij},\qquad
              \rho^\Sigma_i = \sum_j m_j W_{ij},

    of each active fluid particle, over itself and the fluid of its level it sees, active
    and ghost (the ghosts complete each level's lattice across a level boundary), by the
    Verlet lists ``start, index`` just built. :math:`\phi_i` is one in the bulk of a fluid
    whose densities agree with its particles' spacing, below one within a few smoothing
    lengths of a free surface; there :math:`\rho^\Sigma_i` is the density the spacing gives.
    Both are -1 for walls and ghosts (nothing asks theirs), and where a wall particle is in
    the support (the fluid alone does not fill it there)."""
    r2max = kp[KP_R2MAX]
    for i in prange(x.shape[0]):
        phi[i] = -1.0
        rho_sum[i] = -1.0
        if kind[i] != FLUID or body[i] == GHOST:
            continue
        xi = x[i]
        zi = z[i]
        ci = comp[i]
        w0 = w_scaled(0.0, kp, hs[i])
        acc = m[i] / rho[i] * w0
        mass = m[i] * w0
        walled = False
        for k in range(start[i], start[i + 1]):
            j = index[k]
            if j == i:  # (a list holds its own particle)
                continue
            ok, dx, dz, r2, s = in_sight(i, j, xi, zi, ci, x, z, kind, body, comp, hs, r2max,
                                         op, kin)
            if not ok:
                continue
            if kind[j] != FLUID:
                walled = True
                break
            w = w_scaled(r2, kp, s)
            acc += m[j] / rho[j] * w
            mass += m[j] * w
        if not walled:
            phi[i] = acc
            rho_sum[i] = mass


@njit(**JIT_PARALLEL)
def packing_density(x, z, rho, rho_old, kind, comp, body, hs, kp, op, kin, start, index,
                    phi, rho_sum, bulk, relax, changed):
    r"""Bring the density of each active fluid particle in the bulk towards the one its
    particles' spacing gives, its summation density (:func:`packing_fraction`):
    :math:`\rho_i \leftarrow \rho_i\,[1 + \kappa e_i]`, :math:`e_i = \rho^\Sigma_i / \rho_i
    - 1` taken within :data:`PACK_STEP` either way (``relax`` :math:`\kappa`), ``rho_old``
    with it, so that no rebuild changes a pressure by more than a few metres of head.

    In the bulk: no wall in its support, and :math:`\phi_j \ge` ``bulk`` for itself and
    every active fluid particle of its level in its support that has no wall in its own, so
    that no free surface is within reach of any of them (a ghost's fraction is not asked:
    it may read a hole in the ghosts' lattice). A particle whose :math:`|e_i|` passes
    :data:`PACK_RANGE` is left as it is: it sits against a cluster of ghosts, which feel
    no force and do not give way. ``changed[i]``: the factor applied (1 where none)."""
    r2max = kp[KP_R2MAX]
    for i in prange(x.shape[0]):
        changed[i] = 1.0
        if kind[i] != FLUID or body[i] == GHOST or phi[i] < bulk:
            continue
        xi = x[i]
        zi = z[i]
        ci = comp[i]
        lo = phi[i]
        for k in range(start[i], start[i + 1]):
            j = index[k]
            ok, dx, dz, r2, s = in_sight(i, j, xi, zi, ci, x, z, kind, body, comp, hs, r2max,
                                         op, kin)
            # the active neighbours with a fraction tell of a free surface: a ghost's
            # might read a hole in the ghosts' lattice, and one with a wall in its support
            # has none (-1; a wall in sight of i itself left phi[i] at -1)
            if ok and 0.0 <= phi[j] < lo:
                lo = phi[j]
        e = rho_sum[i] / rho[i] - 1.0
        if lo >= bulk and abs(e) <= PACK_RANGE:
            f = 1.0 + relax * min(max(e, -PACK_STEP), PACK_STEP)
            rho[i] *= f
            rho_old[i] *= f
            changed[i] = f


def wall_contact(box, guard, dx: float) -> tuple[str, str, float, float] | None:
    """Where an edge of ``box`` (xmin, xmax, zmin, zmax) meets a fixed wall of the tank,
    whose surfaces ``guard`` gives (:func:`sph.engine.walls.tank_guard`: the end walls'
    x, +-inf where an end is no fixed wall, the floor's z and the end walls' top): the
    edge, the wall and the point, or None.

    An edge meets a wall where it crosses the wall's surface inside the tank, or runs
    along it within 1.5 ``dx`` (the first fluid particles lie half a spacing off it): a
    level boundary the flow crosses along a wall, where a family that changes level is not
    held by the wall beside it (docs/validation/refinement.md, "A sloshing tank"). An edge
    inside a wall or above the end walls meets none. Fixed walls other than the tank's
    (an obstacle of a case) are not looked at."""
    xmin, xmax, zmin, zmax = box
    left, right, floor, top = guard[TG_LEFT], guard[TG_RIGHT], guard[TG_FLOOR], guard[TG_TOP]
    reach = 1.5 * dx
    for name, x in (("left", xmin), ("right", xmax)):
        if left < x < right and zmin <= floor + reach and zmax > floor:
            return name, "floor", float(x), float(floor)
        for wall, gap in (("left end wall", x - left), ("right end wall", right - x)):
            if 0.0 <= gap <= reach and zmin < top and zmax > floor:
                return name, wall, float(x), float(max(zmin, floor))
    for name, z in (("bottom", zmin), ("top", zmax)):
        if floor < z < top:
            if xmin <= left + reach and xmax > left:
                return name, "left end wall", float(left), float(z)
            if xmax >= right - reach and xmin < right:
                return name, "right end wall", float(right), float(z)
        if 0.0 <= z - floor <= reach and xmax > left and xmin < right:
            return name, "floor", float(max(xmin, left)), float(z)
    return None


def levels(hs: np.ndarray) -> np.ndarray:
    """Refinement level of each particle from its smoothing length ratio ``hs``."""
    return np.rint(-np.log2(hs)).astype(np.int32)


def active_fluid(parts: Particles) -> np.ndarray:
    """Mask of the fluid particles that carry mass (not ghosts)."""
    return (parts.kind == FLUID) & (parts.body != GHOST)


def level_counts(parts: Particles, n_levels: int) -> np.ndarray:
    """Active fluid particles per level ``0 .. n_levels``."""
    lev = levels(parts.hs[active_fluid(parts)])
    return np.bincount(lev, minlength=n_levels + 1)[:n_levels + 1].astype(np.float64)
