"""Tests of the engine's compilation settings (sph.engine.jit)."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path


def test_compiled_kernels_are_cached_per_version_of_the_engine(tmp_path):
    """Numba checks a cached kernel against its own file only; the engine keeps its cache in
    a folder named by a hash of every engine module, so a change to any module (say the
    kernel functions that every pair loop inlines) gives a fresh process a fresh cache."""
    import numba

    from sph.engine import jit

    engine = Path(jit.__file__).parent
    copy = tmp_path / "engine"
    copy.mkdir()
    for f in engine.glob("*.py"):
        (copy / f.name).write_bytes(f.read_bytes())
    before = jit.engine_source_hash(copy)
    assert before == jit.engine_source_hash(engine)
    with open(copy / "kernels.py", "a") as fh:
        fh.write("\n# changed\n")
    assert jit.engine_source_hash(copy) != before
    assert numba.config.CACHE_DIR == jit.cache_dir(os.environ.get("NUMBA_CACHE_DIR"))
    assert numba.config.CACHE_DIR.endswith("numba-" + before)
    # a fresh process puts its compiled kernels there
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    code = textwrap.dedent("""
        import numpy as np
        from sph.engine.eos import fluid_pressures
        rho = np.full(3, 1000.0); p = np.zeros(3)
        fluid_pressures(rho, np.zeros(3, np.int32), p, 1000.0, 1.0e5, 7.0)
    """)
    subprocess.run([sys.executable, "-c", code], env=env, check=True)
    assert list((tmp_path / "cache" / ("numba-" + before)).rglob("*.nbi"))


def test_the_fluid_loop_variants_are_found_again_in_the_cache():
    """Numba keys a cached closure by a hash of its cells, pickled. The fluid loop's compiled
    variants (``sph.engine.fluid._INTERACT``) close over their three flags alone, and two
    processes hash them alike; a compiled function in a cell would pickle with an identity
    of its own process, and the variant would be compiled anew by every run."""
    from sph.engine.fluid import _INTERACT

    for key, variant in _INTERACT.items():
        cells = tuple(c.cell_contents for c in variant.py_func.__closure__)
        assert sorted(cells) == sorted(key), key
    code = textwrap.dedent("""
        import hashlib
        from numba.core.serialize import dumps
        from sph.engine.fluid import _INTERACT
        for key in sorted(_INTERACT):
            cells = tuple(c.cell_contents for c in _INTERACT[key].py_func.__closure__)
            print(key, hashlib.sha256(dumps(cells)).hexdigest())
    """)
    runs = [subprocess.run([sys.executable, "-c", code], check=True, capture_output=True,
                           text=True).stdout for _ in range(2)]
    assert runs[0] == runs[1] and len(runs[0].splitlines()) == 8


def test_a_run_that_asks_for_two_threads_gets_two(monkeypatch):
    """The suite's workers run on one thread by default (``SPH_THREADS=1``, tests/conftest.py);
    the tests of the parallel loops ask for two (``numerics.threads: 2``) and must get two,
    or they would check the loops on one thread only. Without the key a run takes
    ``SPH_THREADS``, and the count is kept within numba's pool (``NUMBA_NUM_THREADS``)."""
    import numba
    import pytest

    from sph.engine.jit import set_threads

    limit = numba.config.NUMBA_NUM_THREADS
    if limit < 2:
        pytest.skip("NUMBA_NUM_THREADS=1: numba's pool has one thread")
    monkeypatch.setenv("SPH_THREADS", "1")
    assert set_threads(2) == 2 and numba.get_num_threads() == 2
    assert set_threads(0) == 1 and numba.get_num_threads() == 1
    assert set_threads(limit + 5) == limit


def test_a_process_knows_the_kernels_it_compiled_itself(tmp_path):
    """:func:`sph.engine.jit.compiled_here` names the kernels a process compiled (an empty
    cache: ``fluid_pressures`` and the serial ``tait_pressure`` it calls), and none once
    they are cached (a second process); with ``parallel`` it keeps to the parallel ones."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    code = textwrap.dedent("""
        import numpy as np
        from sph.engine.eos import fluid_pressures
        from sph.engine.jit import compiled_here
        rho = np.full(3, 1000.0); p = np.zeros(3)
        fluid_pressures(rho, np.zeros(3, np.int32), p, 1000.0, 1.0e5, 7.0)
        print(sorted(compiled_here()), compiled_here(parallel=True))
    """)
    runs = [subprocess.run([sys.executable, "-c", code], env=env, check=True,
                           capture_output=True, text=True).stdout.strip() for _ in range(2)]
    assert runs == ["['fluid_pressures', 'tait_pressure'] ['fluid_pressures']", "[] []"]
