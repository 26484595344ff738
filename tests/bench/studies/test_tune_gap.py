"""dp_gap's tuning procedure: profile validation, scoring, the tie rule, a small run."""

import doctest

import numpy as np
import pytest

from bench.studies import tune_gap
from bench.cli import main as _main

TINY = """\
name = "tiny"
seed = 1
tracker = "dp_gap"
off_rel = [0.1, 0.3]
switch_rows = [3.0]
dp_trackers = ["dp8"]
k_sigma = [3.0, 6.0]
max_gap = ["none", 10]
min_run = [1, 5]
seeds = [100]
kinds = ["dim", "printed"]
real = false
hit_px = 3.0
tie = 0.005
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
    result = doctest.testmod(tune_gap, extraglobs={"np": np})
    assert result.attempted > 0 and result.failed == 0


def test_the_committed_profile_follows_the_rules():
    p = tune_gap.load_profile(tune_gap.DEFAULT_PROFILE)
    assert p.seed != 0
    assert {e["scene"] for e in p.experiments} == {"sphere", "plane"}
    assert {"specular", "absorbing", "patchy"} <= {e["material"] for e in p.experiments}
    assert {e.get("background", "wall") for e in p.experiments} == {"wall", "none"}
    assert p.render["width"] == 512 and p.render["height"] == 480
    assert p.tracker == "dp_gap" and set(p.dp_trackers) == {"dp4", "dp8"}
    assert p.real and min(p.seeds) >= 100 and "dim" in p.kinds and None in p.max_gap


@pytest.mark.parametrize(
    "edit, message",
    [
        (("seed = 1", "seed = -1"), r"`seed` must be an integer >= 0, got -1"),
        (("off_rel = [0.1, 0.3]", "off_rel = [0.1, 1.5]"), r"`off_rel` must be a non-empty list of finite numbers in"),
        (("off_rel = [0.1, 0.3]", "off_rel = [0.1, 0.1]"), r"`off_rel` must not repeat a value"),
        (("switch_rows = [3.0]", "switch_rows = [-1.0]"), r"`switch_rows` must be a non-empty list"),
        (('tracker = "dp_gap"', 'tracker = "dp8"'), r"`tracker` must name a tracker with off_rel"),
        (('dp_trackers = ["dp8"]', 'dp_trackers = ["threshold"]'), r"`dp_trackers` must list trackers with k_sigma"),
        (('max_gap = ["none", 10]', 'max_gap = ["all"]'), r"`max_gap` must list distinct integers >= 0 or 'none'"),
        (('kinds = ["dim", "printed"]', 'kinds = ["snow"]'), r"`kinds` must be a list of"),
        (("min_run = [1, 5]", "min_run = [0]"), r"`min_run` must be a non-empty list of integers >= 1"),
        (("tie = 0.005", "tie = 0.005\nbogus = 1"), r"`profile` has unknown key\(s\) \['bogus'\]"),
        (("hit_px = 3.0\n", ""), r"`profile` lacks the key 'hit_px'"),
        (("spp = 2\n", ""), r"`render` must have exactly the keys"),
        (('material = "matte"\n', ""), r"`experiments` entries need `scene` and `material`"),
    ],
)
def test_bad_profiles_name_the_key(tmp_path, edit, message):
    path = tmp_path / "p.toml"
    path.write_text(TINY.replace(*edit))
    with pytest.raises(ValueError, match=message):
        tune_gap.load_profile(path)


def test_a_missing_profile_is_one_line_and_status_2(tmp_path, capsys):
    assert _main(["tune", "dp_gap", "--profile", str(tmp_path / "nope.toml"), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "cannot read tuning profile" in err[0] and "no such file" in err[0]


def test_ties_go_to_the_smallest_off_rel_then_the_largest_switch():
    s = {(0.1, 3.0): 0.60, (0.1, 10.0): 0.598, (0.05, 3.0): 0.55, (0.3, 3.0): 0.603}
    assert tune_gap.choose(s, tie=0.005) == (0.1, 10.0)
    assert tune_gap.choose(s, tie=0.0) == (0.3, 3.0)
    # with the level quantile in the grid: then the smallest quantile (None, not in the grid, first)
    q = {(0.1, 10.0, 0.9): 0.60, (0.1, 10.0, 0.75): 0.599, (0.3, 3.0, 0.5): 0.601}
    assert tune_gap.choose(q, tie=0.005) == (0.1, 10.0, 0.75)
    assert tune_gap.choose({(0.1, 3.0, None): 0.6, (0.1, 3.0, 0.5): 0.6}, tie=0.0) == (0.1, 3.0, None)


def test_the_level_quantile_is_an_optional_dimension_of_stage_1(tmp_path):
    path = tmp_path / "p.toml"
    path.write_text(TINY)
    assert tune_gap.load_profile(path).level_quantile is None
    path.write_text(TINY.replace("switch_rows = [3.0]", "switch_rows = [3.0]\nlevel_quantile = [0.5, 0.9]"))
    assert tune_gap.load_profile(path).level_quantile == [0.5, 0.9]
    assert tune_gap.load_profile(tune_gap.DEFAULT_PROFILE).level_quantile == [0.5, 0.75, 0.9]
    for value, message in (("[1.5]", "`level_quantile` must be a non-empty list"),
                           ("[0.5, 0.5]", "`level_quantile` must not repeat a value")):
        path.write_text(TINY.replace("switch_rows = [3.0]", f"switch_rows = [3.0]\nlevel_quantile = {value}"))
        with pytest.raises(ValueError, match=message):
            tune_gap.load_profile(path)


def test_rule_ties_go_to_the_rule_closest_to_the_paper():
    s = {(3.0, None, 1): 0.80, (3.0, 10, 1): 0.801, (3.0, 20, 5): 0.80, (6.0, None, 5): 0.70}
    assert tune_gap.choose_rule(s, tie=0.002) == (3.0, None, 1)  # no max_gap: bridges every row
    assert tune_gap.choose_rule(s, tie=0.0) == (3.0, 10, 1)


@pytest.mark.slow
def test_stripebench_tune_dp_gap_runs_the_procedure(tmp_path, capsys):
    from bench.cli import main

    path = tmp_path / "p.toml"
    path.write_text(TINY)
    out = tmp_path / "o"
    assert main(["tune", "dp_gap", "--profile", str(path), "--out", str(out), "--quiet"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert lines[0].startswith("frames: {'synthetic': 2, 'renders': 3, 'real': 0}")
    assert any(x.startswith("stage1 (dp_gap): chosen off_rel=") for x in lines)
    assert any(x.startswith("stage2 (dp8): chosen k_sigma=") for x in lines)
    rows = (out / "tune_gap.csv").read_text().strip().splitlines()
    assert rows[0] == ("stage,setting,tracker,group,kind,n_hit,n_wrong,n_missed,n_false,n_quiet,n_unknown,precision,"
                       "recall,f1,false_report_rate")
    # stage 1: 2 settings x (1 render kind + 2 synthetic kinds); stage 2: 8 rules x the same 3 kinds
    assert len(rows) == 1 + 2 * 3 + 8 * 3
    import json

    s = json.loads((out / "summary.json").read_text())
    assert set(s["stage2"]) == {f"k_sigma={k:g},max_gap={g},min_run={m}" for k in (3, 6) for g in ("none", 10)
                                for m in (1, 5)}
    assert s["chosen"]["max_gap"] in (None, 10) and s["chosen"]["off_rel"] in (0.1, 0.3)
    # the rule's stage scores the readings of one solve: the same as the tracker made with that rule
    assert (out / "tune_dp_gap.png").stat().st_size > 1000
    assert main(["tune", "dp_gap", "--profile", str(tmp_path / "nope.toml"), "--out", str(out)]) == 2


@pytest.mark.slow
def test_the_stripe_stage_runs_with_the_choices_of_stages_one_and_two(tmp_path, capsys):
    from bench.cli import main

    path = tmp_path / "p.toml"
    text = TINY.replace('kinds = ["dim", "printed"]', 'kinds = ["dim", "lamps_leds"]').replace(
        "[render]", 'stripe_trackers = ["dp8", "dp_gap"]\nstripe_tests = ["none", {}]\n[render]')
    path.write_text(text)
    out = tmp_path / "o"
    assert main(["tune", "dp_gap", "--profile", str(path), "--out", str(out), "--quiet"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert any(x.startswith("stage3 (dp8): chosen stripe_test=") for x in lines)
    assert any(x.startswith("stage3 (dp_gap): chosen stripe_test=") for x in lines)
    import json

    s = json.loads((out / "summary.json").read_text())
    assert list(s["stage3"]) == ["dp8", "dp_gap"]  # chosen for each tracker
    assert all(list(v) == ["stripe_test=none", "stripe_test=defaults"] for v in s["stage3"].values())
    assert set(s["chosen"]["stripe_test"]) == {"dp8", "dp_gap"}
    assert all(v in (None, {}) for v in s["chosen"]["stripe_test"].values())
    assert {"stage3:dp8", "stage3:dp_gap"} <= set(s["photographs"]) and "stage3:dp8" in s["figures"]
    rows = [r.split(",") for r in (out / "tune_gap.csv").read_text().strip().splitlines()[1:] if r.startswith("3,")]
    assert {r[2] for r in rows} == {"dp8", "dp_gap"} and {r[3] for r in rows} == {"synthetic", "renders"}


@pytest.mark.slow
def test_stage_1_with_the_level_quantile_chooses_it_and_stage_3_uses_it(tmp_path):
    import json

    from bench.cli import main

    path = tmp_path / "p.toml"
    path.write_text(TINY.replace("switch_rows = [3.0]", "switch_rows = [3.0]\nlevel_quantile = [0.5, 0.9]"))
    out = tmp_path / "o"
    assert main(["tune", "dp_gap", "--profile", str(path), "--out", str(out), "--quiet"]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert set(s["stage1"]) == {f"off_rel={o:g},switch_rows=3,level_quantile={q:g}" for o in (0.1, 0.3)
                                for q in (0.5, 0.9)}
    assert s["chosen"]["level_quantile"] in (0.5, 0.9)
    assert (out / "tune_dp_gap.png").stat().st_size > 0
