"""Checkpoints: the complete state of a run in one file, so that a killed run resumes.

A checkpoint is a numpy ``.npz`` archive ``step-NNNNNNNNNN.npz`` (the step number, ten
digits) in the checkpoint directory of an output file, ``OUT.nc.ckpt/`` next to ``OUT.nc``
(:func:`checkpoint_dir`). It holds numpy arrays only (it is read with
``allow_pickle=False``, so loading one never runs code):

================================  ==========================================================
``format``, ``version``           checkpoint format number, package version that wrote it
``config``                        the resolved case configuration as YAML text
``particles.f``, ``particles.i``  every particle field (:mod:`sph.engine.particles`), in the sorted
                                  order of the last evaluation, with the time derivatives
                                  of that evaluation (``ax, az, drho``) and both leapfrog
                                  levels
``kin``                           the kinematics of every wall group as used by the last
                                  evaluation (rigid-body accelerations included)
``t``, ``step``, ``dt``           time, step number (also the MLS/Euler step counter), last
                                  time step
``next_output`` ... ``wall_s``    the output, snapshot and checkpoint schedule, elapsed wall
                                  time, the one-off warnings already given
``record.*``                      the time series sampled so far
``stateful.K.*``                  ``get_state()`` of each stateful object (rigid bodies,
                                  the damage opening)
``sha256``                        SHA-256 of everything above
================================  ==========================================================

A file is written under a temporary name, flushed to disk and renamed (atomic on POSIX);
after that the older files beyond the newest ``keep`` are deleted. A checkpoint that
cannot be read, fails its checksum or is of another format is skipped with a logged
message and the previous one is used (:func:`find_checkpoint`).

Resuming restores every array bit for bit and does not re-evaluate the derivatives: the
next step continues exactly where the interrupted run was, so that a resumed run produces
the same numbers as an uninterrupted one (``docs/checkpoints.md``).
"""

from __future__ import annotations

import hashlib
import logging
import os
import re
import zipfile
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from sph import __version__
from sph.engine.stepper import StateMismatch
from sph.io.atomic import write_atomic
from sph.schema import ConfigError

log = logging.getLogger(__name__)

FORMAT_VERSION = 1
_NAME = re.compile(r"^step-(\d{10})\.npz$")
_TMP = re.compile(r"^\.step-\d{10}\.npz\.tmp-\d+$")

#: config keys that may differ between a checkpoint and the run that resumes it: they say
#: how long to run, what to write and when to call a run blown up, not what is computed
#: (the results do not depend on the thread count)
RESUMABLE_KEYS = frozenset({
    "title", "numerics.threads", "run.t_end", "run.max_steps", "run.flush_seconds",
    "run.vtk_interval", "run.checkpoint_interval", "run.checkpoint_wall_seconds",
    "run.keep_checkpoints", "run.check_interval", "run.density_min", "run.density_max",
    "run.max_lost_fraction",
})

#: config keys in which a run may differ from the run whose checkpoint it starts from
#: (:func:`start_from`, ``sph run --start-from``): the damage opening, which does nothing
#: before t1
SEED_KEYS = ("geometry.damage.",)


class CheckpointError(RuntimeError):
    """A checkpoint file that cannot be used (unreadable, truncated, corrupt, or of another
    format); the message names the file."""


class CheckpointMismatch(ConfigError):
    """A checkpoint written for another configuration; ``keys`` lists the differing keys."""

    def __init__(self, directory: Path, differences: list[tuple[str, Any, Any]],
                 seed: bool = False):
        self.keys = [k for k, _, _ in differences]
        shown = "; ".join(f"{k} = {_short(old)} there, {_short(new)} here"
                          for k, old, new in differences[:8])
        more = f" (and {len(differences) - 8} more)" if len(differences) > 8 else ""
        advice = ("a run starts from another's checkpoint only if they differ in "
                  f"{', '.join(k + '*' for k in SEED_KEYS)} alone" if seed else
                  "start over with --restart (or delete that directory), or restore these "
                  "values")
        super().__init__(", ".join(self.keys), f"the checkpoint in {str(directory)!r} was "
                         f"written for another configuration: {shown}{more}; {advice}")


def _short(value) -> str:
    text = "(absent)" if value is _ABSENT else repr(value)
    return text if len(text) <= 60 else text[:56] + " ..."


_ABSENT = object()


# --------------------------------------------------------------------------- paths


def checkpoint_dir(out_path: str | os.PathLike[str]) -> Path:
    """The checkpoint directory of an output file: ``OUT.nc`` -> ``OUT.nc.ckpt``."""
    out = Path(out_path)
    return out.with_name(out.name + ".ckpt")


def output_of(directory: str | os.PathLike[str]) -> Path:
    """The output file of a checkpoint directory: ``OUT.nc.ckpt`` -> ``OUT.nc``
    (the inverse of :func:`checkpoint_dir`)."""
    d = Path(directory)
    return d.with_name(d.name.removesuffix(".ckpt"))


def checkpoint_files(directory: str | os.PathLike[str]) -> list[Path]:
    """The checkpoint files in ``directory``, oldest (lowest step) first."""
    d = Path(directory)
    if not d.is_dir():
        return []
    found = [(int(m.group(1)), p) for p in d.iterdir() if (m := _NAME.match(p.name))]
    return [p for _, p in sorted(found)]


def remove_checkpoints(directory: str | os.PathLike[str]) -> None:
    """Delete the checkpoints (and stale temporary files) in ``directory``, then the
    directory itself if nothing else is left in it."""
    d = Path(directory)
    if not d.is_dir():
        return
    for p in d.iterdir():
        if _NAME.match(p.name) or _TMP.match(p.name):
            p.unlink(missing_ok=True)
    try:
        d.rmdir()
    except OSError:
        log.warning("checkpoint directory %s holds other files; left in place", d)


# --------------------------------------------------------------------------- writing


def _payload(sim) -> dict[str, np.ndarray]:
    """Every array a checkpoint holds, except its checksum: the format, the version and
    the configuration, then the run's state (:meth:`sph.driver.Simulation.get_state`)."""
    out: dict[str, np.ndarray] = {
        "format": np.array(FORMAT_VERSION),
        "version": np.array(__version__),
        "config": np.array(sim.cfg.to_yaml()),
    }
    out.update(sim.get_state())
    return out


def _digest(arrays: dict[str, np.ndarray]) -> str:
    h = hashlib.sha256()
    for name in sorted(arrays):
        if name == "sha256":
            continue
        a = np.ascontiguousarray(arrays[name])
        h.update(f"{name}|{a.dtype.str}|{a.shape}|".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def write_checkpoint(sim, directory: str | os.PathLike[str], keep: int = 2) -> Path:
    """Write the state of ``sim`` to ``directory/step-NNNNNNNNNN.npz`` atomically and keep
    only the newest ``keep`` checkpoints.

    Call it between steps (the derivatives of the current state must be up to date, as
    they are after :meth:`sph.driver.Simulation.advance`).

    Raises
    ------
    sph.io.atomic.OutputWriteError
        When the file cannot be written (unwritable directory, disk full); the previous
        checkpoints are left as they were.
    """
    d = Path(directory)
    path = d / f"step-{sim.step:010d}.npz"
    arrays = _payload(sim)
    arrays["sha256"] = np.array(_digest(arrays))

    def write(tmp: Path) -> None:
        with open(tmp, "wb") as fh:
            np.savez(fh, **arrays)

    write_atomic(path, write, "checkpoint")
    for old in checkpoint_files(d)[:-keep] if keep > 0 else []:
        old.unlink(missing_ok=True)
    log.debug("checkpoint at t = %.6g s (step %d): %s", sim.t, sim.step, path)
    return path


# --------------------------------------------------------------------------- reading


def load_checkpoint(path: str | os.PathLike[str]) -> dict[str, np.ndarray]:
    """Read and verify one checkpoint file.

    Raises
    ------
    CheckpointError
        If the file cannot be read (truncated, not an archive), its checksum does not
        match (corrupt), or it is of another format version. The message names the file.
    """
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as z:
            arrays = {k: z[k] for k in z.files}
    except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile,
            zipfile.LargeZipFile) as exc:
        raise CheckpointError(f"checkpoint {str(path)!r} cannot be read (truncated or "
                              f"corrupt?): {exc}") from exc
    if "sha256" not in arrays or "format" not in arrays:
        raise CheckpointError(f"checkpoint {str(path)!r} is incomplete: no checksum")
    if str(arrays["sha256"]) != _digest(arrays):
        raise CheckpointError(f"checkpoint {str(path)!r} is corrupt: checksum mismatch")
    if int(arrays["format"]) != FORMAT_VERSION:
        raise CheckpointError(f"checkpoint {str(path)!r} has format {int(arrays['format'])}; "
                              f"this version of sph-flood reads format {FORMAT_VERSION}")
    return arrays


def find_checkpoint(directory: str | os.PathLike[str]):
    """The newest valid checkpoint in ``directory`` as ``(path, arrays)``, or None.

    Files that fail :func:`load_checkpoint` are skipped with a warning naming them and the
    reason; the next older one is tried."""
    for path in reversed(checkpoint_files(directory)):
        try:
            return path, load_checkpoint(path)
        except CheckpointError as exc:
            log.warning("skipping %s", exc)
    return None


def _flatten(node, prefix: str = "") -> dict[str, Any]:
    if isinstance(node, dict):
        out: dict[str, Any] = {}
        for k, v in node.items():
            out.update(_flatten(v, f"{prefix}.{k}" if prefix else str(k)))
        return out
    return {prefix: node}


def config_differences(stored_yaml: str, cfg) -> list[tuple[str, Any, Any]]:
    """Keys whose values differ between a stored config (YAML text) and ``cfg``, as
    ``(key, stored value, current value)``; the :data:`RESUMABLE_KEYS` are ignored."""
    old = _flatten(yaml.safe_load(stored_yaml))
    new = _flatten(cfg.to_dict())
    diffs = []
    for key in sorted(set(old) | set(new)):
        if key in RESUMABLE_KEYS:
            continue
        a, b = old.get(key, _ABSENT), new.get(key, _ABSENT)
        if a != b:
            diffs.append((key, a, b))
    return diffs


def restore(sim, arrays: dict[str, np.ndarray], source: str | os.PathLike[str] = "",
            seed: bool = False) -> None:
    """Put the state of a checkpoint into a freshly built :class:`~sph.driver.Simulation`.

    ``seed``: the checkpoint is another run's, whose configuration may differ from this
    one's in the :data:`SEED_KEYS` (the damage opening), taken before the opening of
    either appeared (:meth:`sph.engine.stepper.Stepper.set_state`): this run continues
    from it as from t = 0, to the bit, its output holding the samples before it.

    Raises
    ------
    CheckpointMismatch
        If the checkpoint was written for another configuration.
    CheckpointError
        If its content does not fit this simulation (other particle fields or objects;
        with ``seed``, taken after an opening appeared).
    """
    where = Path(source).parent if source else Path(".")
    stored = str(arrays["config"])
    diffs = [d for d in config_differences(stored, sim.cfg)
             if not (seed and d[0].startswith(SEED_KEYS))]
    if diffs:
        raise CheckpointMismatch(where, diffs, seed)
    if str(arrays["version"]) != __version__:
        log.warning("checkpoint %s was written by sph-flood %s, this is %s: the resumed run "
                    "may differ from an uninterrupted one", source, arrays["version"],
                    __version__)
    try:
        sim.set_state(arrays, seed=seed)
    except (StateMismatch, KeyError) as exc:
        raise CheckpointError(f"checkpoint {str(source)!r} does not fit this case: {exc}"
                              ) from exc
    interval = sim.cfg.run.checkpoint_interval
    old_interval = (yaml.safe_load(stored).get("run") or {}).get("checkpoint_interval", 0.0)
    if interval != old_interval:  # a new checkpoint schedule from now on
        sim.next_checkpoint = sim.t + interval
    sim.restored_from = Path(source) if source else None


# --------------------------------------------------------------------------- start or resume


class NoCheckpoint(ConfigError):
    """``mode="resume"`` found nothing to resume."""


def start_from(sim, source: str | os.PathLike[str]) -> Path:
    """Start ``sim`` from another run's checkpoint ``source`` (a checkpoint file, or a
    checkpoint directory: its newest valid checkpoint), as :func:`restore` with ``seed``.

    Returns the checkpoint file. Raises :class:`NoCheckpoint` when there is none, and
    :class:`CheckpointError` (unreadable, or not fitting this case) or
    :class:`CheckpointMismatch` as :func:`restore`."""
    path, arrays = read_source(source, "to start from")
    restore(sim, arrays, path, seed=True)
    return path


def read_source(source: str | os.PathLike[str], purpose: str = "") -> tuple[Path, dict]:
    """The checkpoint ``source`` names, as ``(path, arrays)``: the file itself, or the
    newest valid checkpoint of a checkpoint directory.

    Raises :class:`NoCheckpoint` when there is none (the message says what it was looked
    for: ``purpose``, e.g. ``"to start from"``) and :class:`CheckpointError` when the file
    named cannot be read."""
    src = Path(source)
    what = f"checkpoint {purpose}".strip()
    if src.is_dir():
        found = find_checkpoint(src)
        if found is None:
            raise NoCheckpoint("", f"no valid {what} in {str(src)!r}")
        return found
    if src.is_file():
        return src, load_checkpoint(src)
    raise NoCheckpoint("", f"no {what} at {str(src)!r}")


def resume_or_start(sim, directory: str | os.PathLike[str], mode: str = "auto"):
    """Prepare ``sim`` to run with checkpoints in ``directory``.

    Parameters
    ----------
    mode : {"auto", "restart", "resume"}
        ``auto``: resume from the newest valid checkpoint if there is one, else start
        from t = 0. ``restart``: delete the checkpoints there and start from t = 0.
        ``resume``: resume, and raise :class:`NoCheckpoint` if there is no valid
        checkpoint.

    Returns
    -------
    pathlib.Path or None
        The checkpoint resumed from, or None for a fresh start.

    Raises
    ------
    CheckpointMismatch
        If the newest valid checkpoint was written for another configuration.
    """
    d = Path(directory)
    if mode not in ("auto", "restart", "resume"):
        raise ValueError(f"mode must be auto, restart or resume; got {mode!r}")
    if mode == "restart":
        if checkpoint_files(d):
            log.info("--restart: deleting the checkpoints in %s", d)
        remove_checkpoints(d)
        return None
    for p in d.iterdir() if d.is_dir() else []:  # left by a writer that was killed
        if _TMP.match(p.name):
            p.unlink(missing_ok=True)
    found = find_checkpoint(d)
    if found is None:
        if mode == "resume":
            what = "no valid checkpoint" if checkpoint_files(d) else "no checkpoint"
            raise NoCheckpoint("", f"{what} to resume from in {str(d)!r}")
        if checkpoint_files(d):
            log.warning("no valid checkpoint in %s: starting from t = 0", d)
        return None
    path, arrays = found
    restore(sim, arrays, path)
    return path
