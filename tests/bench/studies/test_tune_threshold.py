"""The detection tuning procedure of the per-row trackers and Steger (bench.studies.tune_threshold)."""

import json

import numpy as np
import pytest

from bench.studies import tune_threshold as tt
from bench.cli import main as _main


def test_frame_scores_of_stage_two():
    assert tt.frame_scores([1.0, np.nan, 5.0, np.nan], [1.5, 3.0, np.nan, np.nan], 3.0) == {"hit": 0.5, "mae_px": 0.5}
    assert np.isnan(tt.frame_scores([np.nan], [1.0], 3.0)["mae_px"])


def test_choices_follow_the_profiles_rules():
    scores = {(4.0, 0.0, 1): 0.78, (4.0, 1.1, 5): 0.8405, (3.0, 1.5, 1): 0.84, (6.0, 1.5, 1): 0.8395}
    assert tt.choose_grid(scores, 0.002) == (6.0, 1.5, 1)  # ties: smaller min_run, larger prominence and k_sigma
    assert tt.choose_grid(scores, 0.0) == (4.0, 1.1, 5)
    widths = {(4.0, 0.0, 1, None): 0.80, (4.0, 0.0, 1, 4.0): 0.801, (4.0, 0.0, 1, 2.5): 0.85}
    assert tt.choose_grid(widths, 0.002) == (4.0, 0.0, 1, 2.5) and tt.choose_grid(widths, 0.06) == (4.0, 0.0, 1, None)
    assert tt.choose_min({0.25: 0.3411, 0.4: 0.3418, 0.0: 0.36}, 0.005) == 0.25
    assert tt.choose_listed({"excess": 0.70, 0.9: 0.774, 0.8: 0.7735}, ["excess", 0.9, 0.8], 0.002) == 0.9


def test_the_committed_profile_loads_and_bad_profiles_name_the_key(tmp_path):
    p = tt.load_profile(tt.DEFAULT_PROFILE)
    assert p.seeds == [100, 101, 102, 103, 104, 105] and p.real and p.seed == 1 and "dim" in p.kinds
    assert {e["scene"] for e in p.renders} == {"sphere", "plane"} and None in p.width_ratio
    text = tt.DEFAULT_PROFILE.read_text()
    bad = tmp_path / "bad.toml"
    for edit, message in ((("\nmin_run = [1, 5, 12]", "\nmin_run = [0]"), "`min_run` must be a non-empty list of integers"),
                          (('width_ratio = ["none", 4.0, 2.5]', 'width_ratio = ["wide"]'), "`width_ratio` must list distinct"),
                          (("seed = 1", "seed = -2"), "`seed` must be an integer >= 0, got -2"),
                          (("real = true", "real = true\nextra = 1"), "unknown key")):
        assert edit[0] in text, edit[0]
        bad.write_text(text.replace(*edit))
        with pytest.raises(ValueError, match=message):
            tt.load_profile(bad)


def _small_profile(tmp_path, renders=False):
    text = tt.DEFAULT_PROFILE.read_text()
    head, _, tail = text.partition("[render]")
    edits = (("seeds = [100, 101, 102, 103, 104, 105]", "seeds = [100]"),
             ('kinds = ["printed", "noisy_floor", "polished", "daylight", "noisy_sensor", "saturated_wide", "thin_faint", '
              '"plain",\n         "dim", "dark_room", "lamps_leds", "window", "skin", "short", "overlay", "lit_sphere"]',
              'kinds = ["dim", "noisy_sensor"]'),
             ("real = true", "real = false"),
             ('trackers = ["threshold", "centroid", "gauss3", "parabolic", "blais_rioux"]', 'trackers = ["threshold"]'),
             ("k_sigma = [3.0, 4.0, 6.0, 10.0]", "k_sigma = [4.0, 40.0]"),
             ("prominence = [0.0, 1.1, 1.5]", "prominence = [0.0]"),
             ("\nmin_run = [1, 5, 12]", "\nmin_run = [1, 5]"),
             ('width_ratio = ["none", 4.0, 2.5]', 'width_ratio = ["none"]'),
             ("frac = [0.0, 0.1, 0.25, 0.4, 0.5, 0.7]", "frac = [0.25]"),
             ("steger_k_sigma = [3.0, 4.0, 6.0, 8.0]", "steger_k_sigma = [4.0]"),
             ("steger_prominence = [0.0, 1.25]", "steger_prominence = [0.0]"),
             ("steger_min_run = [1, 5, 12]", "steger_min_run = [1]"),
             ('colour_trackers = ["threshold", "centroid", "gauss3", "parabolic", "blais_rioux", "com_bg", "steger"]',
              'colour_trackers = ["threshold"]'),
             ('colour_rules = ["excess", 1.0, 0.95, 0.9, 0.8, 0.7, 0.5, 0.0, "laser"]', 'colour_rules = ["excess", 0.9]'))
    for a, b in edits:
        assert a in head, a
        head = head.replace(a, b)
    render = "[render]\nwidth = 64\nheight = 60\nspp = 2\nn_angles = 2\n"
    if renders:
        render += '\n[[renders]]\nscene = "sphere"\nmaterial = "matte"\n'
    else:
        head = head.replace("seed = 1\n", "seed = 1\nrenders = []\n")
    prof = tmp_path / "small.toml"
    prof.write_text(head + render)
    return prof


def test_a_small_run_writes_its_files_and_chooses_from_its_grid(tmp_path):
    out = tmp_path / "out"
    assert _main(["tune", "threshold", "--profile", str(_small_profile(tmp_path)), "--out", str(out), "--quiet"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["n_frames"] == {"synthetic": 2, "renders": 0, "real": 0}
    assert summary["chosen"]["frac"] == 0.25 and summary["chosen"]["width_ratio"] is None
    assert (out / "tune.csv").read_text().startswith("stage,setting,tracker,group,kind,n_hit,n_wrong,n_missed,n_false")
    # k_sigma = 40 says "no stripe" on most of the dim stripe rows: its F1 is lower, it is never chosen
    s1 = summary["stage1"]
    assert s1["k_sigma=4,prominence=0,min_run=1,width_ratio=none"] > s1["k_sigma=40,prominence=0,min_run=1,width_ratio=none"]
    assert summary["chosen"]["k_sigma"] == 4.0
    fig = summary["figures"]["stage1"]["synthetic"]
    assert set(fig) == {"dim", "noisy_sensor", "all"} and 0 <= fig["all"]["false_report_rate"] <= 1
    # stage 5: the committed profile's stripe-question candidates, "none" (the trackers as they are) first
    s5 = summary["stage5"]  # chosen for each tracker of the profile's stripe_trackers
    assert list(s5) == ["threshold", "centroid", "gauss3", "parabolic", "blais_rioux", "com_bg", "steger"]
    n_tests = len(tt.load_profile(tt.DEFAULT_PROFILE).stripe_tests)  # the small profile keeps the shipped candidates
    assert all(list(v)[:2] == ["stripe_test=none", "stripe_test=defaults"] and len(v) == n_tests for v in s5.values())
    assert any(k.endswith("level_min=0.15") for k in s5["threshold"])
    assert set(summary["chosen"]["stripe_test"]) == set(s5)
    assert all(v is None or isinstance(v, dict) for v in summary["chosen"]["stripe_test"].values())
    assert set(summary["figures"]["stage5:threshold"]["synthetic"]) == {"dim", "noisy_sensor", "all"}
    # the ceiling is the profile's; without photographs no setting is held to it
    assert summary["max_false_rate"] == 0.1 and summary["above_false_rate_ceiling"] == {}
    # the stage's "none" is stage 1's choice, asked of the same frames: the same counts for threshold
    import csv

    with open(out / "tune.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    key1 = "k_sigma=4,prominence=0,min_run={m},width_ratio=none".format(m=summary["chosen"]["min_run"])
    counts = ("kind", "n_hit", "n_wrong", "n_missed", "n_false", "n_quiet")

    def pick(stage, setting):
        return sorted(tuple(r[k] for k in counts) for r in rows
                      if (r["stage"], r["setting"], r["tracker"]) == (stage, setting, "threshold"))

    assert pick("1", key1) and pick("1", key1) == pick("5", "stripe_test=none")


def test_the_stripe_stage_is_optional_and_its_candidates_are_checked(tmp_path):
    from bench.config.tune import stripe_stage

    text = tt.DEFAULT_PROFILE.read_text()
    assert stripe_stage({}) == ([], [])
    bad = tmp_path / "bad.toml"
    start = text.index("stripe_trackers =")
    end = text.index("\n\n[render]")
    for new, message in (('stripe_trackers = ["threshold"]', "`stripe_tests` must be given with `stripe_trackers`"),
                         ('stripe_trackers = ["threshold"]\nstripe_tests = ["none", "none"]', "must not repeat"),
                         ('stripe_trackers = ["threshold"]\nstripe_tests = [{width_ratio = 0.5}]',
                          r"`stripe_tests\[0\]`: `stripe_test`: `width_ratio` must be None or a number >= 1"),
                         ('stripe_trackers = ["threshold"]\nstripe_tests = [{wide = 1}]', "unknown setting"),
                         ('stripe_trackers = ["dp4x"]\nstripe_tests = ["none"]', "`stripe_trackers` must list"),
                         ('stripe_trackers = ["steger", "steger"]\nstripe_tests = ["none"]',
                          "`stripe_trackers` must not repeat a tracker")):
        bad.write_text(text[:start] + new + text[end:])
        with pytest.raises(ValueError, match=message):
            tt.load_profile(bad)
    bad.write_text(text[:start] + text[end:])
    p = tt.load_profile(bad)
    assert p.stripe_trackers == [] and p.stripe_tests == []


def test_the_false_report_ceiling_is_optional_and_checked(tmp_path):
    from bench.config.tune import load_gap_profile
    from bench.studies.hard_frames import KINDS
    from bench.studies.tune_gap import DEFAULT_PROFILE as GAP_PROFILE

    # both committed procedures hold every tracker to the 10 % where a setting can
    assert tt.load_profile(tt.DEFAULT_PROFILE).max_false_rate == 0.1
    assert load_gap_profile(GAP_PROFILE, KINDS).max_false_rate == 0.1
    text = tt.DEFAULT_PROFILE.read_text()
    bad = tmp_path / "bad.toml"
    for value in ("1.5", "-0.1", '"low"', "nan"):
        bad.write_text(text.replace("max_false_rate = 0.10", f"max_false_rate = {value}"))
        with pytest.raises(ValueError, match="`max_false_rate` must be"):
            tt.load_profile(bad)
    bad.write_text(text.replace("max_false_rate = 0.10\n", ""))
    assert tt.load_profile(bad).max_false_rate is None


@pytest.mark.slow
def test_renders_take_part(tmp_path):
    out = tmp_path / "out"
    chosen, summary, records = tt.run(tt.load_profile(_small_profile(tmp_path, renders=True)), out, progress=False)
    assert summary["n_frames"]["renders"] == 2
    assert any(r["group"] == "renders" and r["kind"] == "sphere-matte" for r in records)
