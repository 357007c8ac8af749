"""Run a benchmark in child processes, interleaved with a reference run, and compare.

The speed of the 2-core hosts this project is measured on drifts by tens of percent between
hours, and even between seconds: a pair loop's rate switches between two levels about 1.6
times apart within one process, with no other load, whatever the thread count, threading
layer or core it is pinned to, and the machine yardstick (:mod:`yardstick`, a bare numba
pair loop) switches with it, while loops that stay in the first-level cache do not. A rate is
therefore only meaningful beside a reference taken minutes, better seconds, apart: the
benchmarks alternate their own run with the reference's (the yardstick, or the same
benchmark at another commit of this repository, checked out in a git worktree under
``.bench/``), one child process each, and report the ratio of the best rates (each side's
fast level), with the medians and the per-round ratios beside it.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def worktree(commit: str) -> Path:
    """A checkout of ``commit`` of this repository under ``.bench/`` (made once)."""
    path = ROOT / ".bench" / commit
    if not (path / "benchmarks").is_dir():
        path.parent.mkdir(exist_ok=True)
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--force", "--detach",
                        str(path), commit], check=True, capture_output=True)
    return path


def run_child(script: Path, args: list[str], root: Path = ROOT) -> dict:
    """Run ``python script args`` with ``root`` first on the path; its last line, as JSON."""
    env = dict(os.environ, PYTHONPATH=str(root))
    env.setdefault("SPH_VALIDATION_DATA", str(ROOT / "data" / "validation"))
    out = subprocess.run([sys.executable, str(script), *args], cwd=root, env=env,
                         capture_output=True, text=True)
    lines = out.stdout.strip().splitlines()
    if out.returncode or not lines:
        raise RuntimeError(f"{script} {' '.join(args)} failed:\n{out.stderr[-2000:]}")
    return json.loads(lines[-1])


def interleave(rounds: int, own, reference) -> tuple[list[float], list[float]]:
    """Call ``own()`` and ``reference()`` alternately ``rounds`` times (each returns a rate);
    return both lists of rates."""
    mine, ref = [], []
    for _ in range(rounds):
        ref.append(reference())
        mine.append(own())
    return mine, ref


def summary(mine: list[float], ref: list[float]) -> dict:
    """The best rate of each (the machine's fast level, which both reach in a few rounds)
    and their ratio; the medians and the per-round ratios beside them."""
    ratios = [a / b for a, b in zip(mine, ref, strict=True)]
    return {"rate": max(mine), "reference_rate": max(ref),
            "ratio": round(max(mine) / max(ref), 3),
            "median_rate": statistics.median(mine),
            "median_reference_rate": statistics.median(ref),
            "median_ratio": round(statistics.median(ratios), 3),
            "ratios": [round(r, 3) for r in ratios]}
