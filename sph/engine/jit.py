"""One place for the numba compilation flags and the thread count.

Every numerical kernel of the engine is compiled with the flags defined here, so that a test
can run the same code with ``NUMBA_DISABLE_JIT=1`` and the whole engine changes behaviour in
one place.
"""

from __future__ import annotations

import os

import numba

#: fast-math flags: reassociation and contraction (vectorised reductions) but no assumption
#: that values are finite, so NaN/inf checks stay meaningful
FASTMATH = {"nsz", "arcp", "contract", "afn", "reassoc"}
#: flags for serial kernels
JIT = dict(cache=True, fastmath=FASTMATH, nogil=True)
#: flags for the inner pair loops: a float division by zero gives inf or NaN (as in numpy;
#: the run's checks catch it) instead of raising, so that no check and branch is compiled
#: into every division
JIT_PAIR = dict(JIT, error_model="numpy")
#: flags for a ``prange`` loop that inlines pair loops of :data:`JIT_PAIR`
JIT_PARALLEL_PAIR = dict(JIT_PAIR, parallel=True)
#: flags for kernels with a ``prange`` loop
JIT_PARALLEL = dict(JIT, parallel=True)

njit = numba.njit


def set_threads(n: int | None) -> int:
    """Set numba's thread count explicitly and return the number in use.

    Parameters
    ----------
    n : int or None
        Requested number of threads; ``None`` or ``0`` means ``NUMBA_NUM_THREADS`` (the
        environment's choice, itself defaulting to the number of cores).
    """
    limit = numba.config.NUMBA_NUM_THREADS
    if not n:
        n = int(os.environ.get("SPH_THREADS", limit))
    n = max(1, min(int(n), limit))
    numba.set_num_threads(n)
    return n
