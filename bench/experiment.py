"""Run a configuration end to end: scans, metrics, samples, statistics.

The run folder's layout, its lock and its readers live in
:mod:`bench.runfolder`; the report is built afterwards by
:func:`bench.report.build_report` (the command line does both).
"""

from __future__ import annotations

import platform
import subprocess
import sys
import time
from importlib import metadata
from pathlib import Path

import numpy as np

from . import analysis, renderahead
from .config import Config
from .runfolder import (RunFolder, default_run_dir, load_run, write_figdata, write_gallery, write_summary,
                        write_tables)
from .scan import STATUS, code_fingerprint, pending_frames, run_scan
from .stats import GROSS_MM, WITHIN_MM

__all__ = ["run", "default_run_dir", "load_run", "versions", "git_revision", "PAPER_IMPROVEMENT"]

PAPER_IMPROVEMENT = 0.30  # "a 30 % improvement in the precision" (sec. 4.3)
GALLERY_FRAMES = 2  # frames per experiment in the report's failure gallery


def _conditions(config: Config) -> list[dict]:
    """The configuration's conditions in order: name and the experiment keys in each
    (an experiment without a ``condition`` is a condition of its own)."""
    out: dict[str, list[str]] = {}
    for e in config.experiments:
        out.setdefault(e.condition or e.key, []).append(e.key)
    return [{"condition": c, "experiments": keys} for c, keys in out.items()]


def _gallery_arrays(gallery: dict) -> dict:
    arrays = {"keys": np.array(sorted(gallery), dtype=str)}
    for key, (image, truth, cols) in gallery.items():
        arrays[f"{key}/image"] = image
        arrays[f"{key}/truth"] = truth
        arrays[f"{key}/labels"] = np.array(list(cols), dtype=str)
        for n, c in cols.items():
            arrays[f"{key}/columns/{n}"] = c
    return arrays


def versions() -> dict[str, str]:
    out = {"python": platform.python_version()}
    for dist in ("stripebench", "numpy", "numba", "scikit-image", "mitsuba", "drjit", "pandas", "matplotlib",
                 "pyvista", "colour-science"):
        try:
            out[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            out[dist] = "not installed"
    return out


def git_revision() -> str:
    """``git describe --always --dirty`` of the source tree, or ``unknown``."""
    root = Path(__file__).resolve().parents[1]
    try:
        out = subprocess.run(["git", "describe", "--always", "--dirty", "--abbrev=12"], cwd=root,
                             capture_output=True, text=True, timeout=10)
        return out.stdout.strip() or "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def _scene_for(experiment, config: Config):
    import scenes

    return scenes.make(experiment.scene, material=experiment.material, seed=config.seed, **config.render,
                       **experiment.overrides)


def _angles(experiment, scene) -> np.ndarray:
    if experiment.angles is not None:
        return np.asarray(experiment.angles, float)
    if experiment.n_angles is not None:
        return scene.object.default_angles(scene.rig.zeta_deg, experiment.n_angles)
    return scene.default_angles()


def _renderer(scan_info: list[dict]) -> str:
    """What rendered the run's frames (:func:`scenes.variant.renderer`; every frame, cached or
    resumed ones too, since the render cache key and the scan fingerprint include it)."""
    if not any(s.get("variant") for s in scan_info):
        return ""
    from scenes import variant

    return variant.renderer()


def _say(msg: str, quiet: bool) -> None:
    if not quiet:
        print(msg, file=sys.stderr, flush=True)


def run(config: Config, out_dir=None, *, progress: bool = True, quiet: bool = False, force: bool = False) -> Path:
    """Run ``config`` into a run folder; returns the folder.

    Parameters
    ----------
    config : Config
    out_dir : path-like, optional
        The run folder (default :func:`bench.runfolder.default_run_dir`). A
        partial run of the same configuration there is resumed.
    progress, quiet : bool
        Progress bars; no progress notes on stderr (damaged or stale files are
        always reported, one line each).
    force : bool
        Clear a folder that holds another configuration's run instead of refusing.

    Raises
    ------
    bench.runfolder.RunFolderError
        The folder is locked by another process, holds another configuration's
        run (without ``force``), or cannot be written (the path and the reason).

    The report is not built here: call :func:`bench.report.build_report` on the result.
    """
    t_start = time.perf_counter()
    out = Path(out_dir) if out_dir is not None else default_run_dir(config)
    tracker_objs = config.make_trackers()
    folder = RunFolder(out)
    folder.open(config.identity(), code_fingerprint(tracker_objs.values()), force=force,
                say=lambda m: _say(m, False))  # damaged or stale files: always said
    try:
        return _run_locked(config, folder, tracker_objs, t_start, progress, quiet)
    finally:
        folder.unlock()


def _scan_all(config, plan, folder, tracker_objs, progress, quiet, helper, records, samples, scan_info,
              gallery):
    """Every experiment's scan in order, appending to ``records``, ``samples``, ``scan_info`` and
    ``gallery``; returns Fig. 7's data (or None). ``helper`` (a started :class:`RenderAhead` or
    None) is told which frame is rendered next."""
    fig7 = None
    for k, (exp, scene, angles) in enumerate(plan):
        _say(f"[{k + 1}/{len(plan)}] {exp.key}: {len(angles)} frames at "
             f"{scene.rig.width}x{scene.rig.height}", quiet)
        t0 = time.perf_counter()
        res, _ = run_scan(exp.key, scene, angles, tracker_objs, spp=scene.params["spp"], seed=config.seed,
                          checkpoint=folder.checkpoint(exp.key), progress=progress,
                          say=lambda m: _say(m, False),  # damaged or stale files: always said
                          on_frame=None if helper is None else (lambda i, k=k: helper.at(k, i)))
        wall = time.perf_counter() - t0
        worst = analysis.worst_frames(res, GALLERY_FRAMES)
        for i in worst:  # re-rendered from the render cache: the same pixels the trackers saw
            frame = scene.render(float(angles[i]), spp=scene.params["spp"], seed=config.seed)
            gallery[f"{exp.key}/{i}"] = (frame.image, frame.truth.columns, {n: res.columns[n][i] for n in res.columns})
            if fig7 is None:
                fig7 = (exp.key, float(angles[i]), (frame.image, frame.background, frame.truth.columns),
                        {n: res.columns[n][i] for n in res.columns})
        rig = scene.rig
        for region in (False, True):
            records += analysis.scan_records(res, rig, exp, object_only=region, restore=config.restore)
        seed = int(np.random.SeedSequence([config.seed, k]).generate_state(1)[0])
        samples += analysis.sample_table(res, rig, exp, config.n_samples, seed, restore=config.restore)
        failures = {n: int(np.count_nonzero(res.status[n])) for n in res.status}
        scan_info.append({"experiment": exp.key, "frames": int(len(angles)), "wall_s": wall,
                          "render_s": res.render_seconds, "variant": res.variant, "failures": failures,
                          "failure_messages": {n: sorted({m for m in res.messages[n] if m})[:5] for n in res.messages}})
        for n, c in failures.items():
            if c:
                _say(f"  {n}: failed on {c} frame(s): {scan_info[-1]['failure_messages'][n][0]}", quiet)
    return fig7


def _run_locked(config, folder, tracker_objs, t_start, progress, quiet) -> Path:
    import pandas as pd

    out = folder.path
    records, samples, scan_info, gallery = [], [], [], {}
    plan = [(exp, scene, _angles(exp, scene)) for exp, scene in
            ((e, _scene_for(e, config)) for e in config.experiments)]
    helper, off = None, renderahead.reason_off(config.render_ahead, [scene for _, scene, _ in plan])
    if off is None:
        pending = [pending_frames(exp.key, scene, angles, tracker_objs, spp=scene.params["spp"], seed=config.seed,
                                  checkpoint=folder.checkpoint(exp.key)) for exp, scene, angles in plan]
        helper = renderahead.RenderAhead([scene for _, scene, _ in plan], [angles for _, _, angles in plan],
                                         config.seed, pending=pending, say=lambda m: _say(m, False))
        helper.start()
    try:
        fig7 = _scan_all(config, plan, folder, tracker_objs, progress, quiet, helper,
                         records, samples, scan_info, gallery)
    finally:
        if helper is not None:
            helper.stop()  # the loop ended, failed or was interrupted: the helper stops now
    if helper is not None:
        _say(helper.summary_line(), quiet)
    metrics = pd.DataFrame.from_records(records)
    samples_df = pd.DataFrame.from_records(samples, columns=analysis.sample_columns(config.trackers))
    if samples_df.empty:
        _say("stripebench: warning: no lit object points were scanned, so there are no sample points", quiet)
    stats = analysis.improvements(samples_df, config.dp, config.baselines, n_boot=config.n_boot, seed=config.seed)
    robust = analysis.robust_table(samples_df, config.trackers)
    conditions = _conditions(config)
    if len(samples_df):
        cond_of = {e.key: (e.condition or e.key) for e in config.experiments}
        by_cond = samples_df.assign(condition=samples_df["experiment"].map(cond_of))
        if by_cond["condition"].nunique() < by_cond["experiment"].nunique():  # conditions group experiments
            stats += [dict(s, group=f"condition:{s['group']}") for s in analysis.improvements(
                by_cond, config.dp, config.baselines, n_boot=config.n_boot, seed=config.seed, group_by="condition")
                if s["group"] != "all"]
            robust += [dict(r, group=f"condition:{r['group']}") for r in analysis.robust_table(
                by_cond, config.trackers, group_by="condition") if r["group"] != "all"]
    write_tables(out, metrics, samples_df)
    write_gallery(out, **_gallery_arrays(gallery))
    if fig7 is not None:
        key, angle, (image, background, truth_cols), cols = fig7
        write_figdata(out, experiment=np.array(key), mirror_angle_deg=np.array(angle), image=image,
                 background=background, truth_columns=truth_cols, trackers=np.array(sorted(cols)),
                 **{f"columns/{n}": c for n, c in cols.items()})
    summary = {
        "config": config.to_dict(), "config_source": config.source, "seed": config.seed,
        "versions": versions(), "git_revision": git_revision(), "run_dir": str(out),
        "variants": sorted({s["variant"] for s in scan_info}), "renderer": _renderer(scan_info), "scans": scan_info,
        "improvement": stats, "paper_improvement": PAPER_IMPROVEMENT, "restore": config.restore,
        "robust": robust, "within_mm": WITHIN_MM, "gross_mm": GROSS_MM, "conditions": conditions,
        "verdicts": analysis.verdicts(robust, stats, config.dp, config.baselines),
        "coverage": _coverage_table(metrics), "status_codes": STATUS,
        "wall_s": time.perf_counter() - t_start,
        "render_ahead": helper.stop() if helper is not None else {"off": off},
    }
    if config.real_set:
        summary["sim_to_real"] = _sim_to_real(config, out, metrics, quiet)
    write_summary(out, summary)
    return out


def _sim_to_real(config: Config, out: Path, metrics, quiet: bool) -> dict:
    """Evaluate the same tracker settings on the configuration's real set (into
    ``<run>/real``) and compare each tracker's mean object hit rate over the
    experiments with its mean hit rate over the photographs."""
    from . import real
    from .real_run import run_real

    dataset = real.SHIPPED if config.real_set == "shipped" else Path(config.real_set)
    _say(f"real set {dataset}: {len(config.tracker_specs)} trackers", quiet)
    rdir = run_real(dataset, out / "real", config.tracker_specs, seed=config.seed, n_boot=min(config.n_boot, 2000),
                    quiet=True)
    rm = real_run_means(rdir)
    obj = metrics[metrics["region"] == "object"]
    synthetic = {str(k): float(v) for k, v in obj.groupby("tracker")["hit_rate"].mean().items()}
    result = real.sim_to_real(synthetic, rm)
    result["dataset"] = str(config.real_set)
    result["sentences"] = real.sim_to_real_sentences(result)
    return result


def real_run_means(real_dir) -> dict[str, float]:
    """label -> mean hit rate over the images of a real run (its ``mean`` rows)."""
    import pandas as pd

    m = pd.read_parquet(Path(real_dir) / "metrics.parquet")
    m = m[m["experiment"] == "mean"]
    return {str(r.tracker): float(r.hit_rate) for r in m.itertuples()}


def _coverage_table(metrics) -> list[dict]:
    m = metrics[metrics["region"] == "all"]
    return [{"experiment": r.experiment, "tracker": r.tracker, "coverage": r.coverage,
             "filled_fraction": r.filled_fraction} for r in m.itertuples()]
