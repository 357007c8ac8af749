"""Fixtures shared by the workflow tier."""

import importlib.util
from pathlib import Path

import pytest

from sph.cli import main

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def figure_script(monkeypatch):
    """Load a script of ``workflow/scripts`` by name; the axes of the figure it saves and
    the figure's own texts are kept in the returned mapping (``drawn["axes"]``,
    ``drawn["texts"]``)."""
    import matplotlib.pyplot as plt

    drawn = {}
    savefig = plt.Figure.savefig

    def keep(fig, out, **kw):
        drawn["axes"] = fig.axes
        drawn["texts"] = [t.get_text() for t in fig.texts]
        return savefig(fig, out, **kw)

    monkeypatch.setattr(plt.Figure, "savefig", keep)

    def load(name):
        spec = importlib.util.spec_from_file_location(
            name, ROOT / "workflow" / "scripts" / f"{name}.py")
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        return module

    return load, drawn


@pytest.fixture
def case_file(tmp_path, capsys):
    """Write the built-in example of a case to a file (as a user would) and return it."""

    def make(name):
        assert main(["example", name]) == 0
        path = tmp_path / f"{name}.yaml"
        path.write_text(capsys.readouterr().out)
        return path

    return make
