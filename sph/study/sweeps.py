"""Parameter studies: sweep configurations, case tables, case files and sweep datasets.

A *sweep* is a set of ``damaged_ship`` runs that differ in a few case parameters (the paper's
Table I: opening size, opening side, cargo fill ratio), run at one resolution *preset*. The
workflow (``Snakefile``) reads its configuration with :func:`load_sweep`, which checks every
key before any job starts; writes one case file per run with :func:`case_document`; and
concatenates the runs into one dataset with a ``case`` dimension with :func:`gather`.

Sweep configuration (``config/config.yaml``; a sweep file under ``config/sweeps/`` overrides
what it names):

=================  ==========================================================================
``sweep``          name of the sweep; its results go to ``results/<sweep>/``
``title``          one line describing the sweep
``cases``          path of a case table (TSV or CSV) or an inline list of rows
``preset``         resolution preset, a name in the presets file
``presets``        path of the presets file
``set``            case-file values (dotted keys) applied to every run of the sweep
``reference``      the reference case of the paper's comparisons (opening, side, fill,
                   amplitude): figures and findings group the cases around it
``t2_periods``     start of the dynamic-equilibrium stage, in wave periods (paper's t2)
``validation``     validation targets to run (see :data:`VALIDATION_TARGETS`)
``validation_data`` folder of the experimental series; null = ``data/validation/``
=================  ==========================================================================

Case table columns: ``case`` (an explicit id, used in file names), ``opening`` (delta_bar =
delta / d; 0 = intact), ``side`` (``back`` or ``head``), ``fill`` (eta, in [0, 1)), and
optionally ``amplitude`` (incident wave amplitude over draught, A / d; 0 = still water; default
the wave of the ``damaged_ship`` case, 2.0 m / 4.2 m = 10/21), ``cargo_density`` (kg/m3 of the
cargo; empty: the sweep's ``set`` value of ``geometry.cargo_density``, else the case's 1000)
and ``description``. Numbers may be written as fractions (``10/21``).

The optional column ``omega`` is the wave frequency (rad/s; default the ``damaged_ship``
case's, 1.0). Each run lasts the preset's number of wave periods and its damage opens at
``t1 = 3.18 T`` of its own wave. The tank follows the wave (:func:`tank_for_wave`): the
built-in tank (ship at 2H = 60 m from the flap, 30 m of open water, then a 60 m absorbing
zone: 0.49 and 0.98 wave lengths of the built-in wave) is kept for waves no longer than the
built-in one, and for a longer wave the open water behind the ship and the absorbing zone
are stretched in proportion to the wave length. :func:`check_waves` refuses a wave that
breaks (Miche's limit), a wave too long for linear flap theory (Ursell number) and a wave
height under two particle spacings.

The defaults of the ship (draught, opening, side, fill, wave) are those of the built-in case,
read from ``sph/cases/damaged_ship.yaml`` (:func:`sph.cases.load_defaults`); the validation
targets and their runs are the table :data:`sph.study.validation.TARGETS`.
"""

from __future__ import annotations

import copy
import hashlib
import math
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from sph import __version__
from sph.bodies.wavemaker import wavenumber
from sph.cases import build_case, load_defaults
from sph.cases.ship import damage_time
from sph.engine.absorber import damping_depth
from sph.engine.config import Fluid
from sph.io.output import cf_attrs, read_dataset
from sph.schema import ConfigError
from sph.study.validation import TARGETS

#: sides of the damage opening
SIDES = ("back", "head")
#: validation targets the workflow knows (:data:`sph.study.validation.TARGETS`)
VALIDATION_TARGETS = tuple(TARGETS)
#: columns of a case table
CASE_COLUMNS = ("case", "opening", "side", "fill", "amplitude", "cargo_density",
                "description")
#: the optional wave-frequency column (rad/s) of a case table
OMEGA_COLUMN = "omega"
CASE_COLUMNS = (*CASE_COLUMNS, OMEGA_COLUMN)
#: the geometry defaults of the ``damaged_ship`` case (sph/cases/damaged_ship.yaml)
SHIP_DEFAULTS = load_defaults("damaged_ship")["geometry"]
#: the ship's draught d (m)
DEFAULT_DRAUGHT = float(SHIP_DEFAULTS["hull"]["draught"])
#: Table I's incident wave over the draught, A / d = 10/21 (A = 2.0 m at d = 4.2 m)
DEFAULT_AMPLITUDE = float(SHIP_DEFAULTS["wavemaker"]["amplitude"]) / DEFAULT_DRAUGHT
#: the reference case's opening delta_bar, side and fill ratio
DEFAULT_OPENING = float(SHIP_DEFAULTS["damage"]["opening"])
DEFAULT_SIDE = str(SHIP_DEFAULTS["damage"]["side"])
DEFAULT_FILL = float(SHIP_DEFAULTS["fill"])
#: the built-in wave's frequency omega (rad/s), the water depth H (m) and gravity (m/s2)
DEFAULT_OMEGA = float(SHIP_DEFAULTS["wavemaker"]["omega"])
DEFAULT_DEPTH = float(SHIP_DEFAULTS["depth"])
GRAVITY = Fluid().gravity
#: top-level keys of a sweep configuration
SWEEP_KEYS = ("sweep", "title", "cases", "preset", "presets", "set", "reference", "t2_periods",
              "validation", "validation_data", "calibrate_wavemaker")
#: sections of a preset
PRESET_KEYS = ("description", "ship", "wave_tank", "sloshing", "decay", "floating_box",
               "dam_break", "cylinder")
#: preset sections needed only by a sweep that lists their validation target
OPTIONAL_SECTIONS = ("cylinder",)
#: keys of each preset section and whether they are required
PRESET_SECTION_KEYS = {
    "ship": {"dx": True, "periods": True, "output_interval": False, "set": False},
    "wave_tank": {"dx_over_amplitude": True, "amplitude": True, "t_end": True, "window": True,
                  "output_interval": False, "set": False},
    "sloshing": {"dx": True, "t_end": True, "fills": True, "output_interval": False,
                 "set": False},
    "decay": {"dx": True, "t_end": True, "heel": True, "heave_offset": True,
              "output_interval": False, "set": False},
    "floating_box": {"dx": True, "t_end": True, "output_interval": False, "set": False},
    "dam_break": {"dx": True, "t_end": True, "output_interval": False, "set": False},
    "cylinder": {"dx": True, "t_end": True, "froude": True, "output_interval": False,
                 "set": False},
}
#: the largest wave frequency a case row may ask for (rad/s; a 0.6 s wave)
OMEGA_MAX = 10.0
#: Miche's breaking limit of a regular wave: H / lambda at most ``MICHE tanh(k h)``
#: (Miche 1944)
MICHE = 0.142
#: the largest Ursell number ``H lambda^2 / h^3``: the second harmonic of a Stokes wave in
#: shallow water is ``a2 / a1 = 3 Ur / (32 pi^2)`` of the first, a quarter at ``8 pi^2 / 3``
#: (26.3); beyond, the wave is a cnoidal one that neither linear flap theory nor the
#: calibration's sinusoid describes
URSELL_MAX = 8.0 * math.pi**2 / 3.0
#: the wave height 2A spans at least this many particle spacings (refused below)
MIN_HEIGHT_SPACINGS = 2.0
#: a wave height under this many spacings is resolved poorly (a warning)
WARN_HEIGHT_SPACINGS = 4.0
#: an absorbing zone shorter than this many wave lengths is warned about (the built-in
#: tank's 60 m zone is 0.98 of its wave's 61.4 m; such a zone reflects 1-2 %,
#: :mod:`sph.engine.absorber`)
MIN_ABSORBER_WAVELENGTHS = 0.95
#: the case-file keys of the tank's lengths along x (:func:`tank_for_wave`)
TANK_KEYS = ("geometry.tank_length", "geometry.ship_x", "geometry.absorber.start",
             "geometry.absorber.length")
_ID = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_-]*$")
_FRACTION = re.compile(r"^\s*([+-]?\d+(?:\.\d*)?)\s*/\s*(\d+(?:\.\d*)?)\s*$")


# ------------------------------------------------------------------------------ numbers
def parse_number(value: Any, key: str) -> float:
    """A finite number from a YAML/table value; ``"10/21"`` style fractions are accepted.

    Raises
    ------
    ConfigError
        Naming ``key`` when the value is not a finite number or fraction.
    """
    if isinstance(value, bool):
        raise ConfigError(key, f"expected a number, got {value!r}")
    if isinstance(value, (int, float, np.integer, np.floating)):
        out = float(value)
    elif isinstance(value, str):
        m = _FRACTION.match(value)
        try:
            out = float(m.group(1)) / float(m.group(2)) if m else float(value)
        except (ValueError, ZeroDivisionError):
            raise ConfigError(key, f"expected a number or a fraction such as 10/21, got "
                              f"{value!r}") from None
    else:
        raise ConfigError(key, f"expected a number, got {value!r}")
    if not math.isfinite(out):
        raise ConfigError(key, f"must be finite; got {value!r}")
    return out


def _in_range(value: float, key: str, lo: float, hi: float, hi_open: bool = False) -> float:
    if value < lo or value > hi or (hi_open and value == hi):
        right = ")" if hi_open else "]"
        raise ConfigError(key, f"must be in [{lo:g}, {hi:g}{right}; got {value:g}")
    return value


def _check_id(value: Any, key: str, what: str) -> str:
    if not isinstance(value, str) or not _ID.match(value):
        raise ConfigError(key, f"{what} must be a non-empty name of letters, digits, '_' and "
                          f"'-' (starting with a letter or digit); got {value!r}")
    return value


def _check_keys(data: Mapping, allowed: Sequence[str], where: str) -> None:
    for k in data:
        if k not in allowed:
            name = f"{where}.{k}" if where else str(k)
            raise ConfigError(name, f"unknown key; allowed keys here: {', '.join(allowed)}")


# ------------------------------------------------------------------------------ case table
def read_case_table(path: str | Path) -> list[dict]:
    """Rows of a case table file (tab- or comma-separated, ``#`` comment lines skipped)."""
    import csv

    path = Path(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise ConfigError("cases", f"cannot read the case table {str(path)!r}: "
                          f"{exc.strerror}") from None
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise ConfigError("cases", f"the case table {str(path)!r} is empty")
    delimiter = "\t" if "\t" in lines[0] else ","
    reader = csv.reader(lines, delimiter=delimiter)
    header = [h.strip() for h in next(reader)]
    rows = []
    for n, fields in enumerate(reader, start=1):
        if len(fields) != len(header):
            raise ConfigError(f"cases[{n}]", f"row {n} of {str(path)!r} has {len(fields)} "
                              f"fields, the header has {len(header)}")
        rows.append({h: f.strip() for h, f in zip(header, fields, strict=True)})
    return rows


def check_cases(rows: Any) -> list[dict]:
    """Validate case rows; returns them with numbers parsed and defaults filled in.

    Checks: a non-empty list of mappings; only the known columns; an explicit, unique,
    file-name-safe ``case`` id; ``opening`` in [0, 1); ``side`` back or head; ``fill`` in
    [0, 1); ``amplitude`` in [0, 2]; ``cargo_density`` in [1, 1e5] kg/m3 or empty (None);
    ``omega`` in (0, 10] rad/s (the checks that need the tank and the resolution are
    :func:`check_waves`'s). Each error names the row's key (``cases[k].column``); whether
    the cargo fits the ship is the engine's check of each run's case file
    (:func:`check_case_document`).
    """
    if not isinstance(rows, list) or not rows:
        raise ConfigError("cases", "expected a non-empty list of cases (or the path of a case "
                          f"table); got {rows!r}")
    out, seen = [], {}
    for k, row in enumerate(rows):
        key = f"cases[{k}]"
        if not isinstance(row, Mapping):
            raise ConfigError(key, f"expected a mapping of columns, got {row!r}")
        _check_keys(row, CASE_COLUMNS, key)
        for col in ("case", "opening", "side", "fill"):
            if col not in row or row[col] in (None, ""):
                raise ConfigError(f"{key}.{col}", "required column is missing")
        cid = _check_id(str(row["case"]) if isinstance(row["case"], int) else row["case"],
                        f"{key}.case", "a case id")
        if cid in seen:
            raise ConfigError(f"{key}.case", f"duplicate case id {cid!r} (also cases[{seen[cid]}])"
                              "; case ids must be unique")
        seen[cid] = k
        side = row["side"]
        if side not in SIDES:
            raise ConfigError(f"{key}.side", f"unknown side {side!r}; must be one of "
                              f"{', '.join(SIDES)}")
        amp = row.get("amplitude")
        amp = DEFAULT_AMPLITUDE if amp in (None, "") else parse_number(amp,
                                                                        f"{key}.amplitude")
        out.append(dict(
            case=cid,
            opening=_in_range(parse_number(row["opening"], f"{key}.opening"),
                              f"{key}.opening", 0.0, 1.0, hi_open=True),
            side=side,
            fill=_in_range(parse_number(row["fill"], f"{key}.fill"), f"{key}.fill", 0.0, 1.0,
                           hi_open=True),
            amplitude=_in_range(amp, f"{key}.amplitude", 0.0, 2.0),
            cargo_density=_cargo_density(row.get("cargo_density"), f"{key}.cargo_density"),
            description=str(row.get("description") or ""),
        ))
        out[-1][OMEGA_COLUMN] = _omega(row.get(OMEGA_COLUMN), f"{key}.{OMEGA_COLUMN}")
    return out


def _cargo_density(value: Any, key: str) -> float | None:
    """The optional ``cargo_density`` column: kg/m3 in the engine's range, or None."""
    if value is None or (isinstance(value, str) and not value.strip()):
        return None
    return _in_range(parse_number(value, key), key, 1.0, 1.0e5)


def _omega(value: Any, key: str) -> float:
    """The wave frequency of a case row (rad/s): the built-in wave's when left out."""
    if value in (None, ""):
        return DEFAULT_OMEGA
    omega = parse_number(value, key)
    if not 0.0 < omega <= OMEGA_MAX:
        raise ConfigError(key, f"must be in (0, {OMEGA_MAX:g}] rad/s; got {omega:g}")
    return omega


# ------------------------------------------------------------------------------ presets
def check_presets(presets: Any, source: str = "presets") -> dict:
    """Validate a presets mapping ``name -> sections`` (see :data:`PRESET_SECTION_KEYS`)."""
    if not isinstance(presets, Mapping) or not presets:
        raise ConfigError(source, "expected a mapping of preset names to settings")
    for name, preset in presets.items():
        where = f"{source}.{name}"
        _check_id(name, where, "a preset name")
        if not isinstance(preset, Mapping):
            raise ConfigError(where, f"expected a mapping of sections, got {preset!r}")
        _check_keys(preset, PRESET_KEYS, where)
        for section, keys in PRESET_SECTION_KEYS.items():
            sec = preset.get(section)
            if sec is None and section in OPTIONAL_SECTIONS:
                continue
            if not isinstance(sec, Mapping):
                raise ConfigError(f"{where}.{section}", "required section is missing or not "
                                  "a mapping")
            _check_keys(sec, tuple(keys), f"{where}.{section}")
            for k, required in keys.items():
                if required and k not in sec:
                    raise ConfigError(f"{where}.{section}.{k}", "required key is missing")
            for k, v in sec.items():
                sub = f"{where}.{section}.{k}"
                if k == "set":
                    _check_set(v, sub)
                elif k in ("dx_over_amplitude", "window", "fills", "froude"):
                    if not isinstance(v, list) or not v:
                        raise ConfigError(sub, f"expected a non-empty list, got {v!r}")
                    for i, x in enumerate(v):
                        _in_range(parse_number(x, f"{sub}[{i}]"), f"{sub}[{i}]", 0.0, 1.0e6)
                    if k == "window" and len(v) != 2:
                        raise ConfigError(sub, f"expected [start, end] in s, got {v!r}")
                else:
                    x = parse_number(v, sub)
                    lo = -90.0 if k in ("heel", "heave_offset") else 0.0
                    if k not in ("heel", "heave_offset") and x <= 0.0:
                        raise ConfigError(sub, f"must be positive; got {x:g}")
                    _in_range(x, sub, lo, 1.0e6)
    return dict(presets)


def _check_set(value: Any, key: str) -> dict:
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        raise ConfigError(key, "expected a mapping of dotted case keys to values, e.g. "
                          "{geometry.hull.kg: 3.4}")
    for k in value:
        if not isinstance(k, str) or not k or " " in k:
            raise ConfigError(f"{key}.{k}", "expected a dotted case key such as numerics.dx")
    return dict(value)


# ------------------------------------------------------------------------------ sweep
def load_sweep(config: Mapping, base: str | Path = ".") -> dict:
    """Check a sweep configuration and resolve it.

    Returns a new mapping with ``cases`` as checked rows, ``presets`` as the checked presets
    mapping, ``preset_settings`` (the chosen preset), ``reference`` and ``t2_periods`` as
    numbers. Paths are relative to ``base``.

    Raises
    ------
    ConfigError
        Naming the offending key: unknown keys, a missing or unknown preset, bad case rows,
        an unknown validation target, ...
    """
    if not isinstance(config, Mapping):
        raise ConfigError("", "the configuration must be a mapping")
    _check_keys(config, SWEEP_KEYS, "")
    for k in ("sweep", "cases", "preset", "presets"):
        if k not in config or config[k] is None or config[k] == "":
            raise ConfigError(k, "required key is missing")
    base = Path(base)
    cfg = dict(config)
    cfg["sweep"] = _check_id(config["sweep"], "sweep", "the sweep name")
    if cfg["sweep"] == "validation":
        raise ConfigError("sweep", "'validation' is reserved for the validation results")
    cfg["title"] = str(config.get("title") or cfg["sweep"])
    cases = config["cases"]
    if isinstance(cases, str):
        cases = read_case_table(base / cases)
    # an empty list: a sweep of validation targets only (config/sweeps/cylinder_froude.yaml)
    validation_only = isinstance(cases, list) and not cases
    if validation_only and not config.get("validation"):
        raise ConfigError("cases", "an empty case table runs no ship: a sweep without cases "
                          "must list validation targets (validation: [...])")
    cfg["cases"] = [] if validation_only else check_cases(cases)
    presets_path = base / str(config["presets"])
    try:
        presets = yaml.safe_load(presets_path.read_text())
    except OSError as exc:
        raise ConfigError("presets", f"cannot read {str(presets_path)!r}: "
                          f"{exc.strerror}") from None
    except yaml.YAMLError as exc:
        raise ConfigError("presets", f"{str(presets_path)!r} is not valid YAML: "
                          f"{exc}") from None
    cfg["presets"] = check_presets(presets, "presets")
    preset = config["preset"]
    if preset not in cfg["presets"]:
        raise ConfigError("preset", f"unknown preset {preset!r}; must be one of "
                          f"{', '.join(cfg['presets'])}")
    cfg["preset_settings"] = cfg["presets"][preset]
    cfg["set"] = _check_set(config.get("set"), "set")
    ref = config.get("reference") or {}
    if not isinstance(ref, Mapping):
        raise ConfigError("reference", f"expected a mapping, got {ref!r}")
    _check_keys(ref, ("opening", "side", "fill", "amplitude", OMEGA_COLUMN), "reference")
    cfg["reference"] = check_cases([dict(case="reference",
                                         opening=ref.get("opening", DEFAULT_OPENING),
                                         side=ref.get("side", DEFAULT_SIDE),
                                         fill=ref.get("fill", DEFAULT_FILL),
                                         amplitude=ref.get("amplitude",
                                                           DEFAULT_AMPLITUDE),
                                         omega=ref.get(OMEGA_COLUMN))])[0]
    cfg["t2_periods"] = _in_range(parse_number(config.get("t2_periods", 7.0), "t2_periods"),
                                  "t2_periods", 0.0, 1.0e4)
    targets = config.get("validation") or []
    if not isinstance(targets, list):
        raise ConfigError("validation", f"expected a list of targets, got {targets!r}")
    for i, t in enumerate(targets):
        if t not in VALIDATION_TARGETS:
            raise ConfigError(f"validation[{i}]", f"unknown validation target {t!r}; must "
                              f"be one of {', '.join(VALIDATION_TARGETS)}")
    cfg["validation"] = list(dict.fromkeys(targets))
    for t in cfg["validation"]:
        if t in OPTIONAL_SECTIONS and t not in cfg["preset_settings"]:
            raise ConfigError(f"presets.{preset}.{t}", f"the validation target {t!r} needs "
                              "this section of the preset")
    calibrate = config.get("calibrate_wavemaker", True)
    if calibrate in ("true", "false", "True", "False"):  # `--config calibrate_wavemaker=false`
        calibrate = calibrate.lower() == "true"
    if not isinstance(calibrate, bool):
        raise ConfigError("calibrate_wavemaker", f"must be true or false; got {calibrate!r}")
    cfg["calibrate_wavemaker"] = calibrate
    # a case without a cargo density gets the one its run will have
    density = float(_check_set(cfg["preset_settings"]["ship"].get("set"), "ship.set").get(
        "geometry.cargo_density", SHIP_DEFAULTS["cargo_density"]))
    density = float(cfg["set"].get("geometry.cargo_density", density))
    for row in cfg["cases"]:
        if row["cargo_density"] is None:
            row["cargo_density"] = density
    check_waves(cfg)
    return cfg


def wave_key(overrides: Mapping[str, Any]) -> str | None:
    """The name of the wave of a ship run's values (:func:`ship_overrides`), which names its
    wavemaker calibration (:mod:`sph.study.calibration`): ``A2_w1`` for A = 2 m and
    omega = 1 rad/s; None in still water."""
    amplitude = overrides.get("geometry.wavemaker.amplitude")
    if amplitude is None:
        return None
    omega = overrides.get("geometry.wavemaker.omega", SHIP_DEFAULTS["wavemaker"]["omega"])
    return f"A{float(amplitude):g}_w{float(omega):g}"


# ------------------------------------------------------------------------------ waves
def wave_length(omega: float, depth: float, gravity: float = GRAVITY) -> float:
    """Length (m) of the linear wave of frequency ``omega`` (rad/s) in water of ``depth``
    (finite-depth dispersion relation, :func:`sph.bodies.wavemaker.wavenumber`)."""
    return 2.0 * math.pi / wavenumber(omega, depth, gravity)


def tank_for_wave(omega: float, depth: float = DEFAULT_DEPTH,
                  gravity: float = GRAVITY) -> dict[str, float]:
    """The tank of a ship run in a wave of frequency ``omega``: the case-file values
    (dotted keys, :data:`TANK_KEYS`) that differ from the built-in tank; none for a wave no
    longer than the built-in one.

    The built-in tank (``sph/cases/damaged_ship.yaml``) has the ship at 2H = 60 m from the
    flap, 30 m of open water behind it and a 60 m absorbing zone to the end wall: 0.49 and
    0.98 lengths of the built-in wave (61.4 m at omega = 1 rad/s, H = 30 m). A longer wave
    stretches the open water and the zone by the ratio ``s`` of the wave lengths (each
    rounded up to the metre), so that the zone stays a wave length long (its reflection is
    then 1-2 %, :mod:`sph.engine.absorber`) and the waves the ship radiates cross half a
    wave length before they are damped. The ship stays at 2H: the flap's evanescent modes
    decay over the depth (as ``exp(-pi x / H)``, 0.2 % at 2H), whatever the wave length, and
    the wavemaker calibration measures the wave there. A shorter wave keeps the built-in
    tank, whose zone is then longer than it needs to be.
    """
    g = SHIP_DEFAULTS
    scale = wave_length(omega, depth, gravity) / wave_length(DEFAULT_OMEGA, depth, gravity)
    if scale <= 1.0 + 1e-12:
        return {}
    ship_x = float(g["ship_x"])
    gap = math.ceil(scale * (float(g["absorber"]["start"]) - ship_x) - 1e-9)
    zone = math.ceil(scale * float(g["absorber"]["length"]) - 1e-9)
    tail = float(g["tank_length"]) - float(g["absorber"]["start"]) - float(
        g["absorber"]["length"])
    start = ship_x + gap
    return {"geometry.tank_length": start + zone + tail, "geometry.absorber.start": start,
            "geometry.absorber.length": float(zone)}


def check_waves(sweep: Mapping) -> None:
    """Refuse the waves of a resolved sweep (:func:`load_sweep`) that its ship runs cannot
    carry. For each case in waves, with its amplitude A, frequency omega, wave length
    lambda, depth h and the preset's dx:

    - steeper than Miche's breaking limit, ``2A / lambda > 0.142 tanh(k h)``;
    - an Ursell number ``2A lambda^2 / h^3`` above :data:`URSELL_MAX` (a long wave whose
      shape is not the sinusoid of linear flap theory);
    - a wave height 2A under :data:`MIN_HEIGHT_SPACINGS` particle spacings (a warning
      under :data:`WARN_HEIGHT_SPACINGS`).

    The tank of :func:`tank_for_wave` has an absorbing zone of at least 0.98 wave lengths;
    a tank that the sweep's ``set`` gives is the user's (the workflow test's is a toy) and
    a zone shorter than :data:`MIN_ABSORBER_WAVELENGTHS` wave lengths is only warned about.

    Raises
    ------
    ConfigError
        Naming the row's column (``cases[k].omega`` or ``cases[k].amplitude``).
    """
    import logging

    preset = sweep.get("preset", "")
    coarse, short = [], []
    for k, row in enumerate(sweep["cases"]):
        over = ship_overrides(row, sweep)
        amp = over["geometry.wavemaker.amplitude"]
        if amp is None:  # still water
            continue
        omega = float(over.get("geometry.wavemaker.omega", DEFAULT_OMEGA))
        depth = float(over.get("geometry.depth", DEFAULT_DEPTH))
        gravity = float(over.get("fluid.gravity", GRAVITY))
        dx = float(over["numerics.dx"])
        lam = wave_length(omega, depth, gravity)
        height = 2.0 * float(amp)
        wave = (f"the wave of amplitude A = {amp:.4g} m at omega = {omega:g} rad/s (length "
                f"{lam:.4g} m in {depth:g} m of water)")
        limit = MICHE * math.tanh(2.0 * math.pi * depth / lam)
        if height / lam > limit:
            raise ConfigError(f"cases[{k}].{OMEGA_COLUMN}", f"{wave} is steeper than the "
                              f"breaking limit: 2A / length = {height / lam:.3g} > 0.142 "
                              f"tanh(kh) = {limit:.3g} (Miche); use a lower omega or a "
                              f"smaller amplitude")
        ursell = height * lam**2 / depth**3
        if ursell > URSELL_MAX:
            raise ConfigError(f"cases[{k}].{OMEGA_COLUMN}", f"{wave} has an Ursell number "
                              f"2A length^2 / h^3 = {ursell:.3g} above {URSELL_MAX:.3g}: a "
                              f"cnoidal wave, not the sinusoid of linear flap theory; use a "
                              f"higher omega or a smaller amplitude")
        if height < MIN_HEIGHT_SPACINGS * dx:
            raise ConfigError(f"cases[{k}].amplitude", f"{wave}: its height 2A = "
                              f"{height:.3g} m spans {height / dx:.2g} particle spacings "
                              f"(dx = {dx:g} m at preset {preset!r}); at least "
                              f"{MIN_HEIGHT_SPACINGS:g} are needed: use a larger amplitude "
                              f"(at a fixed steepness kA, a lower omega) or a finer preset")
        if height < WARN_HEIGHT_SPACINGS * dx:
            coarse.append(f"{row['case']} ({height / dx:.2g})")
        zone = float(over.get("geometry.absorber.length",
                              SHIP_DEFAULTS["absorber"]["length"]))
        if zone < MIN_ABSORBER_WAVELENGTHS * lam:
            short.append(f"{row['case']} ({zone / lam:.2f})")
    log = logging.getLogger(__name__)
    if coarse:
        log.warning("wave heights 2A of fewer than %g particle spacings at preset %r (the "
                    "wave is damped more on its way to the ship; the calibration makes up "
                    "for it): %s", WARN_HEIGHT_SPACINGS, preset, ", ".join(coarse))
    if short:
        log.warning("absorbing zones of the tank the sweep sets shorter than %g wave lengths "
                    "(part of the wave reflects from the end wall; without the tank in "
                    "`set`, tank_for_wave sizes it): %s", MIN_ABSORBER_WAVELENGTHS,
                    ", ".join(short))


# ------------------------------------------------------------------------------ case files
def nest(overrides: Mapping[str, Any]) -> dict:
    """``{"a.b": 1, "a.c": 2}`` -> ``{"a": {"b": 1, "c": 2}}``."""
    out: dict = {}
    for key, value in overrides.items():
        parts = key.split(".")
        node = out
        for i, part in enumerate(parts[:-1]):
            nxt = node.setdefault(part, {})
            if not isinstance(nxt, dict):
                raise ConfigError(".".join(parts[: i + 1]), f"is set both as a value and as a "
                                  f"section (setting {key})")
            node = nxt
        if isinstance(node.get(parts[-1]), dict):
            raise ConfigError(key, "is set both as a value and as a section")
        node[parts[-1]] = copy.deepcopy(value)
    return out


def case_document(case: str, overrides: Mapping[str, Any]) -> dict:
    """The case file of one run: the built-in case ``case`` with ``overrides`` (dotted keys)
    on top; the engine fills in every other value from the case's defaults."""
    doc = {"case": case}
    doc.update(nest(overrides))
    return doc


def check_case_document(doc: Mapping, where: str):
    """Build the engine's configuration of a case file (every key and range checked, the
    ship's geometry rules included) and return it; errors name the run and the key."""

    try:
        return build_case(copy.deepcopy(dict(doc)))
    except ConfigError as exc:
        raise ConfigError(f"{where}: {exc.key}" if exc.key else where,
                          str(exc).split(": ", 1)[-1] if exc.key else str(exc)) from None


def configuration_digest(cfg) -> str:
    """A short digest of a run's whole configuration, every default of its built-in case
    filled in (:meth:`~sph.engine.config.CaseConfig.to_yaml`). The workflow gives it to the
    rules that write case files as a parameter: a case file names only what the sweep sets,
    so without it a changed default of a built-in case (an update of the package) would
    leave the runs made with the old one standing."""
    return hashlib.sha256(cfg.to_yaml().encode()).hexdigest()[:16]


def check_documents(ship: Mapping[str, Mapping],
                    validation: Mapping[str, Mapping]) -> dict[str, dict[str, str]]:
    """Build the case file of every run of a sweep with the engine's checks, before any job
    starts: ``ship`` maps each case id to its overrides (:func:`ship_overrides`),
    ``validation`` is :func:`validation_runs`. Raises the first :class:`ConfigError`, naming
    the run and the key; the ship's log messages about resolution are left to the runs' own
    logs. Returns the :func:`configuration_digest` of every run: ``{"ship": {case id:
    digest}, "validation": {"target/run": digest}}``."""
    import logging

    quiet = logging.getLogger("sph")
    level = quiet.level
    quiet.setLevel(logging.ERROR)
    digests: dict[str, dict[str, str]] = {"ship": {}, "validation": {}}
    try:
        for cid, over in ship.items():
            cfg = check_case_document(case_document("damaged_ship", over), f"case {cid!r}")
            digests["ship"][cid] = configuration_digest(cfg)
        for target, runs in validation.items():
            for run, (case, over) in runs.items():
                cfg = check_case_document(case_document(case, over),
                                          f"validation {target}/{run}")
                digests["validation"][f"{target}/{run}"] = configuration_digest(cfg)
    finally:
        quiet.setLevel(level)
    return digests


def _wave_period(overrides: Mapping[str, Any]) -> float:
    omega = overrides.get("geometry.wavemaker.omega")
    if omega is None:
        omega = SHIP_DEFAULTS["wavemaker"]["omega"]
    return 2.0 * math.pi / float(omega)


def ship_overrides(row: Mapping, sweep: Mapping) -> dict:
    """Case-file values (dotted keys) of one Table I style run: the preset's and the
    sweep's ``set``, then the row's opening, side, fill, wave (``omega`` only where it is
    not the built-in wave's, so that a Table I case file names no frequency) and the tank
    for its wave (:func:`tank_for_wave`, unless the sweep sets the tank), and the duration
    of the preset's number of wave periods."""
    ship = sweep["preset_settings"]["ship"]
    over: dict[str, Any] = {}
    over.update(ship.get("set") or {})
    over.update(sweep.get("set") or {})
    over["numerics.dx"] = parse_number(ship["dx"], "ship.dx")
    over["geometry.damage.opening"] = float(row["opening"])
    over["geometry.damage.side"] = row["side"]
    over["geometry.fill"] = float(row["fill"])
    if row.get("cargo_density") is not None:
        over["geometry.cargo_density"] = float(row["cargo_density"])
    omega = float(row.get(OMEGA_COLUMN, DEFAULT_OMEGA))
    if omega != DEFAULT_OMEGA or "geometry.wavemaker.omega" in over:
        over["geometry.wavemaker.omega"] = omega
    if not any(k in over for k in TANK_KEYS):  # a tank the sweep sets is kept as it is
        over.update(tank_for_wave(omega, float(over.get("geometry.depth", DEFAULT_DEPTH)),
                                  float(over.get("fluid.gravity", GRAVITY))))
    draught = over.get("geometry.hull.draught", DEFAULT_DRAUGHT)
    amplitude = float(row["amplitude"]) * float(draught)
    if amplitude > 0.0:
        over["geometry.wavemaker.amplitude"] = round(amplitude, 12)
        over["geometry.wavemaker.theta0"] = None
    else:  # still water
        over["geometry.wavemaker.amplitude"] = None
        over["geometry.wavemaker.theta0"] = 0.0
    period = _wave_period(over)
    over["run.t_end"] = round(parse_number(ship["periods"], "ship.periods") * period, 9)
    if "output_interval" in ship:
        over["run.output_interval"] = parse_number(ship["output_interval"],
                                                   "ship.output_interval")
    return over


#: the case-file keys of the damage opening: ship runs that differ in these alone are the
#: same run until the opening appears at t1 (:func:`predamage_runs`)
DAMAGE_PREFIX = "geometry.damage."
#: of those, the one that also sets when the runs part
DAMAGE_TIME_KEY = "geometry.damage.time_periods"


def predamage_runs(ship: Mapping[str, Mapping]) -> dict[str, dict]:
    """The runs to t1 that ship runs share: ``ship`` maps each case id to its overrides
    (:func:`ship_overrides`); the runs that differ only in the damage opening (its size,
    its side, or none) are one and the same run until the opening appears at t1
    (:meth:`sph.engine.stepper.Stepper.set_state` with ``seed``), so each group of two or
    more runs the intact ship once, to the last output sample before t1, and its cases
    start from that run's last checkpoint (``sph run --start-from``). In Table I cases 1-5
    share 3.18 of their 12 periods.

    Returns ``{run id: {"cases": [case ids], "overrides": the shared run's values,
    "digest": its :func:`configuration_digest`}}``; the run id is ``predamage_`` and the
    group's first case id. Its values are the group's with
    the opening 0, ``run.t_end`` one output interval before t1 and ``run.keep_checkpoints``
    on. A group whose t1 is within an output interval of the start shares nothing."""
    groups: dict[tuple, list[str]] = {}
    for cid, over in ship.items():
        key = tuple(sorted((k, repr(v)) for k, v in over.items()
                           if not k.startswith(DAMAGE_PREFIX) or k == DAMAGE_TIME_KEY))
        groups.setdefault(key, []).append(cid)
    out: dict[str, dict] = {}
    for cases in groups.values():
        if len(cases) < 2:
            continue
        over = {k: v for k, v in ship[cases[0]].items()
                if not k.startswith(DAMAGE_PREFIX) or k == DAMAGE_TIME_KEY}
        over["geometry.damage.opening"] = 0.0
        cfg = check_case_document(case_document("damaged_ship", over),
                                  f"the run to t1 of cases {', '.join(cases)}")
        t_end = damage_time(cfg) - cfg.run.output_interval
        if t_end <= 0.0:
            continue
        over["run.t_end"] = round(t_end, 9)
        over["run.keep_checkpoints"] = True
        run = f"predamage_{cases[0]}"
        cfg = check_case_document(case_document("damaged_ship", over), f"run {run}")
        out[run] = {"cases": cases, "overrides": over, "digest": configuration_digest(cfg)}
    return out


def validation_runs(sweep: Mapping, data_dir: str | Path) -> dict[str, dict[str, tuple]]:
    """Runs of the validation targets of the sweep's preset: ``target -> run id ->
    (engine case, overrides)``, from each target's record in
    :data:`sph.study.validation.TARGETS` and the preset's section of the same name."""
    p = sweep["preset_settings"]
    out = {}
    for target in sweep["validation"]:
        runs = TARGETS[target].runs(_parsed(p[target], target), Path(data_dir))
        out[target] = {run: (TARGETS[target].case, over) for run, over in runs.items()}
    return out


def _parsed(section: Mapping, where: str) -> dict:
    """A preset section with its numbers (and lists of numbers) parsed; ``set`` as is."""
    out = {}
    for k, v in section.items():
        key = f"{where}.{k}"
        if k == "set":
            out[k] = v
        elif isinstance(v, list):
            out[k] = [parse_number(x, f"{key}[{i}]") for i, x in enumerate(v)]
        else:
            out[k] = parse_number(v, key)
    return out


# ------------------------------------------------------------------------------ groups
def _close(a: float, b: float) -> bool:
    return abs(a - b) <= 1e-6 * max(1.0, abs(a), abs(b))


def groups(cases: Sequence[Mapping], reference: Mapping) -> dict[str, list[str]]:
    """The paper's comparisons as lists of case ids (each sorted by the varied parameter).

    ``opening``: back-side openings at the reference fill and wave, intact included (Figs.
    12-15); ``side``: the reference opening on both sides (Figs. 17-19); ``fill``: the
    reference opening and side at every fill (Figs. 21-23); ``amplitude``: the reference
    opening, side and fill at every wave amplitude (Fig. 10). Every group is at the
    reference's wave frequency. A group is listed when it compares at least two cases.
    """
    ref = reference
    cases = [c for c in cases if _close(float(c.get(OMEGA_COLUMN, DEFAULT_OMEGA)),
                                        float(ref.get(OMEGA_COLUMN, DEFAULT_OMEGA)))]

    def match(c, **kw):
        for k, v in kw.items():
            if k == "side" and c["side"] != v:
                return False
            if k != "side" and not _close(float(c[k]), float(v)):
                return False
        return True

    g = {
        "opening": sorted((c for c in cases if (c["side"] == ref["side"] or c["opening"] == 0)
                           and match(c, fill=ref["fill"], amplitude=ref["amplitude"])),
                          key=lambda c: c["opening"]),
        "side": sorted((c for c in cases if match(c, opening=ref["opening"], fill=ref["fill"],
                                                   amplitude=ref["amplitude"])),
                       key=lambda c: SIDES.index(c["side"])),
        "fill": sorted((c for c in cases if match(c, opening=ref["opening"], side=ref["side"],
                                                   amplitude=ref["amplitude"])),
                       key=lambda c: c["fill"]),
        "amplitude": sorted((c for c in cases if match(c, opening=ref["opening"],
                                                        side=ref["side"], fill=ref["fill"])),
                            key=lambda c: c["amplitude"]),
    }
    # an intact case appears once in the opening group whatever its side column says
    seen: set = set()
    g["opening"] = [c for c in g["opening"]
                    if not (c["opening"] == 0 and ("intact" in seen or seen.add("intact")))]
    return {k: [c["case"] for c in v] for k, v in g.items() if len(v) >= 2}


# ------------------------------------------------------------------------------ gather
#: per-run global attributes kept as variables along ``case`` in the sweep dataset
CASE_SCALARS = ("wall_clock_seconds", "steps", "n_total", "particle_steps_per_second",
                "wave_period", "damage_time", "lost_particles", "guarded_particles")
#: global attributes that must agree between the runs of a sweep (kept as global attributes)
SHARED_ATTRS = ("wave_period", "damage_time", "omega", "dx", "draught", "breadth",
                "hull_depth", "cabin_area", "depth", "kernel", "density_filter",
                "speed_of_sound")


def _nominal_times(cfg: Mapping) -> np.ndarray:
    """The output times of a run's resolved configuration."""
    dt = float(cfg["run"]["output_interval"])
    t_end = float(cfg["run"]["t_end"])
    n = int(math.floor(t_end / dt + 1e-9))
    return np.arange(n + 1) * dt


#: a side of the hull counts as in the absorbing zone where the zone's damping rate there
#: reaches this fraction of the wave frequency: the sink sigma v beside the inertia
#: omega v of the flow about the hull (in the paper's tank 6.6 m into the zone)
ZONE_DAMPING = 0.02


def zone_clearance(config: Mapping, attrs: Mapping | None = None) -> tuple[float, float]:
    """How far the ship of a resolved case configuration ``config`` may sway towards +x
    and towards -x before a side of its hull (upright, at the waterline) lies where an
    absorbing zone damps at :data:`ZONE_DAMPING` times the wave frequency
    (:mod:`sph.engine.absorber`: sigma = (c / l) d / (l - d + dx) at a depth d into the
    zone; ``attrs``, the run's attributes, give its speed ``absorber_speed``, ``omega``
    and ``dx``; without them, the zone's edge): the zone at the tank's end and its mirror
    by the flap (``inf`` where there is none, or no hull)."""
    g = config.get("geometry", {})
    zone = g.get("absorber") or {}
    if "hull" not in g or not zone.get("enabled"):
        return math.inf, math.inf
    half = 0.5 * float(g["hull"]["breadth"])
    start, x, length = float(zone["start"]), float(g["ship_x"]), float(zone["length"])
    depth = 0.0  # how far into the zone the damping reaches ZONE_DAMPING omega
    attrs = attrs or {}
    if all(k in attrs for k in ("absorber_speed", "omega", "dx")):
        depth = damping_depth(ZONE_DAMPING * float(attrs["omega"]),
                              float(attrs["absorber_speed"]), length, float(attrs["dx"]))
    back = start + depth - (x + half)
    head = (x - half) - (float(g["tank_length"]) - start - depth) if zone.get("mirrored") \
        else math.inf
    return back, head


def gather(paths: Sequence[str | Path], cases: Sequence[Mapping], attrs: Mapping | None = None):
    """Concatenate the runs of a sweep into one dataset with a ``case`` dimension.

    The time series are interpolated linearly onto the nominal output times
    ``k * run.output_interval`` (a run samples at the first step at or after each of them,
    less than one time step later), so that all cases share one ``time`` coordinate: the
    longest run's; a run that ends sooner (in a sweep over wave frequency each run lasts the
    same number of its own periods) is NaN after its end. A run that stopped before its end
    (global attribute ``status`` other than ``completed``: it blew up, or reached
    ``run.max_steps``) is kept, NaN after its last sample, and its status is the variable
    ``case_status``: one case that blew up does not withhold the others, and the findings
    that need it past its end say so (:func:`sph.study.findings.compute_findings`). A run
    that says it completed but ends before its ``run.t_end`` is refused. The case parameters
    become coordinates along ``case`` (``opening``, ``side``, ``fill``, ``amplitude``,
    ``omega``), the per-run cost figures, wave period, damage time and resolved
    configurations variables along it, as are the ship's clearances to the absorbing zones
    (:func:`zone_clearance`), and the attributes that the runs share global attributes
    (:func:`one_wave` selects the cases of one wave).
    """
    import xarray as xr


    if len(paths) != len(cases):
        raise ValueError(f"{len(paths)} files for {len(cases)} cases")
    if not paths:
        raise ValueError("nothing to gather")
    sets = [read_dataset(path) for path in paths]
    statuses = [str(ds.attrs.get("status", "")) for ds in sets]
    configs = [yaml.safe_load(ds.attrs["config"]) for ds in sets]
    grids = [_nominal_times(cfg) for cfg in configs]
    grid = max(grids, key=len)
    parts = []
    for ds, case, own, status, cfg in zip(sets, cases, grids, statuses, configs,
                                          strict=True):
        t = ds["time"].values
        if not len(t):
            raise ValueError(f"case {case['case']!r} has no samples (status {status!r})")
        tol = 1e-6 * max(1.0, own[-1])
        if status == "completed" and t[-1] < own[-1] - tol:
            raise ValueError(f"case {case['case']!r} ends at t = {t[-1]:g} s, before its "
                             f"t_end = {own[-1]:g} s, although it says it completed")
        end = own[-1] if status == "completed" else float(t[-1])
        timed = [v for v in ds.data_vars if "time" in ds[v].dims]
        if len(t) > 1:
            out = ds[timed].interp(time=grid, kwargs={"fill_value": "extrapolate"})
        else:  # stopped at its first sample: that sample, NaN after it (masked below)
            out = ds[timed].reindex(time=grid, method="nearest")
        if grid[-1] > end + tol:  # a shorter run: nothing after its end
            out = out.where(xr.DataArray(grid <= end + tol, dims="time"))
        for v in timed:
            out[v].attrs = dict(ds[v].attrs)
        out["time"].attrs = dict(ds["time"].attrs)
        for name in CASE_SCALARS:
            if name in ds.attrs:
                out[name] = ds.attrs[name]  # int (steps, particles) or float
                out[name].attrs = cf_attrs(name)
        out["case_config"] = str(ds.attrs.get("config", ""))
        out["case_config"].attrs = cf_attrs("case_config")
        out["case_status"] = status
        out["case_status"].attrs = cf_attrs("case_status")
        clear = zone_clearance(cfg or {}, ds.attrs)
        for name, value in zip(("zone_clearance_back", "zone_clearance_head"), clear,
                               strict=True):
            out[name] = value
            out[name].attrs = cf_attrs(name)
        out.attrs = {}
        parts.append(out)
    ds = xr.concat(parts, dim="case", join="outer", coords="minimal", compat="override",
                   combine_attrs="drop_conflicts")
    ds = ds.assign_coords(
        case=("case", np.array([c["case"] for c in cases], dtype=object)),
        opening=("case", np.array([c["opening"] for c in cases], dtype=float)),
        side=("case", np.array([c["side"] for c in cases], dtype=object)),
        fill=("case", np.array([c["fill"] for c in cases], dtype=float)),
        amplitude=("case", np.array([c["amplitude"] for c in cases], dtype=float)),
        description=("case", np.array([c.get("description", "") for c in cases],
                                      dtype=object)),
        cargo_density=("case", np.array([float(s.attrs.get("cargo_density", math.nan))
                                         for s in sets])),
    )
    for name in ("case", "opening", "side", "fill", "amplitude", "description",
                 "cargo_density"):
        ds[name].attrs = cf_attrs(name)
    ds = ds.assign_coords({OMEGA_COLUMN: ("case", np.array(
        [c.get(OMEGA_COLUMN, DEFAULT_OMEGA) for c in cases], dtype=float))})
    ds[OMEGA_COLUMN].attrs = cf_attrs(OMEGA_COLUMN)
    source = f"sph-flood {__version__}"
    import datetime as _dt

    stamp = _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    glob = {"Conventions": "CF-1.10", "title": "sph-flood sweep dataset", "source": source,
            "history": f"{stamp}: gathered {len(cases)} runs by {source}"}
    for name in SHARED_ATTRS:
        values = {sets[0].attrs.get(name)} | {s.attrs.get(name) for s in sets[1:]}
        if len(values) == 1 and None not in values:
            glob[name] = sets[0].attrs[name]
    glob.update({k: v for k, v in (attrs or {}).items() if v is not None})
    ds.attrs = glob
    for s in sets:
        s.close()
    return ds


def one_wave(ds, cases: Sequence[str] = ()):
    """The cases ``cases`` of a sweep dataset (default: those at the first case's wave
    frequency), which must share one wave period, as a dataset of their own: the times
    after the last of them ends dropped, and their wave period, damage time and frequency
    as global attributes, as in a sweep at one wave frequency. The end is that of the runs
    that completed: a run that stopped early is NaN after its end (:func:`gather`)."""
    cases = list(cases)
    if not cases:
        cases = [str(c) for c in ds["case"].values]
        if OMEGA_COLUMN in ds.coords:
            first = float(ds[OMEGA_COLUMN].values[0])
            cases = [c for c, w in zip(cases, ds[OMEGA_COLUMN].values, strict=True)
                     if _close(float(w), first)]
    sub = ds.sel(case=cases)
    attrs = dict(ds.attrs)
    for name in ("wave_period", "damage_time"):
        if name not in sub.data_vars:
            continue
        values = np.unique(sub[name].values)
        if len(values) != 1:
            raise ValueError(f"cases {', '.join(cases)} have different {name}s "
                             f"{', '.join(f'{v:g}' for v in values)} s")
        attrs[name] = float(values[0])
    if "wave_period" in attrs:
        attrs["omega"] = 2.0 * math.pi / float(attrs["wave_period"])
    ran = np.zeros(sub.sizes["time"], dtype=bool)
    done = np.ones(sub.sizes["case"], dtype=bool)  # a run that stopped early sets no end
    if "case_status" in sub.data_vars:
        done = sub["case_status"].values == "completed"
    for name in ("roll", "heave", "sway"):
        if name in sub.data_vars and done.any():
            ran |= np.isfinite(sub[name].values[done]).all(axis=0)
    if ran.any() and not ran[-1]:
        sub = sub.isel(time=slice(0, int(np.nonzero(ran)[0][-1]) + 1))
    sub.attrs = attrs
    return sub


def write_case_table(cases: Sequence[Mapping], path: str | Path) -> None:
    """Write checked case rows as a TSV table (the sweep's resolved case table)."""
    lines = ["\t".join(CASE_COLUMNS)]
    for c in cases:
        lines.append("\t".join(f"{c[k]:.10g}" if isinstance(c[k], float) else
                               "" if c.get(k) is None else str(c[k]) for k in CASE_COLUMNS))
    Path(path).write_text("\n".join(lines) + "\n")
