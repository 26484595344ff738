"""Parameter checks used by trackers' ``_validate_params``."""

from __future__ import annotations

import numbers

__all__ = ["check_real", "check_int", "check_optional_real", "check_choice"]


def check_real(name: str, value, *, low=None, high=None, low_open=False, high_open=False) -> None:
    """Raise ``ValueError`` unless ``value`` is a real number in range
    (``low_open``/``high_open`` exclude the bound itself)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or value != value:
        raise ValueError(f"`{name}` must be a real number, got {value!r}")
    if low is not None and (value <= low if low_open else value < low):
        raise ValueError(f"`{name}` must be {'>' if low_open else '>='} {low}, got {value!r}")
    if high is not None and (value >= high if high_open else value > high):
        raise ValueError(f"`{name}` must be {'<' if high_open else '<='} {high}, got {value!r}")


def check_optional_real(name: str, value, **kw) -> None:
    if value is not None:
        check_real(name, value, **kw)


def check_int(name: str, value, *, low=None) -> None:
    """Raise ``ValueError`` unless ``value`` is an integer >= ``low``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ValueError(f"`{name}` must be an integer, got {value!r}")
    if low is not None and value < low:
        raise ValueError(f"`{name}` must be >= {low}, got {value!r}")


def check_choice(name: str, value, choices) -> None:
    """Raise ``ValueError`` unless ``value`` is one of ``choices`` (strings)."""
    if not isinstance(value, str) or value not in choices:
        listed = ", ".join(repr(c) for c in sorted(choices))
        raise ValueError(f"`{name}` must be one of {listed}, got {value!r}")
