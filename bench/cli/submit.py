"""Trackers from any language: ``stripebench export``, ``score`` and ``leaderboard``.

``export`` writes a configuration's frames as a frame set (:mod:`bench.run.export`),
``score`` turns a submission on it into an ordinary run (:mod:`bench.run.score`),
``leaderboard`` ranks the trackers of comparable runs (:mod:`bench.report.leaderboard`).
"""

from __future__ import annotations

import sys
from pathlib import Path

from bench.cli.common import Command, UsageError, check_env, check_out_folder
from bench.cli.options import add_force, add_out, add_quiet, add_seed, add_trackers, arg_type
from bench.config.options import finite_float, seed_value

__all__ = ["COMMANDS"]

CONFIG_DOC = "docs/config.md"


def _add_export(p) -> None:
    from bench.config import PROFILES

    p.add_argument("config", nargs="?", type=Path, help=f"configuration file (format: {CONFIG_DOC})")
    p.add_argument("--profile", choices=PROFILES, help="an embedded configuration instead")
    add_out(p, "the frame set's folder", required=True)
    p.add_argument("--test-fraction", type=arg_type(lambda n, v: finite_float(n, v, low=0, high=1), "--test-fraction"),
                   default=0.3, metavar="F",
                   help="share of frames in the test split (truth in truth_test/; 0 .. 1, default 0.3)")
    add_seed(p, "seed for renders and the split")
    p.add_argument("--test-seed", type=arg_type(seed_value, "--test-seed"), metavar="N",
                   help="seed of the test frames' angles and renders (default: a fresh secret one, kept in "
                        "truth_test/withheld.json; give that one to write the same frame set again)")
    p.add_argument("--participants", type=Path, metavar="DIR",
                   help="also write a participants' bundle to DIR: the frame set without the test split's truth "
                        "(hand it out; keep --out to score the submissions)")
    add_force(p)
    add_quiet(p, "no progress notes")


def _export(args) -> int:
    from bench.config import load, profile, with_overrides
    from bench.run.export import export

    if (args.config is None) == (args.profile is None):
        raise UsageError("give a CONFIG.toml or --profile (one of them)")
    config = load(args.config) if args.config is not None else profile(args.profile)
    if args.seed is not None:
        config = with_overrides(config, seed=args.seed)
    check_env()
    check_out_folder(args.out, inputs=[("CONFIG", args.config)])
    if args.participants is not None:
        from bench.run.export import check_bundle_folder

        check_out_folder(args.participants, "--participants")
        check_bundle_folder(args.out, args.participants)
    out = export(config, args.out, test_fraction=args.test_fraction, test_seed=args.test_seed, quiet=args.quiet,
                 force=args.force)
    print(f"stripebench: frame set at {out}")
    if args.participants is not None:
        from bench.run.export import participants_bundle

        bundle = participants_bundle(out, args.participants, force=args.force)
        print(f"stripebench: participants' bundle (no test truth) at {bundle}")
    return 0


def _add_score(p) -> None:
    p.add_argument("dataset", type=Path, help="frame set folder (stripebench export)")
    p.add_argument("submission", type=Path,
                   help="folder with submission.csv (frame,row,col[,score]) and optionally times.csv (frame,ms)")
    add_out(p, "the scored run's folder", required=True)
    p.add_argument("--label", help="the submission's label (default: the submission folder's name)")
    add_trackers(p, "built-in trackers to run beside it, as for `run` (default: the frame set's configuration's)")
    p.add_argument("--alone", action="store_true", help="score the submission alone: no built-in tracker beside it")
    p.add_argument("--split", default="all", choices=["all", "dev", "test"], help="which frames to score")
    add_force(p)
    add_quiet(p, "no progress notes")
    p.add_argument("--no-report", action="store_true", help="write the results only, not figures and report.html")


def _score(args) -> int:
    from bench.run.score import SubmissionError, score

    check_env()
    check_out_folder(args.out, inputs=[("DATASET", args.dataset), ("SUBMISSION", args.submission)])
    if args.alone and args.trackers is not None:
        raise UsageError("--alone and --trackers exclude each other: --alone runs no built-in tracker")
    try:
        out = score(args.dataset, args.submission, args.out, label=args.label,
                    trackers=() if args.alone else args.trackers,
                    split=args.split, quiet=args.quiet, force=args.force)
    except SubmissionError as exc:
        from bench.errors import one_line

        for line in exc.problems:
            print(f"stripebench score: {one_line(line)}", file=sys.stderr)
        return 2
    if args.no_report:
        print(f"stripebench: results in {out}")
        return 0
    from bench.report.run import build_report
    from bench.store.runfolder import RunFolder

    with RunFolder(out, kind="score") as folder:
        folder.lock()
        path = build_report(out, quiet=args.quiet)
    print(f"stripebench: report at {path}")
    return 0


def _add_leaderboard(p) -> None:
    from bench.report.leaderboard import DEFAULT_RANK_BY, RANK_BY

    p.add_argument("runs", nargs="+", type=Path, metavar="RUN", help="finished run or scored-submission folders")
    add_out(p, "output folder (leaderboard.html, leaderboard.csv)", required=True)
    p.add_argument("--rank-by", choices=RANK_BY, default=DEFAULT_RANK_BY,
                   help="rank by F1 over rows (default: misses and false reports alike), AP over rows (the "
                        "tracker's score ranking its reports), or the ±5 mm fraction of sample points (within: the "
                        "paper's reading, blind to false reports); the false-report rate stands beside each")


def _leaderboard(args) -> int:
    from bench.report.leaderboard import LeaderboardError, build_leaderboard

    check_out_folder(args.out)
    notes = []
    try:
        page = build_leaderboard(args.runs, args.out, args.rank_by, notes)
    except LeaderboardError as exc:
        raise UsageError(str(exc)) from None
    for n in notes:
        print(f"stripebench: leaderboard: {n}", file=sys.stderr)
    print(f"stripebench: leaderboard at {page} (and {page.with_suffix('.csv').name})")
    return 0


COMMANDS = (
    Command("export", "write a configuration's frames as a frame set (PNGs, truth CSVs) for any program to track",
            _add_export, _export, renders=True),
    Command("score", "score a submission (submission.csv, times.csv) on an exported frame set as a run",
            _add_score, _score),
    Command("leaderboard", "rank the trackers of comparable runs per condition: one HTML page and a CSV",
            _add_leaderboard, _leaderboard),
)
