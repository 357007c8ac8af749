"""Structure-of-arrays particle storage.

All particles of a run (fluid and wall) live in two 2-D arrays, one of floats and one of
integers, one row per field. Sorting by cell (see :mod:`sph.engine.neighbours`) permutes both arrays
with one parallel gather, and the numba loops receive the rows as contiguous 1-D views.
"""

from __future__ import annotations

import numpy as np
from numba import prange

from sph.engine.jit import JIT_PARALLEL, njit

FLUID = 0
WALL = 1
#: the field ``body`` of a ghost fluid particle of a refinement level (it carries no mass;
#: :mod:`sph.engine.refinement`); an active fluid particle has -1
GHOST = -2

#: float fields, in row order
FLOAT_FIELDS = (
    "x", "z", "vx", "vz", "rho", "p", "m",
    "vx_old", "vz_old", "rho_old",  # previous level of the leapfrog (Verlet) scheme
    "ax", "az", "drho",  # time derivatives from the last evaluation
    "sx", "sz",  # particle shift from the last evaluation (sph.engine.shifting)
    "bx", "bz",  # wall particles: position in the frame of their body (rest position)
    "x_sort", "z_sort",  # position at the last sort by cell (sph.engine.neighbours)
    "x_inner", "z_inner",  # position at the last refresh of the inner lists (same)
    "hs",  # smoothing length over the case's h: 1, halved per refinement level
    # (sph.engine.refinement)
)
#: integer fields
INT_FIELDS = (
    "kind",  # FLUID or WALL
    "body",  # wall particles: motion group (0 = fixed tank); fluid: -1, GHOST for a ghost
    "comp",  # compartment: a pair interacts only when compartments match
    "pid",  # original index, stable across sorting
    "parent",  # refinement children: the pid of the particle they were made from; else -1
    # (sph.engine.refinement)
)
#: particles per block of the permutation
_GATHER_BLOCK = 2048
_FI = {n: k for k, n in enumerate(FLOAT_FIELDS)}
_II = {n: k for k, n in enumerate(INT_FIELDS)}
_FIELDS = FLOAT_FIELDS + INT_FIELDS


class Particles:
    """All particles of a run.

    Attributes are row views (``parts.x``, ``parts.kind``...) that stay valid until the next
    :meth:`permute`; re-read them after sorting.
    """

    def __init__(self, n: int):
        self.f = np.zeros((len(FLOAT_FIELDS), n), dtype=np.float64)
        self.i = np.zeros((len(INT_FIELDS), n), dtype=np.int32)
        self._f_buf = np.empty_like(self.f)
        self._i_buf = np.empty_like(self.i)
        self.i[_II["pid"]] = np.arange(n, dtype=np.int32)
        self.i[_II["parent"]] = -1
        self.f[_FI["hs"]] = 1.0

    @property
    def n(self) -> int:
        return self.f.shape[1]

    def __getattr__(self, name):
        # called only for a name not in the instance: the row view is made once and kept
        # there until permute swaps the arrays (a step reads about 90 of them)
        if name in _FI:
            view = self.f[_FI[name]]
        elif name in _II:
            view = self.i[_II[name]]
        else:
            raise AttributeError(name)
        self.__dict__[name] = view
        return view

    def _forget_views(self) -> None:
        for name in _FIELDS:
            self.__dict__.pop(name, None)

    def permute(self, order: np.ndarray) -> None:
        """Reorder every field so that particle ``k`` becomes the old ``order[k]``."""
        _gather(self.f, self._f_buf, order)
        _gather(self.i, self._i_buf, order)
        self.f, self._f_buf = self._f_buf, self.f
        self.i, self._i_buf = self._i_buf, self.i
        self._forget_views()

    def take(self, keep: np.ndarray) -> Particles:
        """A new set holding the particles where ``keep`` is True (order kept)."""
        # compress writes the rows contiguous; a mask on the columns (f[:, keep]) gave a
        # Fortran-ordered copy that of_columns then transposed: several times as long
        return Particles.of_columns(np.compress(keep, self.f, axis=1),
                                    np.compress(keep, self.i, axis=1))

    @classmethod
    def of_columns(cls, f: np.ndarray, i: np.ndarray) -> Particles:
        """A set holding the float and integer columns ``f``, ``i`` (rows as
        :data:`FLOAT_FIELDS` and :data:`INT_FIELDS`), copied to contiguous arrays."""
        out = cls.__new__(cls)
        out.f = np.ascontiguousarray(f)
        out.i = np.ascontiguousarray(i)
        out._f_buf = np.empty_like(out.f)
        out._i_buf = np.empty_like(out.i)
        return out

    @classmethod
    def from_arrays(cls, fluid_xz, fluid_rho, mass, wall_xz, wall_body, wall_body_xz,
                    fluid_comp=None, wall_comp=None) -> Particles:
        """Build the set from fluid and wall positions (fluid first, then walls)."""
        nf, nw = len(fluid_xz), len(wall_xz)
        parts = cls(nf + nw)
        parts.x[:nf], parts.z[:nf] = fluid_xz[:, 0], fluid_xz[:, 1]
        parts.x[nf:], parts.z[nf:] = wall_xz[:, 0], wall_xz[:, 1]
        parts.rho[:nf] = fluid_rho
        parts.rho_old[:nf] = fluid_rho
        parts.m[:] = mass
        parts.kind[nf:] = WALL
        parts.body[:nf] = -1
        parts.body[nf:] = wall_body
        parts.bx[nf:], parts.bz[nf:] = wall_body_xz[:, 0], wall_body_xz[:, 1]
        if fluid_comp is not None:
            parts.comp[:nf] = fluid_comp
        if wall_comp is not None:
            parts.comp[nf:] = wall_comp
        return parts


@njit(**JIT_PARALLEL)
def _gather(src, dst, order):
    """``dst[:, k] = src[:, order[k]]``, field by field within blocks of particles (each
    field's writes contiguous, its reads nearly so: ``order`` is close to the identity)."""
    nf = src.shape[0]
    n = src.shape[1]
    for b in prange((n + _GATHER_BLOCK - 1) // _GATHER_BLOCK):
        lo = b * _GATHER_BLOCK
        hi = min(n, lo + _GATHER_BLOCK)
        for f in range(nf):
            for k in range(lo, hi):
                dst[f, k] = src[f, order[k]]
