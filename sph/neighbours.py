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

from .jit import JIT, njit


class CellGrid:
    """Cells of side ``cell`` covering ``[xmin, xmax] x [zmin, zmax]`` plus one padding layer."""

    def __init__(self, xmin: float, xmax: float, zmin: float, zmax: float, cell: float):
        self.cell = float(cell)
        self.x0 = xmin - cell
        self.z0 = zmin - cell
        self.ncx = int(math.ceil((xmax - xmin) / cell)) + 2
        self.ncz = int(math.ceil((zmax - zmin) / cell)) + 2
        self.bounds = (xmin, xmax, zmin, zmax)
        self.cell_start = np.zeros(self.ncx * self.ncz + 1, dtype=np.int64)
        self._counts = np.zeros(self.ncx * self.ncz, dtype=np.int64)
        self.cell_of = np.zeros(0, dtype=np.int64)
        self.order = np.zeros(0, dtype=np.int64)

    def sort(self, x: np.ndarray, z: np.ndarray) -> int:
        """Bin the particles; fills ``order`` (new position -> old index), ``cell_start``
        and ``cell_of`` (cell of each particle in the *new* order). Returns the number of
        particles outside the domain."""
        n = x.shape[0]
        if self.order.shape[0] != n:
            self.order = np.empty(n, dtype=np.int64)
            self.cell_of = np.empty(n, dtype=np.int64)
            self._tmp = np.empty(n, dtype=np.int64)
        return _counting_sort(x, z, self.x0, self.z0, 1.0 / self.cell, self.ncx, self.ncz,
                              self._tmp, self._counts, self.cell_start, self.order,
                              self.cell_of)


@njit(**JIT)
def _counting_sort(x, z, x0, z0, inv_cell, ncx, ncz, tmp, counts, cell_start, order,
                   cell_sorted):
    n = x.shape[0]
    counts[:] = 0
    n_out = 0
    for i in range(n):
        fx = (x[i] - x0) * inv_cell
        fz = (z[i] - z0) * inv_cell
        # also catches NaN: comparisons with NaN are false
        if not (fx >= 1.0 and fx < ncx - 1 and fz >= 1.0 and fz < ncz - 1):
            n_out += 1
            fx = min(max(fx, 0.0), ncx - 1.0) if fx == fx else 0.0
            fz = min(max(fz, 0.0), ncz - 1.0) if fz == fz else 0.0
        c = int(fz) * ncx + int(fx)
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
