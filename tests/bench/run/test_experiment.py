"""The harness end to end on tiny renders (64x60)."""

import csv
import filecmp
import hashlib
import json

import numpy as np
import pandas as pd
import pytest

from bench.config import parse
from bench.run.experiment import default_run_dir, run

pytestmark = pytest.mark.slow


def test_run_folder_holds_everything(tiny_run):
    out, cfg = tiny_run
    for name in ("run.json", "config.json", "metrics.parquet", "metrics.csv", "timings.csv", "samples.csv",
                 "summary.json", "report.html",
                 "figdata.npz", "scans/cone-patchy.npz", "scans/plane-absorbing.npz",
                 "gallery.npz", "figures/fig7_tracking.png", "figures/fig10_cone-patchy.png",
                 "figures/bars_hit_rate.png", "figures/gallery_00.png"):
        assert (out / name).is_file(), name
    m = pd.read_parquet(out / "metrics.parquet")
    assert len(m) == 2 * 4 * 2  # experiments x trackers x regions
    assert set(m["tracker"]) == set(cfg.trackers)
    for col in ("px_mae", "px_rmse", "px_p95", "depth_mae_mm", "depth_rmse_mm", "depth_p95_mm", "coverage",
                "hit_rate", "condition", "outlier_rate", "false_detections", "filled_fraction", "failed_frames"):
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
    assert s["metrics_sha256"] == hashlib.sha256((out / "metrics.csv").read_bytes()).hexdigest()
    assert set(s["machine"]) == {"cpu", "cores", "system", "arch"} and s["machine"]["cores"] >= 1
    assert {"numpy", "mitsuba", "drjit", "numba"} <= set(s["versions"]) and s["git_revision"]
    groups = {(i["group"], i["dp"], i["baseline"], i["statistic"]) for i in s["improvement"]}
    assert ("all", "dp4", "threshold", "rmse") in groups and ("cone-patchy", "dp8", "threshold", "std") in groups
    for i in s["improvement"]:
        if np.isfinite(i["value"]):
            assert i["low"] <= i["high"]
    assert s["coverage"] and all(0 <= c["coverage"] <= 1 for c in s["coverage"] if c["coverage"] == c["coverage"])


def test_report_links_its_own_figures(tiny_run):
    import re

    out, _ = tiny_run
    page = (out / "report.html").read_text()
    srcs = re.findall(r'<img src="([^"]+)"', page)
    assert len(srcs) >= 4 and "data:image" not in page and "src=\"http" not in page
    assert all(s.startswith("figures/") and (out / s).is_file() for s in srcs)  # every figure beside the page
    assert {p.name for p in (out / "figures").glob("*.png")} == {s.removeprefix("figures/") for s in srcs}
    for section in ("Which tracker is more precise", "The paper's condition: patchy cone", "At a glance",
                    "Every sample (Fig. 10)", "Failure gallery", "The paper's statistic", "Both halves per experiment"):
        assert section in page, section


def test_the_within_fraction_recomputed_from_samples_equals_the_reported_one(tiny_run):
    out, cfg = tiny_run
    s = json.loads((out / "summary.json").read_text())
    samples = pd.read_csv(out / "samples.csv")
    rob = {(r["group"], r["tracker"]): r for r in s["robust"]}
    assert s["restore"] == "rows" and s["within_mm"] == 5.0
    for key, g in samples.groupby("experiment"):
        for name in cfg.trackers:
            e = g[f"error_mm_{name}"].to_numpy(float)
            assert rob[(key, name)]["within"] == pytest.approx(np.mean(np.abs(e) <= 5.0))
            assert rob[(key, name)]["n_gross"] == int(np.sum(np.abs(e) > 50.0))
    assert {v["group"] for v in s["verdicts"]} >= {"all", "cone-patchy"}
    assert s["conditions"] == [{"condition": "patchy cone", "experiments": ["cone-patchy"]},
                               {"condition": "plane-absorbing", "experiments": ["plane-absorbing"]}]


def test_gallery_holds_the_worst_frames_as_rendered(tiny_run):
    from bench.store.files import load_npz

    out, cfg = tiny_run
    g = load_npz(out / "gallery.npz")
    keys = [str(k) for k in g["keys"]]
    assert {k.rsplit("/", 1)[0] for k in keys} == {"cone-patchy", "plane-absorbing"}
    scans = {k: load_npz(out / "scans" / f"{k}.npz") for k in ("cone-patchy", "plane-absorbing")}
    for k in keys:
        exp, i = k.rsplit("/", 1)
        assert g[f"{k}/image"].dtype == np.uint8 and g[f"{k}/image"].shape == (60, 64)
        np.testing.assert_array_equal(g[f"{k}/truth"], scans[exp]["truth_columns"][int(i)])
        for n in cfg.trackers:
            np.testing.assert_array_equal(g[f"{k}/columns/{n}"], scans[exp][f"columns/{n}"][int(i)])


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


@pytest.mark.slow
def test_a_real_set_gives_the_sim_to_real_comparison(tiny_dict, tmp_path):
    from bench.report.run import build_report

    d = {**tiny_dict, "real_set": "shipped", "real_predict": True, "trackers": ["threshold", "dp4"],
         "baselines": ["threshold"], "dp": ["dp4"],
         "experiments": [{**tiny_dict["experiments"][0], "condition": "colour-no-filter"}]}
    out = run(parse(d), tmp_path / "r", progress=False, quiet=True)
    s = json.loads((out / "summary.json").read_text())["sim_to_real"]
    by = {c["condition"]: c for c in s["by_class"]["classes"]}  # the experiment's condition against the manifest's
    from bench.store.realset import SHIPPED
    tags = [r["condition"] for r in csv.DictReader((SHIPPED / "manifest.csv").read_text().splitlines())]
    assert s["by_class"]["matched"] == ["colour-no-filter"]
    assert by["colour-no-filter"]["n_photographs"] == tags.count("colour-no-filter") >= 12
    assert by["turntable-saturated"]["rendered"] is False
    assert by["turntable-saturated"]["n_photographs"] == tags.count("turntable-saturated") >= 2
    real = pd.read_parquet(out / "real" / "metrics.parquet")
    means = real[real.experiment == "mean"].set_index("tracker")["hit_rate"]
    m = pd.read_parquet(out / "metrics.parquet")
    synth = m[m.region == "object"].groupby("tracker")["hit_rate"].mean()
    rows = {t["tracker"]: t for t in s["table"]}
    assert set(rows) == {"threshold", "dp4"} and s["n"] == 2 and s["dataset"] == "shipped"
    for name in rows:
        assert rows[name]["real"] == pytest.approx(means[name]) and rows[name]["synthetic"] == pytest.approx(synth[name])
    assert s["sentences"][0].startswith("hit rate: too few trackers")  # two trackers: no rank correlation is claimed
    # both halves (issue 66): F1 and the false-report rate of every row of the renders against the photographs'
    assert [t.split(":")[0] for t in s["sentences"]].count("F1 over rows") >= 1
    frr = s["detection"]["false_report_rate"]["table"]
    syn = m[m.region == "all"].groupby("tracker")["false_report_rate"].mean()
    assert frr and all(t["synthetic"] == pytest.approx(syn[t["tracker"]]) for t in frr)
    det = s["by_class_detection"]["f1"]
    assert det["matched"] == ["colour-no-filter"]
    f1c = {c["condition"]: c for c in det["classes"]}["colour-no-filter"]
    rf = real[real.experiment.isin(f1c["photographs"])].groupby("tracker")["f1"].mean()
    sf = m[m.region == "all"].groupby("tracker")["f1"].mean()
    for t in f1c["table"]:
        assert t["real"] == pytest.approx(rf[t["tracker"]]) and t["synthetic"] == pytest.approx(sf[t["tracker"]])
    rc = real[real.experiment.isin(by["colour-no-filter"]["photographs"])].groupby("tracker")["hit_rate"].mean()
    for t in by["colour-no-filter"]["table"]:
        assert t["real"] == pytest.approx(rc[t["tracker"]]) and t["synthetic"] == pytest.approx(synth[t["tracker"]])
    # predicted beside measured on the same photographs: the measured side is the real run's pooled rows
    p = s["predicted"]
    assert len(p["photographs"]) + len(p["shrunk"]) + len(p["out_of_range"]) == len(tags)
    pooled = real[real.experiment.isin(p["photographs"])].groupby("tracker")[["n_hit", "n_wrong", "n_missed"]].sum()
    for t in p["hit_rate"]["table"]:
        n = pooled.loc[t["tracker"]]
        assert t["real"] == pytest.approx(n["n_hit"] / (n["n_hit"] + n["n_wrong"] + n["n_missed"]))
        assert 0.0 <= t["synthetic"] <= 1.0
    assert (out / "real" / "predict" / "predicted.csv").is_file()
    page = build_report(out, quiet=True).read_text()
    assert "Renders vs photographs" in page and "Matched by class of condition" in page
    assert "Predicted beside measured, photograph by photograph" in page


@pytest.mark.slow
def test_a_run_with_a_real_set_predicts_only_when_asked(tiny_dict, tmp_path, monkeypatch):
    """``real_predict`` is off by default (not in the configuration's dict, so its hash is the one before the key
    existed): the sim-to-real section reads the measured figures alone and nothing is predicted; ``--predict`` sets it,
    and a configuration without a real set refuses ``--predict`` in one line."""
    import shutil

    from bench.cli import main
    from bench.run import real as real_run
    from bench.store.realset import SHIPPED

    ds = tmp_path / "set"
    ds.mkdir()
    for f in ("bb_board.png", "bb_board_ref.csv"):
        shutil.copy(SHIPPED / f, ds / f)
    (ds / "manifest.csv").write_text("name,has_background,laser_colour,rotate,channel,rig\nbb_board,0,red,0,r,b33boy\n")
    d = {**tiny_dict, "real_set": str(ds), "trackers": ["threshold", "dp4"], "baselines": ["threshold"], "dp": ["dp4"],
         "experiments": [tiny_dict["experiments"][0]]}
    config = parse(d)
    assert config.real_predict is False and "real_predict" not in config.to_dict()
    assert parse({**d, "real_predict": True}).to_dict()["real_predict"] is True

    def refuse(*a, **k):
        raise AssertionError("predicted without being asked")

    monkeypatch.setattr(real_run, "predict_real", refuse)
    out = run(config, tmp_path / "r", progress=False, quiet=True)
    s = json.loads((out / "summary.json").read_text())["sim_to_real"]
    assert "predicted" not in s and s["n"] == 2 and not (out / "real" / "predict").exists()
    assert main(["run", "--profile", "quick", "--predict", "--out", str(tmp_path / "q")]) == 2


@pytest.mark.slow
def test_a_settings_own_restore_in_the_run_its_checkpoints_and_its_identity(gate_dict, tmp_path):
    from bench.store.files import load_npz
    from bench.store.runfolder import RunFolderError

    gaps = {"label": "threshold_gaps", "name": "threshold", "restore": "none"}
    gate_dict.update(trackers=["threshold", "dp4", gaps, {"label": "argmax", "name": "threshold",
                                                          "params": {"threshold": -1.0}}],
                     baselines=["threshold", "threshold_gaps", "argmax"], n_samples=60)
    gate_dict["experiments"][0]["ambient_lux"] = 1500.0  # a dim stripe: the threshold misses some rows
    cfg = parse(gate_dict)
    out = run(cfg, tmp_path / "r", progress=False, quiet=True)
    key = cfg.experiments[0].key
    ck = load_npz(out / "scans" / f"{key}.npz")
    # the checkpoint keeps the setting's own columns under its label: the same tracker, the same columns
    np.testing.assert_array_equal(ck["columns/threshold_gaps"], ck["columns/threshold"])
    s = pd.read_csv(out / "samples.csv")
    missed = s["filled_threshold"].to_numpy(bool)
    assert missed.any() and not missed.all()
    assert s["error_mm_threshold_gaps"].isna().to_numpy().tolist() == missed.tolist()
    np.testing.assert_array_equal(s.loc[~missed, "error_mm_threshold_gaps"], s.loc[~missed, "error_mm_threshold"])
    assert not s["filled_threshold_gaps"].any() and s["error_mm_argmax"].notna().all()
    m = pd.read_parquet(out / "metrics.parquet")
    fill = m[m.region == "all"].set_index("tracker")["filled_fraction"]
    assert fill["threshold_gaps"] == 0.0 and fill["threshold"] > 0.0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["restore_by_tracker"] == {"threshold": "rows", "dp4": "rows", "threshold_gaps": "none",
                                             "argmax": "rows"}
    r = next(i for i in summary["improvement"] if (i["group"], i["dp"], i["baseline"], i["statistic"])
             == ("all", "dp4", "threshold_gaps", "rmse"))
    assert (r["n_samples"], r["n_missing_baseline"], r["n"]) == (len(s), int(missed.sum()), int((~missed).sum()))
    assert [c["baseline"] for c in summary["paper_claims"]] == ["threshold", "threshold_gaps", "argmax"]
    rob = {x["tracker"]: x for x in summary["robust"] if x["group"] == "all"}
    assert rob["threshold_gaps"]["n_missing"] == int(missed.sum())
    # the same configuration resumes from the checkpoints; another restore of the setting is another run
    before = dict(load_npz(out / "scans" / f"{key}.npz"))
    run(cfg, out, progress=False, quiet=True)
    after = load_npz(out / "scans" / f"{key}.npz")
    assert sorted(after) == sorted(before) and any(k.startswith("seconds/threshold_gaps") for k in before)
    for k in before:  # the per-frame tracker times too: nothing was tracked again
        np.testing.assert_array_equal(after[k], before[k])
    other = parse({**gate_dict, "trackers": [{**gaps, "restore": "rows"} if t == gaps else t
                                             for t in gate_dict["trackers"]]})
    assert other.restore_by_label()["threshold_gaps"] == "rows"
    with pytest.raises(RunFolderError, match="holds a run of another configuration"):
        run(other, out, progress=False, quiet=True)
