"""The declared objective over finished ``predictcheck`` runs (``stripebench predictscore``), and paired differences.

A change of the prediction's rules is judged on renders, where the truth is known (:mod:`bench.studies.predict_check`):
:func:`objective` scores finished runs (the per-case score, the mean over cases of the mean |predicted - measured| of
hit rate and F1; the false-report |difference| beside it; the pooled figures), and :func:`paired` sets runs of two
versions of the code side by side, family by family and seed by seed.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from bench.studies.predict_check import DEFAULTS, FAR

__all__ = ["family_of", "objective", "PAIRED", "paired", "score"]


def family_of(doc: dict) -> str:
    """The render family of a ``predict_check.json`` document: ``native``, or its ``--downscale``, ``--line-fwhm``,
    ``--laser-power``, ``--channel``, ``--distractor``, ``--jpeg-quality`` and ``--truth``, then ``--rows`` and
    ``--states`` where they are not the defaults, after its ``--profile`` where that is not ``field``. A document
    without ``rows`` or ``states`` was scored on ``seen`` rows with ``given`` states.

    Examples
    --------
    >>> now = {"downscale": 1, "line_fwhm_mrad": None, "rows": "clear"}
    >>> family_of(now), family_of({**now, "downscale": 4, "line_fwhm_mrad": 1.2})
    ('native', 'downscale 4, line 1.2 mrad')
    >>> family_of({**now, "channel": "laser"}), family_of({**now, "states": "fallback"})
    ('downscale 1, channel laser', 'native, states fallback')
    >>> family_of({**now, "profile": "marble", "laser_power_mw": 60.0, "jpeg_quality": 75})
    'marble: downscale 1, 60 mW, JPEG 75'
    >>> family_of({"downscale": 1, "line_fwhm_mrad": None})
    'native, rows seen'
    """
    d, lw, mw = int(doc.get("downscale", 1)), doc.get("line_fwhm_mrad"), doc.get("laser_power_mw")
    ch, dis, tr = doc.get("channel", "auto"), doc.get("distractor", "none"), doc.get("truth", "render")
    jq = doc.get("jpeg_quality")
    profile = doc.get("profile", "field")
    if d == 1 and lw is None and mw is None and ch == "auto" and dis == "none" and tr == "render" and jq is None:
        family = "native"
    else:
        family = (f"downscale {d}" + ("" if lw is None else f", line {float(lw):g} mrad")
                  + ("" if mw is None else f", {float(mw):g} mW") + ("" if ch == "auto" else f", channel {ch}")
                  + ("" if dis == "none" else f", {dis}") + ("" if jq is None else f", JPEG {int(jq)}")
                  + ("" if tr == "render" else f", truth {tr}"))
    if doc.get("rows", "seen") != DEFAULTS["rows"]:
        family += f", rows {doc.get('rows', 'seen')}"
    if doc.get("states", "given") != DEFAULTS["states"]:
        family += f", states {doc['states']}"
    return family if profile == "field" else f"{profile}: {family}"


def objective(docs: dict, min_rows: int = 0) -> dict:
    """The declared objective over finished ``predictcheck`` runs (name -> its ``predict_check.json``): per run, the
    *per-case score* (each case's mean |predicted - measured| of hit rate and F1, averaged:
    :func:`bench.evaluate.prediction.per_group_error`), the per-case false-report |difference| (and on the rows a
    reference scores, :data:`bench.studies.predict_check.FAR`), the pooled score and the pooled false-report
    |difference|; then their means over the runs, and the per-case score's mean per family (:func:`family_of`). With
    ``min_rows`` > 0 the per-case figures leave out the cases whose frames hold fewer measured stripe rows (a
    document's ``_case_rows``, case -> rows, from its ``measured.csv``): a hit rate on 15 rows is mostly its own noise;
    the pooled figures keep every case, and each run says how many it left out (``n_left_out``).

    Examples
    --------
    >>> case = lambda h, f, r: {"hit_rate": {"mean_abs_diff": h}, "f1": {"mean_abs_diff": f},
    ...                         "false_report_rate": {"mean_abs_diff": r}}
    >>> doc = {"downscale": 1, "line_fwhm_mrad": None, "rows": "clear", "seed": 1,
    ...        "cases": {"a": case(0.02, 0.04, 0.1), "b": case(0.06, 0.08, 0.3)}, "pooled": case(0.01, 0.03, 0.2)}
    >>> o = objective({"r1": doc})
    >>> round(o["per_case"], 6), round(o["false_report_per_case"], 6), round(o["pooled"], 6), o["families"]
    (0.05, 0.2, 0.02, {'native': 0.05})
    >>> o = objective({"r1": {**doc, "_case_rows": {"a": 600, "b": 15}}}, min_rows=100)
    >>> round(o["per_case"], 6), o["runs"]["r1"]["n_left_out"], round(o["pooled"], 6)
    (0.03, 1, 0.02)
    """
    from bench.evaluate.prediction import per_group_error

    if not docs:
        raise ValueError("`docs` must hold at least one predictcheck run, got none")
    if isinstance(min_rows, bool) or not isinstance(min_rows, (int, np.integer)) or min_rows < 0:
        raise ValueError(f"`min_rows` must be an integer >= 0, got {min_rows!r}")
    runs = {}
    for name, doc in docs.items():
        _check_doc(name, doc)
        cases = doc["cases"]
        if min_rows:
            if "_case_rows" not in doc:
                raise ValueError(f"{name}: leaving out cases by their rows needs the run's measured.csv")
            cases = {k: v for k, v in cases.items() if doc["_case_rows"].get(k, 0) >= min_rows}
            if not cases:
                raise ValueError(f"{name}: no case measured on {min_rows} stripe rows or more")
        err = per_group_error(cases)
        far_vals = [float(v[FAR]["mean_abs_diff"]) for v in cases.values()
                    if FAR in v and np.isfinite(v[FAR]["mean_abs_diff"])]
        far = float(np.mean(far_vals)) if far_vals else float("nan")
        pooled = doc["pooled"]
        runs[name] = {"family": family_of(doc), "seed": doc.get("seed"), "n_left_out": len(doc["cases"]) - len(cases),
                      "per_case": 0.5 * (err["hit_rate"] + err["f1"]), "per_case_hit_rate": err["hit_rate"],
                      "per_case_f1": err["f1"], "false_report_per_case": err["false_report_rate"],
                      "false_report_far_per_case": far,
                      "pooled": 0.5 * (pooled["hit_rate"]["mean_abs_diff"] + pooled["f1"]["mean_abs_diff"]),
                      "pooled_hit_rate": pooled["hit_rate"]["mean_abs_diff"],
                      "pooled_f1": pooled["f1"]["mean_abs_diff"],
                      "pooled_false_report": pooled["false_report_rate"]["mean_abs_diff"]}

    def mean(k):  # over the runs that have the figure (no false-report rows: NaN)
        vals = [r[k] for r in runs.values() if np.isfinite(r[k])]
        return float(np.mean(vals)) if vals else float("nan")

    families: dict = {}
    for r in runs.values():
        families.setdefault(r["family"], []).append(r["per_case"])
    keys = ("per_case", "per_case_hit_rate", "per_case_f1", "false_report_per_case", "false_report_far_per_case",
            "pooled", "pooled_hit_rate", "pooled_f1", "pooled_false_report")
    return {"runs": runs, **{k: mean(k) for k in keys},
            "families": {f: float(np.mean(v)) for f, v in families.items()}}


def _check_doc(name: str, doc) -> None:
    """A ``predict_check.json`` document that :func:`objective` can read, else one ``ValueError`` line naming
    ``name`` and the first thing wrong: a JSON object whose ``cases`` (a non-empty object) and ``pooled`` hold, per
    figure, an object with a numeric ``mean_abs_diff``."""
    if not isinstance(doc, dict):
        raise ValueError(f"{name}: predict_check.json is not a JSON object (a {type(doc).__name__})")
    cases, pooled = doc.get("cases"), doc.get("pooled")
    if not cases or not pooled:
        raise ValueError(f"{name}: a predictcheck run with no case predicted")
    if not isinstance(cases, dict):
        raise ValueError(f"{name}: predict_check.json's `cases` is not an object")
    for where, entry in [("pooled", pooled), *((f"cases.{k}", v) for k, v in cases.items())]:
        for f in ("hit_rate", "f1", "false_report_rate"):
            v = entry.get(f) if isinstance(entry, dict) else None
            x = v.get("mean_abs_diff") if isinstance(v, dict) else None
            if x is not None and (isinstance(x, bool) or not isinstance(x, (int, float))):
                x = None
            if x is None:
                raise ValueError(f"{name}: predict_check.json's `{where}.{f}.mean_abs_diff` is missing or not a number")
        far = entry.get(FAR) if isinstance(entry, dict) else None
        if far is not None and not (isinstance(far, dict) and isinstance(far.get("mean_abs_diff"), (int, float))):
            raise ValueError(f"{name}: predict_check.json's `{where}.{FAR}.mean_abs_diff` is not a number")


#: :func:`paired`'s figures (:func:`objective`'s per-run keys), each with its column's header in ``predictscore``.
PAIRED = {"per_case": "per case", "false_report_per_case": "false-report |diff|", "false_report_far_per_case": "far",
          "pooled": "pooled", "pooled_false_report": "pooled false-report"}


def paired(docs: dict, against: dict, min_rows: int = 0) -> dict:
    """Each run of ``docs`` beside the run of ``against`` of its family and seed (name -> ``predict_check.json``):
    the differences (this minus that) of :func:`objective`'s per-run figures (with ``min_rows``), per pair, and per
    family their mean, least and greatest over the seeds, so that a choice between two versions of the procedure
    sees how far its difference moves from seed to seed.

    Raises
    ------
    ValueError
        A run with no partner of its family and seed in the other set, two runs of one family and seed in one set,
        or a pair made by the same code (both record ``code``, :func:`bench.studies.predict_check.code_of_run`, with
        one ``fingerprint``: their differences are nought by construction, not a finding).

    Examples
    --------
    >>> case = lambda h: {"hit_rate": {"mean_abs_diff": h}, "f1": {"mean_abs_diff": h},
    ...                   "false_report_rate": {"mean_abs_diff": 0.1}}
    >>> doc = lambda seed, h: {"downscale": 1, "line_fwhm_mrad": None, "rows": "clear", "seed": seed,
    ...                        "cases": {"a": case(h)}, "pooled": case(h)}
    >>> p = paired({"n1": doc(1, 0.03), "n2": doc(2, 0.05)}, {"o1": doc(1, 0.02), "o2": doc(2, 0.02)})
    >>> [round(v, 3) for v in p["families"]["native"]["per_case"]], round(p["per_case"], 3)
    ([0.02, 0.01, 0.03], 0.02)
    """
    def keyed(group, which):
        out = {}
        for name, r in objective(group, min_rows)["runs"].items():
            k = (r["family"], r["seed"])
            if k in out:
                raise ValueError(f"{which}: two runs of family {k[0]!r} and seed {k[1]}: {out[k][0]} and {name}")
            out[k] = (name, r)
        return out

    mine, theirs = keyed(docs, "the RUNs"), keyed(against, "--against")
    if set(mine) != set(theirs):
        k = sorted(set(mine) ^ set(theirs), key=str)[0]
        where = "--against has" if k in mine else "the RUNs have"
        raise ValueError(f"{where} no run of family {k[0]!r} and seed {k[1]} to pair with")
    for k in sorted(mine, key=str):
        a, b = (docs[mine[k][0]].get("code") or {}), (against[theirs[k][0]].get("code") or {})
        if a.get("fingerprint") and a.get("fingerprint") == b.get("fingerprint"):
            raise ValueError(f"{mine[k][0]} and {theirs[k][0]} were made by the same code (fingerprint "
                             f"{a['fingerprint']}, revision {a.get('revision', 'unknown')}): a pair compares two "
                             "versions (run each from its own folder: `python -m` imports the folder's `bench` first)")
    keys = tuple(PAIRED)
    pairs = {k: {f: mine[k][1][f] - theirs[k][1][f] for f in keys} | {"runs": (mine[k][0], theirs[k][0])}
             for k in sorted(mine, key=str)}

    def spread(vals):  # mean, least, greatest of the finite ones (a run without the figure: NaN)
        v = [x for x in vals if np.isfinite(x)]
        return (float(np.mean(v)), float(min(v)), float(max(v))) if v else (float("nan"),) * 3

    families: dict = {}
    for (fam, _), d in pairs.items():
        families.setdefault(fam, []).append(d)
    fam_out = {fam: {f: spread([d[f] for d in ds]) for f in keys} | {"n": len(ds)} for fam, ds in families.items()}
    return {"pairs": pairs, "families": fam_out, **{f: spread([d[f] for d in pairs.values()])[0] for f in keys}}


def _read_runs(runs, rows: bool = False) -> dict:
    """Run folder -> its ``predict_check.json`` (checked: :func:`_check_doc`); with ``rows``, each with ``_case_rows``
    (case -> the measured stripe rows of its frames, from ``measured.csv``: hit, wrong and missed rows of its first
    tracker, the same for every tracker since the row states are the frame's)."""
    import pandas as pd

    from bench.errors import InputError
    from bench.store.textfiles import read_json

    docs = {}
    for run in runs:
        path = Path(run) / "predict_check.json"
        try:
            doc = read_json(path, "predictcheck result")
            _check_doc(str(run), doc)
            if rows:
                m = pd.read_csv(Path(run) / "measured.csv")
                m = m[m["tracker"] == m["tracker"].iloc[0]]
                n = (m["n_hit"] + m["n_wrong"] + m["n_missed"]).groupby(m["experiment"].str.rsplit("@", n=1).str[0])
                doc["_case_rows"] = {str(k): int(v) for k, v in n.sum().items()}
        except (InputError, OSError, ValueError, KeyError, IndexError, TypeError, AttributeError) as exc:
            raise ValueError(f"{str(run)!r} is not a finished predictcheck run ({type(exc).__name__}: {exc})") from None
        docs[str(run)] = doc
    return docs


def score(*, runs, against=None, min_rows: int = 0) -> int:
    """``stripebench predictscore RUN [RUN ...] [--against RUN ...] [--min-rows N]``: :func:`objective` over finished
    ``predictcheck`` runs, printed; with ``against``, each run's difference from its partner of the same family and
    seed (:func:`paired`); with ``min_rows``, the per-case figures without the cases measured on fewer stripe rows. 0,
    or 2 with one line on stderr for a folder that is not a finished run or a run without a partner."""
    try:
        docs = _read_runs(runs, rows=bool(min_rows))
        o = objective(docs, min_rows)
        pair = paired(docs, _read_runs(against, rows=bool(min_rows)), min_rows) if against else None
    except ValueError as exc:
        print(f"stripebench predictscore: {str(exc)[:300]}", file=sys.stderr)
        return 2
    fw = max(28, 2 + max(len(r["family"]) for r in o["runs"].values()))
    print(f"{'run':<44}{'family':<{fw}}{'seed':>5}{'per case':>10}{'hit / F1':>16}{'false':>8}{'far':>8}{'pooled':>9}")
    for name, r in o["runs"].items():
        print(f"{name[-43:]:<44}{r['family']:<{fw}}{str(r['seed']):>5}{r['per_case']:>10.4f}"
              f"{r['per_case_hit_rate']:>8.4f} {r['per_case_f1']:.4f}{r['false_report_per_case']:>8.4f}"
              f"{r['false_report_far_per_case']:>8.4f}{r['pooled']:>9.4f}")
    fam = ", ".join(f"{f} {v:.5f}" for f, v in o["families"].items())
    print(f"per-case score {o['per_case']:.5f} ({fam}); false-report |diff| per case {o['false_report_per_case']:.5f} "
          f"(on the rows a photograph's reference scores: {o['false_report_far_per_case']:.5f}); "
          f"pooled score {o['pooled']:.4f} ({len(o['runs'])} runs)")
    print(f"mean |predicted - measured| per case: hit rate {o['per_case_hit_rate']:.4f}, F1 {o['per_case_f1']:.4f}; "
          f"pooled: hit rate {o['pooled_hit_rate']:.4f}, F1 {o['pooled_f1']:.4f}")
    if min_rows:
        left = sum(r["n_left_out"] for r in o["runs"].values())
        total = sum(len(d["cases"]) for d in docs.values())
        print(f"per-case figures without the cases measured on fewer than {min_rows} stripe rows: {left} of {total} "
              "left out (the pooled figures keep them)")
    if pair is not None:
        print(f"paired with --against (these minus those, per family: mean [least, greatest] over "
              f"{len(pair['pairs'])} pairs):")
        print(f"{'family':<{fw}}{'pairs':>6}" + "".join(f"{h:>30}" for h in PAIRED.values()))
        for fam, d in pair["families"].items():
            cells = "".join(f"{d[k][0]:>+12.5f} [{d[k][1]:+.5f}, {d[k][2]:+.5f}]".rjust(30) for k in PAIRED)
            print(f"{fam:<{fw}}{d['n']:>6}{cells}")
        print(f"per-case score {pair['per_case']:+.5f}; false-report |diff| per case "
              f"{pair['false_report_per_case']:+.5f} (far {pair['false_report_far_per_case']:+.5f}); "
              f"pooled score {pair['pooled']:+.5f}, pooled false-report |diff| {pair['pooled_false_report']:+.5f}")
    return 0
