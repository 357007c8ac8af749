"""O(N) neighbour search: a cell-linked list with particles sorted by cell.

The domain is covered by square cells whose side equals the kernel support radius, with one
layer of padding cells all around. Particles are counting-sorted by cell (row-major order),
after which the three cells of one row that surround a particle are contiguous in memory:
a pair loop visits three contiguous index ranges ``cell_start[c-1] .. cell_start[c+2]``
for the rows above, at and below the particle's cell. No particle may sit in a padding cell;
the sort reports how many do (they have left the domain).
"""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from sph.engine.jit import JIT, JIT_PARALLEL, njit
from sph.engine.kernels import pair_scale
from sph.engine.particles import FLUID

#: the skin of the Verlet lists (:class:`NeighbourList`) and of the cells, as a fraction of
#: the kernel support: lists and cells are rebuilt when a particle has moved half of it
SKIN = 0.15
#: the skin of the inner lists (:meth:`NeighbourList.refresh`), as a fraction of the
#: kernel support
INNER_SKIN = 0.04


class CellGrid:
    """Cells of side ``cell`` covering ``[xmin, xmax] x [zmin, zmax]`` plus one padding layer."""

    def __init__(self, xmin: float, xmax: float, zmin: float, zmax: float, cell: float):
        self.cell = float(cell)
        self.x0 = xmin - cell  # origin of the padded grid
        self.z0 = zmin - cell
        # interior cells 1 .. n; a point exactly on xmax (zmax) still falls in cell n
        self.ncx = int(math.floor((xmax - xmin) / cell)) + 3
        self.ncz = int(math.floor((zmax - zmin) / cell)) + 3
        self.bounds = (xmin, xmax, zmin, zmax)
        self.cell_start = np.zeros(self.ncx * self.ncz + 1, dtype=np.int64)
        self._counts = np.zeros(self.ncx * self.ncz, dtype=np.int64)
        self.cell_of = np.zeros(0, dtype=np.int64)
        self.order = np.zeros(0, dtype=np.int64)
        self._tmp = np.zeros(0, dtype=np.int64)

    def sort(self, x: np.ndarray, z: np.ndarray) -> int:
        """Bin the particles; fills ``order`` (new position -> old index), ``cell_start``
        and ``cell_of`` (cell of each particle in the *new* order). Returns the number of
        particles outside the domain."""
        n = x.shape[0]
        if self.order.shape[0] != n:
            self.order = np.empty(n, dtype=np.int64)
            self.cell_of = np.empty(n, dtype=np.int64)
            self._tmp = np.empty(n, dtype=np.int64)
        xmin, xmax, zmin, zmax = self.bounds
        return _counting_sort(x, z, xmin, xmax, zmin, zmax, 1.0 / self.cell, self.ncx, self.ncz,
                              self._tmp, self._counts, self.cell_start, self.order,
                              self.cell_of)


@njit(**JIT)
def _counting_sort(x, z, xmin, xmax, zmin, zmax, inv_cell, ncx, ncz, tmp, counts, cell_start,
                   order, cell_sorted):
    n = x.shape[0]
    counts[:] = 0
    n_out = 0
    for i in range(n):
        if _inside(x[i], z[i], xmin, xmax, zmin, zmax):
            c = int((z[i] - zmin) * inv_cell + 1.0) * ncx + int((x[i] - xmin) * inv_cell + 1.0)
        else:
            n_out += 1
            c = 0  # a padding cell: never visited by a pair loop
        tmp[i] = c
        counts[c] += 1
    acc = 0
    for c in range(counts.shape[0]):
        cell_start[c] = acc
        acc += counts[c]
        counts[c] = cell_start[c]
    cell_start[counts.shape[0]] = acc
    for i in range(n):
        c = tmp[i]
        k = counts[c]
        order[k] = i
        cell_sorted[k] = c
        counts[c] = k + 1
    return n_out


@njit(**JIT)
def neighbour_count(x, z, cell_of, cell_start, ncx, r2max, i):
    """Number of particles within ``sqrt(r2max)`` of particle ``i`` (itself excluded).

    The reference pattern of every pair loop of the engine, used by the tests."""
    c = cell_of[i]
    cnt = 0
    for row in (c - ncx, c, c + ncx):
        for j in range(cell_start[row - 1], cell_start[row + 2]):
            if j == i:
                continue
            dx = x[i] - x[j]
            dz = z[i] - z[j]
            if dx * dx + dz * dz < r2max:
                cnt += 1
    return cnt


class NeighbourList:
    """Verlet lists: for each fluid particle the particles (any kind, any compartment), for
    each wall particle the fluid particles (any compartment), within the kernel support
    plus a skin, in cell order, at the positions of the last sort.

    While no particle has moved more than half the skin since then
    (:func:`moved_or_outside`), every pair within the support is in the list, so the pair
    loop visits the list instead of the three rows of cells: about a third of the
    candidates for the Gaussian kernel, and no sort or permutation of the particles. The
    lists are stored compressed: particle ``i``'s neighbours are
    ``index[start[i]:start[i + 1]]``. A wall particle deep in its wall has an empty list.

    Each particle also has an inner list (:meth:`refresh`): the entries of its list within
    the support plus a thinner skin (:data:`INNER_SKIN`), in the same order, at
    ``inner[start[i]:inner_end[i]]``. It is refreshed from the Verlet list whenever a
    particle has moved half that skin, every few steps, and the pair loops go over it
    (the fluid loop with the pairs beyond the support masked): about 1.05 entries per
    neighbour instead of 1.4, and no selection of the neighbours at every step."""

    #: unsigned, so that a numba loop indexing with them compiles no negative-index
    #: wrap-around (it halves the cost of a loop over a list)
    DTYPE_START = np.uint64
    DTYPE_INDEX = np.uint32

    def __init__(self):
        self.start = np.zeros(1, dtype=self.DTYPE_START)
        self.index = np.zeros(0, dtype=self.DTYPE_INDEX)
        self.inner = np.zeros(0, dtype=self.DTYPE_INDEX)
        self.inner_end = np.zeros(0, dtype=self.DTYPE_START)
        # the build's work: each particle's room (its candidates) and the lists in it
        self._room = np.zeros(1, dtype=self.DTYPE_START)
        self._scratch = np.zeros(0, dtype=self.DTYPE_INDEX)

    def build(self, x, z, kind, grid: CellGrid, radius: float, hs) -> None:
        """Lists of radius ``radius`` from the cells of ``grid`` (particles sorted by it);
        under variable resolution a pair's radius is ``radius`` times its smoothing length
        ratio (``hs``, :func:`sph.engine.kernels.pair_scale`; None: uniform).

        One pass over the candidates: each particle's list is written into room for all
        its candidates (the particles of the three rows of cells around it) as its
        distances are tested, then the lists are packed, in the same order."""
        n = x.shape[0]
        if self.start.shape[0] != n + 1:
            self.start = np.zeros(n + 1, dtype=self.DTYPE_START)
            self._room = np.zeros(n + 1, dtype=self.DTYPE_START)
        # each level's particles in cells of their own (pairs of different levels are
        # never listed), or all in the grid's
        bins = [(None, grid)] if hs is None else _level_grids(x, z, hs, grid, radius)
        self._room[:] = 0
        for perm, g in bins:
            _candidate_counts(perm, g.cell_of, g.cell_start, g.ncx, self._room[1:])
        np.cumsum(self._room[1:], out=self._room[1:])
        if self._scratch.shape[0] < self._room[n]:
            self._scratch = np.empty(int(1.2 * self._room[n]) + 16, dtype=self.DTYPE_INDEX)
        self.start[:] = 0
        for perm, g in bins:
            _fill_candidates(x, z, kind, hs, perm, g.cell_of, g.cell_start, g.ncx,
                             radius * radius, self._room, self._scratch, self.start[1:])
        np.cumsum(self.start[1:], out=self.start[1:])
        total = int(self.start[n])
        if self.index.shape[0] < total:
            self.index = np.empty(int(1.2 * total) + 16, dtype=self.DTYPE_INDEX)
        _pack_lists(self.start, self._room, self._scratch, self.index)

    def refresh(self, x, z, radius: float, hs) -> None:
        """The inner lists of radius ``radius`` (at most the radius of :meth:`build`, and
        scaled per pair in the same way) from the lists, at the positions ``x, z``.

        The loops that sum over them may add in an order that depends on where in the
        list a neighbour sits (the compiler may split a sum into partial sums), so a
        restart rebuilds them from the positions they were refreshed at (the particle
        fields ``x_inner, z_inner``) to continue bit for bit."""
        n = x.shape[0]
        if self.inner.shape[0] < self.index.shape[0]:
            self.inner = np.empty_like(self.index)
        if self.inner_end.shape[0] != n:
            self.inner_end = np.zeros(n, dtype=self.DTYPE_START)
        _fill_inner(x, z, hs, radius * radius, self.start, self.index, self.inner,
                    self.inner_end)


def _level_grids(x, z, hs, grid: CellGrid, radius: float) -> list[tuple]:
    """Under variable resolution a pair of different levels is never listed, so each
    level's particles are binned in cells of their own list radius (in the cells of the
    coarsest level a particle of level ``l`` would test :math:`4^l` times the candidates it
    needs): ``(perm, cells)`` per level, ``perm`` the particles in the cells' order. A
    particle outside the grid's domain is left out (its list stays empty)."""
    level = np.rint(-np.log2(hs)).astype(np.int64)
    xmin, xmax, zmin, zmax = grid.bounds
    inside = (x >= xmin) & (x <= xmax) & (z >= zmin) & (z <= zmax)
    out = []
    for lev in np.unique(level):
        sel = np.nonzero((level == lev) & inside)[0]
        if len(sel) == 0:
            continue
        xs, zs = x[sel], z[sel]
        cells = CellGrid(xs.min(), xs.max(), zs.min(), zs.max(), radius * 2.0 ** -lev)
        cells.sort(xs, zs)
        out.append((sel[cells.order], cells))
    return out


@njit(inline="always", **JIT)
def _listed(i, j, x, z, kind, hs, r2):
    """True when particle ``j`` belongs in particle ``i``'s list: within ``sqrt(r2)`` times
    the pair's smoothing length ratio, and fluid unless ``i`` is fluid (a wall particle
    lists the fluid only). Branch-free."""
    dx = x[i] - x[j]
    dz = z[i] - z[j]
    s = pair_scale(hs, i, j)
    return (dx * dx + dz * dz < r2 * s * s) & ((kind[i] == FLUID) | (kind[j] == FLUID))


@njit(inline="always", **JIT)
def _inside(x, z, xmin, xmax, zmin, zmax):
    """True when ``(x, z)`` lies in the domain; false for NaN (every comparison with NaN is
    false)."""
    return x >= xmin and x <= xmax and z >= zmin and z <= zmax


@njit(**JIT_PARALLEL)
def _candidate_counts(perm, cell_of, cell_start, ncx, room):
    """The number of candidates of each particle (the particles in the three rows of cells
    around it) into ``room``: the most its list can hold. The particles are binned in
    ``cell_of``/``cell_start`` in the order of ``perm`` (the particles of one refinement
    level in cells of their own), or in their own order (``perm`` None)."""
    for k in prange(cell_of.shape[0]):
        i = np.int64(k) if perm is None else np.int64(perm[k])
        c = cell_of[k]
        room[i] = ((cell_start[c - ncx + 2] - cell_start[c - ncx - 1])
                   + (cell_start[c + 2] - cell_start[c - 1])
                   + (cell_start[c + ncx + 2] - cell_start[c + ncx - 1]))


@njit(**JIT_PARALLEL)
def _fill_candidates(x, z, kind, hs, perm, cell_of, cell_start, ncx, r2, room, scratch,
                     counts):
    """Each particle's list into ``scratch[room[i]:]`` and its length into ``counts``,
    binned as in :func:`_candidate_counts`. Every candidate is stored and kept when listed
    (branch-free): a particle's room holds all its candidates."""
    for k in prange(cell_of.shape[0]):
        i = np.int64(k) if perm is None else np.int64(perm[k])
        e = room[i]
        c = cell_of[k]
        for row in (c - ncx, c, c + ncx):
            for m in range(cell_start[row - 1], cell_start[row + 2]):
                j = np.int64(m) if perm is None else np.int64(perm[m])
                scratch[e] = j
                e += np.uint64(1) if _listed(i, j, x, z, kind, hs, r2) else np.uint64(0)
        counts[i] = e - room[i]


@njit(**JIT_PARALLEL)
def _pack_lists(start, room, scratch, index):
    """The lists from their rooms in ``scratch`` into ``index[start[i]:start[i + 1]]``."""
    for i in prange(start.shape[0] - 1):
        a = start[i]
        b = room[i]
        for q in range(start[i + 1] - a):
            index[a + q] = scratch[b + q]


@njit(**JIT_PARALLEL)
def _fill_inner(x, z, hs, r2, start, index, inner, inner_end):
    for i in prange(x.shape[0]):
        k = start[i]
        for e in range(start[i], start[i + 1]):
            j = index[e]
            dx = x[i] - x[j]
            dz = z[i] - z[j]
            s = pair_scale(hs, i, j)
            inner[k] = j  # branch-free: stored always, kept when within reach
            k += np.uint64(1) if dx * dx + dz * dz < r2 * s * s else np.uint64(0)
        inner_end[i] = k


@njit(**JIT_PARALLEL)
def moved_or_outside(x, z, xs, zs, half_skin2, xmin, xmax, zmin, zmax, hs=None):
    """True when a particle has moved more than ``sqrt(half_skin2)`` from ``(xs, zs)`` or
    is outside the domain (or NaN): the lists and cells must be rebuilt. Under variable
    resolution (``hs``: each particle's smoothing length over the case's) a particle's own
    level's skin counts, ``sqrt(half_skin2) hs``: its pairs are of its level, listed at that
    level's radius."""
    n = x.shape[0]
    bad = 0
    for i in prange(n):
        dx = x[i] - xs[i]
        dz = z[i] - zs[i]
        lim = half_skin2 if hs is None else half_skin2 * hs[i] * hs[i]
        if not (dx * dx + dz * dz <= lim and _inside(x[i], z[i], xmin, xmax, zmin, zmax)):
            bad += 1
    return bad > 0
