"""How the benchmark writes numbers in sentences, tables and pages: one home for every formatter.

Pure: a value in, a string out; a missing value (None or NaN) is ``–``. The report's HTML
toolkit (:mod:`bench.report.html`) and the sentences of :mod:`bench.evaluate.readings` use these.
"""

from __future__ import annotations

import math
import numbers

__all__ = ["MISSING", "pct", "interval", "num", "signed", "fixed", "estimate"]

#: What a missing value is written as.
MISSING = "–"


def _ok(v) -> bool:
    return isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v)


def pct(value) -> str:
    """A fraction in per cent to the unit.

    Examples
    --------
    >>> pct(0.934), pct(float("nan")), pct(None)
    ('93 %', '–', '–')
    """
    return f"{100 * value:.0f} %" if _ok(value) else MISSING


def interval(low, high) -> str:
    """``[96, 99]``: an interval of fractions in per cent, ``[–]`` when either end is missing.

    Examples
    --------
    >>> interval(0.912, 0.954), interval(None, 0.5)
    ('[91, 95]', '[–]')
    """
    return f"[{100 * low:.0f}, {100 * high:.0f}]" if _ok(low) and _ok(high) else f"[{MISSING}]"


def num(value, unit: str = "") -> str:
    """Two significant digits, with an optional unit.

    Examples
    --------
    >>> num(0.3149, " mm"), num(164.2), num(None)
    ('0.31 mm', '1.6e+02', '–')
    """
    return f"{value:.2g}{unit}" if _ok(value) else MISSING


def signed(value) -> str:
    """A signed error to two decimals.

    Examples
    --------
    >>> signed(0.812), signed(-0.03), signed(float("nan"))
    ('+0.81', '-0.03', '–')
    """
    return f"{value:+.2f}" if _ok(value) else MISSING


def fixed(value, fmt: str = ".3f") -> str:
    """``format(value, fmt)``.

    Examples
    --------
    >>> fixed(0.73094), fixed(12.5, ".1f"), fixed(None)
    ('0.731', '12.5', '–')
    """
    return format(value, fmt) if _ok(value) else MISSING


def estimate(value, low, high, fmt: str = ".3f") -> str:
    """A value with its interval, each ``format(.., fmt)``: ``0.949 [0.882, 0.990]``; ``[–]`` when an end is missing.

    Examples
    --------
    >>> estimate(0.9491, 0.882, 0.99), estimate(0.5, float("nan"), 0.7), estimate(None, None, None)
    ('0.949 [0.882, 0.990]', '0.500 [–]', '– [–]')
    """
    ends = f"[{format(low, fmt)}, {format(high, fmt)}]" if _ok(low) and _ok(high) else f"[{MISSING}]"
    return f"{fixed(value, fmt)} {ends}"
