"""Boundary validation helpers: messages name the argument and echo the bad value."""

from __future__ import annotations

import math
import numbers

__all__ = ["real", "positive", "non_negative", "in_range", "positive_int"]


def real(name: str, value) -> float:
    """``value`` as a finite float, else ``ValueError`` naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(float(value)):
        raise ValueError(f"`{name}` must be a finite number, got {value!r}")
    return float(value)


def positive(name: str, value) -> float:
    """Finite and > 0."""
    v = real(name, value)
    if v <= 0:
        raise ValueError(f"`{name}` must be > 0, got {value!r}")
    return v


def non_negative(name: str, value) -> float:
    """Finite and >= 0."""
    v = real(name, value)
    if v < 0:
        raise ValueError(f"`{name}` must be >= 0, got {value!r}")
    return v


def in_range(name: str, value, lo: float, hi: float, *, lo_open: bool = False) -> float:
    """Finite and in ``[lo, hi]`` (``(lo, hi]`` with ``lo_open``)."""
    v = real(name, value)
    if v > hi or v < lo or (lo_open and v == lo):
        left = "(" if lo_open else "["
        raise ValueError(f"`{name}` must be in {left}{lo}, {hi}], got {value!r}")
    return v


def positive_int(name: str, value) -> int:
    """An integer >= 1 (bools refused)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ValueError(f"`{name}` must be an integer >= 1, got {value!r}")
    if value < 1:
        raise ValueError(f"`{name}` must be an integer >= 1, got {value!r}")
    return int(value)
