"""The ``stripebench`` command line.

Exit status: 0 success, 1 a failed check (``stripebench check``), 2 a usage,
configuration, input or file-system error (one line on stderr naming the
problem, see ``docs/errors.md``), 130 interrupted.
"""

from __future__ import annotations

import argparse
import errno
import json
import os
import re
import sys
from pathlib import Path

__all__ = ["main", "build_parser", "plain", "version"]

CONFIG_DOC = "docs/config.md"


class UsageError(Exception):
    """A bad command-line value: one line for the user, exit status 2."""


def plain(text: str) -> str:
    """Docstring text for a terminal: reStructuredText roles and literals removed.

    Examples
    --------
    >>> plain("see :func:`bench.run` and ``--out``")
    'see bench.run and --out'
    """
    text = re.sub(r":[a-z]+:`~?([^`]+)`", r"\1", text)
    return text.replace("``", "")


def version() -> str:
    """The installed ``stripebench`` version (or the source tree's, from ``pyproject.toml``)."""
    from importlib import metadata

    try:
        return metadata.version("stripebench")
    except metadata.PackageNotFoundError:
        import tomllib

        pyproject = Path(__file__).resolve().parents[1] / "pyproject.toml"
        try:
            return tomllib.loads(pyproject.read_text(encoding="utf-8"))["project"]["version"]
        except (OSError, KeyError, ValueError):
            return "unknown"


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (``stripebench: error: ...``, exit status 2)."""

    def error(self, message):
        self.exit(2, f"stripebench: error: {message} (see `{self.prog} -h`)\n")


# -- shared option types ------------------------------------------------------------
def _seed_arg(value: str) -> int:
    try:
        seed = int(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer >= 0, got {value!r}") from None
    if seed < 0:
        raise argparse.ArgumentTypeError(f"must be an integer >= 0, got {value!r}")
    return seed


def _trackers_arg(value: str | None):
    """``--trackers``: tracker settings as in configurations (:func:`bench.config.parse_trackers_arg`)."""
    if value is None:
        return None
    from .config import parse_trackers_arg

    return parse_trackers_arg(value)


def _say(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def _check_env() -> None:
    """The folders named by environment variables must be folders (or creatable), and
    ``$STRIPEBENCH_LLVM_TARGET`` well formed."""
    for var in ("STRIPEBENCH_CACHE_DIR", "STRIPEBENCH_RUNS"):
        value = os.environ.get(var)
        if not value:
            continue
        p = Path(value)
        if p.exists() and not p.is_dir():
            raise UsageError(f"${var} must name a folder, got {value!r} (a file)")
        if p.is_dir() and not os.access(p, os.W_OK | os.X_OK):
            raise UsageError(f"${var} names a folder this user cannot write: {value!r}")
    from scenes import variant

    try:
        variant.parse_llvm_target(os.environ.get(variant.ENV_LLVM_TARGET, ""))
    except ValueError as exc:
        raise UsageError(str(exc)) from None


def _run_config(config, args) -> int:
    from .config import with_overrides
    from .experiment import run

    changes = {}
    specs = _trackers_arg(args.trackers)
    if specs is not None:
        labels = [s.label for s in specs]
        changes["trackers"] = [s.to_value() for s in specs]
        changes["baselines"] = [b for b in config.baselines if b in labels]
        changes["dp"] = [d for d in config.dp if d in labels]
    if args.seed is not None:
        changes["seed"] = args.seed
    if args.no_render_ahead:
        changes["render_ahead"] = False
    if changes:
        config = with_overrides(config, **changes)
    _check_env()
    if args.out is not None and args.out.exists() and not args.out.is_dir():
        raise UsageError(f"--out must be a folder, got {str(args.out)!r} (a file)")
    out = run(config, args.out, progress=not args.quiet, quiet=args.quiet, force=args.force)
    if args.no_report:
        print(f"stripebench: results in {out}")
        return 0
    from .report import build_report
    from .runfolder import RunFolder

    with RunFolder(out) as folder:
        folder.lock()  # no other process may change the folder while its report is built
        path = build_report(out, quiet=args.quiet)
    print(f"stripebench: report at {path}")
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
    from .runfolder import RunFolder, load_summary

    summary = load_summary(args.run)  # one line if it is not a finished run
    with RunFolder(args.run) as folder:
        folder.lock()
        if summary.get("kind") == "real":
            from .real_run import build_real_report

            path = build_real_report(Path(args.run))
        else:
            path = build_report(Path(args.run), quiet=args.quiet)
    print(f"stripebench: report at {path}")
    return 0


def _gate_rows(baseline: dict, current: dict, what: str):
    from . import gate

    diff = gate.comparability(baseline.get("config"), current.get("config"))
    if diff:
        raise UsageError(f"{what} are not comparable: they differ in {'; '.join(diff)} "
                         f"(compared: {', '.join(gate.COMPARED_KEYS)})")
    return gate.compare(baseline, current)


def _print_rows(rows, args) -> int:
    from . import gate

    failed = [r for r in rows if r.failed]
    if args.json:
        print(json.dumps(gate.rows_to_json(rows, all_rows=args.all), indent=1))
    else:
        print(gate.format_table(rows, all_rows=args.all))
    return 1 if failed else 0


def _cmd_check(args) -> int:
    from . import gate

    run_dir = Path(args.run)
    current = gate.baseline_from_run(run_dir)
    if args.update:
        doc = gate.write_baseline(run_dir, args.baseline)
        print(f"stripebench: wrote baseline {args.baseline} ({len(doc['metrics'])} entries) from {run_dir}")
        return 0
    try:
        baseline = gate.load_baseline(args.baseline)
    except (FileNotFoundError, ValueError) as exc:
        raise UsageError(str(exc)) from None
    what = f"run {str(run_dir)!r} and baseline {str(args.baseline)!r}"
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


def _cmd_compare(args) -> int:
    from . import gate

    a, b = gate.baseline_from_run(args.run_a), gate.baseline_from_run(args.run_b)
    rows = _gate_rows(a, b, f"runs {str(args.run_a)!r} and {str(args.run_b)!r}")
    status = _print_rows(rows, args)
    if not args.json:
        print(f"stripebench compare: {args.run_b} against {args.run_a}: "
              f"{sum(r.failed for r in rows)} worse or missing, {sum(r.verdict == 'better' for r in rows)} better")
    return status


def tracker_table() -> list[dict]:
    """Every registered tracker: name, class, module, sub-pixel claim, summary,
    parameters with their defaults."""
    import inspect

    import trackers

    out = []
    for name in trackers.available():
        t = trackers.make(name)
        cls = type(t)
        sig = inspect.signature(cls.__init__) if cls.__init__ is not object.__init__ else None
        params = {}
        for k, v in t.get_params().items():
            default = sig.parameters[k].default if sig is not None and k in sig.parameters else v
            params[k] = None if default is inspect.Parameter.empty else default
        doc = plain((cls.__doc__ or "").strip()).splitlines()
        out.append({"name": name, "class": cls.__qualname__, "module": cls.__module__, "subpixel": bool(t.subpixel),
                    "summary": doc[0] if doc else "", "params": params})
    return out


def _cmd_trackers(args) -> int:
    table = tracker_table()
    if args.json:
        print(json.dumps(table, indent=1, default=repr))
        return 0
    for t in table:
        params = ", ".join(f"{k}={v!r}" for k, v in t["params"].items())
        print(f"{t['name']:<14} {'sub-pixel' if t['subpixel'] else 'whole-pixel':<12} {t['summary']}")
        if params:
            print(f"{'':<27}params: {params}")
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
    if args.rest and args.rest[0] == "--sweep":
        from .perf import sweep as perf_sweep

        return perf_sweep.main(args.rest[1:])
    from .perf import trackers as perf_trackers

    return perf_trackers.main(args.rest)


def _cmd_estimators(args) -> int:
    from . import estimators

    return estimators.main(args.rest)


def _cmd_track(args) -> int:
    """``stripebench track IMAGE... --out DIR``: trackers on photographs (exit 1 if a file failed)."""
    from . import real
    from .real_run import track_images

    specs = _trackers_arg(args.trackers)
    if specs is None:
        from .config import parse_trackers

        specs = parse_trackers([])
    if args.background is not None:
        try:
            real.read_image(args.background)
        except real.ImageError as exc:
            raise UsageError(f"--background: {exc}") from None
    failed = track_images(args.images, args.out, specs, background=args.background, pair=not args.no_pair,
                          channel=args.channel, laser=args.laser, rotate_deg=args.rotate)
    return 1 if failed else 0


def _cmd_real(args) -> int:
    """``stripebench real DATASET --out RUN``: trackers evaluated on a real set."""
    from . import real
    from .real_run import run_real

    specs = _trackers_arg(args.trackers)
    if specs is None:
        from .config import parse_trackers

        specs = parse_trackers([])
    if not (args.tol > 0):
        raise UsageError(f"--tol must be a number > 0 (px), got {args.tol!r}")
    if args.n_boot < 10:
        raise UsageError(f"--n-boot must be an integer >= 10, got {args.n_boot!r}")
    dataset = Path(args.dataset)
    if args.check:
        _, problems = real.validate_dataset(dataset)
        for line in problems:
            print(f"stripebench real: {line}", file=sys.stderr)
        if problems:
            return 2
        print(f"stripebench real: {dataset} is a valid real set")
        return 0
    if args.out is None:
        from .runio import runs_root

        args.out = runs_root() / f"real-{dataset.resolve().name}"
    try:
        out = run_real(dataset, args.out, specs, tol_px=args.tol, n_boot=args.n_boot, seed=args.seed or 0,
                       quiet=args.quiet)
    except real.DatasetError as exc:
        for line in exc.problems:
            print(f"stripebench real: {line}", file=sys.stderr)
        return 2
    if not args.quiet:
        import json

        summary = json.loads((out / "summary.json").read_text())
        print(f"{'tracker':<16}{'hit rate':>10}{'95 % CI':>18}{'MAE px':>9}{'coverage':>10}")
        for lab, s in summary["trackers"].items():
            h = s["hit_rate"]
            ci = f"[{h['lo']:.3f}, {h['hi']:.3f}]"
            print(f"{lab:<16}{h['mean']:>10.3f}{ci:>18}{s['mae_px']['mean']:>9.2f}{s['coverage']['mean']:>10.3f}")
    print(f"stripebench: report at {out / 'report.html'}")
    return 0


# -- stripebench sweep (robustness sweeps on Dask; bench/sweep.py) ---------------------------------------------------

def _cmd_sweep(args) -> int:
    from .config import with_overrides
    from .sweep import SweepError, load, run_sweep

    config, sweep = load(args.config)
    if args.seed is not None:
        config = with_overrides(config, seed=args.seed)
    if args.workers is not None and args.workers < 0:
        raise UsageError(f"--workers must be an integer >= 0, got {args.workers!r}")
    if args.chunk is not None and args.chunk < 1:
        raise UsageError(f"--chunk must be an integer >= 1, got {args.chunk!r}")
    if args.scheduler is not None and args.scheduler != "sync" and not args.scheduler.startswith(("tcp://", "tls://")):
        raise UsageError(f"--scheduler must be 'sync' or an address like tcp://HOST:PORT, got {args.scheduler!r}")
    if args.scheduler not in (None, "sync") and args.workers is not None:
        raise UsageError("--workers sizes the local cluster; it cannot be combined with --scheduler ADDRESS")
    try:
        out = run_sweep(config, sweep, args.out, scheduler=args.scheduler, workers=args.workers, chunk=args.chunk,
                        progress=not args.quiet, quiet=args.quiet, timeout_s=args.timeout)
    except SweepError as exc:
        raise UsageError(str(exc)) from None
    from .sweep_report import build_report

    build_report(out)
    print(f"stripebench: sweep table at {out / 'sweep.parquet'}, report at {out / 'report.html'}")
    return 0


def _add_sweep_parser(sub) -> None:
    p = sub.add_parser("sweep", help="robustness sweep: a configuration with a [sweep] table, on Dask")
    p.add_argument("config", type=Path, help="configuration file with a [sweep] table (see bench/sweep.py)")
    p.add_argument("--out", type=Path, help="sweep folder (default: results/runs/<name>-sweep-<hash>); "
                                             "finished units there are skipped")
    p.add_argument("--scheduler", help="'sync' (sequential) or the address of a running Dask scheduler, "
                                       "tcp://HOST:PORT (default: an in-process LocalCluster)")
    p.add_argument("--workers", type=int, help="workers of the local cluster (default: one per CPU; 0 = sequential)")
    p.add_argument("--chunk", type=int, help="grid points per task (default: every point of a render batch)")
    p.add_argument("--timeout", type=float, help="give up after this many seconds (finished units are kept)")
    p.add_argument("--seed", type=_seed_arg, help="seed for renders, noise, samples")
    p.add_argument("--quiet", action="store_true", help="no progress")
    p.set_defaults(func=_cmd_sweep)


def _cmd_translucency(args) -> int:
    from . import translucency

    return translucency.main(args.rest)


def build_parser() -> argparse.ArgumentParser:
    """The whole command tree (one parser, shared option types)."""
    from .config import PROFILES

    fmt = argparse.RawDescriptionHelpFormatter
    parser = _Parser(prog="stripebench", formatter_class=fmt,
                     description="A physically based rendering benchmark for laser-stripe trackers.",
                     epilog="Exit status: 0 ok, 1 a failed check, 2 a bad input (one line on stderr), 130 interrupted.")
    parser.add_argument("--version", action="version", version=f"stripebench {version()}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True

    def run_options(p):
        p.add_argument("--trackers", help="comma-separated tracker names or TOML inline tables "
                       "{label=..., name=..., params={...}} (default: the configuration's)")
        p.add_argument("--out", type=Path, help="run folder (default: results/runs/<name>-<config hash>; "
                                                 "a partial run of the same configuration there is resumed)")
        p.add_argument("--force", action="store_true",
                       help="clear --out first if it holds another configuration's run or other files")
        p.add_argument("--seed", type=_seed_arg, help="seed for renders, noise, samples and bootstrap")
        p.add_argument("--quiet", action="store_true", help="no progress bars or notes")
        p.add_argument("--no-report", action="store_true", help="write the results only, not figures and report.html")
        p.add_argument("--no-render-ahead", action="store_true",
                       help="render every frame in this process only, no helper process (the same results; "
                            "the configuration key render_ahead = false)")

    def json_options(p, what):
        p.add_argument("--json", action="store_true", help=f"print {what} as JSON")
        p.add_argument("--all", action="store_true", help="show every check, not only the changed ones")

    p = sub.add_parser("reproduce", help="the paper's experiment on the embedded default settings",
                       formatter_class=fmt)
    p.add_argument("--profile", default="paper", choices=PROFILES, help="embedded configuration (default: paper)")
    run_options(p)
    p.set_defaults(func=_cmd_reproduce)
    p = sub.add_parser("run", help="run an experiment configuration (TOML) or an embedded profile",
                       formatter_class=fmt,
                       epilog=f"The configuration format, with a complete example: {CONFIG_DOC}.")
    p.add_argument("config", nargs="?", type=Path, help=f"configuration file (format: {CONFIG_DOC})")
    p.add_argument("--profile", choices=PROFILES, help="an embedded configuration instead")
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
    json_options(p, "the checks")
    p.set_defaults(func=_cmd_check)
    p = sub.add_parser("track", help="run trackers on photographs (PNG/JPEG/TIFF): a CSV and an overlay per image")
    p.add_argument("images", nargs="+", metavar="IMAGE", help="image files (8/16-bit, grey or colour)")
    p.add_argument("--out", type=Path, required=True, help="output folder")
    p.add_argument("--trackers", help="tracker names or settings as for `run` (default: every registered tracker)")
    p.add_argument("--background", metavar="OFF_IMAGE", help="a laser-off frame used for every image")
    p.add_argument("--no-pair", action="store_true", help="do not use NAME_off.EXT beside NAME.EXT as background")
    p.add_argument("--channel", default="auto", choices=["auto", "r", "g", "b", "gray", "excess"],
                   help="what the trackers see of a colour image (auto: excess of the laser's colour)")
    p.add_argument("--laser", default="red", choices=["red", "green", "blue"], help="laser colour (default red)")
    p.add_argument("--rotate", type=int, default=0, choices=[0, 90, 180, 270],
                   help="turn the image counter-clockwise first (for horizontal stripes)")
    p.set_defaults(func=_cmd_track)
    p = sub.add_parser("real", help="evaluate trackers on a real set (manifest.csv, NAME.png, NAME_ref.csv)")
    p.add_argument("dataset", help="real-set folder (e.g. bench/data/real)")
    p.add_argument("--out", type=Path, help="run folder (default: results/runs/real-<dataset name>)")
    p.add_argument("--trackers", help="tracker names or settings as for `run` (default: every registered tracker)")
    p.add_argument("--tol", type=float, default=3.0, help="hit tolerance in px (default 3)")
    p.add_argument("--n-boot", type=int, default=2000, help="bootstrap resamples over images (default 2000)")
    p.add_argument("--seed", type=_seed_arg, help="bootstrap seed (default 0)")
    p.add_argument("--check", action="store_true", help="only validate the dataset (one line per problem, exit 2)")
    p.add_argument("--quiet", action="store_true")
    p.set_defaults(func=_cmd_real)
    p = sub.add_parser("compare", help="compare two runs' metrics (RUN_B against RUN_A); exit 1 if RUN_B is worse",
                       description="The same table as `check`, RUN_A taking the baseline's place. Refused when "
                                   "the runs differ in render size/spp, experiments or seed.")
    p.add_argument("run_a", metavar="RUN_A", help="the reference run folder")
    p.add_argument("run_b", metavar="RUN_B", help="the run folder compared with it")
    json_options(p, "the comparison")
    p.set_defaults(func=_cmd_compare)
    p = sub.add_parser("trackers", help="list the registered trackers with their parameters")
    p.add_argument("--json", action="store_true", help="print the list as JSON (parameters and defaults)")
    p.set_defaults(func=_cmd_trackers)
    sub.add_parser("scenes", help="list the scenes and materials").set_defaults(func=_cmd_scenes)
    p = sub.add_parser("estimators", help="the sub-pixel estimator study (see `stripebench estimators -h`)",
                       add_help=False)
    p.add_argument("rest", nargs=argparse.REMAINDER)
    p.set_defaults(func=_cmd_estimators)
    p = sub.add_parser("translucency", help="the subsurface-scattering bias study (see `stripebench translucency -h`)",
                       add_help=False)
    p.add_argument("rest", nargs=argparse.REMAINDER)
    p.set_defaults(func=_cmd_translucency)
    p = sub.add_parser("perf", help="speed benchmarks: trackers (default), `perf --scenes` or `perf --sweep`", add_help=False)
    p.add_argument("rest", nargs=argparse.REMAINDER)
    p.set_defaults(func=_cmd_perf)
    _add_sweep_parser(sub)
    p = sub.add_parser("tune", help="choose a default by its committed procedure: `tune dp` (the DP's h_weight)",
                       description="Run a committed tuning procedure. `dp`: the DP trackers' h_weight on "
                                   "bench/profiles/tune_dp.toml (sphere and plane, seed 1; never the paper's "
                                   "objects or seed); writes tune.csv and tune_dp.png and prints the chosen value.")
    p.add_argument("what", choices=["dp"], help="what to tune")
    p.add_argument("--profile", help="tuning profile (TOML; default: bench/profiles/tune_dp.toml)")
    p.add_argument("--out", type=Path, help="output folder (default: results/runs/tune_dp)")
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    p.set_defaults(func=_cmd_tune)
    return parser


def _cmd_tune(args) -> int:
    from . import tune

    argv = (["--profile", args.profile] if args.profile else []) + (["--out", str(args.out)] if args.out else [])
    return tune.main(argv + (["--quiet"] if args.quiet else []))


_PASSTHROUGH = {"perf": _cmd_perf, "estimators": _cmd_estimators, "translucency": _cmd_translucency}


def _os_message(exc: OSError) -> str:
    reason = "no space left on the device" if exc.errno == errno.ENOSPC else (exc.strerror or str(exc))
    if exc.filename is None:
        return f"{type(exc).__name__}: {reason}"
    return f"cannot use {str(exc.filename)!r}: {reason}"


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] in _PASSTHROUGH:  # these parse their own options (-h included)
        return int(_PASSTHROUGH[argv[0]](argparse.Namespace(rest=argv[1:])) or 0)
    parser = build_parser()
    args = parser.parse_args(argv)
    from .config import ConfigError
    from .runfolder import RunFolderError

    try:
        return int(args.func(args) or 0)
    except (UsageError, ConfigError, RunFolderError) as exc:
        print(f"stripebench: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # `stripebench trackers | head`: the reader left
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except OSError as exc:
        print(f"stripebench: error: {_os_message(exc)}", file=sys.stderr)
        return 2
    except MemoryError:
        print("stripebench: error: out of memory; use fewer or smaller frames (see docs/errors.md)", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("stripebench: interrupted; rerun the same command to resume", file=sys.stderr)
        return 130


if __name__ == "__main__":
    raise SystemExit(main())
