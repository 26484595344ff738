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
    assert p.seed != 0
    assert {e["scene"] for e in p.experiments} == {"sphere", "plane"}
    assert {e["material"] for e in p.experiments} == {"matte", "patchy", "absorbing", "glossy"}
    assert p.render["width"] == 512 and p.render["height"] == 480
    assert set(p.trackers) == {"dp4", "dp8"} and 1.0 in p.h_weights


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


def test_hit_fraction_counts_missed_rows_as_misses():
    truth = np.array([[10.0, 20.0, 30.0, np.nan], [5.0, 5.0, 5.0, 5.0]])
    on = np.array([[True, True, True, True], [False, True, False, False]])
    cols = np.array([[13.0, np.nan, 33.5, 1.0], [50.0, 2.5, 5.0, 5.0]])
    # lit rows: (0,0) hit at 3 px, (0,1) missed, (0,2) 3.5 px off, (1,1) 2.5 px: hit; (0,3) has no truth
    assert tune.hit_fraction(cols, truth, on, 3.0) == (0.5, 4)
    assert np.isnan(tune.hit_fraction(cols, truth, np.zeros_like(on), 3.0)[0])


def test_ties_go_to_the_larger_h_weight():
    assert tune.choose({1.0: 0.5, 0.5: 0.7, 0.25: 0.704, 0.1: 0.69}, tie=0.005) == 0.5
    assert tune.choose({1.0: 0.5, 0.5: 0.7, 0.25: 0.71}, tie=0.005) == 0.25
    assert tune.choose({1.0: 0.5, 0.5: 0.7, 0.25: 0.71}, tie=0.0) == 0.25


@pytest.mark.slow
def test_a_small_run_writes_its_outputs_and_resumes(tmp_path, capsys):
    path = tmp_path / "p.toml"
    path.write_text(TINY + '\n[[experiments]]\nscene = "plane"\nmaterial = "absorbing"\nambient_lux = 200\n')
    out = tmp_path / "out"
    assert _main(["tune", "dp", "--profile", str(path), "--out", str(out), "--quiet"]) == 0
    line = capsys.readouterr().out.strip().splitlines()
    assert len(line) == 1 and line[0].startswith("chosen h_weight = ")
    rows = (out / "tune.csv").read_text().strip().splitlines()
    assert rows[0] == "h_weight,tracker,experiment,hit_fraction,rows" and len(rows) == 1 + 2 * 2
    assert "plane-absorbing_ambient_lux=200" in (out / "tune.csv").read_text()
    assert (out / "tune_dp.png").stat().st_size > 1000
    ckpts = sorted(p.name for p in (out / "checkpoints").iterdir())
    assert ckpts == ["plane-absorbing_ambient_lux=200.npz", "sphere-matte.npz"]
    stamps = {p: p.stat().st_mtime_ns for p in (out / "checkpoints").iterdir()}
    chosen, scores, _ = tune.run(tune.load_profile(path), out, progress=False)
    assert chosen in (1.0, 0.1) and set(scores) == {1.0, 0.1}
    # resumed from the checkpoints: nothing re-rendered, the checkpoints rewritten with the same content
    assert all(pathlib.Path(p).exists() for p in stamps)


def test_stripebench_tune_dp_runs_the_procedure(tmp_path, capsys):
    from bench.cli import main

    path = tmp_path / "p.toml"
    path.write_text(TINY)
    assert main(["tune", "dp", "--profile", str(path), "--out", str(tmp_path / "o"), "--quiet"]) == 0
    assert capsys.readouterr().out.startswith("chosen h_weight = ")
    assert (tmp_path / "o" / "tune.csv").is_file()
    assert main(["tune", "dp", "--profile", str(tmp_path / "nope.toml"), "--out", str(tmp_path / "o")]) == 2
