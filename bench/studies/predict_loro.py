"""``stripebench predictloro``: the prediction judged leave one rig out against the null prediction on a labelled set.

The trackers are measured on every photograph of a real set (:func:`bench.run.real.run_real`) and predicted for the
same photographs from the photographs alone (:func:`bench.run.predict.run_predict`, without a calibration: its own
figures). Each rig is then held out in turn (:func:`bench.evaluate.predict_loro.evaluate`): the method's figures for
its photographs and the null's (each tracker's mean over the other rigs) against its measured figures: the error of
F1, of the false-report rate and of the hit rate, the regret of the pick, and the coverage and width of intervals
calibrated on the other rigs. With ``calibration`` the figures that back what ``predict`` states for a new rig are
written there (:func:`bench.evaluate.predict_loro.calibration`; the shipped one is
``bench/data/predict_calibration.json``). docs/predict.md gives the figures of the shipped set.
"""

from __future__ import annotations

import hashlib
import json
import sys
from pathlib import Path

import numpy as np

__all__ = ["study", "loro_tables", "candidate_lines"]


def loro_tables(predicted_photos, metrics, rig_of: dict, trackers) -> tuple:
    """``(predicted, measured, rigs, photo_counts)``: the per-rig figure tables of the method's per-photograph
    predictions and of the measured per-image rows (:func:`bench.evaluate.predict_loro.rig_table`; a real run's
    ``mean`` rows left out), the rigs in sorted order, and rig -> (P, T, 6) its predicted photographs' counts.

    Examples
    --------
    >>> import pandas as pd
    >>> pred = pd.DataFrame({"name": ["p", "q"], "tracker": "t", "n_hit": [9, 5], "n_wrong": 0, "n_missed": [1, 5],
    ...                      "n_false": 0, "n_quiet": 0, "n_unknown": 0})
    >>> real = pred.rename(columns={"name": "experiment"}).assign(n_hit=[8, 4], n_missed=[2, 6])
    >>> p, m, rigs, counts = loro_tables(pred, real, {"p": "a", "q": "b"}, ["t"])
    >>> rigs, p["hit_rate"].ravel().tolist(), m["hit_rate"].ravel().tolist(), counts["b"].shape
    (['a', 'b'], [0.9, 0.5], [0.8, 0.4], (1, 1, 6))
    """
    from bench.evaluate.outcomes import COUNT_KEYS
    from bench.evaluate.predict_loro import rig_table

    trackers = [str(t) for t in trackers]
    per_image = metrics[metrics["experiment"] != "mean"]
    rigs = sorted({rig_of[n] for n in per_image["experiment"].astype(str) if n in rig_of})
    predicted = rig_table(predicted_photos, "name", rig_of, rigs, trackers)
    measured = rig_table(per_image, "experiment", rig_of, rigs, trackers)
    counts = {}
    for rig in rigs:
        names = sorted({str(n) for n in predicted_photos["name"] if rig_of.get(str(n)) == rig})
        c = np.zeros((len(names), len(trackers), len(COUNT_KEYS)), np.int64)
        for i, n in enumerate(names):
            rows = predicted_photos[predicted_photos["name"].astype(str) == n].set_index("tracker")
            for j, t in enumerate(trackers):
                if t in rows.index:
                    c[i, j] = rows.loc[t, list(COUNT_KEYS)].to_numpy(np.int64)
        counts[rig] = c
    return predicted, measured, rigs, counts


def study(*, dataset, out, trackers=None, calibration=None, n_boot: int = 1000, seed: int = 0, quiet: bool = False,
          force: bool = False, settings=None, candidates: bool = False) -> int:
    """Measure, predict and judge leave one rig out; print per rig and pooled, predict's figures beside the null's.

    Parameters
    ----------
    dataset : path
        A real set (its manifest names each photograph's rig).
    out : path
        Output folder: ``real/`` (the measured run), ``predict/`` (the prediction) and ``predict_loro.json``.
    trackers : sequence of :class:`bench.config.TrackerSpec`, optional
        Default: ``predict``'s (every listed tracker and ``learned``).
    calibration : path, optional
        Also write the calibration there (``bench/data/predict_calibration.json`` is the shipped one).
    n_boot, seed : int
        The bootstrap resamples and seed of both runs and of the chance draws.
    quiet, force : bool
        No progress; write over a finished folder.
    settings : bench.evaluate.predict_settings.PredictSettings, optional
        The prediction's tuned values (default: the product's).
    candidates : bool
        Also print the declared candidates of docs/predict.md beside the adopted procedure (:func:`candidate_lines`).

    Returns
    -------
    int
        0.
    """
    from bench.config import parse_trackers
    from bench.evaluate import predict_loro as pl
    from bench.evaluate.predict_settings import DEFAULT
    from bench.run.predict import run_predict
    from bench.run.real import run_real
    from bench.store import realset as real
    from bench.store.files import atomic_write_text
    from bench.store.predictfiles import write_calibration
    from bench.store.provenance import git_revision
    from bench.store.realrun import load_real_run

    s = DEFAULT if settings is None else settings
    if trackers is None:
        from bench.run.predict import default_trackers

        trackers = parse_trackers(default_trackers())
    say = (lambda m: None) if quiet else (lambda m: print(m, file=sys.stderr, flush=True))
    out = Path(out)
    images = real.load_dataset(dataset)
    rig_of = {im.name: im.rig for im in images}
    say(f"stripebench predictloro: measuring {len(images)} photographs of {len(set(rig_of.values()))} rigs")
    rdir = run_real(dataset, out / "real", trackers, seed=seed, n_boot=n_boot, quiet=True, force=force)
    say("stripebench predictloro: predicting them from themselves")
    res = run_predict(dataset, out / "predict", trackers, n_boot=n_boot, seed=seed, settings=s, calibration=None,
                      say=lambda m: None)
    labels = [t.label for t in trackers]
    metrics, every = load_real_run(rdir)["metrics"], res["predicted_photos"]
    own = every[every["shrink"] == 1]  # coarse answers are not pooled (docs/predict.md)
    predicted, measured, rigs, counts = loro_tables(own, metrics, rig_of, labels)
    photos = {r: sum(1 for n in rig_of.values() if n == r) for r in rigs}
    answered = {r: len({n for n in own["name"].astype(str) if rig_of.get(n) == r}) for r in rigs}
    shrunk = {r: len({n for n in every[every["shrink"] != 1]["name"].astype(str) if rig_of.get(n) == r})
              for r in rigs}
    share = np.array([answered[r] / photos[r] for r in rigs])
    loro = pl.evaluate(predicted, measured, rigs, labels, level=s.interval_level, photo_counts=counts,
                       n_draws=s.pick_draws, seed=seed, answered=share, tie_chance=s.tie_chance)
    for r in rigs:
        loro["rigs"][r].update(n_photos=photos[r], n_predicted=answered[r], n_shrunk=shrunk[r])
    manifest = (Path(dataset) / "manifest.csv").read_bytes()
    provenance = {"command": "stripebench predictloro", "dataset": str(dataset),
                  "manifest_sha256": hashlib.sha256(manifest).hexdigest(), "n_photos": len(images),
                  "git_revision": git_revision(), "seed": seed, "n_boot": n_boot, "settings": s.to_value()}
    doc = {"kind": "predict_loro", "provenance": provenance, **loro}
    atomic_write_text(out / "predict_loro.json", json.dumps(doc, indent=1, default=float) + "\n")
    if calibration is not None:
        cal = pl.calibration(predicted, measured, rigs, labels, loro, answered=share)
        write_calibration(calibration, {**cal, "loro": loro["pooled"], "provenance": provenance})
    for line in _lines(loro):
        print(line)
    if candidates:
        for line in candidate_lines(every, metrics, rig_of, labels, s, seed):
            print(line)
    print(f"stripebench: leave one rig out in {out / 'predict_loro.json'}"
          + ("" if calibration is None else f"; calibration {calibration}"))
    return 0


def _lines(loro: dict) -> list[str]:
    """The table ``predictloro`` prints: per rig and pooled, the method's figures beside the null's."""
    head = (f"{'rig':<16}{'photos':>7}{'pred.':>6}{'F1 error':>16}{'false-rep. error':>18}{'hit-rate error':>16}"
            f"{'regret':>15}{'F1 covered':>12}")
    lines = ["leave one rig out: predict / null", head]

    def pair(d, f):
        return f"{d[f]['method']['error']:.3f} / {d[f]['null']['error']:.3f}"

    for rig, e in loro["rigs"].items():
        cov = e["f1"]["method"]
        lines.append(f"{rig:<16}{e.get('n_photos', 0):>7}{e.get('n_predicted', 0):>6}{pair(e, 'f1'):>16}"
                     f"{pair(e, 'false_report_rate'):>18}{pair(e, 'hit_rate'):>16}"
                     f"{e['regret']['method']:>7.3f} / {e['regret']['null']:.3f}"
                     f"{cov['covered']:>6}/{cov['n_intervals']}")
    p = loro["pooled"]

    def pooled(f):
        return f"{p[f]['method']['error']:.3f} / {p[f]['null']['error']:.3f}"

    lines.append(f"{'all rigs':<16}{'':>7}{'':>6}{pooled('f1'):>16}{pooled('false_report_rate'):>18}"
                 f"{pooled('hit_rate'):>16}{p['regret']['method']:>7.3f} / {p['regret']['null']:.3f}")
    for f in ("f1", "false_report_rate", "hit_rate"):
        m, n = p[f]["method"], p[f]["null"]
        lines.append(f"{f}: {loro['level']:.0%} intervals hold {m['coverage']:.0%} of the measured figures, mean width "
                     f"{m['width']:.3f} (the null's: {n['coverage']:.0%}, {n['width']:.3f})")
    c = p["chance"]
    if c["n_rigs"]:
        lines.append(f"the pick's stated chance of being best: {c['stated']:.0%} on average; it was the best measured on "
                     f"{c['best']:.0%} of the {c['n_rigs']} rigs, and the pick or a tracker tied with it on "
                     f"{c['in_tie']:.0%} ({c['n_tied']:.1f} trackers on average)")
    return lines


def candidate_lines(every, metrics, rig_of: dict, labels, settings, seed: int = 0) -> list[str]:
    """The declared candidates of docs/predict.md ("The candidates") judged on the same measurement, each a line of
    its pooled leave-one-rig-out figures: coarse answers pooled, not pooled or only where there is no other; toward
    the null and less its bias; the photographs without an answer at the null's figure. The adopted procedure: coarse
    answers not pooled, the unanswered photographs at the null's figure, no adjustment."""
    from bench.evaluate import predict_loro as pl

    own_rigs = {rig_of[str(n)] for n in every[every["shrink"] == 1]["name"]}
    pools = {"no coarse answers": every[every["shrink"] == 1], "coarse answers pooled": every,
             "coarse only where no other": every[(every["shrink"] == 1)
                                                   | ~every["name"].astype(str).map(rig_of).isin(own_rigs)]}
    lines = [f"{'candidate':<52}{'F1 error':>10}{'false-rep.':>12}{'regret':>9}{'F1 cov.':>9}{'width':>8}"]
    for pool, rows in pools.items():
        pred, meas, rigs, counts = loro_tables(rows, metrics, rig_of, labels)
        n = {r: sum(1 for v in rig_of.values() if v == r) for r in rigs}
        share = np.array([len({x for x in rows["name"].astype(str) if rig_of.get(x) == r}) / n[r] for r in rigs])
        for adjust, answered in (("none", None), ("blend", None), ("bias", None), ("none", share)):
            e = pl.evaluate(pred, meas, rigs, labels, level=settings.interval_level, photo_counts=counts,
                            n_draws=settings.pick_draws, seed=seed, adjust=adjust, answered=answered)
            p = e["pooled"]
            name = pool + ({"blend": ", toward the null", "bias": ", less its bias"}.get(adjust, "")
                           + (", unanswered at the null's" if answered is not None else ""))
            lines.append(f"{name:<52}{p['f1']['method']['error']:>10.4f}"
                         f"{p['false_report_rate']['method']['error']:>12.4f}{p['regret']['method']:>9.4f}"
                         f"{p['f1']['method']['coverage']:>9.2f}{p['f1']['method']['width']:>8.3f}")
    p = e["pooled"]
    lines.append(f"{'the null':<52}{p['f1']['null']['error']:>10.4f}{p['false_report_rate']['null']['error']:>12.4f}"
                 f"{p['regret']['null']:>9.4f}{p['f1']['null']['coverage']:>9.2f}{p['f1']['null']['width']:>8.3f}")
    return lines
