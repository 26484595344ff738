"""The prediction judged leave one rig out against the null prediction, and what it may then claim.

For each rig of a labelled set held out in turn (:func:`bench.evaluate.loro.rig_folds`), ``predict``'s figures for its
photographs are set against the figures measured on them, and so are the *null prediction*'s: each tracker's mean
measured figure over the other rigs (:func:`bench.evaluate.loro.null_prediction`). Both are scored the same way
(:func:`evaluate`):

- the error of a figure: the mean over trackers of |predicted - measured|;
- the regret of the pick: the best measured F1 less the measured F1 of the tracker ranked first;
- the coverage of the stated intervals (the share holding the measured figure) and their mean width. An interval is
  the figure +- a split-conformal half-width (:func:`conformal_half_width`) of the |predicted - measured| of the other
  rigs (the held-out rig never calibrates its own interval; each other rig's null is taken without it too).

Where the method's figure is not closer than the null's over the held-out rigs, ``predict`` states the null's,
labelled so (:func:`calibration`), and its pick is the null's where that one's regret is lower. The chance that the
pick is best (:func:`chance_best`) comes from draws of the photographs resampled, each with a rig's own error vector
added. Every rig weighs the same. Pure functions: arrays and tables in, numbers out.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["FIGURES", "SOURCES", "rig_table", "conformal_half_width", "f1_of_counts", "chance_best", "evaluate",
           "calibration", "stated"]

#: The figures judged, as ``predict`` names them, and their :func:`bench.evaluate.outcomes.detection_figures` keys.
FIGURES = {"hit_rate": "recall", "f1": "f1", "false_report_rate": "false_report_rate"}
#: How ``predict`` labels a stated figure (:func:`stated`), by its source in the calibration: the method's own
#: (``predicted``), the shipped set's mean (``null``), or the method's where no calibration covers the tracker.
SOURCES = {"method": "predicted", "null": "null (the shipped set's mean)", None: "predicted, uncalibrated"}


def rig_table(df, name_col: str, rig_of: dict, rigs, trackers) -> dict:
    """Figure (:data:`FIGURES`) -> array (rigs, trackers): each rig's figure per tracker, its photographs' rows pooled
    (:func:`bench.evaluate.prediction.predicted_figures`: a prediction's false-report frames count where ``df`` has
    them); NaN where a rig has no photograph in ``df`` or the figure is undefined.

    Parameters
    ----------
    df : pandas.DataFrame
        Per-photograph rows: ``name_col``, ``tracker`` and the row-outcome counts ``n_hit`` ...
    rig_of : dict
        Photograph name -> rig; photographs not in it are left out.

    Examples
    --------
    >>> import pandas as pd
    >>> df = pd.DataFrame({"name": ["a", "b", "a"], "tracker": ["t", "t", "u"], "n_hit": [8, 2, 5], "n_wrong": 0,
    ...                    "n_missed": [2, 8, 5], "n_false": 0, "n_quiet": 0})
    >>> rig_table(df, "name", {"a": "r1", "b": "r2"}, ["r1", "r2"], ["t", "u"])["hit_rate"].tolist()
    [[0.8, 0.5], [0.2, nan]]
    """
    from bench.evaluate.outcomes import COUNT_KEYS
    from bench.evaluate.prediction import predicted_figures

    rigs, trackers = list(rigs), list(trackers)
    out = {f: np.full((len(rigs), len(trackers)), np.nan) for f in FIGURES}
    keys = [k for k in (*COUNT_KEYS, "n_false_cut", "n_quiet_cut") if k in df.columns]
    sub = df.assign(_rig=df[name_col].astype(str).map(rig_of)).dropna(subset=["_rig"])
    for (rig, lab), rows in sub.groupby(["_rig", "tracker"], sort=False):
        if rig in rigs and str(lab) in trackers:
            fig = predicted_figures({k: int(rows[k].sum()) for k in keys})
            for f, key in FIGURES.items():
                out[f][rigs.index(rig), trackers.index(str(lab))] = fig[key]
    return out


def conformal_half_width(residuals, level: float) -> float:
    """The split-conformal half-width of absolute ``residuals`` at ``level``: their ceil((n + 1) level)-th smallest
    (NaN and inf left out); inf where that rank exceeds n (too few residuals to promise the level).

    Examples
    --------
    >>> conformal_half_width([0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07, 0.08, 0.09], 0.8)
    0.08
    >>> conformal_half_width([0.1, 0.2], 0.8)
    inf
    """
    r = np.sort(np.abs(np.asarray(residuals, dtype=np.float64).ravel()))
    r = r[np.isfinite(r)]
    if not 0.0 < level < 1.0:
        raise ValueError(f"`level` must lie in (0, 1), got {level!r}")
    k = math.ceil((r.size + 1) * level)
    return float(r[k - 1]) if 0 < k <= r.size else float("inf")


def f1_of_counts(counts) -> np.ndarray:
    """F1 over rows of row-outcome counts (..., >= 5: hit, wrong, missed, false, quiet), NaN where undefined.

    Examples
    --------
    >>> f1_of_counts([[8, 1, 1, 2, 8, 0]]).round(4).tolist()
    [0.7619]
    """
    c = np.asarray(counts, dtype=np.float64)
    h, w, m, f = c[..., 0], c[..., 1], c[..., 2], c[..., 3]
    den = 2 * h + 2 * w + m + f
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(den > 0, 2 * h / den, np.nan)


def chance_best(point, residuals, photo_counts=None, *, n_draws: int = 1000, seed: int = 0) -> dict:
    """How sure a pick is: draws of every tracker's F1, each the ``point`` figures (T,) plus the error vector
    (measured - stated, (T,), NaN read as 0) of a rig of ``residuals`` (R, T) drawn at random and, with
    ``photo_counts`` (P, T, 5+: each photograph's row-outcome counts), the photographs resampled with replacement
    (their pooled F1 less their F1 on all of them).

    Returns
    -------
    dict
        ``pick``: the index of the highest finite ``point``; ``chance``: (T,) the share of draws in which each tracker
        has the highest F1; ``beats``: (T,) the share in which each stands at least as high as the pick.

    Examples
    --------
    >>> r = chance_best([0.9, 0.8, 0.89], [[0.0, 0.0, 0.02], [0.0, 0.0, -0.02]], n_draws=400)
    >>> r["pick"], [round(x, 1) for x in r["chance"]], [round(x, 1) for x in r["beats"]]
    (0, [0.6, 0.0, 0.4], [1.0, 0.0, 0.4])
    """
    point = np.asarray(point, dtype=np.float64)
    if not np.isfinite(point).any():
        raise ValueError("`point` has no finite figure to pick from")
    res = np.nan_to_num(np.asarray(residuals, dtype=np.float64).reshape(-1, point.size), nan=0.0)
    rng = np.random.default_rng(seed)
    draws = np.tile(np.where(np.isfinite(point), point, -np.inf), (n_draws, 1))
    if res.shape[0]:
        draws += res[rng.integers(0, res.shape[0], n_draws)]
    if photo_counts is not None:
        pc = np.asarray(photo_counts, dtype=np.float64)
        whole = np.nan_to_num(f1_of_counts(pc.sum(axis=0)), nan=0.0)
        idx = rng.integers(0, pc.shape[0], (n_draws, pc.shape[0]))
        boot = np.nan_to_num(f1_of_counts(pc[idx].sum(axis=1)), nan=0.0)
        draws += boot - whole[None, :]
    pick = int(np.nanargmax(np.where(np.isfinite(point), point, -np.inf)))
    best = draws.argmax(axis=1)
    chance = np.bincount(best, minlength=point.size) / n_draws
    beats = (draws >= draws[:, [pick]]).mean(axis=0)
    return {"pick": pick, "chance": chance.tolist(), "beats": beats.tolist()}


def _mean_abs(a, b) -> float:
    d = np.abs(np.asarray(a) - np.asarray(b))
    d = d[np.isfinite(d)]
    return float(d.mean()) if d.size else float("nan")


def _interval_stats(stated, measured, half) -> tuple[int, int, float]:
    """(intervals holding the measured figure, intervals with a measured figure, their summed width, clipped to
    [0, 1]) of ``stated`` +- ``half``."""
    ok = np.isfinite(stated) & np.isfinite(measured)
    lo, hi = np.clip(stated - half, 0.0, 1.0), np.clip(stated + half, 0.0, 1.0)
    inside = ok & (measured >= lo - 1e-12) & (measured <= hi + 1e-12)
    return int(inside.sum()), int(ok.sum()), float((hi - lo)[ok].sum())


def _regret(stated_f1, measured_f1) -> float:
    """Best measured F1 less the measured F1 of the tracker ``stated_f1`` ranks first (NaN without a measured F1)."""
    m = np.asarray(measured_f1, dtype=np.float64)
    s = np.asarray(stated_f1, dtype=np.float64)
    if not np.isfinite(m).any() or not np.isfinite(s).any():
        return float("nan")
    pick = int(np.nanargmax(np.where(np.isfinite(s), s, -np.inf)))
    return float(np.nanmax(m) - (m[pick] if np.isfinite(m[pick]) else 0.0))


def _nulls(measured: np.ndarray, keep) -> np.ndarray:
    """(R, T): each kept rig's null (the mean of the other kept rigs' figures, NaN where none has one); NaN rows for
    the rigs not kept."""
    from bench.evaluate.loro import null_prediction

    idx = [i for i in range(measured.shape[0]) if keep[i]]
    out = np.full(measured.shape, np.nan)
    if len(idx) < 2:
        return out
    by = null_prediction({str(i): measured[i] for i in idx})
    for i in idx:
        out[i] = by[str(i)]
    return out


def evaluate(predicted: dict, measured: dict, rigs, trackers, *, level: float = 0.8, photo_counts=None,
             n_draws: int = 1000, seed: int = 0, adjust: str = "none", answered=None, tie_chance: float = 0.1) -> dict:
    """Leave one rig out: the method's figures and the null's, each rig held out in turn (module docstring).

    Parameters
    ----------
    predicted, measured : dict
        Figure (:data:`FIGURES`) -> array (rigs, trackers) (:func:`rig_table`). A rig whose predicted figure is NaN
        (no photograph predicted) is stated the null's figure, as ``predict`` states it.
    rigs, trackers : sequence of str
        The rows' and columns' names.
    level : float
        The intervals' nominal coverage (split conformal).
    photo_counts : dict, optional
        Rig -> (P, T, 5+) its predicted photographs' row-outcome counts: with them each fold also states the chance
        that the method's pick is best (:func:`chance_best`, the other rigs' errors; ``n_draws``, ``seed``), and the
        pooled figures say how often the pick was the best measured, and how often the best measured was the pick or a
        tracker tied with it (best in at least ``tie_chance`` of the draws).
    adjust : {'none', 'blend', 'bias'}
        How the method's figures are adjusted on each fold's training rigs before they are stated (:data:`ADJUSTS`,
        :func:`fit_adjust`): a candidate judged here.
    answered : array_like, shape (rigs,), optional
        Each rig's share of photographs with an answer: its stated figure is then that share of the method's and the
        rest the null's (:func:`with_unanswered`).

    Returns
    -------
    dict
        ``rigs``: rig -> per figure ``method`` and ``null`` (``error``, ``covered``, ``n_intervals``, ``width``,
        ``half_width``), ``regret`` (``method``, ``null``), ``n_null`` (trackers stated the null for want of a
        prediction); ``pooled``: per figure and source the mean error over rigs, the coverage over every interval and
        the mean width, and the mean regrets; ``level``, ``rigs_order``, ``trackers``.

    Examples
    --------
    Three rigs, two trackers; the method off by 0.01 everywhere, the rigs far apart:

    >>> m = {f: np.array([[0.9, 0.5], [0.6, 0.8], [0.7, 0.7]]) for f in FIGURES}
    >>> p = {f: v + 0.01 for f, v in m.items()}
    >>> e = evaluate(p, m, ["a", "b", "c"], ["t", "u"], level=0.5)
    >>> round(e["pooled"]["f1"]["method"]["error"], 3), round(e["pooled"]["f1"]["null"]["error"], 3)
    (0.01, 0.167)
    >>> e["pooled"]["regret"]["method"], round(e["pooled"]["regret"]["null"], 3)
    (0.0, 0.2)
    """
    rigs, trackers = [str(r) for r in rigs], [str(t) for t in trackers]
    R = len(rigs)
    if R < 3:
        raise ValueError(f"leave one rig out with calibration needs at least three rigs, got {R}")
    per_rig, tallies = {}, {f: {s: [0, 0, 0.0, []] for s in ("method", "null")} for f in FIGURES}
    regrets = {"method": [], "null": []}
    for i, rig in enumerate(rigs):
        train = np.arange(R) != i
        entry = {"n_null": int(np.sum(~np.isfinite(predicted["f1"][i]) & np.isfinite(measured["f1"][i])))}
        stated_f1 = {}
        for f in FIGURES:
            m = measured[f]
            null_i = _nulls(m, np.ones(R, bool))[i]  # the other rigs' mean
            inner = _nulls(m, train)  # each calibration rig's null without it and without the held-out rig
            share = np.ones(R) if answered is None else np.asarray(answered, dtype=np.float64)
            fit = fit_adjust(adjust, predicted[f][train], m[train], inner[train])
            own = with_unanswered(apply_adjust(adjust, fit, predicted[f][i], null_i), null_i, share[i])
            stated = {"method": own, "null": null_i}
            calib = {"method": with_unanswered(apply_adjust(adjust, fit, predicted[f][train], inner[train]),
                                               inner[train], share[train][:, None]), "null": inner[train]}
            entry[f] = {}
            for s in ("method", "null"):
                half = conformal_half_width(calib[s] - m[train], level)
                cov, n, width = _interval_stats(stated[s], m[i], half)
                err = _mean_abs(stated[s], m[i])
                entry[f][s] = {"error": err, "covered": cov, "n_intervals": n, "width": width / n if n else math.nan,
                               "half_width": half}
                t = tallies[f][s]
                t[0] += cov
                t[1] += n
                t[2] += width
                t[3].append(err)
            if f == "f1":
                stated_f1 = stated
        entry["regret"] = {s: _regret(stated_f1[s], measured["f1"][i]) for s in ("method", "null")}
        m_f1 = measured["f1"][i]
        if photo_counts is not None and np.isfinite(stated_f1["method"]).any() and np.isfinite(m_f1).any():
            res = (measured["f1"] - np.where(np.isfinite(predicted["f1"]), predicted["f1"], _nulls(measured["f1"],
                                                                                                   train)))[train]
            pc = photo_counts.get(rig)
            cb = chance_best(stated_f1["method"], res, pc if pc is not None and len(pc) else None,
                             n_draws=n_draws, seed=seed)
            tied = [j for j, c in enumerate(cb["chance"]) if j == cb["pick"] or c >= tie_chance]
            best = int(np.nanargmax(np.where(np.isfinite(m_f1), m_f1, -np.inf)))
            entry["chance"] = {"stated": cb["chance"][cb["pick"]],
                               "best": bool(np.isfinite(m_f1[cb["pick"]]) and m_f1[cb["pick"]] >= np.nanmax(m_f1)),
                               "in_tie": bool(best in tied or m_f1[tied].max() >= m_f1[best]), "n_tied": len(tied)}
        for s in regrets:
            regrets[s].append(entry["regret"][s])
        per_rig[rig] = entry

    def mean(v):
        v = [x for x in v if np.isfinite(x)]
        return float(np.mean(v)) if v else float("nan")

    pooled = {f: {s: {"error": mean(t[3]), "coverage": t[0] / t[1] if t[1] else math.nan,
                      "width": t[2] / t[1] if t[1] else math.nan, "n_intervals": t[1]}
                  for s, t in by.items()} for f, by in tallies.items()}
    pooled["regret"] = {s: mean(v) for s, v in regrets.items()}
    ch = [e["chance"] for e in per_rig.values() if "chance" in e]
    pooled["chance"] = {"stated": mean([c["stated"] for c in ch]), "best": mean([float(c["best"]) for c in ch]),
                        "in_tie": mean([float(c["in_tie"]) for c in ch]), "n_tied": mean([c["n_tied"] for c in ch]),
                        "n_rigs": len(ch)}
    return {"rigs": per_rig, "pooled": pooled, "level": float(level), "rigs_order": rigs, "trackers": trackers,
            "adjust": adjust}


#: The adjustments of the method's figures judged leave one rig out (docs/predict.md, "Declared before they ran"):
#: ``none``; ``blend``, ``w`` x the method's + (1 - ``w``) x the null's, ``w`` of :data:`BLEND_WEIGHTS` with the least
#: mean error on the fitting rigs; ``bias``, each tracker's figure less its mean error on them.
ADJUSTS = ("none", "blend", "bias")
#: The weights ``blend`` chooses among.
BLEND_WEIGHTS = tuple(round(0.1 * k, 1) for k in range(11))


def fit_adjust(kind: str, predicted, measured, null):
    """The adjustment ``kind`` (:data:`ADJUSTS`) fitted on rigs' (n, T) figures: None, the blend's weight, or each
    tracker's mean error (T,).

    Examples
    --------
    >>> p, m = np.array([[0.9, 0.8], [0.7, 0.6]]), np.array([[0.8, 0.7], [0.6, 0.5]])
    >>> fit_adjust("bias", p, m, m).round(3).tolist(), fit_adjust("blend", p, m, m)
    ([0.1, 0.1], 0.0)
    """
    if kind not in ADJUSTS:
        raise ValueError(f"`adjust` must be one of {', '.join(ADJUSTS)}, got {kind!r}")
    if kind == "none":
        return None
    p, m, n = (np.asarray(x, dtype=np.float64) for x in (predicted, measured, null))
    if kind == "bias":
        d = p - m
        with np.errstate(invalid="ignore"):
            return np.where(np.isfinite(d).any(axis=0), np.nanmean(np.where(np.isfinite(d), d, np.nan), axis=0)
                            if np.isfinite(d).any() else 0.0, 0.0)
    best = None
    for w in BLEND_WEIGHTS:
        s = apply_adjust("blend", w, p, n)
        e = np.mean([x for x in (_mean_abs(s[k], m[k]) for k in range(len(s))) if np.isfinite(x)] or [np.inf])
        if best is None or e < best[0] - 1e-12:
            best = (e, w)
    return best[1]


def with_unanswered(stated, null, share) -> np.ndarray:
    """A rig's stated figures with its photographs that have no answer counted at the ``null``'s: ``share`` (the
    photographs with an answer, 0-1) of ``stated`` and the rest of ``null`` (the null's where ``stated`` is NaN).

    Examples
    --------
    >>> with_unanswered(np.array([0.9, np.nan]), np.array([0.5, 0.6]), 0.75).round(3).tolist()
    [0.8, 0.6]
    """
    s, n = np.asarray(stated, dtype=np.float64), np.asarray(null, dtype=np.float64)
    mixed = share * s + (1.0 - share) * n
    return np.where(np.isfinite(mixed), mixed, np.where(np.isfinite(s), s, n))


def apply_adjust(kind: str, fit, predicted, null) -> np.ndarray:
    """The method's figures ``predicted`` adjusted by ``fit`` (:func:`fit_adjust`), the ``null``'s where it has none.

    Examples
    --------
    >>> apply_adjust("blend", 0.5, np.array([0.9, np.nan]), np.array([0.7, 0.6])).round(3).tolist()
    [0.8, 0.6]
    """
    p, n = np.asarray(predicted, dtype=np.float64), np.asarray(null, dtype=np.float64)
    if kind == "blend":
        s = fit * p + (1.0 - fit) * n
    elif kind == "bias":
        s = p - fit
    else:
        s = p
    return np.where(np.isfinite(s), s, n)


def calibration(predicted: dict, measured: dict, rigs, trackers, loro: dict, answered=None) -> dict:
    """What ``predict`` states for a rig outside the set, from every rig of it, and the leave-one-rig-out figures that
    back it (``loro``: :func:`evaluate` of the same tables; ``answered``: each rig's share of photographs with an
    answer, as :func:`evaluate` read it).

    Returns
    -------
    dict
        Per figure: ``source`` (``method`` where its leave-one-rig-out error is below the null's, else ``null``),
        ``half_width`` of each source (split conformal over every rig's errors; the null's each rig's without it),
        ``null`` (tracker -> the mean of the rigs' measured figures), and the leave-one-rig-out ``coverage``,
        ``width`` and ``error`` of each source; ``pick``: ``source`` (the method's pick where its regret is lower)
        and both ``regret`` figures; ``residuals``: per source, rig -> the signed F1 errors (measured - stated) per
        tracker, the draws of :func:`chance_best`; ``level``, ``rigs``, ``trackers``.

    Examples
    --------
    >>> m = {f: np.array([[0.9, 0.5], [0.6, 0.8], [0.7, 0.7]]) for f in FIGURES}
    >>> p = {f: v + 0.01 for f, v in m.items()}
    >>> c = calibration(p, m, ["a", "b", "c"], ["t", "u"], evaluate(p, m, ["a", "b", "c"], ["t", "u"], level=0.5))
    >>> c["f1"]["source"], c["pick"]["source"], round(c["f1"]["half_width"]["method"], 3), c["f1"]["null"]["u"]
    ('method', 'method', 0.01, 0.6666666666666666)
    """
    from bench.evaluate.loro import null_prediction

    rigs, trackers = [str(r) for r in rigs], [str(t) for t in trackers]
    level = loro["level"]
    out = {"level": level, "rigs": rigs, "trackers": trackers}
    residuals = {}
    for f in FIGURES:
        m = measured[f]
        null_each = null_prediction({r: m[i] for i, r in enumerate(rigs)})
        inner = np.array([null_each[r] for r in rigs])
        share = np.ones(len(rigs)) if answered is None else np.asarray(answered, dtype=np.float64)
        stated = {"method": with_unanswered(predicted[f], inner, share[:, None]), "null": inner}
        with np.errstate(invalid="ignore"):
            overall = np.nanmean(np.where(np.isfinite(m), m, np.nan), axis=0) if np.isfinite(m).any() else \
                np.full(len(trackers), np.nan)
        lp = loro["pooled"][f]
        better = lp["method"]["error"] < lp["null"]["error"]
        out[f] = {"source": "method" if better else "null",
                  "half_width": {s: conformal_half_width(stated[s] - m, level) for s in stated},
                  "null": {t: float(v) for t, v in zip(trackers, overall)},
                  **{k: {s: lp[s][k] for s in lp} for k in ("coverage", "width", "error")}}
        if f == "f1":
            residuals = {s: {r: [float(x) for x in (m[i] - stated[s][i])] for i, r in enumerate(rigs)}
                         for s in stated}
    reg = loro["pooled"]["regret"]
    out["pick"] = {"source": "method" if reg["method"] < reg["null"] else "null", "regret": dict(reg)}
    out["residuals"] = residuals
    return out


def stated(predicted: dict, trackers, calib: dict | None, photo_counts=None, *, answered: float = 1.0,
           n_draws: int = 1000, tie_chance: float = 0.2, seed: int = 0) -> dict:
    """What ``predict`` states for a rig's photographs: each figure from the source the calibration chose, with its
    interval, and the pick with its chance of being best and the trackers tied with it.

    Parameters
    ----------
    predicted : dict
        Figure (:data:`FIGURES`) -> (T,): the method's figures for these photographs (NaN: none predicted).
    trackers : sequence of str
        The T trackers.
    calib : dict or None
        :func:`calibration`'s (a tracker it does not list has no null); None: every figure the method's, labelled
        uncalibrated, without an interval.
    photo_counts : array_like, shape (P, T, 5+), optional
        Each predicted photograph's row-outcome counts (the F1 draws resample them).
    answered : float
        The share of the rig's photographs with an answer: the rest count at the null's figure
        (:func:`with_unanswered`), where the calibration has one.
    n_draws, tie_chance, seed
        :func:`chance_best`'s draws; a tracker that is the best in at least ``tie_chance`` of them is tied with the
        pick.

    Returns
    -------
    dict
        Per figure: ``value``, ``lo``, ``hi`` (T,) and ``source`` (T,, :data:`SOURCES`' labels); ``pick`` (its name
        or None), ``pick_source``, ``chance`` (T,), ``tied`` (the names tied with the pick, itself left out).

    Examples
    --------
    >>> m = {f: np.array([[0.9, 0.5], [0.6, 0.8], [0.7, 0.7]]) for f in FIGURES}
    >>> p = {f: v + 0.01 for f, v in m.items()}
    >>> c = calibration(p, m, ["a", "b", "c"], ["t", "u"], evaluate(p, m, ["a", "b", "c"], ["t", "u"], level=0.5))
    >>> s = stated({f: np.array([0.95, 0.4]) for f in FIGURES}, ["t", "u"], c, n_draws=200)
    >>> s["pick"], s["tied"], s["f1"]["source"][0], [round(float(x), 2) for x in (s["f1"]["lo"][0], s["f1"]["hi"][0])]
    ('t', [], 'predicted', [0.94, 0.96])
    >>> stated({f: np.array([0.95, np.nan]) for f in FIGURES}, ["t", "u"], None)["f1"]["source"]
    ['predicted, uncalibrated', 'predicted, uncalibrated']
    """
    trackers = [str(t) for t in trackers]
    T = len(trackers)
    out = {}
    for f in FIGURES:
        p = np.asarray(predicted[f], dtype=np.float64)
        if calib is None or f not in calib:
            out[f] = {"value": p, "lo": np.full(T, np.nan), "hi": np.full(T, np.nan), "source": [SOURCES[None]] * T}
            continue
        c = calib[f]
        null = np.array([c["null"].get(t, np.nan) for t in trackers], dtype=np.float64)
        known = np.array([t in c["null"] for t in trackers])
        use_null = known & ((c["source"] == "null") | ~np.isfinite(p))
        value = np.where(use_null, null, np.where(known, with_unanswered(p, null, answered), p))
        half = np.where(use_null, c["half_width"]["null"], c["half_width"]["method"])
        half = np.where(known, half, np.nan)
        out[f] = {"value": value, "lo": np.clip(value - half, 0.0, 1.0), "hi": np.clip(value + half, 0.0, 1.0),
                  "source": [SOURCES["null"] if u else SOURCES["method"] if k else SOURCES[None]
                             for u, k in zip(use_null, known)]}
    pick_source = None if calib is None else calib["pick"]["source"]
    if pick_source == "null":
        point = np.array([calib["f1"]["null"].get(t, np.nan) for t in trackers], dtype=np.float64)
        counts = None
    else:
        point, counts = np.asarray(predicted["f1"], dtype=np.float64), photo_counts
        if calib is not None:  # the method's own, its unanswered photographs at the null's
            null = np.array([calib["f1"]["null"].get(t, np.nan) for t in trackers], dtype=np.float64)
            point = np.where(np.isfinite(null), with_unanswered(point, null, answered), point)
        if not np.isfinite(point).any() and calib is not None:  # nothing predicted: the null's pick
            point = np.array([calib["f1"]["null"].get(t, np.nan) for t in trackers], dtype=np.float64)
            pick_source, counts = "null", None
    if not np.isfinite(point).any():
        return {**out, "pick": None, "pick_source": pick_source, "chance": [math.nan] * T, "tied": []}
    res = np.zeros((0, T))
    if calib is not None:
        by = calib["residuals"]["null" if pick_source == "null" else "method"]
        order = list(calib["trackers"])
        res = np.array([[v[order.index(t)] if t in order else 0.0 for t in trackers] for v in by.values()])
    cb = chance_best(point, res, counts, n_draws=n_draws, seed=seed)
    tied = [t for j, t in enumerate(trackers) if j != cb["pick"] and cb["chance"][j] >= tie_chance]
    return {**out, "pick": trackers[cb["pick"]], "pick_source": pick_source, "chance": cb["chance"], "tied": tied}
