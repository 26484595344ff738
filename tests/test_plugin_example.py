"""The plugin tutorial's example package (tests/plugin_example) installs, registers
through its entry point and runs through the command line."""

import json
import os
import pathlib
import subprocess
import sys

import pytest

REPO = pathlib.Path(__file__).resolve().parents[1]
EXAMPLE = REPO / "tests" / "plugin_example"

TOML = """
name = "plugin"
trackers = ["threshold", "example_peak"]
baselines = ["threshold"]
dp = ["example_peak"]
n_samples = 5
n_boot = 20
[render]
width = 64
height = 60
spp = 1
ambient_spp = 1
[[experiments]]
scene = "plane"
material = "matte"
n_angles = 2
"""


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """The example installed into a temporary site folder: its package and a
    ``.dist-info`` whose ``entry_points.txt`` comes from the example's pyproject
    (what ``pip install`` writes; the project's venv has no ``wheel`` to build it)."""
    import shutil
    import tomllib

    meta = tomllib.loads((EXAMPLE / "pyproject.toml").read_text())["project"]
    target = tmp_path_factory.mktemp("site")
    shutil.copytree(EXAMPLE / "src" / "sb_example_tracker", target / "sb_example_tracker",
                    ignore=shutil.ignore_patterns("__pycache__"))
    dist = target / f"{meta['name'].replace('-', '_')}-{meta['version']}.dist-info"
    dist.mkdir()
    (dist / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {meta['name']}\nVersion: {meta['version']}\n")
    lines = [f"[{group}]\n" + "".join(f"{k} = {v}\n" for k, v in eps.items())
             for group, eps in meta["entry-points"].items()]
    (dist / "entry_points.txt").write_text("\n".join(lines))
    return {**os.environ, "PYTHONPATH": os.pathsep.join([str(target), str(REPO)])}


@pytest.mark.slow
def test_the_example_plugin_is_listed_and_passes_the_conformance_suite(installed):
    out = subprocess.run([sys.executable, "-m", "bench.cli", "trackers", "--json"], capture_output=True, text=True,
                         env=installed, cwd=REPO, check=True)
    table = {t["name"]: t for t in json.loads(out.stdout)}
    assert table["example_peak"]["params"] == {"min_contrast": 0.1} and table["example_peak"]["subpixel"] is True
    code = ("import trackers; from trackers.testing import check_tracker; "
            "check_tracker(trackers.make('example_peak')); print('ok')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=installed, cwd=REPO)
    assert out.stdout.strip() == "ok", out.stderr[-2000:]


@pytest.mark.slow
def test_the_example_plugin_runs_through_the_harness(installed, tmp_path):
    cfg = tmp_path / "plugin.toml"
    cfg.write_text(TOML)
    out = subprocess.run([sys.executable, "-m", "bench.cli", "run", str(cfg), "--out", str(tmp_path / "run"),
                          "--quiet", "--no-report"], capture_output=True, text=True, env=installed, cwd=REPO)
    assert out.returncode == 0, out.stderr[-2000:]
    assert "example_peak" in (tmp_path / "run" / "metrics.csv").read_text()
