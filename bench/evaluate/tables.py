"""From scans to metric records, sample points and improvement statistics.

Pure functions: a :class:`bench.store.checkpoint.ScanResult`, a rig and numbers in,
tables out. Depth is the paper's ``R`` (eq. 3), the distance from the mirror
axis; errors are in mm.
"""

from __future__ import annotations

import numpy as np

from bench.evaluate.metrics import frame_record
from bench.evaluate.restore import restore_depth_map
from bench.evaluate.outcomes import GROSS_MM, WITHIN_MM
from bench.evaluate.stats import (STATISTICS, resample_indices, improvement_interval, robust_summary,
                                  spread_resampled)
from bench.evaluate.triangulation import depth_cm

__all__ = ["true_depth_cm", "tracker_depth_cm", "restore_of", "restored_points", "scan_records", "scan_states",
           "detection_rows", "detection_table", "false_points", "draw_samples", "sample_table", "sample_columns",
           "improvements", "robust_table", "verdicts", "worst_frames", "OBJECT_BLIND"]

#: The figures a false report moves: NaN in region ``object``, whose rows off the object are unknown
#: (:func:`scan_states`), so no report there can be false; region ``all`` scores them over every row.
#: The object region keeps the stripe half (hit rate, recall, coverage, the errors) and the counts.
OBJECT_BLIND = ("precision", "f1", "false_report_rate", "ap", "false_detections")


def true_depth_cm(scan) -> np.ndarray:
    """``R`` (cm) of the ground-truth points, (F, H), NaN where no stripe."""
    p = scan.truth_points_cm
    return np.hypot(p[..., 0], p[..., 1])


def tracker_depth_cm(scan, name: str, rig) -> np.ndarray:
    """``R`` (cm) triangulated from a tracker's columns, (F, H)."""
    return depth_cm(scan.columns[name], rig)


def restore_of(restore, label: str) -> str:
    """The restoration of tracker ``label``: ``restore`` itself when it is one method
    for every tracker, else its entry for ``label`` (a mapping label -> method, as
    :meth:`bench.config.Config.restore_by_label` gives; a label it lacks is a ``KeyError``).

    >>> restore_of("rows", "dp4"), restore_of({"threshold_gaps": "none"}, "threshold_gaps")
    ('rows', 'none')
    """
    return restore if isinstance(restore, str) else restore[label]


def restored_points(scan, name: str | None, rig, restore: str = "rows"):
    """3-D points of the ground truth (``name=None``) or of a tracker's restored
    surface, for the report's shape figures.

    Parameters
    ----------
    scan : ScanResult
        One experiment's scan (frames x rows).
    name : str or None
        Tracker label, or None for the ground truth.
    rig : scenes.rig.Rig
        The rig of eqs. (3), (4), (7).
    restore : str
        How missed rows are filled (:func:`bench.evaluate.restore.restore_depth_map`).

    Returns
    -------
    points : numpy.ndarray, shape (F, H, 3), cm
        NaN away from the object (a margin of one cell is kept).
    errors : numpy.ndarray, shape (F, H), mm, or None
        Restored depth minus the true depth, as in :func:`scan_records`; None for the truth.
    """
    from bench.evaluate.triangulation import points_from_depth

    F, H = scan.truth_columns.shape
    if name is None:
        pts = scan.truth_points_cm.copy()
        pts[~scan.on_object] = np.nan
        return pts, None
    r, _ = restore_depth_map(tracker_depth_cm(scan, name, rig), restore)
    pts = points_from_depth(r, np.arange(H, dtype=float)[None, :], scan.angles[:, None], rig)
    r_true = true_depth_cm(scan)
    err = 10.0 * (r - r_true)
    # show the object: the cells whose true point is on the object (and a margin of one)
    on = scan.on_object.copy()
    on[1:] |= scan.on_object[:-1]
    on[:-1] |= scan.on_object[1:]
    on[:, 1:] |= scan.on_object[:, :-1]
    on[:, :-1] |= scan.on_object[:, 1:]
    pts[~on] = np.nan
    return pts, err


def false_points(scan, name: str, rig) -> np.ndarray:
    """The false 3-D points of a tracker on a scan: every report on a row with no stripe (truth NaN),
    triangulated by eqs. (3), (4), (5) as the tracker's columns would be: (N, 3) cm, frames in order.

    Each is a point where there is no surface: junk in a scanner's point cloud, a phantom obstacle
    for the paper's robot.
    """
    from bench.evaluate.triangulation import points_from_depth

    cols = scan.columns[name]
    f, r = np.nonzero(np.isnan(scan.truth_columns) & ~np.isnan(cols))
    if f.size == 0:
        return np.zeros((0, 3))
    depth = depth_cm(cols[f, r], rig)
    return points_from_depth(depth, r.astype(float), scan.angles[f], rig)


def scan_records(scan, rig, experiment, *, object_only: bool = False, restore="rows") -> list[dict]:
    """One metric record per tracker for one scan (see :func:`bench.evaluate.metrics.frame_record`).

    ``restore`` is one method of :data:`bench.evaluate.restore.METHODS` for every
    tracker or a mapping label -> method (:func:`restore_of`).

    Adds ``scene``, ``material``, ``experiment``, ``tracker``, ``ms_per_frame``
    (mean over frames of the tracker's own time), ``failed_frames``,
    ``filled_fraction`` (lit rows the restoration had to fill) and ``region``
    (``"object"`` with ``object_only``: the stripe rows on the object, every other row unknown,
    so the figures of :data:`OBJECT_BLIND` are NaN there; ``"all"``: every row).
    """
    truth = scan.truth_columns.copy()
    r_true = true_depth_cm(scan)
    if object_only:
        truth[~scan.on_object] = np.nan
    lit = ~np.isnan(truth)
    state = scan_states(scan, object_only)
    out = []
    for name in sorted(scan.columns):
        cols = scan.columns[name]
        r_pred = tracker_depth_cm(scan, name, rig)
        rec = frame_record(
            np.where(scan.on_object, cols, np.nan) if object_only else cols,
            truth,
            depth_pred_mm=10.0 * np.where(lit, r_pred, np.nan),
            depth_true_mm=10.0 * np.where(lit, r_true, np.nan),
            false_cols=scan.false_columns,
            state=state,
            score=scan.scores.get(name),
        )
        if object_only:  # no row of this region can hold a false report: nothing here prices one
            rec.update({k: float("nan") for k in OBJECT_BLIND})
        _, filled = restore_depth_map(r_pred, restore_of(restore, name))
        rec.update(
            experiment=experiment.key, scene=experiment.scene, material=experiment.material, tracker=name,
            region="object" if object_only else "all", condition=getattr(experiment, "condition", "") or "",
            ms_per_frame=float(1e3 * np.nanmean(scan.seconds[name])) if np.isfinite(scan.seconds[name]).any()
            else float("nan"),
            failed_frames=int(np.count_nonzero(scan.status[name] != 0)),
            filled_fraction=float(filled[lit].mean()) if lit.any() else float("nan"),
            frames=int(scan.angles.size),
        )
        out.append(rec)
    return out


def scan_states(scan, object_only: bool = False) -> np.ndarray:
    """The row states (:mod:`bench.evaluate.outcomes`) of a scan, (F, H): exact truth (a lit visible
    stripe, or none); for the object region, stripe rows on the object and every other row unknown
    (the object region scores only the object's stripe).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> s = SimpleNamespace(truth_columns=np.array([[1.0, np.nan, 2.0]]), on_object=np.array([[True, False, False]]))
    >>> scan_states(s).tolist(), scan_states(s, object_only=True).tolist()
    ([[1, 0, 1]], [[1, -1, -1]])
    """
    from bench.evaluate.outcomes import STRIPE, UNSURE, truth_states

    states = truth_states(scan.truth_columns)
    if object_only:
        states = np.where(scan.on_object & (states == STRIPE), STRIPE, UNSURE).astype(np.int8)
    return states


def detection_rows(scan) -> dict:
    """Each tracker's row outcomes and scores on a scan (region ``all``): label -> ``(codes, scores)``,
    both (F, H) (:func:`bench.evaluate.outcomes.row_outcomes`; scores NaN where nothing is reported)."""
    from bench.evaluate.outcomes import row_outcomes

    states = scan_states(scan)
    out = {}
    for name in sorted(scan.columns):
        cols = scan.columns[name]
        out[name] = (row_outcomes(cols, scan.truth_columns, states),
                     np.where(np.isnan(cols), np.nan, scan.scores.get(name, np.nan)))
    return out


def detection_table(rows_by_experiment: dict, groups, *, n_boot: int, seed: int) -> list[dict]:
    """Detection figures with bootstrap intervals over frames, per group of experiments and tracker.

    Parameters
    ----------
    rows_by_experiment : dict
        experiment key -> :func:`detection_rows` of its scan.
    groups : sequence of (str, sequence of str)
        Group name -> the experiment keys it pools (e.g. ``("condition:...", [keys])``, ``("all", keys)``).
    n_boot, seed : int
        Resamples of frames, and the seed (group ``i`` and tracker ``j`` use ``SeedSequence([seed, i, j])``).

    Returns
    -------
    list of dict
        ``group, tracker, n_frames, n_scans`` (experiments pooled), the counts ``n_hit`` ...,
        ``precision, recall, f1, false_report_rate, ap`` each with ``_lo`` and ``_hi``,
        ``ap_constant`` and ``false_points_per_scan`` (``n_false`` over ``n_scans``: reports on
        stripe-less rows, each a 3-D point where there is no surface).
    """
    from bench.evaluate.ranking import bootstrap_frames

    out = []
    for gi, (group, keys) in enumerate(groups):
        keys = [k for k in keys if k in rows_by_experiment]
        if not keys:
            continue
        labels = sorted(set.intersection(*(set(rows_by_experiment[k]) for k in keys)))
        for ti, label in enumerate(labels):
            codes = [c for k in keys for c in rows_by_experiment[k][label][0]]
            scores = [s for k in keys for s in rows_by_experiment[k][label][1]]
            s = int(np.random.SeedSequence([seed, gi, ti]).generate_state(1)[0])
            r = bootstrap_frames(codes, scores, n_boot=n_boot, seed=s)
            out.append({"group": group, "tracker": label, "n_scans": len(keys), **r,
                        "false_points_per_scan": r["n_false"] / len(keys)})
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


def sample_table(scan, rig, experiment, n: int, seed, restore="rows") -> list[dict]:
    """The sample points of one scan with each tracker's depth error (mm) on
    its restored surface (:func:`bench.evaluate.restore.restore_depth_map` by ``restore``,
    one method or a mapping label -> method, :func:`restore_of`; NaN where the
    restoration leaves no value)."""
    f, r = draw_samples(scan, n, seed)
    r_true = true_depth_cm(scan)
    rows = [{"experiment": experiment.key, "scene": experiment.scene, "material": experiment.material,
             "sample": k, "frame": int(fi), "row": int(ri), "mirror_angle_deg": float(scan.angles[fi]),
             "true_depth_cm": float(r_true[fi, ri])} for k, (fi, ri) in enumerate(zip(f, r))]
    for name in sorted(scan.columns):
        filled, was_filled = restore_depth_map(tracker_depth_cm(scan, name, rig), restore_of(restore, name))
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
    list of dict: ``group, dp, baseline, statistic, value, low, high, n,
    n_samples, n_missing_dp, n_missing_baseline``.
    The ratio is over the pairs where both errors have a value (``n`` of the
    group's ``n_samples``); ``n_missing_dp`` and ``n_missing_baseline`` count the
    samples each side could not restore (NaN errors, e.g. with ``restore =
    "none"``), so a ratio over fewer pairs says why. Fewer than 2 pairs: NaN.

    Examples
    --------
    >>> import pandas as pd
    >>> s = pd.DataFrame({"error_mm_d": [1.0, -1.0, 2.0, np.nan], "error_mm_b": [2.0, np.nan, -4.0, 8.0]})
    >>> r = improvements(s, ["d"], ["b"], n_boot=10, seed=0, group_by=None)[0]
    >>> r["statistic"], round(r["value"], 4), r["n"], r["n_samples"], r["n_missing_dp"], r["n_missing_baseline"]
    ('rmse', 0.5, 2, 4, 1, 1)
    """
    groups = [("all", samples)]
    if group_by is not None and len(samples):
        groups += [(str(k), g) for k, g in samples.groupby(group_by, sort=True)]
    out = []
    for gi, (label, g) in enumerate(groups):
        resampled = {}  # (tracker, statistic, pair's points) -> spread_resampled: shared by its pairs

        def spreads(name, errors, ok, si, stat):
            key = (name, si, ok.tobytes())
            if key not in resampled:
                idx = resample_indices(int(np.random.SeedSequence([seed, gi, si]).generate_state(1)[0]),
                                        int(ok.sum()), int(n_boot))
                resampled[key] = spread_resampled(errors[ok], stat, idx)
            return resampled[key]

        for dp in dp_names:
            for base in base_names:
                if len(g) == 0:
                    a = b = np.zeros(0)
                else:
                    a = g[f"error_mm_{dp}"].to_numpy(float)
                    b = g[f"error_mm_{base}"].to_numpy(float)
                ok = ~np.isnan(a) & ~np.isnan(b)
                counts = {"n_samples": int(a.size), "n_missing_dp": int(np.isnan(a).sum()),
                          "n_missing_baseline": int(np.isnan(b).sum())}
                for si, stat in enumerate(STATISTICS):
                    if ok.sum() < 2:
                        res = {"value": np.nan, "low": np.nan, "high": np.nan, "n": int(ok.sum())}
                    else:  # bootstrap_improvement(a[ok], b[ok], stat, ...), each side's resamples once
                        res = improvement_interval(spreads(dp, a, ok, si, stat), spreads(base, b, ok, si, stat),
                                                   int(ok.sum()))
                    out.append({"group": label, "dp": dp, "baseline": base, "statistic": stat, "value": res["value"],
                                "low": res["low"], "high": res["high"], "n": res["n"], **counts})
    return out


def robust_table(samples, labels, *, group_by: str | None = "experiment", within_mm: float = WITHIN_MM,
                 gross_mm: float = GROSS_MM) -> list[dict]:
    """Robust figures of every tracker's sample errors, per group and pooled.

    A sample with no value (NaN: nothing restored there) counts as a miss: it
    is in the denominator of ``within`` but never inside the band.

    Parameters
    ----------
    samples : pandas.DataFrame
        :func:`sample_table` rows.
    labels : sequence of str
        Tracker labels (``error_mm_<label>`` columns).

    Returns
    -------
    list of dict: ``group, tracker, n, n_missing, within, within_low, within_high,
    median_abs_mm, median_mm, p95_abs_mm, n_gross, rmse_mm`` (see :func:`bench.evaluate.stats.robust_summary`;
    ``within`` and its Wilson interval are over all ``n`` samples, missing ones included;
    the other figures over the samples with a value). Group ``"all"`` pools every sample
    (over unlike conditions).
    """
    from bench.evaluate.stats import wilson_interval

    groups = [("all", samples)]
    if group_by is not None and len(samples):
        groups += [(str(k), g) for k, g in samples.groupby(group_by, sort=False)]
    out = []
    for label, g in groups:
        for name in labels:
            e = g[f"error_mm_{name}"].to_numpy(float) if len(g) else np.zeros(0)
            r = robust_summary(e, within_mm=within_mm, gross_mm=gross_mm)
            n_all = int(e.size)
            k = int(round(r["within"] * r["n"])) if r["n"] else 0
            lo, hi = wilson_interval(k, n_all)
            out.append({"group": label, "tracker": name, "n": n_all, "n_missing": n_all - r["n"],
                        "within": k / n_all if n_all else float("nan"), "within_low": lo, "within_high": hi,
                        "median_abs_mm": r["median_abs_mm"], "median_mm": r["median_mm"],
                        "p95_abs_mm": r["p95_abs_mm"],
                        "n_gross": r["n_gross"], "rmse_mm": r["rmse_mm"]})
    return out


def verdicts(robust: list[dict], improvement: list[dict], dp_labels, base_labels) -> list[dict]:
    """Which of each (DP, baseline) pair is more precise, per group, by each statistic.

    A statistic decides only when its intervals say so: the ±5 mm fraction when
    the two Wilson intervals do not overlap, the RMSE ratio when its bootstrap
    interval excludes 0; otherwise it is ``"tie"``. Median |error| and gross-error
    counts are reported alongside without a test.

    Returns
    -------
    list of dict: ``group, dp, baseline, within`` (winner label or ``"tie"``),
    ``rmse`` (likewise), and the figures of both trackers.
    """
    rob = {(r["group"], r["tracker"]): r for r in robust}
    imp = {(i["group"], i["dp"], i["baseline"]): i for i in improvement if i["statistic"] == "rmse"}
    out = []
    for group in dict.fromkeys(r["group"] for r in robust):
        for d in dp_labels:
            for b in base_labels:
                rd, rb = rob.get((group, d)), rob.get((group, b))
                if rd is None or rb is None:
                    continue
                if rd["within_low"] > rb["within_high"]:
                    w = d
                elif rb["within_low"] > rd["within_high"]:
                    w = b
                else:
                    w = "tie"
                i = imp.get((group, d, b))
                if i is None or not np.isfinite(i["low"]):
                    rm = "tie"
                elif i["low"] > 0:
                    rm = d
                elif i["high"] < 0:
                    rm = b
                else:
                    rm = "tie"
                out.append({"group": group, "dp": d, "baseline": b, "within": w, "rmse": rm,
                            "dp_figures": rd, "baseline_figures": rb, "ratio": i})
    return out


def worst_frames(scan, k: int) -> list[int]:
    """The ``k`` frames where the trackers fail most, on both halves of detection: largest mean over
    trackers of the fraction of the frame's rows that fail (a stripe row not hit: wrong, or nothing
    reported; a stripe-less row with a report: a false 3-D point), worst first; ties to the earlier
    frame. Frames with no lit row are never chosen; fewer than ``k`` if fewer frames have lit rows."""
    from bench.evaluate.outcomes import hits

    lit = ~np.isnan(scan.truth_columns)
    n_lit = lit.sum(axis=1)
    H = scan.truth_columns.shape[1]
    fail = np.zeros(scan.truth_columns.shape[0])
    for name in scan.columns:
        cols = scan.columns[name]
        missed = (lit & ~hits(cols, scan.truth_columns)).sum(axis=1)
        false = (~lit & ~np.isnan(cols)).sum(axis=1)
        fail += (missed + false) / H
    fail /= max(len(scan.columns), 1)
    ok = np.flatnonzero(n_lit > 0)
    order = ok[np.argsort(-fail[ok], kind="stable")]
    return [int(i) for i in order[:k]]
