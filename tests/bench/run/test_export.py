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
    """The organiser writes the set again, byte for byte, from its seed and the test seed it keeps."""
    from bench.config import parse
    from bench.run.export import WITHHELD, export

    kept = json.loads((tiny_export / fs.TRUTH_DIRS["test"] / WITHHELD).read_text())["test_seed"]
    again = export(parse(tiny_dict), tmp_path / "again", test_seed=kept, quiet=True)
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
    nominal = angles_for(exp, scene).tolist()
    assert [f["angle_deg"] for f in frames if f["split"] == "dev"] == [a for a, f in zip(nominal, frames)
                                                                      if f["split"] == "dev"]
    frames = [f for f in frames if f["split"] == "dev"]  # the run's frames (test frames: test_frame's angles)
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


def test_the_bundle_does_not_let_export_render_the_test_truth_again(tiny_export, tmp_path):
    """Issue 66: everything a participants' bundle holds (the configuration, the seed, the test fraction) exports a
    set whose test truth is not the withheld one; the test seed and the test frames' angles are nowhere in it."""
    from bench.config import parse
    from bench.run.export import WITHHELD, export, participants_bundle

    bundle = participants_bundle(tiny_export, tmp_path / "bundle")
    meta = json.loads((bundle / "dataset.json").read_text())
    cfg = parse(meta["config"], "dataset.json", machine=False)
    assert cfg.seed == meta["seed"]
    again = export(cfg, tmp_path / "again", test_fraction=meta["split"]["test_fraction"], quiet=True)
    test_dir = fs.TRUTH_DIRS["test"]
    withheld = sorted(p.name for p in (tiny_export / test_dir).glob("*.csv"))
    assert withheld and withheld == sorted(p.name for p in (again / test_dir).glob("*.csv"))
    # a test frame whose stripe lands on no object row has a header-only truth under any draw: it tells nothing, and
    # two draws may both give it; every truth that holds a stripe row differs
    pairs = [((tiny_export / test_dir / n).read_bytes(), (again / test_dir / n).read_bytes()) for n in withheld]
    holding = [(a, b) for a, b in pairs if a.count(b"\n") > 1 or b.count(b"\n") > 1]
    assert any(a.count(b"\n") > 1 for a, _ in holding) and all(a != b for a, b in holding)
    dev = sorted(p.name for p in (tiny_export / fs.TRUTH_DIRS["dev"]).glob("*.csv"))
    assert all((tiny_export / "truth" / n).read_bytes() == (again / "truth" / n).read_bytes() for n in dev)
    # nothing in the bundle names the test seed or a test frame's angle
    kept = json.loads((tiny_export / test_dir / WITHHELD).read_text())["test_seed"]
    full = fs.read_frameset(tiny_export)
    test_angles = [f["angle_deg"] for f in full.frames if f["split"] == "test"]
    texts = [p.read_bytes() for p in bundle.rglob("*") if p.is_file()]
    assert not any(str(kept).encode() in t for t in texts)
    assert not any(repr(a).encode() in t for a in test_angles for t in texts)
    shown = fs.read_frameset(bundle)
    assert all(np.isnan(f["angle_deg"]) == (f["split"] == "test") for f in shown.frames)
    assert all(a is None for e in meta["experiments"] for a, f in zip(e["angles_deg"], shown.frames_of(e["key"]))
               if f["split"] == "test")


def test_a_frame_without_an_angle_is_refused_outside_a_bundles_test_split(tiny_export, tmp_path):
    import shutil

    root = tmp_path / "set"
    shutil.copytree(tiny_export, root)
    rows = (root / "frames.csv").read_text().splitlines()
    head = rows[0].split(",")
    dev = next(i for i, r in enumerate(rows[1:], 1) if r.split(",")[head.index("split")] == "dev")
    cells = rows[dev].split(",")
    cells[head.index("angle_deg")] = ""
    rows[dev] = ",".join(cells)
    (root / "frames.csv").write_text("\n".join(rows) + "\n")
    with pytest.raises(fs.FrameSetError, match=rf"line {dev + 1}: angle_deg must be a finite number"):
        fs.read_frameset(root)


def test_export_refuses_a_bad_test_seed(tiny_dict, tmp_path):
    from bench.config import parse
    from bench.errors import InputError
    from bench.run.export import export

    for bad in (-1, 2**63, 1.5, True):
        with pytest.raises(InputError, match=r"--test-seed must be an integer in \[0, 2\*\*63\)"):
            export(parse(copy.deepcopy(tiny_dict)), tmp_path / "x", test_seed=bad, quiet=True)
    assert not (tmp_path / "x").exists()
