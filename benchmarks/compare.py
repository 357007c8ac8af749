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

Where both sides can run step by step (:mod:`step_server`), :func:`lockstep` goes further:
two child processes, started once, take turns a block of steps at a time (a fraction of a
second each), so that a switch of the machine's level falls on both sides alike; the ratio
is then that of the summed times, with the median of the per-block ratios beside it.
"""

from __future__ import annotations

import argparse
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


def _child_env(root: Path) -> dict:
    """The environment of a child process with ``root`` first on the path."""
    env = dict(os.environ, PYTHONPATH=str(root))
    env.setdefault("SPH_VALIDATION_DATA", str(ROOT / "data" / "validation"))
    return env


def run_child(script: Path, args: list[str], root: Path = ROOT) -> dict:
    """Run ``python script args`` with ``root`` first on the path; its last line, as JSON."""
    out = subprocess.run([sys.executable, str(script), *args], cwd=root, env=_child_env(root),
                         capture_output=True, text=True)
    lines = out.stdout.strip().splitlines()
    if out.returncode or not lines:
        raise RuntimeError(f"{script} {' '.join(args)} failed:\n{out.stderr[-2000:]}")
    return json.loads(lines[-1])


def _serve(script: Path, args: list[str], root: Path) -> subprocess.Popen:
    child = subprocess.Popen([sys.executable, str(script), *args], cwd=root,
                             env=_child_env(root),
                             stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    line = child.stdout.readline()
    if not line.startswith("ready"):
        child.kill()
        raise RuntimeError(f"{script} under {root} did not start: {line!r}")
    return child


def lockstep(script: Path, args: list[str], root: Path, reference_root: Path,
             blocks: int) -> dict:
    """Run ``script args`` (a step server: prints ``ready``, then the seconds of one block
    per input line) twice, with ``root`` and with ``reference_root`` first on the path, and
    let them take turns for ``blocks`` blocks each, in the order own, reference, reference,
    own, ... (so that a steady drift favours neither). Returns the ratio of the reference's
    summed time to this tree's (a speed-up), the median per-block ratio and both lists of
    block times."""
    own, ref = _serve(script, args, root), _serve(script, args, reference_root)
    times: dict[int, list[float]] = {id(own): [], id(ref): []}
    try:
        for k in range(blocks):
            for child in ((own, ref) if k % 2 == 0 else (ref, own)):
                child.stdin.write("\n")
                child.stdin.flush()
                times[id(child)].append(float(child.stdout.readline()))
    finally:
        for child in (own, ref):
            child.stdin.close()
            child.wait()
    mine, theirs = times[id(own)], times[id(ref)]
    return {"ratio": round(sum(theirs) / sum(mine), 3),
            "median_ratio": round(statistics.median(b / a for a, b in
                                                    zip(mine, theirs, strict=True)), 3),
            "seconds": mine, "reference_seconds": theirs}


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


def run_report_main(doc: str, run, report, run_args) -> None:
    """The command line of a benchmark that runs cases into a folder and compares them:
    ``run --out DIR [options]`` calls ``run(args)``, ``report DIR`` calls ``report(args)``;
    ``run_args(parser)`` adds the run's own options. ``doc``: the module docstring."""
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("--out", required=True)
    run_args(r)
    r.set_defaults(fn=run)
    p = sub.add_parser("report")
    p.add_argument("dir")
    p.set_defaults(fn=report)
    args = ap.parse_args()
    args.fn(args)
