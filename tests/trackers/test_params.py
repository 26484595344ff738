"""Parameter constraints (trackers._params): each refuses what it calls invalid, naming the parameter."""

import math

import pytest

from trackers._params import Bool, Choice, Int, Real

CONSTRAINTS = [Real(), Real(low=0, low_open=True), Real(low=0, high=1, high_open=True), Real(optional=True),
               Real(low=0.5, finite=False), Int(), Int(low=1), Int(low=0, high=10, optional=True),
               Choice(frozenset({"a", "b"})), Bool()]


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
