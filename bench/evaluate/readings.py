"""The paper's "method without DP", read three ways, and its claim tested per reading.

Wang et al. (2008) compare DP with "a simple method such as threshold" and say
of it only: "For those rows with the laser light undetectable, the depth of the
corresponding point could not be computed" (sec. 2) and, of Fig. 10, "Those
black points with big errors are points with laser light undetectable"
(sec. 4.3). A ``threshold`` tracker setting is one of three readings of that
method (:func:`reading_of`):

``"filled"``
    the derived threshold, rows it misses filled linearly along the row
    (``restore = "rows"``): the paper never describes this;
``"gaps"``
    the derived threshold, rows it misses have no depth (``restore = "none"``):
    sec. 2's "could not be computed"; such a sample cannot be a point in Fig. 10
    and counts as outside every band;
``"argmax"``
    the brightest pixel of every row (a negative ``threshold``: every pixel of
    an 8-bit frame is above it): every sample has a depth, and where the
    stripe is too dim for the threshold the brightest pixel is often elsewhere:
    sec. 4.3's black points with big errors.

:data:`PAPER_READING` is the one the paper's text supports. The paper's claim
has three parts, each tested with its interval (:func:`paper_claims`): most
samples within ±5 mm with DP, DP more precise than the method without it, and
"a 30 % improvement in the precision" (the RMSE ratio ``1 - S_DP / S_noDP``).
The verdict on that size (:func:`improvement_verdict`) says "not determined" where
the ratio's interval holds the claim but is as wide as the claim itself.

Pure functions: the run's tables (as in ``summary.json``) in, dicts out.
"""

from __future__ import annotations

import numpy as np

from bench.evaluate.formats import interval, pct, signed_interval, signed_pct
from bench.evaluate.outcomes import PAPER_IMPROVEMENT, WITHIN_MM, within

__all__ = ["READINGS", "PAPER_READING", "PAPER_WHY", "reading_of", "improvement_verdict", "claim_verdicts",
           "claims_of", "paper_claims", "claim_sentence", "headline_group", "headline_lines", "CLAIM_WORDS"]

READINGS = {
    "filled": "threshold, missed rows filled along the row",
    "gaps": "threshold, missed rows have no depth",
    "argmax": "the brightest pixel of every row",
}
PAPER_READING = "argmax"
PAPER_WHY = ("the paper's Fig. 10 (sec. 4.3) shows the method without DP as black points, and \"those black points "
             "with big errors are points with laser light undetectable\": those points have a depth, and a wrong "
             "one, which only the brightest pixel of every row gives; sec. 2's \"the depth of the corresponding "
             "point could not be computed\" is the gaps reading, whose missing points cannot be drawn in Fig. 10; "
             "the paper never describes filling missed rows")


def reading_of(setting, run_restore: str = "rows") -> str | None:
    """Which reading of the paper's method without DP a tracker setting is.

    Parameters
    ----------
    setting : str or dict
        A configuration's tracker entry (a name, or ``{label, name, params[, restore]}``).
    run_restore : str
        The run's ``restore`` (used when the setting carries none).

    Returns
    -------
    ``"filled"``, ``"gaps"``, ``"argmax"`` (see the module docstring) or None
    for any other setting (another tracker, or a fixed non-negative threshold).

    Examples
    --------
    >>> reading_of("threshold"), reading_of({"label": "g", "name": "threshold", "restore": "none"})
    ('filled', 'gaps')
    >>> reading_of({"label": "a", "name": "threshold", "params": {"threshold": -1.0}}), reading_of("dp4")
    ('argmax', None)
    """
    if isinstance(setting, str):
        setting = {"name": setting}
    if setting.get("name") != "threshold":
        return None
    thr = setting.get("params", {}).get("threshold")
    if thr is not None:
        return "argmax" if thr < 0 else None
    return "gaps" if (setting.get("restore") or run_restore) == "none" else "filled"


def _interval_result(low: float, high: float, above: float) -> str:
    if not (np.isfinite(low) and np.isfinite(high)):
        return "undefined"
    if low > above:
        return "above"
    if high < above:
        return "below"
    return "contains"


def improvement_verdict(low: float, high: float, claim: float = PAPER_IMPROVEMENT,
                        max_width: float | None = None) -> str:
    """The verdict on the paper's size of improvement from the RMSE ratio's interval.

    The rule, in order:

    1. ``"undefined"``: no finite interval (fewer than 2 pairs);
    2. ``"exceeded"``: the interval lies above ``claim`` (``low > claim``);
    3. ``"not reproduced"``: the interval lies below ``claim`` (``high < claim``);
    4. the interval holds ``claim``: ``"reproduced"`` only when it is narrower than
       ``max_width`` (``high - low < max_width``; default ``claim`` itself, so that a
       reproduced ratio also excludes no improvement at all), else ``"not determined"``:
       an interval as wide as the claim cannot tell the claim from no improvement or
       from twice the claim (e.g. +86 % [+3, +94] resting on one gross error).

    Parameters
    ----------
    low, high : float
        The ratio's 95 % interval (fractions; NaN without one).
    claim : float
        The paper's ratio (:data:`bench.evaluate.outcomes.PAPER_IMPROVEMENT`).
    max_width : float, optional
        The widest interval that still decides "reproduced" (default ``claim``).

    Examples
    --------
    >>> improvement_verdict(0.03, 0.94), improvement_verdict(0.22, 0.41), improvement_verdict(0.98, 0.99)
    ('not determined', 'reproduced', 'exceeded')
    >>> improvement_verdict(-0.02, 0.28), improvement_verdict(float("nan"), float("nan"))
    ('not reproduced', 'undefined')
    """
    width = claim if max_width is None else max_width
    result = _interval_result(low, high, claim)
    if result == "contains":
        return "reproduced" if high - low < width else "not determined"
    return {"above": "exceeded", "below": "not reproduced", "undefined": "undefined"}[result]


def claim_verdicts(verdict: dict, ratio: dict | None, paper_improvement: float = PAPER_IMPROVEMENT) -> dict:
    """The paper's three claims on one (DP, baseline) pair of one group.

    Parameters
    ----------
    verdict : dict
        A :func:`bench.evaluate.tables.verdicts` entry (``within``, ``rmse`` winners,
        ``dp_figures``, ``baseline_figures``).
    ratio : dict or None
        The pair's RMSE entry of :func:`bench.evaluate.tables.improvements`.
    paper_improvement : float
        The paper's ratio (:data:`bench.evaluate.outcomes.PAPER_IMPROVEMENT`).

    Returns
    -------
    dict with ``most_within`` ("reproduced" when DP's Wilson interval of the ±5 mm
    fraction lies above 1/2, "not reproduced" below, else "undecided"),
    ``more_precise`` ("reproduced": DP wins by a statistic and loses by none;
    "contradicted": the baseline wins by one and DP by none; "mixed"; "not shown":
    both intervals overlap) and ``improvement`` (:func:`improvement_verdict` of the
    ratio's interval).

    Examples
    --------
    >>> fig = lambda w, lo, hi: {"within": w, "within_low": lo, "within_high": hi}
    >>> v = {"dp": "d", "baseline": "b", "within": "d", "rmse": "tie", "dp_figures": fig(0.9, 0.85, 0.94),
    ...      "baseline_figures": fig(0.6, 0.5, 0.7)}
    >>> claim_verdicts(v, {"value": 0.5, "low": 0.35, "high": 0.7})
    {'most_within': 'reproduced', 'more_precise': 'reproduced', 'improvement': 'exceeded'}
    """
    d, b = verdict["dp"], verdict["baseline"]
    fd = verdict["dp_figures"]
    most = {"above": "reproduced", "below": "not reproduced", "contains": "undecided",
            "undefined": "undecided"}[_interval_result(fd["within_low"], fd["within_high"], 0.5)]
    wins = {verdict["within"], verdict["rmse"]}
    if d in wins and b in wins:
        precise = "mixed"
    elif d in wins:
        precise = "reproduced"
    elif b in wins:
        precise = "contradicted"
    else:
        precise = "not shown"
    r = ratio or {}
    imp = improvement_verdict(r.get("low", np.nan), r.get("high", np.nan), paper_improvement)
    return {"most_within": most, "more_precise": precise, "improvement": imp}


def claims_of(entry: dict, paper_improvement: float = PAPER_IMPROVEMENT) -> dict:
    """The claims of a :func:`paper_claims` entry as every view shows them: the entry's own, with the
    improvement's verdict taken again by :func:`improvement_verdict` from the ratio's interval it holds
    (a summary written under an earlier rule shows the current one).

    Examples
    --------
    >>> e = {"claims": {"most_within": "reproduced", "more_precise": "reproduced", "improvement": "reproduced"},
    ...      "figures": {"ratio_low": 0.03, "ratio_high": 0.94}}
    >>> claims_of(e)["improvement"]
    'not determined'
    """
    f = entry["figures"]
    return {**entry["claims"], "improvement": improvement_verdict(f.get("ratio_low", np.nan),
                                                                  f.get("ratio_high", np.nan), paper_improvement)}


def headline_group(robust: list[dict], conditions: list[dict]) -> tuple[str, list[str]] | None:
    """The statistics group of the configuration's first condition (the paper's) and
    its experiment keys: ``condition:<name>`` when the run grouped conditions, else
    the condition's first experiment; None without conditions."""
    if not conditions:
        return None
    groups = {r["group"] for r in robust}
    c = conditions[0]
    g = f"condition:{c['condition']}"
    return (g if g in groups else c["experiments"][0]), list(c["experiments"])






def paper_claims(config: dict, robust: list[dict], improvement: list[dict], verdicts: list[dict],
                 conditions: list[dict], samples=None, *, paper_improvement: float = PAPER_IMPROVEMENT,
                 within_mm: float = WITHIN_MM) -> list[dict]:
    """The paper's claim in its own condition, per reading of its method without DP.

    For each baseline of ``config`` that is a reading (:func:`reading_of`), in the
    configuration's order, the claims of :func:`claim_verdicts` for the first DP
    label against it in the first condition (:func:`headline_group`), with the
    figures behind them and one plain sentence. If no baseline is a reading, the
    first baseline is reported (``reading`` None).

    Parameters
    ----------
    config : dict
        The configuration (``Config.to_dict()``: ``trackers``, ``baselines``, ``dp``, ``restore``).
    robust, improvement, verdicts, conditions : list of dict
        The run's tables (``summary.json``'s ``robust``, ``improvement``, ``verdicts``, ``conditions``).
    samples : pandas.DataFrame, optional
        The run's sample table; with it, for each reading, how many of the
        baseline's samples outside ±``within_mm`` lie where a derived-threshold
        reading has no depth of its own (``outside_undetectable``: the paper's
        "points with laser light undetectable").
    paper_improvement, within_mm : float

    Returns
    -------
    list of dict: ``baseline, reading, description, paper_reading, dp, group,
    experiments, claims, figures`` (the ±5 mm fractions, the RMSE ratio with ``n``,
    ``n_samples``, ``n_missing_dp``, ``n_missing_baseline``), ``outside``,
    ``outside_undetectable`` (None without ``samples`` or without a derived-threshold
    reading) and ``sentence``. Empty without a DP label, a baseline or conditions.
    """
    dps, bases = list(config.get("dp", [])), list(config.get("baselines", []))
    hg = headline_group(robust, conditions)
    if not dps or not bases or hg is None:
        return []
    group, keys = hg
    dp = dps[0]
    run_restore = config.get("restore", "rows")
    settings = {}
    for t in config.get("trackers", []):
        settings[t if isinstance(t, str) else t["label"]] = t
    kinds = {b: reading_of(settings.get(b, b), run_restore) for b in bases}
    chosen = [b for b in bases if kinds[b] is not None] or bases[:1]
    verd = {(v["group"], v["dp"], v["baseline"]): v for v in verdicts}
    ratios = {(i["group"], i["dp"], i["baseline"]): i for i in improvement if i["statistic"] == "rmse"}
    undetect = None
    sub = None
    if samples is not None and len(samples):
        sub = samples[samples["experiment"].isin(keys)]
        ref = next((b for b in bases if kinds[b] == "filled"), None)
        gap = next((b for b in bases if kinds[b] == "gaps"), None)
        if ref is not None:
            undetect = sub[f"filled_{ref}"].to_numpy(bool)
        elif gap is not None:
            undetect = np.isnan(sub[f"error_mm_{gap}"].to_numpy(float))
    out = []
    for b in chosen:
        v = verd.get((group, dp, b))
        if v is None:
            continue
        r = ratios.get((group, dp, b)) or {}
        claims = claim_verdicts(v, r, paper_improvement)
        fd, fb = v["dp_figures"], v["baseline_figures"]
        outside = outside_u = None
        if sub is not None:
            e = sub[f"error_mm_{b}"].to_numpy(float)
            far = ~within(e, within_mm)  # no value counts as outside
            outside = int(far.sum())
            if undetect is not None:
                outside_u = int((far & undetect).sum())
        kind = kinds[b]
        desc = READINGS.get(kind, f"baseline {b}")
        figures = {"dp_within": fd["within"], "dp_within_low": fd["within_low"], "dp_within_high": fd["within_high"],
                   "baseline_within": fb["within"], "baseline_within_low": fb["within_low"],
                   "baseline_within_high": fb["within_high"], "n": fd["n"],
                   **{f"ratio_{k}": r.get(k, float("nan")) for k in ("value", "low", "high")},
                   "ratio_n": r.get("n", 0),
                   **{k: r.get(k, 0) for k in ("n_samples", "n_missing_dp", "n_missing_baseline")}}
        entry = {"baseline": b, "reading": kind, "description": desc, "paper_reading": kind == PAPER_READING,
                 "dp": dp, "group": group, "experiments": keys, "claims": claims, "figures": figures,
                 "outside": outside, "outside_undetectable": outside_u}
        entry["sentence"] = claim_sentence(entry, within_mm, paper_improvement)
        out.append(entry)
    return out


#: The words of each verdict in the sentences and the terminal's headline (:func:`claim_sentence`,
#: :func:`headline_lines`); ``{b}`` is the baseline, ``{claim}`` the paper's ratio.
CLAIM_WORDS = {
    "most_within": {"reproduced": "reproduced", "not reproduced": "not reproduced", "undecided": "undecided"},
    "more_precise": {"reproduced": "reproduced", "contradicted": "contradicted ({b} is more precise)",
                     "mixed": "mixed (the two statistics disagree)", "not shown": "not shown (the intervals overlap)"},
    "improvement": {"reproduced": "reproduced", "exceeded": "exceeded (DP improves more than {claim})",
                    "not reproduced": "not reproduced",
                    "not determined": "not determined (the interval is as wide as the {claim} claimed)",
                    "undefined": "undefined (too few pairs)"},
}


def _words(part: str, verdict: str, b: str, paper_improvement: float) -> str:
    return CLAIM_WORDS[part][verdict].format(b=b, claim=pct(paper_improvement))


def claim_sentence(entry: dict, within_mm: float = WITHIN_MM, paper_improvement: float = PAPER_IMPROVEMENT) -> str:
    """One plain-text sentence on a :func:`paper_claims` entry (not HTML: escape it to show it)."""
    f, c, b, d = entry["figures"], claims_of(entry, paper_improvement), entry["baseline"], entry["dp"]
    ratio = f"RMSE ratio {signed_pct(f['ratio_value'])} {signed_interval(f['ratio_low'], f['ratio_high'])}"
    if f.get("n_missing_dp") or f.get("n_missing_baseline"):
        ratio += (f" over the {f['ratio_n']} of {f['n_samples']} pairs where both have a depth ({b} has none at "
                  f"{f['n_missing_baseline']}, {d} at {f['n_missing_dp']})")
    precise = _words("more_precise", c["more_precise"], b, paper_improvement)
    imp = _words("improvement", c["improvement"], b, paper_improvement)
    head = f"{b} ({entry['description']})" if entry["reading"] else b
    s = (f"Against {head}: {d} puts {pct(f['dp_within'])} {interval(f['dp_within_low'], f['dp_within_high'])} of the "
         f"samples within ±{within_mm:g} mm (most samples: {c['most_within']}) against "
         f"{pct(f['baseline_within'])} {interval(f['baseline_within_low'], f['baseline_within_high'])}; "
         f"DP more precise: {precise}; the {pct(paper_improvement)} improvement: {imp}, {ratio}.")
    if entry.get("outside") and entry.get("outside_undetectable") is not None and entry["reading"] != "filled":
        s += (f" {entry['outside_undetectable']} of {b}'s {entry['outside']} samples outside ±{within_mm:g} mm lie "
              f"where the threshold detects no stripe.")
    return s


def headline_lines(summary: dict) -> list[str]:
    """The run's headline as plain text lines (what ``stripebench reproduce`` prints, the report's
    headline in words): the paper's claim in its condition, one line per reading of its method
    without DP (``summary["paper_claims"]``), each part's verdict (:func:`claims_of`) with its figures.
    Empty without claims.

    Examples
    --------
    >>> headline_lines({})
    []
    """
    claims = summary.get("paper_claims") or []
    if not claims:
        return []
    within = summary.get("within_mm", WITHIN_MM)
    claim = summary.get("paper_improvement", PAPER_IMPROVEMENT)
    c0 = claims[0]
    title = next((c["condition"] for c in summary.get("conditions", [])), c0["group"])
    if title.lower().startswith("the paper's condition: "):
        title = title[len("the paper's condition: "):]
    lines = [f"The paper's claim in its condition ({title}; {', '.join(c0['experiments'])}; "
             f"{c0['figures']['n']} sample points; DP = {c0['dp']}), 95 % intervals, per reading of its "
             "method without DP:"]
    for e in claims:
        f, c, b = e["figures"], claims_of(e, claim), e["baseline"]
        who = b + (f" ({e['description']})" if e["reading"] else "")
        if e.get("paper_reading"):
            who += ", the reading the paper's text supports"
        pairs = ""
        if f.get("n_missing_dp") or f.get("n_missing_baseline"):
            pairs = f" over {f['ratio_n']} of {f['n_samples']} pairs"
        lines.append(
            f"  {who}: most within ±{within:g} mm with DP: {_words('most_within', c['most_within'], b, claim)} "
            f"({pct(f['dp_within'])} {interval(f['dp_within_low'], f['dp_within_high'])} against "
            f"{pct(f['baseline_within'])} {interval(f['baseline_within_low'], f['baseline_within_high'])}); "
            f"DP more precise: {_words('more_precise', c['more_precise'], b, claim)}; the {pct(claim)} improvement: "
            f"{_words('improvement', c['improvement'], b, claim)}; RMSE ratio {signed_pct(f['ratio_value'])} "
            f"{signed_interval(f['ratio_low'], f['ratio_high'])}{pairs}")
    return lines
