"""dp_gap's tuning procedure: profile validation, scoring, the tie rule, a small run."""

import doctest

import numpy as np
import pytest

from bench.studies import tune_gap

TINY = """\
name = "tiny"
seed = 1
tracker = "dp_gap"
references = ["dp8"]
off_rel = [0.1, 0.3]
switch_rows = [3.0]
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
    assert p.tracker == "dp_gap" and set(p.references) == {"dp4", "dp8"}


@pytest.mark.parametrize(
    "edit, message",
    [
        (("seed = 1", "seed = -1"), r"`seed` must be an integer >= 0, got -1"),
        (("off_rel = [0.1, 0.3]", "off_rel = [0.1, 1.5]"), r"`off_rel` must be a non-empty list of finite numbers in"),
        (("off_rel = [0.1, 0.3]", "off_rel = [0.1, 0.1]"), r"`off_rel` must not repeat a value"),
        (("switch_rows = [3.0]", "switch_rows = [-1.0]"), r"`switch_rows` must be a non-empty list"),
        (('tracker = "dp_gap"', 'tracker = "dp8"'), r"`tracker` must name a tracker with off_rel"),
        (('references = ["dp8"]', 'references = ["nope"]'), r"`references` must be a list of registered"),
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
    assert tune_gap.main(["--profile", str(tmp_path / "nope.toml"), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "cannot read tuning profile" in err[0] and "no such file" in err[0]


def test_score_counts_wrong_reports_anywhere_and_misses_as_neutral():
    truth = np.array([[10.0, 20.0, 30.0, np.nan], [5.0, 5.0, 5.0, 5.0]])
    on = np.array([[True, True, True, True], [False, True, False, False]])
    cols = np.array([[13.0, np.nan, 33.5, 1.0], [50.0, 2.5, 5.0, np.nan]])
    # lit object rows: (0,0) hit, (0,1) missed, (0,2) 3.5 px off: wrong, (1,1) hit -> h = 2/4
    # wrong: (0,2), (0,3) reported without truth, (1,0) 45 px off the background's truth -> w = 3/4
    assert tune_gap.gap_score(cols, truth, on, 3.0) == (0.5, 0.75, 4)
    assert np.isnan(tune_gap.gap_score(cols, truth, np.zeros_like(on), 3.0)[0])


def test_ties_go_to_the_smallest_off_rel_then_the_largest_switch():
    s = {(0.1, 3.0): 0.60, (0.1, 10.0): 0.598, (0.05, 3.0): 0.55, (0.3, 3.0): 0.603}
    assert tune_gap.choose(s, tie=0.005) == (0.1, 10.0)
    assert tune_gap.choose(s, tie=0.0) == (0.3, 3.0)


@pytest.mark.slow
def test_stripebench_tune_dp_gap_runs_the_procedure(tmp_path, capsys):
    from bench.cli import main

    path = tmp_path / "p.toml"
    path.write_text(TINY)
    out = tmp_path / "o"
    assert main(["tune", "dp_gap", "--profile", str(path), "--out", str(out), "--quiet"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert lines[-1].startswith("chosen off_rel = ") and lines[1].startswith("sphere-matte")
    rows = (out / "tune_gap.csv").read_text().strip().splitlines()
    assert rows[0] == "off_rel,switch_rows,tracker,experiment,hit_fraction,wrong_fraction,score,rows"
    assert len(rows) == 1 + 3  # two grid points and one reference
    assert (out / "tune_dp_gap.png").stat().st_size > 1000
    assert main(["tune", "dp_gap", "--profile", str(tmp_path / "nope.toml"), "--out", str(out)]) == 2
