"""Run a configuration end to end: scans, metrics, samples, statistics.

The run folder's layout, its lock and its readers live in
:mod:`bench.store.runfolder` (the checkpoints in :mod:`bench.store.checkpoint`,
the figure data in :mod:`bench.store.figdata`, the summary's builder in
:mod:`bench.store.summary`); the report is built afterwards by
:func:`bench.report.run.build_report` (the command line does both).
"""

from __future__ import annotations

import concurrent.futures
import dataclasses
import time
from pathlib import Path

import numpy as np

from bench.evaluate import readings, tables as analysis
from bench.run import renderahead
from bench.run.plan import angles_for, renderer_for, say, scene_for
from bench.run.camera_view import tracker_images
from bench.config import Config
from bench.store.checkpoint import STATUS
from bench.store.figdata import FigData, GalleryFrame
from bench.store.runfolder import (RunFolder, default_run_dir, load_run, write_figdata, write_gallery, write_summary,
                        write_tables)
from bench.store.summary import build_summary
from bench.run.scan import pending_frames, run_scan
from bench.run.track import build_trackers
from bench.store.provenance import code_fingerprint, git_revision, versions
from bench.evaluate.outcomes import GROSS_MM, PAPER_IMPROVEMENT, WITHIN_MM

__all__ = ["run", "scan_tables", "finish_run", "default_run_dir", "load_run", "distinct_trackers", "PAPER_IMPROVEMENT"]

GALLERY_FRAMES = 2  # frames per experiment in the report's failure gallery


def figure_data(experiment: str, angle_deg: float, image, background, truth_columns, columns: dict) -> FigData:
    """Fig. 7's data for the report, with the paper's accumulated cost field (Fig. 7b, 4-connected)
    computed here, by the run, so that the report only reads it."""
    from trackers.dp import accumulated_cost

    return FigData(experiment, angle_deg, image, background, truth_columns, columns,
                   accumulated_cost(image, connectivity=4))


def _conditions(config: Config) -> list[dict]:
    """The configuration's conditions in order: name and the experiment keys in each
    (an experiment without a ``condition`` is a condition of its own)."""
    out: dict[str, list[str]] = {}
    for e in config.experiments:
        out.setdefault(e.condition or e.key, []).append(e.key)
    return [{"condition": c, "experiments": keys} for c, keys in out.items()]


def run(config: Config, out_dir=None, *, progress: bool = True, quiet: bool = False, force: bool = False) -> Path:
    """Run ``config`` into a run folder; returns the folder.

    Parameters
    ----------
    config : Config
    out_dir : path-like, optional
        The run folder (default :func:`bench.store.runfolder.default_run_dir`). A
        partial run of the same configuration there is resumed.
    progress, quiet : bool
        Progress bars; no progress notes on stderr (damaged or stale files are
        always reported, one line each).
    force : bool
        Clear a folder that holds another configuration's run instead of refusing.

    Raises
    ------
    bench.store.runfolder.RunFolderError
        The folder is locked by another process, holds another configuration's
        run (without ``force``), or cannot be written (the path and the reason).

    The report is not built here: call :func:`bench.report.run.build_report` on the result.
    """
    t_start = time.perf_counter()
    renderer_for(config)
    out = Path(out_dir) if out_dir is not None else default_run_dir(config)
    tracker_objs = build_trackers(config.tracker_specs)
    folder = RunFolder(out)
    folder.open(config.identity(), code_fingerprint(tracker_objs.values()), force=force,
                say=lambda m: say(m, False))  # damaged or stale files: always said
    try:
        return _run_locked(config, folder, tracker_objs, t_start, progress, quiet)
    finally:
        folder.unlock()


def scan_tables(config: Config, index: int, experiment, rig, res, restore=None) -> tuple[list[dict], list[dict]]:
    """The metric records (both regions) and sample points of one experiment's scan.

    Parameters
    ----------
    config : Config
        Gives the seed, ``n_samples`` and each setting's restoration.
    index : int
        The experiment's position in ``config.experiments`` (it seeds the sample draw).
    experiment : bench.config.Experiment
    rig : scenes.rig.Rig
    res : bench.store.checkpoint.ScanResult
    restore : dict, optional
        label -> restoration; default :meth:`Config.restore_by_label` (a scored
        run adds its submission's label).

    Returns
    -------
    (records, samples) : lists of dict, as :func:`bench.evaluate.tables.scan_records`
    and :func:`bench.evaluate.tables.sample_table` give them.
    """
    restore = config.restore_by_label() if restore is None else restore  # a setting's own, else the run's
    records = []
    for region in (False, True):
        records += analysis.scan_records(res, rig, experiment, object_only=region, restore=restore)
    seed = int(np.random.SeedSequence([config.seed, index]).generate_state(1)[0])
    return records, analysis.sample_table(res, rig, experiment, config.n_samples, seed, restore=restore)


def _scan_all(config, plan, folder, tracker_objs, progress, quiet, helper, records, samples, scan_info,
              gallery):
    """Every experiment's scan in order, appending to ``records``, ``samples``, ``scan_info`` and
    ``gallery`` (:class:`GalleryFrame` s); returns Fig. 7's :class:`FigData` (or None). ``helper`` (a started :class:`RenderAhead` or
    None) is told which frame is rendered next."""
    fig7 = None
    for k, (exp, scene, angles) in enumerate(plan):
        say(f"[{k + 1}/{len(plan)}] {exp.key}: {len(angles)} frames at "
             f"{scene.rig.width}x{scene.rig.height}", quiet)
        t0 = time.perf_counter()
        res = run_scan(exp.key, scene, angles, tracker_objs, spp=scene.params["spp"], seed=config.seed,
                       checkpoint=folder.checkpoint(exp.key), progress=progress,
                       say=lambda m: say(m, False),  # damaged or stale files: always said
                       on_frame=None if helper is None else (lambda i, k=k: helper.at(k, i)))
        wall = time.perf_counter() - t0
        worst = analysis.worst_frames(res, GALLERY_FRAMES)
        for i in worst:  # re-rendered from the render cache: the same pixels the trackers saw
            frame = scene.render(float(angles[i]), spp=scene.params["spp"], seed=config.seed)
            cols = {n: res.columns[n][i] for n in res.columns}
            image, background = tracker_images(frame, scene.params)
            gallery.append(GalleryFrame(exp.key, int(i), image, frame.truth.columns, cols))
            if fig7 is None:
                fig7 = figure_data(exp.key, float(angles[i]), image, background, frame.truth.columns, cols)
        recs, samps = scan_tables(config, k, exp, scene.rig, res)
        records += recs
        samples += samps
        failures = {n: int(np.count_nonzero(res.status[n])) for n in res.status}
        scan_info.append({"experiment": exp.key, "frames": int(len(angles)),
                          "angles_deg": [float(a) for a in angles], "wall_s": wall,
                          "render_s": res.render_seconds, "variant": res.variant, "failures": failures,
                          "rig": dataclasses.asdict(scene.rig),
                          "failure_messages": {n: sorted({m for m in res.messages[n] if m})[:5] for n in res.messages}})
        for n, c in failures.items():
            if c:
                say(f"  {n}: failed on {c} frame(s): {scan_info[-1]['failure_messages'][n][0]}", quiet)
    return fig7


def _run_locked(config, folder, tracker_objs, t_start, progress, quiet) -> Path:
    out = folder.path
    records, samples, scan_info, gallery = [], [], [], []
    plan = [(exp, scene, angles_for(exp, scene)) for exp, scene in
            ((e, scene_for(e, config)) for e in config.experiments)]
    helper, off = None, renderahead.reason_off(config.render_ahead, [scene for _, scene, _ in plan])
    if off is None:
        pending = [pending_frames(exp.key, scene, angles, tracker_objs, spp=scene.params["spp"], seed=config.seed,
                                  checkpoint=folder.checkpoint(exp.key)) for exp, scene, angles in plan]
        helper = renderahead.RenderAhead([scene for _, scene, _ in plan], [angles for _, _, angles in plan],
                                         config.seed, pending=pending, say=lambda m: say(m, False))
        helper.start()
    try:
        fig7 = _scan_all(config, plan, folder, tracker_objs, progress, quiet, helper,
                         records, samples, scan_info, gallery)
    finally:
        if helper is not None:
            helper.stop()  # the loop ended, failed or was interrupted: the helper stops now
    if helper is not None:
        say(helper.summary_line(), quiet)
    render_ahead = helper.stop() if helper is not None else {"off": off}
    return finish_run(config, out, records, samples, scan_info, gallery, fig7, t_start=t_start, quiet=quiet,
                      render_ahead=render_ahead)


def finish_run(config: Config, out: Path, records: list[dict], samples: list[dict], scan_info: list[dict],
               gallery: list, fig7, *, t_start: float, quiet: bool, render_ahead: dict, kind: str = "run",
               submissions: tuple[str, ...] = (), builtins: tuple[str, ...] | None = None,
               extra: dict | None = None) -> Path:
    """Everything a run writes after its scans: tables, gallery, Fig. 7's data, statistics, summary.

    Parameters
    ----------
    config : Config
    out : Path
        The (locked) run folder.
    records, samples, scan_info : list of dict
        :func:`scan_tables`' records and samples of every experiment, and one
        entry per experiment (frames, wall and render seconds, failures).
    gallery : list of bench.store.figdata.GalleryFrame
    fig7 : bench.store.figdata.FigData or None
    t_start : float
        ``time.perf_counter()`` at the start (the summary's wall time).
    quiet : bool
    render_ahead : dict
        What the render-ahead helper did (or why it was off).
    kind : str
        The summary's kind: ``"run"``, or ``"score"`` for a scored submission
        (:mod:`bench.run.score`; no sim-to-real step).
    submissions : tuple of str
        Labels of scored submissions: tracked beside ``config.trackers``, restored
        with the run's ``restore`` and compared with the baselines as the DP trackers are.
    builtins : tuple of str, optional
        The labels of ``config.trackers`` that were tracked (default all of them; ``()`` for a
        submission scored alone): only these enter the robust figures and the summary.
    extra : dict, optional
        More summary fields.
    """
    import pandas as pd

    labels = (*(config.trackers if builtins is None else builtins), *submissions)
    dp = (*config.dp, *submissions)
    metrics = pd.DataFrame.from_records(records)
    samples_df = pd.DataFrame.from_records(samples, columns=analysis.sample_columns(labels))
    if samples_df.empty:
        say("stripebench: warning: no lit object points were scanned, so there are no sample points", quiet)
    conditions = _conditions(config)
    # the statistics and the detection figures (bootstrap intervals: seconds of numpy and of a numba loop,
    # much of it without the GIL) in two threads while this one writes the tables and tracks the real set
    # (whose tracker time-outs need the main thread's signals); each is a pure function of its arguments
    # and its own seeds, so the results are the same as one after the other
    with concurrent.futures.ThreadPoolExecutor(2, thread_name_prefix="stripebench-stats") as pool:
        statistics = pool.submit(_statistics, config, samples_df, labels, dp)
        detection_job = pool.submit(_detection, config, out, conditions)
        write_tables(out, metrics, samples_df)
        write_gallery(out, gallery)
        if fig7 is not None:
            write_figdata(out, fig7)
        extra = dict(extra or {})
        if config.real_set and kind == "run":
            extra["sim_to_real"] = _sim_to_real(config, out, metrics, quiet)
        stats, robust = statistics.result()
        detection = detection_job.result()
    verdicts = analysis.verdicts(robust, stats, dp, config.baselines)
    claims = readings.paper_claims(config.to_dict(), robust, stats, verdicts, conditions, samples_df,
                                   paper_improvement=PAPER_IMPROVEMENT, within_mm=WITHIN_MM)
    summary = build_summary(
        kind, config=config.to_dict(), config_source=config.source, seed=config.seed,
        versions=versions(), git_revision=git_revision(), run_dir=str(out),
        variants=sorted({s["variant"] for s in scan_info}), renderer=_renderer(scan_info), scans=scan_info,
        improvement=stats, paper_improvement=PAPER_IMPROVEMENT, restore=config.restore,
        restore_by_tracker={**config.restore_by_label(), **{n: config.restore for n in submissions}},
        robust=robust, within_mm=WITHIN_MM, gross_mm=GROSS_MM, conditions=conditions,
        verdicts=verdicts, paper_claims=claims, detection=detection,
        coverage=_coverage_table(metrics), status_codes=STATUS,
        wall_s=time.perf_counter() - t_start,
        render_ahead=render_ahead, **extra)
    write_summary(out, summary)
    return out


def _statistics(config: Config, samples_df, labels, dp) -> tuple[list, list]:
    """The improvement intervals and robust figures of a run's samples, pooled, per experiment and
    (where conditions group experiments) per condition: ``(stats, robust)``."""
    stats = analysis.improvements(samples_df, dp, config.baselines, n_boot=config.n_boot, seed=config.seed)
    robust = analysis.robust_table(samples_df, labels)
    if len(samples_df):
        cond_of = {e.key: (e.condition or e.key) for e in config.experiments}
        by_cond = samples_df.assign(condition=samples_df["experiment"].map(cond_of))
        if by_cond["condition"].nunique() < by_cond["experiment"].nunique():  # conditions group experiments
            stats += [dict(s, group=f"condition:{s['group']}") for s in analysis.improvements(
                by_cond, dp, config.baselines, n_boot=config.n_boot, seed=config.seed, group_by="condition")
                if s["group"] != "all"]
            robust += [dict(r, group=f"condition:{r['group']}") for r in analysis.robust_table(
                by_cond, labels, group_by="condition") if r["group"] != "all"]
    return stats, robust


#: Resamples of frames behind the detection figures' intervals (fewer than the samples' ``n_boot``: an
#: interval per condition and tracker over thousands of rows).
DETECTION_BOOT = 1000


def _detection(config: Config, out: Path, conditions: list[dict]) -> list[dict]:
    """Detection figures (precision, recall, F1, false-report rate, AP, false points per scan) with
    bootstrap intervals over frames, per condition and pooled (``all``), from the run's checkpoints
    (:func:`bench.evaluate.tables.detection_table`)."""
    from bench.store.checkpoint import read_checkpoint
    from bench.store.runfolder import LAYOUT

    rows = {}
    for e in config.experiments:
        res, _ = read_checkpoint(out / LAYOUT["scans"] / f"{e.key}.npz", e.key)
        if res is not None:
            rows[e.key] = analysis.detection_rows(res)
    groups = [(f"condition:{c['condition']}", c["experiments"]) for c in conditions]
    groups.append(("all", [e.key for e in config.experiments]))
    return analysis.detection_table(rows, groups, n_boot=min(config.n_boot, DETECTION_BOOT), seed=config.seed)


def _sim_to_real(config: Config, out: Path, metrics, quiet: bool) -> dict:
    """Evaluate the same tracker settings on the configuration's real set (into
    ``<run>/real``) and compare each tracker's figures on the renders (mean over the experiments) with
    its figures on the photographs, both halves: the hit rate (the object's stripe rows against the
    photographs' mean hit rate: ``table``, ``spearman_rho``) and, in ``detection``, F1 over rows and the
    false-report rate (every row of the renders against the photographs' pooled rows of known state);
    ``sentences`` says each (:func:`bench.evaluate.simreal.sim_to_real_headline`). Where experiments
    carry a ``condition``, also matched by class (``by_class``, the hit rate, and ``by_class_detection``,
    F1 and the false-report rate: :func:`bench.evaluate.simreal.sim_to_real_by_class` against the
    manifest's ``condition`` column); and, with ``real_predict`` (``run --predict``), the figures predicted
    for the photographs (``predicted``: :func:`bench.run.real.predict_real`, into ``<run>/real/predict``)
    beside the measured ones."""
    from bench.evaluate import simreal
    from bench.store import realset as real
    from bench.store.realrun import load_real_run, real_run_means
    from bench.run.real import predict_real, run_real

    dataset = real.SHIPPED if config.real_set == "shipped" else Path(config.real_set)
    specs = distinct_trackers(config.tracker_specs)
    say(f"real set {dataset}: {len(specs)} trackers", quiet)
    rdir = run_real(dataset, out / "real", specs, seed=config.seed, n_boot=min(config.n_boot, 2000),
                    quiet=True, force=True)  # a folder inside this run's, which this process holds
    rm = real_run_means(rdir)
    obj = metrics[metrics["region"] == "object"]
    synthetic = {str(k): float(v) for k, v in obj.groupby("tracker")["hit_rate"].mean().items()}
    result = simreal.sim_to_real(synthetic, rm)
    result["dataset"] = str(config.real_set)
    every = metrics[metrics["region"] == "all"]  # detection: every row (the object region cannot see a false report)
    result["detection"] = {  # both halves of detection, every row: the renders' mean against the photographs'
        k: simreal.sim_to_real({str(t): float(v) for t, v in every.groupby("tracker")[k].mean().items()},
                               real_run_means(rdir, k)) for k in simreal.DETECTION_FIGURES}
    result["sentences"] = simreal.sim_to_real_headline(result)
    say("renders vs photographs, Spearman's rho across trackers: " + "; ".join(
        f"{simreal.FIGURES[k]} {r['spearman_rho']:.2f}" for k, r in
        (("hit_rate", result), *result["detection"].items())), quiet)
    cond_of = {e.key: e.condition for e in config.experiments if e.condition}
    if cond_of:  # experiments that name a class of photograph: the comparison matched by class
        rmet = load_real_run(rdir)["metrics"]
        image_class = {im.name: im.meta.get("condition", "") for im in real.load_dataset(dataset)}
        photos = rmet[rmet["experiment"] != "mean"]

        def by_class(rendered, key):
            by_exp = rendered[rendered["experiment"].isin(list(cond_of))].assign(
                condition=lambda d: d["experiment"].map(cond_of))
            syn = {str(c): {str(k): float(v) for k, v in g.groupby("tracker")[key].mean().items()}
                   for c, g in by_exp.groupby("condition")}
            per_image = {str(n): {str(r.tracker): float(getattr(r, key)) for r in g.itertuples()}
                         for n, g in photos.groupby("experiment")}
            return simreal.sim_to_real_by_class(syn, per_image, image_class)

        result["by_class"] = by_class(obj, "hit_rate")
        result["by_class_detection"] = {k: by_class(every, k) for k in simreal.DETECTION_FIGURES}
    if not config.real_predict:
        return result
    # the same trackers' figures predicted for these photographs (each with its own stripe moved, and in place) beside the
    # measured ones, row for row: unlike the means above, both sides are the same photographs
    result["predicted"] = predict_real(dataset, rdir, specs, n_boot=min(config.n_boot, 1000), seed=config.seed,
                                       say=lambda m: None)["doc"]
    p = result["predicted"]
    say(f"real set predicted beside measured: hit rate rho {p['hit_rate']['spearman_rho']:.2f}, mean |diff| "
        f"{p['hit_rate']['mean_abs_diff']:.3f}; F1 rho {p['f1']['spearman_rho']:.2f}, mean |diff| "
        f"{p['f1']['mean_abs_diff']:.3f} ({len(p['photographs'])} photographs)"
        + ("" if not p.get("measured_reliability") else "; the measured ranks' own split-half rho: hit rate "
           f"{p['measured_reliability']['hit_rate']['split_half_rho']:.2f}, F1 "
           f"{p['measured_reliability']['f1']['split_half_rho']:.2f}"), quiet)
    return result


def distinct_trackers(specs) -> list:
    """The tracker settings that are distinct trackers: the first of each (name, params),
    in order. Settings that differ only in ``restore`` track alike (restoration acts on
    the depth map afterwards), so the photographs, which have no restoration, and the
    sim-to-real rank correlation count each tracker once.

    Examples
    --------
    >>> from bench.config import TrackerSpec
    >>> [s.label for s in distinct_trackers([TrackerSpec("threshold", "threshold"),
    ...     TrackerSpec("threshold_gaps", "threshold", {}, "none"), TrackerSpec("argmax", "threshold", {"threshold": -1.0})])]
    ['threshold', 'argmax']
    """
    seen, out = set(), []
    for s in specs:
        key = (s.name, repr(sorted(s.params.items())))
        if key not in seen:
            seen.add(key)
            out.append(s)
    return out


def _renderer(scan_info: list[dict]) -> str:
    """What rendered the run's frames (:func:`scenes.variant.renderer`; every frame, cached or
    resumed ones too, since the render cache key and the scan fingerprint include it)."""
    if not any(s.get("variant") for s in scan_info):
        return ""
    from scenes import variant

    return variant.renderer()


def _coverage_table(metrics) -> list[dict]:
    m = metrics[metrics["region"] == "all"]
    return [{"experiment": r.experiment, "tracker": r.tracker, "coverage": r.coverage,
             "filled_fraction": r.filled_fraction} for r in m.itertuples()]
