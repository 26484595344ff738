"""The run configuration's schema: its keys, defaults, comments and limits, and :func:`parse`.

A configuration is a TOML document::

    name = "paper"            # free text, names the run
    seed = 0                  # one seed for renders, noise, samples and bootstrap
    trackers = []             # tracker names or settings; empty = every registered tracker
                              # (a setting: {label = "dp4_iso", name = "dp4", params = {h_weight = 1.0}},
                              # optionally with its own restore = "none" overriding the run's `restore`)
    baselines = ["threshold", "centroid"]   # labels of the trackers "without DP"
    dp = ["dp4", "dp8"]       # labels of the DP trackers compared with them
    n_samples = 150           # sample points per experiment (the paper's 150)
    n_boot = 2000             # bootstrap resamples for the confidence intervals
    restore = "rows"          # how missed rows are filled before sampling: "rows" or "none" (bench.evaluate.restore)
    real_set = ""             # also evaluate the trackers on photographs: "shipped" or a folder (sim-to-real)
    real_predict = false      # with real_set: also predict their figures on those photographs (`run --predict`)
    render_ahead = true       # a helper process renders later frames into the render cache meanwhile
                              # (bench.run.renderahead; results are the same either way)
    llvm_target = ""          # the LLVM target of the renders: "" (Dr.Jit's native choice), "portable"
                              # (x86-64-v3, 8 lanes: the same frames on every such CPU; the ci profile's),
                              # "native" or CPU/WIDTH[/FEATURES]; $STRIPEBENCH_LLVM_TARGET overrides it

    [render]                  # shared by every experiment
    width = 512
    height = 480
    spp = "auto"              # samples per pixel of the laser pass(es): an integer, or "auto": each
    ambient_spp = "auto"      # material's counts chosen by `stripebench perf sampling` (scenes.sampling)

    [[experiments]]           # one scan each
    name = "cone-paper"       # optional identifier (default: scene-material plus overrides)
    condition = "paper"       # optional group in reports (the first condition leads the report)
    scene = "cone"
    material = "patchy"
    n_angles = 40             # or: angles = [-3.0, -2.5, ...] (deg)
    ambient_lux = 400.0       # optional per-experiment scene overrides:
    laser_power_mw = 3.0      # ambient_lux, laser_power_mw, line_fwhm_mrad, ...
    support = "table"         # background ("wall"/"none"), background_distance_cm, background_albedo,
                              # support ("none"/"table"), support_albedo

Every key is checked: an unknown key, a wrong type or an invalid value raises
:class:`~bench.errors.ConfigError` with one line naming the key and echoing the value. The
full reference, with a complete example, is ``docs/config.md``.

The schema has one home: the defaults are those of :class:`Config`'s fields,
the top-level keys are its fields, the numbers' and switches' limits are
:data:`CONSTRAINTS` and :data:`EXPERIMENT_CONSTRAINTS` (the trackers' constraint
types, :mod:`bench.config.checks`), the scene overrides are the scene parameters
(:data:`scenes.params.DEFAULTS`) minus those the harness owns (:data:`HARNESS_KEYS`),
with the extra bounds of :data:`bench.config.limits.SCENE_BOUNDS`. Tracker settings
are :mod:`bench.config.tracker_specs`; reading files and the embedded profiles,
:mod:`bench.config.loading`.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass, field, fields, replace
from typing import Any

from bench.config.checks import Bool, Choice, Int, Real, accepts, describe, require
from bench.config.limits import check_real_set, check_scene, estimate_memory_bytes, memory_limit_bytes
from bench.config.tracker_specs import LABEL_CHARS, TrackerSpec, parse_trackers
from bench.errors import ConfigError
from bench.evaluate.outcomes import N_SAMPLES
from bench.evaluate.restore import METHODS

__all__ = ["Config", "Experiment", "parse", "RENDER_KEYS", "HARNESS_KEYS", "EXECUTION_KEYS", "OPTIONAL_KEYS",
           "scene_override_keys", "MAX_ANGLE_DEG", "MAX_N_SAMPLES", "MIN_N_BOOT", "MAX_N_BOOT", "CONSTRAINTS",
           "EXPERIMENT_CONSTRAINTS"]

RENDER_KEYS = ("width", "height", "spp", "ambient_spp")  # the `[render]` table, shared by every experiment
# scene parameters the harness sets itself (not per-experiment overrides)
HARNESS_KEYS = ("material", *RENDER_KEYS, "seed", "n_angles", "cache", "cache_dir")
MAX_ANGLE_DEG = 45.0  # |mirror angle|: beyond it the camera turns more than 90 deg
MAX_N_SAMPLES = 10**6  # `n_samples`: 1 .. this
MIN_N_BOOT, MAX_N_BOOT = 10, 10**6  # `n_boot` (runs and real runs)
#: The top-level numbers, switches and choices, in the trackers' constraint types (:mod:`bench.config.checks`).
CONSTRAINTS = {
    "seed": Int(low=0),
    "n_samples": Int(low=1, high=MAX_N_SAMPLES),
    "n_boot": Int(low=MIN_N_BOOT, high=MAX_N_BOOT),
    "restore": Choice(METHODS),
    "render_ahead": Bool(),
    "real_predict": Bool(),
}
#: An experiment's numbers (its ``n_angles`` also at most :data:`scenes.params.MAX_SIZE`; each of its
#: ``angles`` a mirror angle within +-:data:`MAX_ANGLE_DEG`; ``[render]`` sizes are integers >= 1 within
#: :data:`scenes.params.MAX_SIZE`, ``spp`` and ``ambient_spp`` also ``"auto"``).
EXPERIMENT_CONSTRAINTS = {
    "n_angles": Int(low=2),
    "angle": Real(low=-MAX_ANGLE_DEG, high=MAX_ANGLE_DEG),
    "render": Int(low=1),
}


def scene_override_keys() -> tuple[str, ...]:
    """The per-experiment scene overrides: :data:`scenes.params.DEFAULTS` minus :data:`HARNESS_KEYS`."""
    from scenes import DEFAULTS

    return tuple(sorted(set(DEFAULTS) - set(HARNESS_KEYS)))


@dataclass(frozen=True)
class Experiment:
    """One scan: a scene, a material, angles and scene-parameter overrides."""

    scene: str
    material: str = "matte"
    n_angles: int | None = None
    angles: tuple[float, ...] | None = None
    overrides: dict[str, Any] = field(default_factory=dict)
    name: str | None = None
    condition: str = ""

    @property
    def key(self) -> str:
        """A file-name-safe identifier: ``name``, or ``scene-material`` plus any overrides."""
        if self.name:
            return self.name
        extra = "".join(f"_{k}={v}" for k, v in sorted(self.overrides.items()))
        return f"{self.scene}-{self.material}{extra}".replace("/", "_").replace(" ", "")


@dataclass(frozen=True)
class Config:
    """A validated experiment configuration (see the module docstring)."""

    name: str = "custom"
    seed: int = 0
    trackers: tuple[str, ...] = ()  # the labels of ``tracker_specs``; empty = every registered tracker
    baselines: tuple[str, ...] = ("threshold", "centroid")
    dp: tuple[str, ...] = ("dp4", "dp8")
    n_samples: int = N_SAMPLES
    n_boot: int = 2000
    render: dict[str, int] = field(default_factory=dict)
    experiments: tuple[Experiment, ...] = ()
    source: str = "<dict>"
    restore: str = "rows"
    real_set: str = ""  # "" none, "shipped" (bench/data/real) or a folder: the sim-to-real comparison
    # with a real set, also predict its figures (bench.run.real.predict_real; `run --predict`): part of the identity,
    # written only when set (OPTIONAL_KEYS)
    real_predict: bool = False
    tracker_specs: tuple[TrackerSpec, ...] = ()
    # a helper process renders frames ahead into the render cache while the run tracks (bench.run.renderahead);
    # how a run executes, not what it computes: not part of the run's identity (:meth:`identity`)
    render_ahead: bool = True
    # the LLVM target the renders ask for (scenes.variant.request_llvm_target); $STRIPEBENCH_LLVM_TARGET overrides
    # it. Part of the identity (it may change the frames), written only when set (OPTIONAL_KEYS)
    llvm_target: str = ""

    def make_trackers(self) -> dict:
        """label -> a new tracker of each setting, in configuration order (plain trackers:
        :func:`bench.run.track.build_trackers` adds ``timeout_s`` and ``isolate``)."""
        return {s.label: s.make() for s in self.tracker_specs}

    def restore_by_label(self) -> dict[str, str]:
        """label -> how that setting's missed rows are restored: its own ``restore``, else the run's.

        Examples
        --------
        >>> cfg = parse({"trackers": ["threshold", {"label": "gaps", "name": "threshold", "restore": "none"}],
        ...              "baselines": [], "dp": [], "experiments": [{"scene": "plane", "n_angles": 2}]})
        >>> cfg.restore_by_label()
        {'threshold': 'rows', 'gaps': 'none'}
        """
        return {s.label: s.restore or self.restore for s in self.tracker_specs}

    def to_dict(self) -> dict[str, Any]:
        """A JSON/TOML-friendly dict that :func:`parse` reads back unchanged.

        Keys of :data:`EXECUTION_KEYS` appear only when they differ from their
        defaults, so that a default configuration's dict (and the hash naming
        its run folder) stays what it was before they existed.
        """
        exps = []
        for e in self.experiments:
            d = {"scene": e.scene, "material": e.material, **e.overrides}
            if e.name:
                d["name"] = e.name
            if e.condition:
                d["condition"] = e.condition
            if e.n_angles is not None:
                d["n_angles"] = e.n_angles
            if e.angles is not None:
                d["angles"] = list(e.angles)
            exps.append(d)
        out = {"name": self.name, "seed": self.seed, "trackers": [s.to_value() for s in self.tracker_specs],
               "baselines": list(self.baselines), "dp": list(self.dp), "n_samples": self.n_samples,
               "n_boot": self.n_boot, "restore": self.restore, "real_set": self.real_set, "render": dict(self.render),
               "experiments": exps}
        for k in (*EXECUTION_KEYS, *OPTIONAL_KEYS):
            if getattr(self, k) != _default(k):
                out[k] = getattr(self, k)
        return out

    def identity(self) -> dict[str, Any]:
        """:meth:`to_dict` without :data:`EXECUTION_KEYS`: what a run computes, which names and
        guards its run folder (a run with ``render_ahead = false`` resumes one made with it on)."""
        return {k: v for k, v in self.to_dict().items() if k not in EXECUTION_KEYS}


_NOT_KEYS = {"source", "tracker_specs"}
EXECUTION_KEYS = ("render_ahead",)  # how a run executes, never what it computes (see Config.identity)
OPTIONAL_KEYS = ("llvm_target", "real_predict")  # written by Config.to_dict only when set, so that older hashes stay
_TOP = {f.name for f in fields(Config)} - _NOT_KEYS
_EXP_KEYS = {f.name for f in fields(Experiment)} - {"overrides"}


def _default(name: str):
    f = next(f for f in fields(Config) if f.name == name)
    value = f.default_factory() if f.default_factory is not field().default_factory else f.default
    return list(value) if isinstance(value, tuple) else value


def _int(path: str, value, constraint: Int) -> int:
    """``value`` as an int within ``constraint``'s lower bound (its upper one: :func:`_at_most`)."""
    return int(require(path, value, replace(constraint, high=None)))


def _at_most(path: str, value: int, constraint: Int) -> None:
    """Check an integer already within ``constraint``'s lower bound against its upper one."""
    if not accepts(constraint, value):
        raise ConfigError(f"`{path}` must be at most {constraint.high}, got {value!r}")


def _names(path: str, value) -> tuple[str, ...]:
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise ConfigError(f"`{path}` must be a list of names, got {value!r}")
    if len(set(value)) != len(value):
        raise ConfigError(f"`{path}` repeats a name: {value!r}")
    return tuple(value)


def _unknown(path: str, d: dict, allowed: set[str]) -> None:
    extra = sorted(set(d) - allowed)
    if extra:
        key = f"{path}.{extra[0]}" if path else extra[0]
        raise ConfigError(f"unknown key `{key}` (valid: {', '.join(sorted(allowed))})")


def parse(data: dict[str, Any], source: str = "<dict>", *, machine: bool = True) -> Config:
    """Validate a configuration dict (as read from TOML) into a :class:`Config`.

    ``machine=False`` skips the checks that depend on this machine (that a
    ``real_set`` folder exists here, that a scan fits in this machine's memory) and
    those that build things (each experiment's scene, each tracker): for a
    configuration saved by a run that already passed them (the report reads a run
    made elsewhere, and needs neither).

    The keys are checked in the order of the module docstring's example; the
    first problem raises.

    Raises
    ------
    ConfigError
        One line naming the key and echoing the value.
    """
    if not isinstance(data, dict):
        raise ConfigError(f"a configuration must be a table, got {type(data).__name__}")
    if "sweep" in data:
        raise ConfigError("this configuration has a `[sweep]` table: run it with `stripebench sweep CONFIG --out DIR`")
    _unknown("", data, _TOP)
    name = data.get("name", _default("name"))
    if not isinstance(name, str) or not name:
        raise ConfigError(f"`name` must be a non-empty string, got {name!r}")
    seed = _int("seed", data.get("seed", _default("seed")), CONSTRAINTS["seed"])
    specs = parse_trackers(data.get("trackers", []), build=machine)
    baselines, dp = _groups(data, tuple(s.label for s in specs))
    n_samples, n_boot = _counts(data)
    restore = require("restore", data.get("restore", _default("restore")), CONSTRAINTS["restore"])
    real_set = data.get("real_set", _default("real_set"))
    if machine:
        real_set = check_real_set(real_set)
    elif not isinstance(real_set, str):  # a saved configuration: its set was checked where it ran
        raise ConfigError(f"`real_set` must be \"\", \"shipped\" or a folder, got {real_set!r}")
    render_ahead = require("render_ahead", data.get("render_ahead", _default("render_ahead")),
                           CONSTRAINTS["render_ahead"])
    llvm_target = _llvm_target(data.get("llvm_target", _default("llvm_target")))
    real_predict = require("real_predict", data.get("real_predict", _default("real_predict")),
                           CONSTRAINTS["real_predict"])
    render = _render(data.get("render", _default("render")))
    exps = _experiments(data.get("experiments"), render, machine)
    if machine:
        _check_memory(exps, render, len(specs))
    return Config(name, seed, tuple(s.label for s in specs), baselines, dp, n_samples, n_boot, render, exps, source,
                  restore=restore, real_set=real_set, tracker_specs=specs, render_ahead=render_ahead,
                  llvm_target=llvm_target, real_predict=real_predict)


def _groups(data: dict, labels: tuple[str, ...]) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """``baselines`` and ``dp``: lists of distinct labels among the trackers'."""
    baselines = _names("baselines", data.get("baselines", _default("baselines")))
    dp = _names("dp", data.get("dp", _default("dp")))
    for group, members in (("baselines", baselines), ("dp", dp)):
        for m in members:
            if m not in labels:
                raise ConfigError(f"`{group}` names {m!r}, which is not among `trackers` {list(labels)}")
    return baselines, dp


def _counts(data: dict) -> tuple[int, int]:
    """``n_samples`` and ``n_boot`` (both lower bounds are checked before either upper one)."""
    counts = {k: _int(k, data.get(k, _default(k)), CONSTRAINTS[k]) for k in ("n_samples", "n_boot")}
    for k, value in counts.items():
        _at_most(k, value, CONSTRAINTS[k])
    return counts["n_samples"], counts["n_boot"]


def _llvm_target(value) -> str:
    """``llvm_target``: a string :func:`scenes.variant.parse_llvm_target` reads."""
    if not isinstance(value, str):
        raise ConfigError(f"`llvm_target` must be a string, got {value!r:.60}")
    from scenes.variant import parse_llvm_target

    try:
        parse_llvm_target(value)
    except ValueError:
        raise ConfigError(f"`llvm_target` must be \"\", \"portable\", \"native\" or CPU/WIDTH[/FEATURES] with WIDTH a "
                          f"power of two in 1..64, got {value!r:.60}") from None
    return value


def _render(table) -> dict:
    """The ``[render]`` table: integers >= 1 within the scenes' limits, ``spp`` and ``ambient_spp`` also ``"auto"``
    (every type and lower bound is checked before any upper one)."""
    if not isinstance(table, dict):
        raise ConfigError(f"`render` must be a table, got {table!r}")
    _unknown("render", table, set(RENDER_KEYS))
    from scenes import MAX_SIZE
    from scenes.sampling import AUTO

    size = EXPERIMENT_CONSTRAINTS["render"]
    render = {}
    for k, v in table.items():
        if k in ("spp", "ambient_spp"):
            render[k] = v if v == AUTO else int(require(f"render.{k}", v, size, f"{describe(size)} or \"{AUTO}\""))
        else:
            render[k] = _int(f"render.{k}", v, size)
    for k, v in render.items():
        if v != AUTO:
            _at_most(f"render.{k}", v, replace(size, high=MAX_SIZE[k]))
    return render


def _experiments(value, render: dict, machine: bool) -> tuple[Experiment, ...]:
    """The ``[[experiments]]``: a non-empty list of tables with distinct keys (:attr:`Experiment.key`)."""
    import scenes

    if not isinstance(value, list) or not value:
        raise ConfigError(f"`experiments` must be a non-empty list of tables, got {value!r}")
    scene_names, overridable = scenes.available(), set(scene_override_keys())
    exps = tuple(_experiment(f"experiments[{i}]", e, scene_names, overridable, render, machine)
                 for i, e in enumerate(value))
    keys = [e.key for e in exps]
    dup = sorted({k for k in keys if keys.count(k) > 1})
    if dup:
        raise ConfigError(f"`experiments` lists {dup[0]!r} twice")
    return exps


def _experiment(path: str, e, scene_names: list[str], overridable: set[str], render: dict,
                machine: bool) -> Experiment:
    """One experiment table; with ``machine`` its scene is built (about 0.4 s), the scene's own checks."""
    import scenes
    from scenes import MAX_SIZE

    if not isinstance(e, dict):
        raise ConfigError(f"`{path}` must be a table, got {e!r}")
    _unknown(path, e, _EXP_KEYS | overridable)
    scene = require(f"{path}.scene", e.get("scene"), Choice(tuple(scene_names)), f"one of {', '.join(scene_names)}")
    material = require(f"{path}.material", e.get("material", "matte"), Choice(tuple(scenes.MATERIALS)),
                       f"one of {', '.join(scenes.MATERIALS)}")
    count = EXPERIMENT_CONSTRAINTS["n_angles"]
    n_angles = _int(f"{path}.n_angles", e["n_angles"], count) if "n_angles" in e else None
    if n_angles is not None:
        _at_most(f"{path}.n_angles", n_angles, replace(count, high=MAX_SIZE["n_angles"]))
    angles = None
    if "angles" in e:
        a = e["angles"]
        if (not isinstance(a, list) or len(a) < 2
                or not all(isinstance(x, numbers.Real) and not isinstance(x, bool) for x in a)):
            raise ConfigError(f"`{path}.angles` must be a list of at least 2 numbers (deg), got {a!r}")
        angles = tuple(float(x) for x in a)
        bad = next((x for x in angles if not accepts(EXPERIMENT_CONSTRAINTS["angle"], x)), None)
        if bad is not None:
            raise ConfigError(f"`{path}.angles` must be finite mirror angles within +-{MAX_ANGLE_DEG:g} deg, "
                              f"got {bad!r}")
        if len(angles) > MAX_SIZE["n_angles"]:
            raise ConfigError(f"`{path}.angles` must list at most {MAX_SIZE['n_angles']} angles, "
                              f"got {len(angles)}")
        if n_angles is not None:
            raise ConfigError(f"`{path}` gives both `n_angles` and `angles`; give one")
    overrides = {k: e[k] for k in sorted(overridable & set(e))}
    if machine:  # a saved configuration's scenes were built when it ran (about 0.4 s each)
        check_scene(path, scene, material, render, overrides)
    exp_name = e.get("name")
    if exp_name is not None and (not isinstance(exp_name, str) or not exp_name
                                 or not set(exp_name) <= LABEL_CHARS):
        raise ConfigError(f"`{path}.name` must be letters, digits, '_', '-' or '.', got {exp_name!r}")
    condition = e.get("condition", "")
    if not isinstance(condition, str):
        raise ConfigError(f"`{path}.condition` must be a string, got {condition!r}")
    return Experiment(scene, material, n_angles, angles, overrides, exp_name, condition)


def _check_memory(exps: tuple[Experiment, ...], render: dict, n_trackers: int) -> None:
    """Refuse an experiment whose scan needs more than :func:`~bench.config.limits.memory_limit_bytes`."""
    from scenes import DEFAULTS

    width = render.get("width", DEFAULTS["width"])
    height = render.get("height", DEFAULTS["height"])
    for i, e in enumerate(exps):
        frames = len(e.angles) if e.angles is not None else (e.n_angles or DEFAULTS["n_angles"])
        need = estimate_memory_bytes(frames, width, height, n_trackers)
        if need > memory_limit_bytes():
            raise ConfigError(f"`experiments[{i}]` needs about {need / 2**30:.1f} GiB of memory "
                              f"({frames} frames of {width}x{height}, {n_trackers} trackers), more than half of "
                              f"this machine's {2 * memory_limit_bytes() / 2**30:.0f} GiB")
