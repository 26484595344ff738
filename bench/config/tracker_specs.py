"""Tracker settings of a configuration: :class:`TrackerSpec`, its labels, and the ``trackers`` list's two forms.

A setting is a registered tracker ``name`` built with ``params`` and reported as
``label``; in TOML it is a plain name or a table ``{label, name, params}``
(optionally with ``restore``, ``timeout_s`` and ``isolate``); on the command line
(``--trackers``) a comma-separated list of either. Every value is checked: the
parameters by the tracker itself (:meth:`trackers.Tracker.validate_params`, with
its ``parameter_constraints``), the setting's own keys with the same constraint
types (:mod:`bench.config.checks`). TOML has no null: a parameter given as
``"none"`` is None (:data:`bench.config.checks.NONE`, :func:`with_nulls`).
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field, replace
from typing import Any

from bench.config.checks import NONE, Bool, Choice, Real, accepts, require
from bench.errors import ConfigError

__all__ = ["TrackerSpec", "LABEL_CHARS", "parse_trackers", "parse_trackers_arg", "TIMEOUT", "with_nulls"]


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
#: A setting's ``timeout_s``: seconds in (0, 86400] (a day).
TIMEOUT = Real(low=0, low_open=True, high=86400)


def with_nulls(params: dict, constraints: dict) -> dict:
    """``params`` with :data:`bench.config.checks.NONE` read as None: a value ``"none"``, and ``"none"`` among a
    table's values (the stripe question's settings), unless the parameter's constraint (``constraints``: name -> a
    :mod:`trackers` constraint) accepts the value as given.

    Examples
    --------
    >>> from trackers import Choice, Real
    >>> with_nulls({"width_ratio": "none", "stripe_test": {"colour_min": "none", "level_min": 0.15}, "mode": "none"},
    ...            {"width_ratio": Real(low=1, optional=True), "mode": Choice(frozenset({"none", "all"}))})
    {'width_ratio': None, 'stripe_test': {'colour_min': None, 'level_min': 0.15}, 'mode': 'none'}
    """
    def null(v):
        if isinstance(v, str) and v == NONE:
            return None
        if isinstance(v, dict):
            return {k: null(x) for k, x in v.items()}
        return v

    out = {}
    for k, v in params.items():
        c = constraints.get(k)
        out[k] = v if c is not None and accepts(c, v) else null(v)
    return out


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

            require(f"{path}.restore", restore, Choice(METHODS))
        timeout_s = value.get("timeout_s")
        if timeout_s is not None:
            require(f"{path}.timeout_s", timeout_s, TIMEOUT, "a number of seconds in (0, 86400]")
        isolate = require(f"{path}.isolate", value.get("isolate", False), Bool())
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
    if spec.params:
        import trackers

        try:  # the constraints of its parameters, where its defaults build
            constraints = getattr(trackers.make(spec.name), "parameter_constraints", {})
        except Exception:  # noqa: BLE001 - a tracker that needs parameters: the check below names the problem
            constraints = {}
        spec = replace(spec, params=with_nulls(spec.params, constraints))
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

