"""The prediction procedure checked on renders (bench.studies.predict_check): a small run through the command."""

import json

import numpy as np
import pandas as pd
import pytest

from bench.cli import main


@pytest.fixture(scope="module")
def checked(tmp_path_factory):
    out = tmp_path_factory.mktemp("predictcheck")
    rc = main(["predictcheck", "--out", str(out), "--profile", "quick", "--size", "128",
               "--trackers", "threshold,dp8", "--quiet"])
    assert rc == 0
    return out


def test_every_case_frame_is_measured_and_matched_or_named(checked):
    doc = json.loads((checked / "predict_check.json").read_text())
    assert doc["kind"] == "predict_check" and doc["seed"] == 1 and doc["trackers"] == ["threshold", "dp8"]
    assert doc["frames"] and doc["size"] == 128 and doc["n_angles"] == 3
    names = [f["name"] for f in doc["frames"]]
    assert len(names) == 2 * 3 and all(f["status"] in ("matched", "out of range") for f in doc["frames"])
    measured = pd.read_csv(checked / "measured.csv")
    assert sorted(set(measured["experiment"])) == sorted(names)  # every frame scored, matched or not
    # each measured frame's rows: 120, one outcome each
    sums = measured[[c for c in measured.columns if c.startswith("n_") and not c.endswith("_far")]].sum(axis=1)
    assert (sums == 120).all()
    # the stripe-less rows a photograph's reference scores are some of them
    for k in ("n_false", "n_quiet"):
        assert (measured[f"{k}_far"] <= measured[k]).all()


def test_false_reports_are_compared_again_on_the_rows_a_photograph_s_reference_scores(checked):
    from bench.evaluate.prediction import compare_by_group, per_group_error
    from bench.studies.predict_check import FAR

    doc = json.loads((checked / "predict_check.json").read_text())
    predicted, measured = pd.read_csv(checked / "predicted.csv"), pd.read_csv(checked / "measured.csv")
    groups = {n: c for c, v in doc["cases"].items() for n in v["photographs"]}
    distant = measured.assign(n_false=measured["n_false_far"], n_quiet=measured["n_quiet_far"])
    far = compare_by_group(predicted, distant, groups)
    for c, v in doc["cases"].items():  # the same prediction, against the far rows' measurement
        assert v[FAR]["n"] == far[c]["false_report_rate"]["n"]
        assert v[FAR]["mean_abs_diff"] == pytest.approx(far[c]["false_report_rate"]["mean_abs_diff"], nan_ok=True)
        every = {r["tracker"]: r["synthetic"] for r in v["false_report_rate"]["table"]}
        assert all(every[r["tracker"]] == pytest.approx(r["synthetic"]) for r in v[FAR]["table"])
    want = per_group_error(far)["false_report_rate"]
    assert doc["per_case"][FAR] == pytest.approx(want, nan_ok=True) and FAR in doc["pooled"]


def test_predicted_beside_measured_per_case_and_pooled(checked):
    doc = json.loads((checked / "predict_check.json").read_text())
    matched = [f["name"] for f in doc["frames"] if f["status"] == "matched"]
    assert matched, "no frame of the quick profile in range"
    predicted = pd.read_csv(checked / "predicted.csv")
    assert sorted(set(predicted["name"])) == sorted(matched)
    assert sorted(doc["pooled"]["photographs"]) == sorted(matched)
    for case in doc["cases"].values():
        for k in ("hit_rate", "f1"):
            assert case[k]["n"] == 2 and 0.0 <= case[k]["mean_abs_diff"] <= 1.0
    for k in ("hit_rate", "f1", "false_report_rate"):  # the per-case error: the cases' own errors averaged
        per = [c[k]["mean_abs_diff"] for c in doc["cases"].values() if np.isfinite(c[k]["mean_abs_diff"])]
        assert doc["per_case"][k] == pytest.approx(np.mean(per)) if per else np.isnan(doc["per_case"][k])
    # the pooled figures are the pooled counts: recompute the measured hit rate of one tracker
    m = pd.read_csv(checked / "measured.csv")
    t = m[(m["tracker"] == "threshold") & m["experiment"].isin(matched)]
    hit = t["n_hit"].sum() / (t["n_hit"].sum() + t["n_wrong"].sum() + t["n_missed"].sum())
    row = next(r for r in doc["pooled"]["hit_rate"]["table"] if r["tracker"] == "threshold")
    assert row["real"] == pytest.approx(hit) and np.isfinite(row["synthetic"])


def test_shrunk_cases_are_the_grid_s_size_with_their_truth_shrunk(tmp_path):
    from bench.config import profile
    from bench.studies.predict_check import case_frames

    config = profile("quick")
    exp = config.experiments[0]
    plain = case_frames(exp, config, seed=1, width=64, height=60, n_angles=1)[0][1]
    shrunk = case_frames(exp, config, seed=1, width=64, height=60, n_angles=1, downscale=2)[0][1]
    assert plain.image.shape == shrunk.image.shape == (60, 64)
    both = np.isfinite(plain.truth_columns) & np.isfinite(shrunk.truth_columns)
    assert both.sum() > 20 and np.median(np.abs(plain.truth_columns[both] - shrunk.truth_columns[both])) < 0.5
    # rendered twice as large and shrunk (another frame, whose stripe is where the plain one's is)
    assert not np.array_equal(plain.image, shrunk.image)
    assert np.nanmedian(np.abs(np.argmax(shrunk.image, axis=1)[both] - shrunk.truth_columns[both])) <= 1.0
    rc = main(["predictcheck", "--out", str(tmp_path / "d2"), "--profile", "quick", "--size", "128",
               "--trackers", "threshold", "--downscale", "2", "--quiet"])
    assert rc == 0 and json.loads((tmp_path / "d2" / "predict_check.json").read_text())["downscale"] == 2


def test_a_narrower_line_for_every_case_makes_a_thinner_stripe():
    from bench.config import profile
    from bench.evaluate import conditions as cond
    from bench.studies.predict_check import case_frames

    config = profile("quick")
    exp = config.experiments[0]
    wide = case_frames(exp, config, seed=1, width=128, height=120, n_angles=1, line_fwhm_mrad=6.0)[0][1]
    thin = case_frames(exp, config, seed=1, width=128, height=120, n_angles=1, line_fwhm_mrad=1.0)[0][1]
    assert cond.measure(thin.image).width_px < 0.6 * cond.measure(wide.image).width_px


def test_the_laser_channel_gives_the_trackers_the_laser_s_own_channel_and_the_photo_says_so():
    from bench.config import profile
    from bench.evaluate.pixels import select_channel
    from bench.studies.predict_check import case_frames

    config = profile("field")
    exp = next(e for e in config.experiments if e.key == "colour-no-filter")
    auto = case_frames(exp, config, seed=1, width=64, height=60, n_angles=1)[0][1]
    plain = case_frames(exp, config, seed=1, width=64, height=60, n_angles=1, channel="laser")[0][1]
    assert auto.channel == "auto" and plain.channel == "r"  # the case's laser is red
    assert np.array_equal(plain.image, select_channel(plain.rgb, "r", "red"))
    assert np.array_equal(auto.rgb, plain.rgb) and not np.array_equal(auto.image, plain.image)
    with pytest.raises(ValueError, match="`channel` must be one of auto, laser, got 'r'"):
        case_frames(exp, config, seed=1, width=64, height=60, n_angles=1, channel="r")


def test_the_white_bar_stands_beside_the_stripe_in_every_channel_and_leaves_the_truth():
    from bench.config import profile
    from bench.studies.predict_check import BAR, case_frames
    from bench.studies.predict_score import family_of

    config = profile("field")
    exp = next(e for e in config.experiments if e.key == "colour-no-filter")
    plain = case_frames(exp, config, seed=1, width=128, height=120, n_angles=1)[0][1]
    barred = case_frames(exp, config, seed=1, width=128, height=120, n_angles=1, distractor="white-bar")[0][1]
    assert np.array_equal(plain.truth_columns, barred.truth_columns, equal_nan=True)
    added = barred.rgb.astype(float) - plain.rgb.astype(float)
    col = int(np.argmax(added.mean(axis=(0, 2))))
    assert abs(abs(col - np.nanmedian(plain.truth_columns)) - BAR.offset_px) <= 1  # beside the stripe
    assert added[:, col].min() >= 0 and np.ptp(added[:, col].mean(axis=0)) < 30  # in every channel alike: white
    assert barred.image[:, col].mean() > plain.image[:, col].mean() + 20  # and the trackers see it
    assert family_of({"downscale": 1, "distractor": "white-bar", "rows": "clear"}) == "downscale 1, white-bar"
    with pytest.raises(ValueError,
                       match="`distractor` must be one of none, white-bar, rival-fringe, got 'lamp'"):
        case_frames(exp, config, seed=1, width=64, height=60, n_angles=1, distractor="lamp")


def test_jpeg_frames_are_the_render_compressed_and_their_family_is_named(tmp_path, capsys):
    """``jpeg_quality``: each case frame's photograph JPEG-compressed (the truth unchanged; the frame changed, in an
    8-bit colour case's every channel); the ``marble-60mw-jpeg`` family sets it; a quality out of 1-95 is refused,
    by the command in one line with status 2."""
    from bench.config import profile
    from bench.studies.predict_check import case_frames, family_options
    from bench.studies.predict_score import family_of

    config = profile("field")
    exp = next(e for e in config.experiments if e.key == "colour-no-filter")
    plain = case_frames(exp, config, seed=1, width=128, height=120, n_angles=1)[0][1]
    packed = case_frames(exp, config, seed=1, width=128, height=120, n_angles=1, jpeg_quality=30)[0][1]
    assert np.array_equal(plain.truth_columns, packed.truth_columns, equal_nan=True)
    assert packed.rgb.dtype == np.uint8 and packed.rgb.shape == plain.rgb.shape
    diff = np.abs(packed.rgb.astype(float) - plain.rgb.astype(float))
    assert all(diff[..., c].mean() > 0.2 for c in range(3)) and diff.mean() < 20  # compressed, not another picture
    assert family_options("marble-60mw-jpeg", {"jpeg_quality": None})["jpeg_quality"] == 75
    doc = {"downscale": 1, "rows": "clear", "profile": "marble", "laser_power_mw": 60.0, "jpeg_quality": 75}
    assert family_of(doc) == "marble: downscale 1, 60 mW, JPEG 75"
    with pytest.raises(ValueError, match="`jpeg_quality` must be an integer 1 .. 95, got 0"):
        case_frames(exp, config, seed=1, width=64, height=60, n_angles=1, jpeg_quality=0)
    capsys.readouterr()
    with pytest.raises(SystemExit) as exc:
        main(["predictcheck", "--out", str(tmp_path / "bad"), "--jpeg-quality", "96", "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert exc.value.code == 2 and len(err) == 1 and "--jpeg-quality: must be an integer 1 .. 95, got '96'" in err[0]


def test_the_rival_fringe_carries_its_share_of_the_stripes_laser_evidence():
    """``rival-fringe``: the white bar kept whole, with a fringe of the laser's colour ``BAR.fringe_px`` beyond it whose
    laser evidence is ``BAR.fringe_share`` of the stripe's (stripe_evidence): a rival nearly as like the laser as the
    stripe. The other channels are the white bar's; the truth is the render's."""
    from bench.config import profile
    from bench.evaluate.pixels import LASER_INDEX
    from bench.run.camera_view import laser_colour
    from bench.studies.predict_check import BAR, case_frames, stripe_evidence
    from bench.studies.predict_score import family_of

    config = profile("field")
    exp = next(e for e in config.experiments if e.key == "colour-no-filter")
    kw = dict(seed=1, width=128, height=120, n_angles=1)
    _, plain, params = case_frames(exp, config, **kw)[0]
    white = case_frames(exp, config, distractor="white-bar", **kw)[0][1]
    rival = case_frames(exp, config, distractor="rival-fringe", **kw)[0][1]
    laser = laser_colour(params["laser_wavelength_nm"])
    li = LASER_INDEX[laser]
    truth = plain.truth_columns
    stripe = stripe_evidence(plain.rgb, truth, laser)
    fringe_col = np.where(np.isfinite(truth), round(np.nanmedian(truth) + BAR.offset_px + BAR.fringe_px), np.nan)
    fringe = stripe_evidence(rival.rgb, fringe_col, laser)
    assert stripe > 5.0 and abs(fringe - BAR.fringe_share * stripe) <= 0.1 * stripe, (stripe, fringe)
    assert stripe_evidence(white.rgb, fringe_col, laser) < 0.2 * fringe  # the white bar alone: no colour
    others = [k for k in range(3) if k != li]
    assert np.array_equal(rival.rgb[..., others], white.rgb[..., others])
    assert np.all(rival.rgb[..., li] >= white.rgb[..., li]) and np.any(rival.rgb[..., li] > white.rgb[..., li])
    assert np.array_equal(rival.truth_columns, truth, equal_nan=True)
    assert family_of({"downscale": 1, "distractor": "rival-fringe", "rows": "clear"}) == "downscale 1, rival-fringe"


def test_the_white_core_family_clips_the_stripe_s_core_white_where_the_cases_own_power_does_not():
    """``white-core`` (50 mW for every case): a colour case's stripe clips white in its core (the laser's channel at
    the top and another over 0.6 of it), as in a third of the shipped photographs; at the case's own power it does
    not. The family is named by its power."""
    from bench.config import profile
    from bench.evaluate.pixels import LASER_INDEX
    from bench.run.camera_view import laser_colour
    from bench.studies.predict_check import case_frames, family_options
    from bench.studies.predict_score import family_of

    def white_core_share(rgb, columns, laser):  # rows whose brightest laser pixel near the truth is clipped white
        rows = np.flatnonzero(np.isfinite(columns))
        li = LASER_INDEX[laser]
        cols = np.rint(columns[rows]).astype(int)
        win = np.stack([rgb[rows, np.clip(cols + d, 0, rgb.shape[1] - 1)] for d in range(-3, 4)], axis=1)
        core = win[np.arange(rows.size), win[..., li].argmax(axis=1)].astype(float)
        return float(np.mean((core[:, li] >= 253) & (np.delete(core, li, axis=1).max(axis=1) > 0.6 * 255)))

    config = profile("field")
    exp = next(e for e in config.experiments if e.key == "board-checker-room")
    kw = dict(seed=1, width=128, height=120, n_angles=1)
    opts = family_options("white-core", {"laser_power_mw": None})
    assert opts == {"laser_power_mw": 50.0}
    (_, own, params), = case_frames(exp, config, **kw)
    (_, white, _), = case_frames(exp, config, **kw, **opts)
    laser = laser_colour(params["laser_wavelength_nm"])
    assert own.rgb is not None and np.array_equal(own.truth_columns, white.truth_columns, equal_nan=True)
    assert white_core_share(own.rgb, own.truth_columns, laser) < 0.05
    assert white_core_share(white.rgb, white.truth_columns, laser) > 0.3
    assert family_of({"downscale": 1, "line_fwhm_mrad": None, "rows": "clear", **opts}) == "downscale 1, 50 mW"


def test_the_marble_480mw_family_glows_near_the_top_beside_a_clipped_core_where_the_profile_s_own_power_does_not():
    """``marble-480mw`` (480 mW for every marble case): the skin sphere's glow beside its clipped core stands
    near the top (``rowstates.glow_rows``), as the shipped ``bb_hand``'s skin does; at the profile's own power the
    core does not clip."""
    from bench.config import profile
    from bench.evaluate import rowstates as rs
    from bench.evaluate import stripe as sp
    from bench.evaluate.pixels import LASER_INDEX
    from bench.run.camera_view import laser_colour
    from bench.studies.predict_check import case_frames, family_options
    from bench.studies.predict_score import family_of

    def glowing(case, laser):  # clipped rows along the truth, and the share of them in a glow near the top
        a = np.asarray(case.original)
        frame = a[..., LASER_INDEX[laser]] if a.ndim == 3 else a
        ext = sp.stripe_extents(frame, guide=case.truth_columns)
        clipped = rs.clipped_peaks(case.original, ext) & np.isfinite(case.truth_columns)
        glow = clipped & rs.glow_rows(frame, ext)
        return int(clipped.sum()), float(glow.sum() / max(clipped.sum(), 1))

    config = profile("marble")
    exp = next(e for e in config.experiments if e.key == "sphere-skin")
    kw = dict(seed=1, width=256, height=240, n_angles=1)  # the cases' size in predictcheck: the glow's reach in px
    opts = family_options("marble-480mw", {"profile": "marble", "laser_power_mw": None})
    assert opts == {"profile": "marble", "laser_power_mw": 480.0}
    (_, own, params), = case_frames(exp, config, **kw)
    (_, bright, _), = case_frames(exp, config, **kw, laser_power_mw=opts["laser_power_mw"])
    laser = laser_colour(params["laser_wavelength_nm"])
    assert glowing(own, laser)[0] == 0
    n, share = glowing(bright, laser)
    assert n >= 20 and share >= 0.5, (n, share)
    assert family_of({"downscale": 1, "line_fwhm_mrad": None, "rows": "clear", **opts}) == "marble: downscale 1, 480 mW"


def test_a_laser_power_for_every_case_makes_a_brighter_stripe(capsys):
    from bench.config import profile
    from bench.studies.predict_check import case_frames

    config = profile("quick")
    exp = config.experiments[0]
    frames = {mw: case_frames(exp, config, seed=1, width=128, height=120, n_angles=1, laser_power_mw=mw)[0][1]
              for mw in (0.5, 5.0)}
    rows = np.isfinite(frames[5.0].truth_columns)
    lift = {mw: float(np.median(f.image[rows].max(axis=1) - np.median(f.image[rows], axis=1)))
            for mw, f in frames.items()}
    assert lift[5.0] > 3.0 * lift[0.5] > 0.0
    with pytest.raises(SystemExit) as exc:  # a power must be > 0
        main(["predictcheck", "--out", "unused", "--laser-power", "0"])
    assert exc.value.code == 2 and "--laser-power: must be a finite number > 0, got '0'" in capsys.readouterr().err


def test_predictscore_prints_the_declared_objective_of_finished_runs(checked, tmp_path, capsys):
    from bench.evaluate.prediction import per_group_error
    from bench.studies.predict_score import objective

    doc = json.loads((checked / "predict_check.json").read_text())
    capsys.readouterr()
    assert main(["predictscore", str(checked)]) == 0
    printed = capsys.readouterr().out.strip().splitlines()
    err = per_group_error(doc["cases"])
    o = objective({"run": doc})
    assert o["per_case"] == pytest.approx(0.5 * (err["hit_rate"] + err["f1"]))
    assert o["families"] == {"quick: native": pytest.approx(o["per_case"])}
    assert printed[-2].startswith(f"per-case score {o['per_case']:.5f} (quick: native {o['per_case']:.5f})")
    assert printed[-2].endswith("(1 runs)") and printed[-1].startswith("mean |predicted - measured| per case: hit rate")
    assert main(["predictscore", str(tmp_path)]) == 2  # not a run: one line
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "is not a finished predictcheck run" in lines[0]


def test_predictscore_min_rows_leaves_out_the_cases_measured_on_few_rows(checked, capsys):
    """``--min-rows N``: the per-case figures without the cases whose frames hold fewer than N measured stripe rows
    (counted from ``measured.csv``); the pooled figures keep them; no case left is one line and status 2."""
    from bench.studies.predict_score import _read_runs, objective

    m = pd.read_csv(checked / "measured.csv")
    m = m[m["tracker"] == "threshold"]
    rows = (m["n_hit"] + m["n_wrong"] + m["n_missed"]).groupby(m["experiment"].str.rsplit("@", n=1).str[0]).sum()
    doc = _read_runs([checked], rows=True)[str(checked)]
    assert doc["_case_rows"] == {k: int(v) for k, v in rows.items()}
    cut = sorted(doc["_case_rows"].get(k, 0) for k in doc["cases"])[len(doc["cases"]) // 2]  # keeps half or more
    kept = {k: v for k, v in doc["cases"].items() if doc["_case_rows"].get(k, 0) >= cut}
    o, full = objective({"r": doc}, cut), objective({"r": doc})
    assert o["runs"]["r"]["n_left_out"] == len(doc["cases"]) - len(kept) and o["pooled"] == full["pooled"]
    only_kept = objective({"r": {**doc, "cases": kept}})
    assert o["per_case"] == pytest.approx(only_kept["per_case"])
    assert o["false_report_far_per_case"] == pytest.approx(only_kept["false_report_far_per_case"], nan_ok=True)
    capsys.readouterr()
    assert main(["predictscore", str(checked), "--min-rows", str(cut)]) == 0
    line = capsys.readouterr().out.strip().splitlines()[-1]
    assert line.startswith(f"per-case figures without the cases measured on fewer than {cut} stripe rows: "
                           f"{len(doc['cases']) - len(kept)} of {len(doc['cases'])} left out")
    assert main(["predictscore", str(checked), "--min-rows", str(int(rows.max()) + 1)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no case measured on" in err[0]
    with pytest.raises(SystemExit) as bad:
        main(["predictscore", str(checked), "--min-rows", "-1"])
    assert bad.value.code == 2 and "--min-rows: must be an integer >= 0" in capsys.readouterr().err


def test_a_named_family_sets_its_options_and_a_conflicting_option_is_one_line(tmp_path, capsys):
    """``--family NAME`` sets the family's options (recorded as if given one by one); an option the family sets,
    given otherwise, is one line and status 2."""
    from bench.studies.predict_score import family_of

    out = tmp_path / "plain"
    assert main(["predictcheck", "--out", str(out), "--profile", "quick", "--size", "128", "--trackers", "threshold",
                 "--family", "plain", "--quiet"]) == 0
    doc = json.loads((out / "predict_check.json").read_text())
    assert doc["channel"] == "laser" and family_of(doc) == "quick: downscale 1, channel laser"
    capsys.readouterr()
    for extra in (["--family", "phone", "--downscale", "2"], ["--family", "marble-480mw", "--profile", "quick"]):
        assert main(["predictcheck", "--out", str(tmp_path / "bad"), "--size", "128", *extra, "--quiet"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and f"family {extra[1]!r} sets" in err[0]
    assert not (tmp_path / "bad" / "predict_check.json").exists()


def test_every_named_family_is_options_the_command_accepts():
    import inspect

    from bench.config import PROFILES
    from bench.studies.predict_check import CASE_CHANNELS, DEFAULTS, DISTRACTORS, FAMILIES, family_options, study

    assert set(FAMILIES) == {"native", "phone", "plain", "rival-fringe", "white-core", "marble-60mw-jpeg", "marble-480mw"}
    params = inspect.signature(study).parameters
    for name in FAMILIES:
        opts = family_options(name, {k: DEFAULTS[k] for k in FAMILIES[name]})
        assert set(opts) <= set(params)
        assert opts.get("profile", "field") in PROFILES and opts.get("downscale", 1) in (1, 2, 4)
        assert opts.get("channel", "auto") in CASE_CHANNELS and opts.get("distractor", "none") in DISTRACTORS
    with pytest.raises(ValueError, match="`family` must be one of"):
        family_options("daylight", {})


def _quick_runs(tmp_path, option: str, values) -> dict:
    """value -> (``predict_check.json``, ``measured.csv``, ``predicted.csv``) of a small ``quick`` profile run
    (``threshold`` only) with ``option`` at each of ``values``."""
    runs = {}
    for v in values:
        out = tmp_path / v
        assert main(["predictcheck", "--out", str(out), "--profile", "quick", "--size", "128", "--trackers",
                     "threshold", option, v, "--quiet"]) == 0
        runs[v] = (json.loads((out / "predict_check.json").read_text()), pd.read_csv(out / "measured.csv"),
                   pd.read_csv(out / "predicted.csv"))
    return runs


def test_the_reference_truth_scores_a_clipped_core_in_a_glow_at_its_true_column_where_the_rule_gives_none():
    """``--truth reference --rows clear``: a row read as seen (a clipped core in a glow, ``seen_states``) has no
    reference column by the rule; it is scored at its true column instead of failing (``row_outcomes`` refuses a
    stripe row without a column), as on ``marble-480mw``."""
    from bench.evaluate import rowstates as rs
    from bench.evaluate import stripe as sp
    from bench.evaluate.outcomes import STRIPE, referenced_columns, row_outcomes
    from bench.studies.predict_check import scored_columns

    rng = np.random.default_rng(3)
    img = rng.normal(30.0, 1.0, (40, 60))
    img[:, 30] += 150.0
    img[10:20, 15:46] = 250.0 + rng.normal(0, 1.0, (10, 31))  # a glow filling the reference window
    img[10:20, 29:32] = 255.0  # its clipped core, 5 DN up: the rule does not see it
    img = np.clip(np.rint(img), 0, 255).astype(np.uint8)
    truth = np.full(40, 30.2)
    along = sp.stripe_extents(img, guide=truth)
    states = rs.seen_states(img, truth, rs.clipped_peaks(img, along))
    assert (states[10:20] == STRIPE).all() and np.isnan(referenced_columns(img, truth)[10:20]).all()
    cols = scored_columns(img, truth, states, "reference")
    assert np.array_equal(cols[10:20], truth[10:20])  # the true column where the rule gives none
    ref = referenced_columns(img, truth)
    assert np.array_equal(np.delete(cols, range(10, 20)), np.delete(ref, range(10, 20)), equal_nan=True)
    assert np.array_equal(scored_columns(img, truth, states, "render"), truth)
    reports = np.full(40, 30.0)
    assert (row_outcomes(reports, cols, states)[10:20] == row_outcomes(reports, truth, states)[10:20]).all()
    with pytest.raises(ValueError, match="`state` says stripe where `truth` has no column"):
        row_outcomes(reports, ref, states)  # what the measured side did before
    with pytest.raises(ValueError, match="`truth` must be one of render, reference, got 'labels'"):
        scored_columns(img, truth, states, "labels")


def test_the_reference_truth_scores_the_measured_side_against_a_photograph_s_reference_columns(tmp_path):
    """``--truth reference``: the measured side is scored against the columns a photograph's reference would give
    (:func:`bench.evaluate.outcomes.referenced_columns`), with the same row states; the prediction is unchanged."""
    from bench.config import parse_trackers_arg
    from bench.config import profile as load_profile
    from bench.evaluate.outcomes import outcome_counts, referenced_columns, referenced_states
    from bench.run import predict_frames as pf
    from bench.run.track import build_trackers
    from bench.studies.predict_check import case_frames, study
    from bench.studies.predict_score import family_of

    runs = _quick_runs(tmp_path, "--truth", ("render", "reference"))
    doc, measured, predicted = runs["reference"]
    assert doc["truth"] == "reference" and family_of(doc) == "quick: downscale 1, truth reference"
    pd.testing.assert_frame_equal(predicted, runs["render"][2])  # the prediction does not depend on it
    config = load_profile("quick")
    tr = build_trackers(parse_trackers_arg("threshold"))
    name, case, _ = next(iter(case_frames(config.experiments[0], config, seed=1, width=128, height=120,
                                          n_angles=3)))
    states = referenced_states(case.image, case.truth_columns)
    cols = referenced_columns(case.image, case.truth_columns)
    assert np.array_equal(np.isfinite(cols), states == 1)  # a column exactly where the rule sees the stripe
    want = outcome_counts(pf.score_frame(tr, case.image, cols, states=states)["threshold"])
    got = measured[(measured["experiment"] == name) & (measured["tracker"] == "threshold")].iloc[0]
    assert {k: int(got[k]) for k in want} == want
    with pytest.raises(ValueError, match="`truth` must be one of render, reference"):
        study(out=tmp_path / "bad", truth="photo")


def test_clear_rows_leave_the_true_stripe_s_dim_rows_out_of_the_measured_side(tmp_path):
    """``--rows clear``: the measured side scores the rows where the reference rule sees the true stripe less those
    where it stands under ``dim_share`` of its typical height (:func:`bench.evaluate.rowstates.dim_rows` along the
    truth), as a photograph's reference leaves them out; the prediction is unchanged. The quick profile's stripes stand
    evenly, so the share is raised here to 0.8 (a settings object passed to the study) to give the rule rows to leave
    out."""
    from bench.config import parse_trackers_arg
    from bench.config import profile as load_profile
    from bench.evaluate import rowstates as rs
    from bench.evaluate import stripe as sp
    from bench.evaluate.outcomes import STRIPE, UNSURE, outcome_counts, referenced_states
    from bench.run import predict_frames as pf
    from bench.run.track import build_trackers
    from bench.evaluate.predict_settings import PredictSettings
    from bench.studies.predict_check import case_frames, study
    from bench.studies.predict_score import family_of

    high = PredictSettings(dim_share=0.8)
    runs = {}
    for v in ("seen", "clear"):
        out = tmp_path / v
        assert study(out=out, profile="quick", size=128, trackers=parse_trackers_arg("threshold"), rows=v, quiet=True,
                     settings=high) == 0
        runs[v] = (json.loads((out / "predict_check.json").read_text()), pd.read_csv(out / "measured.csv"),
                   pd.read_csv(out / "predicted.csv"))
    assert runs["clear"][0]["settings"]["dim_share"] == 0.8
    doc, measured, predicted = runs["clear"]
    assert doc["rows"] == "clear" and family_of(doc) == "quick: native"
    assert family_of(runs["seen"][0]) == "quick: native, rows seen"
    pd.testing.assert_frame_equal(predicted, runs["seen"][2])  # the prediction does not depend on it
    config = load_profile("quick")
    tr = build_trackers(parse_trackers_arg("threshold"))
    n_dim, n_clipped, names = 0, 0, []
    for name, case, _ in case_frames(config.experiments[0], config, seed=1, width=128, height=120,
                                     n_angles=3):
        seen = referenced_states(case.image, case.truth_columns)
        along = sp.stripe_extents(case.image, guide=case.truth_columns)
        clipped = rs.clipped_peaks(case.original, along)
        with_clipped = rs.seen_states(case.image, case.truth_columns, clipped)  # a clipped core is seen
        n_clipped += int(((with_clipped == STRIPE) & (seen != STRIPE)).sum())
        dim = rs.dim_rows(along, clipped=clipped, guided=True, settings=high) & (with_clipped == STRIPE)
        n_dim += int(dim.sum())
        for rows, states in (("seen", seen), ("clear", np.where(dim, UNSURE, with_clipped))):
            want = outcome_counts(pf.score_frame(tr, case.image, case.truth_columns, states=states)["threshold"])
            m = runs[rows][1]
            got = m[(m["experiment"] == name) & (m["tracker"] == "threshold")].iloc[0]
            assert {k: int(got[k]) for k in want} == want
        names.append(name)
    stripe_rows = {r: int(m[m["experiment"].isin(names)].eval("n_hit + n_wrong + n_missed").sum())
                   for r, (_, m, _) in runs.items()}
    assert n_dim > 0 and stripe_rows["clear"] == stripe_rows["seen"] - n_dim + n_clipped  # one outcome per row
    with pytest.raises(ValueError, match="`rows` must be one of seen, clear"):
        study(out=tmp_path / "bad", rows="all")


def test_predictscore_against_prints_each_family_s_paired_difference(checked, tmp_path, capsys):
    """``--against``: each run beside the other version's run of its family and seed; a copy whose cases are all
    0.01 further off differs by exactly that, and a run without a partner is one line and status 2."""
    from bench.studies.predict_score import objective, paired

    doc = json.loads((checked / "predict_check.json").read_text())
    worse = json.loads(json.dumps(doc))
    for case in worse["cases"].values():
        for k in ("hit_rate", "f1"):
            case[k]["mean_abs_diff"] += 0.01
    worse["pooled"]["hit_rate"]["mean_abs_diff"] += 0.02  # the pooled score is the mean of hit rate's and F1's
    worse["code"] = dict(doc["code"], fingerprint="0" * 16)  # another version's run
    other = tmp_path / "worse"
    other.mkdir()
    (other / "predict_check.json").write_text(json.dumps(worse))
    p = paired({"worse": worse}, {"base": doc})
    assert p["per_case"] == pytest.approx(0.01) and p["families"]["quick: native"]["n"] == 1
    assert p["per_case"] == pytest.approx(objective({"w": worse})["per_case"] - objective({"b": doc})["per_case"])
    assert p["pooled"] == pytest.approx(0.01)
    capsys.readouterr()
    assert main(["predictscore", str(other), "--against", str(checked)]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    assert out[-1].startswith("per-case score +0.01000;") and "paired with --against" in out[-4]
    assert "pooled score +0.01000" in out[-1]
    seed2 = dict(doc, seed=2)
    (tmp_path / "s2").mkdir()
    (tmp_path / "s2" / "predict_check.json").write_text(json.dumps(seed2))
    assert main(["predictscore", str(tmp_path / "s2"), "--against", str(checked)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "the RUNs have no run of family 'quick: native' and seed 1 to pair with" in err[0]
    assert main(["predictscore", str(checked), "--against", str(tmp_path / "s2")]) == 2
    assert "--against has no run of family 'quick: native' and seed 1" in capsys.readouterr().err


def test_a_run_records_its_code_and_two_runs_of_the_same_code_are_not_paired(checked, tmp_path, capsys):
    """``predict_check.json`` names the code that made it (``code_of_run``: the source fingerprint of ``bench``,
    ``trackers`` and ``scenes``); pairing a run with one made by the same code is one line and status 2 (a candidate
    run from the base's folder, whose paired differences would all be nought), and a run from before runs recorded
    their code still pairs."""
    from bench.studies.predict_check import code_of_run
    from bench.studies.predict_score import paired

    doc = json.loads((checked / "predict_check.json").read_text())
    assert doc["code"] == code_of_run() and len(doc["code"]["fingerprint"]) == 16
    copy = tmp_path / "copy"
    copy.mkdir()
    (copy / "predict_check.json").write_text(json.dumps(doc))
    with pytest.raises(ValueError, match="made by the same code"):
        paired({"copy": doc}, {"base": doc})
    capsys.readouterr()
    assert main(["predictscore", str(copy), "--against", str(checked)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"fingerprint {doc['code']['fingerprint']}" in err[0]
    old = {k: v for k, v in doc.items() if k != "code"}
    assert paired({"old": old}, {"base": doc})["per_case"] == 0.0


def test_fallback_states_read_both_sides_rows_as_a_reference_without_states(tmp_path):
    """``--states fallback``: the measured side's rows and the prediction's frames are read as a reference without
    row states is (:func:`bench.evaluate.outcomes.fallback_of`): the stripe rows are the same on each side; the
    measured stripe-less rows change (rows without the laser near the stripe are no longer scored, unseen stretches
    far from it are); the prediction scores every stripe-less row it scored before and more."""
    from bench.studies.predict_check import study
    from bench.studies.predict_score import family_of

    runs = _quick_runs(tmp_path, "--states", ("given", "fallback"))
    (g_doc, g_meas, g_pred), (f_doc, f_meas, f_pred) = runs["given"], runs["fallback"]
    assert (g_doc["states"], f_doc["states"]) == ("given", "fallback")
    assert family_of(g_doc) == "quick: native" and family_of(f_doc) == "quick: native, states fallback"
    stripe = "n_hit + n_wrong + n_missed"
    none = "n_false + n_quiet"
    for g, f in ((g_meas, f_meas), (g_pred, f_pred)):
        assert (g.eval(stripe).to_numpy() == f.eval(stripe).to_numpy()).all()
    assert (f_meas.eval(none).to_numpy() != g_meas.eval(none).to_numpy()).any()
    assert (f_pred.eval(none).to_numpy() >= g_pred.eval(none).to_numpy()).all()
    assert (f_pred.eval(none).to_numpy() > g_pred.eval(none).to_numpy()).any()
    with pytest.raises(ValueError, match="`states` must be one of given, fallback, got 'none'"):
        study(out=tmp_path / "bad", states="none")


@pytest.mark.parametrize("content", ["[]", "null", '"text"', "3", "[" * 5000 + "]" * 5000, '{"cases": []}',
                                     '{"cases": {"a": 1}, "pooled": {"f1": 2}}'])
def test_predictscore_on_a_damaged_result_is_one_line(tmp_path, capsys, content):
    """A predict_check.json that is a list, null, a string, a number, nested past any sense or of the wrong shape:
    one line naming the folder, exit 2 (no AttributeError, RecursionError or TypeError)."""
    run = tmp_path / "run"
    run.mkdir()
    (run / "predict_check.json").write_text(content)
    capsys.readouterr()
    assert main(["predictscore", str(run)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"stripebench predictscore: {str(run)!r} is not a finished predictcheck")
    assert len(err[0]) < 400


def test_predictcheck_refuses_to_replace_another_configuration_s_finished_check(checked, tmp_path, capsys):
    """--out holding a finished check of another configuration (here another seed) is refused in one line before
    anything renders; the same configuration again, or --force, writes."""
    import shutil

    out = tmp_path / "copy"
    shutil.copytree(checked, out)
    before = (out / "predict_check.json").read_text()
    capsys.readouterr()
    assert main(["predictcheck", "--out", str(out), "--profile", "quick", "--size", "128", "--trackers",
                 "threshold,dp8", "--seed", "2", "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "holds a finished check of another configuration (seed: 1 there, 2 here)" in err[0]
    assert "use --force" in err[0] and (out / "predict_check.json").read_text() == before
    assert main(["predictcheck", "--out", str(out), "--profile", "quick", "--size", "128", "--trackers",
                 "threshold,dp8", "--seed", "2", "--quiet", "--force"]) == 0
    assert json.loads((out / "predict_check.json").read_text())["seed"] == 2
