"""Sim-to-real numbers: one tracker on one photograph, and synthetic against real figures across trackers.

Pure functions (arrays and dicts in, numbers out). The hit rule is
:data:`bench.evaluate.outcomes.HIT_PX` (:func:`bench.evaluate.outcomes.hits`), the one every table uses.
Renders and photographs are compared on :data:`FIGURES`: the hit rate (the stripe half, on the
object's stripe rows), and F1 over rows and the false-report rate (both halves, every row of known
state), each by :func:`sim_to_real`, :func:`sim_to_real_headline` and :func:`sim_to_real_by_class`.
"""

from __future__ import annotations

import math

import numpy as np

from bench.evaluate.outcomes import HIT_PX, hits

__all__ = ["image_metrics", "sim_to_real", "sim_to_real_sentences", "sim_to_real_headline", "class_real_hit_rates",
           "sim_to_real_by_class", "FIGURES", "DETECTION_FIGURES"]

#: The figures renders and photographs are compared on -> their name in sentences: the hit rate (stripe rows; a
#: synthetic run's ``object`` region), and F1 over rows and the false-report rate (:data:`DETECTION_FIGURES`:
#: a synthetic run's ``all`` region, the photographs' rows of known state), which see a false report.
FIGURES = {"hit_rate": "hit rate", "f1": "F1 over rows", "false_report_rate": "false-report rate"}
#: The figures of :data:`FIGURES` that price a false report.
DETECTION_FIGURES = ("f1", "false_report_rate")


def image_metrics(columns, reference, tol_px: float = HIT_PX, *, state=None, score=None) -> dict[str, float]:
    """One tracker on one photograph.

    Parameters
    ----------
    columns : array_like, shape (H,)
        The tracker's columns (px), NaN where it reports nothing.
    reference : array_like, shape (H,)
        Reference columns (px), NaN where there is none.
    tol_px : float
        A reference row is a hit when ``|col - ref| <= tol_px``.
    state : array_like of int, shape (H,), optional
        The rows' states (stripe, no stripe, unknown: :mod:`bench.evaluate.outcomes`); default
        the fallback rule on ``reference`` (:func:`bench.evaluate.outcomes.fallback_states`).
    score : array_like, shape (H,), optional
        The tracker's per-row score (for ``ap``).

    Returns
    -------
    dict
        ``hit_rate`` (hits / reference rows; a missing detection is a miss),
        ``mae_px`` (mean ``|col - ref|`` over the hits), ``coverage`` (reference
        rows with a detection), ``n_ref``; then the row outcomes
        ``n_hit`` ... ``n_unknown``, ``precision``, ``recall``, ``f1``,
        ``false_report_rate`` (reports on rows with no stripe, over those rows: a row
        whose state is unknown is neither) and ``ap`` (NaN without ``score``),
        ``ap_constant``. NaN where undefined.

    Examples
    --------
    >>> m = image_metrics([10.0, 14.0, np.nan, 3.0], [11.0, 10.0, 5.0, np.nan], state=[1, 1, 1, 0])
    >>> m["hit_rate"], m["mae_px"], m["coverage"]
    (0.3333333333333333, 1.0, 0.6666666666666666)
    >>> m["n_false"], m["precision"], m["false_report_rate"]
    (1, 0.3333333333333333, 1.0)
    """
    from bench.evaluate.outcomes import fallback_states
    from bench.evaluate.ranking import outcome_record

    if not (isinstance(tol_px, (int, float)) and tol_px >= 0 and math.isfinite(tol_px)):
        raise ValueError(f"`tol_px` must be a finite number >= 0, got {tol_px!r}")
    c = np.asarray(columns, dtype=np.float64)
    r = np.asarray(reference, dtype=np.float64)
    if c.shape != r.shape or c.ndim != 1:
        raise ValueError(f"`columns` {c.shape} and `reference` {r.shape} must be 1-D of the same length")
    has_ref = ~np.isnan(r)
    n_ref = int(has_ref.sum())
    det = ~np.isnan(c)
    err = np.abs(c[has_ref] - r[has_ref])
    hit = hits(c[has_ref], r[has_ref], tol_px)
    out = {
        "hit_rate": float(hit.sum() / n_ref) if n_ref else float("nan"),
        "mae_px": float(err[hit].mean()) if hit.any() else float("nan"),
        "coverage": float(det[has_ref].sum() / n_ref) if n_ref else float("nan"),
        "n_ref": n_ref,
    }
    out.update(outcome_record(c, r, fallback_states(r) if state is None else state, score, tol_px))
    return out


def sim_to_real(synthetic_hit_rates: dict, real_hit_rates: dict) -> dict:
    """Compare the hit rates the renders predict with those measured on photographs.

    Parameters
    ----------
    synthetic_hit_rates, real_hit_rates : dict
        Tracker label -> hit rate in [0, 1]; only labels in both are compared.

    Returns
    -------
    dict
        ``table``: list of ``{tracker, synthetic, real, delta, rank_synthetic,
        rank_real}`` sorted by real hit rate (rank 1 = best, ties averaged);
        ``spearman_rho``, ``spearman_p`` (``scipy.stats.spearmanr`` across
        trackers; NaN with fewer than 3 trackers or constant rates); ``n``.

    Examples
    --------
    >>> r = sim_to_real({"a": 0.9, "b": 0.5, "c": 0.7}, {"a": 0.6, "b": 0.2, "c": 0.4, "d": 0.1})
    >>> r["n"], r["spearman_rho"], r["table"][0]["tracker"]
    (3, 1.0, 'a')
    """
    from scipy.stats import rankdata, spearmanr

    for arg, d in (("synthetic_hit_rates", synthetic_hit_rates), ("real_hit_rates", real_hit_rates)):
        if not isinstance(d, dict):
            raise ValueError(f"`{arg}` must be a dict of tracker -> hit rate, got {type(d).__name__}")
        for k, v in d.items():
            if not isinstance(v, (int, float)) or (not math.isnan(v) and not 0.0 <= v <= 1.0):
                raise ValueError(f"`{arg}[{k!r}]` must be a hit rate in [0, 1], got {v!r}")
    labels = [k for k in synthetic_hit_rates if k in real_hit_rates
              and not math.isnan(synthetic_hit_rates[k]) and not math.isnan(real_hit_rates[k])]
    s = np.array([synthetic_hit_rates[k] for k in labels], dtype=float)
    r = np.array([real_hit_rates[k] for k in labels], dtype=float)
    rank_s = rankdata(-s) if labels else np.array([])
    rank_r = rankdata(-r) if labels else np.array([])
    table = [{"tracker": k, "synthetic": float(s[i]), "real": float(r[i]), "delta": float(r[i] - s[i]),
              "rank_synthetic": float(rank_s[i]), "rank_real": float(rank_r[i])} for i, k in enumerate(labels)]
    table.sort(key=lambda t: (-t["real"], t["tracker"]))
    rho = p = float("nan")
    if len(labels) >= 3 and np.ptp(s) > 0 and np.ptp(r) > 0:
        res = spearmanr(s, r)
        rho, p = float(res.statistic), float(res.pvalue)
    return {"table": table, "spearman_rho": rho, "spearman_p": p, "n": len(labels)}


def sim_to_real_sentences(result: dict, *, margin: float = 0.10, figure: str | None = None) -> list[str]:
    """Plain sentences on a :func:`sim_to_real` result: the rank agreement, then
    the trackers whose real figure lies more than ``margin`` below (renders
    over-predict) or above (under-predict) the synthetic one. ``figure`` (a name of
    :data:`FIGURES`) starts each sentence; without it the figure is the hit rate.

    Examples
    --------
    >>> r = sim_to_real({"a": 0.9, "b": 0.5, "c": 0.7}, {"a": 0.6, "b": 0.45, "c": 0.7})
    >>> sim_to_real_sentences(r)[1]
    'The renders over-predict a (synthetic 0.90, real 0.60).'
    >>> sim_to_real_sentences(r, figure="F1 over rows")[1]
    'F1 over rows: the renders over-predict a (synthetic 0.90, real 0.60).'
    """
    if figure is not None:
        return [f"{figure}: {t[0].lower()}{t[1:]}" for t in sim_to_real_sentences(result, margin=margin)]
    out = []
    rho, n = result["spearman_rho"], result["n"]
    if n < 3 or math.isnan(rho):
        out.append(f"Too few trackers with distinct figures ({n}) for a rank correlation.")
    else:
        word = "agree" if rho >= 0.7 else "partly agree" if rho >= 0.3 else "do not agree"
        out.append(f"Synthetic and real rankings of {n} trackers {word} (Spearman's rho = {rho:.2f}).")
    over = [t for t in result["table"] if t["delta"] < -margin]
    under = [t for t in result["table"] if t["delta"] > margin]

    def fmt(ts):
        return ", ".join(f"{t['tracker']} (synthetic {t['synthetic']:.2f}, real {t['real']:.2f})" for t in ts)

    if over:
        out.append(f"The renders over-predict {fmt(over)}.")
    if under:
        out.append(f"The renders under-predict {fmt(under)}.")
    if not over and not under and result["table"]:
        out.append(f"Every tracker's real figure lies within {margin:.2f} of the synthetic one.")
    return out


def sim_to_real_headline(result: dict, *, margin: float = 0.10) -> list[str]:
    """The sentences of a run's sim-to-real comparison, both halves: those of the hit rates
    (:func:`sim_to_real_sentences` of ``result``, each starting ``hit rate:``), then those of each
    figure of ``result["detection"]`` (F1 over rows, the false-report rate: :data:`DETECTION_FIGURES`).

    Examples
    --------
    >>> r = sim_to_real({"a": 0.9, "b": 0.5, "c": 0.7}, {"a": 0.85, "b": 0.5, "c": 0.7})
    >>> r["detection"] = {"false_report_rate": sim_to_real({"a": 0.0, "b": 0.1, "c": 0.3}, {"a": 0.4, "b": 0.1, "c": 0.3})}
    >>> sim_to_real_headline(r)[-1]
    'false-report rate: the renders under-predict a (synthetic 0.00, real 0.40).'
    """
    out = sim_to_real_sentences(result, margin=margin, figure=FIGURES["hit_rate"])
    for k, r in (result.get("detection") or {}).items():
        out += sim_to_real_sentences(r, margin=margin, figure=FIGURES.get(k, k))
    return out


def class_real_hit_rates(real_by_image: dict, image_class: dict) -> dict:
    """Each class's real figure per tracker (a hit rate, or any figure of :data:`FIGURES`): the mean over
    its photographs where it is defined.

    Parameters
    ----------
    real_by_image : dict
        Photograph name -> {tracker label -> figure in [0, 1] (NaN: undefined, e.g. no reference rows)}.
    image_class : dict
        Photograph name -> class (a manifest's ``condition``; ``""`` = untagged, left out).

    Returns
    -------
    dict
        class -> ``{"photographs": [names, sorted], "hit_rates": {tracker: mean over the
        photographs with a finite rate}}``; photographs without a class are left out.

    Examples
    --------
    >>> r = class_real_hit_rates({"p": {"a": 0.2}, "q": {"a": 0.6}, "x": {"a": 1.0}},
    ...                          {"p": "c1", "q": "c1", "x": ""})
    >>> r["c1"]["photographs"], round(r["c1"]["hit_rates"]["a"], 6)
    (['p', 'q'], 0.4)
    """
    for arg, d in (("real_by_image", real_by_image), ("image_class", image_class)):
        if not isinstance(d, dict):
            raise ValueError(f"`{arg}` must be a dict, got {type(d).__name__}")
    out: dict = {}
    for name in sorted(real_by_image):
        cls = str(image_class.get(name, "") or "").strip()
        if not cls:
            continue
        entry = out.setdefault(cls, {"photographs": [], "_rates": {}})
        entry["photographs"].append(name)
        for label, v in real_by_image[name].items():
            if isinstance(v, (int, float)) and not math.isnan(v):
                entry["_rates"].setdefault(label, []).append(float(v))
    return {c: {"photographs": e["photographs"],
                "hit_rates": {k: float(np.mean(v)) for k, v in e["_rates"].items()}} for c, e in out.items()}


def sim_to_real_by_class(synthetic_by_class: dict, real_by_image: dict, image_class: dict) -> dict:
    """Synthetic against real hit rates (or any one figure of :data:`FIGURES`), matched by class of condition.

    A class is a rendered experiment's ``condition`` and a photograph's manifest
    ``condition``; a class is compared where both sides have it. Per class the
    renders' rates are the run's (mean over the experiments of that condition),
    the real ones the mean over its photographs (:func:`class_real_hit_rates`),
    and :func:`sim_to_real` gives the table and Spearman's rho across trackers.

    Parameters
    ----------
    synthetic_by_class : dict
        Class -> {tracker label -> synthetic hit rate in [0, 1]}.
    real_by_image : dict
        Photograph name -> {tracker label -> real hit rate in [0, 1]}.
    image_class : dict
        Photograph name -> class.

    Returns
    -------
    dict
        ``classes``: one entry per class of either side, sorted by name:
        ``{condition, photographs (names), n_photographs, rendered (bool), table,
        spearman_rho, spearman_p, n}`` (``table`` etc. as :func:`sim_to_real`, empty
        and NaN where the class lacks renders or photographs; rho also NaN with
        fewer than 3 trackers). ``matched``: the classes with both.
        ``overall``: :func:`sim_to_real` of each tracker's mean over the matched
        classes (each class weighs the same on both sides). ``mean_abs_delta``:
        tracker -> mean over the matched classes of ``|synthetic - real|``.

    Examples
    --------
    >>> r = sim_to_real_by_class({"c1": {"a": 0.9, "b": 0.5}, "c2": {"a": 0.4, "b": 0.8}},
    ...                          {"p": {"a": 0.7, "b": 0.2}}, {"p": "c1"})
    >>> r["matched"], [(c["condition"], c["n_photographs"]) for c in r["classes"]]
    (['c1'], [('c1', 1), ('c2', 0)])
    >>> {k: round(v, 6) for k, v in r["mean_abs_delta"].items()}
    {'a': 0.2, 'b': 0.3}
    """
    if not isinstance(synthetic_by_class, dict):
        raise ValueError(f"`synthetic_by_class` must be a dict of class -> {{tracker: hit rate}}, "
                         f"got {type(synthetic_by_class).__name__}")
    real_by_class = class_real_hit_rates(real_by_image, image_class)
    nan = float("nan")
    classes, matched = [], []
    for cls in sorted(set(synthetic_by_class) | set(real_by_class)):
        photos = real_by_class.get(cls, {}).get("photographs", [])
        rendered = cls in synthetic_by_class
        if rendered and photos:
            cmp = sim_to_real(dict(synthetic_by_class[cls]), real_by_class[cls]["hit_rates"])
            matched.append(cls)
        else:
            cmp = {"table": [], "spearman_rho": nan, "spearman_p": nan, "n": 0}
        classes.append({"condition": cls, "photographs": list(photos), "n_photographs": len(photos),
                        "rendered": rendered, **cmp})
    syn_sum: dict = {}
    real_sum: dict = {}
    for c in classes:
        for t in c["table"]:
            syn_sum.setdefault(t["tracker"], []).append(t["synthetic"])
            real_sum.setdefault(t["tracker"], []).append(t["real"])
    # a tracker enters the overall comparison only where it has a rate in every matched class
    full = [k for k, v in syn_sum.items() if len(v) == len(matched)]
    overall = sim_to_real({k: float(np.mean(syn_sum[k])) for k in full},
                          {k: float(np.mean(real_sum[k])) for k in full}) if matched else \
        {"table": [], "spearman_rho": nan, "spearman_p": nan, "n": 0}
    mad = {k: float(np.mean(np.abs(np.array(syn_sum[k]) - np.array(real_sum[k])))) for k in sorted(full)}
    return {"classes": classes, "matched": matched, "overall": overall, "mean_abs_delta": mad}
