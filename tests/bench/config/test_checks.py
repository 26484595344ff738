"""One constraint vocabulary: configuration values are checked with the trackers' constraint types (issue 36)."""

import pytest

import trackers
from bench.config import ConfigError, checks, limits, schema, sweep, tune

TABLES = {"schema.CONSTRAINTS": schema.CONSTRAINTS, "schema.EXPERIMENT_CONSTRAINTS": schema.EXPERIMENT_CONSTRAINTS,
          "limits.SCENE_BOUNDS": limits.SCENE_BOUNDS, "tune.CONSTRAINTS": tune.CONSTRAINTS,
          "tune.GAP_CONSTRAINTS": tune.GAP_CONSTRAINTS, "tune.THRESHOLD_CONSTRAINTS": tune.THRESHOLD_CONSTRAINTS,
          "sweep.REPEATS": {"repeats": sweep.REPEATS}}
CONSTRAINTS = [(f"{table}[{key}]", c) for table, cs in TABLES.items() for key, c in cs.items()]


@pytest.mark.parametrize("where, constraint", CONSTRAINTS, ids=[w for w, _ in CONSTRAINTS])
def test_every_configuration_constraint_is_a_trackers_constraint_type(where, constraint):
    assert isinstance(constraint, (trackers.Int, trackers.Real, trackers.Choice, trackers.Bool)), where


@pytest.mark.parametrize("where, constraint", CONSTRAINTS, ids=[w for w, _ in CONSTRAINTS])
def test_what_a_constraint_refuses_is_one_config_error_line_naming_the_path(where, constraint):
    for value in constraint.invalid():  # the values the trackers' conformance suite refuses
        with pytest.raises(ConfigError) as exc:
            checks.require("a.b", value, constraint)
        assert str(exc.value).startswith("`a.b` must be ") and "\n" not in str(exc.value), (where, value)


@pytest.mark.parametrize("constraint, phrase", [
    (trackers.Int(low=0), "an integer >= 0"),
    (trackers.Int(low=1, high=1000), "an integer 1 .. 1000"),
    (trackers.Real(low=0), "a finite number >= 0"),
    (trackers.Real(low=0, finite=False), "a number >= 0"),
    (trackers.Real(low=0, low_open=True, high=1), "a finite number in (0, 1]"),
    (trackers.Bool(), "true or false"),
    (trackers.Choice(("rows", "none")), "one of 'rows', 'none'"),
    (trackers.Choice(frozenset({"b", "a"})), "one of 'a', 'b'"),
])
def test_describe_words_a_constraint_as_a_configuration_message_does(constraint, phrase):
    assert checks.describe(constraint) == phrase


def test_the_scene_bounds_are_the_published_upper_and_lower_bounds():
    assert limits.SCENE_UPPER_BOUNDS == {"laser_power_mw": 1e5, "ambient_lux": 1e6, "exposure_ms": 1e4}
    assert limits.SCENE_LOWER_BOUNDS == {"f_number": 0.5, "line_fwhm_mrad": 1e-3}
    assert limits.scene_value_problem("f_number", 0.1) == "must be at least 0.5"
    assert limits.scene_value_problem("ambient_lux", float("inf")) == "must be at most 1e+06"
    assert limits.scene_value_problem("ambient_lux", float("nan")) is None  # the scene names it
