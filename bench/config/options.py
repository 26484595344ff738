"""Command-line options shared by every ``stripebench`` command and study: types, limits, defaults.

Each option is defined once here and added to a parser by its ``add_*``
function; the defaults are read from the schema (:class:`bench.config.Config`,
:data:`REAL_DEFAULTS`), never repeated. The value checks are plain functions
raising :class:`bench.config.ConfigError` (so the library and the command line
share them); :func:`arg_type` turns one into an argparse type, whose message
argparse prints as one line (``stripebench: error: argument --x: ...``).

Examples
--------
>>> positive_int("--frames", "8")
8
>>> finite_float("--timeout", "nan", low=0, low_open=True)
Traceback (most recent call last):
...
bench.errors.ConfigError: --timeout must be a finite number > 0, got 'nan'
>>> scheduler_address("tcp://127.0.0.1:8786")
'tcp://127.0.0.1:8786'
"""

from __future__ import annotations

import argparse
import math
import os
import re
import sys
from pathlib import Path

from bench.config import MAX_N_BOOT, MIN_N_BOOT, ConfigError, parse_trackers_arg
from bench.evaluate.outcomes import HIT_PX

__all__ = ["OneLineParser", "HelpFormatter", "arg_type", "positive_int", "int_in_range", "finite_float",
           "finite_floats", "size_value", "seed_value", "workers_value", "cpu_count", "scheduler_address", "plain_tracker_names",
           "add_out", "add_quiet", "add_seed", "add_trackers", "add_n_boot", "add_tol", "REAL_DEFAULTS",
           "SCHEDULER_SCHEMES", "MAX_TIMEOUT_S", "study_parser", "study_main", "plain", "first_paragraph"]

#: Defaults of a real-photograph run (``stripebench real``; a configuration's ``real_set`` uses the same).
REAL_DEFAULTS = {"tol_px": HIT_PX, "n_boot": 2000, "seed": 0}
#: Address schemes of a Dask scheduler ``--scheduler`` accepts (Dask's protocol uses pickle: trusted schedulers only).
SCHEDULER_SCHEMES = ("tcp", "tls")
#: Largest ``--timeout`` (a year, s): beyond it asyncio's timers overflow.
MAX_TIMEOUT_S = 365 * 86400.0


class OneLineParser(argparse.ArgumentParser):
    """argparse with one-line errors (``stripebench: error: ...``, exit status 2)."""

    def error(self, message):
        self.exit(2, f"stripebench: error: {message} (see `{self.prog} -h`)\n")


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


def int_in_range(name: str, value, low: int, high: int | None = None) -> int:
    """``value`` (an int or its decimal text) if ``low <= value <= high``, else :class:`ConfigError`."""
    try:
        n = int(value) if isinstance(value, str) and len(value) <= 20 else value
    except ValueError:
        n = None
    if isinstance(n, bool) or not isinstance(n, int) or n < low or (high is not None and n > high):
        span = f">= {low}" if high is None else f"{low} .. {high}"
        if high is not None and high >= 2**62:
            span = f">= {low} (at most 2**63 - 1)"
        raise ConfigError(f"{name} must be an integer {span}, got {value!r}")
    return n


def positive_int(name: str, value, high: int | None = None) -> int:
    """An integer >= 1 (at most ``high``)."""
    return int_in_range(name, value, 1, high)


def spp_value(name: str, value):
    """A sample count: ``"auto"`` (the per-material counts of :mod:`scenes.sampling`) or an integer
    1 .. 65536."""
    if value == "auto":
        return value
    try:
        return positive_int(name, value, 65536)
    except ConfigError:
        raise ConfigError(f"{name} must be \"auto\" or an integer 1 .. 65536, got {value!r}") from None


def finite_float(name: str, value, *, low: float | None = None, high: float | None = None,
                 low_open: bool = False) -> float:
    """A finite number (text or number) within the bounds, else :class:`ConfigError`."""
    try:
        x = float(value)
    except (TypeError, ValueError, OverflowError):
        x = math.nan
    ok = math.isfinite(x) and (low is None or (x > low if low_open else x >= low)) and (high is None or x <= high)
    if not ok:
        span = "" if low is None else (f" > {low:g}" if low_open else f" >= {low:g}")
        span += "" if high is None else (f" and <= {high:g}" if span else f" <= {high:g}")
        raise ConfigError(f"{name} must be a finite number{span}, got {value!r}")
    return x


def finite_floats(name: str, text: str, *, low: float | None = None, low_open: bool = False) -> list[float]:
    """Comma-separated finite numbers within the bounds (at least one, none repeated).

    Examples
    --------
    >>> finite_floats("--sigmas", "0.5, 1", low=0, low_open=True)
    [0.5, 1.0]
    """
    parts = [v.strip() for v in str(text).split(",") if v.strip()]
    if not parts:
        raise ConfigError(f"{name} must list at least one number, got {text!r}")
    values = []
    for v in parts:
        try:
            values.append(finite_float(name, v, low=low, low_open=low_open))
        except ConfigError as exc:
            raise ConfigError(f"{exc} (in {text!r})" if len(parts) > 1 else str(exc)) from None
    if len(set(values)) != len(values):
        raise ConfigError(f"{name} repeats a value: {text!r}")
    return values


def size_value(name: str, text) -> tuple[int, int]:
    """``WIDTHxHEIGHT`` within the scenes' limits (:data:`scenes.params.MAX_SIZE`).

    Examples
    --------
    >>> size_value("--size", "128x120")
    (128, 120)
    """
    from scenes.params import MAX_SIZE

    parts = str(text).lower().split("x")
    if len(parts) != 2:
        raise ConfigError(f"{name} must be WIDTHxHEIGHT (e.g. 128x120), got {text!r}")
    w = positive_int(name, parts[0].strip(), MAX_SIZE["width"])
    h = positive_int(name, parts[1].strip(), MAX_SIZE["height"])
    return w, h


def seed_value(name: str, value) -> int:
    """A seed: an integer 0 .. 2**63 - 1."""
    return int_in_range(name, value, 0, 2**63 - 1)


def cpu_count() -> int:
    """The CPUs this process may use (its affinity, else :func:`os.cpu_count`)."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def workers_value(name: str, value) -> int:
    """Local worker processes: 0 (sequential) .. this machine's CPUs."""
    return int_in_range(name, value, 0, cpu_count())


_HOST = re.compile(r"^(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9._-]+)$")


def scheduler_address(value: str, name: str = "--scheduler") -> str:
    """``"sync"`` or a Dask scheduler address ``tcp://HOST:PORT`` / ``tls://HOST:PORT``
    (PORT 1 .. 65535), checked before anything connects.

    Examples
    --------
    >>> scheduler_address("tcp://127.0.0.1:notaport")
    Traceback (most recent call last):
    ...
    bench.errors.ConfigError: --scheduler must be 'sync' or an address like tcp://HOST:PORT (PORT 1..65535), got 'tcp://127.0.0.1:notaport'
    """
    if value == "sync":
        return value
    bad = ConfigError(f"{name} must be 'sync' or an address like tcp://HOST:PORT (PORT 1..65535), got {value!r}")
    if not isinstance(value, str) or "://" not in value:
        raise bad
    scheme, rest = value.split("://", 1)
    host, sep, port = rest.rpartition(":")
    if scheme not in SCHEDULER_SCHEMES or not sep or not _HOST.match(host) or not port.isascii() \
            or not port.isdigit() or not 1 <= int(port) <= 65535:
        raise bad
    return value


def plain_tracker_names(specs, name: str = "--trackers") -> list[str]:
    """The names of tracker settings that must be plain names (the studies run each tracker with its defaults)."""
    if any(s.params or s.label != s.name for s in specs):
        raise ConfigError(f"{name}: this command runs each tracker with its defaults; give plain names")
    return [s.name for s in specs]


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
    """``--tol PX``: the hit tolerance of real runs (finite, > 0)."""
    parser.add_argument("--tol", type=arg_type(lambda n, v: finite_float(n, v, low=0, low_open=True), "--tol"),
                        default=REAL_DEFAULTS["tol_px"], metavar="PX",
                        help=f"hit tolerance in px (finite, > 0; default {REAL_DEFAULTS['tol_px']:g})")


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


def study_main(prog: str, doc: str, add_arguments, command, argv=None) -> int:
    """A study's ``main(argv)``: the parser built by the study's ``add_arguments``, then
    ``command(args)``; an expected failure (:class:`bench.errors.StripebenchError`) is one
    line on stderr and exit status 2, as on the ``stripebench`` command line."""
    from bench.errors import StripebenchError

    parser = study_parser(prog, first_paragraph(doc))
    add_arguments(parser)
    args = parser.parse_args(argv)
    try:
        return int(command(args) or 0)
    except StripebenchError as exc:
        print(f"stripebench: error: {exc}", file=sys.stderr)
        return 2


def study_parser(prog: str, description: str) -> OneLineParser:
    """The parser of a study's own ``main(argv)`` (``python -m bench.studies...``): the same
    one-line errors and plain-text help as the ``stripebench`` command tree."""
    return OneLineParser(prog=prog, description=description, formatter_class=HelpFormatter)
