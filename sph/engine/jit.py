"""One place for the numba compilation flags and the thread count.

Every numerical kernel of the engine is compiled with the flags defined here, so that a test
can run the same code with ``NUMBA_DISABLE_JIT=1`` and the whole engine changes behaviour in
one place.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

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

#: every kernel of the engine, as :func:`njit` made it, in the order defined
KERNELS: list = []


def njit(*args, **flags):
    """:func:`numba.njit`, keeping each kernel it makes in :data:`KERNELS` so that a process
    can tell which kernels it compiled itself (:func:`compiled_here`)."""
    if args and callable(args[0]):
        kernel = numba.njit(*args, **flags)
        KERNELS.append(kernel)
        return kernel
    decorate = numba.njit(*args, **flags)

    def keep(fn):
        kernel = decorate(fn)
        KERNELS.append(kernel)
        return kernel
    return keep


def compiled_here(parallel: bool = False) -> list[str]:
    """The kernels that this process compiled itself instead of loading them from numba's
    cache (the cache had no entry for a signature they were called with), by name; with
    ``parallel``, only those compiled with ``parallel=True``, the ones known to differ.

    A process that compiles the pair loop's parallel kernel itself runs other machine code,
    equal to round-off, than one that loads it from the cache (docs/checkpoints.md, "What
    is bit-identical, and why"): ``sph run`` starts again in a new process when this is not
    empty, so that every run computes with the kernels every later run loads. Kernels
    compiled without a cache (none in the engine) and Python functions (under
    ``NUMBA_DISABLE_JIT``) are not counted."""
    from numba.core.caching import NullCache

    names = []
    for kernel in KERNELS:
        stats = getattr(kernel, "stats", None)
        if stats is None or isinstance(getattr(kernel, "_cache", None), NullCache):
            continue
        if parallel and not kernel.targetoptions.get("parallel"):
            continue
        if sum(stats.cache_misses.values()):
            names.append(kernel.py_func.__qualname__)
    return names


def engine_source_hash(folder: Path = Path(__file__).parent) -> str:
    """A hash of every module of the engine (``sph/engine/*.py``): 16 hex digits."""
    h = hashlib.sha256()
    for path in sorted(folder.glob("*.py")):
        h.update(path.name.encode())
        h.update(path.read_bytes())
    return h.hexdigest()[:16]


def cache_dir(base: str | None = None) -> str:
    """Where numba keeps the engine's compiled kernels: a folder per version of the
    engine's sources, under ``NUMBA_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/sph-flood``
    (``~/.cache/sph-flood``).

    Numba checks a cached kernel against its own source file only: a kernel that inlines a
    function of another module (every pair loop inlines the kernel functions) would keep
    the old code after that module changed, and a run after an update would differ from a
    fresh installation's. A folder per version of the whole engine rules that out. (A
    process that compiles the pair loop's parallel kernel itself still runs other machine
    code, equal to round-off, than one that loads it from the cache, which is why ``sph
    run`` starts again once it has compiled kernels: :func:`compiled_here`,
    docs/checkpoints.md, "What is bit-identical, and why".)"""
    if not base:
        base = os.path.join(os.environ.get("XDG_CACHE_HOME")
                            or os.path.join(os.path.expanduser("~"), ".cache"), "sph-flood")
    return os.path.join(base, "numba-" + engine_source_hash())


# before any kernel below is defined: numba picks the cache folder when it decorates one
numba.config.CACHE_DIR = cache_dir(numba.config.CACHE_DIR)


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
