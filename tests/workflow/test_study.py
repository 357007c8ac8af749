"""Tests of the sweep configuration, case files and sweep datasets (sph.study.sweeps)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from sph.io.output import build_dataset, write_netcdf_atomic
from sph.schema import ConfigError
from sph.study import sweeps as study

ROOT = Path(__file__).resolve().parents[2]


def _config(**changes):
    cfg = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    cfg.update(changes)
    return cfg


def _load(**changes):
    return study.load_sweep(_config(**changes), base=ROOT)


def test_default_sweep_is_table_one():
    s = _load()
    cases = {c["case"]: c for c in s["cases"]}
    assert list(cases) == [f"case{k}" for k in range(1, 9)]
    assert cases["case1"]["opening"] == 0.0
    assert cases["case2"]["opening"] == pytest.approx(5 / 21)
    assert cases["case4"]["opening"] == pytest.approx(5 / 7)
    assert cases["case5"]["side"] == "head"
    assert [cases[f"case{k}"]["fill"] for k in (6, 7, 8)] == [0.25, 0.5, 0.75]
    assert all(c["amplitude"] == pytest.approx(10 / 21) for c in cases.values())
    assert study.groups(s["cases"], s["reference"]) == {
        "opening": ["case1", "case2", "case3", "case4"],
        "side": ["case3", "case5"],
        "fill": ["case3", "case6", "case7", "case8"],
    }


@pytest.mark.parametrize("text, value", [("10/21", 10 / 21), ("5/7", 5 / 7), (" 0.25 ", 0.25),
                                         (0, 0.0), ("1e-1", 0.1)])
def test_parse_number(text, value):
    assert study.parse_number(text, "k") == pytest.approx(value)


@pytest.mark.parametrize("text", ["ten", "1/0", True, None, "nan", [1]])
def test_parse_number_refuses(text):
    with pytest.raises(ConfigError, match="^k: "):
        study.parse_number(text, "k")


ROW = dict(case="a", opening=0.5, side="back", fill=0.0)


@pytest.mark.parametrize("rows, key, message", [
    ([ROW, dict(ROW)], "cases[1].case", "duplicate case id 'a'"),
    ([dict(ROW, side="port")], "cases[0].side", "unknown side 'port'"),
    ([dict(ROW, fill=1.5)], "cases[0].fill", r"must be in \[0, 1\); got 1.5"),
    ([dict(ROW, fill=1.0)], "cases[0].fill", r"must be in \[0, 1\)"),
    ([dict(ROW, fill=-0.1)], "cases[0].fill", r"must be in \[0, 1\)"),
    ([dict(ROW, opening=1.2)], "cases[0].opening", r"must be in \[0, 1\)"),
    ([dict(ROW, colour="red")], "cases[0].colour", "unknown key"),
    ([dict(ROW, case="a b")], "cases[0].case", "case id must be"),
    ([{k: v for k, v in ROW.items() if k != "fill"}], "cases[0].fill", "required column"),
    ([], "cases", "non-empty list"),
])
def test_bad_cases_name_the_key(rows, key, message):
    with pytest.raises(ConfigError, match=message) as err:
        study.check_cases(rows)
    assert err.value.key == key


@pytest.mark.parametrize("changes, key", [
    (dict(fil=0.5), "fil"),
    (dict(preset="fine"), "preset"),
    (dict(sweep="validation"), "sweep"),
    (dict(sweep="my sweep"), "sweep"),
    (dict(validation=["wave_tank", "towing"]), "validation[1]"),
    (dict(reference={"opening": 0.5, "colour": 1}), "reference.colour"),
    (dict(t2_periods=-1), "t2_periods"),
    (dict(cases="config/cases/missing.tsv"), "cases"),
])
def test_bad_sweep_names_the_key(changes, key):
    with pytest.raises(ConfigError) as err:
        _load(**changes)
    assert err.value.key == key
    assert str(err.value).startswith(f"{key}: ")


def test_case_table_with_unknown_column(tmp_path):
    table = tmp_path / "cases.tsv"
    table.write_text("case\topening\tside\tfill\tspeed\nx\t0\tback\t0\t3\n")
    with pytest.raises(ConfigError, match="unknown key") as err:
        _load(cases=str(table))
    assert err.value.key == "cases[0].speed"


def test_presets_are_checked():
    presets = yaml.safe_load((ROOT / "config" / "presets.yaml").read_text())
    assert set(presets) >= {"coarse", "medium", "paper"}
    study.check_presets(presets)
    bad = {"p": dict(presets["coarse"], ship={"dx": 0.8})}
    with pytest.raises(ConfigError) as err:
        study.check_presets(bad)
    assert err.value.key == "presets.p.ship.periods"
    bad = {"p": dict(presets["coarse"], ship={"dx": 0.8, "periods": 10, "dy": 1})}
    with pytest.raises(ConfigError, match="unknown key"):
        study.check_presets(bad)


def test_presets_halve_dx_in_units_of_the_wave_amplitude():
    s = {p: _load(preset=p)["preset_settings"] for p in ("coarse", "medium", "paper")}
    amp = s["coarse"]["wave_tank"]["amplitude"]
    assert [s[p]["ship"]["dx"] / amp for p in ("coarse", "medium", "paper")] == \
        pytest.approx([0.4, 0.2, 0.1])
    assert s["paper"]["wave_tank"]["dx_over_amplitude"] == [0.4, 0.2, 0.1]


def test_ship_overrides_and_case_document():
    s = _load()
    case4 = next(c for c in s["cases"] if c["case"] == "case4")
    over = study.ship_overrides(case4, s)
    assert over["numerics.dx"] == 0.8
    assert over["geometry.damage.opening"] == pytest.approx(5 / 7)
    assert over["geometry.wavemaker.amplitude"] == pytest.approx(2.0)
    assert over["run.t_end"] == pytest.approx(12 * 2 * math.pi)
    assert over["geometry.cargo_density"] == 1000.0  # water: the case table's default
    doc = study.case_document("damaged_ship", over)
    assert doc["geometry"]["damage"] == {"opening": pytest.approx(5 / 7), "side": "back"}
    cfg = study.check_case_document(doc, "case4")
    assert cfg.numerics.dx == 0.8
    assert cfg.geometry.hull.breadth == 16.0  # from the built-in case's defaults


def test_cargo_density_column_of_table_one():
    """Table I carries one cargo, an oil of 850 kg/m3, at every fill (the empty ships keep
    the case's default); every run's case file has its row's density and passes the
    engine's checks, every damaged ship keeps a positive GM once flooded, corrected for its
    cargo's free surface (with water the 25 and 50 % ships have -0.11 m), and the checked
    rows pass the checked-table schema."""
    import jsonschema

    from sph.cases.ship import damaged_gm, masses

    s = _load()
    dens = {c["case"]: c["cargo_density"] for c in s["cases"]}
    assert dens == {**{f"case{k}": 1000.0 for k in range(1, 6)},
                    **{f"case{k}": 850.0 for k in range(6, 9)}}
    schema = yaml.safe_load((ROOT / "config" / "schema" / "cases_checked.schema.yaml")
                            .read_text())
    for c in s["cases"]:
        jsonschema.validate(c, schema)
        over = study.ship_overrides(c, s)
        assert over["geometry.cargo_density"] == dens[c["case"]]
        cfg = study.check_case_document(study.case_document("damaged_ship", over), c["case"])
        assert cfg.geometry.cargo_density == dens[c["case"]]
        if cfg.geometry.damage.opening > 0.0:
            assert damaged_gm(cfg, masses(cfg))[1] > 0.3, c["case"]
    raw = yaml.safe_load((ROOT / "config" / "schema" / "cases.schema.yaml").read_text())
    for row in study.read_case_table(ROOT / "config" / "cases" / "table1.tsv"):
        jsonschema.validate(row, raw)


def test_cargo_density_column_falls_back_on_set_and_is_written_out(tmp_path):
    rows = [dict(case="a", opening="10/21", side="back", fill=0.5),
            dict(case="b", opening="10/21", side="back", fill=0.5, cargo_density="900")]
    s = _load(cases=rows, set={"geometry.cargo_density": 950.0, "numerics.shifting": 0.5})
    over = {c["case"]: study.ship_overrides(c, s) for c in s["cases"]}
    assert over["a"]["geometry.cargo_density"] == 950.0  # `set` for a row without one
    assert over["b"]["geometry.cargo_density"] == 900.0  # the column wins over `set`
    assert over["a"]["numerics.shifting"] == 0.5  # `set` still applies to other keys
    assert _load(cases=rows)["cases"][0]["cargo_density"] == 1000.0  # the case's water
    study.write_case_table(s["cases"], tmp_path / "cases.tsv")
    back = study.check_cases(study.read_case_table(tmp_path / "cases.tsv"))
    assert [c["cargo_density"] for c in back] == [950.0, 900.0]


@pytest.mark.parametrize("value, message", [
    (-5, r"must be in \[1, 100000\]; got -5"),
    (2.0e5, r"must be in \[1, 100000\]"),
    ("oil", "expected a number"),
])
def test_bad_cargo_density_is_refused_naming_the_row(value, message):
    with pytest.raises(ConfigError, match=message) as err:
        _load(cases=[dict(ROW), dict(ROW, case="b", cargo_density=value)])
    assert err.value.key == "cases[1].cargo_density"


def test_cargo_the_ship_cannot_carry_is_refused_before_any_job():
    """Water at 75 % fill outweighs the displacement at the paper's draught: the run's case
    file is refused naming the run, the key and the densest cargo that fits."""
    s = _load(cases=[dict(case="w75", opening="10/21", side="back", fill=0.75,
                          cargo_density=1000)])
    over = study.ship_overrides(s["cases"][0], s)
    with pytest.raises(ConfigError, match=r"dry part .* -0.536 % of the displacement.*"
                       r"allowed \(0, 917\] kg/m3") as err:
        study.check_case_document(study.case_document("damaged_ship", over), "case 'w75'")
    assert err.value.key == "case 'w75': geometry.cargo_density"


def test_still_water_case_has_no_wave():
    s = _load(cases=[dict(case="still", opening="10/21", side="back", fill=0, amplitude=0)])
    over = study.ship_overrides(s["cases"][0], s)
    assert over["geometry.wavemaker.theta0"] == 0.0
    assert over["geometry.wavemaker.amplitude"] is None
    study.check_case_document(study.case_document("damaged_ship", over), "still")


def test_engine_checks_name_the_run_and_the_key():
    s = _load(cases=[dict(case="high", opening=0.99, side="back", fill=0)])
    over = study.ship_overrides(s["cases"][0], s)
    with pytest.raises(ConfigError, match="above the waterline") as err:
        study.check_case_document(study.case_document("damaged_ship", over), "case 'high'")
    assert err.value.key == "case 'high': geometry.damage.opening"


def test_nest_refuses_a_value_and_a_section():
    assert study.nest({"a.b": 1, "a.c": 2, "d": 3}) == {"a": {"b": 1, "c": 2}, "d": 3}
    with pytest.raises(ConfigError):
        study.nest({"a": 1, "a.b": 2})


def test_validation_runs_cover_every_target(tmp_path):
    s = _load()
    runs = study.validation_runs(s, tmp_path)
    # the default sweep runs every target but the cylinder in a current, which has its own
    # sweep (config/sweeps/cylinder_froude.yaml)
    assert list(runs) == [t for t in study.VALIDATION_TARGETS if t != "cylinder"]
    assert [o["numerics.dx"] for _, o in runs["wave_tank"].values()] == \
        pytest.approx([2.0, 1.2, 0.8])
    # the wave tank runs with the ship's numerics and absorbing zone, not the wave_tank
    # case's tuned ones (half the viscosity, twice the absorber's strength)
    from sph.cases import builtin
    ship = builtin("damaged_ship", ["geometry.damage.opening=0"])
    tuned = builtin("wave_tank")
    for case, over in runs["wave_tank"].values():
        cfg = builtin(case, list(over.items()))
        assert cfg.numerics.alpha == ship.numerics.alpha != tuned.numerics.alpha
        assert cfg.numerics.density_filter == ship.numerics.density_filter
        assert cfg.geometry.absorber.strength == ship.geometry.absorber.strength != \
            tuned.geometry.absorber.strength
    assert list(runs["sloshing"]) == ["fill25", "fill50", "fill75"]
    assert runs["decay"]["heave"][1]["geometry.dofs.roll"] is False
    assert runs["floating_box"]["box"][1]["geometry.wavemaker.file"].endswith(
        "CaseFloatingWavesVal_Flap.dat")


def test_schemas_list_the_targets_of_the_table():
    """The JSON schemas of config/schema/ name the validation targets too: they must agree
    with the table (sph.study.validation.TARGETS) and the presets' sections."""
    from sph.study.validation import TARGETS

    schema = yaml.safe_load((ROOT / "config" / "schema" / "config.schema.yaml").read_text())
    assert schema["properties"]["validation"]["items"]["enum"] == list(TARGETS)
    presets = yaml.safe_load((ROOT / "config" / "schema" / "presets.schema.yaml").read_text())
    sections = presets["additionalProperties"]["properties"]
    required = set(presets["additionalProperties"]["required"])
    assert set(TARGETS) - set(study.OPTIONAL_SECTIONS) <= required
    assert not required & set(study.OPTIONAL_SECTIONS)  # needed only by a sweep that lists it
    for target in TARGETS:
        assert set(sections[target]["properties"]) == set(study.PRESET_SECTION_KEYS[target])
        assert {k for k, required in study.PRESET_SECTION_KEYS[target].items() if required} \
            == set(sections[target]["required"])


def test_ship_defaults_come_from_the_case_file():
    """The draught, the default wave (A / d) and the reference case of the sweeps are those
    of sph/cases/damaged_ship.yaml, stated nowhere else."""
    from sph.cases import load_defaults

    g = load_defaults("damaged_ship")["geometry"]
    assert study.DEFAULT_DRAUGHT == g["hull"]["draught"] == 4.2
    assert study.DEFAULT_AMPLITUDE == g["wavemaker"]["amplitude"] / g["hull"]["draught"]
    assert study.DEFAULT_AMPLITUDE == pytest.approx(10 / 21, rel=1e-15)
    ref = _load(reference=None)["reference"]
    assert (ref["opening"], ref["side"], ref["fill"]) == (g["damage"]["opening"],
                                                         g["damage"]["side"], g["fill"])
    row = study.check_cases([dict(case="a", opening="10/21", side="back", fill=0)])[0]
    over = study.ship_overrides(row, _load())
    assert over["geometry.wavemaker.amplitude"] == g["wavemaker"]["amplitude"]


def _run_file(path, case, t_end=1.0, dt_out=0.1, jitter=0.0, status="completed", seed=0,
              geometry=None):
    rng = np.random.default_rng(seed)
    n = int(round(t_end / dt_out)) + 1
    t = np.arange(n) * dt_out + jitter * rng.random(n) * (np.arange(n) > 0)
    roll = np.sin(t)
    ds = build_dataset(
        t, {"roll": roll, "heave": 0.1 * t, "flood_ratio": t / 10},
        probes={"probe_elevation": (["WP1", "W2"], np.vstack([t, 2 * t]))},
        attrs=dict(case="damaged_ship", status=status, wave_period=6.28, damage_time=2.0,
                   dx=0.8, speed_of_sound=171.6, wall_clock_seconds=12.5, steps=100,
                   n_total=1000, lost_particles=0, guarded_particles=seed,
                   particle_steps_per_second=8000.0, opening=case["opening"],
                   cargo_density=850.0 if case["fill"] > 0.0 else 1000.0),
        config_yaml=yaml.safe_dump({"run": {"t_end": t_end, "output_interval": dt_out},
                                    **({"geometry": geometry} if geometry else {})}))
    write_netcdf_atomic(ds, path)
    return path


def test_gather_builds_a_case_dimension(tmp_path):
    cases = study.check_cases([dict(case="a", opening=0, side="back", fill=0),
                               dict(case="b", opening="10/21", side="head", fill=0.5)])
    ship = dict(ship_x=60.0, tank_length=150.0, hull=dict(breadth=16.0),
                absorber=dict(enabled=True, start=90.0, length=60.0, mirrored=False))
    paths = [_run_file(tmp_path / "a.nc", cases[0], jitter=0.004),
             _run_file(tmp_path / "b.nc", cases[1], jitter=0.004, seed=1, geometry=ship)]
    ds = study.gather(paths, cases, {"sweep": "demo", "preset": "coarse"})
    # the hull's back side at 68 m, the zone from 90 m (the runs name no absorber speed:
    # its edge); a run without a hull: none
    assert ds["zone_clearance_back"].values.tolist() == [math.inf, 22.0]
    assert ds["zone_clearance_head"].values.tolist() == [math.inf, math.inf]
    assert ds["zone_clearance_back"].attrs["units"] == "m"
    assert ds.sizes["case"] == 2 and ds.sizes["time"] == 11
    np.testing.assert_allclose(ds["time"].values, np.arange(11) * 0.1)
    assert list(ds["case"].values) == ["a", "b"]
    assert ds["opening"].values[1] == pytest.approx(10 / 21)
    assert list(ds["side"].values) == ["back", "head"]
    for name in ("opening", "side", "fill", "amplitude", "cargo_density"):
        assert name in ds.coords and ds[name].dims == ("case",)
    assert ds["cargo_density"].values.tolist() == [1000.0, 850.0]  # from each run's attrs
    assert ds["roll"].dims == ("case", "time")
    assert ds["roll"].attrs["units"] == "degree"
    assert ds["opening"].attrs["units"] == "1"
    # heave is linear: interpolation onto the nominal times is exact
    np.testing.assert_allclose(ds["heave"].values[0], 0.1 * np.arange(11) * 0.1, atol=1e-12)
    assert ds.attrs["Conventions"] == "CF-1.10"
    assert ds.attrs["sweep"] == "demo" and ds.attrs["wave_period"] == 6.28
    assert ds.attrs["speed_of_sound"] == 171.6  # shared: fast_runs measures against it
    assert ds.attrs["source"].startswith("sph-flood")
    assert ds["wall_clock_seconds"].values.tolist() == [12.5, 12.5]
    assert ds["guarded_particles"].values.tolist() == [0, 1]  # each run's count
    assert ds["lost_particles"].attrs["long_name"].startswith("fluid particles")
    out = tmp_path / "sweep.nc"
    write_netcdf_atomic(ds, out)
    import xarray as xr

    with xr.open_dataset(out) as back:
        assert back.sizes["case"] == 2
        assert back["time"].attrs["units"] == "s"
        assert back["side"].values.tolist() == ["back", "head"]


def test_zone_clearance_of_the_paper_ship_and_of_mirrored_and_absent_zones():
    """The sway at which a side of the upright hull lies where an absorbing zone damps at
    2 % of the wave frequency: the paper's tank (ship at 2H = 60 m, B = 16 m, zone from
    3H = 90 m) gives 90 - 68 = 22 m to the zone's edge towards +x, 6.65 m more to where it
    damps that much, and none towards the flap; a mirrored zone also bounds -x."""
    from sph.cases import builtin

    cfg = builtin("damaged_ship").to_dict()
    assert study.zone_clearance(cfg) == (22.0, math.inf)  # no run attributes: the edge
    # the damping sigma = (c / l) d / (l - d + dx) reaches 2 % of omega d = 6.65 m in
    # (c = 9.768 m/s, the phase speed at omega = 1 rad/s and H = 30 m; l = 60 m)
    run = dict(absorber_speed=9.768, omega=1.0, dx=0.8)
    back, head = study.zone_clearance(cfg, run)
    d = back - 22.0
    assert d == pytest.approx(6.652, abs=1e-3) and head == math.inf
    assert 9.768 / 60.0 * d / (60.0 - d + 0.8) == pytest.approx(0.02 * 1.0, rel=1e-12)
    g = cfg["geometry"]
    g["absorber"]["mirrored"], g["absorber"]["start"] = True, 100.0
    # zones [0, 50] and [100, 150]: head side at 52 m, back side at 68 m
    assert study.zone_clearance(cfg) == (32.0, 2.0)
    back, head = study.zone_clearance(cfg, run)
    assert back == pytest.approx(32.0 + d) and head == pytest.approx(2.0 + d)
    g["absorber"]["enabled"] = False
    assert study.zone_clearance(cfg) == (math.inf, math.inf)
    assert study.zone_clearance({"run": {}}) == (math.inf, math.inf)


def test_gather_keeps_a_run_that_stopped_and_refuses_a_short_completed_one(tmp_path):
    """A run that blew up is the result of its case: it is gathered NaN after its last
    sample, with its status, and does not cut the others short; a run that says it
    completed but ends before its t_end is refused."""
    cases = study.check_cases([dict(case="a", opening=0, side="back", fill=0),
                               dict(case="b", opening=0.3, side="back", fill=0)])
    a = _run_file(tmp_path / "a.nc", cases[0])
    b = _run_file(tmp_path / "b.nc", cases[1], t_end=1.0)
    ds = xr.open_dataset(b).load()
    ds.close()
    stopped = ds.isel(time=slice(0, 5))  # blew up after t = 0.4 s
    stopped.attrs["status"] = "failed: simulation stopped at step 40, t = 0.4 s: NaN"
    write_netcdf_atomic(stopped, b)
    ds = study.gather([a, b], cases)
    assert ds.sizes["time"] == 11  # the completed run sets the time axis
    assert ds["case_status"].values.tolist() == ["completed", stopped.attrs["status"]]
    roll_b = ds["roll"].sel(case="b").values
    assert np.isfinite(roll_b[:5]).all() and np.isnan(roll_b[5:]).all()
    np.testing.assert_allclose(roll_b[:5], np.sin(np.arange(5) * 0.1), atol=1e-12)
    assert np.isfinite(ds["roll"].sel(case="a").values).all()
    assert study.one_wave(ds).sizes["time"] == 11  # the stopped run sets no end
    b = _run_file(tmp_path / "b.nc", cases[1], t_end=0.5)
    ds = study.gather([a, b], cases)  # the longer run sets the time axis
    assert ds.sizes["time"] == 11
    assert np.isnan(ds["roll"].sel(case="b").values[6:]).all()
    assert np.isfinite(ds["roll"].sel(case="b").values[:6]).all()
    ds = xr.open_dataset(b).load()
    ds.close()
    write_netcdf_atomic(ds.isel(time=slice(0, 3)), b)  # "completed", yet ends at 0.2 s
    with pytest.raises(ValueError, match="'b' ends at t = 0.2 s.*says it completed"):
        study.gather([a, b], cases)


# ------------------------------------------------------------------------------ wave frequency
def _rao_sweep(**changes):
    cfg = _config()
    cfg.update(yaml.safe_load((ROOT / "config" / "sweeps" / "roll_rao.yaml").read_text()))
    cfg.update(changes)
    return study.load_sweep(cfg, base=ROOT)


def test_omega_column_defaults_to_the_built_in_wave():
    rows = study.check_cases([dict(ROW), dict(ROW, case="b", omega="3/5")])
    assert rows[0]["omega"] == study.DEFAULT_OMEGA == 1.0
    assert rows[1]["omega"] == pytest.approx(0.6)
    over = study.ship_overrides(rows[0], _load())
    assert "geometry.wavemaker.omega" not in over  # a Table I case file names no frequency
    assert not any(k in over for k in study.TANK_KEYS)


@pytest.mark.parametrize("omega, message", [
    (0, r"must be in \(0, 10\] rad/s; got 0"),
    (-0.5, r"must be in \(0, 10\] rad/s"),
    (12, r"must be in \(0, 10\] rad/s; got 12"),
    ("fast", "expected a number"),
])
def test_bad_omega_names_the_column(omega, message):
    with pytest.raises(ConfigError, match=message) as err:
        study.check_cases([dict(ROW), dict(ROW, case="b", omega=omega)])
    assert err.value.key == "cases[1].omega"


@pytest.mark.parametrize("row, changes, key, message", [
    # A = 2 m at 2 rad/s: k A = 0.82, twice Miche's limit
    (dict(omega=2.0), {}, "cases[1].omega", "steeper than the breaking limit"),
    # A = 2.1 m at 0.2 rad/s in 30 m of water: a 528 m long wave, Ursell number 43
    (dict(omega=0.2, amplitude=0.5), {}, "cases[1].omega",
     "Ursell number 2A length.2 / h.3 = 43.4 above 26.3"),
    # A = 0.42 m: a wave height of 1.05 spacings at the coarse dx = 0.8 m
    (dict(amplitude=0.1), {}, "cases[1].amplitude", "spans 1 particle spacings"),
])
def test_waves_the_runs_cannot_carry_are_refused(row, changes, key, message):
    rows = [dict(ROW), dict(ROW, case="b", **row)]
    with pytest.raises(ConfigError, match=message) as err:
        _load(cases=rows, **changes)
    assert err.value.key == key


def test_a_tank_the_sweep_sets_is_kept_and_a_short_zone_warned_about(caplog):
    import logging

    rows = [dict(ROW), dict(ROW, case="b", omega=0.6, amplitude=1.1)]
    with caplog.at_level(logging.WARNING, logger="sph.study.sweeps"):
        s = _load(cases=rows, set={"geometry.tank_length": 150.0})
    # the built-in 60 m zone is 0.41 of the 147 m wave
    assert "shorter than 0.95 wave lengths" in caplog.text and "b (0.41)" in caplog.text
    assert "a (" not in caplog.text
    over = study.ship_overrides(s["cases"][1], s)
    assert over["geometry.tank_length"] == 150.0 and "geometry.absorber.start" not in over


def test_the_tank_follows_the_wave_length():
    """The built-in tank for waves up to the built-in one's length; for a longer wave the
    open water behind the ship and the absorbing zone keep their proportions of the wave
    length (0.49 and 0.98), the ship stays at 2H from the flap."""
    g = study.SHIP_DEFAULTS
    lam0 = study.wave_length(1.0, 30.0)
    assert lam0 == pytest.approx(61.37, abs=0.01)
    assert (g["absorber"]["start"] - g["ship_x"]) / lam0 == pytest.approx(0.489, abs=1e-3)
    assert g["absorber"]["length"] / lam0 == pytest.approx(0.978, abs=1e-3)
    for omega in (1.0, 1.2, 1.4, 3.0):
        assert study.tank_for_wave(omega) == {}
    for omega in (0.95, 0.8, 0.6, 0.4):
        lam = study.wave_length(omega, 30.0)
        tank = study.tank_for_wave(omega)
        start, zone = tank["geometry.absorber.start"], tank["geometry.absorber.length"]
        assert 0.978 * lam <= zone <= 0.978 * lam + 1.0  # rounded up to the metre
        assert 0.489 * lam <= start - g["ship_x"] <= 0.489 * lam + 1.0
        assert tank["geometry.tank_length"] == start + zone
        assert "geometry.ship_x" not in tank
    assert study.tank_for_wave(0.6) == {"geometry.tank_length": 276.0,
                                        "geometry.absorber.start": 132.0,
                                        "geometry.absorber.length": 144.0}
    # the engine takes the stretched tank (ship inside, clear of the zone; zone inside)
    row = study.check_cases([dict(ROW, omega=0.6, amplitude=1.1)])[0]
    over = study.ship_overrides(row, _load())
    assert over["geometry.tank_length"] == 276.0
    assert over["geometry.wavemaker.omega"] == 0.6
    assert over["run.t_end"] == pytest.approx(12 * 2 * math.pi / 0.6)
    cfg = study.check_case_document(study.case_document("damaged_ship", over), "w060")
    assert cfg.geometry.absorber.length == 144.0 and cfg.geometry.ship_x == 60.0


def test_roll_rao_sweep_holds_the_wave_slope():
    """config/sweeps/roll_rao.yaml: the intact ship and the reference damage at the same
    eleven frequencies from 0.6 to 1.4 rad/s, every wave at the paper's slope kA (A = 2 m
    at 1 rad/s), one wavemaker calibration per wave, the paper's groups at 1 rad/s."""
    from sph.bodies.wavemaker import wavenumber

    s = _rao_sweep()
    cases = s["cases"]
    assert len(cases) == 22
    intact = [c for c in cases if c["opening"] == 0]
    damaged = [c for c in cases if c["opening"] > 0]
    omegas = [c["omega"] for c in intact]
    assert omegas == [c["omega"] for c in damaged] == sorted(omegas)
    assert (omegas[0], omegas[-1], len(omegas)) == (0.6, 1.4, 11)
    assert all((c["opening"], c["side"], c["fill"]) == (pytest.approx(10 / 21), "back", 0.0)
               for c in damaged)
    ka = wavenumber(1.0, 30.0) * 2.0
    for c in cases:
        assert wavenumber(c["omega"], 30.0) * c["amplitude"] * 4.2 == pytest.approx(ka,
                                                                                  rel=2e-5)
    keys = {study.wave_key(study.ship_overrides(c, s)) for c in cases}
    assert len(keys) == 11 and "A2_w1" in keys  # Table I's wave, Table I's calibration
    # the zone at strength 2 in every case: 2.4 % reflection at 0.6 rad/s instead of 6.4 %
    assert {study.ship_overrides(c, s)["geometry.absorber.strength"] for c in cases} == {2.0}
    assert study.groups(cases, s["reference"]) == {"opening": ["intact_w100",
                                                               "damaged_w100"]}


def test_groups_are_at_the_reference_wave():
    rows = study.check_cases([dict(ROW, case="a", opening=0), dict(ROW, case="b"),
                              dict(ROW, case="c", opening=0, omega=0.8),
                              dict(ROW, case="d", omega=0.8)])
    ref = dict(rows[1], case="ref")
    assert study.groups(rows, ref) == {"opening": ["a", "b"]}
    assert study.groups(rows, dict(ref, omega=0.8)) == {"opening": ["c", "d"]}
    s = _load(cases=[dict(r) for r in rows], reference={"omega": 0.8})
    assert s["reference"]["omega"] == 0.8


def test_gather_of_several_waves_keeps_each_run_to_its_end(tmp_path):
    """Runs of two wave periods: the time axis is the longer run's, the shorter is NaN
    after its end; the frequency, period and damage time of each case are kept along
    ``case``, and :func:`one_wave` takes the cases of one wave back out."""
    cases = study.check_cases([dict(case="a", opening=0, side="back", fill=0),
                               dict(case="b", opening=0, side="back", fill=0, omega=0.5)])
    a = _run_file(tmp_path / "a.nc", cases[0], t_end=1.0)
    b = _run_file(tmp_path / "b.nc", cases[1], t_end=2.0)
    ds = xr_open(b)
    ds.attrs.update(wave_period=12.56, damage_time=4.0)
    write_netcdf_atomic(ds, b)
    ds = study.gather([a, b], cases)
    assert ds.sizes["time"] == 21
    assert ds["omega"].values.tolist() == [1.0, 0.5]
    assert ds["omega"].attrs["units"] == "rad s-1"
    assert ds["wave_period"].values.tolist() == [6.28, 12.56]
    assert "wave_period" not in ds.attrs and "damage_time" not in ds.attrs
    assert np.isnan(ds["roll"].sel(case="a").values[11:]).all()
    assert np.isfinite(ds["roll"].sel(case="b").values).all()
    one = study.one_wave(ds, ["a"])
    assert one.sizes["time"] == 11 and one.attrs["wave_period"] == 6.28
    assert one.attrs["damage_time"] == 2.0
    assert study.one_wave(ds).sizes["case"] == 1  # default: the first case's wave
    with pytest.raises(ValueError, match="different wave_periods"):
        study.one_wave(ds, ["a", "b"])


def xr_open(path):
    from sph.io.output import read_dataset

    ds = read_dataset(path)
    ds.load()
    ds.close()
    return ds



def test_a_ship_case_warns_of_a_zone_shorter_than_its_wave(caplog):
    """`sph run` of a ship case in a long wave and the paper's tank warns; the tank of
    tank_for_wave does not."""
    import logging

    from sph.cases import builtin

    with caplog.at_level(logging.WARNING, logger="sph.cases.ship"):
        builtin("damaged_ship", ["geometry.wavemaker.omega=0.6"])
    assert "absorbing zone (60 m) is 0.41 lengths of the 146.8 m wave" in caplog.text
    caplog.clear()
    tank = [f"{k}={v}" for k, v in study.tank_for_wave(0.6).items()]
    with caplog.at_level(logging.WARNING, logger="sph.cases.ship"):
        builtin("damaged_ship", ["geometry.wavemaker.omega=0.6", *tank])
        builtin("damaged_ship")
    assert "absorbing zone" not in caplog.text


def test_configuration_digest_follows_the_whole_configuration():
    """The digest the workflow's case-file rules carry is of the configuration the engine
    builds, every default filled in: a case file that states a default explicitly has the
    digest of one that leaves it out, one that changes it another; check_documents returns
    one per run of the sweep."""
    s = _load()
    over = study.ship_overrides(s["cases"][2], s)

    def digest(extra):
        doc = study.case_document("damaged_ship", {**over, **extra})
        return study.configuration_digest(study.check_case_document(doc, "case3"))

    ramp = study.check_case_document(study.case_document("damaged_ship", over), "case3") \
        .geometry.wavemaker.ramp_time
    assert digest({}) == digest({"geometry.wavemaker.ramp_time": ramp})
    assert digest({}) != digest({"geometry.wavemaker.ramp_time": 0.0})
    digests = study.check_documents({"case3": over}, {})
    assert digests == {"ship": {"case3": digest({})}, "validation": {}}


def test_the_cases_that_differ_in_the_opening_alone_share_their_run_to_t1():
    """Table I: cases 1-5 (intact, three openings, two sides; the same fill and wave) share
    one run of the intact ship to one output interval before t1 = 3.18 T, keeping its
    checkpoints; each cargo case differs in its fill and shares nothing. In the rao sweep
    each wave's intact and damaged runs share one."""
    s = _load()
    over = {c["case"]: study.ship_overrides(c, s) for c in s["cases"]}
    runs = study.predamage_runs(over)
    assert list(runs) == ["predamage_case1"]
    run = runs["predamage_case1"]
    assert run["cases"] == ["case1", "case2", "case3", "case4", "case5"]
    seed = run["overrides"]
    period = 2.0 * math.pi / study.DEFAULT_OMEGA
    t1 = 3.18 * period
    assert seed["run.t_end"] == pytest.approx(t1 - seed["run.output_interval"], abs=1e-8)
    assert seed["geometry.damage.opening"] == 0.0 and seed["run.keep_checkpoints"] is True
    assert {k: v for k, v in seed.items() if not k.startswith(("geometry.damage.", "run."))} \
        == {k: v for k, v in over["case4"].items()
            if not k.startswith(("geometry.damage.", "run."))}
    built = study.check_case_document(study.case_document("damaged_ship", seed), "seed")
    assert run["digest"] == study.configuration_digest(built)
    assert built.run.t_end == seed["run.t_end"] and built.run.keep_checkpoints
    rao = _rao_sweep()
    rao_runs = study.predamage_runs({c["case"]: study.ship_overrides(c, rao)
                                     for c in rao["cases"]})
    assert len(rao_runs) == 11
    assert all(len(r["cases"]) == 2 for r in rao_runs.values())
    # a damage time within an output interval of the start: nothing to share
    early = {k: dict(v, **{"geometry.damage.time_periods": 0.001}) for k, v in over.items()}
    assert study.predamage_runs(early) == {}
