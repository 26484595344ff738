"""Choose the DP trackers' default ``h_weight`` by a fixed procedure (``stripebench tune dp``).

The profile (default ``bench/config/profiles/tune_dp.toml``) lists the experiments
(scene, material, optional scene-parameter overrides), the render settings,
the seed, the trackers and the grid of ``h_weight`` values. Every experiment
is one scan (:func:`bench.run.scan.run_scan`, renders cached on disk, one
checkpoint per experiment under ``OUT/checkpoints``, so an interrupted run
resumes) tracked by every tracker at every ``h_weight``.

Criterion (written in the profile before any result was seen): the *hit
fraction* of a tracker at an ``h_weight`` in an experiment is the fraction of
its lit object rows (rows whose truth lies on the object, over all frames)
where the tracker's column is within ``hit_px`` pixels of the truth; a row it
does not report is a miss. The score of an ``h_weight`` is the mean hit
fraction over experiments and trackers; the chosen default is the
``h_weight`` with the best score, ties (scores within ``tie``) going to the
larger ``h_weight``.

Output in ``OUT`` (default ``results/runs/tune_dp/``): ``tune.csv`` (columns
h_weight, tracker, experiment, hit_fraction, rows), the curve ``tune_dp.png``
and one printed line with the chosen value.
"""

from __future__ import annotations

import csv
import pathlib
import sys

import numpy as np

from bench.evaluate.metrics import hits
from bench.config.tune import DEFAULT_PROFILE, TuneProfile, load_profile  # noqa: F401  (the profile's schema)

__all__ = ["TuneProfile", "load_profile", "hit_fraction", "choose", "run", "study", "DEFAULT_PROFILE", "DEFAULT_OUT",
           "WHAT"]

DEFAULT_OUT = "results/runs/tune_dp"
WHAT = ("dp", "dp_gap", "threshold")  # what can be tuned: `dp`, the DP trackers' h_weight; `dp_gap`, its off level and switch cost


def _key(e: dict) -> str:
    extra = "".join(f"_{k}={v}" for k, v in sorted(e.items()) if k not in ("scene", "material"))
    return f"{e['scene']}-{e['material']}{extra}"


def hit_fraction(columns, truth_columns, on_object, hit_px: float) -> tuple[float, int]:
    """Fraction of the lit object rows where ``columns`` is within ``hit_px``
    of the truth, and the number of those rows.

    Parameters
    ----------
    columns, truth_columns : array_like (F, H) or (H,), float, px
        Tracked and true columns (NaN: not reported / no truth).
    on_object : array_like, same shape, bool
    hit_px : float
        Largest hit distance in pixels.

    Returns
    -------
    fraction : float
        NaN if there is no lit object row.
    rows : int

    Examples
    --------
    >>> hit_fraction([10.0, np.nan, 30.0, 5.0], [10.5, 20.0, 40.0, 5.0], [True, True, True, False], 3.0)
    (0.3333333333333333, 3)
    """
    cols = np.asarray(columns, float)
    truth = np.asarray(truth_columns, float)
    lit = np.asarray(on_object, bool) & np.isfinite(truth)
    n = int(lit.sum())
    if n == 0:
        return float("nan"), 0
    return float((hits(cols, truth, hit_px) & lit).sum() / n), n


def choose(scores: dict[float, float], tie: float) -> float:
    """The h_weight with the best score; scores within ``tie`` of the best
    go to the larger h_weight.

    Examples
    --------
    >>> choose({1.0: 0.80, 0.1: 0.853, 0.05: 0.856}, tie=0.005)
    0.1
    """
    best = max(scores.values())
    return max(h for h, s in scores.items() if s >= best - tie)


def _tracker_name(name: str, h: float) -> str:
    return f"{name}@h={h:g}"


def run(profile: TuneProfile, out: pathlib.Path, *, progress: bool = True) -> tuple[float, dict, list[dict]]:
    """Run the tuning scans and score them.

    Returns
    -------
    chosen : float
        The chosen h_weight.
    scores : dict h_weight -> float
        Mean hit fraction over experiments and trackers.
    records : list of dict
        One per (h_weight, tracker, experiment): ``hit_fraction``, ``rows``.
    """
    import scenes
    import trackers

    from bench.run.scan import run_scan

    out.mkdir(parents=True, exist_ok=True)
    tr = {_tracker_name(n, h): trackers.make(n, h_weight=h) for n in profile.trackers for h in profile.h_weights}
    r = profile.render
    records = []
    for k, e in enumerate(profile.experiments):
        overrides = {key: v for key, v in e.items() if key not in ("scene", "material")}
        scene = scenes.make(e["scene"], material=e["material"], seed=profile.seed, width=r["width"],
                            height=r["height"], spp=r["spp"], **overrides)
        angles = scene.object.default_angles(scene.rig.zeta_deg, r["n_angles"])
        key = _key(e)
        if progress:
            print(f"[{k + 1}/{len(profile.experiments)}] {key}: {len(angles)} frames", file=sys.stderr, flush=True)
        res = run_scan(key, scene, angles, tr, spp=r["spp"], seed=profile.seed,
                       checkpoint=out / "checkpoints" / f"{key}.npz", progress=progress)
        for n in profile.trackers:
            for h in profile.h_weights:
                frac, rows = hit_fraction(res.columns[_tracker_name(n, h)], res.truth_columns, res.on_object,
                                          profile.hit_px)
                records.append({"h_weight": h, "tracker": n, "experiment": key, "hit_fraction": frac, "rows": rows})
    scores = {}
    for h in profile.h_weights:
        vals = [rec["hit_fraction"] for rec in records if rec["h_weight"] == h and np.isfinite(rec["hit_fraction"])]
        scores[h] = float(np.mean(vals)) if vals else float("nan")
    finite = {h: s for h, s in scores.items() if np.isfinite(s)}
    if not finite:
        from bench.config import ConfigError

        raise ConfigError("`profile` gives no lit object row in any experiment: nothing to score")
    chosen = choose(finite, profile.tie)
    with open(out / "tune.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=["h_weight", "tracker", "experiment", "hit_fraction", "rows"])
        w.writeheader()
        w.writerows(records)
    _plot(profile, records, scores, chosen, out / "tune_dp.png")
    return chosen, scores, records


def _plot(profile, records, scores, chosen, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    hs = np.array(profile.h_weights)
    order = np.argsort(hs)
    fig, ax = plt.subplots(figsize=(6.4, 4.0), dpi=120)
    for n, colour in zip(profile.trackers, ("tab:blue", "tab:orange", "tab:green", "tab:red")):
        exps = sorted({rec["experiment"] for rec in records})
        for e in exps:
            y = [next(rec["hit_fraction"] for rec in records if rec["h_weight"] == h and rec["tracker"] == n
                      and rec["experiment"] == e) for h in hs[order]]
            ax.plot(hs[order], y, "-", color=colour, lw=0.5, alpha=0.35)
        mean = [np.nanmean([rec["hit_fraction"] for rec in records if rec["h_weight"] == h and rec["tracker"] == n])
                for h in hs[order]]
        ax.plot(hs[order], mean, "o-", color=colour, lw=2, label=f"{n} (mean over experiments)")
    ax.plot(hs[order], [scores[h] for h in hs[order]], "k--", lw=1.5, label="score (mean of all)")
    ax.axvline(chosen, color="k", lw=0.8, ls=":")
    ax.set_xscale("log")
    ax.set_xlabel("h_weight (horizontal edge weight)")
    ax.set_ylabel(f"lit object rows within {profile.hit_px:g} px")
    ax.set_title(f"{profile.name}: chosen h_weight = {chosen:g} (thin: single experiments)", fontsize=9)
    ax.set_ylim(0, 1.02)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def study(*, profile=DEFAULT_PROFILE, out=DEFAULT_OUT, quiet: bool = False) -> int:
    """``stripebench tune dp``: run the procedure on the tuning profile ``profile`` (a TOML path) into
    the folder ``out`` (created), print the chosen ``h_weight`` and return 0; ``quiet``: no progress bars. A bad
    profile raises :class:`bench.config.ConfigError` (one line) before any scan."""
    from bench.studies.tuning import run_study

    profile, out, (chosen, scores, _) = run_study(load_profile, run, profile, out, quiet)
    curve = ", ".join(f"{h:g}: {scores[h]:.3f}" for h in sorted(scores, reverse=True))
    print(f"chosen h_weight = {chosen:g} (mean hit fraction {scores[chosen]:.3f}; by h_weight {curve}); "
          f"{out / 'tune.csv'}")
    return 0
