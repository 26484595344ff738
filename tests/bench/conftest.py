"""Shared run fixtures of the harness tests: tiny configurations (64x60 renders)
and session-wide runs of them, so each is rendered and tracked once."""

import copy

import pytest

TINY = {
    "name": "tiny",
    "seed": 1,
    "trackers": ["threshold", "centroid", "dp4", "dp8"],
    "baselines": ["threshold"],
    "dp": ["dp4", "dp8"],
    "n_samples": 12,
    "n_boot": 50,
    "render": {"width": 64, "height": 60, "spp": 2, "ambient_spp": 1},
    "experiments": [
        {"scene": "cone", "material": "patchy", "n_angles": 3, "condition": "patchy cone"},
        {"scene": "plane", "material": "absorbing", "n_angles": 2},
    ],
}

GATE = {
    "name": "gate",
    "seed": 0,
    "trackers": ["threshold", "dp4"],
    "baselines": ["threshold"],
    "dp": ["dp4"],
    "n_samples": 10,
    "n_boot": 20,
    "render": {"width": 64, "height": 60, "spp": 2, "ambient_spp": 1},
    "experiments": [{"scene": "cone", "material": "patchy", "n_angles": 4, "line_fwhm_mrad": 10.0}],
}


@pytest.fixture
def tiny_dict():
    """A fresh copy of the two-experiment configuration (cone and plane, four trackers)."""
    return copy.deepcopy(TINY)


@pytest.fixture
def gate_dict():
    """A fresh copy of the one-experiment configuration (cone, threshold and dp4, 4 frames)."""
    return copy.deepcopy(GATE)


@pytest.fixture(scope="session")
def tiny_run(tmp_path_factory):
    """``(run folder, Config)`` of :data:`TINY`, run once per session, with its report."""
    from bench.config import parse
    from bench.run.experiment import run
    from bench.report.run import build_report

    cfg = parse(copy.deepcopy(TINY))
    out = run(cfg, tmp_path_factory.mktemp("tiny") / "run", progress=False, quiet=True)
    build_report(out, quiet=True)
    return out, cfg


@pytest.fixture(scope="session")
def gate_run(tmp_path_factory):
    """``(run folder, baseline path)`` of :data:`GATE`, run once per session (no report)."""
    from bench.run import gate
    from bench.config import parse
    from bench.run.experiment import run

    out = run(parse(copy.deepcopy(GATE)), tmp_path_factory.mktemp("gate") / "run", progress=False, quiet=True)
    base = tmp_path_factory.mktemp("gate-baseline") / "baseline.json"
    gate.write_baseline(out, base)
    return out, base


@pytest.fixture(scope="session")
def tiny_export(tmp_path_factory):
    """The frame set of :data:`TINY` (``stripebench export``), written once per session."""
    from bench.config import parse
    from bench.run.export import export

    return export(parse(copy.deepcopy(TINY)), tmp_path_factory.mktemp("tiny-export") / "frames", quiet=True)
