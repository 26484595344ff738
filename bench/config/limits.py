"""What a configuration's values must also respect: scene-override bounds, the scene's own checks, a real set, memory.

One home for the checks that a run configuration (:mod:`bench.config.schema`), a
``[sweep]`` table (:mod:`bench.config.sweep`) and a tuning profile
(:mod:`bench.config.tune`) share. The scene overrides' extra bounds are
:class:`trackers.Real` constraints (:data:`SCENE_BOUNDS`), the vocabulary of the
trackers' parameters.
"""

from __future__ import annotations

import os
from pathlib import Path

from bench.config.checks import Real, accepts
from bench.errors import ConfigError

__all__ = ["SCENE_BOUNDS", "SCENE_UPPER_BOUNDS", "SCENE_LOWER_BOUNDS", "scene_value_problem", "check_scene",
           "check_real_set", "estimate_memory_bytes", "memory_limit_bytes"]

#: Per-experiment overrides with bounds beyond the scene's own checks. Upper bounds: the sensor's Poisson
#: noise overflows above them ("lam value too large"); lower bounds: a faster lens also overflows it, a thinner
#: sheet needs a laser-profile table beyond memory. Not ``finite``: the scene itself refuses an infinity below.
SCENE_BOUNDS = {
    "laser_power_mw": Real(high=1e5, finite=False),
    "ambient_lux": Real(high=1e6, finite=False),
    "exposure_ms": Real(high=1e4, finite=False),
    "f_number": Real(low=0.5, finite=False),
    "line_fwhm_mrad": Real(low=1e-3, finite=False),
}
#: The upper bounds of :data:`SCENE_BOUNDS`, key -> bound.
SCENE_UPPER_BOUNDS = {k: c.high for k, c in SCENE_BOUNDS.items() if c.high is not None}
#: The lower bounds of :data:`SCENE_BOUNDS`, key -> bound.
SCENE_LOWER_BOUNDS = {k: c.low for k, c in SCENE_BOUNDS.items() if c.low is not None}


def scene_value_problem(key: str, value) -> str | None:
    """What is wrong with a scene override beyond the scene's own checks
    (:data:`SCENE_BOUNDS`), or None. The one check that experiments and
    ``[sweep]`` values share.

    Examples
    --------
    >>> scene_value_problem("ambient_lux", 1e7)
    'must be at most 1e+06'
    >>> scene_value_problem("ambient_lux", 400.0) is None
    True
    """
    bounds = SCENE_BOUNDS.get(key)
    if bounds is None or not accepts(Real(finite=False), value) or accepts(bounds, value):
        return None  # no bound, or the scene names a wrong type (or NaN)
    if bounds.high is not None and value > bounds.high:
        return f"must be at most {bounds.high:g}"
    return f"must be at least {bounds.low:g}"


def check_scene(path: str, scene: str, material: str, render: dict, overrides: dict) -> None:
    """Validate one experiment's scene (or one ``[sweep]`` value applied to it): the bounds of
    :func:`scene_value_problem` on every override, then the scene's own checks (:func:`scenes.make`).

    Raises
    ------
    ConfigError
        ``PATH.KEY must be at most ...`` or ``PATH: <the scene's message>``.
    """
    import scenes

    for k in sorted(overrides):
        problem = scene_value_problem(k, overrides[k])
        if problem:
            raise ConfigError(f"`{path}.{k}` {problem}, got {overrides[k]!r}")
    try:  # let the scene validate its own parameters
        scenes.make(scene, material=material, **render, **overrides)
    except (TypeError, KeyError, ValueError) as exc:
        msg = exc.args[0] if exc.args else str(exc)
        raise ConfigError(f"`{path}`: {msg}") from None


def check_real_set(value, path: str = "real_set", *, full: bool = False) -> str:
    """Validate a ``real_set`` value: ``""``, ``"shipped"`` or a folder holding a
    ``manifest.csv``; with ``full`` the whole set (:func:`bench.store.realset.validate_dataset`:
    every image and reference read), so that a broken set is found before any scan.

    Raises
    ------
    ConfigError
        One line naming ``path``, the value and the first problem (with the count of others).
    """
    if not isinstance(value, str):
        raise ConfigError(f"`{path}` must be \"\", \"shipped\" or a folder, got {value!r}")
    if not value:
        return value
    from bench.store import realset

    folder = realset.SHIPPED if value == "shipped" else Path(value)
    if value != "shipped" and not folder.is_dir():
        raise ConfigError(f"`{path}` must be \"\", \"shipped\" or a folder, got {value!r} (no such folder)")
    if not (folder / "manifest.csv").is_file():
        raise ConfigError(f"`{path}` names {value!r}, which is not a real set (no manifest.csv; see docs/real.md)")
    if full:
        _, problems = realset.validate_dataset(folder)
        if problems:
            more = f" (and {len(problems) - 1} more problem(s); `stripebench real {value} --check` lists them)" \
                if len(problems) > 1 else ""
            raise ConfigError(f"`{path}` {value!r} is not a valid real set: {problems[0]}{more}")
    return value


def estimate_memory_bytes(n_frames: int, width: int, height: int, n_trackers: int) -> int:
    """A rough upper estimate of the memory one scan needs (bytes): the
    checkpoint's frame x row arrays (columns, scores, truth) with working copies,
    plus one frame's render buffers.

    Examples
    --------
    >>> estimate_memory_bytes(40, 512, 480, 10) < 2**30
    True
    """
    per_row = 8 * (2 * n_trackers + 5)
    return int(3 * n_frames * height * per_row + 40 * 8 * width * height)


def memory_limit_bytes() -> int:
    """Half of this machine's physical memory, bytes (8 GiB when it cannot be read): the most
    a run's or a sweep's estimate may ask for."""
    try:
        return int(0.5 * os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return 8 * 2**30

