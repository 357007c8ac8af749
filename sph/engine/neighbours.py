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

from sph.engine.jit import JIT, njit


#: particles per block of the parallel pair loops that keep a neighbour buffer
#: (:func:`gather_neighbours`). The split is fixed, so results do not depend on the number
#: of threads.
BLOCK = 256


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
        # the test is written so that NaN fails it (comparisons with NaN are false)
        if x[i] >= xmin and x[i] <= xmax and z[i] >= zmin and z[i] <= zmax:
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


@njit(**JIT)
def max_candidates(cell_start, ncx):
    """The most particles a pair loop visits for one particle: the largest sum over the
    three rows of three cells around any interior cell (the size of a neighbour buffer,
    :func:`gather_neighbours`)."""
    most = 0
    ncells = cell_start.shape[0] - 1
    for c in range(ncx + 1, ncells - ncx - 1):
        cnt = 0
        for row in (c - ncx, c, c + ncx):
            cnt += cell_start[row + 2] - cell_start[row - 1]
        most = max(most, cnt)
    return most


@njit(inline="always", **JIT)
def gather_neighbours(i, x, z, comp, kind, want_kind, cell_of, cell_start, ncx, r2max, buf):
    """Indices of the particles within ``sqrt(r2max)`` of particle ``i`` (itself included)
    and of its compartment, and of kind ``want_kind`` unless it is negative, into ``buf``
    (at least :func:`max_candidates` long); returns their number.

    Written without a branch (every candidate is stored, and the count advances only for a
    neighbour), so that the roughly two candidates in three that lie outside the support
    cost no mispredicted jump; the pair loop then visits the neighbours only."""
    xi = x[i]
    zi = z[i]
    ci = comp[i]
    any_kind = want_kind < 0
    nn = 0
    c = cell_of[i]
    for row in (c - ncx, c, c + ncx):
        for j in range(cell_start[row - 1], cell_start[row + 2]):
            dx = xi - x[j]
            dz = zi - z[j]
            buf[nn] = j
            ok = (dx * dx + dz * dz < r2max) & (comp[j] == ci) & (any_kind | (kind[j] == want_kind))
            nn += 1 if ok else 0
    return nn
