"""Shared run fixtures of the harness tests: tiny configurations (64x60 renders)
and session-wide runs of them, so each is rendered and tracked once."""

import copy

import numpy as np
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


#: The test seed of the ``tiny_export`` frame set.
TINY_TEST_SEED = 20261207


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
    """The frame set of :data:`TINY` (``stripebench export``) with a dev and a test split (test seed
    :data:`TINY_TEST_SEED`), written once per test run."""
    from bench.config import parse
    from bench.run.export import export

    return export(parse(copy.deepcopy(TINY)), tmp_path_factory.mktemp("tiny-export") / "frames",
                  test_seed=TINY_TEST_SEED, quiet=True)


@pytest.fixture(scope="session")
def tiny_export_dev(tmp_path_factory):
    """The frame set of :data:`TINY` without a test split: every frame is the run's own (a test frame is
    rendered elsewhere, bench.run.export.test_frame), so a submission scores as the run does."""
    from bench.config import parse
    from bench.run.export import export

    return export(parse(copy.deepcopy(TINY)), tmp_path_factory.mktemp("tiny-export-dev") / "frames",
                  test_fraction=0.0, quiet=True)


def _tiny_trainset(root, *, rgb: bool):
    """One hand-made 8x6 frame (a stripe at column 2.5 in rows 0-3, none in rows 4-5) in a training set's layout."""
    from bench.run.trainset import _png
    from bench.store import frameset as fs

    (root / "images").mkdir(parents=True)
    (root / "truth").mkdir()
    img = np.full((6, 8), 20, np.uint8)
    img[:4, 2:4] = 200
    off = np.full((6, 8), 20, np.uint8)
    if rgb:
        img, off = np.stack([img, img // 2, img // 2], axis=2), np.stack([off] * 3, axis=2)
    for name, a in (("f.png", img), ("f_off.png", off)):
        (root / "images" / name).write_bytes(_png(a))
    cols = np.array([2.5, 2.5, 2.5, 2.5, np.nan, np.nan])
    (root / "truth" / "f.csv").write_text(fs.truth_csv(cols, np.zeros((6, 3)), np.where(np.isfinite(cols), 0, -1)))
    return {"frame": "f", "image": "images/f.png", "background": "images/f_off.png", "height": 6,
            "camera": "rgb" if rgb else "mono", "laser_wavelength_nm": 650.0}, img, off


@pytest.fixture
def tiny_trainset():
    """A maker of one-frame training sets: ``tiny_trainset(root, rgb=...)`` -> (frames.csv row, image,
    laser-off frame)."""
    return _tiny_trainset
