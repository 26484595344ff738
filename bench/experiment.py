"""Run a configuration end to end: scans, metrics, samples, statistics, report.

Layout of a run folder (``results/runs/<name>-<hash>/`` by default, where the
hash covers the configuration, so rerunning the same command resumes)::

    config.json        the validated configuration
    scans/<exp>.npz    per-experiment checkpoint (frames x rows of every tracker)
    figdata.npz        the frame and fields Fig. 7 shows
    gallery.npz        per experiment, the frames where the trackers miss the truth most
    metrics.parquet    one record per tracker x experiment x region
    metrics.csv        the same
    samples.csv        the sample points, one depth-error column per tracker
    summary.json       config, seed, versions, git revision, statistics, timings
    figures/*.png
    report.html        self-contained report
"""

from __future__ import annotations

import json
import platform
import subprocess
import sys
import time
from importlib import metadata
from pathlib import Path

import numpy as np

from . import analysis
from .config import Config
from .runio import atomic_write_text, config_hash, load_npz, runs_root, save_npz
from .scan import STATUS, run_scan
from .stats import GROSS_MM, WITHIN_MM

__all__ = ["run", "default_run_dir", "versions", "git_revision", "PAPER_IMPROVEMENT"]

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


def default_run_dir(config: Config) -> Path:
    """``<runs root>/<name>-<hash of the configuration>``."""
    return runs_root() / f"{config.name}-{config_hash(config.to_dict())}"


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


def _say(msg: str, quiet: bool) -> None:
    if not quiet:
        print(msg, file=sys.stderr, flush=True)


def run(config: Config, out_dir=None, *, progress: bool = True, quiet: bool = False, report: bool = True) -> Path:
    """Run ``config``; returns the run folder. Resumes a partial run in ``out_dir``."""
    import pandas as pd

    t_start = time.perf_counter()
    out = Path(out_dir) if out_dir is not None else default_run_dir(config)
    out.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out / "config.json", json.dumps(config.to_dict(), indent=2))
    tracker_objs = config.make_trackers()
    records, samples, scan_info, gallery = [], [], [], {}
    fig7 = None
    for k, exp in enumerate(config.experiments):
        scene = _scene_for(exp, config)
        angles = _angles(exp, scene)
        _say(f"[{k + 1}/{len(config.experiments)}] {exp.key}: {len(angles)} frames at "
             f"{scene.rig.width}x{scene.rig.height}", quiet)
        t0 = time.perf_counter()
        res, _ = run_scan(exp.key, scene, angles, tracker_objs, spp=scene.params["spp"], seed=config.seed,
                          checkpoint=out / "scans" / f"{exp.key}.npz", progress=progress)
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
    _write_tables(out, metrics, samples_df)
    save_npz(out / "gallery.npz", **_gallery_arrays(gallery))
    if fig7 is not None:
        key, angle, (image, background, truth_cols), cols = fig7
        save_npz(out / "figdata.npz", experiment=np.array(key), mirror_angle_deg=np.array(angle), image=image,
                 background=background, truth_columns=truth_cols, trackers=np.array(sorted(cols)),
                 **{f"columns/{n}": c for n, c in cols.items()})
    summary = {
        "config": config.to_dict(), "config_source": config.source, "seed": config.seed,
        "versions": versions(), "git_revision": git_revision(), "run_dir": str(out),
        "variants": sorted({s["variant"] for s in scan_info}), "scans": scan_info,
        "improvement": stats, "paper_improvement": PAPER_IMPROVEMENT, "restore": config.restore,
        "robust": robust, "within_mm": WITHIN_MM, "gross_mm": GROSS_MM, "conditions": conditions,
        "verdicts": analysis.verdicts(robust, stats, config.dp, config.baselines),
        "coverage": _coverage_table(metrics), "status_codes": STATUS,
        "wall_s": time.perf_counter() - t_start,
    }
    atomic_write_text(out / "summary.json", json.dumps(summary, indent=2, default=_json_default))
    if report:
        from .report import build_report

        build_report(out, quiet=quiet)
        summary["wall_s"] = time.perf_counter() - t_start
        atomic_write_text(out / "summary.json", json.dumps(summary, indent=2, default=_json_default))
    return out


def _json_default(o):
    if isinstance(o, (np.integer,)):
        return int(o)
    if isinstance(o, (np.floating,)):
        return float(o)
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")


def _coverage_table(metrics) -> list[dict]:
    m = metrics[metrics["region"] == "all"]
    return [{"experiment": r.experiment, "tracker": r.tracker, "coverage": r.coverage,
             "filled_fraction": r.filled_fraction} for r in m.itertuples()]


def _write_tables(out: Path, metrics, samples) -> None:
    import io

    from .runio import atomic_write_bytes

    buf = io.BytesIO()
    metrics.to_parquet(buf, index=False)
    atomic_write_bytes(out / "metrics.parquet", buf.getvalue())
    atomic_write_text(out / "metrics.csv", metrics.to_csv(index=False))
    atomic_write_text(out / "samples.csv", samples.to_csv(index=False))


def load_run(run_dir) -> dict:
    """The saved results of a run: ``metrics`` and ``samples`` DataFrames,
    ``summary`` dict and ``figdata`` arrays (or None)."""
    import pandas as pd

    run_dir = Path(run_dir)
    if not (run_dir / "summary.json").exists():
        raise FileNotFoundError(f"{run_dir} is not a finished run (no summary.json)")
    return {
        "metrics": pd.read_parquet(run_dir / "metrics.parquet"),
        "samples": pd.read_csv(run_dir / "samples.csv"),
        "summary": json.loads((run_dir / "summary.json").read_text()),
        "figdata": load_npz(run_dir / "figdata.npz"),
        "gallery": load_npz(run_dir / "gallery.npz"),
        "scans": {p.stem: load_npz(p) for p in sorted((run_dir / "scans").glob("*.npz"))},
    }
