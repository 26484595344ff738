"""The run report's figures: which a run gets, from its saved files, drawn in worker processes.

:func:`make_figures` writes ``figures/*.png`` of a finished run from what the run saved
(its summary, tables, checkpoints, ``figdata.npz`` and ``gallery.npz``; each experiment's
rig from the summary). It decides which figures a run gets and with what titles; the
drawing itself is :mod:`bench.report.figures`. The 2-D figures are drawn in worker
processes (:func:`figure_workers`) while this process draws the 3-D ones. The page
around them is :mod:`bench.report.run`.
"""

from __future__ import annotations

import sys
from pathlib import Path

from bench.evaluate import readings
from bench.evaluate.metrics import hit_rate
from bench.evaluate.tables import false_points, restore_of, restored_points
from bench.report.detection import condition_groups, pr_curves
from bench.store.runfolder import load_run

__all__ = ["make_figures", "figure_workers", "FIGURE_WORKERS_MIN_JOBS", "tracker_readings", "tracker_restore",
           "warn"]


def tracker_readings(cfg: dict) -> dict[str, str | None]:
    """label -> its reading of the paper's method without DP (:func:`bench.evaluate.readings.reading_of`)."""
    return {(t if isinstance(t, str) else t["label"]): readings.reading_of(t, cfg.get("restore", "rows"))
            for t in cfg.get("trackers", [])}


def tracker_restore(summary, label: str) -> str:
    """How ``label``'s missed rows were restored in this run (:func:`bench.evaluate.tables.restore_of` of the
    summary's ``restore_by_tracker``; a label it lacks: the run's ``restore``)."""
    by_label = summary.get("restore_by_tracker") or {}
    return restore_of(by_label, label) if label in by_label else summary.get("restore", "rows")


def warn(msg: str) -> None:
    """One note to stderr (a damaged file skipped, the figures drawn here after all)."""
    print(msg, file=sys.stderr)


def _sweeps(cfg) -> list[tuple[str, str, list[str]]]:
    """Experiments of one scene and material that differ in exactly one numeric
    override: (title, key, experiment keys) for each such family of 3 or more."""
    from bench.config import parse

    exps = parse(cfg, "summary.json", machine=False).experiments
    fams: dict = {}
    for e in exps:
        for k, v in e.overrides.items():
            if isinstance(v, (int, float)) and not isinstance(v, bool):
                rest = tuple(sorted((kk, repr(vv)) for kk, vv in e.overrides.items() if kk != k))
                fams.setdefault((e.scene, e.material, k, rest), []).append(e.key)
    return [(f"{s}/{m}", k, keys) for (s, m, k, _), keys in fams.items() if len(keys) >= 3]


FIGURE_WORKERS_MIN_JOBS = 8
"""The fewest 2-D figures worth drawing in worker processes (each worker's start and imports cost
about a second of CPU; a run of the ``paper`` profile has 47 figures, about 12 s of drawing)."""


def figure_workers(n_jobs: int, workers: int | None = None) -> int:
    """How many worker processes draw ``n_jobs`` 2-D figures: 0 (draw them in this process) or more.

    ``workers`` None (the default) takes every usable core when there are at least
    :data:`FIGURE_WORKERS_MIN_JOBS` figures and 2 cores, else 0; an integer is taken as given
    (capped at ``n_jobs``).

    Examples
    --------
    >>> figure_workers(3, 4), figure_workers(47, 0), figure_workers(47, 2)
    (3, 0, 2)
    """
    from bench.run.renderahead import usable_cores

    if workers is None:
        cores = usable_cores()
        workers = cores if cores >= 2 and n_jobs >= FIGURE_WORKERS_MIN_JOBS else 0
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 0:
        raise ValueError(f"`workers` must be an integer >= 0 or None, got {workers!r}")
    return min(workers, n_jobs)


def _draw(jobs: list, workers: int, meanwhile) -> list[Path]:
    """Run the figure ``jobs`` (``(function, args, kwargs)``, each writing one PNG and returning its
    path), in ``workers`` processes (0: here, in order), calling ``meanwhile()`` in this process while
    they draw; returns the paths in the jobs' order. A figure is a pure function of its arguments, so
    the files are the same bytes either way (tested)."""
    if workers == 0:
        paths = [f(*a, **k) for f, a, k in jobs]
        meanwhile()
        return paths
    import concurrent.futures
    import multiprocessing

    def here(why: BaseException) -> list[Path]:
        warn(f"figures drawn in this process: the worker processes failed ({type(why).__name__}: {why})")
        return [f(*a, **k) for f, a, k in jobs]

    import os

    from trackers.processes import die_with_parent

    # spawn: a clean child (no Dr.Jit or Dask threads of a run forked mid-flight), started by this
    # process itself, so that the kernel kills it when this process dies, whatever the signal
    # (a forkserver's children outlive a killed parent, and keep its stdout open)
    ctx = multiprocessing.get_context("spawn")
    pool = None
    try:
        pool = concurrent.futures.ProcessPoolExecutor(max_workers=workers, mp_context=ctx,
                                                      initializer=die_with_parent, initargs=(os.getpid(),))
        futures = [pool.submit(f, *a, **k) for f, a, k in jobs]
    except OSError as exc:  # no worker process could start: everything here
        if pool is not None:
            pool.shutdown(wait=False, cancel_futures=True)
        paths = here(exc)
        meanwhile()
        return paths
    with pool:
        try:
            meanwhile()
            try:
                return [fut.result() for fut in futures]
            except concurrent.futures.process.BrokenProcessPool as exc:  # a worker died: draw them again here
                return here(exc)
        except BaseException:
            pool.shutdown(wait=False, cancel_futures=True)
            raise


def _default_rig(scene: str, cfg: dict):
    """The rig of a run that did not save its own (summaries before it did): the scene's default at the
    run's frame size. The report's one use of :mod:`scenes`, and only for such runs (a run that saved
    its rigs never reaches it: tested)."""
    import scenes

    return scenes.make(scene, width=int(cfg["render"].get("width", 512)), height=int(cfg["render"].get("height", 480))).rig


def make_figures(run_dir, *, quiet: bool = False, data: dict | None = None,
                 workers: int | None = None) -> dict[str, list[Path]]:
    """Write every figure of a run into ``run_dir/figures``; returns them by
    section. ``data`` is the run's :func:`~bench.run.experiment.load_run` if the
    caller already has it. The 2-D figures are drawn in ``workers`` processes
    (:func:`figure_workers`; default: every usable core when there are enough figures) while
    this process draws the 3-D ones."""
    import pandas as pd

    from bench.report import figures
    from bench.config import parse
    from scenes.rig import Rig

    run_dir = Path(run_dir)
    data = load_run(run_dir, say=warn) if data is None else data
    summary, metrics, samples = data["summary"], data["metrics"], data["samples"]
    cfg = summary["config"]
    # each experiment's rig as the run saved it (runs before it was saved: the scene's default rig)
    rigs = {s["experiment"]: Rig(**s["rig"]) for s in summary.get("scans", []) if isinstance(s.get("rig"), dict)}
    config = parse(cfg, "summary.json", machine=False)
    figdir = run_dir / "figures"
    figdir.mkdir(exist_ok=True)
    for old in figdir.glob("*.png"):  # figures of an earlier report must not linger
        old.unlink()
    out: dict[str, list[Path]] = {"tracking": [], "samples": [], "gallery": [], "bars": [], "curves": [],
                                  "shapes": [], "pr": []}
    jobs: list[tuple[str, tuple]] = []  # (section, (function, args, kwargs)): the 2-D figures, drawn below

    def later(section, function, *args, **kwargs):
        jobs.append((section, (function, args, kwargs)))

    fd = data["figdata"]
    if fd is not None:  # the cost field as the run saved it (None from runs before figdata format 3)
        later("tracking", figures.fig_tracking, fd.image, fd.cost_field, fd.columns,
              fd.truth_columns, figdir / "fig7_tracking.png",
              title=f"{fd.experiment} at mirror angle {fd.mirror_angle_deg:.2f} deg "
                    "(the frame where the trackers miss most)")
    stats = {(s["group"], s["dp"], s["baseline"], s["statistic"]): s for s in summary["improvement"]}
    rob = {(r["group"], r["tracker"]): r for r in summary.get("robust", [])}
    dp0 = cfg["dp"][0] if cfg["dp"] else None
    base0 = cfg["baselines"][0] if cfg["baselines"] else None
    if dp0 and base0 and len(samples):
        kinds = tracker_readings(cfg)
        paper = next((b for b in cfg["baselines"] if kinds.get(b) == readings.PAPER_READING), None)
        filled = next((b for b in cfg["baselines"] if kinds.get(b) == "filled"), None)
        first = set(summary["conditions"][0]["experiments"]) if summary.get("conditions") else set()
        for key, g in samples.groupby("experiment", sort=False):
            g = g.reset_index(drop=True)
            # the paper's condition: the reading the paper describes beside the filled one
            bases = [paper, base0] if key in first and paper is not None and paper != base0 else [base0]
            st = {b: stats.get((key, dp0, b, "rmse")) for b in bases}
            r = {n: rob[(key, n)] for n in (dp0, *bases) if (key, n) in rob}
            und = g[f"filled_{filled}"].to_numpy(bool) if filled is not None and len(bases) > 1 else None
            later("samples", figures.fig_samples,
                  g, dp0, bases, figdir / f"fig10_{key}.png", title=f"{key}: {len(g)} samples", stat=st, robust=r,
                  within_mm=summary.get("within_mm", 5.0), undetectable=und,
                  readings={b: readings.READINGS[kinds[b]] for b in bases if kinds.get(b)})
    gal = data.get("gallery")
    if gal is not None:
        for k, g in enumerate(gal):
            tracks, truth = g.columns, g.truth_columns
            rate = {n: hit_rate(tracks[n], truth) for n in tracks}
            worst = ", ".join(f"{n} {rate[n]:.2f}" for n in sorted(rate, key=lambda n: rate[n])[:4])
            later("gallery", figures.fig_gallery, g.image, truth, tracks, figdir / f"gallery_{k:02d}.png",
                  title=f"{g.experiment}, frame {g.frame}: lowest hit rates {worst}")
    for k, (title, _, keys) in enumerate(condition_groups(summary)):
        curves = pr_curves(data["scans"], keys, list(config.trackers))
        if curves:
            later("pr", figures.fig_pr, curves, figdir / f"pr_{k:02d}.png",
                  title=f"{title}: precision-recall over rows ({len(keys)} scan(s))")
    if len(metrics):
        later("bars", figures.fig_bars, metrics, figdir / "bars_hit_rate.png", "hit_rate",
              "hit rate on the object's stripe rows, per experiment")
        later("bars", figures.fig_bars, metrics, figdir / "bars_f1.png", "f1",
              "F1 over every row (misses and false reports alike), per experiment", region="all")
        for title, key, keys in _sweeps(cfg):
            m = metrics[(metrics["region"] == "object") & metrics["experiment"].isin(keys)]
            val = {e.key: e.overrides[key] for e in config.experiments if e.key in keys}
            t = pd.DataFrame({key: m["experiment"].map(val), "tracker": m["tracker"], "hit_rate": m["hit_rate"]})
            mark = {"ambient_lux": 400.0, "laser_power_mw": 3.0}.get(key)
            later("curves", figures.fig_curves, t, key, figdir / f"curve_{title.replace('/', '-')}_{key}.png",
                  title=f"{title}: hit rate on the object against {key}", mark=mark)

    def shapes():
        """3-D restored shapes (VTK, in this process): the first experiment of each scene."""
        done = set()
        # the first two DP settings and the first two baselines (each surface costs about 1 s of off-screen
        # rendering)
        show = list(cfg["dp"])[:2] + list(cfg["baselines"])[:2] or list(config.trackers)[:4]
        for exp in config.experiments:
            if exp.scene in done or exp.key not in data["scans"]:
                continue
            done.add(exp.scene)
            scan = data["scans"][exp.key]
            rig = rigs.get(exp.key) or _default_rig(exp.scene, cfg)
            names = [n for n in show if n in scan.columns]
            surf = {"ground truth": restored_points(scan, None, rig)[0]}
            errs, fps = {}, {}
            for n in names:
                surf[n], errs[n] = restored_points(scan, n, rig, tracker_restore(summary, n))
                fps[n] = false_points(scan, n, rig)
            try:
                out["shapes"].append(figures.fig_shapes(surf, figdir / f"shape_{exp.key}.png", title=exp.key,
                                                        errors_mm=errs, false_points=fps))
            except Exception as exc:  # a missing OpenGL must not lose the rest of the report
                if not quiet:
                    print(f"stripebench: 3-D figure of {exp.key} skipped: {type(exc).__name__}: {exc}",
                          file=sys.stderr)

    paths = _draw([job for _, job in jobs], figure_workers(len(jobs), workers), shapes)
    for (section, _), path in zip(jobs, paths):
        out[section].append(path)
    return out
