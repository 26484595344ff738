"""The ``[sweep]`` table of a sweep configuration: its keys, limits and validation.

A sweep configuration is an ordinary configuration (:mod:`bench.config`) with a
``[sweep]`` table::

    [sweep]
    ambient_lux = [0, 100, 400, 1000, 2000]   # any scene override key, a list of values
    laser_power_mw = [1.0, 3.0, 10.0]
    repeats = 3                                # independent noise/sample draws per point (1 .. MAX_REPEATS)

Every swept value is checked as an experiment's own override is: the same
bounds (:func:`bench.config.scene_value_problem`), then the scene's checks. The grid's
size is bounded before it is built: at most :data:`MAX_POINTS` grid points,
:data:`MAX_REPEATS` repeats, :data:`MAX_EVALUATIONS` evaluations (frames x
points x repeats over the experiments), and a results table estimated within
half of this machine's memory (:data:`ROW_BYTES` per row). Running a sweep is
:mod:`bench.run.sweep`.
"""

from __future__ import annotations

import itertools
import math
import numbers
from dataclasses import dataclass
from typing import Any

from bench.config.checks import Int, require
from bench.config.limits import memory_limit_bytes, scene_value_problem
from bench.config.loading import read_toml
from bench.config.schema import Config, parse, scene_override_keys
from bench.errors import ConfigError

__all__ = ["Sweep", "parse_sweep", "load", "sweep_keys", "MAX_POINTS", "MAX_REPEATS", "MAX_EVALUATIONS",
           "ROW_BYTES", "estimate_rows"]

#: Most grid points (the product of the value lists).
MAX_POINTS = 100_000
#: Most repeats per grid point.
MAX_REPEATS = 1000
#: ``repeats``, in the trackers' constraint types (:mod:`bench.config.checks`).
REPEATS = Int(low=1, high=MAX_REPEATS)
#: Most evaluations (one frame at one grid point and one repeat), summed over the experiments.
MAX_EVALUATIONS = 10**8
#: Estimated driver memory per row of the results table (a dict of ~30 fields, then a DataFrame row), bytes.
ROW_BYTES = 2048


def sweep_keys() -> frozenset:
    """The keys a ``[sweep]`` table may list: every per-experiment scene override and ``material``."""
    return frozenset(set(scene_override_keys()) | {"material"})


@dataclass(frozen=True)
class Sweep:
    """A validated ``[sweep]`` table: the swept keys with their values, and the repeats.

    Examples
    --------
    >>> s = Sweep((("ambient_lux", (0.0, 400.0)), ("laser_power_mw", (1.0, 3.0, 10.0))), repeats=2)
    >>> len(s.points()), s.points()[1]
    (6, {'ambient_lux': 0.0, 'laser_power_mw': 3.0})
    """

    axes: tuple[tuple[str, tuple], ...]
    repeats: int = 1

    @property
    def keys(self) -> tuple[str, ...]:
        return tuple(k for k, _ in self.axes)

    @property
    def n_points(self) -> int:
        """The number of grid points (without building them)."""
        return math.prod(len(v) for _, v in self.axes)

    def points(self) -> list[dict[str, Any]]:
        """The grid: every combination of the values, the last key varying fastest."""
        return [dict(zip(self.keys, combo)) for combo in itertools.product(*(v for _, v in self.axes))]

    def to_dict(self) -> dict[str, Any]:
        return {**{k: list(v) for k, v in self.axes}, "repeats": self.repeats}


def estimate_rows(config: Config, n_points: int, repeats: int) -> int:
    """Rows of a sweep's results table: experiments x grid points x repeats x trackers."""
    return len(config.experiments) * n_points * repeats * max(1, len(config.tracker_specs))


def _frames(config: Config) -> int:
    from scenes import DEFAULTS

    return sum(len(e.angles) if e.angles is not None else (e.n_angles or DEFAULTS["n_angles"])
               for e in config.experiments)


def _check_size(config: Config, lengths: dict[str, int], repeats: int) -> None:
    n_points = math.prod(lengths.values())
    shape = " x ".join(f"{n} {k}" for k, n in lengths.items())
    if n_points > MAX_POINTS:
        raise ConfigError(f"`sweep` has {n_points} grid points ({shape}); at most {MAX_POINTS}")
    evaluations = _frames(config) * n_points * repeats
    if evaluations > MAX_EVALUATIONS:
        raise ConfigError(f"`sweep` asks for {evaluations} evaluations ({_frames(config)} frames over the "
                          f"experiments x {n_points} grid points x {repeats} repeat(s)); at most {MAX_EVALUATIONS}")
    need = estimate_rows(config, n_points, repeats) * ROW_BYTES
    if need > memory_limit_bytes():
        raise ConfigError(f"`sweep`'s results table needs about {need / 2**30:.1f} GiB of memory "
                          f"({estimate_rows(config, n_points, repeats)} rows), more than half of this machine's "
                          f"{2 * memory_limit_bytes() / 2**30:.0f} GiB")


def parse_sweep(table, config: Config) -> Sweep:
    """Validate a ``[sweep]`` table against a parsed configuration.

    The sizes are checked first (nothing is built for a grid that is too large),
    then every value by building each experiment's scene with it, with the
    bounds an experiment's own override has (:func:`bench.config.scene_value_problem`).

    Raises
    ------
    ConfigError
        Not a table, an unknown key, an empty or non-list value, a repeated value,
        a value the bounds or the scene reject, a bad ``repeats``, a grid too large;
        one line naming ``sweep.<key>``.
    """
    import scenes

    if not isinstance(table, dict):
        raise ConfigError(f"`sweep` must be a table, got {table!r}")
    repeats = require("sweep.repeats", table.get("repeats", 1), REPEATS)
    lengths = {}
    for key, values in table.items():
        if key == "repeats":
            continue
        if key not in sweep_keys():
            raise ConfigError(f"unknown key `sweep.{key}` (valid: {', '.join(sorted(sweep_keys() | {'repeats'}))})")
        if not isinstance(values, list) or not values:
            raise ConfigError(f"`sweep.{key}` must be a non-empty list of values, got {values!r:.80}")
        lengths[key] = len(values)
    if not lengths:
        raise ConfigError(f"`sweep` must sweep at least one key (valid: {', '.join(sorted(sweep_keys()))})")
    _check_size(config, lengths, int(repeats))
    axes = []
    for key, values in table.items():
        if key == "repeats":
            continue
        vals = []
        for v in values:
            if isinstance(v, bool) or not isinstance(v, (str, numbers.Real)):
                raise ConfigError(f"`sweep.{key}` must hold numbers or names, got {v!r:.80}")
            vals.append(float(v) if isinstance(v, numbers.Real) else v)
        if len(set(vals)) != len(vals):
            raise ConfigError(f"`sweep.{key}` repeats a value: {values!r:.80}")
        for i, e in enumerate(config.experiments):
            for v in vals:
                where = f"`sweep.{key}` = {v!r} (experiment {i}, {e.key})"
                problem = scene_value_problem(key, v)  # the bounds of an experiment's own override
                if problem:
                    raise ConfigError(f"{where}: {problem}")
                params = {**config.render, **e.overrides, "material": e.material, key: v}
                try:
                    scenes.make(e.scene, **params)
                except (TypeError, KeyError, ValueError) as exc:
                    msg = exc.args[0] if exc.args else str(exc)
                    raise ConfigError(f"{where}: {msg}") from None
        axes.append((key, tuple(vals)))
    return Sweep(tuple(axes), int(repeats))


def load(path) -> tuple[Config, Sweep]:
    """Read a sweep configuration file: the configuration and its ``[sweep]`` table."""
    data = read_toml(path)
    if not isinstance(data, dict) or "sweep" not in data:
        raise ConfigError(f"{path}: a sweep configuration needs a `[sweep]` table (see docs/sweeps.md)")
    data = dict(data)
    table = data.pop("sweep")
    config = parse(data, source=str(path))
    return config, parse_sweep(table, config)
