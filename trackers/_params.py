"""Parameter checks and the constraint types of :attr:`trackers.Tracker.parameter_constraints`.

A tracker declares its parameters' constraints as data (scikit-learn's
``_parameter_constraints`` is the model)::

    parameter_constraints = {"eps": Real(low=0, low_open=True), "half_window": Int(low=0),
                             "threshold": Real(optional=True), "estimator": Choice({"gauss3", "parabolic"})}

:meth:`trackers.Tracker.validate_params` checks every parameter against its
constraint (one line naming the parameter and echoing its value), and the
conformance suite (:func:`trackers.testing.check_parameter_constraints`)
checks, for every tracker, that each parameter has a constraint and that the
values each constraint calls invalid are refused.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

__all__ = ["check_real", "check_int", "check_optional_real", "check_choice", "Real", "Int", "Choice", "Bool",
           "StrList"]


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
    """Raise ``ValueError`` unless ``value`` is one of ``choices`` (strings, or integers: then
    an integer of equal value, not a bool)."""
    kinds = (str,) if all(isinstance(c, str) for c in choices) else (numbers.Integral,)
    if isinstance(value, bool) or not isinstance(value, kinds) or value not in choices:
        listed = ", ".join(repr(c) for c in sorted(choices))
        raise ValueError(f"`{name}` must be one of {listed}, got {value!r}")


@dataclass(frozen=True)
class Real:
    """A real number (not a bool) within bounds; finite unless ``finite=False``; None allowed if ``optional``.

    Examples
    --------
    >>> Real(low=0, low_open=True).check("eps", 0.5)
    >>> Real(low=0, low_open=True).check("eps", 0)
    Traceback (most recent call last):
    ...
    ValueError: `eps` must be > 0, got 0
    """

    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    optional: bool = False
    finite: bool = True

    def check(self, name: str, value) -> None:
        if value is None and self.optional:
            return
        check_real(name, value, low=self.low, high=self.high, low_open=self.low_open, high_open=self.high_open)
        if self.finite and not math.isfinite(value):
            raise ValueError(f"`{name}` must be a finite number, got {value!r}")

    def invalid(self) -> list:
        """Values this constraint refuses (for the conformance suite)."""
        out = ["1.0", True, float("nan")]
        if not self.optional:
            out.append(None)
        if self.finite:
            out += [float("inf"), float("-inf")]
        if self.low is not None:
            out.append(self.low if self.low_open else self.low - max(1.0, abs(self.low)))
        if self.high is not None:
            out.append(self.high if self.high_open else self.high + max(1.0, abs(self.high)))
        return out


@dataclass(frozen=True)
class Int:
    """An integer (not a bool) within bounds; None allowed if ``optional``.

    Examples
    --------
    >>> Int(low=1).check("side_inner", 0)
    Traceback (most recent call last):
    ...
    ValueError: `side_inner` must be >= 1, got 0
    """

    low: int | None = None
    high: int | None = None
    optional: bool = False

    def check(self, name: str, value) -> None:
        if value is None and self.optional:
            return
        check_int(name, value, low=self.low)
        if self.high is not None and value > self.high:
            raise ValueError(f"`{name}` must be <= {self.high}, got {value!r}")

    def invalid(self) -> list:
        out = [1.5, "1", True]
        if not self.optional:
            out.append(None)
        if self.low is not None:
            out.append(self.low - 1)
        if self.high is not None:
            out.append(self.high + 1)
        return out


@dataclass(frozen=True)
class Choice:
    """One of a set of strings (or of integers, e.g. ``Choice(frozenset({4, 8}))``; not bools).

    Examples
    --------
    >>> Choice(frozenset({"gauss3", "parabolic"})).check("estimator", "cubic")
    Traceback (most recent call last):
    ...
    ValueError: `estimator` must be one of 'gauss3', 'parabolic', got 'cubic'
    """

    values: frozenset | tuple  # a tuple keeps an order for those who list it (bench.config.checks.describe)

    def check(self, name: str, value) -> None:
        check_choice(name, value, self.values)

    def invalid(self) -> list:
        if all(isinstance(c, str) for c in self.values):
            return ["not-one-of-them", 1, None]
        return [max(self.values) + 1, str(min(self.values)), float(min(self.values)) + 0.5, True, None]


@dataclass(frozen=True)
class Bool:
    """True or False (not 0 or 1)."""

    def check(self, name: str, value) -> None:
        if not isinstance(value, bool):
            raise ValueError(f"`{name}` must be True or False, got {value!r}")

    def invalid(self) -> list:
        return [1, "yes", None]



@dataclass(frozen=True)
class StrList:
    """A non-empty list or tuple of strings (a command line).

    Examples
    --------
    >>> StrList().check("command", ["prog", "--fast"])
    >>> StrList().check("command", [])
    Traceback (most recent call last):
    ...
    ValueError: `command` must be a non-empty list of strings, got []
    """

    def check(self, name: str, value) -> None:
        if not (isinstance(value, (list, tuple)) and value and all(isinstance(a, str) for a in value)):
            raise ValueError(f"`{name}` must be a non-empty list of strings, got {value!r}")

    def invalid(self) -> list:
        return [[], "prog", ["prog", 1], None]
