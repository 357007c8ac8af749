"""Shared pytest configuration for the whole suite."""

import numba
import numpy as np
import pytest

# Keep numba's thread pool within the 2-core budget of CI and small laptops.
numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))


@pytest.fixture(autouse=True)
def _raise_on_floating_point_errors():
    """Turn silent NaN/inf producers (divide, overflow, invalid) into exceptions."""
    previous = np.seterr(all="raise")
    try:
        yield
    finally:
        np.seterr(**previous)
