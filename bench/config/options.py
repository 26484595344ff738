"""The values of the command-line options: their checks, limits and defaults (no argparse here).

The value checks are plain functions raising :class:`bench.config.ConfigError`, so the
library and the command line share them; the command line's parsers, argparse types
and shared options (``--out``, ``--seed``, ...) are :mod:`bench.cli.options`.

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

import math
import os
import re

from bench.config import ConfigError
from bench.evaluate.outcomes import HIT_PX

__all__ = ["positive_int", "int_in_range", "finite_float", "finite_floats", "size_value", "width16_value",
           "names_check", "seed_value", "spp_value",
           "workers_value", "cpu_count", "scheduler_address", "plain_tracker_names", "REAL_DEFAULTS",
           "SCHEDULER_SCHEMES", "MAX_TIMEOUT_S", "MAX_TOL_PX"]

#: Defaults of a real-photograph run (``stripebench real``; a configuration's ``real_set`` uses the same).
REAL_DEFAULTS = {"tol_px": HIT_PX, "n_boot": 2000, "seed": 0}
#: The largest hit tolerance of a real run, px: a report farther than this from the reference says nothing of
#: where the stripe is (a tolerance of 1e30 px would count every report a hit).
MAX_TOL_PX = 100.0
#: Address schemes of a Dask scheduler ``--scheduler`` accepts (Dask's protocol uses pickle: trusted schedulers only).
SCHEDULER_SCHEMES = ("tcp", "tls")
#: Largest ``--timeout`` (a year, s): beyond it asyncio's timers overflow.
MAX_TIMEOUT_S = 365 * 86400.0


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
    from scenes import MAX_SIZE

    parts = str(text).lower().split("x")
    if len(parts) != 2:
        raise ConfigError(f"{name} must be WIDTHxHEIGHT (e.g. 128x120), got {text!r}")
    w = positive_int(name, parts[0].strip(), MAX_SIZE["width"])
    h = positive_int(name, parts[1].strip(), MAX_SIZE["height"])
    return w, h


def width16_value(name: str, text) -> int:
    """An image width in px, a multiple of 16 (the height is 15/16 of it: square pixels at 16:15), within
    the scenes' limit.

    Examples
    --------
    >>> width16_value("--size", "128")
    128
    """
    from scenes import MAX_SIZE

    w = positive_int(name, text, MAX_SIZE["width"])
    if w < 16 or w % 16:
        raise ConfigError(f"{name} must be a multiple of 16 (square pixels at 16:15), got {text!r}")
    return w


def names_check(what: str, valid):
    """A check ``check(name, text) -> list[str]`` of a comma-separated list of ``what`` names, each one of
    ``valid()`` (called when a value is checked, so that the list is read only when needed).

    Examples
    --------
    >>> names_check("object", lambda: ["cone", "hand"])("--objects", "hand, cone")
    ['hand', 'cone']
    """
    def check(name, text):
        values = [n.strip() for n in str(text).split(",") if n.strip()]
        bad = [v for v in values if v not in valid()]
        if not values or bad:
            raise ConfigError(f"{name} must name some of {', '.join(valid())}, got unknown {what} "
                              f"{(bad or [text])[0]!r}")
        return values

    return check


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
    """The names of tracker settings (:class:`bench.config.TrackerSpec`, or names) that must be plain names
    (the studies run each tracker with its defaults)."""
    if any(not isinstance(s, str) and (s.params or s.label != s.name) for s in specs):
        raise ConfigError(f"{name}: this command runs each tracker with its defaults; give plain names")
    return [s if isinstance(s, str) else s.name for s in specs]
