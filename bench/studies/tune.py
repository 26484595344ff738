"""Choose the DP trackers' default ``h_weight`` by a fixed procedure (``stripebench tune dp``).

The profile (default ``bench/config/profiles/tune_dp.toml``) lists the tuning frames
(:mod:`bench.studies.tuning`), none of them the paper run's: renders of the profile's
experiments (spheres and planes, never the cone or the hand) at its seed (never 0),
cached on disk like any run's; the synthetic hard frames of its ``kinds`` and ``seeds``
with their laser-off frames; and, with ``check_real``, the shipped photographs, scored
*beside* the choice and never in it. It also lists the trackers and the grid of
``h_weight`` values. Every tracker at every ``h_weight`` tracks every frame, given the
frame's laser-off frame where it has one, as the benchmark gives it.

Criterion (written in the profile before any result was seen): the tuning objective
(:func:`bench.studies.tuning.objective`), the mean over the groups ``renders`` and
``synthetic`` of each group's F1 over rows (row outcomes pooled over the group's frames
and the trackers), so a row left out where the stripe is costs as much as a column
reported where there is none; only the ``h_weight`` values that go blind on the fewest
plain frames are eligible (:meth:`bench.studies.tuning.Tally.eligible`). The chosen default
is the eligible ``h_weight`` with the best objective, ties (within ``tie``) going to the
larger ``h_weight`` (closer to the paper's isotropic cost).

Output in ``OUT`` (default ``results/runs/tune_dp/``): ``tune.csv``
(:data:`bench.studies.tuning.RECORD_FIELDS`: one line per ``h_weight``, tracker, group and
kind: row-outcome counts, precision, recall, F1, false-report rate), ``summary.json``
(the objective and each group's figures per ``h_weight``, the choice), the curves
``tune_dp.png`` and, on stdout, a table of both halves per ``h_weight`` (recall: stripe rows
hit; false-report rate: stripe-less rows with a report) and the chosen value.
"""

from __future__ import annotations

import pathlib
import sys

import numpy as np

from bench.config.tune import DEFAULT_PROFILE, TuneProfile, parse_profile  # noqa: F401  (the profile's schema)

__all__ = ["TuneProfile", "load_profile", "choose", "run", "study", "table_lines", "setting_label",
           "OBJECTIVE_GROUPS", "DEFAULT_PROFILE", "DEFAULT_OUT", "WHAT"]

DEFAULT_OUT = "results/runs/tune_dp"
WHAT = ("dp", "dp_gap", "threshold")  # what can be tuned: `dp`, the DP trackers' h_weight; `dp_gap`, its off level and switch cost
#: The groups of frames the objective averages; the photographs (``check_real``) are scored beside.
OBJECTIVE_GROUPS = ("renders", "synthetic")


def load_profile(path) -> TuneProfile:
    """Read and validate a profile (:func:`bench.config.tune.load_profile` with the hard-frame kinds).

    Raises
    ------
    bench.config.ConfigError
        A missing or unknown key or a bad value, named in the message (one line).
    """
    from bench.config.tune import load_profile as load
    from bench.studies.hard_frames import KINDS

    return load(path, KINDS)


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


def setting_label(h: float) -> str:
    """The setting's name in ``tune.csv`` and ``summary.json``.

    Examples
    --------
    >>> setting_label(0.25)
    'h_weight=0.25'
    """
    return f"h_weight={h:g}"


def run(profile: TuneProfile, out: pathlib.Path, *, progress: bool = True) -> tuple[float, dict, list[dict]]:
    """Track every tuning frame with every tracker at every ``h_weight`` and score them.

    Returns
    -------
    chosen : float
        The chosen h_weight.
    summary : dict
        ``objective`` (h_weight label -> the objective), ``figures`` (h_weight label -> group ->
        pooled counts and :func:`bench.evaluate.outcomes.detection_figures`, the photographs' group
        ``real`` included where checked), ``chosen``, ``eligible``, ``blind``, ``n_frames`` and
        ``objective_groups``.
    records : list of dict
        One per h_weight, tracker, group and kind (:meth:`bench.studies.tuning.Tally.records`).

    Raises
    ------
    bench.config.ConfigError
        No h_weight has a finite objective (no stripe row and no report in any group).
    """
    import trackers

    from bench.evaluate.outcomes import detection_figures
    from bench.studies import tuning

    def say(msg):
        if progress:
            print(msg, file=sys.stderr, flush=True)

    out.mkdir(parents=True, exist_ok=True)
    frames = tuning.rendered_frames(profile.experiments, profile.render, profile.seed, progress=progress)
    frames += tuning.synthetic_frames(profile.kinds, profile.seeds, background=True)
    checks = tuning.real_frames() if profile.check_real else []
    tally, check = tuning.Tally(1, profile.hit_px), tuning.Tally(1, profile.hit_px)
    for h in profile.h_weights:
        key = setting_label(h)
        for n in profile.trackers:
            t = trackers.make(n, h_weight=h)
            for f in frames:
                tally.add(key, n, f, f.track(t))
            for f in checks:
                check.add(key, n, f, f.track(t))
        say(f"h_weight = {h:g} done")
    scores = {h: tally.objective(setting_label(h)) for h in profile.h_weights}
    finite = {h: s for h, s in scores.items() if np.isfinite(s)}
    if not finite:
        from bench.config import ConfigError

        raise ConfigError("`profile` gives no stripe row and no report in any group: nothing to score")
    eligible = tally.eligible(finite, setting_label)
    chosen = choose(eligible, profile.tie)
    figures = {}
    for h in profile.h_weights:
        key = setting_label(h)
        groups = {g: sum(kinds.values()) for g, kinds in tally.by_group(key).items()}
        groups.update({g: sum(kinds.values()) for g, kinds in check.by_group(key).items()})
        figures[key] = {g: {**tuning.counts_record(c), **detection_figures(c)} for g, c in groups.items()}
    n_frames = {g: sum(1 for f in frames + checks if f.group == g) for g in tuning.GROUPS}
    summary = {"profile": profile.name, "chosen": chosen, "objective_groups": list(OBJECTIVE_GROUPS),
               "objective": "mean over groups of F1", "n_frames": n_frames,
               "scores": {setting_label(h): s for h, s in scores.items()},
               "eligible": [setting_label(h) for h in eligible],
               "blind": {k: v for k, v in tally.blind.items() if v}, "figures": figures}
    records = tally.records() + check.records()
    tuning.write_records(out, "tune.csv", records, summary)
    _plot(profile, summary, out / "tune_dp.png")
    return chosen, summary, records


def table_lines(summary: dict, h_weights, reference: float | None = None) -> list[str]:
    """Both halves per ``h_weight``, as ``stripebench tune dp`` prints them: the objective, then per group
    F1, recall (stripe rows hit) and false-report rate (stripe-less rows with a report), with the
    counts behind the two halves; ``*`` marks the chosen value, ``reference`` (e.g. the trackers'
    current default) is marked ``<``.

    Examples
    --------
    >>> fig = {"f1": 0.9, "recall": 0.85, "false_report_rate": 0.1, "n_hit": 85, "n_wrong": 5, "n_missed": 10,
    ...        "n_false": 10, "n_quiet": 90}
    >>> s = {"chosen": 0.5, "scores": {"h_weight=0.5": 0.9}, "figures": {"h_weight=0.5": {"renders": fig}}}
    >>> table_lines(s, [0.5])[1]
    'h_weight=0.5  *  0.9000  F1 0.900, recall 0.850 (85/100), false reports 0.100 (10/100)'
    """
    groups = list(dict.fromkeys(g for figs in summary["figures"].values() for g in figs))
    head = "setting          objective  " + "  |  ".join(
        f"{g}{'' if g in summary.get('objective_groups', groups) else ' (beside, not in the objective)'}"
        for g in groups)
    lines = [head]
    for h in h_weights:
        key = setting_label(h)
        mark = "*" if h == summary["chosen"] else ("<" if reference is not None and h == reference else " ")
        cells = []
        for g in groups:
            f = summary["figures"][key].get(g)
            if f is None:
                cells.append("–")
                continue
            stripe = f["n_hit"] + f["n_wrong"] + f["n_missed"]
            none = f["n_false"] + f["n_quiet"]
            cells.append(f"F1 {f['f1']:.3f}, recall {f['recall']:.3f} ({f['n_hit']}/{stripe}), "
                         f"false reports {f['false_report_rate']:.3f} ({f['n_false']}/{none})")
        lines.append(f"{key:<14s}{mark}  {summary['scores'][key]:.4f}  " + "  |  ".join(cells))
    return lines


def _plot(profile, summary, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    hs = sorted(profile.h_weights)
    keys = [setting_label(h) for h in hs]
    groups = list(dict.fromkeys(g for figs in summary["figures"].values() for g in figs))
    colours = dict(zip(("renders", "synthetic", "real"), ("tab:blue", "tab:orange", "tab:green")))
    fig, ax = plt.subplots(1, 2, figsize=(11.0, 4.0), dpi=110)
    ax[0].plot(hs, [summary["scores"][k] for k in keys], "ko-", lw=2, label="objective (mean F1 over "
               + ", ".join(summary["objective_groups"]) + ")")
    for g in groups:
        beside = "" if g in summary["objective_groups"] else " (beside)"
        ax[0].plot(hs, [summary["figures"][k].get(g, {}).get("f1", np.nan) for k in keys], "o-",
                   color=colours.get(g, "0.5"), lw=1, label=f"{g} F1{beside}")
        ax[1].plot(hs, [summary["figures"][k].get(g, {}).get("recall", np.nan) for k in keys], "o-",
                   color=colours.get(g, "0.5"), label=f"{g}: recall (stripe rows hit){beside}")
        ax[1].plot(hs, [summary["figures"][k].get(g, {}).get("false_report_rate", np.nan) for k in keys], "s--",
                   color=colours.get(g, "0.5"), label=f"{g}: false-report rate{beside}")
    for a in ax:
        a.axvline(summary["chosen"], color="k", lw=0.8, ls=":")
        a.set_xscale("log")
        a.set_xlabel("h_weight (horizontal edge weight)")
        a.set_ylim(0, 1.02)
        a.grid(alpha=0.3)
    ax[0].legend(fontsize=7, loc="lower left")
    ax[1].legend(fontsize=7, loc="center left")  # between the recall curves (high) and the false reports (low)
    ax[0].set_ylabel("F1 over rows")
    ax[1].set_ylabel("fraction of rows")
    fig.suptitle(f"{profile.name}: chosen h_weight = {summary['chosen']:g}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def study(*, profile=DEFAULT_PROFILE, out=DEFAULT_OUT, quiet: bool = False) -> int:
    """``stripebench tune dp``: run the procedure on the tuning profile ``profile`` (a TOML path) into
    the folder ``out`` (created), print both halves per ``h_weight`` and the chosen one, and return 0;
    ``quiet``: no progress lines. A bad profile raises :class:`bench.config.ConfigError` (one line)
    before any frame."""
    from trackers.dp import DEFAULT_H_WEIGHT

    from bench.studies.tuning import run_study

    profile, out, (chosen, summary, _) = run_study(load_profile, run, profile, out, quiet)
    print(f"frames: {', '.join(f'{g} {n}' for g, n in summary['n_frames'].items())}; objective: the mean over {', '.join(summary['objective_groups'])} "
          "of F1 over rows (* chosen, < the trackers' default now)")
    print("\n".join(table_lines(summary, sorted(profile.h_weights, reverse=True), DEFAULT_H_WEIGHT)))
    if summary["blind"]:
        print("blind on plain frames: " + "; ".join(f"{k}: {len(v)}" for k, v in summary["blind"].items()))
    print(f"chosen h_weight = {chosen:g} (objective {summary['scores'][setting_label(chosen)]:.4f}; the trackers' "
          f"default now {DEFAULT_H_WEIGHT:g}); {out / 'tune.csv'}")
    return 0
