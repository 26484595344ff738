"""A tiny run of the sub-pixel estimator study."""

import csv

import numpy as np
import pytest

from bench.studies import estimators


def _main(argv):
    """``stripebench estimators ARGV``."""
    from bench.cli import main

    return main(["estimators", *argv])


def test_stripe_frame_truth_and_phases():
    rng = np.random.default_rng(0)
    img, truth, off = estimators.stripe_frame(1.5, 100.0, 0.0, rng, height=64, width=48)
    assert img.dtype == np.uint8 and img.shape == (64, 48) and off.shape == img.shape
    assert np.all(off == 10)  # noise-free laser-off frame is the background
    # rows sweep one pixel of sub-pixel phase
    assert truth[-1] - truth[0] == pytest.approx(63 / 64)
    w = img.astype(float) - 10.0
    assert np.abs((w * np.arange(48)).sum(1) / w.sum(1) - truth).max() < 0.02


def test_tiny_study_writes_table_and_plot(tmp_path):
    argv = ["--out", str(tmp_path), "--sigmas", "1,2", "--peaks", "100", "--noises", "0.5,4", "--frames", "2",
            "--trackers", "gauss3,centroid,threshold"]
    assert _main(argv) == 0
    with open(tmp_path / "estimators.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert tuple(rows[0].keys()) == estimators.FIELDS
    # threshold is not a sub-pixel tracker: left out
    assert {r["tracker"] for r in rows} == {"gauss3", "centroid"}
    assert len(rows) == 2 * 2 * 1 * 2
    for r in rows:
        assert int(r["rows"]) == 2 * 64 and float(r["reported"]) == 1.0
        assert 0 <= float(r["mean_abs_px"]) <= float(r["rmse_px"]) <= 1.0
    # the physics: less noise, smaller error, for every estimator and width
    err = {(r["tracker"], r["sigma_px"], r["noise_dn"]): float(r["mean_abs_px"]) for r in rows}
    for name in ("gauss3", "centroid"):
        for sigma in ("1", "2"):
            assert err[(name, sigma, "0.5")] < err[(name, sigma, "4")]
    png = (tmp_path / "estimators.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) < 300_000


def test_study_is_seeded():
    a = estimators.run_study([1.0], [50.0], [2.0], frames=1, seed=3, tracker_names=["gauss3"])
    b = estimators.run_study([1.0], [50.0], [2.0], frames=1, seed=3, tracker_names=["gauss3"])
    c = estimators.run_study([1.0], [50.0], [2.0], frames=1, seed=4, tracker_names=["gauss3"])
    assert a == b and a != c


def test_bad_arguments(tmp_path):
    with pytest.raises(SystemExit):
        _main(["--out", str(tmp_path), "--trackers", "nope"])
    with pytest.raises(SystemExit):
        _main(["--out", str(tmp_path), "--sigmas", "one"])
    assert _main(["--out", str(tmp_path), "--peaks", "50,100", "--plot-peak", "70"]) == 2
    with pytest.raises(SystemExit):
        _main(["--out", str(tmp_path), "--sigmas", "nan"])
