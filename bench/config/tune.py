"""The schema of a tuning profile (``stripebench tune dp``; ``bench/config/profiles/tune_dp.toml``).

A tuning profile is a TOML document with exactly these keys (all required)::

    name = "tune_dp"            # free text
    seed = 1                    # integer >= 0 (never the evaluation's seed 0)
    trackers = ["dp4", "dp8"]   # registered trackers with an `h_weight` parameter
    h_weights = [1.0, 0.5]      # finite numbers > 0, none repeated
    hit_px = 3.0                # a row is a hit within this many pixels (finite, >= 0)
    tie = 0.005                 # scores within this of the best tie (finite, >= 0)
    seeds = [100, 101]          # the synthetic hard frames' seeds (integers >= 0; may be empty)
    kinds = ["printed"]         # their kinds (bench.studies.hard_frames.KINDS; may be empty)
    check_real = true           # score the shipped photographs beside the choice (never in it)

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
experiment) and the numbers with the trackers' constraint types (:data:`CONSTRAINTS`,
:data:`GAP_CONSTRAINTS`, :data:`THRESHOLD_CONSTRAINTS`; :mod:`bench.config.checks`);
every problem raises :class:`bench.config.ConfigError` with one line.
The procedure itself is :mod:`bench.studies.tune`.

The ``tune threshold`` and ``tune dp_gap`` profiles may also hold the stripe question's stage
(:func:`stripe_stage`): ``stripe_trackers`` (the trackers it chooses for, each on its own) and
``stripe_tests`` (the candidates, in order of preference: ``"none"``, the question not asked, or a
table of :class:`trackers.StripeTest` settings, ``"none"`` for a test not asked); both or neither.
"""

from __future__ import annotations

import pathlib
from dataclasses import dataclass, field

from bench.config.checks import NONE, Bool, Choice, Int, Real, accepts, describe, require
from bench.config.limits import check_scene
from bench.config.loading import read_toml
from bench.config.schema import RENDER_KEYS, scene_override_keys
from bench.errors import ConfigError

__all__ = ["TuneProfile", "load_profile", "parse_profile", "TOP_KEYS", "TUNE_RENDER_KEYS", "DEFAULT_PROFILE",
           "GapProfile", "load_gap_profile", "GAP_TOP_KEYS", "STRIPE_KEYS", "stripe_stage", "GAP_DEFAULT_PROFILE",
           "TuneThresholdProfile", "load_threshold_profile", "THRESHOLD_TOP_KEYS"]

#: The committed profile of ``stripebench tune dp``.
DEFAULT_PROFILE = pathlib.Path(__file__).resolve().parent / "profiles" / "tune_dp.toml"
TOP_KEYS = ("name", "seed", "trackers", "h_weights", "hit_px", "tie", "seeds", "kinds", "check_real", "render",
            "experiments")
#: A tuning profile's ``[render]`` table: the run's :data:`bench.config.RENDER_KEYS` but ``ambient_spp``
#: (the scans use the scene's), plus ``n_angles`` (frames per scan).
TUNE_RENDER_KEYS = tuple(k for k in RENDER_KEYS if k != "ambient_spp") + ("n_angles",)
#: The numbers of a ``tune dp`` profile (of ``h_weights``: each value; the ``[render]`` sizes are integers
#: 1 .. :data:`scenes.params.MAX_SIZE`).
CONSTRAINTS = {"seed": Int(low=0), "h_weights": Real(low=0, low_open=True), "hit_px": Real(low=0), "tie": Real(low=0),
               "seeds": Int(low=0), "check_real": Bool()}


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
    seeds: list[int] = field(default_factory=list)
    kinds: list[str] = field(default_factory=list)
    check_real: bool = False


def parse_profile(data, kinds=()) -> TuneProfile:
    """Validate a tuning profile dict (as read from TOML); ``kinds`` are the hard-frame kinds it may
    name (:data:`bench.studies.hard_frames.KINDS`).

    Raises
    ------
    ConfigError
        A missing or unknown key or a bad value, named in the message.
    """
    from scenes import MAX_SIZE

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
    seed = require("seed", data["seed"], CONSTRAINTS["seed"])
    import trackers

    names = data["trackers"]
    if not isinstance(names, list) or not names:
        raise ConfigError(f"`trackers` must be a non-empty list, got {names!r}")
    for n in names:
        if not isinstance(n, str) or n not in trackers.available() or "h_weight" not in trackers.make(n).get_params():
            raise ConfigError(f"`trackers` must name trackers with an h_weight parameter, got {n!r}")
    hws = _grid(data, "h_weights", CONSTRAINTS["h_weights"])
    for key in ("hit_px", "tie", "check_real"):
        require(key, data[key], CONSTRAINTS[key])
    seeds = data["seeds"]
    if not isinstance(seeds, list) or not all(accepts(CONSTRAINTS["seeds"], x) for x in seeds):
        raise ConfigError(f"`seeds` must be a list of {describe(CONSTRAINTS['seeds'], plural=True)}, got {seeds!r}")
    ks = data["kinds"]
    if not isinstance(ks, list) or not all(accepts(Choice(tuple(kinds)), k) for k in ks):
        raise ConfigError(f"`kinds` must be a list of {', '.join(kinds)}, got {ks!r}")
    render = data["render"]
    if not isinstance(render, dict) or set(render) != set(TUNE_RENDER_KEYS):
        raise ConfigError(f"`render` must have exactly the keys {sorted(TUNE_RENDER_KEYS)}, got {render!r}")
    for k, v in render.items():
        require(f"render.{k}", v, Int(low=1, high=MAX_SIZE[k]))
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
                       float(data["tie"]), dict(render), [dict(e) for e in exps], [int(x) for x in seeds], list(ks),
                       data["check_real"])


def load_profile(path, kinds=()) -> TuneProfile:
    """Read (:func:`bench.config.read_toml`: a regular UTF-8 file) and validate a tuning profile;
    ``kinds`` as :func:`parse_profile`.

    Raises
    ------
    ConfigError
        Unreadable, invalid TOML, or a missing or unknown key or a bad value, named in the message.
    """
    return parse_profile(read_toml(path, "tuning profile"), kinds)


# ---------------------------------------------------------------------------------------------------- dp_gap

#: The committed profile of ``stripebench tune dp_gap``.
GAP_DEFAULT_PROFILE = pathlib.Path(__file__).resolve().parent / "profiles" / "tune_dp_gap.toml"
#: The optional keys of the stripe question's stage (:func:`stripe_stage`), in the threshold and dp_gap profiles.
STRIPE_KEYS = {"stripe_trackers", "stripe_tests"}
#: The optional false-report ceiling of the threshold and dp_gap profiles (:func:`false_ceiling`).
CEILING_KEY = "max_false_rate"
#: The optional keys of a ``tune dp_gap`` profile besides those above.
GAP_OPTIONAL_KEYS = {"level_quantile"}
GAP_TOP_KEYS = {"name", "seed", "tracker", "off_rel", "switch_rows", "hit_px", "tie", "render", "experiments",
                "seeds", "kinds", "real", "dp_trackers", "k_sigma", "max_gap", "min_run"}
GAP_RENDER_KEYS = {"width", "height", "spp", "n_angles"}
#: The numbers and switches of a ``tune dp_gap`` profile (of a list: each value; ``max_gap`` also ``"none"``).
GAP_CONSTRAINTS = {"seed": Int(low=0), "seeds": Int(low=0), "off_rel": Real(low=0.0, high=1.0),
                   "switch_rows": Real(low=0.0), "hit_px": Real(low=0, finite=False), "tie": Real(low=0, finite=False),
                   "real": Bool(), "k_sigma": Real(low=0), "max_gap": Int(low=0), "min_run": Int(low=1),
                   "level_quantile": Real(low=0.0, high=1.0)}


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
    stripe_trackers: list[str] = field(default_factory=list)
    stripe_tests: list = field(default_factory=list)
    max_false_rate: float | None = None
    #: stage 1's grid of the tracker's ``level_quantile`` (None: not a dimension of the grid; the tracker's default)
    level_quantile: list[float] | None = None


def _fail(msg: str):
    raise ConfigError(msg)


def _read_profile(path, keys: set) -> dict:
    """A tuning profile's table (a regular UTF-8 TOML file, bounded nesting), refused if it has a key
    outside ``keys``."""
    data = read_toml(pathlib.Path(path), "tuning profile")
    unknown = set(data) - keys
    if unknown:
        _fail(f"`profile` has unknown key(s) {sorted(unknown)}; valid: {sorted(keys)}")
    return data


def _grid(data, key, constraint: Real | Int, cast=float):
    """A grid of distinct values ``constraint`` accepts, each passed through ``cast`` (``int`` for an
    :class:`Int` grid)."""
    vals = data[key]
    if not isinstance(vals, list) or not vals or not all(accepts(constraint, v) for v in vals):
        _fail(f"`{key}` must be a non-empty list of {describe(constraint, plural=True)}, got {vals!r}")
    if len(set(vals)) != len(vals):
        _fail(f"`{key}` must not repeat a value, got {vals!r}")
    return [cast(v) for v in vals]


def load_gap_profile(path, kinds=()) -> GapProfile:
    """Read and validate a ``stripebench tune dp_gap`` profile; ``kinds`` are the hard-frame kinds it
    may name (:data:`bench.studies.hard_frames.KINDS`).

    Raises
    ------
    bench.config.ConfigError
        A missing or unknown key or a bad value, named in the message (one line).
    """
    data = _read_profile(path, GAP_TOP_KEYS | STRIPE_KEYS | GAP_OPTIONAL_KEYS | {CEILING_KEY})
    for key in sorted(GAP_TOP_KEYS):
        if key not in data:
            _fail(f"`profile` lacks the key {key!r}")
    c = GAP_CONSTRAINTS
    seed = require("seed", data["seed"], c["seed"])
    import trackers

    name = data["tracker"]
    if name not in trackers.available() or not {"off_rel", "switch_rows"} <= set(trackers.make(name).get_params()):
        _fail(f"`tracker` must name a tracker with off_rel and switch_rows parameters, got {name!r}")
    dps = data["dp_trackers"]
    if not isinstance(dps, list) or any(n not in trackers.available()
                                        or not {"k_sigma", "max_gap", "min_run"} <= set(trackers.make(n).get_params())
                                        for n in dps):
        _fail(f"`dp_trackers` must list trackers with k_sigma, max_gap and min_run parameters, got {dps!r}")
    off = _grid(data, "off_rel", c["off_rel"])
    quantiles = None
    if "level_quantile" in data:
        if "level_quantile" not in trackers.make(name).get_params():
            _fail(f"`level_quantile` needs a tracker with a level_quantile parameter, got {name!r}")
        quantiles = _grid(data, "level_quantile", c["level_quantile"])
    sw = _grid(data, "switch_rows", c["switch_rows"])
    for key in ("hit_px", "tie"):
        require(key, data[key], c[key])
    seeds = data["seeds"]
    if not isinstance(seeds, list) or not all(accepts(c["seeds"], x) for x in seeds):
        _fail(f"`seeds` must be a list of {describe(c['seeds'], plural=True)}, got {seeds!r}")
    ks = data["kinds"]
    if not isinstance(ks, list) or not all(accepts(Choice(tuple(kinds)), k) for k in ks):
        _fail(f"`kinds` must be a list of {', '.join(kinds)}, got {ks!r}")
    require("real", data["real"], c["real"])
    render, exps = _render_experiments(data)
    return GapProfile(str(data["name"]), seed, name, off, sw, float(data["hit_px"]), float(data["tie"]), render, exps,
                      [int(x) for x in seeds], list(ks), data["real"], list(dps), _grid(data, "k_sigma", c["k_sigma"]),
                      _none_int_grid(data, "max_gap", c["max_gap"]), _int_grid(data, "min_run", c["min_run"]),
                      *stripe_stage(data), max_false_rate=false_ceiling(data), level_quantile=quantiles)


# ---------------------------------------------------------------------------------------------------- threshold

THRESHOLD_TOP_KEYS = {"name", "seeds", "kinds", "real", "hit_px", "tie", "tie_px", "trackers", "k_sigma",
                      "prominence", "min_run", "width_ratio", "frac", "colour_trackers", "colour_rules", "steger_k_sigma",
                      "steger_prominence", "steger_min_run", "seed", "render", "renders"}
#: The numbers and switches of a ``tune threshold`` profile (of a list: each value; ``width_ratio`` also
#: ``"none"``; each of ``colour_rules`` a knee or one of :data:`COLOUR_RULE_NAMES`).
THRESHOLD_CONSTRAINTS = {"seeds": Int(low=0), "seed": Int(low=0), "real": Bool(), "hit_px": Real(low=0, finite=False),
                         "tie": Real(low=0, finite=False), "tie_px": Real(low=0, finite=False), "k_sigma": Real(low=0),
                         "prominence": Real(low=0), "min_run": Int(low=1), "width_ratio": Real(low=1.0),
                         "frac": Real(low=0, high=0.99), "colour_rules": Real(low=0, high=1),
                         "steger_k_sigma": Real(low=0), "steger_prominence": Real(low=0), "steger_min_run": Int(low=1)}
#: The named rules ``colour_rules`` may list besides knees (:mod:`bench.evaluate.colour`).
COLOUR_RULE_NAMES = Choice(("excess", "laser"))


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
    stripe_trackers: list[str] = field(default_factory=list)
    stripe_tests: list = field(default_factory=list)
    max_false_rate: float | None = None


def false_ceiling(data) -> float | None:
    """A profile's false-report ceiling (``max_false_rate``, a share in [0, 1]; None where the profile has none):
    a setting under which a tracker reports on more of the photographs' stripe-less rows is not eligible where
    another keeps every tracker within it (:meth:`bench.studies.tuning.Tally.eligible`).

    Examples
    --------
    >>> false_ceiling({"max_false_rate": 0.1}), false_ceiling({})
    (0.1, None)
    """
    if CEILING_KEY not in data:
        return None
    return float(require(CEILING_KEY, data[CEILING_KEY], Real(low=0, high=1)))


def stripe_stage(data) -> tuple[list[str], list]:
    """The stripe question's stage of a profile: ``(stripe_trackers, stripe_tests)``, both empty where the
    profile has neither key (no such stage). ``stripe_tests`` come back as None (not asked) or dicts of
    :class:`trackers.StripeTest` settings (a tracker's ``stripe_test`` parameter; ``"none"`` read as None).

    Raises
    ------
    bench.config.ConfigError
        One key without the other, a tracker without a ``stripe_test`` parameter, a candidate that is not
        ``"none"`` or a table of valid settings, or a repeated candidate (one line).

    Examples
    --------
    >>> stripe_stage({"stripe_trackers": ["dp4"], "stripe_tests": ["none", {}, {"colour_min": "none"}]})
    (['dp4'], [None, {}, {'colour_min': None}])
    """
    have = STRIPE_KEYS & set(data)
    if not have:
        return [], []
    if have != STRIPE_KEYS:
        _fail(f"`{sorted(STRIPE_KEYS - have)[0]}` must be given with `{sorted(have)[0]}`")
    import trackers
    from trackers._stripe import as_test

    names = data["stripe_trackers"]
    known = set(trackers.available(unlisted=True)) - {"external"}  # `external` needs its command
    if (not isinstance(names, list) or not names or not all(isinstance(n, str) and n in known for n in names)
            or any("stripe_test" not in trackers.make(n).get_params() for n in names)):
        _fail(f"`stripe_trackers` must list trackers with a stripe_test parameter, got {names!r}")
    if len(set(names)) != len(names):
        _fail(f"`stripe_trackers` must not repeat a tracker (the question is chosen for each), got {names!r}")
    tests = data["stripe_tests"]
    if not isinstance(tests, list) or not tests:
        _fail(f"`stripe_tests` must be a non-empty list of 'none' or tables of stripe-question settings, "
              f"got {tests!r}")
    out = []
    for i, t in enumerate(tests):
        if t == NONE:
            out.append(None)
            continue
        if not isinstance(t, dict):
            _fail(f"`stripe_tests[{i}]` must be 'none' or a table of stripe-question settings, got {t!r}")
        value = {k: (None if v == NONE else v) for k, v in t.items()}
        try:
            as_test(value)
        except ValueError as exc:
            _fail(f"`stripe_tests[{i}]`: {exc}")
        out.append(value)
    keys = [None if t is None else as_test(t) for t in out]
    if len(set(keys)) != len(keys):
        _fail(f"`stripe_tests` must not repeat a candidate, got {tests!r}")
    return list(names), out


def _int_grid(data, key, constraint: Int):
    """A grid of distinct integers ``constraint`` accepts."""
    return _grid(data, key, constraint, int)


def _none_grid(data, key, constraint: Real | Int, cast, what: str):
    """A grid of values ``constraint`` accepts (each passed through ``cast``) or ``"none"`` (None: no
    limit), distinct; ``what`` names the values in the message."""
    vals = data[key]
    if (not isinstance(vals, list) or not vals or len(set(map(str, vals))) != len(vals)
            or not all(v == NONE or accepts(constraint, v) for v in vals)):
        _fail(f"`{key}` must list distinct {what} or 'none', got {vals!r}")
    return [None if v == NONE else cast(v) for v in vals]


def _none_int_grid(data, key, constraint: Int):
    """A grid of integers ``constraint`` accepts or ``"none"`` (None: no limit), distinct."""
    return _none_grid(data, key, constraint, int, describe(constraint, plural=True))


def _none_real_grid(data, key, constraint: Real):
    """A grid of finite numbers ``constraint`` accepts or ``"none"`` (None: no limit), distinct."""
    # worded "numbers", not describe()'s "finite numbers": the message as it was
    return _none_grid(data, key, constraint, float, f"numbers >= {constraint.low}")


def _render_experiments(data, keys=GAP_RENDER_KEYS, exp_key="experiments", allow_empty=False):
    """The ``[render]`` table (exactly ``keys``) and the experiments of ``exp_key``, validated."""
    from scenes import MAX_SIZE

    render = data["render"]
    if not isinstance(render, dict) or set(render) != set(keys):
        _fail(f"`render` must have exactly the keys {sorted(keys)}, got {render!r}")
    for k, v in render.items():
        require(f"render.{k}", v, Int(low=1, high=MAX_SIZE[k]))
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
    data = _read_profile(path, THRESHOLD_TOP_KEYS | STRIPE_KEYS | {CEILING_KEY})
    missing = sorted(THRESHOLD_TOP_KEYS - set(data))
    if missing:
        raise ConfigError(f"`profile` lacks the key(s) {missing}")
    c = THRESHOLD_CONSTRAINTS
    seeds = data["seeds"]
    if not isinstance(seeds, list) or not seeds or not all(accepts(c["seeds"], s) for s in seeds):
        raise ConfigError(f"`seeds` must be a non-empty list of {describe(c['seeds'], plural=True)}, got {seeds!r}")
    seed = require("seed", data["seed"], c["seed"])
    allowed = tuple(kinds)
    kinds = data["kinds"]
    if not isinstance(kinds, list) or not kinds or not all(accepts(Choice(allowed), k) for k in kinds):
        raise ConfigError(f"`kinds` must be a non-empty list of {', '.join(allowed)}, got {kinds!r}")
    require("real", data["real"], c["real"])
    for key in ("hit_px", "tie", "tie_px"):
        require(key, data[key], c[key])
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
            or not all(accepts(COLOUR_RULE_NAMES, r) or accepts(c["colour_rules"], r) for r in rules)):
        raise ConfigError(f"`colour_rules` must list distinct knees in [0, 1], 'excess' or 'laser', got {rules!r}")
    render, renders = _render_experiments(data, exp_key="renders", allow_empty=True)
    return TuneThresholdProfile(
        str(data["name"]), [int(s) for s in seeds], list(kinds), data["real"], float(data["hit_px"]),
        float(data["tie"]), float(data["tie_px"]), list(data["trackers"]), _grid(data, "k_sigma", c["k_sigma"]),
        _grid(data, "prominence", c["prominence"]), _int_grid(data, "min_run", c["min_run"]),
        _none_real_grid(data, "width_ratio", c["width_ratio"]), _grid(data, "frac", c["frac"]),
        list(data["colour_trackers"]), [r if isinstance(r, str) else float(r) for r in rules],
        _grid(data, "steger_k_sigma", c["steger_k_sigma"]), _grid(data, "steger_prominence", c["steger_prominence"]),
        _int_grid(data, "steger_min_run", c["steger_min_run"]), seed, render, renders, *stripe_stage(data),
        max_false_rate=false_ceiling(data))
