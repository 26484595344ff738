"""``stripebench loro``: each rig tracked with the choice made without its photographs, pooled."""

import json
import shutil

import numpy as np
import pytest

from bench.cli import main
from bench.store.realset import SHIPPED
from bench.studies.loro import fold_settings, parse_setting
from trackers.threshold import DEFAULT_MIN_RUN

FAMILY = f"k_sigma=4,prominence=1.1,min_run={DEFAULT_MIN_RUN},width_ratio=4"  # the threshold family's defaults
BLIND = "k_sigma=400,prominence=1.1,min_run=5,width_ratio=4"  # a setting that reports (almost) nothing
RENDERS = "k_sigma=6,prominence=1.1,min_run=5,width_ratio=4"  # a choice the renders alone made


def _judged(by_rig, kept=FAMILY, renders=RENDERS, trackers=("threshold",)):
    return {"in_sample": kept, "by_rig": by_rig, "renders_only": renders, "kept": kept, "rigs": sorted(by_rig),
            "figures": {}, "trackers": {t: {} for t in trackers}}


def _summaries(tmp_path, stage1):
    th = {"photographs": {"stage1": stage1, "stage4": _judged({"albrecht": "rule=0.9", "b33boy": "rule=0.9"},
                                                               "rule=0.9", "rule=0.9")}}
    gap = {"photographs": {}}
    (tmp_path / "th.json").write_text(json.dumps(th))
    (tmp_path / "gap.json").write_text(json.dumps(gap))
    return tmp_path / "th.json", tmp_path / "gap.json"


@pytest.fixture
def two_rigs(tmp_path):
    d = tmp_path / "set"
    d.mkdir()
    lines = (SHIPPED / "manifest.csv").read_text(encoding="utf-8").splitlines()
    chosen = [row for row in lines[1:] if row.split(",")[0] in ("al_room0", "al_room1", "bb_board")]
    for row in chosen:
        name = row.split(",")[0]
        for suffix in (".png", "_ref.csv"):
            shutil.copy(SHIPPED / f"{name}{suffix}", d / f"{name}{suffix}")
    (d / "manifest.csv").write_text("\n".join([lines[0], *chosen]) + "\n", encoding="utf-8")
    return d


def test_parse_setting_and_fold_settings():
    assert parse_setting("off_rel=0.2,switch_rows=3") == {"off_rel": 0.2, "switch_rows": 3}
    th = {"photographs": {"stage1": _judged({"a": FAMILY, "b": BLIND})}}
    plans, notes = fold_settings({"threshold": th}, ["a", "b", "c"])
    assert plans["b"]["threshold"]["k_sigma"] == 400 and plans["a"]["threshold"]["k_sigma"] == 4
    assert plans["b"]["com_bg"] == plans["b"]["threshold"]  # com_bg shares the family's detection
    assert plans["c"]["threshold"]["k_sigma"] == 4 and "no fold for c" in notes[0]
    # a stage that kept the renders' choice: every fold is tracked with it, whatever the folds chose
    th = {"photographs": {"stage1": {**_judged({"a": BLIND, "b": BLIND}, kept=FAMILY, renders=FAMILY)}}}
    th["photographs"]["stage1"]["in_sample"] = BLIND
    plans, _ = fold_settings({"threshold": th}, ["a", "b"])
    assert plans["a"]["threshold"]["k_sigma"] == 4 and plans["b"]["threshold"]["k_sigma"] == 4


def test_loro_tracks_each_rig_with_its_fold_s_choice(two_rigs, tmp_path, capsys):
    th, gap = _summaries(tmp_path, _judged({"albrecht": FAMILY, "b33boy": BLIND}))
    out = tmp_path / "loro.csv"
    assert main(["loro", "--dataset", str(two_rigs), "--threshold", str(th), "--gap", str(gap), "--out", str(out),
                 "--trackers", "threshold", "--quiet"]) == 0
    import pandas as pd

    t = pd.read_csv(out)
    assert list(t.columns[:4]) == ["tracker", "f1_loro", "false_report_rate_loro", "f1_in_sample"]
    row = t.iloc[0]
    assert row["tracker"] == "threshold" and row["n_rigs"] == 2 and row["n_photographs"] == 3
    assert row["rigs_moved"] == "b33boy"
    # in sample: the committed defaults everywhere, as stripebench real scores them
    assert main(["real", str(two_rigs), "--out", str(tmp_path / "r"), "--trackers", "threshold", "--quiet"]) == 0
    m = pd.read_csv(tmp_path / "r" / "metrics.csv")
    m = m[m["experiment"] != "mean"]
    hit, wrong, missed, false = (int(m[f"n_{o}"].sum()) for o in ("hit", "wrong", "missed", "false"))
    assert row["f1_in_sample"] == pytest.approx(2 * hit / (2 * hit + 2 * wrong + missed + false), abs=5e-5)
    # held out, b33boy's photograph is tracked with the blind setting its fold chose: fewer rows found
    assert row["recall_loro"] < hit / (hit + wrong + missed)
    assert np.isfinite(row["f1_loro"]) and row["f1_loro"] < row["f1_in_sample"]


def test_loro_refuses_a_summary_without_a_leave_one_rig_out_judgement(tmp_path, capsys):
    (tmp_path / "th.json").write_text(json.dumps({"chosen": {}}))
    assert main(["loro", "--threshold", str(tmp_path / "th.json"), "--gap", str(tmp_path / "nope.json")]) == 2
    assert "no `photographs` block" in capsys.readouterr().err
