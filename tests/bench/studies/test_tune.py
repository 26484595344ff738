"""The h_weight tuning procedure: profile validation, scoring, the tie rule, a small run."""

import doctest
import pathlib

import numpy as np
import pytest

from bench.studies import tune
from bench.cli import main as _main

TINY = """\
name = "tiny"
seed = 1
trackers = ["dp4"]
h_weights = [1.0, 0.1]
hit_px = 3.0
tie = 0.005
seeds = [100]
kinds = ["plain"]
check_real = false
[render]
width = 64
height = 60
spp = 2
n_angles = 3
[[experiments]]
scene = "sphere"
material = "matte"
"""


def test_docstring_examples():
    result = doctest.testmod(tune, extraglobs={"np": np})
    assert result.attempted > 0 and result.failed == 0


def test_the_committed_profile_follows_the_rules():
    p = tune.load_profile(tune.DEFAULT_PROFILE)
    assert p.seed != 0 and 0 not in p.seeds
    assert {e["scene"] for e in p.experiments} == {"sphere", "plane"}  # never the paper's cone or hand
    assert {"matte", "patchy", "absorbing", "glossy", "specular"} <= {e["material"] for e in p.experiments}
    assert {e.get("background") for e in p.experiments} == {None, "none"}  # both geometries
    assert p.render["width"] == 512 and p.render["height"] == 480
    assert set(p.trackers) == {"dp4", "dp8"} and 1.0 in p.h_weights and 0.25 in p.h_weights
    assert p.kinds and p.seeds and p.check_real


@pytest.mark.parametrize(
    "edit, message",
    [
        (("seed = 1", "seed = -1"), r"`seed` must be an integer >= 0, got -1"),
        (("h_weights = [1.0, 0.1]", "h_weights = [1.0, 0]"), r"`h_weights` must be a non-empty list of finite"),
        (("h_weights = [1.0, 0.1]", "h_weights = [1.0, 1.0]"), r"`h_weights` must not repeat a value"),
        (('trackers = ["dp4"]', 'trackers = ["centroid"]'), r"`trackers` must name trackers with an h_weight"),
        (("tie = 0.005", "tie = 0.005\nbogus = 1"), r"`profile` has unknown key\(s\) \['bogus'\]"),
        (("hit_px = 3.0\n", ""), r"`profile` lacks the key 'hit_px'"),
        (("spp = 2\n", ""), r"`render` must have exactly the keys"),
        (('material = "matte"\n', ""), r"`experiments` entries need `scene` and `material`"),
        (('kinds = ["plain"]', 'kinds = ["nope"]'), r"`kinds` must be a list of printed, "),
        (("seeds = [100]", "seeds = [-1]"), r"`seeds` must be a list of integers >= 0"),
        (("check_real = false", "check_real = 1"), r"`check_real` must be"),
        (("check_real = false\n", ""), r"`profile` lacks the key 'check_real'"),
    ],
)
def test_bad_profiles_name_the_key(tmp_path, edit, message):
    path = tmp_path / "p.toml"
    path.write_text(TINY.replace(*edit))
    from bench.config import ConfigError

    with pytest.raises(ConfigError, match=message):
        tune.load_profile(path)


def test_a_missing_profile_is_one_line_and_status_2(tmp_path, capsys):
    assert _main(["tune", "dp", "--profile", str(tmp_path / "nope.toml"), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "cannot read tuning profile" in err[0] and "no such file" in err[0]


def test_ties_go_to_the_larger_h_weight():
    assert tune.choose({1.0: 0.5, 0.5: 0.7, 0.25: 0.704, 0.1: 0.69}, tie=0.005) == 0.5
    assert tune.choose({1.0: 0.5, 0.5: 0.7, 0.25: 0.71}, tie=0.005) == 0.25
    assert tune.choose({1.0: 0.5, 0.5: 0.7, 0.25: 0.71}, tie=0.0) == 0.25


def test_the_choice_is_the_objective_over_renders_and_synthetic_frames(tmp_path):
    """Both halves: each h_weight's score is the tuning objective of its pooled row outcomes (a false
    report lowers it as a miss does), the photographs are scored beside and never move it."""
    from bench.evaluate.outcomes import COUNT_KEYS, detection_figures
    from bench.studies import tuning

    path = tmp_path / "p.toml"
    path.write_text(TINY)
    profile = tune.load_profile(path)
    chosen, summary, records = tune.run(profile, tmp_path / "a", progress=False)
    assert set(summary["scores"]) == {"h_weight=1", "h_weight=0.1"} and summary["objective_groups"] == [
        "renders", "synthetic"]
    for key, figs in summary["figures"].items():
        assert set(figs) == {"renders", "synthetic"}
        counts = {g: np.array([f[k] for k in COUNT_KEYS]) for g, f in figs.items()}
        assert summary["scores"][key] == pytest.approx(tuning.objective(counts))
        for g, f in figs.items():
            assert f["false_report_rate"] == detection_figures(counts[g])["false_report_rate"]
            assert f["n_false"] + f["n_quiet"] > 0  # the frames have stripe-less rows: the false half is priced
    # the records are the figures' counts split by tracker and kind
    for key in summary["figures"]:
        for g in ("renders", "synthetic"):
            assert sum(r["n_false"] for r in records if r["setting"] == key and r["group"] == g) == \
                summary["figures"][key][g]["n_false"]
    eligible = {float(k.split("=")[1]): summary["scores"][k] for k in summary["eligible"]}
    assert chosen == tune.choose(eligible, profile.tie)
    head = (tmp_path / "a" / "tune.csv").read_text().splitlines()[0]
    assert head == ",".join(tuning.RECORD_FIELDS)
    assert (tmp_path / "a" / "tune_dp.png").stat().st_size > 1000
    # a pretend photograph group: scored beside (its own figures), the scores and the choice unchanged
    photo = tuning.TuningFrame("real", "p", "rig", np.full((40, 30), 10, np.uint8), None,
                               np.r_[np.full(20, 15.0), np.full(20, np.nan)],
                               np.r_[np.ones(20, np.int8), np.zeros(20, np.int8)])
    photo.image[:20, 15] = 200
    photo.image[20:, 3] = 90  # a bright line where there is no stripe: a report there is false
    import unittest.mock as mock

    with mock.patch.object(tuning, "real_frames", return_value=[photo]):
        profile.check_real = True
        chosen2, summary2, _ = tune.run(profile, tmp_path / "b", progress=False)
    assert chosen2 == chosen and summary2["scores"] == summary["scores"]
    assert all("real" in figs for figs in summary2["figures"].values())
    lines = tune.table_lines(summary2, [1.0, 0.1], 0.1)
    assert "real (beside, not in the objective)" in lines[0] and len(lines) == 3


def test_stripebench_tune_dp_runs_the_procedure(tmp_path, capsys):
    from bench.cli import main

    path = tmp_path / "p.toml"
    path.write_text(TINY)
    assert main(["tune", "dp", "--profile", str(path), "--out", str(tmp_path / "o"), "--quiet"]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    assert out[0].startswith("frames: synthetic 1, renders 3, real 0; objective: the mean over renders, synthetic")
    assert out[-1].startswith("chosen h_weight = ") and "recall" in out[2] and "false reports" in out[2]
    assert (tmp_path / "o" / "tune.csv").is_file()
    assert main(["tune", "dp", "--profile", str(tmp_path / "nope.toml"), "--out", str(tmp_path / "o")]) == 2
