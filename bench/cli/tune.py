"""The ``tune`` command: ``stripebench tune {dp,dp_gap,threshold}``, the committed tuning procedures.

``WHAT`` names the procedure; its work is the plain function ``study(profile=..., out=..., quiet=...)``
of :mod:`bench.studies.tune` (``dp``), :mod:`bench.studies.tune_gap` (``dp_gap``) or
:mod:`bench.studies.tune_threshold` (``threshold``), each with its own default profile and output folder.
"""

from __future__ import annotations

import importlib
import pathlib

from bench.cli.common import Command, call, description_of
from bench.cli.options import add_out, add_quiet

__all__ = ["COMMAND", "PROCEDURES"]

#: What ``tune`` can tune, and the module of each procedure.
PROCEDURES = {"dp": "bench.studies.tune", "dp_gap": "bench.studies.tune_gap", "threshold": "bench.studies.tune_threshold"}


def add_arguments(parser) -> None:
    """The options of ``stripebench tune``."""
    parser.add_argument("what", choices=tuple(PROCEDURES), help="what to tune: dp (the DP trackers' h_weight), dp_gap "
                                                                "(dp_gap's off_rel and switch_rows), threshold (the "
                                                                "threshold trackers' per-row detection, com_bg's level, "
                                                                "the auto colour rule)")
    parser.add_argument("--profile", type=pathlib.Path, default=None, metavar="TOML",
                        help="tuning profile (default: bench/config/profiles/tune_<what>.toml)")
    add_out(parser, "output folder (default: results/runs/tune_<what>)", default=None)
    add_quiet(parser, "no progress bars")


def run(args) -> int:
    """Run the procedure ``args.what`` with its defaults where no ``--profile`` or ``--out`` is given; a bad
    profile raises :class:`bench.config.ConfigError` (one line) before any work."""
    module = importlib.import_module(PROCEDURES[args.what])
    return call(module.study, args, profile=module.DEFAULT_PROFILE if args.profile is None else args.profile,
                out=module.DEFAULT_OUT if args.out is None else args.out)


#: ``stripebench tune WHAT``.
COMMAND = Command("tune", "choose a default by its committed procedure: `tune dp` (the DP's h_weight)", add_arguments,
                  run, description=description_of("bench.studies.tune"), renders=True)
