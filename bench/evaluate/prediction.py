"""Predicted beside measured: a prediction's figures set against a labelled set's, per tracker.

``stripebench real --predict`` and ``stripebench predictcheck`` compare the figures predicted for
photographs (or frames standing in for them) with the figures measured on them: Spearman's rank
correlation across trackers and the mean |predicted - measured|, for hit rate, F1 and the false-report
rate, pooled over all photographs (:func:`compare_with_real`) or within groups of them
(:func:`compare_by_group`). Both sides pool the rows of the photographs compared, from their row-outcome
counts; a prediction's false-report rate also counts its false-report frames' stripe-less rows
(:func:`predicted_figures`). How far the measured ranks are themselves repeatable, the most a prediction's rank
correlation can be expected to show, is :func:`rank_reliability`; how far the rank correlation itself rests on which
photographs were taken, :func:`rank_interval`. Pure functions on tables.
"""

from __future__ import annotations

import numpy as np

__all__ = ["COMPARED", "predicted_figures", "compare_with_real", "compare_by_group", "comparison_doc",
           "per_group_error", "rank_reliability", "rank_interval", "stepped_up", "FIGURE_KEYS", "RELIABILITY_SPLITS",
           "RELIABILITY_MIN_PHOTOS", "INTERVAL_DRAWS"]

#: The figures compared.
COMPARED = ("hit_rate", "f1", "false_report_rate")
#: Each compared figure's key in :func:`bench.evaluate.outcomes.detection_figures`.
FIGURE_KEYS = {"hit_rate": "recall", "f1": "f1", "false_report_rate": "false_report_rate"}
#: :func:`rank_reliability`'s random halves of the photographs.
RELIABILITY_SPLITS = 200
#: ... and the fewest photographs it splits (two per half); :func:`rank_interval` resamples as few.
RELIABILITY_MIN_PHOTOS = 4
#: :func:`rank_interval`'s resamples of the photographs.
INTERVAL_DRAWS = 1000


def predicted_figures(counts: dict) -> dict:
    """A prediction's figures from its row-outcome counts: :func:`bench.evaluate.outcomes.detection_figures` of
    the counts of the moved frames and the photograph in place (``n_hit`` ...), with the false-report rate also
    counting the false-report frames' stripe-less rows (``n_false_cut``, ``n_quiet_cut``, when given:
    :func:`bench.run.predict_frames.cut_counts`), which only that figure reads (docs/predict.md).

    Examples
    --------
    >>> c = {"n_hit": 8, "n_wrong": 0, "n_missed": 2, "n_false": 1, "n_quiet": 9}
    >>> f = predicted_figures({**c, "n_false_cut": 3, "n_quiet_cut": 7})
    >>> f["recall"], round(f["f1"], 4), f["false_report_rate"]
    (0.8, 0.8421, 0.2)
    """
    from bench.evaluate.outcomes import COUNT_KEYS, detection_figures

    moved = {k: int(counts[k]) for k in COUNT_KEYS if k in counts}
    fig = detection_figures(moved)
    cut_false, cut_quiet = int(counts.get("n_false_cut", 0)), int(counts.get("n_quiet_cut", 0))
    if cut_false or cut_quiet:
        fig["false_report_rate"] = detection_figures(
            {**moved, "n_false": moved.get("n_false", 0) + cut_false,
             "n_quiet": moved.get("n_quiet", 0) + cut_quiet})["false_report_rate"]
    return fig


def compare_with_real(predicted, real_metrics, names) -> dict:
    """Predicted beside measured, per figure (:data:`COMPARED`), on the same photographs.

    Parameters
    ----------
    predicted : pandas.DataFrame
        ``predicted.csv`` of :func:`bench.run.predict.run_predict`.
    real_metrics : pandas.DataFrame
        A real run's ``metrics`` (per-image rows with the row-outcome counts ``n_hit`` ...).
    names : iterable of str
        The photographs to pool the measured figures over (the matched ones).

    Returns
    -------
    dict
        Figure -> :func:`bench.evaluate.simreal.sim_to_real` of predicted ("synthetic") against
        measured ("real", the photographs' rows pooled, as the prediction pools the renders'), with
        ``mean_abs_diff`` (mean over trackers of ``|predicted - measured|``) added.

    Examples
    --------
    >>> import pandas as pd
    >>> pred = pd.DataFrame({"tracker": ["a", "b", "c"], "hit_rate": [0.9, 0.5, 0.7], "f1": [0.9, 0.5, 0.7],
    ...                      "false_report_rate": [0.0, 0.0, 0.0]})
    >>> rows = [{"experiment": "p", "tracker": t, "n_hit": h, "n_wrong": 0, "n_missed": 10 - h, "n_false": 0,
    ...          "n_quiet": 0} for t, h in (("a", 8), ("b", 4), ("c", 6))]
    >>> r = compare_with_real(pred, pd.DataFrame(rows), ["p"])
    >>> r["hit_rate"]["spearman_rho"], round(r["hit_rate"]["mean_abs_diff"], 3)
    (1.0, 0.1)
    """
    measured = _pooled_figures(real_metrics, "experiment", names)
    predicted_figs = {f: {str(t): float(v) for t, v in zip(predicted["tracker"], predicted[f])} for f in COMPARED}
    return _compare(predicted_figs, measured)


def compare_by_group(predicted_photos, real_metrics, groups: dict) -> dict:
    """Predicted beside measured within groups of photographs (a rig, or each photograph alone).

    Both sides pool the rows of the group's photographs (the prediction: its renders' row
    outcomes, ``predicted_photos.csv``; the measurement: the real run's per-image counts).

    Parameters
    ----------
    predicted_photos : pandas.DataFrame
        :func:`bench.run.predict.run_predict`'s ``predicted_photos`` (``name``, ``tracker``, the counts ``n_hit`` ...).
    real_metrics : pandas.DataFrame
        A real run's ``metrics`` (per-image rows with the row-outcome counts).
    groups : dict
        Photograph name -> group label; photographs not in it (or not matched) are left out.

    Returns
    -------
    dict
        Group label -> ``{"photographs": [...], "hit_rate": ..., "f1": ..., "false_report_rate": ...}``, each as
        :func:`compare_with_real`'s (:func:`bench.evaluate.simreal.sim_to_real` with ``mean_abs_diff``).

    Examples
    --------
    >>> import pandas as pd
    >>> def rec(name, t, h):
    ...     return {"name": name, "experiment": name, "tracker": t, "n_hit": h, "n_wrong": 0,
    ...             "n_missed": 10 - h, "n_false": 0, "n_quiet": 0}
    >>> pred = pd.DataFrame([rec("p", t, h) for t, h in (("a", 9), ("b", 5), ("c", 7))])
    >>> real = pd.DataFrame([rec("p", t, h) for t, h in (("a", 8), ("b", 4), ("c", 6))])
    >>> r = compare_by_group(pred, real, {"p": "rig1"})
    >>> r["rig1"]["photographs"], r["rig1"]["hit_rate"]["spearman_rho"], round(r["rig1"]["hit_rate"]["mean_abs_diff"], 3)
    (['p'], 1.0, 0.1)
    """
    out = {}
    matched = set(predicted_photos["name"])
    for g in dict.fromkeys(groups.values()):
        names = [n for n, gg in groups.items() if gg == g and n in matched]
        if names:
            out[g] = {"photographs": names, **_compare(_pooled_figures(predicted_photos, "name", names),
                                                       _pooled_figures(real_metrics, "experiment", names))}
    return out


def comparison_doc(result: dict) -> dict:
    """The JSON form of one :func:`compare_with_real` or :func:`compare_by_group` entry: per figure
    ``spearman_rho``, ``spearman_p``, ``mean_abs_diff``, ``n`` and the per-tracker ``table`` (and
    ``photographs`` when the entry names them)."""
    doc = {"photographs": result["photographs"]} if "photographs" in result else {}
    for f in COMPARED:
        v = result[f]
        doc[f] = {k: v[k] for k in ("spearman_rho", "spearman_p", "mean_abs_diff", "n", "table")}
    return doc


def per_group_error(groups: dict) -> dict:
    """Per figure (:data:`COMPARED`), the mean over the groups of :func:`compare_by_group`'s ``mean_abs_diff``
    (groups whose figure has no tracker are left out; NaN when none has one): the error a user of one group (one
    rig, one case) meets, where the pooled comparison lets errors of unlike groups cancel.

    Examples
    --------
    >>> g = {"a": {f: {"mean_abs_diff": 0.25} for f in COMPARED}, "b": {f: {"mean_abs_diff": 0.75} for f in COMPARED}}
    >>> per_group_error(g)
    {'hit_rate': 0.5, 'f1': 0.5, 'false_report_rate': 0.5}
    """
    out = {}
    for f in COMPARED:
        vals = [float(v[f]["mean_abs_diff"]) for v in groups.values() if np.isfinite(v[f]["mean_abs_diff"])]
        out[f] = float(np.mean(vals)) if vals else float("nan")
    return out


def stepped_up(r: float) -> float:
    """The Spearman-Brown step-up ``2 r / (1 + r)`` of a split-half correlation ``r``: the reliability of the whole
    set. NaN for ``r <= 0``: halves that do not agree have no reliability to step up (the formula would give a
    "reliability" beyond -1 as ``r`` falls below -1/3).

    Examples
    --------
    >>> stepped_up(0.5), stepped_up(1.0), stepped_up(-0.34)
    (0.6666666666666666, 1.0, nan)
    """
    r = float(r)
    return 2.0 * r / (1.0 + r) if r > 0.0 else float("nan")


def rank_reliability(real_metrics, names, *, n_splits: int = RELIABILITY_SPLITS, seed: int = 0) -> dict:
    """How repeatable the measured ranks of the trackers are: per figure (:data:`COMPARED`), Spearman's rho between
    the figures measured on two random halves of the photographs ``names`` (rows pooled within each half), over
    ``n_splits`` seeded splits.

    Parameters
    ----------
    real_metrics : pandas.DataFrame
        A real run's ``metrics`` (per-image rows with the row-outcome counts ``n_hit`` ...).
    names : sequence of str
        The photographs (at least :data:`RELIABILITY_MIN_PHOTOS`).
    n_splits : int
        Random halves drawn (>= 1).
    seed : int
        Their seed.

    Returns
    -------
    dict
        Figure -> ``split_half_rho`` (the median over the splits; NaN where no split ranks), ``iqr`` ([25th, 75th]
        percentile) and ``full_set`` (:func:`stepped_up`: the reliability of the ranks measured on all the
        photographs; NaN where the halves do not agree) and ``n_splits`` (the splits that ranked). Read as test-retest
        reliability: a prediction of the trackers' true figures is expected to correlate with the measured ranks by
        about ``sqrt(full_set)`` (one made from the same photographs shares their particulars and may do better on
        them, not on other photographs; docs/predict.md).

    Examples
    --------
    >>> import pandas as pd
    >>> rows = [{"experiment": f"p{i}", "tracker": t, "n_hit": h, "n_wrong": 0, "n_missed": 10 - h, "n_false": 0,
    ...          "n_quiet": 0} for i in range(6) for t, h in (("a", 9), ("b", 5), ("c", 7))]
    >>> rank_reliability(pd.DataFrame(rows), [f"p{i}" for i in range(6)], n_splits=20)["hit_rate"]["split_half_rho"]
    1.0
    """
    from bench.evaluate.outcomes import detection_figures

    names = _checked_names(names, "split in halves", n_splits=n_splits)
    _, per_tracker = _count_stack(real_metrics, "experiment", names, "`real_metrics`")
    counts = np.stack(list(per_tracker.values()), axis=1)  # (photographs, trackers, 5)
    rng = np.random.default_rng(seed)
    pairs = []
    for _ in range(int(n_splits)):
        order = rng.permutation(len(names))
        halves = [[detection_figures(c) for c in counts[idx].sum(axis=0)]
                  for idx in np.array_split(order, [len(names) // 2])]
        pairs.append(halves)
    rhos = _ranked_rhos(pairs)
    out = {}
    for f in COMPARED:
        if rhos[f]:
            r = float(np.median(rhos[f]))
            q = [float(v) for v in np.percentile(rhos[f], [25, 75])]
            full = stepped_up(r)
        else:
            r, q, full = float("nan"), [float("nan")] * 2, float("nan")
        out[f] = {"split_half_rho": r, "iqr": q, "full_set": full, "n_splits": len(rhos[f])}
    return out


def rank_interval(predicted_photos, real_metrics, names, *, n_draws: int = INTERVAL_DRAWS, seed: int = 0,
                  level: float = 0.95) -> dict:
    """How far the rank correlation of predicted and measured figures rests on which photographs were taken: per
    figure (:data:`COMPARED`), the central ``level`` interval of Spearman's rho between the trackers' predicted and
    measured figures, both sides pooled over the same bootstrap resample of the photographs ``names`` (drawn with
    replacement, ``n_draws`` seeded draws; a photograph drawn twice counts its rows twice).

    Parameters
    ----------
    predicted_photos : pandas.DataFrame
        :func:`bench.run.predict.run_predict`'s ``predicted_photos`` (``name``, ``tracker``, the counts ``n_hit`` ...,
        and ``n_false_cut``, ``n_quiet_cut`` where it has them).
    real_metrics : pandas.DataFrame
        A real run's ``metrics`` (per-image rows with the row-outcome counts).
    names : sequence of str
        The photographs (at least :data:`RELIABILITY_MIN_PHOTOS`), each on both sides.
    n_draws : int
        Resamples (>= 1).
    seed : int
        Their seed.
    level : float
        The interval's coverage, in (0, 1).

    Returns
    -------
    dict
        Figure -> ``interval`` ([low, high]), ``median`` (NaN where no resample ranks) and ``n_draws`` (the resamples
        whose figures rank on both sides: at least 3 trackers with a figure, not all equal).

    Examples
    --------
    Four photographs on which the prediction orders three trackers as the measurement does:

    >>> import pandas as pd
    >>> hits = pd.DataFrame({"name": [f"p{i}" for i in range(4) for _ in "abc"], "tracker": list("abc") * 4,
    ...                      "n_hit": [9, 5, 7] * 4, "n_wrong": 0, "n_missed": [1, 5, 3] * 4,
    ...                      "n_false": 0, "n_quiet": 0})
    >>> real = hits.rename(columns={"name": "experiment"}).assign(n_hit=[8, 4, 6] * 4, n_missed=[2, 6, 4] * 4)
    >>> pred = hits
    >>> rank_interval(pred, real, ["p0", "p1", "p2", "p3"], n_draws=50)["hit_rate"]
    {'interval': [1.0, 1.0], 'median': 1.0, 'n_draws': 50}
    """
    names = _checked_names(names, "resample", n_draws=n_draws)
    if not 0.0 < float(level) < 1.0:
        raise ValueError(f"`level` must lie in (0, 1), got {level!r}")
    pred_keys, pred = _count_stack(predicted_photos, "name", names, "both tables")
    real_keys, real = _count_stack(real_metrics, "experiment", names, "both tables")
    trackers = [t for t in pred if t in real]
    P = np.stack([pred[t] for t in trackers], axis=1)  # (photographs, trackers, counts)
    R = np.stack([real[t] for t in trackers], axis=1)
    rng = np.random.default_rng(seed)
    pairs = []
    for _ in range(int(n_draws)):
        idx = rng.integers(0, len(names), len(names))
        pairs.append([[predicted_figures(dict(zip(keys, (int(v) for v in row)))) for row in stack[idx].sum(axis=0)]
                      for keys, stack in ((pred_keys, P), (real_keys, R))])
    rhos = _ranked_rhos(pairs)
    tail = 50.0 * (1.0 - float(level))
    return {f: {"interval": ([float(v) for v in np.percentile(rhos[f], [tail, 100.0 - tail])] if rhos[f]
                             else [float("nan")] * 2),
                "median": float(np.median(rhos[f])) if rhos[f] else float("nan"), "n_draws": len(rhos[f])}
            for f in COMPARED}


def _checked_names(names, purpose: str, **count) -> list:
    """``names`` as distinct strings, refused unless at least :data:`RELIABILITY_MIN_PHOTOS` (to ``purpose``) and the
    one keyword ``count`` (its name and value) an integer >= 1."""
    names = list(dict.fromkeys(str(n) for n in names))
    if len(names) < RELIABILITY_MIN_PHOTOS:
        raise ValueError(f"`names` must hold at least {RELIABILITY_MIN_PHOTOS} photographs to {purpose}, "
                         f"got {len(names)}")
    (key, n), = count.items()
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"`{key}` must be an integer >= 1, got {n!r}")
    return names


def _ranked_rhos(pairs) -> dict:
    """Figure (:data:`COMPARED`) -> the list of Spearman's rho, one per pair of ``pairs`` (each two sides' per-tracker
    :func:`~bench.evaluate.outcomes.detection_figures`, lists in one tracker order) where at least 3 trackers have
    the figure on both sides and neither side's are all equal (else none: no ranks to compare), in the pairs' order.
    The pairs whose trackers all have the figure are ranked together, row by row, the others one by one."""
    from scipy.stats import rankdata

    out = {}
    for f in COMPARED:
        x = np.array([[d[FIGURE_KEYS[f]] for d in a] for a, _ in pairs], dtype=np.float64).reshape(len(pairs), -1)
        y = np.array([[d[FIGURE_KEYS[f]] for d in b] for _, b in pairs], dtype=np.float64).reshape(len(pairs), -1)
        ok = np.isfinite(x) & np.isfinite(y)
        rho = np.full(len(pairs), np.nan)
        whole = ok.all(axis=1) & (x.shape[1] >= 3)
        if whole.any():  # Pearson's r of the ranks, every row at once
            rx, ry = rankdata(x[whole], axis=1), rankdata(y[whole], axis=1)
            rx -= rx.mean(axis=1, keepdims=True)
            ry -= ry.mean(axis=1, keepdims=True)
            den = np.sqrt((rx * rx).sum(axis=1) * (ry * ry).sum(axis=1))
            with np.errstate(invalid="ignore", divide="ignore"):
                rho[whole] = np.where(den > 0, (rx * ry).sum(axis=1) / den, np.nan)  # a side all equal: no ranks
        for i in np.flatnonzero(~whole & (ok.sum(axis=1) >= 3)):
            xi, yi = x[i, ok[i]], y[i, ok[i]]
            if np.ptp(xi) > 0 and np.ptp(yi) > 0:
                rho[i] = float(np.corrcoef(rankdata(xi), rankdata(yi))[0, 1])
        out[f] = [float(v) for v in rho if np.isfinite(v)]
    return out


def _count_stack(df, name_col: str, names, table: str) -> tuple:
    """``(keys, {tracker: counts})``: the row-outcome count columns of ``df`` (:data:`COUNT_KEYS` and a prediction's
    ``n_false_cut``, ``n_quiet_cut``) and per tracker an integer array (photographs ``names``, keys), 0 where a
    photograph has no row; a name missing from ``df`` (the caller's ``table``, as its message names it) is refused."""
    import pandas as pd

    from bench.evaluate.outcomes import COUNT_KEYS

    sub = df.assign(**{name_col: df[name_col].astype(str), "tracker": df["tracker"].astype(str)})
    missing = sorted(set(names) - set(sub[name_col]))
    if missing:
        raise ValueError(f"`names` must be photographs of {table}, got {', '.join(map(repr, missing[:3]))}"
                         + (f" and {len(missing) - 3} more" if len(missing) > 3 else ""))
    keys = [k for k in (*COUNT_KEYS[:5], "n_false_cut", "n_quiet_cut") if k in sub.columns]
    table = sub[sub[name_col].isin(set(names))].groupby([name_col, "tracker"])[keys].sum()
    return keys, {t: table.reindex(pd.MultiIndex.from_product([names, [t]]), fill_value=0).to_numpy(dtype=np.int64)
                  for t in dict.fromkeys(sub["tracker"])}


def _pooled_figures(df, name_col: str, names) -> dict:
    """Figure -> tracker -> value from the row-outcome counts of ``df``'s rows of ``names``, pooled
    (:func:`predicted_figures`: a prediction's false-report frames count where ``df`` has them)."""
    from bench.evaluate.outcomes import COUNT_KEYS

    sub = df[df[name_col].isin(set(names))]
    keys = [k for k in (*COUNT_KEYS, "n_false_cut", "n_quiet_cut") if k in sub.columns]
    out: dict = {f: {} for f in COMPARED}
    for lab, rows in sub.groupby("tracker", sort=False):
        fig = predicted_figures({k: int(rows[k].sum()) for k in keys})
        for f in COMPARED:
            out[f][str(lab)] = fig[FIGURE_KEYS[f]]
    return out


def _compare(predicted: dict, measured: dict) -> dict:
    from bench.evaluate.simreal import sim_to_real

    out = {}
    for f in COMPARED:
        res = sim_to_real(predicted[f], measured[f])
        diffs = [abs(row["delta"]) for row in res["table"]]
        res["mean_abs_diff"] = float(np.mean(diffs)) if diffs else float("nan")
        out[f] = res
    return out
