"""Fixtures shared by the workflow tier."""

import pytest

from sph.cli import main


@pytest.fixture
def case_file(tmp_path, capsys):
    """Write the built-in example of a case to a file (as a user would) and return it."""

    def make(name):
        assert main(["example", name]) == 0
        path = tmp_path / f"{name}.yaml"
        path.write_text(capsys.readouterr().out)
        return path

    return make
