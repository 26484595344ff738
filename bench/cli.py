"""The ``stripebench`` command line."""

from __future__ import annotations

import argparse
import sys

__all__ = ["main"]


def _cmd_trackers(args) -> int:
    import trackers

    for name in trackers.available():
        t = trackers.make(name)
        doc = (type(t).__doc__ or "").strip().splitlines()[0] if type(t).__doc__ else ""
        print(f"{name:<14} {'sub-pixel' if t.subpixel else 'whole-pixel':<12} {doc}")
    return 0


def _cmd_perf(args) -> int:
    from bench.perf import trackers as perf_trackers

    return perf_trackers.main(args.rest)


def _cmd_reproduce(args) -> int:
    # until the evaluation harness lands, the main job is the tracker benchmark
    from bench.perf import trackers as perf_trackers

    return perf_trackers.main([])


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="stripebench",
        description="A physically based rendering benchmark for laser-stripe trackers.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    p = sub.add_parser("reproduce", help="run the paper's experiment on the default settings")
    p.set_defaults(func=_cmd_reproduce)
    p = sub.add_parser("trackers", help="list the registered trackers")
    p.set_defaults(func=_cmd_trackers)
    p = sub.add_parser("perf", help="time every tracker on 512x480 frames (see `stripebench perf -h`)",
                       add_help=False)
    p.add_argument("rest", nargs=argparse.REMAINDER)
    p.set_defaults(func=_cmd_perf)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except KeyboardInterrupt:
        print("stripebench: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    raise SystemExit(main())
