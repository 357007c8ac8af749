"""Property-based tests of the case-file validation: random invalid configurations of every
built-in case are refused with a :class:`~sph.schema.ConfigError` that names the key (or,
for a file that is not readable YAML at all, the file), never with another exception.

The kinds of invalid input are listed in ``config_fuzz.kinds`` and ``config_fuzz.case_kinds``
(38 kinds: unknown and non-string keys, wrong types, values out of range, on open bounds,
NaN, infinities, integers too large for a float or for Python to print, bad choices,
sections and lists of the wrong shape, rules across keys, YAML syntax errors, bytes that are
not UTF-8, control characters, documents that are not mappings, impossible dates, integer
literals too long to read, and six kinds of bad ``--set`` overrides including multi-line
values). Each kind is drawn for random cases, keys and values.
"""

from __future__ import annotations

import functools

import pytest
import yaml
from config_fuzz import Invalid, Schema, case_kinds, case_schema, kinds
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from sph.cases import CASES
from sph.cli import main

CASE_NAMES = sorted(CASES)


@functools.cache
def _schema(name: str) -> Schema:
    return case_schema(name)


@functools.cache
def _strategies(name: str) -> dict:
    schema = _schema(name)
    return {**kinds(schema), **case_kinds(schema, tuple(CASES))}


KIND_NAMES = list(_strategies(CASE_NAMES[0]))

FUZZ = settings(max_examples=25, deadline=None, derandomize=False,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])


def assert_refused(schema: Schema, inv: Invalid, directory) -> None:
    """``inv`` is refused with ``schema.error`` naming ``inv.key`` (the file if ``""``) in
    a one-line message."""
    path = directory / "case.yaml"
    if inv.mapping is not None:
        def call():
            return schema.load_mapping(inv.mapping)
    else:
        path.write_bytes(inv.text)

        def call():
            return schema.load_file(path, inv.overrides)
    with pytest.raises(schema.error) as info:
        call()
    exc = info.value
    message = str(exc)
    key = schema.key_of(exc)
    assert key == inv.key, f"{inv.kind}: named {key!r}, expected {inv.key!r}: {message}"
    if key:
        assert message.startswith(f"{key}: "), message
    else:
        assert str(path) in message, message
    assert "\n" not in message and len(message) < 1000, message


def test_every_kind_is_counted():
    assert len(KIND_NAMES) == 38
    for name in CASE_NAMES:  # every kind applies to every built-in case
        assert list(_strategies(name)) == KIND_NAMES


@pytest.mark.parametrize("kind", KIND_NAMES)
@FUZZ
@given(data=st.data())
def test_invalid_case_config_is_refused_naming_the_key(kind, data, tmp_path_factory):
    name = data.draw(st.sampled_from(CASE_NAMES), label="case")
    inv = data.draw(_strategies(name)[kind], label="input")
    assert_refused(_schema(name), inv, tmp_path_factory.mktemp("fuzz"))


def _as_file(inv: Invalid) -> tuple[bytes, list]:
    if inv.text is not None:
        return inv.text, inv.overrides
    try:
        return yaml.safe_dump(inv.mapping, sort_keys=False).encode(), []
    except (ValueError, yaml.YAMLError):  # e.g. integers too long to print
        assume(False)
        raise


@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much,
                                 HealthCheck.function_scoped_fixture])  # capsys: read each time
@given(data=st.data())
def test_cli_refuses_invalid_case_in_one_line(data, tmp_path_factory, capsys):
    """Through ``sph run``: exit status 2 and one line ``error: ...``, no traceback, no
    output, whatever the kind of mistake."""
    name = data.draw(st.sampled_from(CASE_NAMES), label="case")
    kind = data.draw(st.sampled_from(KIND_NAMES), label="kind")
    inv = data.draw(_strategies(name)[kind], label="input")
    text, overrides = _as_file(inv)
    directory = tmp_path_factory.mktemp("cli")
    path = directory / "case.yaml"
    path.write_bytes(text)
    out = directory / "out.nc"
    argv = ["run", str(path), "-o", str(out), "--check", "--no-progress"]
    for item in overrides:
        argv += ["--set", item]
    capsys.readouterr()
    assert main(argv) == 2
    captured = capsys.readouterr()
    lines = [ln for ln in captured.err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error:"), captured.err
    assert "Traceback" not in captured.err
    assert not out.exists()
