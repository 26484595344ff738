"""The notebook API: evaluate one tracker on a profile, load a saved run.

Two functions for a Python session (a notebook, a script) instead of the
``stripebench`` command line; both write and read the same run folders as
``stripebench run``:

- :func:`evaluate` runs a profile's configuration with one tracker (an
  instance, a registered name or a settings dict) and returns its metrics table;
- :func:`load_run` reads a finished run's tables back (:class:`RunTables`).

This is the ``api`` layer (the top but one: it may use ``run``, ``report``,
``store`` and ``config``). It is *not* ``bench.evaluate``, which is the pure
evaluation layer (metrics and statistics on arrays); see ``docs/api.md``.

Every expected failure raises a :class:`bench.errors.StripebenchError`
subclass whose message is one line (a bad argument or configuration key:
:class:`bench.errors.ConfigError`; an unusable run folder:
``bench.store.files.RunFolderError``).
"""

from __future__ import annotations

import contextlib
import os
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

from bench import config as _config
from bench.errors import ConfigError

__all__ = ["evaluate", "load_run", "RunTables", "OVERRIDE_KEYS"]

#: configuration keys :func:`evaluate` accepts as ``**overrides`` (``trackers``, ``baselines`` and
#: ``dp`` are set by the call: the one tracker, no baselines, no DP group)
OVERRIDE_KEYS = tuple(sorted(f.name for f in fields(_config.Config)
                             if f.name not in ("trackers", "baselines", "dp", "source", "tracker_specs")))


@dataclass(frozen=True)
class RunTables:
    """The tables of one finished run folder (what :func:`load_run` returns).

    Attributes
    ----------
    path : Path
        The run folder.
    metrics : pandas.DataFrame
        One row per experiment x tracker x region. Keys: ``experiment``, ``scene``,
        ``material``, ``condition``, ``tracker`` (the label), ``region`` (``"all"``: every
        row; ``"object"``: the object's stripe rows, every other row unknown, so its
        detection figures that a false report moves are NaN,
        :data:`bench.evaluate.tables.OBJECT_BLIND`). Pixel errors against the truth
        (px, detected lit rows): ``px_mae``, ``px_rmse``, ``px_p95``; depth errors on the
        restored surface (mm): ``depth_mae_mm``, ``depth_rmse_mm``, ``depth_p95_mm``;
        fractions in [0, 1]: ``coverage``, ``hit_rate`` (within 3 px,
        :data:`bench.evaluate.metrics.HIT_PX`), ``false_lock_rate``, ``outlier_rate``,
        ``filled_fraction``, ``false_detections`` (reports among the rows with no stripe);
        the row outcomes and detection figures (docs/detection.md); counts: ``n_rows``, ``n_lit``,
        ``n_detected``, ``failed_frames``, ``frames``; timing: ``ms_per_frame`` (wall
        ms per frame on the machine that ran it). NaN where a value is undefined
        (no lit rows in the region).
    samples : pandas.DataFrame
        The sample points of the paper's statistics, one row each: ``experiment``,
        ``scene``, ``material``, ``sample``, ``frame``, ``row``, ``mirror_angle_deg``,
        ``true_depth_cm``, then per tracker label ``error_mm_<label>`` (depth error, mm)
        and ``filled_<label>`` (the row was restored, not detected). Empty (with these
        columns) when no lit object row was scanned.
    summary : dict
        ``summary.json``: the configuration (``config``), the seed, versions, the
        improvement statistics (``improvement``), robust summaries (``robust``),
        verdicts, per-scan timings (``scans``), wall time (``wall_s``) and more.
    """

    path: Path
    metrics: Any
    samples: Any
    summary: dict


def load_run(path) -> RunTables:
    """The tables of the finished run folder at ``path``.

    Parameters
    ----------
    path : path-like
        A folder written by :func:`evaluate`, ``stripebench run`` or ``stripebench score``.

    Returns
    -------
    RunTables
        ``metrics``, ``samples`` and ``summary`` (columns documented on :class:`RunTables`).

    Raises
    ------
    bench.store.files.RunFolderError
        Not a folder, not a finished run, or an unreadable summary, metrics or samples file.
    ConfigError
        ``path`` is not a path.
    """
    from bench.store.runfolder import load_run as _load

    if not isinstance(path, (str, os.PathLike)):
        raise ConfigError(f"`path` must be a run folder path, got {path!r}")
    r = _load(path)
    return RunTables(Path(path), r["metrics"], r["samples"], r["summary"])


def _spec_value(tracker, label: str | None):
    """(the ``trackers`` entry of the configuration, the class to register for the call or None)."""
    import trackers as _trackers
    from trackers import Tracker

    if isinstance(tracker, Tracker):
        cls = type(tracker)
        params = tracker.get_params()
        name = cls.name
        if name and name in _trackers.available(unlisted=True) and type(_trackers.make(name)) is cls:
            return {"label": label or name, "name": name, "params": params}, None
        lab = label or name or cls.__name__.lower()
        if lab in _trackers.available(unlisted=True):
            raise ConfigError(f"`label` {lab!r} is a registered tracker of another class; pass label= another name "
                              f"for this {cls.__name__}")
        return {"label": lab, "name": lab, "params": params}, (lab, cls)
    if isinstance(tracker, str):
        return (tracker if label is None else {"label": label, "name": tracker}), None
    if isinstance(tracker, dict):
        return (dict(tracker) if label is None else {**tracker, "label": label}), None
    raise ConfigError(f"`tracker` must be a trackers.Tracker, a registered name or a settings dict "
                      f"{{label, name, params}}, got {tracker!r}")


@contextlib.contextmanager
def _registered(entry):
    """Register ``(label, class)`` for the duration of the block (nothing when ``entry`` is None)."""
    if entry is None:
        yield
        return
    import trackers as _trackers

    label, cls = entry
    _trackers.register(label, cls)
    try:
        yield
    finally:
        _trackers.unregister(label)


def _own_class_dir(cfg, cls) -> Path:
    """The default folder of a run of an unregistered class: the configuration's hash with the
    class's source text in it (a class edited in a notebook cell has no module file for the run
    folder's code fingerprint to see, so an edit must change the folder)."""
    import inspect

    from bench.store.files import config_hash
    from bench.store.runfolder import named_run_dir

    try:
        source = inspect.getsource(cls)
    except (OSError, TypeError):  # no source to be had (defined by exec): the fingerprint is what there is
        source = None
    return named_run_dir(cfg.name, config_hash({"config": cfg.identity(), "class_source": source}))


def _configuration(profile, spec, overrides: dict):
    if isinstance(profile, _config.Config):
        base = profile
    elif isinstance(profile, os.PathLike) or (isinstance(profile, str) and profile.endswith(".toml")):
        base = _config.load(profile)
    elif isinstance(profile, str):
        base = _config.profile(profile)
    else:
        raise ConfigError(f"`profile` must be a profile name ({', '.join(_config.PROFILES)}), a TOML path or a "
                          f"bench.config.Config, got {profile!r}")
    bad = sorted(set(overrides) - set(OVERRIDE_KEYS))
    if bad:
        raise ConfigError(f"evaluate() got an unknown configuration key {bad[0]!r} (valid: {', '.join(OVERRIDE_KEYS)})")
    d = base.to_dict()
    changes = dict(overrides)
    if isinstance(changes.get("render"), dict):  # render sizes are merged over the profile's
        changes["render"] = {**d["render"], **changes["render"]}
    d.update(changes)
    d.update(trackers=[spec], baselines=[], dp=[])
    return _config.parse(d, source=base.source)


def evaluate(tracker, profile="quick", *, label: str | None = None, out=None, force: bool = False,
             quiet: bool = True, **overrides):
    """Run ``profile``'s experiments with one tracker; its metrics table.

    The run is an ordinary run folder (the same files as ``stripebench run``; build
    its page with ``stripebench report``): ``out``, else
    ``<runs root>/<profile name>-<hash>`` (:func:`bench.store.runfolder.default_run_dir`;
    the runs root is ``$STRIPEBENCH_RUNS`` or ``./results/runs``). A finished or
    partial run of the same configuration there is reused or resumed.

    Parameters
    ----------
    tracker : trackers.Tracker, str or dict
        A tracker instance (built with its current parameters; a class that is not
        registered is registered under ``label`` for the call only and is run in
        this process, and its default run folder's name includes a hash of the
        class's source when :func:`inspect.getsource` finds it), a registered name (``"dp4"``), or a settings dict as in a
        configuration's ``trackers`` list (``{"label": ..., "name": ..., "params": {...}}``,
        optionally ``restore``, ``timeout_s``, ``isolate``).
    profile : str, path-like or bench.config.Config
        An embedded profile (``"quick"``, ``"ci"``, ``"paper"``, ...), a TOML
        configuration file, or a configuration. Its ``trackers`` are replaced by
        ``tracker`` and its ``baselines`` and ``dp`` emptied (so the summary has no
        improvement ratios).
    label : str, optional
        The tracker's label in the tables (default: its name).
    out : path-like, optional
        The run folder.
    force : bool
        Clear an ``out`` that holds another configuration's run instead of refusing.
    quiet : bool
        No progress notes on stderr (damaged or stale files are always reported).
    **overrides
        Configuration keys (:data:`OVERRIDE_KEYS`: ``seed``, ``n_samples``, ``n_boot``,
        ``render``, ``experiments``, ``restore``, ``name``, ``real_set``, ...), validated by
        :func:`bench.config.parse` as for any run. ``render`` is merged over the
        profile's (``render={"width": 64, "height": 60}`` keeps its ``spp``); the
        others replace the profile's value.

    Returns
    -------
    pandas.DataFrame
        The run's metrics, one row per experiment x region (``"all"``, ``"object"``),
        columns as :attr:`RunTables.metrics`; ``df.attrs["run_dir"]`` is the run
        folder (read everything with :func:`load_run`).

    Raises
    ------
    ConfigError
        A bad ``tracker``, ``profile`` or ``label``, an unknown or invalid configuration key.
    bench.store.files.RunFolderError
        The run folder is locked, holds another configuration's run (without ``force``),
        or cannot be written.
    """
    from bench.run import experiment

    if label is not None and not isinstance(label, str):
        raise ConfigError(f"`label` must be a string, got {label!r}")
    if out is not None and not isinstance(out, (str, os.PathLike)):
        raise ConfigError(f"`out` must be a path (str or path-like), got {out!r:.60}")
    for name, flag in (("force", force), ("quiet", quiet)):
        if not isinstance(flag, bool):
            raise ConfigError(f"`{name}` must be True or False, got {flag!r:.60}")
    spec, entry = _spec_value(tracker, label)
    with _registered(entry):
        cfg = _configuration(profile, spec, overrides)
        if out is None and entry is not None:
            out = _own_class_dir(cfg, entry[1])
        folder = experiment.run(cfg, out, progress=False, quiet=quiet, force=force)
    tables = load_run(folder)
    metrics = tables.metrics.reset_index(drop=True)
    metrics.attrs["run_dir"] = str(folder)
    return metrics
