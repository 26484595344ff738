"""Parameter constraints (trackers._params): each refuses what it calls invalid, naming the parameter."""

import math

import pytest

from trackers._params import Bool, Choice, Int, Real, StrList

CONSTRAINTS = [Real(), Real(low=0, low_open=True), Real(low=0, high=1, high_open=True), Real(optional=True),
               Real(low=0.5, finite=False), Int(), Int(low=1), Int(low=0, high=10, optional=True),
               Choice(frozenset({"a", "b"})), Choice(frozenset({4, 8})), Bool(), StrList()]


@pytest.mark.parametrize("constraint", CONSTRAINTS, ids=repr)
def test_every_invalid_value_is_refused_with_the_name(constraint):
    assert constraint.invalid()
    for bad in constraint.invalid():
        with pytest.raises(ValueError, match="^`p` must be"):
            constraint.check("p", bad)


def test_valid_values_pass_and_bounds_are_exact():
    Real(low=0, high=1, high_open=True).check("p", 0)
    Real(low=0, high=1).check("p", 1)
    Real(optional=True).check("p", None)
    Real(low=0.5, finite=False).check("p", math.inf)
    Int(low=0, high=10).check("p", 10)
    Int(optional=True).check("p", None)
    Choice(frozenset({"a", "b"})).check("p", "b")
    Bool().check("p", False)
    with pytest.raises(ValueError, match=r"^`p` must be a finite number, got inf$"):
        Real(low=0).check("p", math.inf)
    with pytest.raises(ValueError, match=r"^`p` must be <= 10, got 11$"):
        Int(high=10).check("p", 11)


def test_an_integer_choice_takes_equal_integers_only():
    import numpy as np

    c = Choice(frozenset({4, 8}))
    c.check("connectivity", 8)
    c.check("connectivity", np.int64(4))
    for bad, shown in ((6, "6"), (True, "True"), (4.0, "4.0"), ("4", "'4'")):
        with pytest.raises(ValueError, match=rf"^`connectivity` must be one of 4, 8, got {shown}$"):
            c.check("connectivity", bad)


def test_a_string_list_is_a_non_empty_list_or_tuple_of_strings():
    StrList().check("command", ("prog",))
    with pytest.raises(ValueError, match=r"^`command` must be a non-empty list of strings, got \['prog', 1\]$"):
        StrList().check("command", ["prog", 1])
