"""The harness end to end on tiny renders (64x60)."""

import filecmp
import json

import numpy as np
import pandas as pd
import pytest

from bench.config import parse
from bench.experiment import default_run_dir, run

pytestmark = pytest.mark.slow


def test_run_folder_holds_everything(tiny_run):
    out, cfg = tiny_run
    for name in ("run.json", "config.json", "metrics.parquet", "metrics.csv", "timings.csv", "samples.csv",
                 "summary.json", "report.html",
                 "figdata.npz", "scans/cone-patchy.npz", "scans/plane-absorbing.npz",
                 "figures/fig7_tracking.png", "figures/fig10_cone-patchy.png", "figures/bars_cone.png"):
        assert (out / name).is_file(), name
    m = pd.read_parquet(out / "metrics.parquet")
    assert len(m) == 2 * 4 * 2  # experiments x trackers x regions
    assert set(m["tracker"]) == set(cfg.trackers)
    for col in ("px_mae", "px_rmse", "px_p95", "depth_mae_mm", "depth_rmse_mm", "depth_p95_mm", "coverage",
                "outlier_rate", "false_detections", "filled_fraction", "failed_frames"):
        assert col in m.columns
    assert "ms_per_frame" not in m.columns  # timings live in timings.csv
    assert pd.read_csv(out / "metrics.csv").shape == m.shape
    t = pd.read_csv(out / "timings.csv")
    assert len(t) == len(m) and (t["ms_per_frame"] > 0).all()


def test_samples_are_the_same_points_for_every_tracker(tiny_run):
    out, cfg = tiny_run
    s = pd.read_csv(out / "samples.csv")
    assert (s.groupby("experiment").size() <= cfg.n_samples).all()
    assert {f"error_mm_{n}" for n in cfg.trackers} <= set(s.columns)
    assert s[["frame", "row"]].notna().all().all() and (s["true_depth_cm"].between(20, 61)).all()


def test_summary_has_statistics_versions_and_revision(tiny_run):
    out, cfg = tiny_run
    s = json.loads((out / "summary.json").read_text())
    assert s["seed"] == 1 and s["paper_improvement"] == 0.30
    assert {"numpy", "mitsuba", "drjit", "numba"} <= set(s["versions"]) and s["git_revision"]
    groups = {(i["group"], i["dp"], i["baseline"], i["statistic"]) for i in s["improvement"]}
    assert ("all", "dp4", "threshold", "rmse") in groups and ("cone-patchy", "dp8", "threshold", "std") in groups
    for i in s["improvement"]:
        if np.isfinite(i["value"]):
            assert i["low"] <= i["high"]
    assert s["coverage"] and all(0 <= c["coverage"] <= 1 for c in s["coverage"] if c["coverage"] == c["coverage"])


def test_report_is_self_contained(tiny_run):
    out, _ = tiny_run
    page = (out / "report.html").read_text()
    assert page.count("data:image/png;base64,") >= 4 and "src=\"http" not in page and "Precision improvement" in page


def test_same_config_and_seed_give_byte_identical_metrics_files(tiny_run, tmp_path):
    out, cfg = tiny_run
    again = run(cfg, tmp_path / "again", progress=False, quiet=True)
    for name in ("metrics.csv", "metrics.parquet", "samples.csv"):
        assert filecmp.cmp(out / name, again / name, shallow=False), name
    # the timings differ from run to run: they are kept apart
    assert (out / "timings.csv").read_bytes() != (again / "timings.csv").read_bytes()


def test_default_run_dir_depends_on_the_configuration(tiny_dict):
    a = default_run_dir(parse(tiny_dict))
    b = default_run_dir(parse({**tiny_dict, "seed": 2}))
    assert a != b and a.name.startswith("tiny-") and default_run_dir(parse(tiny_dict)) == a
