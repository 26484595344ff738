"""The importable packages are this repository's, not PyPI's namesakes."""

import importlib
import pathlib
import subprocess
import sys

import pytest

REPO = pathlib.Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("name", ["trackers", "bench", "scenes"])
def test_package_comes_from_this_repository(name):
    module = importlib.import_module(name)
    assert pathlib.Path(module.__file__).resolve().is_relative_to(REPO), module.__file__


def test_import_trackers_is_light():
    code = (
        "import sys, trackers; trackers.available(); "
        "bad = [m for m in ('mitsuba', 'drjit', 'matplotlib', 'pyvista', 'numba') if m in sys.modules]; "
        "print(','.join(bad))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, check=True)
    assert out.stdout.strip() == "", f"import trackers imported {out.stdout.strip()}"


def test_making_a_tracker_does_not_import_the_renderer():
    code = (
        "import sys, trackers; [trackers.make(n) for n in trackers.available()]; "
        "bad = [m for m in ('mitsuba', 'drjit', 'matplotlib', 'pyvista') if m in sys.modules]; print(','.join(bad))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, check=True)
    assert out.stdout.strip() == ""
