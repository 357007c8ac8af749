"""Typed, validated, frozen case configuration built from YAML.

A case file is a YAML mapping with the sections ``case``, ``title``, ``numerics``, ``fluid``,
``run``, ``geometry`` (its keys depend on the case) and ``probes``. Every key is declared
below with its type, default, allowed range and meaning; unknown keys, wrong types and
out-of-range values raise :class:`ConfigError` naming the key and the allowed range, before
any particle is created.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, get_args, get_origin, get_type_hints

import yaml


class ConfigError(ValueError):
    """An invalid case or sweep configuration; ``key`` is the dotted path of the culprit."""

    def __init__(self, key: str, message: str):
        self.key = key
        super().__init__(f"{key}: {message}" if key else message)


def spec(default=dataclasses.MISSING, *, lo=None, hi=None, lo_open=False, hi_open=False,
         choices=None, doc="", unit=""):
    """Declare a config field with its range and documentation."""
    meta = dict(lo=lo, hi=hi, lo_open=lo_open, hi_open=hi_open, choices=choices, doc=doc,
                unit=unit)
    if isinstance(default, list):
        return field(default_factory=lambda d=default: list(d), metadata=meta)
    return field(default=default, metadata=meta)


def show(value, limit: int = 80) -> str:
    """A value as an error message shows it: ``repr`` cut to ``limit`` characters; an
    integer too long to print (Python refuses beyond 4300 digits) by its size."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 200:
        return f"an integer of about {int(value.bit_length() * math.log10(2)) + 1} digits"
    try:
        text = repr(value)
    except (ValueError, RecursionError):  # huge integers inside containers, self-references
        text = f"a {type(value).__name__}"
    return text if len(text) <= limit else text[: limit - 4] + " ..."


def _range_text(meta) -> str:
    if meta.get("text"):
        return meta["text"]
    if meta.get("choices"):
        return "one of " + ", ".join(repr(c) for c in meta["choices"])
    lo, hi = meta.get("lo"), meta.get("hi")
    left = "(" if meta.get("lo_open") else "["
    right = ")" if meta.get("hi_open") else "]"
    lo_s = "-inf" if lo is None else f"{lo:g}"
    hi_s = "inf" if hi is None else f"{hi:g}"
    unit = f" {meta['unit']}" if meta.get("unit") else ""
    return f"in {left}{lo_s}, {hi_s}{right}{unit}"


def _type_name(tp) -> str:
    return {float: "a number", int: "an integer", str: "a string", bool: "true or false"}.get(
        tp, getattr(tp, "__name__", str(tp)))


def _check_scalar(key: str, value, tp, meta):
    if value is None and meta.get("default_none"):
        return None
    if tp is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ConfigError(key, f"expected a number {_range_text(meta)}, got {show(value)}")
        try:
            value = float(value)
        except OverflowError:  # an integer beyond the float range
            raise ConfigError(key, f"must be finite, {_range_text(meta)}; got {show(value)}"
                          ) from None
        if not math.isfinite(value):
            raise ConfigError(key, f"must be finite, {_range_text(meta)}; got {show(value)}")
    elif tp is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ConfigError(key, f"expected an integer {_range_text(meta)}, "
                              f"got {show(value)}")
    elif tp is bool:
        if not isinstance(value, bool):
            raise ConfigError(key, f"expected true or false, got {show(value)}")
        return value
    elif tp is str:
        if not isinstance(value, str):
            raise ConfigError(key, f"expected a string, got {show(value)}")
    choices = meta.get("choices")
    if choices is not None:
        if value not in choices:
            raise ConfigError(key, f"must be {_range_text(meta)}; got {show(value)}")
        return value
    if tp in (int, float):
        lo, hi = meta.get("lo"), meta.get("hi")
        bad = (lo is not None and (value < lo or (meta.get("lo_open") and value == lo))) or (
            hi is not None and (value > hi or (meta.get("hi_open") and value == hi)))
        if bad:
            raise ConfigError(key, f"must be {_range_text(meta)}; got {show(value)}")
    return value


def build(cls, data: Any, key: str = ""):
    """Build the frozen dataclass ``cls`` from ``data``, validating every field."""
    if data is None:
        data = {}
    if not isinstance(data, dict):
        raise ConfigError(key, f"expected a mapping of keys to values, got {show(data)}")
    hints = get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls)}
    for k in data:
        if k not in fields:
            allowed = ", ".join(sorted(fields))
            where = f"{key}.{k}" if key else str(k)
            raise ConfigError(where, f"unknown key {show(k)}; allowed keys here: {allowed}")
    values = {}
    for name, f in fields.items():
        sub = f"{key}.{name}" if key else name
        tp = hints[name]
        if name in data:
            value = data[name]
        elif f.default is not dataclasses.MISSING:
            values[name] = f.default
            continue
        elif f.default_factory is not dataclasses.MISSING:
            value = f.default_factory()
        else:
            want = _type_name(tp) if tp in (str, bool) else _range_text(f.metadata)
            raise ConfigError(sub, f"required key is missing (expected {want})")
        values[name] = _convert(sub, value, tp, f.metadata)
    obj = cls(**values)
    check = getattr(obj, "check", None)
    if check is not None:
        check(key)
    return obj


def _convert(key, value, tp, meta):
    origin = get_origin(tp)
    if origin is list:
        (item_tp,) = get_args(tp)
        if not isinstance(value, list):
            raise ConfigError(key, f"expected a list, got {show(value)}")
        return tuple(_convert(f"{key}[{i}]", v, item_tp, meta) for i, v in enumerate(value))
    if origin is not None and type(None) in get_args(tp):  # Optional[X]
        if value is None:
            return None
        (inner,) = [a for a in get_args(tp) if a is not type(None)]
        return _convert(key, value, inner, meta)
    if dataclasses.is_dataclass(tp):
        if isinstance(value, tp):
            return value
        return build(tp, value, key)
    return _check_scalar(key, value, tp, meta)


# --------------------------------------------------------------------------- sections


@dataclass(frozen=True)
class Numerics:
    """Discretisation and numerical model."""

    dx: float = spec(lo=0.0, lo_open=True, hi=100.0, unit="m", doc="initial particle spacing")
    kernel: str = spec("gaussian", choices=("gaussian", "wendland"),
                       doc="smoothing kernel: improved Gaussian (3h support) or Wendland C2 (2h)")
    h_factor: float | None = spec(None, lo=1.0, hi=2.0,
                                  doc="h/dx; default 1.23 (gaussian) or 1.41 (wendland)")
    density_filter: str = spec("mls", choices=("mls", "delta", "ddt", "none"),
                               doc="MLS re-initialisation, delta-SPH diffusion with the "
                                   "renormalised density gradient (delta) or with the "
                                   "hydrostatic density difference subtracted (ddt), or none")
    mls_interval: int = spec(20, lo=1, hi=10000, doc="steps between MLS re-initialisations")
    delta: float = spec(0.1, lo=0.0, hi=1.0, doc="delta-SPH coefficient (delta and ddt)")
    alpha: float = spec(0.02, lo=0.0, hi=1.0, doc="artificial viscosity coefficient")
    c_factor: float = spec(10.0, lo=3.0, hi=200.0,
                           doc="speed of sound c0 = c_factor * sqrt(g * depth)")
    cfl: float = spec(0.2, lo=0.0, lo_open=True, hi=0.5, doc="Courant number")
    euler_interval: int = spec(40, lo=2, hi=10000,
                               doc="steps between Euler re-couplings of the Verlet scheme")
    shifting: float = spec(0.0, lo=0.0, hi=10.0,
                           doc="particle shifting coefficient C (Sun et al. 2017); 0 = off")
    wall_layers: int = spec(0, lo=0, hi=20,
                            doc="layers of dummy particles; 0 = enough to cover the support")
    threads: int = spec(0, lo=0, hi=1024, doc="numba threads; 0 = NUMBA_NUM_THREADS")

    @property
    def h(self) -> float:
        from .kernels import DEFAULT_H_FACTOR

        return self.dx * (self.h_factor or DEFAULT_H_FACTOR[self.kernel])


@dataclass(frozen=True)
class Fluid:
    """Liquid properties and gravity."""

    rho0: float = spec(1000.0, lo=1.0, hi=1.0e5, unit="kg/m3", doc="reference density")
    gamma: float = spec(7.0, lo=1.0, hi=10.0, doc="Tait exponent")
    gravity: float = spec(9.81, lo=0.0, hi=100.0, unit="m/s2", doc="gravity (acts along -z)")


@dataclass(frozen=True)
class Run:
    """Duration, output and run-time checks."""

    t_end: float = spec(lo=0.0, lo_open=True, hi=1.0e6, unit="s", doc="simulated duration")
    output_interval: float = spec(0.01, lo=0.0, lo_open=True, hi=1.0e6, unit="s",
                                  doc="time between output samples")
    vtk_interval: float = spec(0.0, lo=0.0, hi=1.0e6, unit="s",
                               doc="time between ParaView snapshots; 0 = none")
    max_steps: int = spec(0, lo=0, hi=10**12, doc="stop after this many steps; 0 = no limit")
    check_interval: int = spec(10, lo=1, hi=100000, doc="steps between blow-up checks")
    density_min: float = spec(0.5, lo=0.0, lo_open=True, hi=1.0, hi_open=True,
                              doc="blow-up if a fluid density falls below this times rho0")
    density_max: float = spec(1.5, lo=1.0, lo_open=True, hi=10.0,
                              doc="blow-up if a fluid density exceeds this times rho0")
    max_lost_fraction: float = spec(0.001, lo=0.0, hi=0.1,
                                    doc="fraction of the fluid particles that may leave the "
                                        "domain (removed and counted, with a warning) before "
                                        "the run stops as blown up; 0 = stop at the first")
    flush_seconds: float = spec(60.0, lo=0.0, lo_open=True, hi=1.0e6, unit="s",
                                doc="wall time between rewrites of the partial output")
    checkpoint_interval: float = spec(0.0, lo=0.0, hi=1.0e6, unit="s",
                                      doc="simulated time between checkpoints; 0 = none by "
                                      "simulated time")
    checkpoint_wall_seconds: float = spec(600.0, lo=0.0, hi=1.0e7, unit="s",
                                          doc="wall time between checkpoints; 0 = none by "
                                          "wall time")
    keep_checkpoints: bool = spec(False, doc="keep the checkpoints (and write a last one) "
                                  "after a successful finish, e.g. to extend the run later "
                                  "with a larger t_end; by default they are deleted")

    def check(self, key):
        if self.output_interval > self.t_end:
            raise ConfigError(f"{key}.output_interval",
                              f"must be in (0, run.t_end = {self.t_end:g}] s; "
                              f"got {self.output_interval:g}")


@dataclass(frozen=True)
class SurfaceProbe:
    """Earth-fixed free-surface elevation probe."""

    name: str = spec(doc="probe name")
    x: float = spec(lo=-1.0e6, hi=1.0e6, unit="m", doc="abscissa")


@dataclass(frozen=True)
class PressureProbe:
    """Earth-fixed pressure probe on a wall."""

    name: str = spec(doc="probe name")
    x: float = spec(lo=-1.0e6, hi=1.0e6, unit="m", doc="abscissa")
    z: float = spec(lo=-1.0e6, hi=1.0e6, unit="m", doc="height")


@dataclass(frozen=True)
class Probes:
    surface: list[SurfaceProbe] = spec([], doc="free-surface elevation probes")
    pressure: list[PressureProbe] = spec([], doc="wall pressure probes")

    def check(self, key):
        names = [p.name for p in self.surface] + [p.name for p in self.pressure]
        for n in names:
            if names.count(n) > 1:
                raise ConfigError(f"{key}", f"probe name {n!r} is used twice; names must be "
                                  "unique")


@dataclass(frozen=True)
class CaseConfig:
    """A whole case: which built-in geometry, and every parameter of the run."""

    case: str
    title: str
    numerics: Numerics
    fluid: Fluid
    run: Run
    geometry: Any
    probes: Probes

    def to_dict(self) -> dict:
        return _to_plain(self)

    def to_yaml(self) -> str:
        return yaml.safe_dump(self.to_dict(), sort_keys=False)


def _to_plain(obj):
    if dataclasses.is_dataclass(obj):
        return {f.name: _to_plain(getattr(obj, f.name)) for f in dataclasses.fields(obj)}
    if isinstance(obj, (list, tuple)):
        return [_to_plain(v) for v in obj]
    return obj


# --------------------------------------------------------------------------- loading


def parse_override(text: str) -> tuple[str, Any]:
    """Split ``key.sub=value`` (value parsed as YAML)."""
    if "=" not in text:
        raise ConfigError(text, "an override must look like key.subkey=value")
    key, raw = text.split("=", 1)
    key = key.strip()
    if not key:
        raise ConfigError(text, "an override must name a key before '='")
    try:
        value = yaml.safe_load(raw)
    except _YAML_ERRORS as exc:
        raise ConfigError(key, f"cannot parse value {show(raw)}: {_yaml_problem(exc)}"
                          ) from None
    return key, value


#: what ``yaml.safe_load`` raises on bad input: syntax errors, and ValueError (or its
#: subclasses) from constructing a scalar such as an impossible date ``2021-02-30`` or an
#: integer of more than 4300 digits; RecursionError on absurdly deep nesting
_YAML_ERRORS = (yaml.YAMLError, ValueError, RecursionError)


def _yaml_problem(exc: BaseException) -> str:
    mark = getattr(exc, "problem_mark", None)
    where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
    if isinstance(exc, yaml.YAMLError):
        problem = getattr(exc, "problem", None) or "syntax error"
    elif isinstance(exc, RecursionError):
        problem = "nested too deeply"
    else:
        problem = f"unreadable value ({show(str(exc), 120)})"
    return f"{problem}{where}"


def apply_overrides(data: dict, overrides) -> dict:
    """Set dotted keys in a nested mapping (copying the touched levels)."""
    data = dict(data)
    for item in overrides:
        key, value = parse_override(item) if isinstance(item, str) else item
        parts = key.split(".")
        node = data
        for i, part in enumerate(parts[:-1]):
            nxt = node.get(part)
            if nxt is None:
                nxt = {}
            elif not isinstance(nxt, dict):
                raise ConfigError(".".join(parts[: i + 1]), "is not a section; cannot set "
                                  f"{key}")
            node[part] = nxt = dict(nxt)
            node = nxt
        node[parts[-1]] = value
    return data


def load_yaml(path: str | Path) -> dict:
    """Read a case file as a mapping, with a clear error on YAML syntax errors."""
    path = Path(path)
    try:
        text = path.read_bytes().decode("utf-8")
    except OSError as exc:
        raise ConfigError("", f"cannot read case file {str(path)!r}: {exc.strerror}") from None
    except UnicodeDecodeError as exc:
        line = exc.object[: exc.start].count(b"\n") + 1
        raise ConfigError("", f"{path} is not UTF-8 text: byte 0x{exc.object[exc.start]:02x} "
                          f"at line {line} cannot be decoded") from None
    try:
        data = yaml.safe_load(text)
    except _YAML_ERRORS as exc:
        raise ConfigError("", f"{path} is not valid YAML: {_yaml_problem(exc)}") from None
    if not isinstance(data, dict):
        raise ConfigError("", f"{path} must hold a mapping of sections (case, numerics, ...)")
    return data


def build_case(data: dict) -> CaseConfig:
    """Validate a raw mapping into a :class:`CaseConfig`."""
    from .cases import CASES

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
    merged = _deep_merge(case.defaults(), data)
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


def _deep_merge(base: dict, top: dict) -> dict:
    out = dict(base)
    for k, v in top.items():
        if isinstance(v, dict) and isinstance(out.get(k), dict):
            out[k] = _deep_merge(out[k], v)
        else:
            out[k] = v
    return out
