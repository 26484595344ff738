"""bench.run.export: the frame set of a configuration, byte-stable for one seed."""

import copy
import csv
import json

import numpy as np
import pytest

from bench.store import frameset as fs
from bench.store.runfolder import RunFolderError


def _files(root):
    return {p.relative_to(root).as_posix(): p.read_bytes() for p in sorted(root.rglob("*"))
            if p.is_file() and p.name != ".lock"}


def test_export_is_byte_stable_for_one_seed(tiny_export, tiny_dict, tmp_path):
    from bench.config import parse
    from bench.run.export import export

    again = export(parse(tiny_dict), tmp_path / "again", quiet=True)
    a, b = _files(tiny_export), _files(again)
    assert sorted(a) == sorted(b)
    assert [k for k in a if a[k] != b[k]] == []


def test_export_writes_the_frames_a_tracker_gets_in_a_run(tiny_export, tiny_dict):
    from bench.config import parse
    from bench.run.plan import angles_for, scene_for

    cfg = parse(tiny_dict)
    fset = fs.read_frameset(tiny_export)
    exp = cfg.experiments[0]
    scene = scene_for(exp, cfg)
    frames = fset.frames_of(exp.key)
    assert [f["angle_deg"] for f in frames] == angles_for(exp, scene).tolist()
    frame = scene.render(frames[1]["angle_deg"], spp=scene.params["spp"], seed=cfg.seed)
    assert frame.image.dtype == np.uint8
    np.testing.assert_array_equal(fs.read_png(tiny_export / frames[1]["image"]), frame.image)
    np.testing.assert_array_equal(fs.read_png(tiny_export / frames[1]["background"]), frame.background)
    cols, pts, on, _ = fs.read_truth(fset.truth_path(frames[1]), 60, None)
    np.testing.assert_array_equal(cols, frame.truth.columns)  # exact: repr round-trips
    np.testing.assert_array_equal(pts, frame.truth.points_cm)
    np.testing.assert_array_equal(on, frame.truth.on_object)


def test_dataset_json_and_frames_csv_describe_the_set(tiny_export):
    meta = json.loads((tiny_export / "dataset.json").read_text())
    assert meta["format"] == fs.FORMAT and meta["profile"] == "tiny" and meta["images"]["dtype"] == "uint8"
    assert [e["key"] for e in meta["experiments"]] == ["cone-patchy", "plane-absorbing"]
    assert meta["experiments"][0]["rig"]["width"] == 64
    with (tiny_export / "frames.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == list(fs.FRAME_COLUMNS)
    assert [r["frame"] for r in rows] == ["cone-patchy-000", "cone-patchy-001", "cone-patchy-002",
                                          "plane-absorbing-000", "plane-absorbing-001"]
    for r in rows:  # each frame's truth is in its split's folder only
        assert r["split"] == fs.split_of(r["frame"], 1, 0.3)
        assert (tiny_export / fs.TRUTH_DIRS[r["split"]] / f"{r['frame']}.csv").is_file()
        other = "test" if r["split"] == "dev" else "dev"
        assert not (tiny_export / fs.TRUTH_DIRS[other] / f"{r['frame']}.csv").exists()
    assert meta["split"]["dev"] + meta["split"]["test"] == 5


def test_export_refuses_another_runs_folder(tiny_run, tiny_dict):
    from bench.config import parse
    from bench.run.export import export

    with pytest.raises(RunFolderError, match="holds a run"):
        export(parse(tiny_dict), tiny_run[0], quiet=True)


def test_export_refuses_a_bad_test_fraction(tiny_dict, tmp_path):
    from bench.config import parse
    from bench.run.export import export

    with pytest.raises(ValueError, match="test_fraction"):
        export(parse(copy.deepcopy(tiny_dict)), tmp_path / "x", test_fraction=1.5, quiet=True)


def test_a_colour_camera_is_refused_before_anything_is_rendered(tiny_dict, tmp_path):
    """Issue 37 item 7: it was refused only after the earlier experiments' frames were written."""
    from bench.config import parse
    from bench.errors import InputError
    from bench.run.export import export

    d = copy.deepcopy(tiny_dict)
    d["experiments"] = [d["experiments"][0], {**d["experiments"][0], "name": "colour", "camera": "rgb"}]
    with pytest.raises(InputError, match=r"experiment 'colour' has a colour camera \(camera = 'rgb'\)"):
        export(parse(d), tmp_path / "x", quiet=True)
    assert not (tmp_path / "x").exists()


def test_a_participants_bundle_withholds_the_test_truth(tiny_run, tiny_export, tmp_path):
    """Issue 37 item 10: the organiser keeps the frame set, participants get it without truth_test/."""
    from bench.run.export import participants_bundle
    from bench.run.score import score

    bundle = participants_bundle(tiny_export, tmp_path / "bundle")
    assert (bundle / "truth").is_dir() and not (bundle / "truth_test").exists()
    assert sorted(p.name for p in (bundle / "images").iterdir()) == sorted(p.name for p in (tiny_export / "images").iterdir())
    meta = json.loads((bundle / "dataset.json").read_text())
    assert meta["test_truth"] == "withheld" and meta["config_hash"] == json.loads(
        (tiny_export / "dataset.json").read_text())["config_hash"]
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "submission.csv").write_text("frame,row,col\n")
    with pytest.raises(fs.FrameSetError, match="participants' bundle: its test truth is withheld"):
        score(bundle, sub, tmp_path / "run", trackers=(), quiet=True)
    assert (score(bundle, sub, tmp_path / "dev", trackers=(), split="dev", quiet=True) / "metrics.csv").is_file()
    with pytest.raises(fs.FrameSetError, match="a participants' bundle already"):
        participants_bundle(bundle, tmp_path / "again")
