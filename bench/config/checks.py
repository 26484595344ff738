"""Configuration values checked with the trackers' constraint types, each problem one ``ConfigError`` line.

A configuration's numbers, counts, switches and choices are constrained with the
types that constrain a tracker's parameters (:attr:`trackers.Tracker.parameter_constraints`:
:class:`trackers.Int`, :class:`trackers.Real`, :class:`trackers.Choice`,
:class:`trackers.Bool`): one vocabulary decides what is valid everywhere. Only
the wording is the configuration's own, and this module is all of it: a
message names the value's TOML path (``experiments[0].n_angles``), speaks TOML
(``true or false``) and describes the whole constraint in one phrase
(``an integer >= 2``), where a tracker's message names a Python parameter.

Structure (tables, lists, strings, labels, paths) is not a parameter constraint
and is checked where it is read (:mod:`bench.config.schema`).

Examples
--------
>>> require("seed", 3, Int(low=0))
3
>>> require("seed", -1, Int(low=0))
Traceback (most recent call last):
...
bench.errors.ConfigError: `seed` must be an integer >= 0, got -1
>>> describe(Real(low=0.0, high=1.0), plural=True)
'finite numbers in [0.0, 1.0]'
>>> describe(Choice(("rows", "none")))
"one of 'rows', 'none'"
"""

from __future__ import annotations

from trackers import Bool, Choice, Int, Real

from bench.errors import ConfigError

__all__ = ["accepts", "describe", "require", "Bool", "Choice", "Int", "Real", "NONE"]

#: The string that stands for None in a configuration, a profile and a tracker's parameters (TOML has no null).
NONE = "none"


def accepts(constraint, value) -> bool:
    """Whether ``constraint`` (a :mod:`trackers` constraint type) accepts ``value``.

    Examples
    --------
    >>> accepts(Int(low=1), 0), accepts(Bool(), True), accepts(Real(low=0), float("nan"))
    (False, True, False)
    """
    try:
        constraint.check("value", value)
    except ValueError:
        return False
    return True


def _bounds(low, high, low_open: bool = False, high_open: bool = False, *, interval: bool) -> str:
    if low is not None and high is not None:
        if interval:
            return f" in {'(' if low_open else '['}{low}, {high}{')' if high_open else ']'}"
        return f" {low} .. {high}"
    if low is not None:
        return f" {'>' if low_open else '>='} {low}"
    if high is not None:
        return f" {'<' if high_open else '<='} {high}"
    return ""


def describe(constraint, *, plural: bool = False) -> str:
    """The configuration's phrase for a constraint: what follows "must be" (``plural``: what follows
    "a list of").

    An :class:`~trackers.Int` reads ``an integer >= LOW`` or ``an integer LOW .. HIGH``, a
    :class:`~trackers.Real` ``a finite number >= LOW`` or ``... in [LOW, HIGH]`` (``a number`` when
    not ``finite``), a :class:`~trackers.Bool` ``true or false`` and a :class:`~trackers.Choice`
    ``one of 'A', 'B'`` (in the order given when its values are a tuple, sorted when a set).
    """
    if isinstance(constraint, Int):
        noun = "integer"
        bounds = _bounds(constraint.low, constraint.high, interval=False)
    elif isinstance(constraint, Real):
        noun = "finite number" if constraint.finite else "number"
        bounds = _bounds(constraint.low, constraint.high, constraint.low_open, constraint.high_open, interval=True)
    elif isinstance(constraint, Bool):
        return "true or false"
    elif isinstance(constraint, Choice):
        values = constraint.values if isinstance(constraint.values, (tuple, list)) else sorted(constraint.values)
        return f"one of {', '.join(map(repr, values))}"
    else:
        raise TypeError(f"no configuration wording for {constraint!r}")
    if plural:
        return f"{noun}s{bounds}"
    return f"{'an' if noun[0] in 'aeiou' else 'a'} {noun}{bounds}"


def require(path: str, value, constraint, what: str | None = None):
    """``value`` if ``constraint`` accepts it.

    Raises
    ------
    ConfigError
        ```PATH` must be WHAT, got VALUE``, with WHAT :func:`describe`'s phrase unless given.
    """
    if not accepts(constraint, value):
        raise ConfigError(f"`{path}` must be {describe(constraint) if what is None else what}, got {value!r}")
    return value
