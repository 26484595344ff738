"""Fixtures of the command-line tests; the helpers are in ``cli_helpers.py`` (this folder is put on
``sys.path`` so that the test modules import them by name)."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

from cli_helpers import TOML  # noqa: E402


@pytest.fixture
def config_file(tmp_path):
    """The tiny configuration written to a file."""
    p = tmp_path / "c.toml"
    p.write_text(TOML)
    return p


@pytest.fixture(scope="module")
def cli_run(tmp_path_factory):
    """A finished 64x60 run made through the command line (no report)."""
    from bench.cli import main

    d = tmp_path_factory.mktemp("clirun")
    cfg = d / "c.toml"
    cfg.write_text(TOML)
    assert main(["run", str(cfg), "--out", str(d / "run"), "--quiet", "--no-report"]) == 0
    return d / "run", cfg
