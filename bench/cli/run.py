"""``stripebench reproduce``, ``run``, ``report``, ``check``, ``compare``: experiments, their reports,
the regression gate."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from bench.cli.common import Command, UsageError, check_env, check_out_folder
from bench.config import PROFILES
from bench.cli.options import add_force, add_out, add_quiet, add_seed, add_trackers

__all__ = ["COMMANDS", "add_run_options", "run_config"]

CONFIG_DOC = "docs/config.md"


def add_run_options(p) -> None:
    """The options of ``reproduce`` and ``run``."""
    add_trackers(p, "comma-separated tracker names or TOML inline tables {label=..., name=..., params={...}} "
                    "(default: the configuration's)")
    add_out(p, "run folder (default: results/runs/<name>-<config hash>; a partial run of the same configuration "
               "there is resumed)")
    add_force(p)
    add_seed(p)
    add_quiet(p)
    p.add_argument("--no-report", action="store_true", help="write the results only, not figures and report.html")
    p.add_argument("--predict", action="store_true",
                   help="with a real set (the configuration's real_set), also predict the trackers' figures on its "
                        "photographs beside the measured ones (the configuration key real_predict = true; "
                        "docs/predict.md)")
    p.add_argument("--no-render-ahead", action="store_true",
                   help="render every frame in this process only, no helper process (the same results; "
                        "the configuration key render_ahead = false)")


def run_config(config, args) -> int:
    """Run ``config`` with the command-line overrides of :func:`add_run_options`, then build its report."""
    from bench.config import check_real_set, with_overrides
    from bench.run.experiment import run

    changes = {}
    if args.trackers is not None:
        labels = [s.label for s in args.trackers]
        changes["trackers"] = [s.to_value() for s in args.trackers]
        changes["baselines"] = [b for b in config.baselines if b in labels]
        changes["dp"] = [d for d in config.dp if d in labels]
    if args.seed is not None:
        changes["seed"] = args.seed
    if args.no_render_ahead:
        changes["render_ahead"] = False
    if args.predict:
        if not config.real_set:
            raise UsageError("--predict needs a configuration with a real set (real_set = \"shipped\" or a folder)")
        changes["real_predict"] = True
    if changes:
        config = with_overrides(config, **changes)
    check_env()
    check_out_folder(args.out, inputs=[("CONFIG", getattr(args, "config", None))])
    check_real_set(config.real_set, full=True)  # a broken real set is found before any scan, not after
    out = run(config, args.out, progress=not args.quiet, quiet=args.quiet, force=args.force)
    _print_headline(out)
    if args.no_report:
        print(f"stripebench: results in {out}")
        return 0
    from bench.report.run import build_report
    from bench.store.runfolder import RunFolder

    with RunFolder(out) as folder:
        folder.lock()  # no other process may change the folder while its report is built
        path = build_report(out, quiet=args.quiet)
    print(f"stripebench: report at {path}")
    return 0


def _print_headline(out) -> None:
    """The run's headline on the terminal (:func:`bench.evaluate.readings.headline_lines`: the paper's claim per
    reading of its method without DP, as the report leads with it)."""
    from bench.evaluate.readings import headline_lines
    from bench.store.runfolder import load_summary

    lines = headline_lines(load_summary(out))
    if lines:
        print("\n".join(lines))


def _add_reproduce(p) -> None:
    p.add_argument("--profile", default="paper", choices=PROFILES, help="embedded configuration (default: paper)")
    add_run_options(p)


def _reproduce(args) -> int:
    from bench.config import profile

    return run_config(profile(args.profile), args)


def _add_run(p) -> None:
    p.add_argument("config", nargs="?", type=Path, help=f"configuration file (format: {CONFIG_DOC})")
    p.add_argument("--profile", choices=PROFILES, help="an embedded configuration instead")
    add_run_options(p)


def _run(args) -> int:
    from bench.config import load, profile

    if args.config is None and args.profile is None:
        raise UsageError("give a CONFIG.toml or --profile")
    if args.config is not None and args.profile is not None:
        raise UsageError("give a CONFIG.toml or --profile, not both")
    config = load(args.config) if args.config is not None else profile(args.profile)
    return run_config(config, args)


def _add_report(p) -> None:
    p.add_argument("run", type=Path, help="run folder")
    add_quiet(p)


def _report(args) -> int:
    from bench.report.run import build_report
    from bench.store.runfolder import RunFolder, load_summary

    summary = load_summary(args.run)  # one line if it is not a finished run
    with RunFolder(args.run) as folder:
        folder.lock()
        if summary.get("kind") == "real":
            from bench.report.real import build_real_report

            path = build_real_report(args.run)
        else:
            path = build_report(args.run, quiet=args.quiet)
    print(f"stripebench: report at {path}")
    return 0


def _json_options(p, what: str) -> None:
    p.add_argument("--json", action="store_true", help=f"print {what} as JSON")
    p.add_argument("--all", action="store_true", help="show every check, not only the changed ones")


def _gate_rows(baseline: dict, current: dict, what: str, *, across_sampling: bool = False):
    from bench.run import gate

    diff = gate.comparability(baseline.get("config"), current.get("config"), across_sampling=across_sampling)
    if diff:
        raise UsageError(f"{what} are not comparable: they differ in {'; '.join(diff)} "
                         f"(compared: {', '.join(gate.COMPARED_KEYS)})")
    return gate.compare(baseline, current)


def _print_rows(rows, args) -> int:
    from bench.run import gate

    if args.json:
        print(json.dumps(gate.rows_to_json(rows, all_rows=args.all), indent=1))
    else:
        print(gate.format_table(rows, all_rows=args.all))
    return 1 if any(r.failed for r in rows) else 0


def _add_check(p) -> None:
    p.add_argument("run", type=Path, help="run folder")
    p.add_argument("--baseline", type=Path, required=True, help="baseline JSON (e.g. results/baselines/ci.json)")
    p.add_argument("--update", action="store_true", help="write the run's metrics as the new baseline instead")
    _json_options(p, "the checks")


def _check(args) -> int:
    from bench.run import gate

    current = gate.baseline_from_run(args.run)
    if args.update:
        doc = gate.write_baseline(args.run, args.baseline)
        print(f"stripebench: wrote baseline {args.baseline} ({len(doc['metrics'])} entries) from {args.run}")
        return 0
    baseline = gate.load_baseline(args.baseline)
    what = f"run {str(args.run)!r} and baseline {str(args.baseline)!r}"
    if gate.renderer_difference(baseline, current):
        raise UsageError(f"{what} are not comparable: their frames were rendered differently, "
                         f"{gate.renderer_difference(baseline, current)} (docs/gate.md)")
    rows = _gate_rows(baseline, current, what)
    status = _print_rows(rows, args)
    if status:
        failed = [r for r in rows if r.failed]
        names = sorted({f"{r.key.split('/')[1] if '/' in r.key else r.key}:{r.metric}" for r in failed})
        print(f"stripebench check: FAILED ({len(failed)} regression(s): {', '.join(names[:12])}"
              f"{' ...' if len(names) > 12 else ''})", file=sys.stderr)
    elif not args.json:
        print("stripebench check: passed")
    return status


def _add_compare(p) -> None:
    p.add_argument("run_a", metavar="RUN_A", type=Path, help="the reference run folder")
    p.add_argument("run_b", metavar="RUN_B", type=Path, help="the run folder compared with it")
    p.add_argument("--across-sampling", action="store_true",
                   help="compare runs whose [render] spp / ambient_spp differ (the same frames up to their Monte "
                        "Carlo noise, e.g. a run at spp = 16 against one at spp = \"auto\")")
    _json_options(p, "the comparison")


def _compare(args) -> int:
    from bench.run import gate

    a, b = gate.baseline_from_run(args.run_a), gate.baseline_from_run(args.run_b)
    rows = _gate_rows(a, b, f"runs {str(args.run_a)!r} and {str(args.run_b)!r}", across_sampling=args.across_sampling)
    status = _print_rows(rows, args)
    if not args.json:
        print(f"stripebench compare: {args.run_b} against {args.run_a}: "
              f"{sum(r.failed for r in rows)} worse or missing, {sum(r.verdict == 'better' for r in rows)} better")
    return status


COMMANDS = (
    Command("reproduce", "the paper's experiment on the embedded default settings", _add_reproduce, _reproduce,
            renders=True),
    Command("run", "run an experiment configuration (TOML) or an embedded profile", _add_run, _run,
            epilog=f"The configuration format, with a complete example: {CONFIG_DOC}.", renders=True),
    Command("report", "rebuild the figures and report.html of a finished run", _add_report, _report),
    Command("check", "compare a run's metrics with a baseline; exit 1 on a regression", _add_check, _check),
    Command("compare", "compare two runs' metrics (RUN_B against RUN_A); exit 1 if RUN_B is worse", _add_compare,
            _compare, description="The same table as `check`, RUN_A taking the baseline's place. Refused when "
                                  "the runs differ in render size/spp (spp alone: `--across-sampling`), experiments or seed."),
)
