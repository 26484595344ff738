"""``stripebench predict``: tables and page on a small folder; an out-of-range photograph named and left out."""

import csv
import json

import imageio.v3 as iio
import numpy as np
import pytest

from bench.cli import main
from bench.run import predict_frames as pf


@pytest.fixture(scope="module")
def photos(tmp_path_factory):
    d = tmp_path_factory.mktemp("photos")
    import scenes

    scene = scenes.make("plane", material="matte", width=128, height=120, seed=0, line_fwhm_mrad=3.0,
                        laser_power_mw=3.0, ambient_lux=400.0, exposure_ms=10.0)
    angles = scene.default_angles()
    iio.imwrite(d / "board.png", scene.render(float(angles[len(angles) // 2])).image)
    rng = np.random.default_rng(0)
    x = np.arange(128.0)
    wide = 30.0 + 120.0 * np.exp(-0.5 * ((x - 64.0) / 12.0) ** 2) + rng.normal(0, 2.0, (120, 128))
    iio.imwrite(d / "blurred.png", np.clip(wide, 0, 255).round().astype(np.uint8))
    return d


def test_predict_by_transplant_moves_each_photo_s_own_stripe(photos, tmp_path, capsys):
    out = tmp_path / "moved"
    rc = main(["predict", str(photos), "--out", str(out), "--trackers", "threshold,dp8", "--n-boot", "200"])
    assert rc == 0
    err = capsys.readouterr().err
    # the blurred stripe (FWHM 28 px) is wider than the reference window (13 px): left out, and why
    assert "blurred: out of range (its stripe is 2" in err and "board: its stripe moved by" in err
    with open(out / "predicted.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    # two moved frames, the photograph in place and two false-report frames (the stripe's ends cut off)
    assert [(r["tracker"], r["n_photos"], r["n_frames"]) for r in rows] == [("threshold", "1", "5"), ("dp8", "1", "5")]
    with open(out / "predicted_photos.csv", newline="") as fh:
        per = list(csv.DictReader(fh))
    for r in per:  # a clean board: both trackers find the moved stripe on (nearly) every row the rule sees
        counts = {k: int(r[k]) for k in ("n_hit", "n_wrong", "n_missed", "n_false", "n_quiet", "n_unknown")}
        assert sum(counts.values()) == pf.N_FULL * 120 and counts["n_hit"] >= 100 and float(r["hit_rate"]) > 0.9
        # the false-report frames' stripe-less rows (the cut ends, 15 or more rows from the moved stripe) feed the
        # false-report rate alone
        cut = int(r["n_false_cut"]) + int(r["n_quiet_cut"])
        assert cut >= 8 and float(r["false_report_rate"]) == pytest.approx(
            (counts["n_false"] + int(r["n_false_cut"])) / (counts["n_false"] + counts["n_quiet"] + cut), abs=1e-5)
    with open(out / "conditions.csv", newline="") as fh:
        cond = list(csv.DictReader(fh))
    board = {r["side"]: r for r in cond if r["name"] == "board"}
    assert set(board) == {"photo", "moved"} and int(float(board["moved"]["shift_px"])) >= 12
    assert float(board["moved"]["distance"]) < 1.0  # the moved photograph keeps the photograph's conditions
    html = (out / "report.html").read_text()
    assert "its stripe moved" in html and "wider than the reference window" in html and html.count("<img") == 3


def test_predict_says_in_one_line_when_a_stripe_runs_across_the_frame(photos, tmp_path, capsys):
    turned = tmp_path / "turned"
    turned.mkdir()
    board = iio.imread(photos / "board.png")
    iio.imwrite(turned / "across.png", np.ascontiguousarray(np.rot90(board)))  # as a horizontal rig's frame
    iio.imwrite(turned / "down.png", board)
    assert main(["predict", str(turned), "--out", str(tmp_path / "p"), "--trackers", "threshold", "--n-boot", "50",
                 "--quiet"]) == 0
    lines = [ln for ln in capsys.readouterr().err.splitlines() if "run across" in ln]
    assert len(lines) == 1 and lines[0].startswith("stripebench predict: across: its stripe seems to run across")
    assert "`--rotate 90`" in lines[0]
    assert main(["predict", str(turned), "--out", str(tmp_path / "q"), "--trackers", "threshold", "--n-boot", "50",
                 "--rotate", "90", "--quiet"]) == 0
    lines = [ln for ln in capsys.readouterr().err.splitlines() if "run across" in ln]
    assert len(lines) == 1 and lines[0].startswith("stripebench predict: down:")  # turned: now the other one


def test_a_laser_colour_the_photographs_do_not_show_is_refused_in_one_line(tmp_path, capsys):
    """Green photographs given as red (the default): one line naming the photograph and the colour it shows, exit 2,
    no table and no out-of-range advice; given as green, predicted."""
    rng = np.random.default_rng(4)
    x = np.arange(128.0)
    folder = tmp_path / "green"
    folder.mkdir()
    for k in range(3):
        img = np.clip(40.0 + rng.normal(0, 2.0, (120, 128, 3)), 0, 255)
        img[..., 1] += 150.0 * np.exp(-0.5 * ((x - 50.0 - 10 * k) / 1.2) ** 2)  # a green line down the frame
        iio.imwrite(folder / f"g{k}.png", np.clip(img, 0, 255).round().astype(np.uint8))
    capsys.readouterr()
    assert main(["predict", str(folder), "--out", str(tmp_path / "p"), "--trackers", "threshold", "--n-boot", "50",
                 "--quiet"]) == 2
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert len(err) == 1 and captured.out == ""
    assert err[0] == ("stripebench: error: g0 (and 2 more): its stripe stands out far more in the green excess than "
                      "in the red one the trackers see: the laser is green, not red; give `--laser green` (a real "
                      "set: its manifest's laser_colour)")
    assert main(["predict", str(folder), "--out", str(tmp_path / "q"), "--trackers", "threshold", "--n-boot", "50",
                 "--laser", "green", "--quiet"]) == 0
    assert "excess" not in capsys.readouterr().err


def test_predict_says_in_one_line_when_a_line_seems_drawn_over_a_photograph(tmp_path, capsys):
    """A colour photograph with a black line drawn down its stripe at half opacity (a tracker's output saved with the
    frame) is named, with the rows the line runs through; the same photograph without the line is not."""
    rng = np.random.default_rng(5)
    x = np.arange(128.0)
    img = 90.0 + rng.normal(0, 2.0, (120, 128, 3))  # a lit wall (on a dark one a dip's depth says nothing)
    img[..., 0] += 165.0 * np.minimum(1.0, 1.3 * np.exp(-0.5 * ((x - 60.0) / 2.0) ** 2))  # a red stripe, clipped core
    img = np.clip(img, 0, 255).round().astype(np.uint8)
    folder = tmp_path / "drawn"
    folder.mkdir()
    iio.imwrite(folder / "clean.png", img)
    drawn = img.astype(float)
    drawn[10:110, 60] *= 0.5  # the line, on one pixel, rows 10-109
    iio.imwrite(folder / "drawn.png", np.clip(drawn, 0, 255).round().astype(np.uint8))
    assert main(["predict", str(folder), "--out", str(tmp_path / "p"), "--trackers", "threshold", "--n-boot", "50",
                 "--quiet"]) == 0
    lines = [ln for ln in capsys.readouterr().err.splitlines() if "drawn over" in ln]
    assert len(lines) == 1 and lines[0].startswith("stripebench predict: drawn: a thin dark line seems drawn over it in ")
    n = int(lines[0].split(" in ")[1].split()[0])
    assert 90 <= n <= 100 and " of its 120 rows (a tracker's output saved with the frame?)" in lines[0]


def test_a_photograph_too_small_to_predict_for_is_one_line_and_left_out(photos, tmp_path, capsys):
    folder = tmp_path / "small"
    folder.mkdir()
    iio.imwrite(folder / "board.png", iio.imread(photos / "board.png"))
    strip = np.full((5, 50), 30, np.uint8)
    strip[:, 25] = 200
    iio.imwrite(folder / "strip.png", strip)  # fewer rows than the stripe estimate's support window
    assert main(["predict", str(folder), "--out", str(tmp_path / "p"), "--trackers", "threshold", "--n-boot", "50",
                 "--quiet"]) == 0
    err = [ln for ln in capsys.readouterr().err.splitlines() if "strip" in ln]
    assert len(err) == 1 and "its frame is 5 x 50 px, too small to predict for (at least 7 rows and 8 columns)" in err[0]
    (folder / "board.png").unlink()
    assert main(["predict", str(folder), "--out", str(tmp_path / "q"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2 and "too small" in err[0] and "no readable photograph" in err[1]


def test_predict_refuses_a_folder_of_other_files(photos, tmp_path):
    out = tmp_path / "busy"
    out.mkdir()
    (out / "keep.txt").write_text("x")
    assert main(["predict", str(photos), "--out", str(out)]) == 2


def test_real_predict_puts_predicted_beside_measured(photos, tmp_path, capsys):
    import json
    import shutil

    ds = tmp_path / "set"
    ds.mkdir()
    shutil.copy(photos / "board.png", ds / "board.png")
    shutil.copy(photos / "board.png", ds / "twin.png")
    frame = iio.imread(ds / "board.png")
    cols = frame.argmax(axis=1).astype(float)
    for n in ("board", "twin"):
        (ds / f"{n}_ref.csv").write_text("row,col\n" + "".join(f"{r},{c:g}\n" for r, c in enumerate(cols)))
    (ds / "manifest.csv").write_text("name,has_background,laser_colour,source_repo\nboard,0,red,someone/rig\n"
                                     "twin,0,red,someone/rig\n")
    out = tmp_path / "run"
    rc = main(["real", str(ds), "--out", str(out), "--trackers", "threshold,dp8,centroid", "--n-boot", "100",
               "--quiet", "--predict"])
    assert rc == 0
    printed = capsys.readouterr().out
    assert "Spearman rho" in printed and "mean |predicted - measured|" in printed
    doc = json.loads((out / "predict" / "compare.json").read_text())
    assert doc["photographs"] == ["board", "twin"] and doc["hit_rate"]["n"] == 3
    assert 0.0 <= doc["f1"]["mean_abs_diff"] <= 1.0
    # per rig (the manifest's source_repo: both photographs, so the pooled figures again) and per photograph
    assert list(doc["rigs"]) == ["someone/rig"] and doc["rigs"]["someone/rig"]["photographs"] == ["board", "twin"]
    for k in ("hit_rate", "f1"):
        assert doc["rigs"]["someone/rig"][k]["mean_abs_diff"] == pytest.approx(doc[k]["mean_abs_diff"], abs=1e-5)
    assert set(doc["per_photograph"]) == {"board", "twin"} and doc["per_photograph"]["twin"]["hit_rate"]["n"] == 3
    assert "someone/rig" in printed
    assert doc["measured_reliability"] is None and "repeatability" not in printed  # two photographs: no halves to rank
    assert doc["rigs"]["someone/rig"]["measured_reliability"] is None
    assert doc["rank_interval"] is None and "resampled" not in printed  # nor sets to resample
    html = (out / "predict" / "report.html").read_text()
    assert "Predicted beside measured" in html and "Per rig" in html and "Per photograph" in html


def test_real_predict_with_four_photographs_says_how_far_its_rank_correlation_rests_on_which_were_taken(
        photos, tmp_path, capsys):
    """With at least four photographs, `real --predict` prints each figure's rho over resampled photograph sets and
    writes it, pooled and per rig, beside the measured ranks' repeatability."""
    import json
    import shutil

    ds = tmp_path / "set"
    ds.mkdir()
    rng = np.random.default_rng(2)
    x = np.arange(128.0)
    names = ("b0", "b1", "b2", "b3")
    for i, n in enumerate(names):  # a stripe at column 50 and, in some rows, a brighter bar beside it
        img = 30.0 + rng.normal(0, 3.0, (120, 128)) + (60.0 + 10 * i) * np.exp(-0.5 * ((x - 50.0) / 1.3) ** 2)
        img[20 + 10 * i:50 + 10 * i, 88:91] += 120.0
        iio.imwrite(ds / f"{n}.png", np.clip(img, 0, 255).round().astype(np.uint8))
        (ds / f"{n}_ref.csv").write_text("row,col\n" + "".join(f"{r},50\n" for r in range(120)))
    (ds / "manifest.csv").write_text("name,has_background,laser_colour,source_repo\n"
                                     + "".join(f"{n},0,red,someone/rig\n" for n in names))
    out = tmp_path / "run"
    assert main(["real", str(ds), "--out", str(out), "--trackers", "threshold,dp8,steger,dp_gap", "--n-boot", "100",
                 "--quiet", "--predict"]) == 0
    printed = capsys.readouterr().out
    doc = json.loads((out / "predict" / "compare.json").read_text())
    assert set(doc["rank_interval"]) == {"hit_rate", "f1", "false_report_rate"}
    for k, v in doc["rank_interval"].items():
        assert len(v["interval"]) == 2 and 0 <= v["n_draws"] <= 1000
        if v["n_draws"]:
            lo, hi = v["interval"]
            assert -1.0 <= lo <= hi <= 1.0 and f"{k}: Spearman rho" in printed
            assert f"95 % of resampled photograph sets {lo:.2f} to {hi:.2f}" in printed
    assert any(v["n_draws"] for v in doc["rank_interval"].values())
    assert doc["rigs"]["someone/rig"]["rank_interval"] == doc["rank_interval"]  # one rig: the same photographs


def test_an_out_of_range_photograph_gets_its_labelled_coarse_answer(tmp_path, capsys):
    """A stripe 18.8 px wide (wider than the 13 px reference window) is predicted shrunk by 2, the least factor that
    brings it in range, and labelled so on stderr, in conditions.csv, predicted_photos.csv and predict.json; the same
    wording of why, from its one home, wherever it is said. With coarse answers off it is left out, and with nothing
    else predicted the command exits 2 in one line."""
    from bench.evaluate.stripe import why_left_out

    d = tmp_path / "phone"
    d.mkdir()
    rng = np.random.default_rng(1)
    x = np.arange(256.0)
    wide = 30.0 + 150.0 * np.exp(-0.5 * ((x - 128.0) / 8.0) ** 2) + rng.normal(0, 2.0, (160, 256))  # FWHM 18.8 px
    iio.imwrite(d / "big.png", np.clip(wide, 0, 255).round().astype(np.uint8))
    rc = main(["predict", str(d), "--out", str(tmp_path / "full"), "--trackers", "threshold,dp8", "--n-boot", "50",
               "--quiet"])  # a coarse answer is said even without progress
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 0
    line = next(ln for ln in err if ln.startswith("stripebench predict: big:"))
    assert line.startswith("stripebench predict: big: predicted shrunk by 2 (its stripe is 18.")
    assert "px wide, wider than the reference window's 13 px): a coarse answer" in line
    with open(tmp_path / "full" / "conditions.csv", newline="") as fh:
        photo = next(r for r in csv.DictReader(fh) if r["side"] == "photo")
    assert photo["status"] == "shrunk by 2" and photo["shrink"] == "2"
    assert photo["why"] == why_left_out(("width_px",), width_px=float(photo["width_px"]))
    with open(tmp_path / "full" / "predicted_photos.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [(r["name"], r["shrink"]) for r in rows] == [("big", "2"), ("big", "2")]
    doc = json.loads((tmp_path / "full" / "predict.json").read_text())
    assert doc["shrunk"] == {"big": 2} and doc["out_of_range"] == {"big": ["width_px"]}
    html = (tmp_path / "full" / "report.html").read_text()
    assert "predicted shrunk by 2 (a coarse answer" in html
    # asked at half size, it is in range: no coarse answer
    assert main(["predict", str(d), "--out", str(tmp_path / "half"), "--trackers", "threshold", "--n-boot", "50",
                 "--downscale", "2"]) == 0
    assert "big: its stripe moved by" in capsys.readouterr().err
    with open(tmp_path / "half" / "conditions.csv", newline="") as fh:
        photo = next(r for r in csv.DictReader(fh) if r["side"] == "photo")
    assert photo["status"] == "own size" and 8.0 < float(photo["width_px"]) < 11.0  # half the full-size FWHM


def test_without_coarse_answers_a_too_wide_stripe_is_left_out_and_a_photograph_without_any_answer_exits_2(tmp_path, capsys):
    from bench.config import parse_trackers
    from bench.evaluate.predict_settings import PredictSettings
    from bench.run.predict import run_predict

    d = tmp_path / "phone"
    d.mkdir()
    rng = np.random.default_rng(1)
    x = np.arange(256.0)
    wide = 30.0 + 150.0 * np.exp(-0.5 * ((x - 128.0) / 8.0) ** 2) + rng.normal(0, 2.0, (160, 256))
    iio.imwrite(d / "big.png", np.clip(wide, 0, 255).round().astype(np.uint8))
    res = run_predict(d, tmp_path / "p", parse_trackers(["threshold"]), n_boot=50,
                      settings=PredictSettings(shrink_coarse=False), say=lambda m: None)
    assert not res["made"]["big"].answered and res["pick"]["tracker"] is None
    assert "big: out of range (its stripe is 18." in capsys.readouterr().err
    short = tmp_path / "short"  # a stripe seen in 4 rows: no answer at any size
    short.mkdir()
    img = 30.0 + rng.normal(0, 2.0, (40, 96))
    img[:4] += 150.0 * np.exp(-0.5 * ((np.arange(96.0) - 40.0) / 1.2) ** 2)
    iio.imwrite(short / "stub.png", np.clip(np.rint(img), 0, 255).astype(np.uint8))
    assert main(["predict", str(short), "--out", str(tmp_path / "q"), "--trackers", "threshold", "--n-boot", "50",
                 "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[0] == ("stripebench predict: stub: out of range (its moved stripe is seen in fewer than 10 rows): left "
                      "out; the stated figures count it at the null's")
    assert err[-1].startswith("stripebench predict: none of the 1 photographs has a prediction")




def _board_folder(photos, tmp_path, name="set"):
    d = tmp_path / name
    d.mkdir()
    iio.imwrite(d / "a.png", iio.imread(photos / "board.png"))
    return d


def test_two_photographs_that_would_share_a_name_are_refused_in_one_line(photos, tmp_path, capsys):
    """``a.png`` and ``a.jpg`` in one folder would both be ``a`` (one scored twice, the other never): one line, exit
    2, before anything is tracked."""
    d = _board_folder(photos, tmp_path)
    iio.imwrite(d / "a.jpg", iio.imread(photos / "board.png"))
    capsys.readouterr()
    assert main(["predict", str(d), "--out", str(tmp_path / "p"), "--trackers", "threshold", "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "a.jpg and a.png would both be the photograph 'a': rename one" in err[0]
    assert not (tmp_path / "p" / "predicted.csv").exists()


@pytest.mark.parametrize("header, row, said", [
    ("name,has_background,laser_colour,rotate", "a,0,red,45", "rotate must be one of 0, 90, 180, 270, got '45'"),
    ("name,has_background,laser_colour", "a,0,purple", "laser_colour must be one of"),
    ("name,has_background,laser_colour", "a,7,red", "has_background must be 0 or 1, got '7'"),
    ("name,has_background", "a,0", "missing column(s) laser_colour"),
])
def test_a_real_set_whose_manifest_has_a_bad_row_or_misses_a_column_is_one_line(photos, tmp_path, capsys, header, row,
                                                                                  said):
    """A manifest row with rotate 45, laser purple or has_background 7, or a manifest without its laser column, is
    reported (the first problem, as `real --check` words it), not dropped or ignored: one line, exit 2."""
    d = _board_folder(photos, tmp_path)
    (d / "a_ref.csv").write_text("row,col,state\n" + "".join(f"{r},60,stripe\n" for r in range(120)))
    (d / "manifest.csv").write_text(f"{header}\n{row}\n")
    capsys.readouterr()
    assert main(["predict", str(d), "--out", str(tmp_path / "p"), "--trackers", "threshold", "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "has a manifest.csv but is not a valid real set" in err[0] and said in err[0], err


def test_real_refuses_the_removed_prediction_options_in_one_line(photos, tmp_path, capsys):
    """``--predict-estimate`` (and ``--predict-frames``) are gone: given, with or without ``--predict``, one line."""
    d = _board_folder(photos, tmp_path)
    for extra in (["--predict-estimate", "reference"], ["--predict", "--predict-frames", "render"]):
        with pytest.raises(SystemExit) as exc:
            main(["real", str(d), "--out", str(tmp_path / "r"), *extra])
        err = capsys.readouterr().err.strip().splitlines()
        assert exc.value.code == 2 and len(err) == 1 and "unrecognized arguments" in err[0]


def test_the_settings_round_trip_into_the_prediction_s_provenance(photos, tmp_path):
    """A prediction made with other settings writes them into predict.json; read back, they are those settings, and the
    prediction made with them differs where they differ (fewer rows required: the same; a wider pad: other shifts)."""
    from bench.config import parse_trackers
    from bench.evaluate.predict_settings import DEFAULT, PredictSettings
    from bench.run.predict import run_predict
    from bench.store.predictfiles import read_predict_settings

    other = PredictSettings(min_rows=12, pad_px=5, interval_level=0.7)
    res = run_predict(photos, tmp_path / "p", parse_trackers(["threshold"]), n_boot=50, settings=other,
                      say=lambda m: None)
    doc, back = read_predict_settings(tmp_path / "p")
    assert back == other and back != DEFAULT and doc["settings"]["pad_px"] == 5 and doc["format"] == 1
    base = run_predict(photos, tmp_path / "q", parse_trackers(["threshold"]), n_boot=50, say=lambda m: None)
    assert read_predict_settings(tmp_path / "q")[1] == DEFAULT
    assert res["made"]["board"].shift_px > base["made"]["board"].shift_px  # wider extents move further
    (tmp_path / "q" / "predict.json").write_text(json.dumps({**doc, "settings": {**doc["settings"], "pad_px": 2.5}}))
    from bench.store.files import RunFolderError

    with pytest.raises(RunFolderError, match="`pad_px` must be a finite int, got 2.5"):
        read_predict_settings(tmp_path / "q")


def test_predict_states_the_pick_its_ties_and_each_figure_with_its_interval_and_source(photos, tmp_path, capsys):
    """With a calibration (here a small one written for the test: F1 by the method, false reports by the null), the
    terminal gives the pick with its chance and ties, its leave-one-rig-out regret, each figure with its interval and
    where the null is stated, the null's label; predicted.csv holds the same."""
    from bench.evaluate import predict_loro as pl
    from bench.run.predict import default_trackers
    from bench.store.predictfiles import write_calibration

    labels = ["threshold", "dp8", "dp_gap"]
    rng = np.random.default_rng(0)
    m = {f: np.clip(0.8 + 0.1 * rng.standard_normal((4, 3)), 0, 1) for f in pl.FIGURES}
    p = {"f1": m["f1"] + 0.01, "hit_rate": m["hit_rate"] + 0.01, "false_report_rate": m["false_report_rate"] + 0.4}
    rigs = ["r1", "r2", "r3", "r4"]
    loro = pl.evaluate(p, m, rigs, labels, level=0.75)
    cal = write_calibration(tmp_path / "cal.json", {**pl.calibration(p, m, rigs, labels, loro), "loro": loro["pooled"],
                                                    "provenance": {"command": "test"}})
    assert {"dp_gap", "learned"} <= set(default_trackers())
    capsys.readouterr()
    assert main(["predict", str(photos), "--out", str(tmp_path / "p"), "--trackers", ",".join(labels), "--n-boot",
                 "50", "--calibration", str(cal)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("use ") and "best in" in out[0] and "of draws" in out[0]
    assert out[1].startswith("  judged leave one rig out on the shipped set (4 rigs): the pick's mean regret")
    with open(tmp_path / "p" / "predicted.csv", newline="") as fh:
        rows = {r["tracker"]: r for r in csv.DictReader(fh)}
    pick = [t for t, r in rows.items() if r["pick"] == "True"]
    assert len(pick) == 1 and out[0].startswith(f"use {pick[0]} ")
    for t, r in rows.items():
        assert r["f1_source"] == "predicted" and r["false_report_rate_source"] == "null (the shipped set's mean)"
        assert float(r["f1_lo"]) <= float(r["f1"]) <= float(r["f1_hi"])
        assert float(r["false_report_rate"]) == pytest.approx(float(r["false_report_rate_null"]))
    assert any("false reports: the null's, the shipped set's mean" in ln for ln in out)
    assert any(ln.startswith("F1: predicted from these photographs; leave one rig out its intervals held") for ln in out)
    doc = json.loads((tmp_path / "p" / "predict.json").read_text())
    assert doc["pick"]["tracker"] == pick[0] and doc["calibration"] == {"command": "test"}
