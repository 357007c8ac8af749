"""Small helpers shared by the tests."""

from __future__ import annotations

import os

import numpy as np
import pytest
import xarray as xr

from sph.analysis import validation_data_dir
from sph.cases.base import load_defaults
from sph.config import apply_overrides, build_case
from sph.solver import Simulation


def run_builtin(case: str, overrides) -> Simulation:
    """Build and run a built-in case with ``overrides`` (list of "key=value")."""
    cfg = build_case(apply_overrides(load_defaults(case), list(overrides)))
    return Simulation(cfg).run()


def require_validation_data():
    """The experimental series live outside the project; CI must have them."""
    d = validation_data_dir()
    if not d.is_dir():
        if os.environ.get("CI"):
            pytest.fail(f"validation data not found at {d} (set SPH_VALIDATION_DATA)")
        pytest.skip(f"validation data not found at {d} (set SPH_VALIDATION_DATA)")
    return d


def assert_same_series(a: xr.Dataset, b: xr.Dataset) -> None:
    """Every variable and coordinate equal bit for bit (NaN where NaN), same dtypes."""
    assert sorted(a.variables) == sorted(b.variables)
    for name in a.variables:
        x, y = a[name].values, b[name].values
        assert x.shape == y.shape, name
        if x.dtype.kind in "OUS":  # labels: str in memory, object when read from a file
            assert [str(v) for v in x.ravel()] == [str(v) for v in y.ravel()], name
            continue
        assert x.dtype == y.dtype, name
        if x.dtype.kind == "f":
            assert np.array_equal(x, y, equal_nan=True), name
        else:
            assert np.array_equal(x, y), name
