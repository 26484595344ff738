"""The schema of a tuning profile (``stripebench tune dp``; ``bench/config/profiles/tune_dp.toml``).

A tuning profile is a TOML document with exactly these keys (all required)::

    name = "tune_dp"            # free text
    seed = 1                    # integer >= 0 (never the evaluation's seed 0)
    trackers = ["dp4", "dp8"]   # registered trackers with an `h_weight` parameter
    h_weights = [1.0, 0.5]      # finite numbers > 0, none repeated
    hit_px = 3.0                # a row is a hit within this many pixels (finite, >= 0)
    tie = 0.005                 # scores within this of the best tie (finite, >= 0)

    [render]                    # the run's [render] keys without ambient_spp, plus n_angles
    width = 512
    height = 480
    spp = 16
    n_angles = 12

    [[experiments]]             # scene and material required; any other key is a scene override
    scene = "sphere"
    material = "matte"

Every value is checked with the limits of a run configuration (the same
:data:`bench.config.RENDER_KEYS` bounds, :func:`bench.config.check_scene` on each
experiment); every problem raises :class:`bench.config.ConfigError` with one line.
The procedure itself is :mod:`bench.studies.tune`.
"""

from __future__ import annotations

import math
import numbers
import pathlib
from dataclasses import dataclass, field

from bench.config import RENDER_KEYS, ConfigError, check_scene, read_toml, scene_override_keys

__all__ = ["TuneProfile", "load_profile", "parse_profile", "TOP_KEYS", "TUNE_RENDER_KEYS", "DEFAULT_PROFILE",
           "GapProfile", "load_gap_profile", "GAP_TOP_KEYS", "GAP_DEFAULT_PROFILE", "TuneThresholdProfile",
           "load_threshold_profile", "THRESHOLD_TOP_KEYS"]

#: The committed profile of ``stripebench tune dp``.
DEFAULT_PROFILE = pathlib.Path(__file__).resolve().parent / "profiles" / "tune_dp.toml"
TOP_KEYS = ("name", "seed", "trackers", "h_weights", "hit_px", "tie", "render", "experiments")
#: A tuning profile's ``[render]`` table: the run's :data:`bench.config.RENDER_KEYS` but ``ambient_spp``
#: (the scans use the scene's), plus ``n_angles`` (frames per scan).
TUNE_RENDER_KEYS = tuple(k for k in RENDER_KEYS if k != "ambient_spp") + ("n_angles",)


@dataclass
class TuneProfile:
    """A validated tuning profile (see the module docstring)."""

    name: str
    seed: int
    trackers: list[str]
    h_weights: list[float]
    hit_px: float
    tie: float
    render: dict
    experiments: list[dict] = field(default_factory=list)


def _finite(x) -> bool:
    return isinstance(x, numbers.Real) and not isinstance(x, bool) and math.isfinite(x)


def parse_profile(data) -> TuneProfile:
    """Validate a tuning profile dict (as read from TOML).

    Raises
    ------
    ConfigError
        A missing or unknown key or a bad value, named in the message.
    """
    from scenes.params import MAX_SIZE

    if not isinstance(data, dict):
        raise ConfigError(f"`profile` must be a table, got {type(data).__name__}")
    unknown = set(data) - set(TOP_KEYS)
    if unknown:
        raise ConfigError(f"`profile` has unknown key(s) {sorted(unknown)}; valid: {sorted(TOP_KEYS)}")
    for key in TOP_KEYS:
        if key not in data:
            raise ConfigError(f"`profile` lacks the key {key!r}")
    if not isinstance(data["name"], str) or not data["name"]:
        raise ConfigError(f"`name` must be a non-empty string, got {data['name']!r}")
    seed = data["seed"]
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ConfigError(f"`seed` must be an integer >= 0, got {seed!r}")
    import trackers

    names = data["trackers"]
    if not isinstance(names, list) or not names:
        raise ConfigError(f"`trackers` must be a non-empty list, got {names!r}")
    for n in names:
        if not isinstance(n, str) or n not in trackers.available() or "h_weight" not in trackers.make(n).get_params():
            raise ConfigError(f"`trackers` must name trackers with an h_weight parameter, got {n!r}")
    hws = data["h_weights"]
    if not isinstance(hws, list) or not hws or any(not _finite(h) or h <= 0 for h in hws):
        raise ConfigError(f"`h_weights` must be a non-empty list of finite numbers > 0, got {hws!r}")
    if len(set(hws)) != len(hws):
        raise ConfigError(f"`h_weights` must not repeat a value, got {hws!r}")
    for key in ("hit_px", "tie"):
        v = data[key]
        if not _finite(v) or not v >= 0:
            raise ConfigError(f"`{key}` must be a finite number >= 0, got {v!r}")
    render = data["render"]
    if not isinstance(render, dict) or set(render) != set(TUNE_RENDER_KEYS):
        raise ConfigError(f"`render` must have exactly the keys {sorted(TUNE_RENDER_KEYS)}, got {render!r}")
    for k, v in render.items():
        if isinstance(v, bool) or not isinstance(v, int) or not 1 <= v <= MAX_SIZE[k]:
            raise ConfigError(f"`render.{k}` must be an integer 1 .. {MAX_SIZE[k]}, got {v!r}")
    exps = data["experiments"]
    if not isinstance(exps, list) or not exps:
        raise ConfigError("`experiments` must be a non-empty list of tables")
    overridable = set(scene_override_keys())
    size = {k: render[k] for k in ("width", "height", "spp")}
    for i, e in enumerate(exps):
        if not isinstance(e, dict) or "scene" not in e or "material" not in e:
            raise ConfigError(f"`experiments` entries need `scene` and `material`, got {e!r}")
        extra = sorted(set(e) - overridable - {"scene", "material"})
        if extra:
            raise ConfigError(f"unknown key `experiments[{i}].{extra[0]}` (valid: scene, material and the scene "
                              f"overrides {', '.join(sorted(overridable))})")
        import scenes

        if e["scene"] not in scenes.available():
            raise ConfigError(f"`experiments[{i}].scene` must be one of {', '.join(scenes.available())}, "
                              f"got {e['scene']!r}")
        overrides = {k: v for k, v in e.items() if k not in ("scene", "material")}
        check_scene(f"experiments[{i}]", e["scene"], e["material"], size, overrides)
    return TuneProfile(data["name"], seed, list(names), [float(h) for h in hws], float(data["hit_px"]),
                       float(data["tie"]), dict(render), [dict(e) for e in exps])


def load_profile(path) -> TuneProfile:
    """Read (:func:`bench.config.read_toml`: a regular UTF-8 file) and validate a tuning profile.

    Raises
    ------
    ConfigError
        Unreadable, invalid TOML, or a missing or unknown key or a bad value, named in the message.
    """
    return parse_profile(read_toml(path, "tuning profile"))


# ---------------------------------------------------------------------------------------------------- dp_gap

#: The committed profile of ``stripebench tune dp_gap``.
GAP_DEFAULT_PROFILE = pathlib.Path(__file__).resolve().parent / "profiles" / "tune_dp_gap.toml"
GAP_TOP_KEYS = {"name", "seed", "tracker", "off_rel", "switch_rows", "hit_px", "tie", "render", "experiments",
                "seeds", "kinds", "real", "dp_trackers", "k_sigma", "max_gap", "min_run"}
GAP_RENDER_KEYS = {"width", "height", "spp", "n_angles"}


@dataclass
class GapProfile:
    """A validated profile of the DP trackers' reporting rules (``bench/config/profiles/tune_dp_gap.toml``)."""

    name: str
    seed: int
    tracker: str
    off_rel: list[float]
    switch_rows: list[float]
    hit_px: float
    tie: float
    render: dict
    experiments: list[dict] = field(default_factory=list)
    seeds: list[int] = field(default_factory=list)
    kinds: list[str] = field(default_factory=list)
    real: bool = False
    dp_trackers: list[str] = field(default_factory=list)
    k_sigma: list[float] = field(default_factory=list)
    max_gap: list = field(default_factory=list)
    min_run: list[int] = field(default_factory=list)


def _fail(msg: str):
    raise ConfigError(msg)


def _grid(data, key, low, high=None):
    vals = data[key]
    if (not isinstance(vals, list) or not vals
            or any(isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < low
                   or (high is not None and v > high) for v in vals)):
        bound = f"in [{low}, {high}]" if high is not None else f">= {low}"
        _fail(f"`{key}` must be a non-empty list of finite numbers {bound}, got {vals!r}")
    if len(set(vals)) != len(vals):
        _fail(f"`{key}` must not repeat a value, got {vals!r}")
    return [float(v) for v in vals]


def load_gap_profile(path, kinds=()) -> GapProfile:
    """Read and validate a ``stripebench tune dp_gap`` profile; ``kinds`` are the hard-frame kinds it
    may name (:data:`bench.studies.hard_frames.KINDS`).

    Raises
    ------
    bench.config.ConfigError
        A missing or unknown key or a bad value, named in the message (one line).
    """
    data = read_toml(pathlib.Path(path), "tuning profile")  # a regular UTF-8 file, bounded nesting
    unknown = set(data) - GAP_TOP_KEYS
    if unknown:
        _fail(f"`profile` has unknown key(s) {sorted(unknown)}; valid: {sorted(GAP_TOP_KEYS)}")
    for key in sorted(GAP_TOP_KEYS):
        if key not in data:
            _fail(f"`profile` lacks the key {key!r}")
    seed = data["seed"]
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        _fail(f"`seed` must be an integer >= 0, got {seed!r}")
    import trackers

    name = data["tracker"]
    if name not in trackers.available() or not {"off_rel", "switch_rows"} <= set(trackers.make(name).get_params()):
        _fail(f"`tracker` must name a tracker with off_rel and switch_rows parameters, got {name!r}")
    dps = data["dp_trackers"]
    if not isinstance(dps, list) or any(n not in trackers.available()
                                        or not {"k_sigma", "max_gap", "min_run"} <= set(trackers.make(n).get_params())
                                        for n in dps):
        _fail(f"`dp_trackers` must list trackers with k_sigma, max_gap and min_run parameters, got {dps!r}")
    off = _grid(data, "off_rel", 0.0, 1.0)
    sw = _grid(data, "switch_rows", 0.0)
    for key in ("hit_px", "tie"):
        v = data[key]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not v >= 0:
            _fail(f"`{key}` must be a number >= 0, got {v!r}")
    seeds = data["seeds"]
    if not isinstance(seeds, list) or any(isinstance(x, bool) or not isinstance(x, int) or x < 0 for x in seeds):
        _fail(f"`seeds` must be a list of integers >= 0, got {seeds!r}")
    ks = data["kinds"]
    if not isinstance(ks, list) or any(k not in tuple(kinds) for k in ks):
        _fail(f"`kinds` must be a list of {', '.join(kinds)}, got {ks!r}")
    if not isinstance(data["real"], bool):
        _fail(f"`real` must be true or false, got {data['real']!r}")
    render, exps = _render_experiments(data)
    return GapProfile(str(data["name"]), seed, name, off, sw, float(data["hit_px"]), float(data["tie"]), render, exps,
                      [int(x) for x in seeds], list(ks), data["real"], list(dps), _grid(data, "k_sigma", 0),
                      _none_int_grid(data, "max_gap", 0), _int_grid(data, "min_run", 1))


# ---------------------------------------------------------------------------------------------------- threshold

THRESHOLD_TOP_KEYS = {"name", "seeds", "kinds", "real", "hit_px", "tie", "tie_px", "trackers", "k_sigma",
                      "prominence", "min_run", "width_ratio", "frac", "colour_trackers", "colour_rules", "steger_k_sigma",
                      "steger_prominence", "steger_min_run", "seed", "render", "renders"}


@dataclass
class TuneThresholdProfile:
    """A validated profile (see ``bench/config/profiles/tune_threshold.toml``)."""

    name: str
    seeds: list[int]
    kinds: list[str]
    real: bool
    hit_px: float
    tie: float
    tie_px: float
    trackers: list[str]
    k_sigma: list[float]
    prominence: list[float]
    min_run: list[int]
    width_ratio: list
    frac: list[float]
    colour_trackers: list[str]
    colour_rules: list
    steger_k_sigma: list[float]
    steger_prominence: list[float]
    steger_min_run: list[int]
    seed: int
    render: dict
    renders: list[dict] = field(default_factory=list)


def _int_grid(data, key, low):
    vals = data[key]
    if (not isinstance(vals, list) or not vals
            or any(isinstance(v, bool) or not isinstance(v, int) or v < low for v in vals)):
        _fail(f"`{key}` must be a non-empty list of integers >= {low}, got {vals!r}")
    if len(set(vals)) != len(vals):
        _fail(f"`{key}` must not repeat a value, got {vals!r}")
    return [int(v) for v in vals]


def _none_int_grid(data, key, low):
    """A grid of integers >= ``low`` or ``"none"`` (None: no limit), distinct."""
    vals = data[key]
    if (not isinstance(vals, list) or not vals or len(set(map(str, vals))) != len(vals)
            or any(v != "none" and (isinstance(v, bool) or not isinstance(v, int) or v < low) for v in vals)):
        _fail(f"`{key}` must list distinct integers >= {low} or 'none', got {vals!r}")
    return [None if v == "none" else int(v) for v in vals]


def _none_real_grid(data, key, low):
    """A grid of finite numbers >= ``low`` or ``"none"`` (None: no limit), distinct."""
    vals = data[key]
    if (not isinstance(vals, list) or not vals or len(set(map(str, vals))) != len(vals)
            or any(v != "none" and (isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v)
                                    or v < low) for v in vals)):
        _fail(f"`{key}` must list distinct numbers >= {low} or 'none', got {vals!r}")
    return [None if v == "none" else float(v) for v in vals]


def _render_experiments(data, keys=GAP_RENDER_KEYS, exp_key="experiments", allow_empty=False):
    """The ``[render]`` table (exactly ``keys``) and the experiments of ``exp_key``, validated."""
    from scenes.params import MAX_SIZE

    render = data["render"]
    if not isinstance(render, dict) or set(render) != set(keys):
        _fail(f"`render` must have exactly the keys {sorted(keys)}, got {render!r}")
    for k, v in render.items():
        if isinstance(v, bool) or not isinstance(v, int) or not 1 <= v <= MAX_SIZE[k]:
            _fail(f"`render.{k}` must be an integer 1 .. {MAX_SIZE[k]}, got {v!r}")
    exps = data[exp_key]
    if not isinstance(exps, list) or (not exps and not allow_empty):
        _fail(f"`{exp_key}` must be a {'' if allow_empty else 'non-empty '}list of tables")
    size = {k: render[k] for k in ("width", "height")}
    for i, e in enumerate(exps):
        if not isinstance(e, dict) or "scene" not in e or "material" not in e:
            _fail(f"`{exp_key}` entries need `scene` and `material`, got {e!r}")
        check_scene(f"{exp_key}[{i}]", e["scene"], e["material"], size,
                    {k: v for k, v in e.items() if k not in ("scene", "material")})
    return dict(render), [dict(e) for e in exps]


def load_threshold_profile(path, kinds) -> TuneThresholdProfile:
    """Read and validate a ``stripebench tune threshold`` profile; ``kinds`` are the hard-frame kinds
    it may name (:data:`bench.studies.hard_frames.KINDS`).

    Raises
    ------
    bench.config.ConfigError
        A missing or unknown key or a bad value, named in the message (one line).
    """
    data = read_toml(pathlib.Path(path), "tuning profile")  # a regular UTF-8 file, bounded nesting
    unknown = set(data) - THRESHOLD_TOP_KEYS
    if unknown:
        raise ConfigError(f"`profile` has unknown key(s) {sorted(unknown)}; valid: {sorted(THRESHOLD_TOP_KEYS)}")
    missing = sorted(THRESHOLD_TOP_KEYS - set(data))
    if missing:
        raise ConfigError(f"`profile` lacks the key(s) {missing}")
    seeds = data["seeds"]
    if not isinstance(seeds, list) or not seeds or any(isinstance(s, bool) or not isinstance(s, int) or s < 0
                                                        for s in seeds):
        raise ConfigError(f"`seeds` must be a non-empty list of integers >= 0, got {seeds!r}")
    seed = data["seed"]
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        _fail(f"`seed` must be an integer >= 0, got {seed!r}")
    allowed = tuple(kinds)
    kinds = data["kinds"]
    if not isinstance(kinds, list) or not kinds or any(k not in allowed for k in kinds):
        raise ConfigError(f"`kinds` must be a non-empty list of {', '.join(allowed)}, got {kinds!r}")
    if not isinstance(data["real"], bool):
        raise ConfigError(f"`real` must be true or false, got {data['real']!r}")
    for key in ("hit_px", "tie", "tie_px"):
        v = data[key]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not v >= 0:
            raise ConfigError(f"`{key}` must be a number >= 0, got {v!r}")
    import trackers

    for key in ("trackers", "colour_trackers"):
        names = data[key]
        if not isinstance(names, list) or not names or any(n not in trackers.available() for n in names):
            raise ConfigError(f"`{key}` must be a non-empty list of registered trackers, got {names!r}")
    for n in data["trackers"]:
        if not {"k_sigma", "prominence", "min_run"} <= set(trackers.make(n).get_params()):
            raise ConfigError(f"`trackers` must name trackers with k_sigma, prominence and min_run, got {n!r}")
    rules = data["colour_rules"]
    if (not isinstance(rules, list) or not rules or len(set(map(str, rules))) != len(rules)
            or any(not (r in ("excess", "laser") or (not isinstance(r, bool) and isinstance(r, (int, float))
                                                     and 0 <= r <= 1)) for r in rules)):
        raise ConfigError(f"`colour_rules` must list distinct knees in [0, 1], 'excess' or 'laser', got {rules!r}")
    render, renders = _render_experiments(data, exp_key="renders", allow_empty=True)
    return TuneThresholdProfile(
        str(data["name"]), [int(s) for s in seeds], list(kinds), data["real"], float(data["hit_px"]),
        float(data["tie"]), float(data["tie_px"]), list(data["trackers"]), _grid(data, "k_sigma", 0),
        _grid(data, "prominence", 0), _int_grid(data, "min_run", 1), _none_real_grid(data, "width_ratio", 1.0),
        _grid(data, "frac", 0, 0.99),
        list(data["colour_trackers"]), [r if isinstance(r, str) else float(r) for r in rules],
        _grid(data, "steger_k_sigma", 0), _grid(data, "steger_prominence", 0), _int_grid(data, "steger_min_run", 1),
        seed, render, renders)
