"""The repository is self-contained: a copy of its files alone plans every sweep.

The copy holds the files of HEAD plus the working tree's changes (``git ls-files -co
--exclude-standard``: tracked files as they are on disk and untracked files that git does not
ignore, so uncommitted changes are tested too) in a folder with no siblings, so that a path
that leaves the repository (a sibling folder of the checkout, say) finds nothing. Snakemake
then plans (``-n``) the default sweep and every sweep of ``config/sweeps/`` there, importing
the ``sph`` package of the copy, with ``SPH_VALIDATION_DATA`` unset.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _git(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(["git", *args], cwd=ROOT, capture_output=True, text=True)


def _in_git_checkout() -> bool:
    if shutil.which("git") is None:
        return False
    top = _git("rev-parse", "--show-toplevel")
    return top.returncode == 0 and Path(top.stdout.strip()).resolve() == ROOT


needs_git = pytest.mark.skipif(not _in_git_checkout(),
                               reason="not in a git checkout of the repository")


@pytest.fixture(scope="module")
def clone(tmp_path_factory) -> Path:
    """The repository's files, copied into ``<fresh folder>/clone``."""
    listed = _git("ls-files", "-z", "-co", "--exclude-standard")
    assert listed.returncode == 0, listed.stderr
    dest = tmp_path_factory.mktemp("isolated") / "clone"
    dest.mkdir()
    for name in listed.stdout.split("\0"):
        src = ROOT / name
        if not name or not src.is_file():  # a tracked file deleted in the working tree
            continue
        (dest / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(src, dest / name)
    return dest


def _env(clone: Path) -> dict:
    env = {k: v for k, v in os.environ.items() if k != "SPH_VALIDATION_DATA"}
    env["PYTHONPATH"] = str(clone)  # the copy's sph package, not the installed one
    env["NUMBA_NUM_THREADS"] = env.get("NUMBA_NUM_THREADS", "2")
    return env


def _run(clone: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, *args], cwd=clone, env=_env(clone),
                          capture_output=True, text=True, timeout=300)


@needs_git
def test_the_copy_imports_its_own_package_and_data(clone):
    res = _run(clone, "-c", "import sph; from sph.study.analysis import validation_data_dir; "
                            "print(sph.__file__); print(validation_data_dir())")
    assert res.returncode == 0, res.stderr
    package, data = (Path(line).resolve() for line in res.stdout.split())
    assert package.is_relative_to(clone.resolve()), package
    assert data == (clone / "data" / "validation").resolve(), data
    assert (data / "hadzic2005").is_dir() and (data / "koshizuka1996").is_dir()


#: sweeps the default suite already dry-runs in the working copy
#: (tests/workflow/test_workflow.py): in a copy only in the slow suite (each plan is a
#: Snakemake start of about 5 s; the default suite stays under ten minutes on two cores)
PLANNED_ELSEWHERE = {"openings_fill", "wave_amplitude", "roll_rao"}


def _sweeps() -> list:
    return [""] + [pytest.param(f"config/sweeps/{p.name}", marks=pytest.mark.slow)
                   if p.stem in PLANNED_ELSEWHERE else f"config/sweeps/{p.name}"
                   for p in sorted((ROOT / "config" / "sweeps").glob("*.yaml"))]


@needs_git
@pytest.mark.parametrize("configfile", _sweeps(), ids=lambda c: Path(c).stem or "default")
def test_the_copy_plans_the_sweep(clone, configfile):
    assert configfile == "" or (clone / configfile).is_file(), f"{configfile} not tracked"
    extra = ["--configfile", configfile] if configfile else []
    res = _run(clone, "-m", "snakemake", "-n", "--cores", "2", *extra)
    assert res.returncode == 0, res.stdout[-3000:] + res.stderr[-3000:]
    assert "This was a dry-run" in res.stdout + res.stderr


@needs_git
def test_no_file_names_a_path_outside_the_repository():
    """Only the documentation may mention the sibling folder of a development checkout."""
    pattern = r"\.\./" + "shared" + r"\|" + "shared/" + "validation-data"
    res = _git("grep", "-n", "--untracked", pattern, "--", ".", ":!docs")
    assert res.returncode == 1, res.stdout + res.stderr  # 1: nothing found
