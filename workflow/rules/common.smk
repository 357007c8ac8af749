# Configuration, paths and helpers shared by the rules.
#
# The sweep configuration is checked here, before any job: first by sph.study.sweeps (every key,
# with messages that name the key and the allowed range), then by the schemas in
# config/schema/ (snakemake's validate), and finally every run's case file is built by the
# engine's own configuration checks (an opening above the waterline, a dx too coarse for the
# opening, a cargo heavier than the displacement, ...).

from pathlib import Path
import re

import pandas as pd
from snakemake.exceptions import WorkflowError
from snakemake.utils import validate

from sph.study import sweeps as study
from sph.study.response import varies_omega
from sph.study.analysis import validation_data_dir
from sph.study.validation import TARGETS
from sph.schema import ConfigError

try:
    SWEEP_CFG = study.load_sweep(config)
except ConfigError as exc:
    raise WorkflowError(f"invalid sweep configuration: {exc}") from None

validate(config, "../../config/schema/config.schema.yaml")
validate(SWEEP_CFG["presets"], "../../config/schema/presets.schema.yaml")
validate(pd.DataFrame(SWEEP_CFG["cases"]), "../../config/schema/cases_checked.schema.yaml")

SWEEP = SWEEP_CFG["sweep"]
PRESET = config["preset"]
CASES = {c["case"]: c for c in SWEEP_CFG["cases"]}
GROUPS = study.groups(SWEEP_CFG["cases"], SWEEP_CFG["reference"])
DATA_DIR = (
    Path(config["validation_data"])
    if config.get("validation_data")
    else validation_data_dir()
)
SHIP_OVERRIDES = {cid: study.ship_overrides(c, SWEEP_CFG) for cid, c in CASES.items()}
# the runs to t1 that the cases differing in the opening alone share (sph.study.sweeps)
try:
    PREDAMAGE = study.predamage_runs(SHIP_OVERRIDES)
except ConfigError as exc:
    raise WorkflowError(f"invalid sweep configuration: {exc}") from None
PREDAMAGE_OF = {cid: run for run, group in PREDAMAGE.items() for cid in group["cases"]}
VALIDATION = study.validation_runs(SWEEP_CFG, DATA_DIR)


try:
    # every run's case file built with the engine's checks (sph.study.sweeps.check_documents)
    # with the digest of each run's whole configuration (the built-in case's defaults filled
    # in): a rule parameter, so that a changed default reruns the runs it changes
    DIGESTS = study.check_documents(SHIP_OVERRIDES, VALIDATION)
except ConfigError as exc:
    raise WorkflowError(f"invalid sweep configuration: {exc}") from None

if "floating_box" in VALIDATION and not (DATA_DIR / "hadzic2005").is_dir():
    raise WorkflowError(
        f"validation_data: no hadzic2005/ in {str(DATA_DIR)!r}; set validation_data "
        "to the folder of the experimental series or drop floating_box from validation"
    )


wildcard_constraints:
    sweep=re.escape(SWEEP),
    case="|".join(re.escape(c) for c in CASES),
    preset=re.escape(PRESET),
    target="|".join(re.escape(t) for t in TARGETS),
    run="[A-Za-z0-9][A-Za-z0-9_-]*",
    figure="fig[0-9a-z_]+",
    predamage="|".join(re.escape(r) for r in PREDAMAGE) or "(?!x)x",


# The paper's figures drawn from a sweep dataset: name -> (group of cases, series).
# Series are dataset variables or body-fixed probes (W1: cargo cabin, W2: damaged cabin).
SHIP_FIGURES = {
    "fig10_amplitude": ("amplitude", ["roll", "heave", "flood_ratio"]),
    "fig12_w2_opening": ("opening", ["W2"]),
    "fig13_flood_opening": ("opening", ["flood_ratio"]),
    "fig14_heave_opening": ("opening", ["heave"]),
    "fig15_roll_opening": ("opening", ["roll"]),
    "fig17_flood_side": ("side", ["flood_ratio"]),
    "fig18_roll_side": ("side", ["roll"]),
    "fig19_heave_side": ("side", ["heave"]),
    "fig21_roll_fill": ("fill", ["roll"]),
    "fig22_probes_fill": ("fill", ["W1", "W2"]),
    "fig23_flood_fill": ("fill", ["flood_ratio"]),
}
# Validation figures, from the table of targets (sph.study.validation.TARGETS): file name ->
# (target whose runs it draws, script in workflow/scripts/).
VALIDATION_FIGURES = {
    name: (target.id, script)
    for target in TARGETS.values()
    for name, script in target.figures
}


def sweep_dir():
    return f"results/{SWEEP}"


def case_path(case, ext):
    return f"results/{SWEEP}/cases/{case}.{ext}"


def validation_dir():
    return f"results/validation/{PRESET}"


def validation_nc(target):
    """The runs of a validation target (none when the sweep does not validate it)."""
    return [f"{validation_dir()}/{target}/{run}.nc" for run in VALIDATION.get(target, {})]


def ship_figures():
    """The figures whose group of cases is in this sweep."""
    return [name for name, (group, _) in SHIP_FIGURES.items() if group in GROUPS]


def rao_outputs():
    """The response over wave frequency (figure and table), for a sweep that runs the ship
    at two or more wave frequencies."""
    if not varies_omega(SWEEP_CFG["cases"]):
        return []
    return [f"{sweep_dir()}/figures/rao.png", f"{sweep_dir()}/rao.csv"]


def validation_figures():
    return [name for name, (target, _) in VALIDATION_FIGURES.items() if target in VALIDATION]


def ship_document(wildcards):
    return study.case_document("damaged_ship", SHIP_OVERRIDES[wildcards.case])


def ship_digest(wildcards):
    return DIGESTS["ship"][wildcards.case]


#: The waves of the sweep's ship runs that get a wavemaker calibration: wave name -> the
#: first case with that wave (sph.study.sweeps.wave_key; none in still water or with
#: calibrate_wavemaker: false).
CALIBRATED_WAVES = {}
if SWEEP_CFG["calibrate_wavemaker"]:
    for cid, over in SHIP_OVERRIDES.items():
        key = study.wave_key(over)
        if key is not None:
            CALIBRATED_WAVES.setdefault(key, cid)


def calibration_document(wildcards):
    """The ship case file whose wave the calibration measures."""
    return study.case_document("damaged_ship",
                               SHIP_OVERRIDES[CALIBRATED_WAVES[wildcards.wave]])


def calibration_digest(wildcards):
    return DIGESTS["ship"][CALIBRATED_WAVES[wildcards.wave]]


def _calibration(sweep, overrides):
    key = study.wave_key(overrides)
    if key is None or key not in CALIBRATED_WAVES:
        return []
    return [f"results/{sweep}/calibration/{key}.json"]


def calibration_of(wildcards):
    """The calibration a ship case file takes its flap angle from ([] if none)."""
    return _calibration(wildcards.sweep, SHIP_OVERRIDES[wildcards.case])


def predamage_path(run, ext):
    return f"results/{SWEEP}/predamage/{run}.{ext}"


def predamage_document(wildcards):
    return study.case_document("damaged_ship", PREDAMAGE[wildcards.predamage]["overrides"])


def predamage_digest(wildcards):
    return PREDAMAGE[wildcards.predamage]["digest"]


def predamage_calibration(wildcards):
    return _calibration(wildcards.sweep, PREDAMAGE[wildcards.predamage]["overrides"])


def predamage_of(wildcards):
    """The shared run to t1 a ship case starts from ([] if none)."""
    run = PREDAMAGE_OF.get(wildcards.case)
    return [] if run is None else [predamage_path(run, "nc")]


def start_option(wildcards):
    """``sph run``'s option to start from the checkpoint of the shared run to t1 (none
    without one; the run then starts from t = 0, as it also does when that checkpoint has
    been deleted)."""
    run = PREDAMAGE_OF.get(wildcards.case)
    if run is None:
        return ""
    ckpt = predamage_path(run, "nc.ckpt")
    return f"$( [ -d '{ckpt}' ] && echo --start-from '{ckpt}' )"


def validation_document(wildcards):
    case, over = VALIDATION[wildcards.target][wildcards.run]
    return study.case_document(case, over)


def validation_digest(wildcards):
    return DIGESTS["validation"][f"{wildcards.target}/{wildcards.run}"]


#: The order in which the engine runs start, longest first, so that the last minutes of a
#: sweep are not one long run alone on one core: the ship cases (each about as long as all
#: validation runs together at the coarse preset), then the validation targets by their
#: measured cost at coarse (floating box 305 s, wave tank 21-208 s with the finest spacing
#: last in the list, decay 79-88 s, dam break 44 s, sloshing 8-18 s; docs/performance.md).
SHIP_PRIORITY = 10
VALIDATION_PRIORITY = {"floating_box": 5, "wave_tank": 4, "decay": 3, "dam_break": 2,
                       "sloshing": 1, "cylinder": 4}


def validation_priority(wildcards):
    """Priority of a validation run: its target's, the later runs of a target (finer
    spacings) slightly ahead."""
    runs = list(VALIDATION[wildcards.target])
    rank = runs.index(wildcards.run) / len(runs)
    return VALIDATION_PRIORITY.get(wildcards.target, 0) + rank


def sweep_attrs():
    """Global attributes of the sweep dataset: the sweep's configuration."""
    import yaml

    keep = {k: config.get(k) for k in ("sweep", "title", "preset", "set", "t2_periods")}
    return dict(
        sweep=SWEEP,
        title=SWEEP_CFG["title"],
        preset=PRESET,
        preset_description=SWEEP_CFG["preset_settings"].get("description", ""),
        t2_periods=SWEEP_CFG["t2_periods"],
        sweep_config=yaml.safe_dump(
            dict(keep, cases=SWEEP_CFG["cases"], preset_settings=SWEEP_CFG["preset_settings"]),
            sort_keys=False,
        ),
    )


def all_targets():
    out = []
    if CASES:  # a sweep of validation targets only has none (cases: [])
        out += [
            f"{sweep_dir()}/{SWEEP}.nc",
            f"{sweep_dir()}/findings.html",
            f"{sweep_dir()}/findings.csv",
        ]
        out += [f"{sweep_dir()}/figures/{name}.png" for name in ship_figures()]
        out += [f"{sweep_dir()}/figures/overview.png"]
        out += rao_outputs()
    if VALIDATION:
        out += [f"{validation_dir()}/validation.html"]
        out += [f"{validation_dir()}/figures/{name}.png" for name in validation_figures()]
    return out
