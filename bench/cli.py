"""The ``stripebench`` command line.

Exit status: 0 success, 1 a failed check (``stripebench check``), 2 a usage or
configuration error (one line on stderr naming the problem), 130 interrupted.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

__all__ = ["main", "build_parser"]


class UsageError(Exception):
    """A bad command-line value: one line for the user, exit status 2."""


def _trackers_arg(value: str | None):
    if value is None:
        return None
    import trackers

    names = [n.strip() for n in value.split(",") if n.strip()]
    if not names:
        raise UsageError(f"--trackers must name at least one tracker, got {value!r}")
    for n in names:
        if n not in trackers.available():
            raise UsageError(f"--trackers: unknown tracker {n!r}; available: {', '.join(trackers.available())}")
    return names


def _seed_arg(value: str) -> int:
    try:
        seed = int(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer >= 0, got {value!r}") from None
    if seed < 0:
        raise argparse.ArgumentTypeError(f"must be an integer >= 0, got {value!r}")
    return seed


def _run_config(config, args) -> int:
    from .config import with_overrides
    from .experiment import run

    changes = {}
    names = _trackers_arg(args.trackers)
    if names is not None:
        changes["trackers"] = names
        changes["baselines"] = [b for b in config.baselines if b in names]
        changes["dp"] = [d for d in config.dp if d in names]
    if args.seed is not None:
        changes["seed"] = args.seed
    if changes:
        config = with_overrides(config, **changes)
    out = run(config, args.out, progress=not args.quiet, quiet=args.quiet)
    print(f"stripebench: report at {out / 'report.html'}")
    return 0


def _cmd_reproduce(args) -> int:
    from .config import profile

    return _run_config(profile(args.profile), args)


def _cmd_run(args) -> int:
    from .config import load, profile

    if args.config is None and args.profile is None:
        raise UsageError("give a CONFIG.toml or --profile")
    if args.config is not None and args.profile is not None:
        raise UsageError("give a CONFIG.toml or --profile, not both")
    config = load(args.config) if args.config is not None else profile(args.profile)
    return _run_config(config, args)


def _cmd_report(args) -> int:
    from .report import build_report

    run_dir = Path(args.run)
    if not (run_dir / "summary.json").exists():
        raise UsageError(f"RUN must be a finished run folder (with summary.json), got {str(run_dir)!r}")
    path = build_report(run_dir, quiet=args.quiet)
    print(f"stripebench: report at {path}")
    return 0


def _cmd_check(args) -> int:
    from . import gate

    run_dir = Path(args.run)
    if not (run_dir / "metrics.parquet").exists() or not (run_dir / "summary.json").exists():
        raise UsageError(f"RUN must be a finished run folder (with metrics.parquet), got {str(run_dir)!r}")
    if args.update:
        doc = gate.write_baseline(run_dir, args.baseline)
        print(f"stripebench: wrote baseline {args.baseline} ({len(doc['metrics'])} entries) from {run_dir}")
        return 0
    try:
        baseline = gate.load_baseline(args.baseline)
    except (FileNotFoundError, ValueError) as exc:
        raise UsageError(str(exc)) from None
    rows = gate.compare(baseline, gate.baseline_from_run(run_dir))
    print(gate.format_table(rows, all_rows=args.all))
    failed = [r for r in rows if r.failed]
    if failed:
        names = sorted({f"{r.key.split('/')[1]}:{r.metric}" for r in failed})
        print(f"stripebench check: FAILED ({len(failed)} regression(s): {', '.join(names[:12])}"
              f"{' ...' if len(names) > 12 else ''})", file=sys.stderr)
        return 1
    print("stripebench check: passed")
    return 0


def _cmd_trackers(args) -> int:
    import trackers

    for name in trackers.available():
        t = trackers.make(name)
        doc = (type(t).__doc__ or "").strip().splitlines()
        print(f"{name:<14} {'sub-pixel' if t.subpixel else 'whole-pixel':<12} {doc[0] if doc else ''}")
    return 0


def _cmd_scenes(args) -> int:
    import scenes

    print("scenes:    " + ", ".join(scenes.available()))
    print("materials: " + ", ".join(scenes.MATERIALS))
    return 0


def _cmd_perf(args) -> int:
    if args.rest and args.rest[0] == "--scenes":
        from .perf import scenes as perf_scenes

        return perf_scenes.main(args.rest[1:])
    from .perf import trackers as perf_trackers

    return perf_trackers.main(args.rest)


def _cmd_estimators(args) -> int:
    from . import estimators

    return estimators.main(args.rest)


def _cmd_translucency(args) -> int:
    from . import translucency

    return translucency.main(args.rest)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="stripebench",
                                     description="A physically based rendering benchmark for laser-stripe trackers.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True

    def run_options(p):
        p.add_argument("--trackers", help="comma-separated tracker names (default: the configuration's)")
        p.add_argument("--out", type=Path, help="run folder (default: results/runs/<name>-<config hash>; "
                                                 "an existing partial run there is resumed)")
        p.add_argument("--seed", type=_seed_arg, help="seed for renders, noise, samples and bootstrap")
        p.add_argument("--quiet", action="store_true", help="no progress bars")

    p = sub.add_parser("reproduce", help="the paper's experiment on the embedded default settings")
    p.add_argument("--profile", default="paper", choices=["paper", "quick", "ci"],
                   help="embedded configuration (default: paper)")
    run_options(p)
    p.set_defaults(func=_cmd_reproduce)
    p = sub.add_parser("run", help="run an experiment configuration (TOML) or an embedded profile")
    p.add_argument("config", nargs="?", type=Path, help="configuration file (see bench/config.py)")
    p.add_argument("--profile", choices=["paper", "quick", "ci"], help="an embedded configuration instead")
    run_options(p)
    p.set_defaults(func=_cmd_run)
    p = sub.add_parser("report", help="rebuild the figures and report.html of a finished run")
    p.add_argument("run", help="run folder")
    p.add_argument("--quiet", action="store_true")
    p.set_defaults(func=_cmd_report)
    p = sub.add_parser("check", help="compare a run's metrics with a baseline; exit 1 on a regression")
    p.add_argument("run", help="run folder")
    p.add_argument("--baseline", type=Path, required=True, help="baseline JSON (e.g. results/baselines/ci.json)")
    p.add_argument("--update", action="store_true", help="write the run's metrics as the new baseline instead")
    p.add_argument("--all", action="store_true", help="show every check, not only the changed ones")
    p.set_defaults(func=_cmd_check)
    sub.add_parser("trackers", help="list the registered trackers").set_defaults(func=_cmd_trackers)
    sub.add_parser("scenes", help="list the scenes and materials").set_defaults(func=_cmd_scenes)
    p = sub.add_parser("estimators", help="the sub-pixel estimator study (see `stripebench estimators -h`)",
                       add_help=False)
    p.add_argument("rest", nargs=argparse.REMAINDER)
    p.set_defaults(func=_cmd_estimators)
    p = sub.add_parser("translucency", help="the subsurface-scattering bias study (see `stripebench translucency -h`)",
                       add_help=False)
    p.add_argument("rest", nargs=argparse.REMAINDER)
    p.set_defaults(func=_cmd_translucency)
    p = sub.add_parser("perf", help="speed benchmarks: trackers (default) or `perf --scenes`", add_help=False)
    p.add_argument("rest", nargs=argparse.REMAINDER)
    p.set_defaults(func=_cmd_perf)
    return parser


_PASSTHROUGH = {"perf": _cmd_perf, "estimators": _cmd_estimators, "translucency": _cmd_translucency}


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] in _PASSTHROUGH:  # these parse their own options (-h included)
        return int(_PASSTHROUGH[argv[0]](argparse.Namespace(rest=argv[1:])) or 0)
    parser = build_parser()
    args = parser.parse_args(argv)
    from .config import ConfigError

    try:
        return int(args.func(args) or 0)
    except (UsageError, ConfigError) as exc:
        print(f"stripebench: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("stripebench: interrupted; rerun the same command to resume", file=sys.stderr)
        return 130


if __name__ == "__main__":
    raise SystemExit(main())
