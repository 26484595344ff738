"""Experiment configurations: TOML files and the embedded profiles, validated.

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
:class:`ConfigError` with one line naming the key and echoing the value. The
full reference, with a complete example, is ``docs/config.md``.

The schema has one home: the defaults are those of :class:`Config`'s fields,
the top-level keys are its fields, the scene overrides are the scene
parameters (:data:`scenes.params.DEFAULTS`) minus those the harness owns
(:data:`HARNESS_KEYS`), and the profile names are :data:`PROFILES`.
"""

from __future__ import annotations

import copy
import math
import numbers
import os
import tomllib
from dataclasses import dataclass, field, fields
from importlib import resources
from pathlib import Path
from typing import Any

from bench.errors import ConfigError, StripebenchError
from bench.evaluate.outcomes import N_SAMPLES

__all__ = ["ConfigError", "Config", "Experiment", "TrackerSpec", "parse_trackers", "parse_trackers_arg", "load",
           "read_toml", "parse", "profile", "with_overrides", "PROFILES", "HARNESS_KEYS", "RENDER_KEYS", "scene_override_keys",
           "SCENE_UPPER_BOUNDS", "EXECUTION_KEYS", "SCENE_LOWER_BOUNDS", "MAX_ANGLE_DEG", "estimate_memory_bytes",
           "scene_value_problem", "check_scene", "check_real_set", "memory_limit_bytes", "StripebenchError",
           "MAX_N_SAMPLES", "MAX_N_BOOT", "MIN_N_BOOT"]

PROFILES = ("paper", "quick", "ci", "marble", "field")
RENDER_KEYS = ("width", "height", "spp", "ambient_spp")  # the `[render]` table, shared by every experiment
# scene parameters the harness sets itself (not per-experiment overrides)
HARNESS_KEYS = ("material", *RENDER_KEYS, "seed", "n_angles", "cache", "cache_dir")
# per-experiment overrides with an upper bound beyond the scene's own checks (the sensor's
# Poisson noise overflows above these: "lam value too large")
SCENE_UPPER_BOUNDS = {"laser_power_mw": 1e5, "ambient_lux": 1e6, "exposure_ms": 1e4}
# and lower bounds (a faster lens also overflows it; a thinner sheet needs a laser-profile table beyond memory)
SCENE_LOWER_BOUNDS = {"f_number": 0.5, "line_fwhm_mrad": 1e-3}
MAX_ANGLE_DEG = 45.0  # |mirror angle|: beyond it the camera turns more than 90 deg
MAX_N_SAMPLES = 10**6  # `n_samples`: 1 .. this
MIN_N_BOOT, MAX_N_BOOT = 10, 10**6  # `n_boot` (runs and real runs)


def scene_value_problem(key: str, value) -> str | None:
    """What is wrong with a scene override beyond the scene's own checks
    (:data:`SCENE_UPPER_BOUNDS`, :data:`SCENE_LOWER_BOUNDS`), or None. The one
    check that experiments and ``[sweep]`` values share.

    Examples
    --------
    >>> scene_value_problem("ambient_lux", 1e7)
    'must be at most 1e+06'
    >>> scene_value_problem("ambient_lux", 400.0) is None
    True
    """
    if not isinstance(value, numbers.Real) or isinstance(value, bool):
        return None  # the scene names a wrong type
    top = SCENE_UPPER_BOUNDS.get(key)
    if top is not None and value > top:
        return f"must be at most {top:g}"
    low = SCENE_LOWER_BOUNDS.get(key)
    if low is not None and value < low:
        return f"must be at least {low:g}"
    return None


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


def scene_override_keys() -> tuple[str, ...]:
    """The per-experiment scene overrides: :data:`scenes.params.DEFAULTS` minus :data:`HARNESS_KEYS`."""
    from scenes.params import DEFAULTS

    return tuple(sorted(set(DEFAULTS) - set(HARNESS_KEYS)))


@dataclass(frozen=True)
class TrackerSpec:
    """One tracker setting: a registered ``name`` built with ``params``, reported as ``label``.

    Labels are what tables, figures, checkpoints, ``baselines`` and ``dp`` refer
    to; a plain name in a configuration is the setting ``label = name`` with the
    tracker's defaults.
    """

    label: str
    name: str
    params: dict[str, Any] = field(default_factory=dict)
    # how this setting's missed rows are restored (one of bench.evaluate.restore.METHODS);
    # None: the run's ``restore``
    restore: str | None = None
    #: seconds one frame may take; a slower frame fails with status ``timeout`` (None: no limit)
    timeout_s: float | None = None
    #: run the tracker in its own worker process: a hang, segfault or exit fails its frames, not the run
    isolate: bool = False

    def make(self):
        """A new tracker of this setting (run it through :func:`bench.run.track.build_trackers`
        to honour ``timeout_s`` and ``isolate``)."""
        import trackers

        return trackers.make(self.name, **self.params)

    def to_value(self):
        """The configuration value: the bare name when it is a plain default setting
        (``restore``, ``timeout_s`` and ``isolate`` appear only when the setting carries them)."""
        if (self.label == self.name and not self.params and self.restore is None and self.timeout_s is None
                and not self.isolate):
            return self.name
        out = {"label": self.label, "name": self.name, "params": dict(self.params)}
        if self.restore is not None:
            out["restore"] = self.restore
        if self.timeout_s is not None:
            out["timeout_s"] = self.timeout_s
        if self.isolate:
            out["isolate"] = True
        return out


#: The characters of a tracker label or an experiment name (they name files and columns).
LABEL_CHARS = frozenset("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-.")


def _tracker_spec(path: str, value, registered: list[str], build: bool = True) -> TrackerSpec:
    if isinstance(value, str):
        spec = TrackerSpec(value, value, {})
    elif isinstance(value, dict):
        extra = sorted(set(value) - {"label", "name", "params", "restore", "timeout_s", "isolate"})
        if extra:
            raise ConfigError(f"unknown key `{path}.{extra[0]}` (valid: label, name, params, restore, timeout_s, "
                              f"isolate)")
        name = value.get("name")
        if not isinstance(name, str):
            raise ConfigError(f"`{path}.name` must be a tracker name, got {name!r}")
        label = value.get("label", name)
        params = value.get("params", {})
        if not isinstance(params, dict):
            raise ConfigError(f"`{path}.params` must be a table, got {params!r}")
        restore = value.get("restore")
        if restore is not None:
            from bench.evaluate.restore import METHODS

            if restore not in METHODS:
                raise ConfigError(f"`{path}.restore` must be one of {', '.join(map(repr, METHODS))}, got {restore!r}")
        timeout_s = value.get("timeout_s")
        if timeout_s is not None and (not isinstance(timeout_s, numbers.Real) or isinstance(timeout_s, bool)
                                      or not 0 < timeout_s <= 86400):
            raise ConfigError(f"`{path}.timeout_s` must be a number of seconds in (0, 86400], got {timeout_s!r}")
        isolate = value.get("isolate", False)
        if not isinstance(isolate, bool):
            raise ConfigError(f"`{path}.isolate` must be true or false, got {isolate!r}")
        spec = TrackerSpec(label, name, dict(params), restore, None if timeout_s is None else float(timeout_s),
                           isolate)
    else:
        raise ConfigError(f"`{path}` must be a tracker name or a table {{label, name, params}}, got {value!r}")
    if not isinstance(spec.label, str) or not spec.label or not set(spec.label) <= LABEL_CHARS:
        raise ConfigError(f"`{path}.label` must be letters, digits, '_', '-' or '.', got {spec.label!r}")
    if spec.name not in registered:
        raise ConfigError(f"`{path}` names unknown tracker {spec.name!r}; available: {', '.join(registered)}")
    if not build:  # a saved configuration: its trackers were built and checked when it ran
        return spec
    try:
        tracker = spec.make()
    except TypeError:
        import trackers

        valid = ", ".join(trackers.make(spec.name).get_params())
        bad = sorted(spec.params)
        raise ConfigError(f"`{path}.params` has an unknown parameter of {spec.name!r} among {bad}; "
                          f"valid: {valid}") from None
    try:
        tracker.validate_params()
    except (TypeError, ValueError) as exc:
        raise ConfigError(f"`{path}.params`: {exc}") from None
    return spec


def parse_trackers(value, path: str = "trackers", *, build: bool = True) -> tuple[TrackerSpec, ...]:
    """Validate a list of tracker names or settings; empty = every registered tracker.

    ``build=False`` checks the settings' shape and names but does not build the trackers
    (their modules are not imported: for a saved configuration, see :func:`parse`).

    Raises
    ------
    ConfigError
        Not a list, an unknown tracker or parameter, a bad value, a bad or repeated label.

    Examples
    --------
    >>> [s.label for s in parse_trackers(["threshold", {"label": "dp4_iso", "name": "dp4",
    ...                                                 "params": {"eps": 1.0}}])]
    ['threshold', 'dp4_iso']
    """
    import trackers

    registered = trackers.available(unlisted=True)  # `external` too, which needs its `command`
    if not isinstance(value, list):
        raise ConfigError(f"`{path}` must be a list of tracker names or settings, got {value!r}")
    if not value:
        return tuple(TrackerSpec(n, n, {}) for n in trackers.available())
    specs = tuple(_tracker_spec(f"{path}[{i}]", v, registered, build) for i, v in enumerate(value))
    labels = [s.label for s in specs]
    dup = sorted({lab for lab in labels if labels.count(lab) > 1})
    if dup:
        raise ConfigError(f"`{path}` repeats the label {dup[0]!r}")
    return specs


def _split_top(text: str) -> list[str]:
    parts, depth, cur = [], 0, []
    for ch in text:
        if ch in "{[":
            depth += 1
        elif ch in "}]":
            depth -= 1
        if ch == "," and depth == 0:
            parts.append("".join(cur))
            cur = []
        else:
            cur.append(ch)
    parts.append("".join(cur))
    return [p.strip() for p in parts if p.strip()]


def parse_trackers_arg(text: str, path: str = "--trackers") -> tuple[TrackerSpec, ...]:
    """The command-line form of :func:`parse_trackers`: comma-separated names or
    TOML inline tables, e.g. ``threshold,{label="dp4_iso",name="dp4",params={h_weight=1.0}}``.

    Examples
    --------
    >>> [s.label for s in parse_trackers_arg('threshold, {label="d", name="dp4"}')]
    ['threshold', 'd']
    """
    items = []
    for part in _split_top(text):
        if part.startswith("{"):
            from bench.store.textfiles import check_structure

            try:
                items.append(check_structure(tomllib.loads(f"x = {part}")["x"], path, error=ConfigError))
            except tomllib.TOMLDecodeError as exc:
                raise ConfigError(f"{path}: {part!r} is not a TOML inline table: {exc}") from None
            except (RecursionError, ValueError):
                raise ConfigError(f"{path}: {part[:40]!r}... is nested too deeply or holds a huge integer") from None
        else:
            items.append(part)
    if not items:
        raise ConfigError(f"{path} must name at least one tracker, got {text!r}")
    return parse_trackers(items, path)


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
OPTIONAL_KEYS = ("llvm_target",)  # written by Config.to_dict only when set, so that older hashes stay
_TOP = {f.name for f in fields(Config)} - _NOT_KEYS
_EXP_KEYS = {f.name for f in fields(Experiment)} - {"overrides"}


def _default(name: str):
    f = next(f for f in fields(Config) if f.name == name)
    value = f.default_factory() if f.default_factory is not field().default_factory else f.default
    return list(value) if isinstance(value, tuple) else value


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


def _where(path: str) -> str:
    return f"`{path}`"


def _int(path: str, value, low: int) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < low:
        raise ConfigError(f"{_where(path)} must be an integer >= {low}, got {value!r}")
    return int(value)


def _names(path: str, value, allowed: list[str] | None) -> tuple[str, ...]:
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise ConfigError(f"{_where(path)} must be a list of names, got {value!r}")
    if allowed is not None:
        for v in value:
            if v not in allowed:
                raise ConfigError(f"{_where(path)} names unknown tracker {v!r}; available: {', '.join(allowed)}")
    if len(set(value)) != len(value):
        raise ConfigError(f"{_where(path)} repeats a name: {value!r}")
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
    made elsewhere, and needs neither)."""
    import scenes

    if not isinstance(data, dict):
        raise ConfigError(f"a configuration must be a table, got {type(data).__name__}")
    if "sweep" in data:
        raise ConfigError("this configuration has a `[sweep]` table: run it with `stripebench sweep CONFIG --out DIR`")
    _unknown("", data, _TOP)
    name = data.get("name", _default("name"))
    if not isinstance(name, str) or not name:
        raise ConfigError(f"`name` must be a non-empty string, got {name!r}")
    seed = _int("seed", data.get("seed", _default("seed")), 0)
    specs = parse_trackers(data.get("trackers", []), build=machine)
    names = tuple(s.label for s in specs)
    baselines = _names("baselines", data.get("baselines", _default("baselines")), None)
    dp = _names("dp", data.get("dp", _default("dp")), None)
    for group, members in (("baselines", baselines), ("dp", dp)):
        for m in members:
            if m not in names:
                raise ConfigError(f"`{group}` names {m!r}, which is not among `trackers` {list(names)}")
    n_samples = _int("n_samples", data.get("n_samples", _default("n_samples")), 1)
    n_boot = _int("n_boot", data.get("n_boot", _default("n_boot")), MIN_N_BOOT)
    for key, value, top in (("n_samples", n_samples, MAX_N_SAMPLES), ("n_boot", n_boot, MAX_N_BOOT)):
        if value > top:
            raise ConfigError(f"`{key}` must be at most {top}, got {value!r}")
    from bench.evaluate.restore import METHODS

    restore = data.get("restore", _default("restore"))
    if restore not in METHODS:
        raise ConfigError(f"`restore` must be one of {', '.join(map(repr, METHODS))}, got {restore!r}")
    real_set = data.get("real_set", _default("real_set"))
    if machine:
        real_set = check_real_set(real_set)
    elif not isinstance(real_set, str):  # a saved configuration: its set was checked where it ran
        raise ConfigError(f"`real_set` must be \"\", \"shipped\" or a folder, got {real_set!r}")
    render_ahead = data.get("render_ahead", _default("render_ahead"))
    if not isinstance(render_ahead, bool):
        raise ConfigError(f"`render_ahead` must be true or false, got {render_ahead!r}")
    llvm_target = data.get("llvm_target", _default("llvm_target"))
    if not isinstance(llvm_target, str):
        raise ConfigError(f"`llvm_target` must be a string, got {llvm_target!r:.60}")
    from scenes.variant import parse_llvm_target

    try:
        parse_llvm_target(llvm_target)
    except ValueError:
        raise ConfigError(f"`llvm_target` must be \"\", \"portable\", \"native\" or CPU/WIDTH[/FEATURES] with WIDTH a "
                          f"power of two in 1..64, got {llvm_target!r:.60}") from None
    render_in = data.get("render", _default("render"))
    if not isinstance(render_in, dict):
        raise ConfigError(f"`render` must be a table, got {render_in!r}")
    _unknown("render", render_in, set(RENDER_KEYS))
    from scenes.params import DEFAULTS as SCENE_DEFAULTS, MAX_SIZE
    from scenes.sampling import AUTO

    render = {}
    for k, v in render_in.items():
        if k in ("spp", "ambient_spp") and v == AUTO:
            render[k] = v
        elif k in ("spp", "ambient_spp") and (isinstance(v, bool) or not isinstance(v, numbers.Integral) or v < 1):
            raise ConfigError(f"{_where(f'render.{k}')} must be an integer >= 1 or \"{AUTO}\", got {v!r}")
        else:
            render[k] = _int(f"render.{k}", v, 1)
    for k, v in render.items():
        if v != AUTO and v > MAX_SIZE[k]:
            raise ConfigError(f"`render.{k}` must be at most {MAX_SIZE[k]}, got {v!r}")
    overridable = set(scene_override_keys())
    exps_in = data.get("experiments")
    if not isinstance(exps_in, list) or not exps_in:
        raise ConfigError(f"`experiments` must be a non-empty list of tables, got {exps_in!r}")
    exps = []
    scene_names = scenes.available()
    for i, e in enumerate(exps_in):
        path = f"experiments[{i}]"
        if not isinstance(e, dict):
            raise ConfigError(f"`{path}` must be a table, got {e!r}")
        _unknown(path, e, _EXP_KEYS | overridable)
        scene = e.get("scene")
        if scene not in scene_names:
            raise ConfigError(f"`{path}.scene` must be one of {', '.join(scene_names)}, got {scene!r}")
        material = e.get("material", "matte")
        if material not in scenes.MATERIALS:
            raise ConfigError(f"`{path}.material` must be one of {', '.join(scenes.MATERIALS)}, got {material!r}")
        n_angles = _int(f"{path}.n_angles", e["n_angles"], 2) if "n_angles" in e else None
        if n_angles is not None and n_angles > MAX_SIZE["n_angles"]:
            raise ConfigError(f"`{path}.n_angles` must be at most {MAX_SIZE['n_angles']}, got {n_angles!r}")
        angles = None
        if "angles" in e:
            a = e["angles"]
            if (not isinstance(a, list) or len(a) < 2
                    or not all(isinstance(x, numbers.Real) and not isinstance(x, bool) for x in a)):
                raise ConfigError(f"`{path}.angles` must be a list of at least 2 numbers (deg), got {a!r}")
            angles = tuple(float(x) for x in a)
            bad = next((x for x in angles if not math.isfinite(x) or abs(x) > MAX_ANGLE_DEG), None)
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
        exps.append(Experiment(scene, material, n_angles, angles, overrides, exp_name, condition))
    keys = [e.key for e in exps]
    dup = sorted({k for k in keys if keys.count(k) > 1})
    if dup:
        raise ConfigError(f"`experiments` lists {dup[0]!r} twice")
    width = render.get("width", SCENE_DEFAULTS["width"])
    height = render.get("height", SCENE_DEFAULTS["height"])
    for i, e in enumerate(exps):
        frames = len(e.angles) if e.angles is not None else (e.n_angles or SCENE_DEFAULTS["n_angles"])
        need = estimate_memory_bytes(frames, width, height, len(specs))
        if machine and need > memory_limit_bytes():
            raise ConfigError(f"`experiments[{i}]` needs about {need / 2**30:.1f} GiB of memory "
                              f"({frames} frames of {width}x{height}, {len(specs)} trackers), more than half of "
                              f"this machine's {2 * memory_limit_bytes() / 2**30:.0f} GiB")
    return Config(name, seed, names, baselines, dp, n_samples, n_boot, render, tuple(exps), source,
                  restore=restore, real_set=real_set, tracker_specs=specs, render_ahead=render_ahead,
                  llvm_target=llvm_target)


def read_toml(path, what: str = "configuration") -> dict[str, Any]:
    """The TOML document at ``path`` as a dict.

    Only a regular file is read, as UTF-8, at most
    :data:`bench.store.textfiles.MAX_DEPTH` levels deep with 64-bit integers
    (:mod:`bench.store.textfiles`).

    Raises
    ------
    ConfigError
        Missing, unreadable, not a regular file (a FIFO is refused without
        waiting), not UTF-8, invalid TOML, nested too deeply, a huge integer.
    """
    from bench.store.textfiles import read_toml_file

    return read_toml_file(path, what, error=ConfigError)


def load(path) -> Config:
    """Read and validate a TOML configuration file."""
    return parse(read_toml(path), source=str(Path(path)))


def profile(name: str) -> Config:
    """One of the embedded profiles: ``paper`` (the default experiment), ``quick``, ``ci``."""
    if not isinstance(name, str) or name not in PROFILES:
        raise ConfigError(f"unknown profile {name!r}; available: {', '.join(PROFILES)}")
    text = resources.files("bench.config.profiles").joinpath(f"{name}.toml").read_text(encoding="utf-8")
    return parse(tomllib.loads(text), source=f"profile:{name}")


def with_overrides(config: Config, **changes) -> Config:
    """A copy with top-level fields replaced (e.g. ``seed``, ``trackers``), re-validated."""
    d = copy.deepcopy(config.to_dict())
    d.update({k: (list(v) if isinstance(v, tuple) else v) for k, v in changes.items()})
    return parse(d, source=config.source)
