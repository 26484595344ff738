"""Experiment configurations: TOML files and the embedded profiles, validated.

A configuration is a TOML document::

    name = "paper"            # free text, names the run
    seed = 0                  # one seed for renders, noise, samples and bootstrap
    trackers = []             # tracker names or settings; empty = every registered tracker
                              # (a setting: {label = "dp4_iso", name = "dp4", params = {h_weight = 1.0}})
    baselines = ["threshold", "centroid"]   # labels of the trackers "without DP"
    dp = ["dp4", "dp8"]       # labels of the DP trackers compared with them
    n_samples = 150           # sample points per experiment (the paper's 150)
    n_boot = 2000             # bootstrap resamples for the confidence intervals
    restore = "rows"          # how missed rows are filled before sampling: "rows" or "none" (bench.restore)

    [render]                  # shared by every experiment
    width = 512
    height = 480
    spp = 16

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
:class:`ConfigError` with one line naming the key and echoing the value.
"""

from __future__ import annotations

import copy
import numbers
import tomllib
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

__all__ = ["ConfigError", "Config", "Experiment", "TrackerSpec", "parse_trackers", "parse_trackers_arg", "load",
           "read_toml", "parse", "profile", "with_overrides", "PROFILES", "SCENE_OVERRIDES"]

PROFILES = ("paper", "quick", "ci")
_TOP = {"name", "seed", "trackers", "baselines", "dp", "n_samples", "n_boot", "restore", "render", "experiments"}
_RENDER = {"width", "height", "spp", "ambient_spp"}
_SCENE_OVERRIDES = {"ambient_lux", "laser_power_mw", "line_fwhm_mrad", "laser_fan_deg", "ambient_illuminant",
                    "laser_wavelength_nm", "filter_center_nm", "filter_fwhm_nm", "filter_peak", "exposure_ms",
                    "f_number", "read_noise_e", "gain_e_per_dn", "background", "background_distance_cm",
                    "background_albedo", "support", "support_albedo"}
_EXPERIMENT = {"name", "condition", "scene", "material", "n_angles", "angles"} | _SCENE_OVERRIDES
SCENE_OVERRIDES = frozenset(_SCENE_OVERRIDES)  # the scene parameters an experiment (or a sweep) may set


class ConfigError(ValueError):
    """A configuration problem; ``str(err)`` is one line for the user."""


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

    def make(self):
        """A new tracker of this setting."""
        import trackers

        return trackers.make(self.name, **self.params)

    def to_value(self):
        """The configuration value: the bare name when it is a plain default setting."""
        if self.label == self.name and not self.params:
            return self.name
        return {"label": self.label, "name": self.name, "params": dict(self.params)}


_LABEL_CHARS = set("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-.")


def _tracker_spec(path: str, value, registered: list[str]) -> TrackerSpec:
    if isinstance(value, str):
        spec = TrackerSpec(value, value, {})
    elif isinstance(value, dict):
        extra = sorted(set(value) - {"label", "name", "params"})
        if extra:
            raise ConfigError(f"unknown key `{path}.{extra[0]}` (valid: label, name, params)")
        name = value.get("name")
        if not isinstance(name, str):
            raise ConfigError(f"`{path}.name` must be a tracker name, got {name!r}")
        label = value.get("label", name)
        params = value.get("params", {})
        if not isinstance(params, dict):
            raise ConfigError(f"`{path}.params` must be a table, got {params!r}")
        spec = TrackerSpec(label, name, dict(params))
    else:
        raise ConfigError(f"`{path}` must be a tracker name or a table {{label, name, params}}, got {value!r}")
    if not isinstance(spec.label, str) or not spec.label or not set(spec.label) <= _LABEL_CHARS:
        raise ConfigError(f"`{path}.label` must be letters, digits, '_', '-' or '.', got {spec.label!r}")
    if spec.name not in registered:
        raise ConfigError(f"`{path}` names unknown tracker {spec.name!r}; available: {', '.join(registered)}")
    try:
        tracker = spec.make()
    except TypeError:
        import trackers

        valid = ", ".join(trackers.make(spec.name).get_params())
        bad = sorted(spec.params)
        raise ConfigError(f"`{path}.params` has an unknown parameter of {spec.name!r} among {bad}; "
                          f"valid: {valid}") from None
    try:
        tracker._validate_params()
    except (TypeError, ValueError) as exc:
        raise ConfigError(f"`{path}.params`: {exc}") from None
    return spec


def parse_trackers(value, path: str = "trackers") -> tuple[TrackerSpec, ...]:
    """Validate a list of tracker names or settings; empty = every registered tracker.

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

    registered = trackers.available()
    if not isinstance(value, list):
        raise ConfigError(f"`{path}` must be a list of tracker names or settings, got {value!r}")
    if not value:
        return tuple(TrackerSpec(n, n, {}) for n in registered)
    specs = tuple(_tracker_spec(f"{path}[{i}]", v, registered) for i, v in enumerate(value))
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
            try:
                items.append(tomllib.loads(f"x = {part}")["x"])
            except tomllib.TOMLDecodeError as exc:
                raise ConfigError(f"{path}: {part!r} is not a TOML inline table: {exc}") from None
        else:
            items.append(part)
    if not items:
        raise ConfigError(f"{path} must name at least one tracker, got {text!r}")
    return parse_trackers(items, path)


@dataclass(frozen=True)
class Experiment:
    """One scan: a scene, a material, angles and scene-parameter overrides."""

    scene: str
    material: str
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

    name: str
    seed: int
    trackers: tuple[str, ...]  # the labels of ``tracker_specs``
    baselines: tuple[str, ...]
    dp: tuple[str, ...]
    n_samples: int
    n_boot: int
    render: dict[str, int]
    experiments: tuple[Experiment, ...]
    source: str = "<dict>"
    restore: str = "rows"
    tracker_specs: tuple[TrackerSpec, ...] = ()

    def make_trackers(self) -> dict:
        """label -> a new tracker of each setting, in configuration order."""
        return {s.label: s.make() for s in self.tracker_specs}

    def to_dict(self) -> dict[str, Any]:
        """A JSON/TOML-friendly dict that :func:`parse` reads back unchanged."""
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
        return {"name": self.name, "seed": self.seed, "trackers": [s.to_value() for s in self.tracker_specs],
                "baselines": list(self.baselines), "dp": list(self.dp), "n_samples": self.n_samples,
                "n_boot": self.n_boot, "restore": self.restore, "render": dict(self.render), "experiments": exps}


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


def parse(data: dict[str, Any], source: str = "<dict>") -> Config:
    """Validate a configuration dict (as read from TOML) into a :class:`Config`."""
    import scenes

    if not isinstance(data, dict):
        raise ConfigError(f"a configuration must be a table, got {type(data).__name__}")
    if "sweep" in data:
        raise ConfigError("this configuration has a `[sweep]` table: run it with `stripebench sweep CONFIG --out DIR`")
    _unknown("", data, _TOP)
    name = data.get("name", "custom")
    if not isinstance(name, str) or not name:
        raise ConfigError(f"`name` must be a non-empty string, got {name!r}")
    seed = _int("seed", data.get("seed", 0), 0)
    specs = parse_trackers(data.get("trackers", []))
    names = tuple(s.label for s in specs)
    baselines = _names("baselines", data.get("baselines", ["threshold", "centroid"]), None)
    dp = _names("dp", data.get("dp", ["dp4", "dp8"]), None)
    for group, members in (("baselines", baselines), ("dp", dp)):
        for m in members:
            if m not in names:
                raise ConfigError(f"`{group}` names {m!r}, which is not among `trackers` {list(names)}")
    n_samples = _int("n_samples", data.get("n_samples", 150), 1)
    n_boot = _int("n_boot", data.get("n_boot", 2000), 10)
    from .restore import METHODS

    restore = data.get("restore", "rows")
    if restore not in METHODS:
        raise ConfigError(f"`restore` must be one of {', '.join(map(repr, METHODS))}, got {restore!r}")
    render_in = data.get("render", {})
    if not isinstance(render_in, dict):
        raise ConfigError(f"`render` must be a table, got {render_in!r}")
    _unknown("render", render_in, _RENDER)
    render = {k: _int(f"render.{k}", v, 1) for k, v in render_in.items()}
    exps_in = data.get("experiments")
    if not isinstance(exps_in, list) or not exps_in:
        raise ConfigError(f"`experiments` must be a non-empty list of tables, got {exps_in!r}")
    exps = []
    scene_names = scenes.available()
    for i, e in enumerate(exps_in):
        path = f"experiments[{i}]"
        if not isinstance(e, dict):
            raise ConfigError(f"`{path}` must be a table, got {e!r}")
        _unknown(path, e, _EXPERIMENT)
        scene = e.get("scene")
        if scene not in scene_names:
            raise ConfigError(f"`{path}.scene` must be one of {', '.join(scene_names)}, got {scene!r}")
        material = e.get("material", "matte")
        if material not in scenes.MATERIALS:
            raise ConfigError(f"`{path}.material` must be one of {', '.join(scenes.MATERIALS)}, got {material!r}")
        n_angles = _int(f"{path}.n_angles", e["n_angles"], 2) if "n_angles" in e else None
        angles = None
        if "angles" in e:
            a = e["angles"]
            if (not isinstance(a, list) or len(a) < 2
                    or not all(isinstance(x, numbers.Real) and not isinstance(x, bool) for x in a)):
                raise ConfigError(f"`{path}.angles` must be a list of at least 2 numbers (deg), got {a!r}")
            angles = tuple(float(x) for x in a)
            if n_angles is not None:
                raise ConfigError(f"`{path}` gives both `n_angles` and `angles`; give one")
        overrides = {k: e[k] for k in sorted(_SCENE_OVERRIDES & set(e))}
        try:  # let the scene validate its own parameters
            scenes.make(scene, material=material, **render, **overrides)
        except (TypeError, KeyError, ValueError) as exc:
            msg = exc.args[0] if exc.args else str(exc)
            raise ConfigError(f"`{path}`: {msg}") from None
        exp_name = e.get("name")
        if exp_name is not None and (not isinstance(exp_name, str) or not exp_name
                                     or not set(exp_name) <= _LABEL_CHARS):
            raise ConfigError(f"`{path}.name` must be letters, digits, '_', '-' or '.', got {exp_name!r}")
        condition = e.get("condition", "")
        if not isinstance(condition, str):
            raise ConfigError(f"`{path}.condition` must be a string, got {condition!r}")
        exps.append(Experiment(scene, material, n_angles, angles, overrides, exp_name, condition))
    keys = [e.key for e in exps]
    dup = sorted({k for k in keys if keys.count(k) > 1})
    if dup:
        raise ConfigError(f"`experiments` lists {dup[0]!r} twice")
    return Config(name, seed, names, baselines, dp, n_samples, n_boot, render, tuple(exps), source, restore, specs)


def read_toml(path) -> dict[str, Any]:
    """The TOML document at ``path`` as a dict (:class:`ConfigError` if unreadable or invalid)."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except OSError as exc:
        raise ConfigError(f"cannot read configuration {str(p)!r}: {exc.strerror}") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{p}: invalid TOML: {exc}") from None


def load(path) -> Config:
    """Read and validate a TOML configuration file."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except OSError as exc:
        raise ConfigError(f"cannot read configuration {str(p)!r}: {exc.strerror}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{p}: invalid TOML: {exc}") from None
    return parse(data, source=str(p))


def profile(name: str) -> Config:
    """One of the embedded profiles: ``paper`` (the default experiment), ``quick``, ``ci``."""
    if name not in PROFILES:
        raise ConfigError(f"unknown profile {name!r}; available: {', '.join(PROFILES)}")
    text = resources.files("bench.profiles").joinpath(f"{name}.toml").read_text(encoding="utf-8")
    return parse(tomllib.loads(text), source=f"profile:{name}")


def with_overrides(config: Config, **changes) -> Config:
    """A copy with top-level fields replaced (e.g. ``seed``, ``trackers``), re-validated."""
    d = copy.deepcopy(config.to_dict())
    d.update({k: (list(v) if isinstance(v, tuple) else v) for k, v in changes.items()})
    return parse(d, source=config.source)
