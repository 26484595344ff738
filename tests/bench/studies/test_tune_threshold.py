"""The tuning procedure of the threshold trackers (bench.studies.tune_threshold)."""

import numpy as np
import pytest

from bench.studies import tune_threshold as tt


def test_frame_scores_balance_hits_and_quiet_rows():
    m = tt.frame_scores([1.0, np.nan, 5.0, np.nan], [1.5, 3.0, np.nan, np.nan], 3.0, [1, 3, 0, 0])
    assert m == {"hit": 0.5, "quiet": 0.5, "score": 0.5, "mae_px": 0.5, "recall": 0.5}
    assert np.isnan(tt.frame_scores([1.0], [1.0], 3.0)["quiet"])


def test_choices_follow_the_profiles_rules():
    scores = {(4.0, 0.0): 0.78, (4.0, 1.1): 0.81, (3.0, 1.5): 0.84}
    recalls = {(4.0, 0.0): 0.951, (4.0, 1.1): 0.944, (3.0, 1.5): 0.85}
    assert tt.choose_grid(scores, 0.002) == (3.0, 1.5)
    assert tt.choose_grid(scores, 0.002, recalls, 0.95) == (4.0, 0.0)
    assert tt.choose_grid(scores, 0.002, recalls, 0.99) == (3.0, 1.5)  # none eligible: all compete
    assert tt.choose_min({0.25: 0.3411, 0.4: 0.3418, 0.0: 0.36}, 0.005) == 0.25
    assert tt.choose_listed({"excess": 0.70, 0.9: 0.774, 0.8: 0.7735}, ["excess", 0.9, 0.8], 0.002) == 0.9


def test_the_committed_profile_loads_and_bad_profiles_name_the_key(tmp_path):
    p = tt.load_profile(tt.DEFAULT_PROFILE)
    assert p.seeds == [100, 101, 102, 103, 104, 105] and p.min_recall == 0.95 and p.real
    text = tt.DEFAULT_PROFILE.read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("min_recall = 0.95", "min_recall = 2"))
    with pytest.raises(ValueError, match="`min_recall` must be a number in \\[0, 1\\], got 2"):
        tt.load_profile(bad)
    bad.write_text(text + "\nextra = 1\n")
    with pytest.raises(ValueError, match="unknown key"):
        tt.load_profile(bad)


def test_a_small_run_writes_its_files_and_chooses_from_its_grid(tmp_path):
    text = tt.DEFAULT_PROFILE.read_text()
    for a, b in (("seeds = [100, 101, 102, 103, 104, 105]", "seeds = [100]"),
                 ('kinds = ["printed", "noisy_floor", "polished", "daylight", "noisy_sensor", "saturated_wide", '
                  '"thin_faint", "plain"]', 'kinds = ["plain", "noisy_sensor"]'),
                 ("real = true", "real = false"), ('trackers = ["threshold", "centroid", "gauss3", "parabolic", '
                                                   '"blais_rioux"]', 'trackers = ["threshold"]'),
                 ("k_sigma = [3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0, 16.0, 24.0]", "k_sigma = [4.0, 24.0]"),
                 ("prominence = [0.0, 1.05, 1.1, 1.25, 1.5, 2.0]", "prominence = [0.0]"),
                 ("frac = [0.0, 0.1, 0.25, 0.4, 0.5, 0.7]", "frac = [0.25]"),
                 ('colour_trackers = ["threshold", "centroid", "gauss3", "parabolic", "blais_rioux", "com_bg", '
                  '"steger"]', 'colour_trackers = ["threshold"]'),
                 ('colour_rules = ["excess", 1.0, 0.95, 0.9, 0.8, 0.7, 0.5, 0.0, "laser"]',
                  'colour_rules = ["excess", 0.9]')):
        assert a in text, a
        text = text.replace(a, b)
    prof = tmp_path / "small.toml"
    prof.write_text(text)
    out = tmp_path / "out"
    assert tt.main(["--profile", str(prof), "--out", str(out), "--quiet"]) == 0
    import json

    summary = json.loads((out / "summary.json").read_text())
    assert summary["chosen"]["k_sigma"] in (4.0, 24.0) and summary["chosen"]["frac"] == 0.25
    assert (out / "tune.csv").read_text().startswith("stage,setting,tracker,group,frame,score")
    # k_sigma = 24 misses the noisy sensor's argmax-right rows: never eligible over 4
    assert summary["stage1_recall"]["k_sigma=4,prominence=0"] > summary["stage1_recall"]["k_sigma=24,prominence=0"]
