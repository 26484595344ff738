"""bench.store.frameset: the split, the truth files, and every problem class of the submission validator."""

import json

import numpy as np
import pytest

from bench.store import frameset as fs
from bench.store.files import RunFolderError


META = {"format": fs.FORMAT, "kind": "stripebench-frames", "config": {}, "config_hash": "0123456789",
        "experiments": [{"key": "e", "rig": {}, "variant": "scalar_rgb", "false_stripes": False}]}


@pytest.fixture
def fset(tmp_path):
    """A hand-made frame set of two frames (4 rows x 6 columns), no images needed."""
    root = tmp_path / "set"
    root.mkdir()
    fs.write_dataset_json(root / "dataset.json", META)
    rows = [{"frame": f"e-00{i}", "image": f"images/e-00{i}.png", "background": f"images/e-00{i}_off.png",
             "experiment": "e", "condition": "e", "split": "dev", "angle_deg": 1.5 * i, "height": 4, "width": 6}
            for i in range(2)]
    fs.write_frames_csv(root / "frames.csv", rows)
    return fs.read_frameset(root)


def _sub(tmp_path, text, times=None):
    d = tmp_path / "sub"
    d.mkdir(exist_ok=True)
    (d / "submission.csv").write_text(text)
    if times is not None:
        (d / "times.csv").write_text(times)
    return d


def test_split_is_seeded_stable_and_near_its_fraction():
    ids = [f"x-{i:03d}" for i in range(2000)]
    a = [fs.split_of(f, 3, 0.3) for f in ids]
    assert a == [fs.split_of(f, 3, 0.3) for f in ids]
    assert a != [fs.split_of(f, 4, 0.3) for f in ids]
    assert 0.26 < a.count("test") / len(a) < 0.34
    with pytest.raises(ValueError, match="test_fraction"):
        fs.split_of("x", 0, -0.1)


def test_truth_round_trips_exactly(tmp_path):
    rng = np.random.default_rng(0)
    cols = rng.uniform(0, 6, 5)
    cols[1] = np.nan
    pts = rng.normal(size=(5, 3))
    pts[1] = np.nan
    part = np.array([1, -1, 2, 0, 1])
    false = np.full((5, 3), np.nan)
    false[1, :2] = [0.1, 1.0 / 3.0]
    (tmp_path / "t.csv").write_text(fs.truth_csv(cols, pts, part, false))
    c, p, on, f = fs.read_truth(tmp_path / "t.csv", 5, 8)
    np.testing.assert_array_equal(c, cols)
    np.testing.assert_array_equal(p, pts)
    assert on.tolist() == [True, False, False, False, True]
    np.testing.assert_array_equal(f[:, :3], false)
    assert np.isnan(f[:, 3:]).all()


def test_a_valid_submission_reads_back(fset, tmp_path):
    sub, problems = fs.read_submission(_sub(tmp_path, "frame,row,col,score\ne-000,0,1.25,3\ne-000,2,,\ne-001,3,5.5,\n",
                                            "frame,ms\ne-000,2.5\n"), fset)
    assert problems == []
    np.testing.assert_array_equal(sub.columns["e-000"], [1.25, np.nan, np.nan, np.nan])
    np.testing.assert_array_equal(sub.columns["e-001"], [np.nan, np.nan, np.nan, 5.5])
    assert sub.scores["e-000"][0] == 3.0 and sub.ms["e-000"] == 2.5 and np.isnan(sub.ms["e-001"])


@pytest.mark.parametrize("line, problem", [
    ("nope,0,1.0,", "unknown frame 'nope'"),
    ("e-000,4,1.0,", "row 4 out of range [0, 4)"),
    ("e-000,-1,1.0,", "row -1 out of range"),
    ("e-000,1.5,1.0,", "row '1.5' is not an integer"),
    ("e-000,0,abc,", "col 'abc' is not a finite number"),
    ("e-000,0,nan,", "col 'nan' is not a finite number"),
    ("e-000,0,inf,", "col 'inf' is not a finite number"),
    ("e-000,0,5.6,", "col 5.6 outside the image"),
    ("e-000,0,-0.6,", "col -0.6 outside the image"),
    ("e-000,0,1.0,x", "score 'x' is not a finite number"),
    ("e-000,0", "2 fields, the header has 4"),
])
def test_each_problem_class_is_one_line(fset, tmp_path, line, problem):
    sub, problems = fs.read_submission(_sub(tmp_path, f"frame,row,col,score\n{line}\n"), fset)
    assert sub is None and len(problems) == 1
    assert problem in problems[0] and "submission.csv line 2" in problems[0]


def test_duplicate_rows_and_every_problem_are_reported(fset, tmp_path):
    sub, problems = fs.read_submission(_sub(tmp_path, "frame,row,col\ne-000,0,1\ne-000,0,2\nnope,0,1\ne-001,9,1\n"),
                                       fset)
    assert sub is None
    assert [p.split(": ", 1)[1] for p in problems] == [
        "duplicate row 0 of frame 'e-000'", "unknown frame 'nope'", "row 9 out of range [0, 4) of frame 'e-001'"]


def test_missing_header_columns_and_files(fset, tmp_path):
    _, problems = fs.read_submission(_sub(tmp_path, "frame,col\ne-000,1\n"), fset)
    assert problems == [f"{tmp_path / 'sub' / 'submission.csv'} line 1: missing header column(s) row "
                        "(expected frame,row,col[,score], got 'frame,col')"]
    _, problems = fs.read_submission(tmp_path / "none", fset)
    assert "must be a folder" in problems[0]
    (tmp_path / "empty").mkdir()
    _, problems = fs.read_submission(tmp_path / "empty", fset)
    assert "submission.csv: missing" in problems[0]


@pytest.mark.parametrize("times, problem", [
    ("frame\ne-000\n", "missing header column(s) ms"),
    ("frame,ms\nnope,1\n", "unknown frame 'nope'"),
    ("frame,ms\ne-000,1\ne-000,2\n", "duplicate frame 'e-000'"),
    ("frame,ms\ne-000,-1\n", "ms '-1' is not a finite number >= 0"),
    ("frame,ms\ne-000,inf\n", "ms 'inf' is not a finite number >= 0"),
])
def test_times_problems(fset, tmp_path, times, problem):
    sub, problems = fs.read_submission(_sub(tmp_path, "frame,row,col\n", times), fset)
    assert sub is None and len(problems) == 1 and problem in problems[0] and "times.csv" in problems[0]


def test_read_frameset_refuses_what_is_not_one(tmp_path, fset):
    with pytest.raises(fs.FrameSetError, match="with dataset.json"):
        fs.read_frameset(tmp_path)
    doc = json.loads((fset.root / "dataset.json").read_text())
    (fset.root / "dataset.json").write_text(json.dumps(dict(doc, format=9)))
    with pytest.raises(RunFolderError, match="format 9"):
        fs.read_frameset(fset.root)


def test_a_spreadsheet_saved_submission_reads_back_and_a_huge_cell_is_one_line(fset, tmp_path):
    from bench.store.textfiles import MAX_CSV_FIELD

    for d in "abc":
        (tmp_path / d).mkdir()
    plain, _ = fs.read_submission(_sub(tmp_path / "a", "frame,row,col,score\ne-000,0,1.25,3\n"), fset)
    bom, problems = fs.read_submission(_sub(tmp_path / "b", "\ufeffframe,row,col,score\r\ne-000,0,1.25,3\r\n"), fset)
    assert problems == [] and np.array_equal(bom.columns["e-000"], plain.columns["e-000"], equal_nan=True)
    huge = "frame,row,col\n" + "e-000,0," + "1" * (MAX_CSV_FIELD + 1) + "\n"
    sub, problems = fs.read_submission(_sub(tmp_path / "c", huge), fset)
    assert sub is None and len(problems) == 1 and "a field is longer than" in problems[0]
