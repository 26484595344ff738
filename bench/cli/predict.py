"""``stripebench predict``: frames with truth made of a rig's photographs (each one's stripe moved), and the trackers'
figures predicted from them; ``stripebench predictcheck``: the same procedure checked on renders, where the truth is
known; ``stripebench predictscore``: the declared objective over finished checks."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from bench.cli.common import Command, UsageError, check_out_folder, study_command
from bench.cli.options import add_force, add_n_boot, add_out, add_quiet, add_seed, add_trackers, arg_type
from bench.config.options import finite_float, int_in_range

__all__ = ["COMMANDS", "SIZES", "terminal_lines", "predict_check_options", "predict_score_options",
           "predict_loro_options"]
#: The render widths ``predictcheck --size`` takes (px; the height is 15/16 of it).
SIZES = (128, 256, 512)


def _add_predict(p) -> None:
    from bench.evaluate.stripe import SHRINKS
    from bench.store.realset import CHANNELS, LASERS, ROTATIONS

    p.add_argument("photos", type=Path, metavar="PHOTOS",
                   help="a folder of photographs from one rig (NAME_off.EXT: laser-off frames; a real set also works, "
                        "its references ignored)")
    add_out(p, "output folder", required=True)
    add_force(p)
    add_trackers(p, "tracker names or settings as for `run` (default: every listed tracker and learned)")
    p.add_argument("--channel", default="auto", choices=CHANNELS,
                   help="what the trackers see of a colour image (auto: excess of the laser's colour)")
    p.add_argument("--laser", default="red", choices=LASERS, help="laser colour (default red)")
    p.add_argument("--rotate", type=int, default=0, choices=ROTATIONS,
                   help="turn the image counter-clockwise first (for horizontal stripes)")
    p.add_argument("--downscale", type=int, default=1, choices=SHRINKS,
                   help="average each N x N block of pixels first, for trackers that run on shrunk frames (a phone's "
                        "full-size photograph: its stripe may be wider than the reference window); default 1")
    p.add_argument("--calibration", type=Path, default=None, metavar="JSON",
                   help="the calibration the figures are stated by (default: the shipped set's, judged leave one rig "
                        "out; `stripebench predictloro --calibration` writes one)")
    add_n_boot(p)
    add_seed(p, "bootstrap seed", default=0)
    add_quiet(p)


def _predict(args) -> int:
    """Measure, move, track: the stated figures, the pick and their page."""
    from bench.config import parse_trackers
    from bench.run.predict import default_trackers, run_predict
    from bench.store.predictfiles import read_calibration

    specs = args.trackers if args.trackers is not None else parse_trackers(default_trackers())
    if not args.photos.is_dir():
        raise UsageError(f"PHOTOS must be a folder, got {str(args.photos)!r}")
    check_out_folder(args.out)
    out = Path(args.out)
    if out.is_dir() and any(out.iterdir()) and not (out / "predict.json").is_file() and not args.force:
        raise UsageError(f"--out {str(out)!r} holds other files (not a prediction); use --force to write into it")
    calibration = read_calibration(args.calibration)
    if args.calibration is not None and calibration is None:
        raise UsageError(f"--calibration {str(args.calibration)!r}: no such file")
    say = (lambda m: None) if args.quiet else (lambda m: print(m, file=sys.stderr, flush=True))
    from bench.report.predict import build_predict_report

    result = run_predict(args.photos, out, specs, channel=args.channel, laser=args.laser, rotate_deg=args.rotate,
                         downscale=args.downscale, n_boot=args.n_boot, seed=args.seed, calibration=calibration,
                         say=say)
    page = build_predict_report(result)
    if not any(m.answered for m in result["made"].values()):
        print(f"stripebench predict: none of the {len(result['made'])} photographs has a prediction, at its own size "
              f"or shrunk (why: {page})", file=sys.stderr)
        return 2
    for line in terminal_lines(result, table=not args.quiet):
        print(line)
    print(f"stripebench: predictions in {out} (report {page})")
    return 0


def terminal_lines(result: dict, *, table: bool = True) -> list[str]:
    """What ``predict`` prints (:func:`bench.run.predict.run_predict`'s ``result``): the pick, its chance of being
    best and the trackers tied with it, its leave-one-rig-out regret; with ``table``, each tracker's stated figures
    with their intervals and sources, and where each source was judged."""
    from bench.evaluate.predict_loro import SOURCES

    figures = ("f1", "false_report_rate", "hit_rate")  # the pick's figure first

    p, pred, calib = result["pick"], result["predicted"], result["calibration"]
    lines = []
    if p["tracker"] is None:
        lines.append("no pick: no tracker has an F1 to rank by")
    else:
        tied = f"; tied with {', '.join(p['tied'])}" if p["tied"] else "; no tracker tied with it"
        whose = "the null's (the shipped set's best on average)" if p["source"] == "null" else "by these photographs"
        lines.append(f"use {p['tracker']} ({whose}): the best in {p['chance']:.0%} of draws of these photographs "
                     f"with a shipped rig's errors{tied}")
        if p["loro_regret"]:
            r = p["loro_regret"]
            lines.append(f"  judged leave one rig out on the shipped set ({len(calib['rigs'])} rigs): the pick's mean "
                         f"regret {r['method']:.3f} F1 (the null's pick: {r['null']:.3f})")
        else:
            lines.append("  no calibration: the pick is not judged (stripebench predictloro --calibration)")
    if not table:
        return lines
    level = f"{calib['level']:.0%} " if calib else ""
    names = {"f1": "F1", "false_report_rate": "false reports", "hit_rate": "hit rate"}
    lines.append(f"{'tracker':<14}" + "".join(f"{names[f] + ' [' + level + 'interval]':>32}" for f in figures))
    short = {SOURCES["method"]: "", SOURCES["null"]: " null", SOURCES[None]: " uncal."}
    for r in pred.to_dict("records"):
        cells = ""
        for f in figures:
            lo, hi, src = r[f + "_lo"], r[f + "_hi"], r[f + "_source"]
            iv = "" if not np.isfinite(lo) else f" [{lo:.2f}, {hi:.2f}]"
            cells += f"{r[f]:.3f}{iv}{short[src]}".rjust(32)
        mark = "*" if r["pick"] else ("=" if r["tied"] else " ")
        lines.append(f"{mark}{r['tracker']:<13}{cells}")
    if calib:
        for f in figures:
            c = calib[f]
            src = c["source"]
            what = ("predicted from these photographs" if src == "method" else
                    f"the null's, the shipped set's mean (predicted, its error was {c['error']['method']:.3f} "
                    f"against the null's {c['error']['null']:.3f})")
            lines.append(f"{names[f]}: {what}; leave one rig out its intervals held {c['coverage'][src]:.0%} of the "
                         f"measured figures, mean width {c['width'][src]:.2f}")
    else:
        lines.append("no calibration: the figures are the method's own, without intervals")
    lines.append("* the pick, = tied with it")
    return lines


def predict_check_options(p) -> None:
    """The options of ``stripebench predictcheck`` (:func:`bench.studies.predict_check.study`)."""
    from bench.config import PROFILES
    from bench.studies.predict_check import BAR, CASE_CHANNELS, DEFAULTS, DISTRACTORS, FAMILIES, ROWS, STATE_READINGS, \
        TRUTHS

    add_out(p, "output folder (predict_check.json, predicted.csv, measured.csv)", required=True)
    p.add_argument("--profile", default=DEFAULTS["profile"], choices=sorted(PROFILES),
                   help=f"the profile whose experiments are the cases (default {DEFAULTS['profile']})")
    add_force(p, "; replace another configuration's finished check")
    add_seed(p, "the cases' render seed", default=DEFAULTS["seed"])
    p.add_argument("--size", type=int, default=DEFAULTS["size"], choices=SIZES,
                   help=f"render width in px of the cases (default {DEFAULTS['size']})")
    p.add_argument("--downscale", type=int, default=DEFAULTS["downscale"], choices=(1, 2, 4),
                   help="render the cases this many times larger and shrink them back, as a phone's frames are: "
                        "stripes standing far above the noise (default 1)")
    p.add_argument("--line-fwhm", dest="line_fwhm_mrad", metavar="MRAD",
                   type=arg_type(lambda n, v: finite_float(n, v, low=0, low_open=True), "--line-fwhm"), default=None,
                   help="every case's laser line width in mrad instead of its own (narrower: thinner, brighter)")
    p.add_argument("--laser-power", dest="laser_power_mw", metavar="MW",
                   type=arg_type(lambda n, v: finite_float(n, v, low=0, low_open=True), "--laser-power"), default=None,
                   help="every case's laser power in mW instead of its own (with a wide --line-fwhm: a wide, bright "
                        "stripe, as a webcam's saturated one)")
    p.add_argument("--channel", default=DEFAULTS["channel"], choices=CASE_CHANNELS,
                   help="what the trackers see of a colour case: auto (the laser-colour blend; default) or laser "
                        "(the laser's own channel, as a rig whose software reads one channel)")
    p.add_argument("--distractor", default=DEFAULTS["distractor"], choices=DISTRACTORS,
                   help="what each case frame carries besides its render: none (default), white-bar (a vertical "
                        "white line beside the stripe, a window's frame or a lamp's stem, added to the photograph) or "
                        f"rival-fringe (the white bar with a fringe carrying {BAR.fringe_share} of the stripe's laser "
                        "evidence)")
    p.add_argument("--jpeg-quality", dest="jpeg_quality", metavar="Q",
                   type=arg_type(lambda n, v: int_in_range(n, v, 1, 95), "--jpeg-quality"),
                   default=DEFAULTS["jpeg_quality"],
                   help="JPEG-compress each case frame's photograph at this quality (1-95), as a webcam or a phone "
                        "does (default: not compressed)")
    p.add_argument("--truth", default=DEFAULTS["truth"], choices=TRUTHS,
                   help="what the measured side scores against: render (the render's truth, the laser sheet's "
                        "centre; default) or reference (the columns a photograph's reference would give: the "
                        "intensity centre near it)")
    p.add_argument("--rows", default=DEFAULTS["rows"], choices=ROWS,
                   help="which stripe rows the measured side scores: clear (every row where the reference rule sees "
                        "the true stripe, less those a photograph's reference leaves out as unclear; default) or seen "
                        "(all of them)")
    p.add_argument("--states", default=DEFAULTS["states"], choices=STATE_READINGS,
                   help="how rows that are not scored stripe rows are read, on both sides: given (as the render's "
                        "truth gives them; default) or fallback (as a real set's reference without row states: every "
                        "row 15 or more rows from a scored stripe row has no stripe)")
    p.add_argument("--family", default=DEFAULTS["family"], choices=tuple(FAMILIES),
                   help="a named render family, which sets its own options: native, phone (--downscale 4 "
                        "--line-fwhm 1.2), plain (--channel laser), rival-fringe (--distractor rival-fringe), "
                        "white-core (--laser-power 50: cores clipped white), marble-60mw-jpeg (--profile marble "
                        "--laser-power 60 --jpeg-quality 75), marble-480mw (--profile marble --laser-power 480); an "
                        "option it sets, given otherwise, is an error (docs/predict.md)")
    add_trackers(p, "tracker names or settings as for `run` (default: the profile's)")
    add_quiet(p)


def predict_score_options(p) -> None:
    """The options of ``stripebench predictscore`` (:func:`bench.studies.predict_check.score`)."""
    p.add_argument("runs", type=Path, nargs="+", metavar="RUN", help="finished predictcheck output folders")
    p.add_argument("--against", type=Path, nargs="+", metavar="RUN", default=None,
                   help="runs of another version of the procedure, one of each RUN's family and seed: print each "
                        "family's paired difference, its mean and its spread over the seeds")
    p.add_argument("--min-rows", dest="min_rows", metavar="N", default=0,
                   type=arg_type(lambda n, v: int_in_range(n, v, 0), "--min-rows"),
                   help="leave out of the per-case figures the cases measured on fewer than N stripe rows (their hit "
                        "rate is mostly noise); the pooled figures keep them (default 0: none left out)")


def predict_loro_options(p) -> None:
    """The options of ``stripebench predictloro`` (:func:`bench.studies.predict_loro.study`)."""
    p.add_argument("dataset", type=Path, metavar="DATASET", help="a real set whose manifest names each photograph's rig")
    add_out(p, "output folder (real/, predict/, predict_loro.json)", required=True)
    add_force(p)
    add_trackers(p, "tracker names or settings as for `run` (default: predict's, every listed tracker and learned)")
    p.add_argument("--calibration", type=Path, default=None, metavar="JSON",
                   help="also write the calibration predict states figures by (the shipped one: "
                        "bench/data/predict_calibration.json)")
    p.add_argument("--candidates", action="store_true",
                   help="also print the declared candidates of docs/predict.md beside the adopted procedure")
    add_n_boot(p)
    add_seed(p, "bootstrap and draw seed", default=0)
    add_quiet(p)


COMMANDS = (
    Command("predict", "predict trackers' figures on a rig's photographs from frames with truth made of them",
            _add_predict, _predict, renders=True),
    study_command("predictcheck", "check predict where the truth is known: renders standing in for photographs",
                  predict_check_options, "bench.studies.predict_check:study", renders=True),
    study_command("predictloro", "predict judged leave one rig out against the null prediction on a labelled set",
                  predict_loro_options, "bench.studies.predict_loro:study"),
    study_command("predictscore", "the declared objective over finished predictcheck runs: per-case and pooled "
                  "scores, per family", predict_score_options, "bench.studies.predict_score:score"),
)
