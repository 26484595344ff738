"""``stripebench sweep``: a configuration with a ``[sweep]`` table, on Dask (:mod:`bench.run.sweep`)."""

from __future__ import annotations

from pathlib import Path

from bench.cli.common import Command, UsageError, check_env, check_out_folder
from bench.cli.options import add_force, add_out, add_quiet, add_seed, arg_type
from bench.config.options import MAX_TIMEOUT_S, finite_float, positive_int, scheduler_address, workers_value

__all__ = ["COMMANDS"]


def _add_sweep(p) -> None:
    p.add_argument("config", type=Path, help="configuration file with a [sweep] table (see docs/sweeps.md)")
    add_out(p, "sweep folder (default: results/runs/<name>-sweep-<hash>); finished units there are skipped")
    add_force(p)
    p.add_argument("--scheduler", type=arg_type(lambda n, v: scheduler_address(v, n), "--scheduler"),
                   metavar="ADDRESS",
                   help="'sync' (sequential) or the address of a running Dask scheduler, tcp://HOST:PORT or "
                        "tls://HOST:PORT (default: an in-process LocalCluster). Dask's protocol uses pickle: "
                        "connect only to a scheduler you trust")
    p.add_argument("--workers", type=arg_type(workers_value, "--workers"), metavar="N",
                   help="workers of the local cluster, 0 .. this machine's CPUs (default: one per CPU; 0 = sequential)")
    p.add_argument("--chunk", type=arg_type(lambda n, v: positive_int(n, v, 10**6), "--chunk"), metavar="N",
                   help="grid points per task (default: every point of a render batch)")
    p.add_argument("--timeout", type=arg_type(lambda n, v: finite_float(n, v, low=0, low_open=True, high=MAX_TIMEOUT_S),
                                              "--timeout"),
                   metavar="S", help="give up after this many seconds (finished units are kept)")
    add_seed(p, "seed for renders, noise, samples")
    add_quiet(p, "no progress")


def _sweep(args) -> int:
    from bench.config import with_overrides
    from bench.config.sweep import load
    from bench.run.sweep import run_sweep

    if args.scheduler not in (None, "sync") and args.workers is not None:
        raise UsageError("--workers sizes the local cluster; it cannot be combined with --scheduler ADDRESS")
    config, sweep = load(args.config)
    if args.seed is not None:
        config = with_overrides(config, seed=args.seed)
    check_env()
    check_out_folder(args.out, inputs=[("CONFIG", args.config)])
    out = run_sweep(config, sweep, args.out, scheduler=args.scheduler, workers=args.workers, chunk=args.chunk,
                    progress=not args.quiet, quiet=args.quiet, timeout_s=args.timeout, force=args.force)
    from bench.report.sweep import build_report

    build_report(out)
    print(f"stripebench: sweep table at {out / 'sweep.parquet'}, report at {out / 'report.html'}")
    return 0


COMMANDS = (
    Command("sweep", "robustness sweep: a configuration with a [sweep] table, on Dask", _add_sweep, _sweep,
            renders=True),
)
