"""Choose the DP trackers' reporting rules by a fixed procedure (``stripebench tune dp_gap``):
``dp_gap``'s off level and switch cost, and the support rule of ``dp4``, ``dp8`` and
``dp8_subpixel`` (``k_sigma``, ``max_gap``, ``min_run``).

The profile (default ``bench/config/profiles/tune_dp_gap.toml``) lists the tuning
frames (:mod:`bench.studies.tuning`: renders of the profile's experiments at its
seed, cached; synthetic hard frames with their laser-off frames; the shipped real
set), the grids and the criterion, written in the profile's header. Two stages:

1. ``dp_gap``'s ``off_rel`` x ``switch_rows`` (x ``level_quantile`` where the profile lists it);
2. the DP trackers' reporting rule, ``k_sigma`` x ``max_gap`` x ``min_run``, scored
   with ``dp_trackers`` (the path of a frame is found once per tracker and every
   rule applied to its readings, :meth:`trackers.dp.DPTracker.readings`);
3. where the profile lists ``stripe_tests``: the stripe question (:mod:`trackers._stripe`,
   a tracker's ``stripe_test``), chosen for each of ``stripe_trackers`` on its own outcomes
   (:func:`bench.studies.tune_threshold.run_stripe_stage`) at the settings chosen in stages 1
   (``dp_gap``) and 2 (the others), each frame with its laser-off frame and colour evidence;
   ties go to the candidate listed first.

All maximise :func:`bench.studies.tuning.objective` (the mean over the groups of
frames of each group's F1 over rows: a miss and a false report priced alike). Every
tracker is given the frame's laser-off frame where it has one, as the benchmark gives it.
Stages 1 and 2 score the trackers without the stripe question (``stripe_test=None``): stage 3
chooses it after them.

Output in ``OUT`` (default ``results/runs/tune_dp_gap/``): ``tune_gap.csv`` (one line
per stage, setting, tracker, group and kind: row-outcome counts, precision, recall,
F1, false-report rate), ``summary.json``, ``tune_dp_gap.png`` (stage 1's grid) and the
chosen values with their figures per group and kind on stdout.
"""

from __future__ import annotations

import pathlib
import sys

import numpy as np

from bench.config.tune import GAP_DEFAULT_PROFILE as DEFAULT_PROFILE, GapProfile, load_gap_profile

__all__ = ["GapProfile", "load_profile", "choose", "choose_rule", "run", "study", "DEFAULT_PROFILE",
           "DEFAULT_OUT"]


def load_profile(path) -> GapProfile:
    """Read and validate a profile (:func:`bench.config.tune.load_gap_profile` with the hard-frame kinds).

    Raises
    ------
    bench.config.ConfigError
        A missing or unknown key or a bad value, named in the message (one line).
    """
    from bench.studies.hard_frames import KINDS

    return load_gap_profile(path, KINDS)

def choose(scores: dict[tuple, float], tie: float) -> tuple:
    """Stage 1's choice: the best ``(off_rel, switch_rows)`` or ``(off_rel, switch_rows, level_quantile)``;
    scores within ``tie`` of the best go to the smallest ``off_rel``, then the largest ``switch_rows`` (the
    fewest rows left out: closest to the paper's DP, which never leaves one out), then the smallest
    ``level_quantile`` (None, not in the grid, first).

    Examples
    --------
    >>> choose({(0.1, 10.0): 0.80, (0.05, 3.0): 0.799, (0.05, 30.0): 0.7991, (0.3, 1.0): 0.5}, tie=0.005)
    (0.05, 30.0)
    """
    best = max(scores.values())
    near = [k for k, v in scores.items() if v >= best - tie]
    return min(near, key=lambda k: (k[0], -k[1], *((-1.0 if q is None else q) for q in k[2:])))


def choose_rule(scores: dict, tie: float) -> tuple:
    """Stage 2's choice: the best ``(k_sigma, max_gap, min_run)``; scores within ``tie`` of the best go to
    the rule that bridges most (no ``max_gap`` first, then the largest), then the smallest ``min_run``,
    then the smallest ``k_sigma``: the closest to the paper's DP.

    Examples
    --------
    >>> choose_rule({(3.0, None, 1): 0.70, (4.0, 10, 5): 0.801, (3.0, 20, 5): 0.800}, tie=0.002)
    (3.0, 20, 5)
    """
    best = max(scores.values())
    near = [k for k, v in scores.items() if v >= best - tie]
    return min(near, key=lambda k: (k[1] is not None, -(k[1] or 0), k[2], k[0]))


def _gap_label(off: float, sw: float, q: float | None = None) -> str:
    return f"off_rel={off:g},switch_rows={sw:g}" + ("" if q is None else f",level_quantile={q:g}")


def _gap_params(off: float, sw: float, q: float | None = None) -> dict:
    return {"off_rel": off, "switch_rows": sw, **({} if q is None else {"level_quantile": q})}


def _rule_label(k: float, gap, m: int) -> str:
    return f"k_sigma={k:g},max_gap={'none' if gap is None else gap},min_run={m}"


def run(profile: GapProfile, out: pathlib.Path, *, progress: bool = True):
    """Run both stages.

    Returns
    -------
    chosen : dict
        ``off_rel``, ``switch_rows`` (stage 1), ``k_sigma``, ``max_gap``, ``min_run`` (stage 2) and, with
        a stage 3, ``stripe_test`` (tracker -> None or a dict of :class:`trackers.StripeTest` settings).
    summary : dict
        The objective of every setting of every stage (``stage3`` per tracker), the chosen settings'
        figures per group and kind (``figures``; stage 3's as ``stage3:<tracker>``, like
        ``photographs`` and ``blind``), ``chosen`` and the number of frames per group.
    records : list of dict
        One per stage, setting, tracker, group and kind.
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
    if profile.real:
        frames += tuning.real_frames()
    t1 = tuning.Tally(1, profile.hit_px, profile.max_false_rate)
    scores1 = {}
    for o in profile.off_rel:
        for sw in profile.switch_rows:
            for q in profile.level_quantile or [None]:
                key = _gap_label(o, sw, q)
                t = trackers.make(profile.tracker, **_gap_params(o, sw, q), stripe_test=None)
                for f in frames:
                    t1.add(key, profile.tracker, f, t.track(f.image, background=f.background).columns)
                scores1[(o, sw, q)] = t1.objective(key)
        say(f"stage 1: off_rel = {o:g} done")
    def pick1(held, photos):
        sc = {k: t1.objective(_gap_label(*k), held_out=held, photographs=photos) for k in scores1}
        return _gap_label(*choose(t1.eligible(sc, lambda k: _gap_label(*k), held_out=held, photographs=photos),
                                  profile.tie))

    judged = {"stage1": t1.judge(pick1)}
    off_best, sw_best, q_best = {_gap_label(*k): k for k in scores1}[judged["stage1"]["kept"]]
    t2 = tuning.Tally(2, profile.hit_px, profile.max_false_rate)
    rules = [(k, g, m) for k in profile.k_sigma for g in profile.max_gap for m in profile.min_run]
    for n in profile.dp_trackers:
        base = trackers.make(n)
        variants = {r: trackers.make(n, k_sigma=r[0], max_gap=r[1], min_run=r[2], stripe_test=None) for r in rules}
        for f in frames:
            readings = base.readings(f.image, f.background)
            for r, t in variants.items():
                t2.add(_rule_label(*r), n, f, t.report(*readings).columns)
        say(f"stage 2: {n} done")
    scores2 = {r: t2.objective(_rule_label(*r)) for r in rules}
    def pick2(held, photos):
        sc = {r: t2.objective(_rule_label(*r), held_out=held, photographs=photos) for r in rules}
        return _rule_label(*choose_rule(t2.eligible(sc, lambda k: _rule_label(*k), held_out=held,
                                                     photographs=photos), profile.tie))

    judged["stage2"] = t2.judge(pick2)
    k_best, gap_best, m_best = {_rule_label(*r): r for r in rules}[judged["stage2"]["kept"]]
    chosen = {**_gap_params(off_best, sw_best, q_best), "k_sigma": k_best, "max_gap": gap_best, "min_run": m_best}
    # stage 3: the stripe question, chosen for each tracker with the choices above (dp_gap its off state, the
    # others their rule)
    from bench.studies.tune_threshold import above_ceiling, run_stripe_stage

    def params_of(n):
        return (_gap_params(off_best, sw_best, q_best) if "off_rel" in trackers.make(n).get_params() else
                {"k_sigma": k_best, "max_gap": gap_best, "min_run": m_best})

    per3 = run_stripe_stage(3, frames, profile.stripe_trackers, profile.stripe_tests, params_of, profile.hit_px,
                            profile.tie, say, max_false_rate=profile.max_false_rate)
    stages = [("stage1", t1, _gap_label(off_best, sw_best, q_best)),
              ("stage2", t2, _rule_label(k_best, gap_best, m_best))]
    if per3.per:
        chosen["stripe_test"] = per3.chosen
        judged.update(per3.judged)
        stages += per3.stages
    figures = {}
    for name, tally, key in stages:
        figures[name] = {g: {**{kd: detection_figures(c) for kd, c in kinds.items()},
                             "all": detection_figures(sum(kinds.values()))}
                         for g, kinds in tally.by_group(key).items()}
    n_frames = {g: sum(1 for f in frames if f.group == g) for g in tuning.GROUPS}
    summary = {"profile": profile.name, "chosen": chosen, "n_frames": n_frames,
               "objective": "mean over groups of F1",
               "blind": {**{f"stage{t.stage}": {k: v for k, v in t.blind.items() if v} for t in (t1, t2)},
                         **per3.blind},
               "stage1": {_gap_label(*k): v for k, v in scores1.items()},
               "stage2": {_rule_label(*k): v for k, v in scores2.items()},
               "stage3": per3.scores,
               "unavoidable_blind_photographs": {name: tally.unavoidable(key) for name, tally, key in stages
                                                 if tally.unavoidable(key)},
               "max_false_rate": profile.max_false_rate, "above_false_rate_ceiling": above_ceiling(stages),
               "figures": figures, "photographs": judged}
    records = t1.records() + t2.records() + per3.records()
    tuning.write_records(out, "tune_gap.csv", records, summary)
    _plot(profile, scores1, (off_best, sw_best, q_best), out / "tune_dp_gap.png")
    return chosen, summary, records


def _plot(profile, scores, chosen, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    offs = sorted(profile.off_rel)
    sws = sorted(profile.switch_rows)
    q = chosen[2]  # the grid's slice at the chosen level_quantile
    z = np.array([[scores[o, s, q] for s in sws] for o in offs])
    fig, ax = plt.subplots(figsize=(6.0, 4.0), dpi=120)
    im = ax.imshow(z, origin="lower", cmap="viridis", aspect="auto")
    for i in range(len(offs)):
        for j in range(len(sws)):
            bold = (offs[i], sws[j]) == tuple(chosen[:2])
            ax.text(j, i, f"{z[i, j]:.3f}", ha="center", va="center", fontsize=7,
                    color="w" if z[i, j] < np.nanmean(z) else "k", weight="bold" if bold else "normal")
    ax.set_xticks(range(len(sws)), [f"{s:g}" for s in sws])
    ax.set_yticks(range(len(offs)), [f"{o:g}" for o in offs])
    ax.set_xlabel("switch_rows (switch cost in rows of the off cost)")
    ax.set_ylabel("off_rel (off level)")
    ax.set_title(f"{profile.name}: objective (mean F1 over groups); chosen {_gap_label(*chosen)}", fontsize=8)
    fig.colorbar(im, ax=ax)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


DEFAULT_OUT = "results/runs/tune_dp_gap"


def study(*, profile=DEFAULT_PROFILE, out=DEFAULT_OUT, quiet: bool = False) -> int:
    """``stripebench tune dp_gap``: run the procedure on the tuning profile ``profile`` (a TOML path) into
    the folder ``out`` (created), print its choices and return 0; ``quiet``: no progress bars. A bad
    profile raises :class:`bench.config.ConfigError` (one line) before any scan."""
    from bench.studies.tune_threshold import ceiling_lines, figure_lines, stripe_key
    from bench.studies.tuning import judged_lines, run_study

    profile, out, (chosen, summary, _) = run_study(load_profile, run, profile, out, quiet)
    ceiling = summary.get("max_false_rate")
    k1 = _gap_label(chosen["off_rel"], chosen["switch_rows"], chosen.get("level_quantile"))
    k2 = _rule_label(chosen["k_sigma"], chosen["max_gap"], chosen["min_run"])
    print(f"frames: {summary['n_frames']}; objective: the mean over groups of F1 over rows")
    stages = [("stage1", k1, profile.tracker, summary["stage1"]),
              ("stage2", k2, ", ".join(profile.dp_trackers), summary["stage2"])]
    stages += [(f"stage3:{n}", stripe_key(test), n, summary["stage3"][n])
               for n, test in chosen.get("stripe_test", {}).items()]
    for stage, names in summary["unavoidable_blind_photographs"].items():
        print(f"{stage}: every setting goes blind on a plain photograph: {', '.join(names)}")
    for stage, key, what, scores in stages:
        best = sorted(scores.items(), key=lambda kv: -kv[1])[:5]
        print(f"{stage.split(':')[0]} ({what}): chosen {key} (objective {scores[key]:.4f}; best five: "
              + ", ".join(f"{kk} {v:.4f}" for kk, v in best) + ")")
        print("\n".join(figure_lines(summary["figures"][stage])))
        print("\n".join(judged_lines(summary["photographs"][stage], ceiling)))
    print("\n".join(ceiling_lines(summary)))
    print(f"{out / 'tune_gap.csv'}")
    return 0
