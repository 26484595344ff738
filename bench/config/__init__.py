"""Experiment configurations: TOML files and the embedded profiles, validated.

The package's modules, lowest first (every name that callers use is re-exported here):

* :mod:`bench.config.checks`: configuration values checked with the trackers' constraint types;
* :mod:`bench.config.limits`: scene-override bounds and the scene's own checks, a real set, memory;
* :mod:`bench.config.tracker_specs`: tracker settings (:class:`TrackerSpec`; ``trackers``, ``--trackers``);
* :mod:`bench.config.schema`: the run configuration (:class:`Config`, :func:`parse`), with every key,
  its default and its comment;
* :mod:`bench.config.loading`: TOML files and the embedded profiles (:func:`load`, :func:`profile`);
* :mod:`bench.config.sweep` and :mod:`bench.config.tune`: the ``[sweep]`` table and the tuning profiles.

The full reference, with a complete example, is ``docs/config.md``.

Examples
--------
>>> from bench import config
>>> config.parse({"experiments": [{"scene": "plane", "n_angles": 2}]}, machine=False).n_samples
150
"""

from __future__ import annotations

from bench.config.limits import (SCENE_BOUNDS, SCENE_LOWER_BOUNDS, SCENE_UPPER_BOUNDS, check_real_set, check_scene,
                                 estimate_memory_bytes, memory_limit_bytes, scene_value_problem)
from bench.config.loading import PROFILES, load, profile, read_toml, with_overrides
from bench.config.schema import (EXECUTION_KEYS, HARNESS_KEYS, MAX_ANGLE_DEG, MAX_N_BOOT, MAX_N_SAMPLES, MIN_N_BOOT,
                                 OPTIONAL_KEYS, RENDER_KEYS, Config, Experiment, parse, scene_override_keys)
from bench.config.tracker_specs import LABEL_CHARS, TrackerSpec, parse_trackers, parse_trackers_arg
from bench.errors import ConfigError, StripebenchError

__all__ = ["ConfigError", "Config", "Experiment", "TrackerSpec", "parse_trackers", "parse_trackers_arg", "load",
           "read_toml", "parse", "profile", "with_overrides", "PROFILES", "HARNESS_KEYS", "RENDER_KEYS",
           "scene_override_keys", "SCENE_UPPER_BOUNDS", "EXECUTION_KEYS", "SCENE_LOWER_BOUNDS", "MAX_ANGLE_DEG",
           "estimate_memory_bytes", "scene_value_problem", "check_scene", "check_real_set", "memory_limit_bytes",
           "StripebenchError", "MAX_N_SAMPLES", "MAX_N_BOOT", "MIN_N_BOOT", "LABEL_CHARS", "OPTIONAL_KEYS",
           "SCENE_BOUNDS"]
