"""Tests of the case configuration: validation errors name the key and the allowed range,
built-in cases validate, overrides apply and the YAML dump round-trips."""

from __future__ import annotations

import dataclasses
import math

import pytest
import yaml

from sph.cases import CASES, build_case, builtin, load_case
from sph.cases.base import example_text, load_defaults
from sph.engine.config import CaseConfig, Run
from sph.schema import ConfigError, apply_overrides, build, parse_override

RANGE_MARKERS = ("in (", "in [", "one of")


def _build(case, overrides=()):
    return builtin(case, overrides)


# --------------------------------------------------------------------------- bad input
#
# Each case: (id, case name, overrides, expected key, whether the message must state the
# allowed range). Overrides are ``key=value`` strings (the value parsed as YAML, exactly as
# ``sph run --set``) or ``(key, value)`` pairs for values YAML text cannot express directly.

BAD_OVERRIDES = [
    ("unknown-top-level-key", "still_water", ["solver.scheme=1"], "solver", False),
    ("unknown-numerics-key", "still_water", ["numerics.dxx=0.01"], "numerics.dxx", False),
    ("unknown-case", "still_water", ["case=nope"], "case", True),
    ("geometry-key-of-other-case", "still_water", ["geometry.fill=0.5"], "geometry.fill",
     False),
    ("negative-dx", "still_water", ["numerics.dx=-0.01"], "numerics.dx", True),
    ("zero-dx", "dam_break", ["numerics.dx=0"], "numerics.dx", True),
    ("dx-as-string", "still_water", [("numerics.dx", "0.1")], "numerics.dx", True),
    ("dx-as-list", "still_water", ["numerics.dx=[0.1]"], "numerics.dx", True),
    ("kernel-cubic", "dam_break", ["numerics.kernel=cubic"], "numerics.kernel", True),
    ("filter-shepard", "still_water", ["numerics.density_filter=shepard"],
     "numerics.density_filter", True),
    ("wall-tension-unknown", "still_water", ["numerics.wall_tension=eq6"],
     "numerics.wall_tension", True),
    ("cfl-too-large", "still_water", ["numerics.cfl=0.9"], "numerics.cfl", True),
    ("c-factor-zero", "still_water", ["numerics.c_factor=0"], "numerics.c_factor", True),
    ("alpha-negative", "sloshing_rect", ["numerics.alpha=-1"], "numerics.alpha", True),
    ("h-factor-too-large", "still_water", ["numerics.h_factor=3"], "numerics.h_factor", True),
    ("euler-interval-one", "still_water", ["numerics.euler_interval=1"],
     "numerics.euler_interval", True),
    ("bool-for-float", "still_water", ["numerics.alpha=true"], "numerics.alpha", True),
    ("bool-for-int", "still_water", ["numerics.threads=false"], "numerics.threads", True),
    ("float-for-int", "still_water", ["numerics.mls_interval=2.5"], "numerics.mls_interval",
     True),
    ("nan-float", "still_water", ["numerics.delta=.nan"], "numerics.delta", True),
    ("inf-float", "still_water", ["run.t_end=.inf"], "run.t_end", True),
    ("minus-inf-float", "still_water", [("fluid.gravity", -math.inf)], "fluid.gravity", True),
    ("section-not-mapping", "still_water", ["numerics=5"], "numerics", False),
    ("title-not-string", "still_water", ["title=5"], "title", False),
    ("output-interval-beyond-t-end", "still_water", ["run.output_interval=5"],
     "run.output_interval", True),
    ("t-end-zero", "still_water", ["run.t_end=0"], "run.t_end", True),
    ("t-end-null", "dam_break", ["run.t_end=null"], "run.t_end", True),
    ("density-min-one", "still_water", ["run.density_min=1.0"], "run.density_min", True),
    ("density-max-one", "still_water", ["run.density_max=1"], "run.density_max", True),
    ("fill-one", "sloshing_rect", ["geometry.fill=1.0"], "geometry.fill", True),
    ("fill-above-one", "sloshing_u", ["geometry.fill=1.5"], "geometry.fill", True),
    ("init-unknown", "sloshing_rect", ["geometry.init=sine"], "geometry.init", True),
    ("amplitude-too-large", "sloshing_rect", ["geometry.amplitude=0.2"], "geometry.amplitude",
     True),
    ("amplitude-too-large-u", "sloshing_u", ["geometry.amplitude=1.5"], "geometry.amplitude",
     True),
    ("column-width-fills-tank", "dam_break", ["geometry.column_width=4.0"],
     "geometry.column_width", True),
    ("column-taller-than-tank", "dam_break", ["geometry.column_height=3.5"],
     "geometry.column_height", True),
    ("depth-above-tank-height", "still_water", ["geometry.depth=2.0"], "geometry.depth", True),
    ("dx-too-coarse-for-depth", "still_water", ["numerics.dx=0.3"], "geometry.depth", False),
    ("dx-too-coarse-for-column", "dam_break", ["numerics.dx=0.3"], "geometry.column_width",
     False),
    ("dx-too-coarse-for-fill", "sloshing_u", ["geometry.fill=0.05"], "geometry.fill", False),
    ("bilge-radius-beyond-half-width", "sloshing_u", ["geometry.bilge_radius=9"],
     "geometry.bilge_radius", True),
    ("surface-probe-outside", "still_water", ["probes.surface=[{name: c, x: 2.5}]"],
     "probes.surface[0].x", True),
    ("pressure-probe-x-outside", "dam_break", ["probes.pressure=[{name: p, x: -0.1, z: 0.1}]"],
     "probes.pressure[0].x", True),
    ("pressure-probe-z-outside", "still_water",
     ["probes.pressure=[{name: a, x: 1.0, z: 0.0}, {name: b, x: 0.0, z: 2.0}]"],
     "probes.pressure[1].z", True),
    ("duplicate-probe-names", "still_water",
     ["probes.surface=[{name: a, x: 0.5}]", "probes.pressure=[{name: a, x: 1.0, z: 0.0}]"],
     "probes", False),
    ("probe-item-not-mapping", "sloshing_rect", ["probes.surface=[0.5]"], "probes.surface[0]",
     False),
    ("probe-list-not-list", "sloshing_rect", ["probes.surface=near_left_wall"],
     "probes.surface", False),
    ("probe-name-missing", "sloshing_rect", ["probes.surface=[{x: 0.5}]"],
     "probes.surface[0].name", False),
    ("probe-unknown-key", "sloshing_rect", ["probes.surface=[{name: a, x: 0.5, z: 1}]"],
     "probes.surface[0].z", False),
    ("override-without-equals", "still_water", ["numerics.dx"], "numerics.dx", False),
    ("override-into-non-section", "still_water", ["run.t_end.x=1"], "run.t_end", False),
    ("override-unparsable-value", "still_water", ["numerics.dx=[0.1"], "numerics.dx", False),
    ("pressure-floor-positive", "still_water", ["numerics.pressure_floor=1000.0"],
     "numerics.pressure_floor", True),
]


@pytest.mark.parametrize("case, overrides, key, with_range",
                         [pytest.param(*c[1:], id=c[0]) for c in BAD_OVERRIDES])
def test_bad_input_is_rejected(case, overrides, key, with_range):
    with pytest.raises(ConfigError) as info:
        _build(case, overrides)
    exc = info.value
    assert isinstance(exc, ValueError)
    assert exc.key == key
    msg = str(exc)
    assert msg.startswith(key)
    assert key in msg
    if with_range:
        assert any(m in msg for m in RANGE_MARKERS), msg


def test_an_exponent_without_its_sign_is_explained():
    """YAML 1.1 reads -1.0e5 as text; the error says how to write the number."""
    with pytest.raises(ConfigError) as info:
        _build("still_water", ["numerics.pressure_floor=-1.0e5"])
    assert info.value.key == "numerics.pressure_floor"
    assert "got '-1.0e5'" in str(info.value) and "1.0e+5" in str(info.value)
    assert _build("still_water", ["numerics.pressure_floor=-1.0e+5"]).numerics.pressure_floor \
        == -1.0e5


def test_bad_input_cases_are_distinct():
    ids = [c[0] for c in BAD_OVERRIDES]
    assert len(ids) == len(set(ids))
    assert len(ids) >= 20


def test_missing_required_key_names_it_with_range():
    with pytest.raises(ConfigError) as info:
        build(Run, {"output_interval": 0.01}, "run")
    assert info.value.key == "run.t_end"
    assert "missing" in str(info.value) and "in (0, 1e+06] s" in str(info.value)


# --------------------------------------------------------------------------- bad files
#
# File-level errors have no key inside the file (exc.key is empty); the message names the
# file instead, and reading never leaks an OSError or a yaml exception.

BAD_FILES = [
    ("yaml-syntax-error", "case: still_water\nnumerics: {dx: 0.1\nrun: [\n", "", None),
    ("top-level-list", "- case: still_water\n- numerics: {dx: 0.1}\n", "", None),
    ("top-level-scalar", "still_water\n", "", None),
    ("empty-file", "", "", None),
    ("nan-in-yaml", "case: still_water\nnumerics:\n  dx: .nan\n", "numerics.dx", "in ("),
    ("inf-in-yaml", "case: dam_break\nrun:\n  output_interval: .inf\n", "run.output_interval",
     "in ("),
    ("case-key-missing", "numerics:\n  dx: 0.1\n", "case", "one of"),
    ("unknown-top-level-in-file", "case: still_water\nsolver: {}\n", "solver", None),
    ("probes-as-list", "case: still_water\nprobes: [1, 2]\n", "probes", None),
]


@pytest.mark.parametrize("text, key, marker", [pytest.param(*c[1:], id=c[0]) for c in BAD_FILES])
def test_bad_case_file_is_rejected(tmp_path, text, key, marker):
    path = tmp_path / "case.yaml"
    path.write_text(text)
    with pytest.raises(ConfigError) as info:
        load_case(path)
    exc = info.value
    assert exc.key == key
    if key:
        assert str(exc).startswith(key)
    else:
        assert str(path) in str(exc)
    if marker:
        assert marker in str(exc)


def test_missing_case_file(tmp_path):
    path = tmp_path / "nowhere" / "case.yaml"
    with pytest.raises(ConfigError) as info:
        load_case(path)
    assert info.value.key == ""
    assert str(path) in str(info.value)


def test_case_file_is_a_directory(tmp_path):
    with pytest.raises(ConfigError) as info:
        load_case(tmp_path)
    assert info.value.key == "" and str(tmp_path) in str(info.value)


def test_build_case_needs_mapping():
    with pytest.raises(ConfigError):
        build_case(["case", "still_water"])


# --------------------------------------------------------------------------- overrides


def test_parse_override():
    assert parse_override("numerics.dx=0.01") == ("numerics.dx", 0.01)
    assert parse_override(" run.t_end = 2 ") == ("run.t_end", 2)
    assert parse_override("title=a=b") == ("title", "a=b")
    assert parse_override("probes.surface=[{name: a, x: 1}]") == (
        "probes.surface", [{"name": "a", "x": 1}])
    with pytest.raises(ConfigError) as info:
        parse_override("=1")
    assert "key" in str(info.value)


def test_apply_overrides_copies_touched_levels():
    base = load_defaults("still_water")
    snapshot = yaml.safe_dump(base)
    out = apply_overrides(base, ["numerics.dx=0.05", "run.t_end=0.5", "new.section.key=1"])
    assert yaml.safe_dump(base) == snapshot  # input untouched
    assert out["numerics"]["dx"] == 0.05 and out["run"]["t_end"] == 0.5
    assert out["numerics"]["kernel"] == base["numerics"]["kernel"]
    assert out["new"] == {"section": {"key": 1}}


def test_overrides_change_values():
    cfg = _build("still_water", [
        "numerics.dx=0.05", "numerics.kernel=wendland", "numerics.density_filter=delta",
        "run.t_end=1", "fluid.rho0=998", "geometry.depth=0.8",
        "probes.surface=[{name: s1, x: 0.25}, {name: s2, x: 1.75}]",
        ("numerics.alpha", 0.05),
    ])
    assert cfg.numerics.dx == 0.05
    assert cfg.numerics.kernel == "wendland"
    assert cfg.numerics.h == pytest.approx(1.41 * 0.05)
    assert cfg.numerics.density_filter == "delta"
    assert cfg.numerics.alpha == 0.05
    assert cfg.run.t_end == 1.0 and isinstance(cfg.run.t_end, float)  # int promoted
    assert cfg.fluid.rho0 == 998.0
    assert cfg.geometry.depth == 0.8
    assert [p.name for p in cfg.probes.surface] == ["s1", "s2"]
    assert cfg.probes.surface[1].x == 1.75
    # untouched values keep the case defaults
    assert cfg.geometry.tank_length == 2.0
    assert [p.name for p in cfg.probes.pressure] == ["bottom_centre", "side_mid"]


def test_explicit_h_factor_and_default():
    assert _build("dam_break").numerics.h == pytest.approx(1.23 * 0.02)
    assert _build("dam_break", ["numerics.h_factor=1.5"]).numerics.h == pytest.approx(0.03)
    assert _build("dam_break", ["numerics.h_factor=null"]).numerics.h_factor is None


def test_load_case_with_overrides(tmp_path):
    path = tmp_path / "dam.yaml"
    path.write_text("case: dam_break\nnumerics:\n  dx: 0.05\n")
    cfg = load_case(path, ["run.t_end=0.2", "geometry.column_width=0.5"])
    assert cfg.case == "dam_break"
    assert cfg.numerics.dx == 0.05
    assert cfg.run.t_end == 0.2
    assert cfg.geometry.column_width == 0.5
    assert cfg.geometry.column_height == 2.0  # from the built-in defaults


# --------------------------------------------------------------------------- built-in cases


def test_builtin_case_names():
    assert set(CASES) == {"still_water", "dam_break", "sloshing_rect", "sloshing_u", "wave_tank",
                          "floating_box", "ship_decay", "damaged_ship", "current_tank",
                          "cylinder_in_current"}


@pytest.mark.parametrize("name", sorted(CASES))
def test_builtin_defaults_validate(name, tmp_path):
    cfg = _build(name)
    assert isinstance(cfg, CaseConfig)
    assert cfg.case == name
    assert cfg.title and isinstance(cfg.title, str)
    # the printed example is the same file and loads from disk
    path = tmp_path / f"{name}.yaml"
    path.write_text(example_text(name))
    assert load_case(path) == cfg
    # a file naming only the case gets the same defaults
    path.write_text(f"case: {name}\n")
    assert load_case(path) == cfg


@pytest.mark.parametrize("name", sorted(CASES))
def test_config_is_frozen(name):
    cfg = _build(name)
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.numerics.dx = 1.0  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.run = None  # type: ignore[misc]


@pytest.mark.parametrize("overrides", [
    [],
    ["numerics.kernel=wendland", "numerics.h_factor=1.3", "numerics.density_filter=none"],
    ["probes.surface=[]", "probes.pressure=[]"],
    [("title", "A title: with a colon # and a hash"), "run.vtk_interval=0.1"],
], ids=["defaults", "numerics", "no-probes", "awkward-title"])
@pytest.mark.parametrize("name", sorted(CASES))
def test_yaml_round_trip(name, overrides):
    cfg = _build(name, overrides)
    text = cfg.to_yaml()
    again = build_case(yaml.safe_load(text))
    assert again == cfg
    assert again.to_yaml() == text
    # the dump is plain YAML: only mappings, lists and scalars
    assert isinstance(yaml.safe_load(text), dict)
