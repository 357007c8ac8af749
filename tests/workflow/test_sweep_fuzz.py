"""Property-based tests of the sweep schema (``sph.study.sweeps.load_sweep``).

Each kind of invalid sweep is a small mutation of the default configuration
(``config/config.yaml`` with an inline case table); hypothesis draws the mutation's values.
Every invalid sweep must be refused with a :class:`ConfigError` whose key names the culprit
and whose message starts with that key: never a traceback, never accepted.
"""

from __future__ import annotations

import copy
from pathlib import Path

import pytest
import yaml

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from sph.schema import ConfigError  # noqa: E402
from sph.study.sweeps import load_sweep  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
ROW = {"case": "c1", "opening": 0.4, "side": "back", "fill": 0.0}


def _base() -> dict:
    cfg = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    cfg["cases"] = [dict(ROW), dict(ROW, case="c2", side="head")]
    return cfg


BASE = _base()

# strategies of bad values
outside_unit = st.one_of(st.floats(max_value=-1e-6, allow_nan=False, allow_infinity=False),
                         st.floats(min_value=1.0, max_value=1e9, allow_nan=False))
not_a_number = st.one_of(st.text(alphabet="abcxyz!?", min_size=1, max_size=6),
                         st.lists(st.integers(), min_size=1, max_size=2))
bad_name = st.text(alphabet=" /\\*?:.", min_size=1, max_size=5)
unknown_word = st.text(alphabet="qwzjk", min_size=3, max_size=8)


def _row(**kw):
    cfg = copy.deepcopy(BASE)
    cfg["cases"][1].update(kw)
    return cfg


def _set(key, value):
    cfg = copy.deepcopy(BASE)
    cfg[key] = value
    return cfg


def _drop_col(col):
    cfg = copy.deepcopy(BASE)
    del cfg["cases"][1][col]
    return cfg


#: kind -> strategy of (config, key the refusal must name)
KINDS = {
    "unknown top-level key": unknown_word.map(lambda w: (_set(w, 1), w)),
    "fill outside [0, 1)": outside_unit.map(lambda v: (_row(fill=v), "cases[1].fill")),
    "fill not a number": not_a_number.map(lambda v: (_row(fill=v), "cases[1].fill")),
    "opening outside [0, 1)": outside_unit.map(lambda v: (_row(opening=v),
                                                          "cases[1].opening")),
    "opening not a number": not_a_number.map(lambda v: (_row(opening=v), "cases[1].opening")),
    "amplitude outside [0, 2]": st.one_of(
        st.floats(max_value=-1e-6, allow_nan=False, allow_infinity=False),
        st.floats(min_value=2.001, max_value=1e9, allow_nan=False),
    ).map(lambda v: (_row(amplitude=v), "cases[1].amplitude")),
    "cargo density outside [1, 1e5]": st.one_of(
        st.floats(max_value=0.999, allow_nan=False, allow_infinity=False),
        st.floats(min_value=1.0001e5, max_value=1e12, allow_nan=False),
    ).map(lambda v: (_row(cargo_density=v), "cases[1].cargo_density")),
    "cargo density not a number": not_a_number.map(
        lambda v: (_row(cargo_density=v), "cases[1].cargo_density")),
    "unknown side": unknown_word.map(lambda v: (_row(side=v), "cases[1].side")),
    "duplicate case id": st.just((_row(case="c1"), "cases[1].case")),
    "bad case id": bad_name.map(lambda v: (_row(case=v), "cases[1].case")),
    "unknown case column": unknown_word.map(lambda w: (_row(**{w: 1}), f"cases[1].{w}")),
    "missing case column": st.sampled_from(["case", "opening", "side", "fill"]).map(
        lambda c: (_drop_col(c), f"cases[1].{c}")),
    # an empty case list is a sweep of validation targets only, which must list some
    "empty case list": st.just((dict(_set("cases", []), validation=[]), "cases")),
    "case row not a mapping": st.integers().map(
        lambda v: (_set("cases", [dict(ROW), v]), "cases[1]")),
    "unknown preset": unknown_word.map(lambda v: (_set("preset", v), "preset")),
    "missing required key": st.sampled_from(["sweep", "cases", "preset", "presets"]).map(
        lambda k: (_set(k, None), k)),
    "bad sweep name": bad_name.map(lambda v: (_set("sweep", v), "sweep")),
    "reserved sweep name": st.just((_set("sweep", "validation"), "sweep")),
    "unknown reference key": unknown_word.map(
        lambda w: (_set("reference", {w: 1}), f"reference.{w}")),
    "reference not a mapping": st.integers(min_value=1).map(
        lambda v: (_set("reference", v), "reference")),
    "t2_periods negative": st.floats(max_value=-1e-6, allow_nan=False,
                                     allow_infinity=False).map(
        lambda v: (_set("t2_periods", v), "t2_periods")),
    "unknown validation target": unknown_word.map(
        lambda w: (_set("validation", ["wave_tank", w]), "validation[1]")),
    "validation not a list": st.just((_set("validation", "wave_tank"), "validation")),
    "set with a key that is no case key": st.text(alphabet="ab .", min_size=1,
                                                   max_size=5).filter(lambda k: " " in k).map(
        lambda k: (_set("set", {k: 1}), f"set.{k}")),
    "set not a mapping": st.integers().map(lambda v: (_set("set", v), "set")),
    "missing presets file": unknown_word.map(
        lambda w: (_set("presets", f"config/{w}.yaml"), "presets")),
}


def test_the_default_sweep_is_accepted():
    out = load_sweep(BASE, ROOT)
    assert [c["case"] for c in out["cases"]] == ["c1", "c2"]


def test_every_kind_is_counted():
    # the number of kinds of invalid sweep covered (reported in docs/workflow.md)
    assert len(KINDS) == 27


@pytest.mark.parametrize("kind", list(KINDS))
@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_invalid_sweep_is_refused_naming_the_key(kind, data):
    cfg, key = data.draw(KINDS[kind])
    with pytest.raises(ConfigError) as err:
        load_sweep(cfg, ROOT)
    assert err.value.key == key, (kind, err.value.key, str(err.value))
    assert str(err.value).startswith(f"{key}: "), str(err.value)
