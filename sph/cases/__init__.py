"""Built-in cases and the case registry.

Each built-in case is a YAML file of defaults (``sph example NAME`` prints it) plus the
geometry code that builds its particles. A user's case file names the case and overrides what
it needs; :func:`load_case` reads, overrides and validates one, :func:`builtin` builds a
built-in case with overrides in one call.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from sph.cases import current, dam_break, floating_box, ship, sloshing, still_water, wave_tank
from sph.cases.base import example_text, load_defaults
from sph.engine.config import CaseConfig, Fluid, Numerics, Probes, Run
from sph.schema import ConfigError, apply_overrides, build, deep_merge, load_yaml, show

__all__ = ["CASES", "build_case", "builtin", "example_text", "load_case", "load_defaults",
           "setup"]

#: name -> module with ``Geometry``, ``defaults()``, ``check(cfg)`` and ``setup(cfg)``
CASES = {
    "still_water": still_water,
    "dam_break": dam_break,
    "sloshing_rect": sloshing.Rect,
    "sloshing_u": sloshing.UTank,
    "wave_tank": wave_tank,
    "floating_box": floating_box,
    "ship_decay": ship.ShipDecay,
    "damaged_ship": ship.DamagedShip,
    "current_tank": current.CurrentTank,
    "cylinder_in_current": current.CylinderInCurrent,
}


def build_case(data: dict) -> CaseConfig:
    """Validate a raw mapping into a :class:`CaseConfig`."""
    if not isinstance(data, dict):
        raise ConfigError("", "a case must be a mapping of sections")
    allowed = {f.name for f in dataclasses.fields(CaseConfig)}
    for k in data:
        if k not in allowed:
            raise ConfigError(str(k), f"unknown key {show(k)}; allowed top-level keys: "
                              + ", ".join(sorted(allowed)))
    name = data.get("case")
    if not isinstance(name, str) or name not in CASES:
        raise ConfigError("case", f"must be one of {', '.join(sorted(CASES))}; "
                          f"got {show(name)}")
    case = CASES[name]
    # defaults of the built-in case first, then the user's values on top
    merged = deep_merge(case.defaults(), data)
    title = merged.get("title", name)
    if not isinstance(title, str):
        raise ConfigError("title", f"expected a string, got {show(title)}")
    cfg = CaseConfig(
        case=name,
        title=title,
        numerics=build(Numerics, merged.get("numerics"), "numerics"),
        fluid=build(Fluid, merged.get("fluid"), "fluid"),
        run=build(Run, merged.get("run"), "run"),
        geometry=build(case.Geometry, merged.get("geometry"), "geometry"),
        probes=build(Probes, merged.get("probes"), "probes"),
    )
    case.check(cfg)
    return cfg


def load_case(path: str | Path, overrides=()) -> CaseConfig:
    """Read, override and validate a case file."""
    return build_case(apply_overrides(load_yaml(path), overrides))


def builtin(name: str, overrides=()) -> CaseConfig:
    """The built-in case ``name`` with ``overrides`` (``"key.sub=value"`` strings or
    ``(key, value)`` pairs) applied, validated."""
    if name not in CASES:
        raise ConfigError("case", f"must be one of {', '.join(sorted(CASES))}; "
                          f"got {show(name)}")
    return build_case(apply_overrides(load_defaults(name), overrides))


def setup(cfg: CaseConfig):
    """Particles and case data (:class:`sph.cases.base.CaseSetup`) of a validated case."""
    return CASES[cfg.case].setup(cfg)
