"""Schema machinery for validated, frozen configurations built from YAML.

Declare each key of a section with :func:`spec` (type, default, allowed range, meaning) on a
frozen dataclass; :func:`build` turns a mapping into that dataclass and raises
:class:`ConfigError` naming the key and the allowed range for an unknown key, a wrong type
or an out-of-range value. Also: ``key.sub=value`` overrides and YAML loading with clear
errors. This module imports nothing from the project.
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import field
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
            hint = ""
            if isinstance(value, str) and re.fullmatch(r"\s*[-+]?\d*\.?\d+[eE]\d+\s*", value):
                hint = " (YAML reads an exponent without its sign as text: write 1.0e+5)"
            raise ConfigError(key, f"expected a number {_range_text(meta)}, got "
                                   f"{show(value)}{hint}")
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
        if not isinstance(value, (list, tuple)):  # a tuple: a built configuration's own
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


def deep_merge(base: dict, top: dict) -> dict:
    out = dict(base)
    for k, v in top.items():
        if isinstance(v, dict) and isinstance(out.get(k), dict):
            out[k] = deep_merge(out[k], v)
        else:
            out[k] = v
    return out
