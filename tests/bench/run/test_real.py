"""``stripebench track`` and ``stripebench real``: outputs, failures, pairing,
rotation, run folders, the gate on real runs, and the shipped set end to end."""

import csv
import json
import shutil

import imageio.v3 as iio
import numpy as np
import pandas as pd
import pytest

from bench.run import gate

from bench.store import realset as real
from bench.cli import main
from bench.report.palette import tracker_rgb
from bench.report.real import overlay


def _frame(h=40, w=50, col=20, value=200, bar=None):
    img = np.full((h, w), 12, np.uint8)
    img[:, col] = value
    img[:, col - 1] = img[:, col + 1] = value // 2
    if bar is not None:  # ambient structure the laser-off frame also shows
        img[:, bar] = 250
    return img


def test_track_writes_csv_and_overlay_and_goes_on_past_a_broken_file(tmp_path, capsys):
    iio.imwrite(tmp_path / "a.png", _frame())
    rgb = np.repeat(_frame(col=30)[..., None], 3, axis=2)
    iio.imwrite(tmp_path / "b.png", rgb)
    (tmp_path / "broken.png").write_bytes(b"\x89PNG but not really")
    out = tmp_path / "out"
    rc = main(["track", str(tmp_path / "a.png"), str(tmp_path / "broken.png"), str(tmp_path / "b.png"),
               "--out", str(out), "--trackers", 'threshold,{label="wide",name="com_bg",params={half_window=3}}'])
    assert rc == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "broken.png" in err[0] and "cannot read image" in err[0]
    for name, col in (("a", 20), ("b", 30)):
        df = pd.read_csv(out / f"{name}.csv")
        assert list(df.columns) == ["row", "col_threshold", "score_threshold", "col_wide", "score_wide"]
        assert len(df) == 40 and np.allclose(df["col_threshold"], col) and np.allclose(df["col_wide"], col)
        ov = iio.imread(out / f"{name}_overlay.png")
        assert ov.shape == (40, 50, 3)
        assert tuple(ov[10, col]) in (tracker_rgb("threshold"), tracker_rgb("wide"))  # a marker on the stripe
    assert not (out / "broken.csv").exists()


def test_track_usage_errors_exit_2(tmp_path, capsys):
    iio.imwrite(tmp_path / "a.png", _frame())
    with pytest.raises(SystemExit) as e:  # a typed option: argparse's one line
        main(["track", str(tmp_path / "a.png"), "--out", str(tmp_path / "o"), "--trackers", "nope"])
    assert e.value.code == 2 and "unknown tracker 'nope'" in capsys.readouterr().err
    assert main(["track", str(tmp_path / "a.png"), "--out", str(tmp_path / "o"),
                 "--background", str(tmp_path / "missing.png")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("stripebench: error: --background:") and "no such file" in err[0]
    with pytest.raises(SystemExit) as e:
        main(["track", str(tmp_path / "a.png"), "--out", str(tmp_path / "o"), "--rotate", "45"])
    assert e.value.code == 2


def test_track_pairs_the_laser_off_frame_by_name(tmp_path):
    # ambient bar at column 40, brighter than the stripe: only the laser-off frame removes it
    iio.imwrite(tmp_path / "s.png", _frame(bar=40))
    iio.imwrite(tmp_path / "s_off.png", _frame(value=12, bar=40))
    args = [str(tmp_path / "s.png"), str(tmp_path / "s_off.png"), "--trackers", "com_bg"]
    assert main(["track", *args, "--out", str(tmp_path / "paired")]) == 0
    assert not (tmp_path / "paired" / "s_off.csv").exists()  # the partner is not tracked itself
    paired = pd.read_csv(tmp_path / "paired" / "s.csv")["col_com_bg"]
    assert np.allclose(paired, 20.0)
    assert main(["track", str(tmp_path / "s.png"), "--trackers", "com_bg", "--no-pair",
                 "--out", str(tmp_path / "alone")]) == 0
    alone = pd.read_csv(tmp_path / "alone" / "s.csv")["col_com_bg"]
    assert not np.isclose(alone, 20.0).any()  # the bar wins or the rows are ambiguous (not reported)
    assert main(["track", str(tmp_path / "s.png"), "--trackers", "com_bg", "--no-pair",
                 "--background", str(tmp_path / "s_off.png"), "--out", str(tmp_path / "explicit")]) == 0
    assert np.allclose(pd.read_csv(tmp_path / "explicit" / "s.csv")["col_com_bg"], 20.0)


def test_track_rotates_horizontal_stripes_and_draws_them_back(tmp_path):
    img = _frame(h=40, w=50, col=20).T.copy()  # stripe along row 20 of a 50 x 40 image
    iio.imwrite(tmp_path / "h.png", img)
    assert main(["track", str(tmp_path / "h.png"), "--trackers", "threshold", "--rotate", "90",
                 "--out", str(tmp_path / "o")]) == 0
    df = pd.read_csv(tmp_path / "o" / "h.csv")
    assert len(df) == 40  # rows of the turned frame = columns of the file
    assert np.allclose(df["col_threshold"], 20)  # turned counter-clockwise: file row 20 -> column 20
    ov = iio.imread(tmp_path / "o" / "h_overlay.png")
    c = tracker_rgb("threshold")
    assert ov.shape == (50, 40, 3) and tuple(ov[20, 5]) == c and tuple(ov[5, 5]) != c


def test_overlay_draws_the_reference_and_skips_nan():
    ov = overlay(np.zeros((5, 6), np.uint8), {"t": [1.0, np.nan, 2.0, 2.0, 2.0]}, reference=[4.0] * 5, radius=0)
    c = tracker_rgb("t")
    assert tuple(ov[0, 1]) == c and tuple(ov[1, 4]) != c and tuple(ov[1, 4]) == (0, 200, 0)
    assert not ov[1, :4].any()


def _tiny_set(root):
    """Two grey images with known stripes and references."""
    root.mkdir()
    a = _frame(col=20)
    b = _frame(col=10, bar=35)  # the bar wins every row for a threshold tracker without background
    iio.imwrite(root / "a.png", a)
    iio.imwrite(root / "b.png", b)
    iio.imwrite(root / "b_off.png", _frame(col=10, value=12, bar=35))
    ref_a = np.full(40, 21.0)  # 1 px off: hits, MAE 1
    ref_a[30:] = np.nan
    ref_b = np.full(40, 10.0)
    for name, ref in (("a", ref_a), ("b", ref_b)):
        lines = ["row,col"] + [f"{i}," + ("" if np.isnan(c) else f"{c}") for i, c in enumerate(ref)]
        (root / f"{name}_ref.csv").write_text("\n".join(lines) + "\n")
    (root / "manifest.csv").write_text("name,has_background,laser_colour,license\na,0,red,CC0\nb,1,red,CC0\n")
    return root


def test_real_runs_with_one_seed_write_byte_identical_metrics_and_keep_timings_apart(tmp_path):
    root = _tiny_set(tmp_path / "set")
    args = ["real", str(root), "--trackers", "threshold,com_bg", "--n-boot", "50", "--quiet"]
    for run in ("r1", "r2"):
        assert main([*args, "--out", str(tmp_path / run)]) == 0
    first, second = (tmp_path / "r1" / "metrics.csv").read_bytes(), (tmp_path / "r2" / "metrics.csv").read_bytes()
    assert first == second  # the time per frame, which differs run to run, is not in them
    m = pd.read_parquet(tmp_path / "r1" / "metrics.parquet")
    t = pd.read_csv(tmp_path / "r1" / "timings.csv")
    assert "ms_per_frame" not in m.columns and len(t) == len(m) and (t["ms_per_frame"] >= 0).all()
    from bench.store.realrun import load_real_run

    joined = load_real_run(tmp_path / "r1")["metrics"]
    assert "ms_per_frame" in joined.columns and joined["ms_per_frame"].notna().all()


def test_real_run_folder_metrics_and_gate(tmp_path, capsys):
    root = _tiny_set(tmp_path / "set")
    out = tmp_path / "run"
    assert main(["real", str(root), "--out", str(out), "--trackers", "threshold,com_bg", "--n-boot", "50"]) == 0
    printed = capsys.readouterr().out
    assert "hit rate" in printed and "report at" in printed
    for f in ("config.json", "metrics.parquet", "metrics.csv", "timings.csv", "summary.json", "report.html",
              "tracks/a.csv", "overlays/b.png"):
        assert (out / f).exists(), f
    m = pd.read_parquet(out / "metrics.parquet").set_index(["experiment", "tracker"])
    assert m.loc[("a", "threshold"), "hit_rate"] == 1.0 and m.loc[("a", "threshold"), "mae_px"] == 1.0
    assert m.loc[("a", "threshold"), "n_ref"] == 30
    # issue 66: the 10 rows past a's reference are within 15 rows of a stripe row, so unknown (the fallback rule):
    # reports there are not false, and no figure counts them as false (the old false_detections was 1.0)
    assert "false_detections" not in m.columns and "false_detections" not in gate.REAL_TOLERANCES
    assert m.loc[("a", "threshold"), "n_unknown"] == 10 and m.loc[("a", "threshold"), "n_false"] == 0
    assert np.isnan(m.loc[("a", "threshold"), "false_report_rate"])
    assert m.loc[("b", "threshold"), "hit_rate"] == 0.0  # the ambient bar, 25 px away
    assert m.loc[("b", "com_bg"), "hit_rate"] == 1.0  # the laser-off frame removes the bar
    assert m.loc[("mean", "threshold"), "hit_rate"] == 0.5
    (out / "report.html").unlink()
    assert main(["report", str(out)]) == 0 and "hit rate" in (out / "report.html").read_text()
    summary = json.loads((out / "summary.json").read_text())
    assert summary["kind"] == "real" and summary["trackers"]["com_bg"]["hit_rate"]["mean"] == 1.0
    base = gate.baseline_from_run(out)
    assert base["kind"] == "real" and set(base["tolerances"]) == set(gate.REAL_TOLERANCES)
    assert set(base["metrics"]["a/threshold/real"]) == set(gate.REAL_TOLERANCES)
    bfile = tmp_path / "real.json"
    assert main(["check", str(out), "--baseline", str(bfile), "--update"]) == 0
    assert main(["check", str(out), "--baseline", str(bfile)]) == 0
    doc = json.loads(bfile.read_text())
    doc["metrics"]["a/threshold/real"]["hit_rate"] = 1.0
    doc["metrics"]["b/com_bg/real"]["hit_rate"] = 1.0
    doc["metrics"]["b/threshold/real"]["hit_rate"] = 0.5  # the run's 0.0 is now a regression
    bfile.write_text(json.dumps(doc))
    capsys.readouterr()
    assert main(["check", str(out), "--baseline", str(bfile)]) == 1
    res = capsys.readouterr()
    assert "1 regression(s): threshold:hit_rate" in res.err
    assert any(line.startswith("b/threshold/real") and line.endswith("REGRESSED") for line in res.out.splitlines())


def test_real_prints_both_halves_and_ranks_by_f1(tmp_path, capsys):
    """Issue 66: the console and the page show F1 and the false-report rate beside the hit rate; trackers,
    the per-image table and the worst images rank by F1."""
    root = _tiny_set(tmp_path / "set")
    out = tmp_path / "run"
    assert main(["real", str(root), "--out", str(out), "--trackers", "threshold,com_bg", "--n-boot", "50"]) == 0
    res = capsys.readouterr()
    lines = res.out.splitlines()
    head = next(i for i, line in enumerate(lines) if line.startswith("tracker"))
    assert "F1" in lines[head] and "false reports" in lines[head] and "hit rate" in lines[head]
    summary = json.loads((out / "summary.json").read_text())
    f1 = {lab: summary["trackers"][lab]["detection"]["f1"] for lab in ("threshold", "com_bg")}
    assert f1["com_bg"] > f1["threshold"]
    rows = [line.split() for line in lines[head + 1:head + 3]]
    assert [r[0] for r in rows] == ["com_bg", "threshold"] and float(rows[0][1]) == pytest.approx(f1["com_bg"], abs=1e-3)
    frr = summary["trackers"]["threshold"]["detection"]["false_report_rate"]
    assert rows[1][4] == ("–" if np.isnan(frr) else f"{frr:.3f}")
    assert "hardest photographs (mean F1 over the trackers): b " in res.out  # the bar beats threshold on b
    assert "F1/false-report rate/hit rate" in res.err
    page = (out / "report.html").read_text()
    per_image = page[page.index("<h2>F1 per image</h2>"):page.index("<h2>The worst images")]
    assert per_image.index(">b<") < per_image.index(">a<")  # the hardest photograph first
    assert "b: F1 0.00" in page and page.index("<td>com_bg</td>") < page.index("<td>threshold</td>")


def test_extra_manifest_columns_are_one_warning_line(tmp_path, capsys):
    root = _tiny_set(tmp_path / "set")
    text = (root / "manifest.csv").read_text().splitlines()
    (root / "manifest.csv").write_text("\n".join([text[0] + ",surface,commit"] + [t + ",paper,abc" for t in text[1:]])
                                       + "\n")
    assert main(["real", str(root), "--check"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["stripebench real: manifest.csv: ignored column(s): surface, commit"]
    assert main(["real", str(root), "--out", str(tmp_path / "run"), "--trackers", "threshold", "--n-boot", "20",
                 "--quiet"]) == 0
    assert capsys.readouterr().err.count("ignored column(s)") == 1


def test_real_on_a_broken_set_lists_every_problem_and_exits_2(tmp_path, capsys):
    root = _tiny_set(tmp_path / "set")
    (root / "a_ref.csv").unlink()
    (root / "b_off.png").unlink()
    assert main(["real", str(root), "--check"]) == 2  # --check: one line per problem
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["stripebench real: a: missing reference a_ref.csv",
                   "stripebench real: b: has_background is 1 but b_off.png is missing"]
    assert main(["real", str(root), "--out", str(tmp_path / "run")]) == 2  # a run: one line, the first problem
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"stripebench: error: DATASET {str(root)!r} is not a valid real set: a: missing reference "
                   "a_ref.csv (and 1 more; `--check` lists them)"]
    assert not (tmp_path / "run").exists()
    with pytest.raises(SystemExit):
        main(["real", str(tmp_path / "set"), "--tol", "0"])
    assert "argument --tol: must be a finite number > 0" in capsys.readouterr().err


@pytest.mark.slow
def test_real_on_three_shipped_images_end_to_end(tmp_path):
    names = ["al_room3", "ag_tape", "dg_weld"]  # one image of each rig
    sub = tmp_path / "subset"
    sub.mkdir()
    rows = list(csv.DictReader((real.SHIPPED / "manifest.csv").read_text().splitlines()))
    with open(sub / "manifest.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]), lineterminator="\n")
        w.writeheader()
        w.writerows(r for r in rows if r["name"] in names)
    for n in names:
        for suffix in (".png", "_ref.csv"):
            shutil.copy(real.SHIPPED / f"{n}{suffix}", sub / f"{n}{suffix}")
    out = tmp_path / "run"
    assert main(["real", str(sub), "--out", str(out), "--trackers", "threshold,steger,dp8", "--quiet"]) == 0
    m = pd.read_parquet(out / "metrics.parquet")
    assert sorted(set(m["experiment"])) == sorted(names + ["mean"])
    assert m["hit_rate"].between(0, 1).all() and (m["status"] == "ok").all()
    # a clear stripe on a wall: every tracker finds it where the reference is
    assert (m[m["experiment"] == "al_room3"]["hit_rate"] > 0.9).all()
    html = (out / "report.html").read_text()
    assert "The worst images per tracker" in html and html.count("<img") == 6


# -- the run-folder guard on `real` and `track` -------------------------------------------------------------------


def _one_line(capsys, *needles):
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("stripebench: error: "), err
    for n in needles:
        assert n in err[0], (n, err[0])
    return err[0]


def test_real_refuses_a_synthetic_run_folder_and_an_unrelated_folder(tmp_path, capsys):
    from bench.store.runfolder import RunFolder

    root = _tiny_set(tmp_path / "set")
    run_dir = tmp_path / "synthetic"
    with RunFolder(run_dir) as rf:
        rf.open({"name": "paper", "render": {}, "experiments": []}, "code")
    (run_dir / "summary.json").write_text('{"synthetic": true}')
    config = (run_dir / "config.json").read_text()
    argv = ["real", str(root), "--trackers", "threshold", "--n-boot", "20", "--quiet"]
    assert main([*argv, "--out", str(run_dir)]) == 2
    _one_line(capsys, "holds a run ('paper'", "not a real run", "--force")
    assert (run_dir / "summary.json").read_text() == '{"synthetic": true}' and (run_dir / "config.json").read_text() == config
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("mine")
    assert main([*argv, "--out", str(mine)]) == 2
    _one_line(capsys, "is not empty and is not a stripebench run folder")
    assert sorted(p.name for p in mine.iterdir()) == ["notes.txt"]
    assert main([*argv, "--out", str(tmp_path / "r")]) == 0  # a fresh folder, then the same configuration again
    assert main([*argv, "--out", str(tmp_path / "r")]) == 0
    capsys.readouterr()
    assert main([*argv[:3], "com_bg", *argv[4:], "--out", str(tmp_path / "r")]) == 2  # other trackers
    _one_line(capsys, "holds a real run of another configuration")
    assert main([*argv[:3], "com_bg", *argv[4:], "--out", str(tmp_path / "r"), "--force"]) == 0


_HOLD = """
import sys, time
from bench.store.runfolder import RunFolder
RunFolder(sys.argv[1]).lock()
print("locked", flush=True)
time.sleep(60)
"""


def test_a_second_real_on_one_folder_is_refused_at_once(tmp_path):
    import subprocess
    import sys

    root = _tiny_set(tmp_path / "set")
    out = tmp_path / "r"
    out.mkdir()
    holder = subprocess.Popen([sys.executable, "-c", _HOLD, str(out)], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "locked"
        proc = subprocess.run([sys.executable, "-m", "bench.cli", "real", str(root), "--out", str(out),
                               "--trackers", "threshold", "--n-boot", "20", "--quiet"],
                              capture_output=True, text=True, timeout=120)
    finally:
        holder.kill()
        holder.wait()
        holder.stdout.close()
    err = proc.stderr.strip().splitlines()
    assert proc.returncode == 2 and len(err) == 1 and "is in use by another stripebench process" in err[0], proc.stderr
    assert not (out / "summary.json").exists()


def test_a_full_disk_during_real_is_one_line_naming_the_file(tmp_path, capsys, monkeypatch):
    import errno
    import os

    root = _tiny_set(tmp_path / "set")

    def full(fd):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "fsync", full)
    assert main(["real", str(root), "--out", str(tmp_path / "r"), "--trackers", "threshold", "--quiet"]) == 2
    line = _one_line(capsys, "no space left on the device", str(tmp_path / "r"))
    assert ".tmp" not in line


def test_track_refuses_colliding_outputs_and_inputs_inside_the_output_folder(tmp_path, capsys):
    for sub in ("a", "b"):
        (tmp_path / sub).mkdir()
        iio.imwrite(tmp_path / sub / "same.png", _frame())
    iio.imwrite(tmp_path / "dup.png", _frame())
    iio.imwrite(tmp_path / "dup.jpg", _frame())
    iio.imwrite(tmp_path / "x.png", _frame())
    iio.imwrite(tmp_path / "x_overlay.png", _frame())
    before = (tmp_path / "x_overlay.png").read_bytes()
    for inputs, out, needle in ((["a/same.png", "b/same.png"], "o1", "would both write same.csv"),
                                (["dup.png", "dup.jpg"], "o2", "would both write dup.csv"),
                                (["x.png", "x_overlay.png"], ".", "is inside the output folder")):
        argv = ["track", *[str(tmp_path / i) for i in inputs], "--out", str(tmp_path / out), "--trackers", "threshold"]
        for force in ([], ["--force"]):
            assert main([*argv, *force]) == 2
            _one_line(capsys, needle)
    assert (tmp_path / "x_overlay.png").read_bytes() == before and not (tmp_path / "o1").exists()


def test_track_into_a_folder_of_other_settings_or_for_another_input_is_refused(tmp_path, capsys):
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    iio.imwrite(tmp_path / "a" / "s.png", _frame(col=20))
    iio.imwrite(tmp_path / "b" / "s.png", _frame(col=30))
    iio.imwrite(tmp_path / "t.png", _frame())
    out = str(tmp_path / "o")
    assert main(["track", str(tmp_path / "a" / "s.png"), "--out", out, "--trackers", "threshold"]) == 0
    assert main(["track", str(tmp_path / "t.png"), "--out", out, "--trackers", "threshold"]) == 0  # adds t
    capsys.readouterr()
    assert main(["track", str(tmp_path / "t.png"), "--out", out, "--trackers", "com_bg"]) == 2
    _one_line(capsys, "holds a track output of another configuration")
    assert main(["track", str(tmp_path / "b" / "s.png"), "--out", out, "--trackers", "threshold"]) == 2
    _one_line(capsys, "s.csv' was written for", "pass --force to replace it")
    assert np.allclose(pd.read_csv(tmp_path / "o" / "s.csv")["col_threshold"], 20)
    assert main(["track", str(tmp_path / "b" / "s.png"), "--out", out, "--trackers", "threshold", "--force"]) == 0
    assert np.allclose(pd.read_csv(tmp_path / "o" / "s.csv")["col_threshold"], 30)
    assert (tmp_path / "o" / "t.csv").exists()


def _turned_jpeg(path, orientation: int):
    """A JPEG whose stored pixels hold a horizontal stripe (row 20) and whose EXIF asks to be shown turned."""
    from PIL import Image

    exif = Image.Exif()
    exif[0x0112] = orientation
    Image.fromarray(_frame(h=40, w=50, col=20).T.copy()).save(path, quality=95, exif=exif)


def test_track_says_in_one_line_when_a_file_asks_to_be_shown_turned_and_tracks_it_as_stored(tmp_path, capsys):
    _turned_jpeg(tmp_path / "phone.jpg", 6)  # shown a quarter turn clockwise: the stripe runs down, as shot
    assert main(["track", str(tmp_path / "phone.jpg"), "--trackers", "threshold", "--out", str(tmp_path / "o")]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "phone.jpg" in err[0] and "EXIF orientation 6 (shown turned)" in err[0]
    assert "`--rotate 270`" in err[0]
    assert len(pd.read_csv(tmp_path / "o" / "phone.csv")) == 50  # as stored: the file's 50 rows
    assert main(["track", str(tmp_path / "phone.jpg"), "--trackers", "threshold", "--rotate", "270",
                 "--out", str(tmp_path / "turned")]) == 0
    assert "EXIF" not in capsys.readouterr().err  # turned as it is shown: nothing to say
    cols = pd.read_csv(tmp_path / "turned" / "phone.csv")["col_threshold"]
    assert len(cols) == 40 and np.all(np.abs(cols - 29) <= 1)  # upright: the stripe runs down column 49 - 20
