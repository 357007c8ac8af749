"""Small helpers shared by the physics tests."""

from __future__ import annotations

import os

import pytest

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
