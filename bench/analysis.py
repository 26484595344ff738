"""From scans to metric records, sample points and improvement statistics.

Pure functions: a :class:`bench.scan.ScanResult`, a rig and numbers in,
tables out. Depth is the paper's ``R`` (eq. 3), the distance from the mirror
axis; errors are in mm.
"""

from __future__ import annotations

import numpy as np

from .metrics import frame_record
from .restore import fill_depth_map
from .stats import STATISTICS, bootstrap_improvement
from .triangulation import depth_cm

__all__ = ["true_depth_cm", "tracker_depth_cm", "scan_records", "draw_samples", "sample_table", "sample_columns",
           "improvements"]


def true_depth_cm(scan) -> np.ndarray:
    """``R`` (cm) of the ground-truth points, (F, H), NaN where no stripe."""
    p = scan.truth_points_cm
    return np.hypot(p[..., 0], p[..., 1])


def tracker_depth_cm(scan, name: str, rig) -> np.ndarray:
    """``R`` (cm) triangulated from a tracker's columns, (F, H)."""
    return depth_cm(scan.columns[name], rig)


def scan_records(scan, rig, experiment, *, object_only: bool = False) -> list[dict]:
    """One metric record per tracker for one scan (see :func:`bench.metrics.frame_record`).

    Adds ``scene``, ``material``, ``experiment``, ``tracker``, ``ms_per_frame``
    (mean over frames of the tracker's own time), ``failed_frames``,
    ``filled_fraction`` (lit rows the restoration had to fill) and ``region``.
    """
    truth = scan.truth_columns.copy()
    r_true = true_depth_cm(scan)
    if object_only:
        truth[~scan.on_object] = np.nan
    lit = ~np.isnan(truth)
    out = []
    for name in sorted(scan.columns):
        cols = scan.columns[name]
        r_pred = tracker_depth_cm(scan, name, rig)
        rec = frame_record(
            np.where(scan.on_object, cols, np.nan) if object_only else cols,
            truth,
            depth_pred_mm=10.0 * np.where(lit, r_pred, np.nan),
            depth_true_mm=10.0 * np.where(lit, r_true, np.nan),
        )
        _, filled = fill_depth_map(r_pred)
        rec.update(
            experiment=experiment.key, scene=experiment.scene, material=experiment.material, tracker=name,
            region="object" if object_only else "all",
            ms_per_frame=float(1e3 * np.nanmean(scan.seconds[name])) if np.isfinite(scan.seconds[name]).any()
            else float("nan"),
            failed_frames=int(np.count_nonzero(scan.status[name] != 0)),
            filled_fraction=float(filled[lit].mean()) if lit.any() else float("nan"),
            frames=int(scan.angles.size),
        )
        out.append(rec)
    return out


def draw_samples(scan, n: int, seed) -> tuple[np.ndarray, np.ndarray]:
    """``n`` random (frame, row) cells on the object's lit, visible surface.

    Drawn without replacement with ``numpy.random.default_rng(seed)`` (all of
    them if there are fewer); the same cells serve every tracker.
    """
    ok = scan.on_object & ~np.isnan(scan.truth_columns)
    f, r = np.nonzero(ok)
    if f.size == 0:
        return f, r
    rng = np.random.default_rng(seed)
    pick = np.sort(rng.choice(f.size, size=min(n, f.size), replace=False))
    return f[pick], r[pick]


SAMPLE_COLUMNS = ("experiment", "scene", "material", "sample", "frame", "row", "mirror_angle_deg", "true_depth_cm")


def sample_columns(tracker_names) -> list[str]:
    """The columns of the sample table for these trackers."""
    return list(SAMPLE_COLUMNS) + [c for n in sorted(tracker_names) for c in (f"error_mm_{n}", f"filled_{n}")]


def sample_table(scan, rig, experiment, n: int, seed) -> list[dict]:
    """The sample points of one scan with each tracker's depth error (mm) on
    its restored surface (missing rows filled from neighbours)."""
    f, r = draw_samples(scan, n, seed)
    r_true = true_depth_cm(scan)
    rows = [{"experiment": experiment.key, "scene": experiment.scene, "material": experiment.material,
             "sample": k, "frame": int(fi), "row": int(ri), "mirror_angle_deg": float(scan.angles[fi]),
             "true_depth_cm": float(r_true[fi, ri])} for k, (fi, ri) in enumerate(zip(f, r))]
    for name in sorted(scan.columns):
        filled, was_filled = fill_depth_map(tracker_depth_cm(scan, name, rig))
        for row, fi, ri in zip(rows, f, r):
            row[f"error_mm_{name}"] = float(10.0 * (filled[fi, ri] - r_true[fi, ri]))
            row[f"filled_{name}"] = bool(was_filled[fi, ri])
    return rows


def improvements(samples, dp_names, base_names, *, n_boot: int, seed: int, group_by: str | None = "experiment"):
    """The precision-improvement statistic ``1 - S_DP / S_noDP`` with bootstrap CIs.

    Parameters
    ----------
    samples : pandas.DataFrame
        :func:`sample_table` rows (``error_mm_<tracker>`` columns).
    dp_names, base_names : sequence of str
    n_boot, seed : int
    group_by : str or None
        Column to group by (one result per group) in addition to the pooled
        result over every sample (group ``"all"``).

    Returns
    -------
    list of dict: ``group, dp, baseline, statistic, value, low, high, n``.
    Pairs where either error is NaN are dropped (``n`` says how many remain).
    """
    groups = [("all", samples)]
    if group_by is not None and len(samples):
        groups += [(str(k), g) for k, g in samples.groupby(group_by, sort=True)]
    out = []
    for gi, (label, g) in enumerate(groups):
        for dp in dp_names:
            for base in base_names:
                if len(g) == 0:
                    a = b = np.zeros(0)
                else:
                    a = g[f"error_mm_{dp}"].to_numpy(float)
                    b = g[f"error_mm_{base}"].to_numpy(float)
                ok = ~np.isnan(a) & ~np.isnan(b)
                for si, stat in enumerate(STATISTICS):
                    if ok.sum() < 2:
                        res = {"value": np.nan, "low": np.nan, "high": np.nan, "n": int(ok.sum())}
                    else:
                        res = bootstrap_improvement(a[ok], b[ok], stat, n_boot=n_boot,
                                                    seed=int(np.random.SeedSequence([seed, gi, si]).generate_state(1)[0]))
                    out.append({"group": label, "dp": dp, "baseline": base, "statistic": stat, "value": res["value"],
                                "low": res["low"], "high": res["high"], "n": res["n"]})
    return out
