"""The regression gate, the oracle and fault tolerance through the whole harness."""

import hashlib
import json

import numpy as np
import pandas as pd
import pytest

import scenes
from bench.run import gate
from bench.cli import main
from bench.config import parse
from bench.run.experiment import run
from bench.report.run import build_report
from trackers import Track, Tracker

pytestmark = pytest.mark.slow


@pytest.fixture
def good_run(gate_run):
    return gate_run


def test_a_run_passes_against_its_own_baseline(good_run, capsys):
    out, base = good_run
    assert main(["check", str(out), "--baseline", str(base)]) == 0
    assert "0 failed" in capsys.readouterr().out


def test_a_degraded_tracker_fails_the_gate_and_is_named(good_run, gate_dict, tmp_path, register_tracker, capsys):
    out, base = good_run
    # the same configuration, but `threshold` built with a threshold no stripe reaches
    from trackers.threshold import ThresholdTracker

    register_tracker("threshold", lambda **kw: ThresholdTracker(threshold=254.0), replace=True)
    bad = run(parse(gate_dict), tmp_path / "bad", progress=False, quiet=True)
    assert main(["check", str(bad), "--baseline", str(base)]) == 1
    captured = capsys.readouterr()
    assert "threshold:coverage" in captured.err and "REGRESSED" in captured.out
    table = [line for line in captured.out.splitlines() if "REGRESSED" in line]
    assert all("/threshold/" in line for line in table)
    assert any(" coverage " in line for line in table)


def test_missing_entries_are_reported_on_both_sides(good_run):
    out, base = good_run
    doc = gate.load_baseline(base)
    current = gate.baseline_from_run(out)
    gone = next(iter(current["metrics"]))
    del current["metrics"][gone]
    current["metrics"]["cone-patchy/newtracker/all"] = {"px_mae": 0.1}
    other = sorted(k for k in doc["metrics"] if k != gone)[0]
    doc["metrics"][other].pop("coverage")
    rows = gate.compare(doc, current)
    verdicts = {(r.key, r.verdict) for r in rows}
    assert (gone, "MISSING IN RUN") in verdicts
    assert ("cone-patchy/newtracker/all", "NOT IN BASELINE") in verdicts
    assert any(r.key == other and r.metric == "coverage" and r.verdict == "NOT IN BASELINE" for r in rows)
    assert sum(r.failed for r in rows) >= 3


def test_verdicts_follow_direction_and_tolerance():
    tol = {"direction": "lower", "abs": 0.1, "rel": 0.0}
    assert gate._verdict("px_mae", 1.0, 1.05, tol) == "ok"
    assert gate._verdict("px_mae", 1.0, 1.2, tol) == "REGRESSED"
    assert gate._verdict("px_mae", 1.0, 0.5, tol) == "better"
    assert gate._verdict("px_mae", None, None, tol) == "ok"
    assert gate._verdict("px_mae", 1.0, None, tol) == "REGRESSED"
    up = {"direction": "higher", "abs": 0.01, "rel": 0.0}
    assert gate._verdict("coverage", 0.9, 0.85, up) == "REGRESSED" and gate._verdict("coverage", 0.9, 0.95, up) == "better"


def test_bad_baseline_files_are_usage_errors(good_run, tmp_path, capsys):
    out, _ = good_run
    junk = tmp_path / "junk.json"
    junk.write_text("{}")
    assert main(["check", str(out), "--baseline", str(junk)]) == 2
    assert "is not a stripebench baseline" in capsys.readouterr().err
    assert main(["check", str(out), "--baseline", str(tmp_path / "none.json")]) == 2
    assert main(["check", str(tmp_path), "--baseline", str(junk)]) == 2


class Oracle(Tracker):
    """Returns the ground truth of the frame it is given (looked up by the
    image's bytes): a check of the harness, not a tracker."""

    name = "oracle"
    subpixel = True
    truth = {}

    def _track(self, image, background):
        cols = self.truth[hashlib.sha1(np.ascontiguousarray(image).tobytes()).hexdigest()]
        return Track(cols, np.where(np.isnan(cols), np.nan, 1.0))


def test_oracle_scores_zero_error_and_full_coverage_through_the_harness(gate_dict, tmp_path, monkeypatch,
                                                                        register_tracker):
    render = scenes.Scene.render

    def recording_render(self, *a, **kw):
        f = render(self, *a, **kw)
        Oracle.truth[hashlib.sha1(f.image.tobytes()).hexdigest()] = f.truth.columns.copy()
        return f

    monkeypatch.setattr(scenes.Scene, "render", recording_render)
    register_tracker("oracle", Oracle)
    cfg = parse({**gate_dict, "trackers": ["oracle", "threshold"], "baselines": ["threshold"], "dp": ["oracle"]})
    out = run(cfg, tmp_path / "oracle", progress=False, quiet=True)
    m = pd.read_parquet(out / "metrics.parquet")
    o = m[m["tracker"] == "oracle"]
    assert (o["px_mae"] == 0).all() and (o["px_p95"] == 0).all() and (o["coverage"] == 1).all()
    a = o[o["region"] == "all"]
    assert (o["outlier_rate"] == 0).all() and (a["false_detections"] == 0).all() and (a["false_report_rate"] == 0).all()
    assert o[o["region"] == "object"]["false_detections"].isna().all()  # the object region cannot see one
    assert (o["depth_rmse_mm"] < 1e-6).all()
    s = pd.read_csv(out / "samples.csv")
    assert len(s) and np.abs(s["error_mm_oracle"]).max() < 1e-6


class Raising(Tracker):
    name = "raising"

    def _track(self, image, background):
        raise ZeroDivisionError("tracker bug")


def test_a_failing_tracker_is_recorded_and_reported(gate_dict, tmp_path, register_tracker):
    register_tracker("raising", Raising)
    cfg = parse({**gate_dict, "trackers": ["threshold", "raising"], "dp": [], "baselines": []})
    out = run(cfg, tmp_path / "fails", progress=False, quiet=True)
    build_report(out, quiet=True)
    summary = json.loads((out / "summary.json").read_text())
    scan = summary["scans"][0]
    assert scan["failures"]["raising"] == 4 and scan["failures"]["threshold"] == 0
    assert "ZeroDivisionError: tracker bug" in scan["failure_messages"]["raising"][0]
    m = pd.read_parquet(out / "metrics.parquet")
    assert (m.loc[m["tracker"] == "raising", "failed_frames"] == 4).all()
    assert "ZeroDivisionError: tracker bug" in (out / "report.html").read_text()


def test_an_interrupted_run_resumes_without_rendering_finished_frames(gate_dict, tmp_path, monkeypatch):
    cfg = parse({**gate_dict, "seed": 5})
    calls = {"n": 0}
    render = scenes.Scene.render

    def counting(self, *a, **kw):
        calls["n"] += 1
        if calls["n"] == 3 and calls.get("interrupt", True):
            raise KeyboardInterrupt
        return render(self, *a, **kw)

    monkeypatch.setattr(scenes.Scene, "render", counting)
    with pytest.raises(KeyboardInterrupt):
        run(cfg, tmp_path / "r", progress=False, quiet=True)
    calls.update(n=0, interrupt=False)
    run(cfg, tmp_path / "r", progress=False, quiet=True)
    # 2 of the 4 frames were finished before the interruption: only the other
    # 2 are rendered again, plus the failure gallery's frames (from the render cache)
    from bench.store.files import load_npz

    assert calls["n"] == 2 + len(load_npz(tmp_path / "r" / "gallery.npz")["keys"])
    full = run(cfg, tmp_path / "ref", progress=False, quiet=True)
    assert (tmp_path / "r" / "metrics.parquet").read_bytes() == (full / "metrics.parquet").read_bytes()
