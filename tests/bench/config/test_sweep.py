"""The [sweep] table's schema (bench/config/sweep.py): the same value limits as a run, bounded sizes."""

import time

import pytest

from bench.config import ConfigError, SCENE_LOWER_BOUNDS, SCENE_UPPER_BOUNDS, parse
from bench.config.sweep import MAX_EVALUATIONS, MAX_POINTS, MAX_REPEATS, Sweep, parse_sweep

BASE = {"name": "s", "trackers": ["threshold"], "baselines": [], "dp": [], "render": {"width": 64, "height": 60},
        "experiments": [{"scene": "cone", "n_angles": 2}]}


@pytest.mark.parametrize("key", sorted(SCENE_UPPER_BOUNDS))
def test_sweep_values_beyond_a_runs_upper_bounds_are_refused_as_a_run_refuses_them(key):
    top = SCENE_UPPER_BOUNDS[key]
    with pytest.raises(ConfigError, match=rf"`experiments\[0\].{key}` must be at most"):
        parse({**BASE, "experiments": [{"scene": "cone", "n_angles": 2, key: top * 10}]})
    with pytest.raises(ConfigError, match=rf"`sweep.{key}` = {top * 10!r} .*must be at most"):
        parse_sweep({key: [top * 10]}, parse(BASE))


@pytest.mark.parametrize("key", sorted(SCENE_LOWER_BOUNDS))
def test_sweep_values_below_a_runs_lower_bounds_are_refused(key):
    with pytest.raises(ConfigError, match=rf"`sweep.{key}` = .*must be at least"):
        parse_sweep({key: [SCENE_LOWER_BOUNDS[key] / 10]}, parse(BASE))


def test_a_huge_grid_is_refused_at_once_without_building_it():
    t0 = time.monotonic()
    table = {"ambient_lux": list(range(3000)), "laser_power_mw": list(range(1, 3001))}
    with pytest.raises(ConfigError, match=rf"`sweep` has 9000000 grid points \(3000 ambient_lux x 3000 "
                                          rf"laser_power_mw\); at most {MAX_POINTS}"):
        parse_sweep(table, parse(BASE))
    assert time.monotonic() - t0 < 5


def test_repeats_and_evaluations_are_bounded():
    with pytest.raises(ConfigError, match=f"integer 1 .. {MAX_REPEATS}, got 1000000000"):
        parse_sweep({"ambient_lux": [0], "repeats": 10**9}, parse(BASE))
    many = {**BASE, "experiments": [{"scene": "cone", "n_angles": 100000}]}
    with pytest.raises(ConfigError, match=f"evaluations .*; at most {MAX_EVALUATIONS}"):
        parse_sweep({"ambient_lux": list(range(2000)), "repeats": 1000}, parse(many))


def test_a_valid_sweep_and_its_point_count():
    s = parse_sweep({"ambient_lux": [0, 400], "material": ["matte", "glossy"], "repeats": 2}, parse(BASE))
    assert isinstance(s, Sweep) and s.n_points == len(s.points()) == 4 and s.repeats == 2
