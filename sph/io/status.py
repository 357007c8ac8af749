"""How far a run has got, read from its output file and its newest checkpoint without
running anything (``sph status``).

A long run (the refined Table I cases take hours to days) writes its partial output every
``run.flush_seconds`` of wall time and a checkpoint every ``run.checkpoint_wall_seconds``
(:mod:`sph.driver`, :mod:`sph.io.checkpoint`). Either may be the newer: the status takes
the simulated time, step and elapsed wall time from the newer of the two, and the run's
own word on how it ended (``status`` of the output: ``completed``, ``interrupted ...``,
``failed: ...``) from the output. A partial output says ``running`` while the run is going
and keeps saying it if the process was killed (or its machine went away); the age of the
newest file tells which, and the table says so where a run that has not ended has written
nothing for much longer than it writes (:meth:`RunStatus.silent`).
"""

from __future__ import annotations

import time
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from sph.io.checkpoint import checkpoint_dir, checkpoint_files, output_of


class StatusError(ValueError):
    """A path that is not a run's output."""


#: wall seconds of computing after which a run's average rate tells its time left (a run
#: stopped during its first step, one checkpoint of 36 s, gave 2900 hours)
AVERAGE_AFTER = 600.0
#: a run that has not ended and has written nothing for this many times its interval
#: between writes, and :data:`SILENT_GRACE` seconds more (a restarted run builds its
#: particles and loads its kernels before it writes), is reported as silent
SILENT_FACTOR = 3.0
SILENT_GRACE = 300.0


@dataclass(frozen=True)
class RunStatus:
    """Where one run stands.

    ``t`` and ``steps`` are the simulated time and step reached (0 for a run not started),
    ``t_end`` the case's ``run.t_end`` (None when neither file exists), ``wall_seconds``
    the wall time the run has spent computing over all its starts (for a run started from
    another run's checkpoint, that run's time to the checkpoint included), ``updated`` the
    modification time of the newer file (seconds since the epoch), ``recent_rate`` the
    simulated seconds per wall hour between the two newest checkpoints (a run keeps two;
    None with fewer), ``max_speed`` (m/s) and ``max_density`` (kg/m3) the largest of the
    run's samples so far (``max_velocity`` and ``density_max`` of its output; None where
    they are not recorded): a run leaving the physics shows there first. ``write_every``
    is the wall time between the run's writes while it runs (the shorter of
    ``run.flush_seconds`` and ``run.checkpoint_wall_seconds``; None if it writes on no
    wall-time schedule)."""

    output: Path
    case: str
    status: str
    t: float
    t_end: float | None
    steps: int
    wall_seconds: float
    updated: float | None
    source: str
    recent_rate: float | None = None
    max_speed: float | None = None
    max_density: float | None = None
    write_every: float | None = None

    @property
    def fraction(self) -> float | None:
        """The share of ``run.t_end`` simulated."""
        return self.t / self.t_end if self.t_end else None

    @property
    def rate(self) -> float | None:
        """Simulated seconds per wall hour, averaged over the run so far."""
        return 3600.0 * self.t / self.wall_seconds if self.wall_seconds > 0 else None

    @property
    def going(self) -> bool:
        """Whether the run has not ended: a partial output that says ``running``, or a
        checkpoint alone."""
        return self.status == "running" or self.status.startswith("started")

    def silent(self, now: float) -> float | None:
        """The seconds since the newest file of a run that has not ended, where that is
        longer than it can be while the run runs (:data:`SILENT_FACTOR` times
        ``write_every`` plus :data:`SILENT_GRACE`): its process was stopped or killed,
        its machine went away, or it waits in a workflow for a core. A run just started
        again reads so until its first write. None otherwise."""
        if not self.going or self.updated is None or not self.write_every:
            return None
        quiet = now - self.updated
        return quiet if quiet > SILENT_FACTOR * self.write_every + SILENT_GRACE else None

    @property
    def hours_left(self) -> float | None:
        """Wall hours to ``t_end`` at the recent rate (else the average one, once the run
        has computed for :data:`AVERAGE_AFTER` seconds: before that it is mostly the run's
        start, building and compiling), for a run that has not ended: a partial output that
        says ``running`` or a checkpoint alone."""
        rate = self.recent_rate or (self.rate if self.wall_seconds >= AVERAGE_AFTER else None)
        if not self.going or not rate or self.t_end is None:
            return None
        return max(0.0, self.t_end - self.t) / rate


def _largest(values) -> float | None:
    """The largest finite sample, None for none."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    return float(v.max()) if v.size else None


#: the samples :func:`_largest` reads, by field of :class:`RunStatus`: the output's
#: variable (a checkpoint holds it as ``record.series.<name>``)
HEALTH = {"max_speed": "max_velocity", "max_density": "density_max"}


def _run_keys(config_text: str) -> tuple[str, float | None, float | None]:
    """The case name, ``run.t_end`` (None if unset) and the wall seconds between writes
    (:attr:`RunStatus.write_every`) of a run's resolved configuration."""
    cfg = yaml.safe_load(config_text) or {}
    run = cfg.get("run", {})
    every = [float(run.get(k) or 0.0) for k in ("flush_seconds", "checkpoint_wall_seconds")]
    every = [e for e in every if e > 0.0]
    return (str(cfg.get("case", "?")), float(run.get("t_end", 0.0)) or None,
            min(every) if every else None)


def _from_output(path: Path) -> dict | None:
    import xarray as xr

    if not path.exists():
        return None
    if path.is_dir():
        raise StatusError(f"{path}: is a directory, not an output file")
    try:
        with xr.open_dataset(path, engine="netcdf4", decode_times=False) as ds:
            attrs = dict(ds.attrs)
            t = float(ds["time"].values[-1]) if "time" in ds and ds["time"].size else 0.0
            health = {k: _largest(ds[v].values) if v in ds else None
                      for k, v in HEALTH.items()}
    except (OSError, ValueError) as exc:
        raise StatusError(f"{path}: not a netCDF file ({str(exc).splitlines()[0]})") from None
    if "config" not in attrs or "status" not in attrs:
        raise StatusError(f"{path}: not an sph-flood output (no 'config' and 'status' "
                          f"attributes)")
    case, t_end, every = _run_keys(attrs["config"])
    return dict(case=str(attrs.get("case", case)), status=str(attrs["status"]), t=t,
                t_end=t_end, write_every=every, steps=int(attrs.get("steps", 0)),
                wall_seconds=float(attrs.get("wall_clock_seconds", 0.0)),
                updated=path.stat().st_mtime, **health)


def _from_checkpoints(directory: Path, most: int = 2) -> list[dict]:
    """The scalars of the ``most`` newest readable checkpoints, newest first (their
    checksums are not verified: that would read every particle; a run that resumes
    verifies its own)."""
    found = []
    for path in reversed(checkpoint_files(directory)):
        try:
            with np.load(path, allow_pickle=False) as a:
                case, t_end, every = _run_keys(str(a["config"]))
                health = {k: _largest(a[f"record.series.{v}"])
                          if f"record.series.{v}" in a.files else None
                          for k, v in HEALTH.items()}
                found.append(dict(case=case, t=float(a["t"]), t_end=t_end, write_every=every,
                                  steps=int(a["step"]), wall_seconds=float(a["wall_seconds"]),
                                  updated=path.stat().st_mtime, name=path.name, **health))
        except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile, yaml.YAMLError):
            continue
        if len(found) == most:
            break
    return found


def run_status(output: str | Path) -> RunStatus:
    """The status of the run writing ``output`` (its ``.nc`` path, which need not exist
    yet). Raises :class:`StatusError` for a path that is not a run's output."""
    output = Path(output)
    out = _from_output(output)
    ckpts = _from_checkpoints(checkpoint_dir(output))
    ckpt = ckpts[0] if ckpts else None
    recent = None
    if len(ckpts) == 2 and ckpts[0]["wall_seconds"] > ckpts[1]["wall_seconds"]:
        recent = 3600.0 * ((ckpts[0]["t"] - ckpts[1]["t"])
                           / (ckpts[0]["wall_seconds"] - ckpts[1]["wall_seconds"]))
    if out is None and ckpt is None:
        return RunStatus(output, "?", "not started", 0.0, None, 0, 0.0, None, "")
    if out is not None and out["status"] == "completed" and out["t_end"]:
        # the run stepped to t_end; its last sample is the last output time before it
        out["t"], newer, status = out["t_end"], out, out["status"]
    elif out is None:
        status, newer = "started (no output written yet)", ckpt
    elif ckpt is None or out["t"] >= ckpt["t"]:
        status, newer = out["status"], out
    else:  # the checkpoint is ahead of the last flush of the output
        status, newer = out["status"], ckpt
    source = f"checkpoint {ckpt['name']}" if newer is ckpt else "output"
    updated = max(d["updated"] for d in (out, ckpt) if d is not None)
    return RunStatus(output, newer["case"], status, newer["t"], newer["t_end"],
                     newer["steps"], newer["wall_seconds"], updated, source, recent,
                     newer["max_speed"], newer["max_density"], newer["write_every"])


def find_outputs(directory: str | Path) -> list[Path]:
    """The outputs of the runs in ``directory``: every ``*.nc`` and every ``*.nc.ckpt``
    checkpoint folder (as its output's path), sorted."""
    d = Path(directory)
    found = {p for p in d.glob("*.nc") if p.is_file()}
    found |= {output_of(p) for p in d.glob("*.nc.ckpt") if p.is_dir()}
    return sorted(found)


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    if seconds < 172800:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 86400:.1f} d"


def _age(seconds: float) -> str:
    return f"{_duration(seconds)} ago"


def _silence(r: RunStatus, now: float) -> str:
    quiet = r.silent(now)
    if quiet is None:
        return ""
    return (f"; not running: nothing written for {_duration(quiet)}, where it writes "
            f"every {r.write_every / 60:.3g} min while it runs (stopped, or waiting for a "
            "core in a workflow; `sph run` again resumes it)")


def summary(rows: list[RunStatus]) -> str:
    """One line on a set of runs (a sweep's folder): how many have completed, are under
    way, have not started or ended otherwise, and for those under way the wall hours left
    at their rates, the longest and summed: with a core each the last ends after the
    longest, on fewer cores after about the sum over their number."""
    done = sum(r.status == "completed" for r in rows)
    going = [r for r in rows if r.going]
    idle = sum(r.status == "not started" for r in rows)
    other = len(rows) - done - len(going) - idle
    parts = [f"{len(rows)} run{'' if len(rows) == 1 else 's'}: {done} completed",
             f"{len(going)} under way"]
    left = [r.hours_left for r in going if r.hours_left is not None]
    if left:
        known = "" if len(left) == len(going) else f" for {len(left)} of them"
        parts[-1] += (f" ({max(left):.1f} h left at the longest, {sum(left):.1f} h summed"
                      f"{known}, at their rates)")
    parts.append(f"{idle} not started")
    if other:
        parts.append(f"{other} ended otherwise (stopped, blew up or failed: the table says)")
    return ", ".join(parts)


def format_table(rows: list[RunStatus], now: float | None = None) -> str:
    """A plain-text table, one line per run."""
    now = time.time() if now is None else now
    head = ("output", "case", "t (s)", "t_end (s)", "done", "steps", "wall (h)",
            "sim s / wall h", "recent", "left (h)", "max speed (m/s)", "max density (kg/m3)",
            "updated", "status")
    lines = [head]
    for r in rows:
        lines.append((
            str(r.output), r.case, f"{r.t:.2f}",
            "-" if r.t_end is None else f"{r.t_end:.2f}",
            "-" if r.fraction is None else f"{100 * r.fraction:.1f} %",
            str(r.steps), f"{r.wall_seconds / 3600:.2f}",
            "-" if r.rate is None else f"{r.rate:.3g}",
            "-" if r.recent_rate is None else f"{r.recent_rate:.3g}",
            "-" if r.hours_left is None else f"{r.hours_left:.1f}",
            "-" if r.max_speed is None else f"{r.max_speed:.3g}",
            "-" if r.max_density is None else f"{r.max_density:.5g}",
            "-" if r.updated is None else _age(max(0.0, now - r.updated)),
            r.status + (f" ({r.source})" if r.source.startswith("checkpoint") else "")
            + _silence(r, now),
        ))
    widths = [max(len(line[k]) for line in lines) for k in range(len(head) - 1)]
    return "\n".join(
        "  ".join([c.ljust(w) for c, w in zip(line[:-1], widths, strict=True)] + [line[-1]])
        for line in lines)
