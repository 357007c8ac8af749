"""Shared pytest configuration for the whole suite."""

import os

import numba
import numpy as np
import pytest

# The suite runs in two pytest-xdist workers (``-n 2`` in pyproject.toml's addopts), one per
# core of CI and small laptops. Each worker's runs take one thread by default
# (``SPH_THREADS``, :func:`sph.engine.jit.set_threads`): two workers of two threads each on
# two cores spend their time waiting at the parallel loops' barriers. The tests that check
# the parallel loops ask for two threads themselves (``numerics.threads: 2``), and get
# them within ``NUMBA_NUM_THREADS``. Without xdist (``-n 0``) every run takes two.
if os.environ.get("PYTEST_XDIST_WORKER"):
    os.environ.setdefault("SPH_THREADS", "1")
DEFAULT_THREADS = max(1, min(int(os.environ.get("SPH_THREADS", 2)), 2,
                             numba.config.NUMBA_NUM_THREADS))
numba.set_num_threads(DEFAULT_THREADS)


@pytest.fixture(autouse=True)
def _default_threads():
    """Put the thread count back after a test that set its own (``numerics.threads``)."""
    yield
    numba.set_num_threads(DEFAULT_THREADS)


@pytest.fixture(autouse=True)
def _raise_on_floating_point_errors():
    """Turn silent NaN/inf producers (divide, overflow, invalid) into exceptions."""
    previous = np.seterr(all="raise")
    try:
        yield
    finally:
        np.seterr(**previous)
