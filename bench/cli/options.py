"""The command-line options every ``stripebench`` command shares: the parser class, argparse types, ``add_*``.

Each shared option is defined once here and added to a parser by its ``add_*``
function; the defaults are read from the schema (:class:`bench.config.Config`,
:data:`bench.config.options.REAL_DEFAULTS`), never repeated. The value checks
themselves are plain functions of :mod:`bench.config.options` raising
:class:`bench.config.ConfigError` (so the library and the command line share
them); :func:`arg_type` turns one into an argparse type, whose message argparse
prints as one line (``stripebench: error: argument --x: ...``). Only the
command layer (:mod:`bench.cli`) knows argparse.

Examples
--------
>>> from bench.config.options import positive_int
>>> p = OneLineParser(prog="t")
>>> _ = p.add_argument("--frames", type=arg_type(positive_int, "--frames"), default=1)
>>> p.parse_args(["--frames", "8"]).frames
8
>>> first_paragraph("Run the study (see :func:`bench.run.run`).\\n\\nMore.")
'Run the study (see bench.run.run).'
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

from bench.config import MAX_N_BOOT, MIN_N_BOOT, ConfigError, parse_trackers_arg
from bench.config.options import MAX_TOL_PX, REAL_DEFAULTS, finite_float, int_in_range, seed_value

__all__ = ["OneLineParser", "HelpFormatter", "arg_type", "add_out", "add_force", "add_quiet", "add_seed",
           "add_trackers", "add_n_boot", "add_tol", "add_frames", "add_estimate", "plain", "first_paragraph"]


class OneLineParser(argparse.ArgumentParser):
    """argparse with one-line errors (``stripebench: error: ...``, exit status 2)."""

    def error(self, message):
        from bench.errors import one_line

        self.exit(2, f"stripebench: error: {one_line(message)} (see `{self.prog} -h`)\n")


class HelpFormatter(argparse.RawDescriptionHelpFormatter):
    """Descriptions as written (plain text), option defaults shown where they are given."""


def arg_type(check, name: str):
    """An argparse ``type`` from a check ``check(name, text) -> value`` raising :class:`ConfigError`."""

    def convert(text):
        try:
            return check(name, text)
        except ConfigError as exc:
            msg = str(exc)
            raise argparse.ArgumentTypeError(msg[len(name) + 1:] if msg.startswith(name + " ") else msg) from None

    convert.__name__ = name.lstrip("-").replace("-", "_")
    return convert


# -- the shared options ---------------------------------------------------------------------------------------------

def add_out(parser, help: str, *, required: bool = False, default=None) -> None:
    """``--out DIR``: the output folder."""
    extra = f" (default: {default})" if default is not None and "default" not in help else ""
    parser.add_argument("--out", type=Path, required=required, default=Path(default) if default else None,
                        metavar="DIR", help=help + extra)


def add_force(parser, extra: str = "") -> None:
    """``--force``: clear ``--out`` first when it holds another configuration's or kind's run (or other files)."""
    parser.add_argument("--force", action="store_true",
                        help="clear --out first if it holds another configuration's or kind's run (or other files)"
                             + extra)


def add_quiet(parser, help: str = "no progress bars or notes") -> None:
    """``--quiet``."""
    parser.add_argument("--quiet", action="store_true", help=help)


def add_seed(parser, help: str = "seed for renders, noise, samples and bootstrap", default=None) -> None:
    """``--seed N`` (an integer >= 0)."""
    extra = f" (default {default})" if default is not None else ""
    parser.add_argument("--seed", type=arg_type(seed_value, "--seed"), default=default, metavar="N", help=help + extra)


def add_trackers(parser, help: str) -> None:
    """``--trackers LIST``: comma-separated names or TOML inline tables, as in configurations
    (:func:`bench.config.parse_trackers_arg`); the value is a tuple of :class:`bench.config.TrackerSpec`."""
    parser.add_argument("--trackers", type=arg_type(lambda n, t: parse_trackers_arg(t, n), "--trackers"),
                        metavar="LIST", help=help)


def add_n_boot(parser) -> None:
    """``--n-boot N``: bootstrap resamples."""
    parser.add_argument("--n-boot", type=arg_type(lambda n, v: int_in_range(n, v, MIN_N_BOOT, MAX_N_BOOT), "--n-boot"),
                        default=REAL_DEFAULTS["n_boot"], metavar="N",
                        help=f"bootstrap resamples over images ({MIN_N_BOOT} .. {MAX_N_BOOT}; "
                             f"default {REAL_DEFAULTS['n_boot']})")


def add_tol(parser) -> None:
    """``--tol PX``: the hit tolerance of real runs (finite, > 0, at most :data:`bench.config.options.MAX_TOL_PX`)."""
    parser.add_argument("--tol", type=arg_type(lambda n, v: finite_float(n, v, low=0, low_open=True, high=MAX_TOL_PX),
                                               "--tol"),
                        default=REAL_DEFAULTS["tol_px"], metavar="PX",
                        help=f"hit tolerance in px (> 0 and <= {MAX_TOL_PX:g}; default {REAL_DEFAULTS['tol_px']:g})")


def plain(text: str) -> str:
    """Docstring text for a terminal: reStructuredText roles and literals removed.

    Examples
    --------
    >>> plain("see :func:`bench.run` and ``--out``")
    'see bench.run and --out'
    """
    text = re.sub(r":[a-z]+:`~?([^`]+)`", r"\1", text)
    return text.replace("``", "")


def first_paragraph(doc: str) -> str:
    """The first paragraph of a docstring as plain text (a command's description)."""
    return plain((doc or "").strip().split("\n\n")[0])
