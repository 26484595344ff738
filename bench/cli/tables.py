"""``stripebench tables RUN``: the README's tables of a run (±5 mm, detection, the paper's claim) with
their provenance, computed from its saved ``summary.json`` (:mod:`bench.report.readme`)."""

from __future__ import annotations

import argparse
from pathlib import Path

from bench.cli.common import Command, UsageError

__all__ = ["COMMANDS"]


def _labels(text: str) -> list[str]:
    """``--trackers`` / ``--ratios``: comma-separated labels, in order, each once.

    Examples
    --------
    >>> _labels("dp4, threshold,dp4")
    ['dp4', 'threshold']
    """
    labels = [s.strip() for s in text.split(",")]
    if not text.strip() or not all(labels):
        raise argparse.ArgumentTypeError(f"must be comma-separated tracker labels, got {text!r}")
    return list(dict.fromkeys(labels))


def _add_tables(p) -> None:
    p.add_argument("run", type=Path, help="a finished run folder, or its committed copy (summary.json and "
                                          "metrics.csv; the paper run's is results/paper)")
    p.add_argument("--markdown", action="store_true", help="markdown tables, ready to paste (default: aligned text)")
    p.add_argument("--trackers", type=_labels, metavar="A,B,...",
                   help="the trackers shown, in order (default: the baselines that read the paper's method "
                        "without DP, then the DP labels)")
    p.add_argument("--ratios", type=_labels, metavar="DP,...",
                   help="the DP labels whose RMSE ratio against the first baseline is shown (default: the first two)")
    p.add_argument("--save", type=Path, metavar="DIR",
                   help="also write the run's committed copy into DIR (created; e.g. results/paper): its metrics.csv "
                        "and its summary.json cut to what the tables read")


def _tables(args) -> int:
    from bench.report.readme import default_trackers, readme_tables
    from bench.store.runfolder import load_summary, metrics_sha256

    summary = load_summary(args.run)
    if summary.get("kind") == "real":
        raise UsageError(f"{str(args.run)!r} is a real-photograph run: `tables` reads a run of renders "
                         "(`stripebench reproduce`, `run` or `score`)")
    digest = metrics_sha256(args.run, summary)
    known = {r["tracker"] for r in summary.get("robust", [])} | {r["tracker"] for r in summary.get("detection", [])}
    known |= set(default_trackers(summary))
    for option, labels in (("--trackers", args.trackers), ("--ratios", args.ratios)):
        unknown = [t for t in labels or () if t not in known]
        if unknown:
            raise UsageError(f"{option}: {unknown[0]!r} is no tracker of this run (its trackers: "
                             f"{', '.join(sorted(known))})")
    dps = set(summary.get("config", {}).get("dp", [])) | {(summary.get("submission") or {}).get("label")}
    bad = [d for d in args.ratios or () if d not in dps]
    if bad:
        raise UsageError(f"--ratios: {bad[0]!r} is not a DP label of this run (its DP labels: "
                         f"{', '.join(sorted(d for d in dps if d))})")
    if args.save is not None:
        _save(args.run, args.save, summary, digest)
    print(readme_tables(summary, digest, trackers=args.trackers, ratios=args.ratios, markdown=args.markdown))
    return 0


def _save(run, dest: Path, summary: dict, digest: str) -> None:
    """The committed copy of ``run`` in ``dest``: ``metrics.csv`` as it is and the cut summary
    (:func:`bench.report.readme.tables_summary`), each written atomically."""
    from bench.report.readme import tables_summary
    from bench.store.files import atomic_write_bytes
    from bench.store.runfolder import LAYOUT, write_summary

    if dest.resolve() == Path(run).resolve():
        raise UsageError(f"--save must name another folder than RUN, got {str(dest)!r}")
    dest.mkdir(parents=True, exist_ok=True)
    atomic_write_bytes(dest / LAYOUT["metrics_csv"], (Path(run) / LAYOUT["metrics_csv"]).read_bytes())
    write_summary(dest, tables_summary(summary, digest))


COMMANDS = (
    Command("tables", "the README's tables of a run (±5 mm, detection, the paper's claim) with their provenance",
            _add_tables, _tables,
            description="Print the README's tables of a finished run (or its committed copy, results/paper: "
                        "summary.json and metrics.csv), every number read from its summary.json, with the run's "
                        "configuration, seed, git revision, renderer, machine and metrics.csv sha256."),
)
