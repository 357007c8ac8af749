"""Generators of invalid configurations for property-based tests (hypothesis).

A :class:`Schema` describes one kind of configuration: a valid raw mapping to start from,
its leaves (dotted key, type and allowed range) and how to load a mapping, a file or a list
of ``key=value`` overrides. Each entry of :data:`KINDS` turns a schema into a hypothesis
strategy of :class:`Invalid` inputs (one kind of mistake each) together with the key the
refusal must name. Case configurations are described by :func:`case_schema`; another
schema (e.g. the workflow's sweep files) plugs in by building a :class:`Schema` for it.
"""

from __future__ import annotations

import dataclasses
import math
import string
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, get_args, get_origin, get_type_hints

import yaml
from hypothesis import strategies as st

# --------------------------------------------------------------------------- description


@dataclass(frozen=True)
class Leaf:
    """One scalar key of a schema: dotted ``key`` (list items as ``name[0]``), its type
    (``float``, ``int``, ``bool``, ``str``), range and choices, whether null is allowed."""

    key: str
    type: type
    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    choices: tuple | None = None
    nullable: bool = False


@dataclass(frozen=True)
class Schema:
    """What the generators need to know about one configuration schema.

    Attributes
    ----------
    name : str
        For test ids.
    valid : dict
        A valid raw mapping (every key present) that the generators change in one place.
    leaves : tuple of Leaf
        The scalar keys of ``valid``.
    sections : tuple of str
        Dotted keys of the mappings in ``valid`` (the top level is ``""``).
    lists : tuple of str
        Dotted keys of the lists of mappings in ``valid``.
    load_mapping : callable(dict)
        Validates a raw mapping; raises ``error`` when it is invalid.
    load_file : callable(Path, overrides)
        Reads and validates a file with ``key=value`` overrides.
    error : exception type
        What a refusal raises; ``key_of(exc)`` returns the key it names.
    """

    name: str
    valid: dict
    leaves: tuple[Leaf, ...]
    sections: tuple[str, ...]
    lists: tuple[str, ...]
    load_mapping: Callable[[dict], Any]
    load_file: Callable[[Path, list], Any]
    error: type[Exception]
    key_of: Callable[[Exception], str] = lambda exc: exc.key  # noqa: E731
    cross_field: tuple[Callable[[dict], tuple[dict, str]], ...] = ()


@dataclass
class Invalid:
    """One invalid input: a mapping, or file bytes (plus overrides), and the key that the
    refusal must name (``""``: a problem of the whole file, named by its path)."""

    kind: str
    key: str
    mapping: dict | None = None
    text: bytes | None = None
    overrides: list = field(default_factory=list)


# --------------------------------------------------------------------------- mapping edits


def get(mapping: dict, key: str):
    node = mapping
    for part in _parts(key):
        node = node[part]
    return node


def replaced(mapping: dict, key: str, value) -> dict:
    """A deep copy of ``mapping`` with ``key`` (dotted, list items as ``name[i]``) set."""
    out = _copy(mapping)
    parts = _parts(key)
    node = out
    for part in parts[:-1]:
        node = node[part]
    node[parts[-1]] = value
    return out


def _copy(node):
    if isinstance(node, dict):
        return {k: _copy(v) for k, v in node.items()}
    if isinstance(node, list):
        return [_copy(v) for v in node]
    return node


def _parts(key: str) -> list:
    parts: list = []
    for part in key.split(".") if key else []:
        while "[" in part:
            name, rest = part.split("[", 1)
            if name:
                parts.append(name)
            idx, part = rest.split("]", 1)
            parts.append(int(idx))
        if part:
            parts.append(part)
    return parts


def _join(section: str, key) -> str:
    return f"{section}.{key}" if section else str(key)


# --------------------------------------------------------------------------- case schema


def _walk(cls, data: dict, prefix: str, leaves, sections, lists) -> None:
    sections.append(prefix)
    hints = get_type_hints(cls)
    for f in dataclasses.fields(cls):
        key = _join(prefix, f.name)
        tp = hints[f.name]
        value = data.get(f.name)
        nullable = False
        if get_origin(tp) is not None and type(None) in get_args(tp) and get_origin(tp) \
                is not list:
            nullable = True
            (tp,) = [a for a in get_args(tp) if a is not type(None)]
        if get_origin(tp) is list:
            (item,) = get_args(tp)
            if dataclasses.is_dataclass(item):
                lists.append(key)
                for i, v in enumerate(value or []):
                    _walk(item, v, f"{key}[{i}]", leaves, sections, lists)
            continue
        if dataclasses.is_dataclass(tp):
            _walk(tp, value or {}, key, leaves, sections, lists)
            continue
        if tp is Any:
            continue
        m = f.metadata
        leaves.append(Leaf(key, tp, m.get("lo"), m.get("hi"), bool(m.get("lo_open")),
                           bool(m.get("hi_open")), m.get("choices"), nullable))


def case_schema(name: str) -> Schema:
    """The schema of the built-in case ``name`` (:mod:`sph.schema`)."""
    from sph.cases import CASES, build_case, load_case
    from sph.cases.base import load_defaults
    from sph.engine.config import CaseConfig
    from sph.schema import ConfigError

    valid = build_case(load_defaults(name)).to_dict()
    leaves: list[Leaf] = [Leaf("title", str)]
    sections: list[str] = []
    lists: list[str] = []
    sections.append("")
    hints = get_type_hints(CaseConfig)
    for f in dataclasses.fields(CaseConfig):
        tp = CASES[name].Geometry if f.name == "geometry" else hints[f.name]
        if dataclasses.is_dataclass(tp):
            _walk(tp, valid[f.name], f.name, leaves, sections, lists)

    def output_interval_beyond_t_end(mapping):
        t_end = mapping["run"]["t_end"]
        return replaced(mapping, "run.output_interval", t_end * 1.5), "run.output_interval"

    def duplicate_probe_names(mapping):
        probes = [{"name": "p", "x": 0.0}, {"name": "p", "x": 0.0}]
        return replaced(mapping, "probes.surface", probes), "probes"

    return Schema(
        name=name, valid=valid, leaves=tuple(leaves), sections=tuple(sections),
        lists=tuple(lists), load_mapping=build_case, load_file=load_case, error=ConfigError,
        cross_field=(output_interval_beyond_t_end, duplicate_probe_names),
    )


# --------------------------------------------------------------------------- strategies

IDENT = st.text(string.ascii_lowercase + "_", min_size=1, max_size=12)
JUNK_SCALARS = st.one_of(st.text(max_size=20), st.integers(), st.floats(allow_nan=False),
                         st.booleans(), st.none())


def _leaves(schema: Schema, pred) -> st.SearchStrategy[Leaf]:
    chosen = [leaf for leaf in schema.leaves if pred(leaf)]
    return st.sampled_from(chosen)


def _numeric(leaf: Leaf) -> bool:
    return leaf.type in (int, float) and leaf.choices is None


def _on_leaf(kind, schema, pred, values):
    """Strategy: a leaf matching ``pred`` set to a value drawn from ``values(leaf)``."""

    @st.composite
    def build(draw):
        leaf = draw(_leaves(schema, pred))
        value = draw(values(leaf))
        return Invalid(kind, leaf.key, mapping=replaced(schema.valid, leaf.key, value))

    return build()


def _below(leaf: Leaf):
    lo = leaf.lo
    if leaf.type is int:
        return st.integers(max_value=int(lo) - (0 if leaf.lo_open else 1))
    values = st.floats(max_value=lo, allow_nan=False, allow_infinity=False)
    if leaf.lo_open:
        return st.one_of(st.just(float(lo)), values.filter(lambda v: v <= lo))
    return values.filter(lambda v: v < lo)


def _above(leaf: Leaf):
    hi = leaf.hi
    if leaf.type is int:
        return st.integers(min_value=int(hi) + (0 if leaf.hi_open else 1))
    values = st.floats(min_value=hi, allow_nan=False, allow_infinity=False)
    if leaf.hi_open:
        return st.one_of(st.just(float(hi)), values.filter(lambda v: v >= hi))
    return values.filter(lambda v: v > hi)


def _unknown_key(schema: Schema, kind: str, where):
    @st.composite
    def build(draw):
        section = draw(st.sampled_from(where))
        node = get(schema.valid, section)
        key = draw(IDENT.filter(lambda k: k not in node))
        value = draw(JUNK_SCALARS)
        return Invalid(kind, _join(section, key),
                       mapping=replaced(schema.valid, _join(section, key), value))

    return build()


def _file(schema: Schema, kind: str, make_bytes):
    """Strategy: the valid mapping as YAML text, changed by ``make_bytes(draw, text)``; the
    refusal names the file (key ``""``)."""

    @st.composite
    def build(draw):
        text = yaml.safe_dump(schema.valid, sort_keys=False).encode()
        return Invalid(kind, "", text=make_bytes(draw, text))

    return build()


def _insert_line(draw, text: bytes, line: bytes) -> bytes:
    lines = text.split(b"\n")
    at = draw(st.integers(0, len(lines)))
    return b"\n".join(lines[:at] + [line] + lines[at:])


def _override(schema: Schema, kind: str, make):
    """Strategy: the valid mapping as a file plus one bad override ``make(draw) ->
    (override, key)``."""

    @st.composite
    def build(draw):
        override, key = make(draw)
        text = yaml.safe_dump(schema.valid, sort_keys=False).encode()
        return Invalid(kind, key, text=text, overrides=[override])

    return build()


def kinds(schema: Schema) -> dict[str, st.SearchStrategy[Invalid]]:
    """Every kind of invalid input, as name -> strategy of :class:`Invalid`."""
    s = schema
    numeric = _numeric
    ranged_lo = lambda leaf: numeric(leaf) and leaf.lo is not None  # noqa: E731
    ranged_hi = lambda leaf: numeric(leaf) and leaf.hi is not None  # noqa: E731
    open_bound = lambda leaf: numeric(leaf) and (leaf.lo_open or leaf.hi_open)  # noqa: E731
    scalar = lambda leaf: True  # noqa: E731
    plain_str = lambda leaf: leaf.type is str  # noqa: E731
    required = lambda leaf: not leaf.nullable  # noqa: E731
    nested = [sec for sec in s.sections if sec.count(".") >= 1 or "[" in sec] or [""]
    top_sections = [sec for sec in s.sections if sec and "." not in sec and "[" not in sec]

    def open_value(leaf):
        bounds = ([leaf.lo] if leaf.lo_open else []) + ([leaf.hi] if leaf.hi_open else [])
        return st.sampled_from([leaf.type(b) for b in bounds])

    def bad_choice(leaf):
        return st.text(max_size=15).filter(lambda v: v not in leaf.choices)

    out = {
        # ---- keys
        "unknown top-level key": _unknown_key(s, "unknown top-level key", [""]),
        "unknown key in a section": _unknown_key(s, "unknown key in a section", top_sections),
        "unknown key in a nested section or list item":
            _unknown_key(s, "unknown key in a nested section or list item", nested),
        "non-string key": st.builds(
            lambda sec, k: Invalid("non-string key", _join(sec, k),
                                   mapping=_with_key(s.valid, sec, k)),
            st.sampled_from(s.sections),
            st.one_of(st.integers(), st.booleans(), st.none(),
                      st.floats(allow_nan=False, allow_infinity=False))),
        # ---- types
        "string for a number": _on_leaf("string for a number", s, numeric,
                                        lambda leaf: st.text(max_size=20)),
        "boolean for a number": _on_leaf("boolean for a number", s, numeric,
                                         lambda leaf: st.booleans()),
        "list or mapping for a scalar": _on_leaf(
            "list or mapping for a scalar", s, scalar,
            lambda leaf: st.one_of(st.lists(JUNK_SCALARS, max_size=3),
                                   st.dictionaries(IDENT, JUNK_SCALARS, max_size=3))),
        "number or boolean for a string": _on_leaf(
            "number or boolean for a string", s, plain_str,
            lambda leaf: st.one_of(st.integers(), st.floats(), st.booleans())),
        "number or string for a boolean": _on_leaf(
            "number or string for a boolean", s, lambda leaf: leaf.type is bool,
            lambda leaf: st.one_of(st.integers(), st.floats(), st.text(max_size=8))),
        "float for an integer": _on_leaf("float for an integer", s,
                                         lambda leaf: leaf.type is int,
                                         lambda leaf: st.floats()),
        "date for a number": _on_leaf(
            "date for a number", s, numeric, lambda leaf: st.dates()),
        "null for a required value": _on_leaf("null for a required value", s, required,
                                              lambda leaf: st.none()),
        # ---- values
        "below the range": _on_leaf("below the range", s, ranged_lo, _below),
        "above the range": _on_leaf("above the range", s, ranged_hi, _above),
        "on an open bound": _on_leaf("on an open bound", s, open_bound, open_value),
        "NaN": _on_leaf("NaN", s, lambda leaf: leaf.type is float,
                        lambda leaf: st.just(math.nan)),
        "infinity": _on_leaf("infinity", s, lambda leaf: leaf.type is float,
                             lambda leaf: st.sampled_from([math.inf, -math.inf])),
        "huge integer for a float": _on_leaf(
            "huge integer for a float", s, lambda leaf: leaf.type is float,
            lambda leaf: st.integers(309, 6000).map(lambda n: 10**n * 7)),
        "huge integer for an integer": _on_leaf(
            "huge integer for an integer", s,
            lambda leaf: _numeric(leaf) and leaf.type is int and leaf.hi is not None
            and leaf.lo is not None,
            lambda leaf: st.integers(20, 6000).map(lambda n: -(10**n) if n % 2 else 10**n)),
        "value not among the choices": _on_leaf(
            "value not among the choices", s, lambda leaf: leaf.choices is not None,
            bad_choice),
        # ---- structure
        "section that is not a mapping": st.builds(
            lambda sec, v: Invalid("section that is not a mapping", sec,
                                   mapping=replaced(s.valid, sec, v)),
            st.sampled_from([sec for sec in s.sections if sec]),
            st.one_of(st.integers(), st.text(max_size=10), st.lists(st.integers(),
                                                                    max_size=2))),
        "list that is not a list": st.builds(
            lambda key, v: Invalid("list that is not a list", key,
                                   mapping=replaced(s.valid, key, v)),
            st.sampled_from(s.lists), st.one_of(st.integers(), st.text(max_size=10),
                                                st.dictionaries(IDENT, st.integers(),
                                                                max_size=2))),
        "list item that is not a mapping": st.builds(
            lambda key, v: Invalid("list item that is not a mapping", f"{key}[0]",
                                   mapping=replaced(s.valid, key, [v])),
            st.sampled_from(s.lists), st.one_of(st.integers(), st.text(max_size=10),
                                                st.lists(st.integers(), max_size=2))),
        "rule across keys": st.sampled_from(s.cross_field).map(
            lambda rule: Invalid("rule across keys", rule(s.valid)[1],
                                 mapping=rule(s.valid)[0])),
        # ---- files
        "YAML syntax error": _file(s, "YAML syntax error", lambda draw, text: _insert_line(
            draw, text, draw(st.sampled_from([
                b"numerics: {dx: 0.1", b"- [unclosed", b'title: "no end', b"\tbad: tab",
                b"a: b: c", b"@reserved: 1", b"key: [1, 2", b"}"])))),
        "bytes that are not UTF-8": _file(s, "bytes that are not UTF-8", lambda draw, text: (
            lambda at, junk: text[:at] + junk + text[at:])(
                draw(st.integers(0, len(text))),
                draw(st.sampled_from([b"\xff", b"\xfe\xfe", b"\x80", b"\xc0\x80", b"\xed\xa0\x80",
                                      b"\xf8\x88\x80\x80\x80"])))),
        "control characters": _file(s, "control characters", lambda draw, text: (
            lambda at, c: text[:at] + c + text[at:])(
                draw(st.integers(0, len(text))),
                bytes([draw(st.sampled_from([0, 1, 7, 8, 11, 12, 14, 27, 31, 127]))]))),
        "document that is not a mapping": _file(
            s, "document that is not a mapping", lambda draw, text: draw(st.sampled_from([
                b"", b"# only a comment\n", b"- case: still_water\n", b"42\n", b"null\n",
                b"just text\n", b"---\n...\n"]))),
        "impossible date": _file(s, "impossible date", lambda draw, text: _insert_line(
            draw, text, b"when: " + draw(st.sampled_from([b"2021-02-30", b"2019-13-01",
                                                          b"2020-00-10"])))),
        "integer literal too long to read": _file(
            s, "integer literal too long to read",
            lambda draw, text: text + b"\nbig: " + b"9" * draw(st.integers(4400, 20000))),
        # ---- command-line overrides
        "override without '='": _override(s, "override without '='", lambda draw: (
            lambda k: (k, k))(draw(st.sampled_from([leaf.key for leaf in s.leaves
                                                    if "[" not in leaf.key])))),
        "override without a key": _override(s, "override without a key", lambda draw: (
            lambda v: (v, v))(draw(st.sampled_from(["=1", " =x", "\t=0.1", "=", " = "])))),
        "override value that is not YAML": _override(
            s, "override value that is not YAML", lambda draw: (
                lambda leaf, v: (f"{leaf}={v}", leaf))(
                    draw(st.sampled_from([leaf.key for leaf in s.leaves if "[" not in leaf.key])),
                    draw(st.sampled_from(["[0.1", "{a: 1", '"open', "1\n---\n2", "a: b: c",
                                          "2021-02-30", "\x00", "[" * 1000 + "]" * 1000])))),
        "multi-line override value": _override(
            s, "multi-line override value", lambda draw: (
                lambda leaf, v: (f"{leaf}={v}", leaf))(
                    draw(st.sampled_from([leaf.key for leaf in s.leaves
                                          if _numeric(leaf) and "[" not in leaf.key])),
                    draw(st.sampled_from(["0.1\nrun.t_end=5", "1\n2", "|\n  0.5",
                                          "0.2\n# comment\nx"])))),
        "override through a value": _override(s, "override through a value", lambda draw: (
            lambda leaf, sub: (f"{leaf}.{sub}=1", leaf))(
                draw(st.sampled_from([leaf.key for leaf in s.leaves if "[" not in leaf.key
                                      and get(s.valid, leaf.key) is not None])),
                draw(IDENT))),
        "override of an unknown key": _override(s, "override of an unknown key", lambda draw: (
            lambda sec, k: (f"{_join(sec, k)}=1", _join(sec, k)))(
                draw(st.sampled_from([sec for sec in s.sections if "[" not in sec])),
                draw(IDENT.filter(lambda k: k not in s.valid and k not in (
                    "numerics", "fluid", "run", "geometry", "probes", "case", "title")))))
            .filter(lambda inv: _unknown(s.valid, inv.key)),
    }
    return out


def case_kinds(schema: Schema, names) -> dict[str, st.SearchStrategy[Invalid]]:
    """Kinds of invalid input particular to case files (``names``: the built-in cases)."""
    s = schema
    return {
        "unknown case name": st.builds(
            lambda v: Invalid("unknown case name", "case",
                              mapping=replaced(s.valid, "case", v)),
            st.one_of(st.text(max_size=15).filter(lambda v: v not in names),
                      st.integers(), st.none(), st.lists(st.text(max_size=3), max_size=2),
                      st.dictionaries(IDENT, st.integers(), max_size=2))),
        "missing case name": st.just(Invalid("missing case name", "case", mapping={
            k: v for k, v in s.valid.items() if k != "case"})),
    }


def _unknown(valid: dict, key: str) -> bool:
    try:
        get(valid, key)
    except (KeyError, TypeError, IndexError):
        return True
    return False


def _with_key(mapping: dict, section: str, key) -> dict:
    out = _copy(mapping)
    node = out
    for part in _parts(section):
        node = node[part]
    node[key] = 1
    return out
