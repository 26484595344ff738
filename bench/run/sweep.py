"""Robustness sweeps: every experiment over a grid of scene parameters, on Dask.

A sweep configuration is an ordinary configuration (:mod:`bench.config`) with a
``[sweep]`` table (its schema, limits and validation: :mod:`bench.config.sweep`)::

    [sweep]
    ambient_lux = [0, 100, 400, 1000, 2000]   # any scene override key, a list of values
    laser_power_mw = [1.0, 3.0, 10.0]
    repeats = 3                                # independent noise/sample draws per point

The grid is the product of the lists (in the order the keys are written),
applied to every ``[[experiments]]`` entry; a swept value replaces the
experiment's own override of that key. Keys: every scene override an experiment
accepts (:func:`bench.config.scene_override_keys`) and ``material``.

**Units of work.** Keys that change the cached unit renders (``material``,
``line_fwhm_mrad``, ``laser_fan_deg``; :data:`scenes.params.RENDER_KEYS`) split an
experiment into render batches; every other key only rescales the cached renders
or changes the sensor. One unit is one render batch (all its mirror angles)
followed by all the grid points that reuse it (or a ``chunk`` of them): scale,
sensor noise, every tracker, metrics. A unit is a pure function of its
specification (:func:`run_unit`) and returns a small table, so workers need no
shared disk (each keeps its own render cache).

**Repeats.** Repeat ``r`` of a grid point uses the same Mitsuba renders (the
configuration's ``seed`` fixes their Monte Carlo noise) and varies

* the sensor noise (shot and read noise of the laser-on image and of the
  laser-off background): ``Scene.render(..., noise_draw=r)``; repeat 0 is the draw
  of an ordinary ``stripebench run``;
* the 150-point sample draw: seeded ``SeedSequence([seed, k])`` for repeat 0 (as
  in a run; ``k`` is the experiment's index) and ``SeedSequence([seed, k, r])``
  otherwise.

The interval over repeats is therefore the spread due to sensor noise and
sampling at one fixed render; render noise (spp) is not resampled.

**Results** in the sweep folder (its files: :mod:`bench.store.sweepfiles`; a run
folder of kind ``sweep``, locked and claimed for the configuration and the grid
like every run folder, :class:`bench.store.runfolder.RunFolder`):
``sweep.parquet`` / ``sweep.csv`` (one row per experiment x grid point x repeat x
tracker label), ``summary.json``, ``report.html`` (curves), ``config.json`` and
``units/<fingerprint>.json``, the finished units with their checksums (a rerun
skips them: resume; a damaged or edited one is said in one line and recomputed).
"""

from __future__ import annotations

import json
import os
import socket
import sys
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np

from bench.config import Config, ConfigError, StripebenchError
from bench.config.sweep import Sweep, load, parse_sweep, sweep_keys  # noqa: F401  (the [sweep] table's schema)
from bench.store.files import config_hash
from bench.evaluate.curves import PAPER_POINT  # noqa: F401  (re-exported: the paper's operating point)

__all__ = ["Sweep", "SweepError", "parse_sweep", "load", "plan", "run_unit", "run_sweep", "default_sweep_dir",
           "load_sweep", "sweep_keys", "PAPER_POINT"]



class SweepError(StripebenchError, RuntimeError):
    """A sweep could not run (scheduler unreachable, workers with other code, timeout): one line."""


def default_sweep_dir(config: Config, sweep: Sweep) -> Path:
    """``<runs root>/<safe name>-sweep-<hash of the configuration and the sweep>``, always inside the runs root
    (the name keeps ``[A-Za-z0-9_.-]``, :func:`bench.store.runfolder.safe_dir_name`)."""
    from bench.store.runfolder import named_run_dir

    return named_run_dir(config.name, f"sweep-{config_hash([config.to_dict(), sweep.to_dict()])}")


# -- planning ------------------------------------------------------------------------------------------------------

def _rerender_keys() -> frozenset:
    """Scene keys that change the cached unit renders (:data:`scenes.params.RENDER_KEYS`, a scene notion:
    not the ``[render]`` table's :data:`bench.config.RENDER_KEYS`)."""
    from scenes import RENDER_KEYS as RERENDER_KEYS

    return frozenset(RERENDER_KEYS)


def plan(config: Config, sweep: Sweep, *, chunk: int | None = None) -> list[dict[str, Any]]:
    """The units of a sweep: JSON-friendly specifications for :func:`run_unit`.

    One unit per experiment x combination of the swept render keys x ``chunk``
    grid points (default: all the grid points of that render batch).
    """
    import scenes

    from bench.run.plan import angles_for

    if chunk is not None and (isinstance(chunk, bool) or not isinstance(chunk, int) or chunk < 1):
        raise ValueError(f"`chunk` must be an integer >= 1, got {chunk!r}")
    render_keys = _rerender_keys()
    points = sweep.points()
    units = []
    for k, e in enumerate(config.experiments):
        scene = scenes.make(e.scene, material=e.material, **config.render, **e.overrides)
        angles = [float(a) for a in angles_for(e, scene)]
        batches: dict[str, list] = {}
        for i, p in enumerate(points):
            rk = {key: v for key, v in p.items() if key in render_keys}
            batches.setdefault(json.dumps(rk, sort_keys=True), []).append({"index": i, "values": p})
        for rk_json, pts in batches.items():
            size = chunk or len(pts)
            for c in range(0, len(pts), size):
                spec = {
                    "experiment_index": k, "experiment_key": e.key, "scene": e.scene, "material": e.material,
                    "overrides": dict(e.overrides), "render_overrides": json.loads(rk_json),
                    "render": dict(config.render), "seed": config.seed, "angles": angles,
                    "points": pts[c:c + size], "repeats": sweep.repeats, "n_samples": config.n_samples,
                    "restore": config.restore,
                    "trackers": [s.to_value() for s in config.tracker_specs], "swept": list(sweep.keys),
                }
                units.append(spec)
    return units


def _fingerprint(spec: dict, source: str) -> str:
    return config_hash({"unit": spec, "source": source})


# -- one unit (runs on a worker) -----------------------------------------------------------------------------------

def run_unit(spec: dict[str, Any]) -> dict[str, Any]:
    """Render one batch and evaluate every grid point and repeat of ``spec`` on it.

    Pure: the same specification (and code) gives the same rows on any machine.

    Parameters
    ----------
    spec : dict
        One entry of :func:`plan`.

    Returns
    -------
    dict with ``rows`` (list of dict: one per grid point x repeat x tracker, see
    the module docstring), ``render_s`` (the render batch, s), ``first_render_s``
    (its first frame: with a cold cache that includes loading the Mitsuba scene
    and JIT compilation, s), ``setup_s`` (making
    and compiling the trackers, first-call imports, s), ``eval_s`` (every grid
    point and repeat: scaling, sensor, trackers, metrics, s), ``frames`` (renders
    in the batch), ``evaluations`` (frames x points x repeats), ``source`` (the
    worker's :func:`bench.store.provenance.source_fingerprint`), ``host``, ``pid``.
    """
    import scenes

    from bench.evaluate import tables as analysis
    from bench.config import Experiment, parse_trackers
    from bench.run.camera_view import frame_colour, tracker_images
    from bench.run.track import build_trackers, track_frame
    from bench.store.checkpoint import ScanResult
    from bench.store.provenance import source_fingerprint
    from bench.evaluate.stats import robust_summary

    t0 = time.perf_counter()
    base = {**spec["overrides"], **spec["render_overrides"]}
    material = base.pop("material", spec["material"])
    seed, render, angles = spec["seed"], spec["render"], np.asarray(spec["angles"], float)
    batch = scenes.make(spec["scene"], material=material, seed=seed, **render, **base)
    spp = batch.params["spp"]
    first_render_s = float("nan")
    for i, a in enumerate(angles):  # the render batch: fills this worker's render cache
        batch.render(float(a), spp=spp, seed=seed)
        if i == 0:
            first_render_s = time.perf_counter() - t0
    render_s = time.perf_counter() - t0

    t1 = time.perf_counter()
    specs = parse_trackers(spec["trackers"])
    trackers_ = build_trackers(specs)
    names = list(trackers_)
    H, W = batch.rig.height, batch.rig.width
    blank = np.zeros((H, W), np.uint8)
    for t in trackers_.values():  # compile (numba) outside the loop
        track_frame(t, blank, blank)
    robust_summary([0.0])  # first-call imports (SciPy) outside the timed loop
    setup_s = time.perf_counter() - t1
    t1 = time.perf_counter()
    k = spec["experiment_index"]
    rows = []
    scale_keys = [key for key in spec["swept"] if key != "material"]
    for point in spec["points"]:
        values = {key: v for key, v in point["values"].items() if key not in spec["render_overrides"]}
        scene = scenes.make(spec["scene"], material=material, seed=seed, **render, **{**base, **values})
        exp = Experiment(spec["scene"], material, None, tuple(angles), {})
        for r in range(spec["repeats"]):
            res = ScanResult.empty(spec["experiment_key"], angles, H, names)
            for i, a in enumerate(angles):
                frame = scene.render(float(a), spp=spp, seed=seed, noise_draw=r)
                res.truth_columns[i] = frame.truth.columns
                res.truth_points_cm[i] = frame.truth.points_cm
                res.on_object[i] = frame.truth.on_object
                image, background = tracker_images(frame, scene.params)
                colour = frame_colour(frame, scene.params)
                for n in names:
                    tr = track_frame(trackers_[n], image, background, colour)
                    res.columns[n][i], res.scores[n][i] = tr.columns, tr.score
                    res.seconds[n][i], res.status[n][i], res.messages[n][i] = tr.seconds, tr.status, tr.message
            res.done[:] = True
            restore = {s.label: s.restore or spec["restore"] for s in specs}  # a setting's own, else the run's
            obj = {d["tracker"]: d for d in analysis.scan_records(res, scene.rig, exp, object_only=True,
                                                                  restore=restore)}
            allr = {d["tracker"]: d for d in analysis.scan_records(res, scene.rig, exp, object_only=False,
                                                                   restore=restore)}
            words = [seed, k] if r == 0 else [seed, k, r]
            sample_seed = int(np.random.SeedSequence(words).generate_state(1)[0])
            samples = analysis.sample_table(res, scene.rig, exp, spec["n_samples"], sample_seed, restore=restore)
            for n in names:
                rs = robust_summary([s[f"error_mm_{n}"] for s in samples])
                o, a_ = obj[n], allr[n]
                row = {"experiment": spec["experiment_key"], "scene": spec["scene"], "material": material,
                       **{key: point["values"][key] for key in scale_keys},
                       "point": int(point["index"]), "repeat": r, "tracker": n,
                       "hit_rate": o["hit_rate"], "depth_mae_mm": o["depth_mae_mm"],
                       "depth_rmse_mm": o["depth_rmse_mm"], "within_5mm": rs["within"],
                       "coverage": o["coverage"], "outlier_rate": o["outlier_rate"], "px_mae": o["px_mae"],
                       "sample_rmse_mm": rs["rmse_mm"], "sample_median_abs_mm": rs["median_abs_mm"],
                       "n_samples": rs["n"], "n_lit_object": o["n_lit"],
                       "hit_rate_all": a_["hit_rate"], "coverage_all": a_["coverage"],
                       "depth_mae_mm_all": a_["depth_mae_mm"], "depth_rmse_mm_all": a_["depth_rmse_mm"],
                       "false_detections": a_["false_detections"], "failed_frames": o["failed_frames"]}
                rows.append(row)
    n_eval = len(angles) * len(spec["points"]) * spec["repeats"]
    return {"rows": rows, "render_s": render_s, "first_render_s": first_render_s, "setup_s": setup_s, "eval_s": time.perf_counter() - t1,
            "frames": int(len(angles)),
            "evaluations": int(n_eval), "source": source_fingerprint(), "host": socket.gethostname(),
            "pid": os.getpid(), "width": int(W), "height": int(H), "trackers": names}


# -- engines -------------------------------------------------------------------------------------------------------

def _engine_name(scheduler: str | None, workers: int | None) -> str:
    if scheduler == "sync" or workers == 0:
        return "sync"
    return "external" if scheduler else "local"


def _execute(units: list[dict], on_result: Callable[[int, dict], None], *, scheduler: str | None,
             workers: int | None, timeout_s: float | None, connect_timeout_s: float, say) -> dict[str, Any]:
    """Run ``units``, calling ``on_result(i, result)`` in the driver as each finishes."""
    engine = _engine_name(scheduler, workers)
    if engine == "sync":
        for i, u in enumerate(units):
            on_result(i, run_unit(u))
        return {"engine": "sync", "workers": 0}
    import logging

    from dask.distributed import Client, as_completed

    from bench.run.cluster import local_cluster

    cluster = None
    logging.getLogger("distributed").setLevel(logging.ERROR)
    try:
        if engine == "external":
            try:
                client = Client(scheduler, timeout=connect_timeout_s)
            except (OSError, TimeoutError) as exc:
                raise SweepError(f"cannot reach the Dask scheduler at {scheduler!r}: {exc}") from None
        else:
            n = workers if workers is not None else (len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity")
                                                     else os.cpu_count() or 1)
            from scenes import variant as _variant

            # the workers take this process's Mitsuba variant instead of each probing for one
            env = {_variant.ENV_VARIANT: _variant.choose()}
            if os.environ.get(_variant.ENV_LLVM_TARGET):  # and its LLVM target (a configuration's or the user's)
                env[_variant.ENV_LLVM_TARGET] = os.environ[_variant.ENV_LLVM_TARGET]
            cluster = local_cluster(n, env)
            client = Client(cluster, timeout=connect_timeout_s)
    except BaseException:
        if cluster is not None:
            cluster.close()
        raise
    info = {"engine": engine, "scheduler": client.scheduler.address}
    futures = []
    try:
        if engine == "local":
            client.wait_for_workers(1, timeout=connect_timeout_s)
        info["workers"] = len(client.scheduler_info(n_workers=-1)["workers"])
        say(f"stripebench sweep: {len(units)} unit(s) on {info['scheduler']} ({info['workers']} worker(s) now)")
        futures = [client.submit(run_unit, u, pure=False, key=f"stripebench-unit-{i}-{time.time_ns()}")
                   for i, u in enumerate(units)]
        index = {f.key: i for i, f in enumerate(futures)}
        try:
            for fut in as_completed(futures, timeout=timeout_s):
                on_result(index[fut.key], fut.result())
        except TimeoutError:
            raise SweepError(f"the sweep did not finish within --timeout {timeout_s} s; finished units are kept, "
                             f"rerun to resume") from None
    finally:
        if futures:
            client.cancel(futures)
        client.close()
        if cluster is not None:
            cluster.close()
    return info


# -- the driver ----------------------------------------------------------------------------------------------------

def _unit_path(out: Path, fp: str) -> Path:
    from bench.store.sweepfiles import unit_path

    return unit_path(out, fp)


def _load_unit(path: Path, say) -> dict | None:
    """A finished unit's result, or None (a damaged, edited or foreign file is said in one line)."""
    from bench.store.sweepfiles import read_unit

    res, why = read_unit(path, clear_bad=True)
    if why:
        say(f"stripebench: sweep unit {path} is {why}: recomputing that unit")
    return res


def _save_unit(path: Path, result: dict) -> None:
    from bench.store.files import os_error
    from bench.store.sweepfiles import write_unit

    try:
        write_unit(path, result)
    except OSError as exc:
        raise os_error("write", path, exc) from None


def run_sweep(config: Config, sweep: Sweep, out_dir=None, *, scheduler: str | None = None,
              workers: int | None = None, chunk: int | None = None, progress: bool = True, quiet: bool = False,
              timeout_s: float | None = None, connect_timeout_s: float = 30.0, force: bool = False) -> Path:
    """Run a sweep; returns its folder. Finished units already in ``out_dir`` are skipped.

    Parameters
    ----------
    config, sweep
        From :func:`load`.
    out_dir : path, optional
        Default :func:`default_sweep_dir`.
    scheduler : str, optional
        ``"sync"`` (sequential, in this process), ``tcp://HOST:PORT`` or ``tls://HOST:PORT``
        (an existing Dask scheduler; Dask's protocol uses pickle, so only a scheduler you
        trust) or None (an in-process ``LocalCluster``).
    workers : int, optional
        Size of the ``LocalCluster``, 0 .. the CPUs this process may use (the default); 0 = sequential.
    chunk : int, optional
        Grid points per unit (default: all the points of a render batch in one unit).
    timeout_s : float, optional
        Give up (finished units kept) when the units take longer than this.
    connect_timeout_s : float
        Bound on connecting to the scheduler and waiting for a first local worker.
    force : bool
        Clear ``out_dir`` first if it holds another configuration's or kind's run (or other files).

    Raises
    ------
    bench.store.runfolder.RunFolderError
        The folder is locked by another process, holds another configuration's or kind's
        run (without ``force``), or cannot be written.
    SweepError
        Scheduler unreachable, workers with other code, timeout.
    """
    from bench.store.provenance import source_fingerprint
    from bench.store.runfolder import RunFolder

    t_start = time.perf_counter()
    from bench.config.options import finite_float, scheduler_address, workers_value

    if workers is not None:
        workers_value("`workers`", workers)  # 0 .. this machine's CPUs
    if scheduler is not None:
        scheduler_address(scheduler, "`scheduler`")  # 'sync' or tcp://HOST:PORT, parsed before connecting
    if timeout_s is not None:
        finite_float("`timeout_s`", timeout_s, low=0, low_open=True)
    if _engine_name(scheduler, workers) != "sync":  # Dask runs a unit in a worker thread of a daemonic process
        held = [s.label for s in config.tracker_specs if s.timeout_s is not None or s.isolate]
        if held:
            raise ConfigError(f"tracker setting {held[0]!r} has `timeout_s` or `isolate`, which only the sync "
                              "scheduler honours (a Dask worker runs trackers in a thread, where neither a time "
                              "limit nor a worker process can be set up); run with --scheduler sync, or drop them")

    def say(msg):
        if not quiet:
            print(msg, file=sys.stderr, flush=True)

    from bench.run.plan import renderer_for

    renderer_for(config)  # before any worker starts: they inherit the target
    out = Path(out_dir) if out_dir is not None else default_sweep_dir(config, sweep)
    units = plan(config, sweep, chunk=chunk)
    source = source_fingerprint()
    folder = RunFolder(out, kind="sweep")
    folder.open({**config.identity(), "sweep": sweep.to_dict()}, source, force=force,
                say=lambda m: print(m, file=sys.stderr, flush=True))  # damaged or stale files: always said
    try:
        return _sweep_locked(config, sweep, folder, units, source, scheduler, workers, progress, quiet, timeout_s,
                             connect_timeout_s, say, t_start)
    finally:
        folder.unlock()


def _sweep_locked(config, sweep, folder, units, source, scheduler, workers, progress, quiet, timeout_s,
                  connect_timeout_s, say, t_start) -> Path:
    import pandas as pd

    from bench.store.provenance import git_revision, versions
    from bench.store.runfolder import write_summary
    from bench.store.summary import build_summary
    from bench.store.sweepfiles import write_sweep_table

    out = folder.path
    fps = [_fingerprint(u, source) for u in units]
    results: dict[int, dict] = {}
    for i, fp in enumerate(fps):
        saved = _load_unit(_unit_path(out, fp), lambda m: print(m, file=sys.stderr, flush=True))
        if saved is not None:
            results[i] = saved
    todo = [i for i in range(len(units)) if i not in results]
    say(f"stripebench sweep: {len(units)} unit(s) ({len(sweep.points())} grid point(s) x {sweep.repeats} "
        f"repeat(s) x {len(config.experiments)} experiment(s)); {len(units) - len(todo)} already done")
    from tqdm import tqdm

    bar = tqdm(total=len(todo), desc="sweep", unit="unit", file=sys.stderr, disable=not progress or quiet or not todo)

    def on_result(j: int, res: dict) -> None:
        i = todo[j]
        if res["source"] != source:
            raise SweepError(f"worker {res['host']} (pid {res['pid']}) runs other stripebench code (source "
                             f"{res['source']}, here {source}); install this revision on every worker")
        _save_unit(_unit_path(out, fps[i]), res)
        results[i] = res
        bar.update(1)
        bar.set_postfix_str(f"render {res['render_s']:.1f} s, eval {res['eval_s']:.1f} s")

    try:
        engine = _execute([units[i] for i in todo], on_result, scheduler=scheduler, workers=workers,
                          timeout_s=timeout_s, connect_timeout_s=connect_timeout_s, say=say) if todo else \
            {"engine": "none (all units were done)"}
    finally:
        bar.close()
    rows = [row for i in range(len(units)) for row in results[i]["rows"]]
    table = pd.DataFrame.from_records(rows)
    write_sweep_table(out, table)
    unit_info = [{"fingerprint": fps[i], "experiment": u["experiment_key"], "render_overrides": u["render_overrides"],
                  "points": len(u["points"]), "repeats": u["repeats"], "frames": results[i]["frames"],
                  "evaluations": results[i]["evaluations"], "render_s": results[i]["render_s"],
                  "setup_s": results[i].get("setup_s", float("nan")),
                  "first_render_s": results[i].get("first_render_s", float("nan")),
                  "eval_s": results[i]["eval_s"], "host": results[i]["host"],
                  "width": results[i]["width"], "height": results[i]["height"]}
                 for i, u in enumerate(units)]
    from bench.evaluate.curves import curves, per_unit_costs

    summary = build_summary(
        "sweep", config=config.to_dict(), sweep=sweep.to_dict(), config_source=config.source,
        seed=config.seed, versions={**versions(), **_dask_versions()}, git_revision=git_revision(),
        source_fingerprint=source, sweep_dir=str(out), engine=engine, units=unit_info,
        costs=per_unit_costs(unit_info), region="object (columns ending in _all: every lit row)",
        repeat_varies="sensor noise (Scene.render noise_draw=repeat) and the sample draw; "
                      "renders are shared by all repeats",
        curves=curves(table, sweep), wall_s=time.perf_counter() - t_start)
    write_summary(out, summary)
    return out


def _dask_versions() -> dict[str, str]:
    from importlib import metadata

    out = {}
    for dist in ("dask", "distributed"):
        try:
            out[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            out[dist] = "not installed"
    return out


def load_sweep(sweep_dir) -> dict[str, Any]:
    """The saved results of a sweep: ``table`` (DataFrame) and ``summary`` (dict)
    (:func:`bench.store.sweepfiles.load_sweep`; ``RunFolderError`` in one line if it is not a finished sweep)."""
    from bench.store.sweepfiles import load_sweep as _load

    return _load(sweep_dir)
