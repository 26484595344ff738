"""Choose the detection defaults of the per-row trackers, ``com_bg``'s threshold-to-zero,
Steger's detection and the ``auto`` colour rule by a fixed procedure (``stripebench tune threshold``).

The profile (default ``bench/config/profiles/tune_threshold.toml``) lists the
tuning frames (:mod:`bench.studies.tuning`: synthetic kinds and seeds of
:mod:`bench.studies.hard_frames`, renders of spheres and planes at the profile's
seed, and whether the shipped real set takes part), the grids and the criteria,
which are written in the profile's header. Five stages, each using the choices of
the ones before:

1. ``k_sigma`` x ``prominence`` x ``min_run`` x ``width_ratio`` of the per-row detection
   (:func:`trackers._detect.detect_rows`), scored with the threshold trackers
   on every tuning frame (the photographs as ``stripebench real`` gives them:
   the manifest's channel, ``auto`` being the committed rule, so the committed
   defaults are a fixed point of the procedure);
2. ``com_bg``'s ``frac`` on the synthetic laser-on/laser-off pairs (the mean
   |error| of its hits: the photographs' references cannot judge a sub-pixel
   estimator);
3. Steger's ``k_sigma`` x ``prominence`` x ``min_run`` (its ridge strength and
   intensity tests), on every tuning frame;
4. the ``auto`` colour rule (:func:`bench.evaluate.colour.saturation_blend` with a knee
   from the grid, the plain excess or the laser's channel) on the colour
   versions of the synthetic frames and of every colour photograph;
5. where the profile lists ``stripe_tests``: the stripe question (:mod:`trackers._stripe`,
   a tracker's ``stripe_test``), chosen for each of ``stripe_trackers`` on its own outcomes
   (:func:`run_stripe_stage`) at the settings chosen above, on every tuning frame with its
   laser-off frame and colour evidence; ties go to the candidate listed first (the committed
   profile lists "none", the trackers as they are, first).

Stages 1, 3, 4 and 5 maximise :func:`bench.studies.tuning.objective`: the mean over
the groups of frames of each group's F1 over rows, a miss and a false report
priced alike. Stages 1-4 score the trackers without the stripe question
(``stripe_test=None``, whatever a tracker's default): stage 5 chooses it after them,
so the procedure's choices do not depend on the committed question.

Output in ``OUT`` (default ``results/runs/tune_threshold/``): ``tune.csv``
(one line per stage, setting, tracker, group and kind: the row-outcome counts
and their precision, recall, F1 and false-report rate; stage 2: ``mae_px``),
``summary.json`` (the objective of every setting and the choices) and a few
printed lines per stage.
"""

from __future__ import annotations

import pathlib
import sys

import numpy as np

from bench.config.tune import TuneThresholdProfile, load_threshold_profile  # noqa: F401  (the schema)

__all__ = ["TuneThresholdProfile", "load_profile", "frame_scores", "choose_grid", "choose_min", "choose_listed",
           "apply_rule", "run", "figure_lines", "study", "stripe_key", "StripeStage", "run_stripe_stage",
           "judge_stripe_tests", "above_ceiling", "ceiling_lines",
           "chosen_params", "DEFAULT_PROFILE", "DEFAULT_OUT"]

DEFAULT_PROFILE = pathlib.Path(__file__).resolve().parents[1] / "config" / "profiles" / "tune_threshold.toml"
DEFAULT_OUT = "results/runs/tune_threshold"


def load_profile(path) -> TuneThresholdProfile:
    """Read and validate a profile (:func:`bench.config.tune.load_threshold_profile` with the hard-frame kinds).

    Raises
    ------
    bench.config.ConfigError
        A missing or unknown key or a bad value, named in the message (one line).
    """
    from bench.studies.hard_frames import KINDS

    return load_threshold_profile(path, KINDS)


def frame_scores(columns, truth, hit_px: float) -> dict[str, float]:
    """A tracker's accuracy on one frame with known stripe rows (stage 2).

    Parameters
    ----------
    columns : array_like, shape (H,)
        The tracker's columns (px), NaN where it reports nothing.
    truth : array_like, shape (H,)
        The stripe's column (px), NaN on stripe-less rows.
    hit_px : float

    Returns
    -------
    dict
        ``hit``: stripe rows within ``hit_px`` over stripe rows; ``mae_px``: mean
        |error| over the hits (NaN if none).

    Examples
    --------
    >>> frame_scores([10.0, 14.0, np.nan, 3.0], [11.0, 10.0, np.nan, np.nan], 3.0)
    {'hit': 0.5, 'mae_px': 1.0}
    """
    from bench.evaluate.outcomes import hits

    c = np.asarray(columns, float)
    t = np.asarray(truth, float)
    has = np.isfinite(t)
    hit = hits(c, t, hit_px)
    err = np.abs(c - t)
    return {"hit": float(hit.sum() / has.sum()) if has.any() else float("nan"),
            "mae_px": float(err[hit].mean()) if hit.any() else float("nan")}


def choose_grid(scores: dict, tie: float):
    """The ``(k_sigma, prominence, min_run[, width_ratio])`` of best score; scores within ``tie`` of the
    best go to no ``width_ratio`` (then the widest), then the smaller ``min_run`` (the simpler rule), then
    the larger prominence, then the larger k_sigma (the more cautious).

    Examples
    --------
    >>> choose_grid({(3.0, 1.1, 1): 0.900, (5.0, 1.5, 1): 0.899, (5.0, 1.1, 1): 0.8, (3.0, 0.0, 5): 0.9}, tie=0.002)
    (5.0, 1.5, 1)
    >>> choose_grid({(3.0, 1.1, 1, 2.5): 0.9, (3.0, 1.1, 1, None): 0.899, (4.0, 1.1, 1, 4.0): 0.9}, tie=0.002)
    (3.0, 1.1, 1, None)
    """
    best = max(scores.values())
    near = [key for key, s in scores.items() if s >= best - tie]

    def pref(key):
        width = key[3] if len(key) > 3 else None
        return (width is None, width or 0, -key[2], key[1], key[0])

    return max(near, key=pref)


def choose_min(values: dict, tie: float):
    """The key of smallest value; values within ``tie`` of it go to the smaller key.

    Examples
    --------
    >>> choose_min({0.0: 0.2, 0.25: 0.1, 0.4: 0.101}, tie=0.005)
    0.25
    """
    best = min(values.values())
    return min(k for k, v in values.items() if v <= best + tie)


def choose_listed(scores: dict, order: list, tie: float):
    """The candidate of best score; ties within ``tie`` go to the one listed first in ``order``.

    Examples
    --------
    >>> choose_listed({"excess": 0.7, 0.8: 0.9, 0.5: 0.899}, ["excess", 0.8, 0.5], tie=0.002)
    0.8
    """
    best = max(scores.values())
    return next(c for c in order if c in scores and scores[c] >= best - tie)


def apply_rule(rgb, laser: str, rule):
    """A colour photograph through a candidate rule of stage 4: ``'excess'``,
    ``'laser'`` or a knee of :func:`bench.evaluate.colour.saturation_blend`; a grey
    photograph (2-D, or three equal channels) is returned as it is."""
    from bench.evaluate.colour import LASER_INDEX, saturation_blend
    from bench.evaluate.pixels import select_channel

    img = np.asarray(rgb)
    if img.ndim == 2 or (np.array_equal(img[..., 0], img[..., 1]) and np.array_equal(img[..., 0], img[..., 2])):
        return np.ascontiguousarray(img if img.ndim == 2 else img[..., 0])
    if rule == "excess":
        return select_channel(img, "excess", laser)
    if rule == "laser":
        return np.ascontiguousarray(img[..., LASER_INDEX[laser]])
    return saturation_blend(img, laser, float(rule))


def _frames(profile, progress):
    """The tuning frames of the profile (:mod:`bench.studies.tuning`)."""
    from bench.studies import tuning

    frames = tuning.synthetic_frames(profile.kinds, profile.seeds, background=True)
    if profile.renders:
        frames += tuning.rendered_frames(profile.renders, profile.render, profile.seed, progress=progress)
    if profile.real:
        frames += tuning.real_frames()
    return frames


def _key(k, p, m, w="n/a") -> str:
    tail = "" if w == "n/a" else f",width_ratio={'none' if w is None else format(w, 'g')}"
    return f"k_sigma={k:g},prominence={p:g},min_run={m:d}{tail}"


def run(profile: TuneThresholdProfile, out: pathlib.Path, *, progress: bool = True):
    """Run the stages (the fifth where the profile lists ``stripe_tests``).

    Returns
    -------
    chosen : dict
        ``k_sigma``, ``prominence``, ``min_run``, ``width_ratio``, ``frac``, ``steger`` (its ``k_sigma``,
        ``prominence``, ``min_run``), ``colour_rule`` and, with a stage 5, ``stripe_test`` (tracker ->
        None, not asked, or a dict of :class:`trackers.StripeTest` settings).
    summary : dict
        The objective of every setting of every stage (``stage1`` ... ``stage4``, keyed by the
        setting as a string; ``stage5`` per tracker), the chosen settings' figures per group and
        kind (``figures``; stage 5's as ``stage5:<tracker>``, like ``photographs`` and ``blind``),
        ``chosen`` and the number of frames per group.
    records : list of dict
        One per stage, setting, tracker, group and kind (see the module docstring).
    """
    import trackers

    from bench.evaluate.outcomes import detection_figures
    from bench.evaluate.pixels import rotate_image
    from bench.studies.tuning import RECORD_FIELDS, Tally, write_records

    def say(msg):
        if progress:
            print(msg, file=sys.stderr, flush=True)

    out.mkdir(parents=True, exist_ok=True)
    frames = _frames(profile, progress)

    # stage 1: the threshold family's detection
    t1 = Tally(1, profile.hit_px, profile.max_false_rate)
    scores1 = {}
    for k in profile.k_sigma:
        for p in profile.prominence:
            for m in profile.min_run:
                for w in profile.width_ratio:
                    key = _key(k, p, m, w)
                    for n in profile.trackers:
                        t = trackers.make(n, k_sigma=k, prominence=p, min_run=m, width_ratio=w, **_unasked(n))
                        for f in frames:
                            t1.add(key, n, f, t.track(f.image, background=f.background).columns)
                    scores1[(k, p, m, w)] = t1.objective(key)
        say(f"stage 1: k_sigma = {k:g} done")
    def pick1(held, photos):
        sc = {kpmw: t1.objective(_key(*kpmw), held_out=held, photographs=photos) for kpmw in scores1}
        return _key(*choose_grid(t1.eligible(sc, lambda kpmw: _key(*kpmw), held_out=held, photographs=photos),
                                 profile.tie))

    judged = {"stage1": t1.judge(pick1)}
    k_best, p_best, m_best, w_best = {_key(*kpmw): kpmw for kpmw in scores1}[judged["stage1"]["kept"]]
    family = {"k_sigma": k_best, "prominence": p_best, "min_run": m_best, "width_ratio": w_best}
    # stage 2: com_bg's frac on laser-on/off pairs
    mae2, rec2 = {}, []
    synth = [f for f in frames if f.group == "synthetic"]
    for fr in profile.frac:
        key = f"frac={fr:g}"
        t = trackers.make("com_bg", frac=fr, stripe_test=None, **family)
        errs = []
        for f in synth:
            m = frame_scores(t.track(f.image, background=f.background).columns, f.truth, profile.hit_px)
            errs.append(m["mae_px"])
        mae2[fr] = _mean(errs)
        rec2.append({"stage": 2, "setting": key, "tracker": "com_bg", "group": "synthetic", "kind": "all",
                     "mae_px": mae2[fr]})
    say("stage 2 done")
    frac_best = choose_min(mae2, profile.tie_px)
    # stage 3: Steger's detection
    t3 = Tally(3, profile.hit_px, profile.max_false_rate)
    scores3 = {}
    for k in profile.steger_k_sigma:
        for p in profile.steger_prominence:
            for m in profile.steger_min_run:
                key = _key(k, p, m)
                t = trackers.make("steger", k_sigma=k, prominence=p, min_run=m, stripe_test=None)
                for f in frames:
                    t3.add(key, "steger", f, t.track(f.image, background=f.background).columns)
                scores3[(k, p, m)] = t3.objective(key)
        say(f"stage 3: steger k_sigma = {k:g} done")
    def pick3(held, photos):
        sc = {kpm: t3.objective(_key(*kpm), held_out=held, photographs=photos) for kpm in scores3}
        return _key(*choose_grid(t3.eligible(sc, lambda kpm: _key(*kpm), held_out=held, photographs=photos),
                                 profile.tie))

    judged["stage3"] = t3.judge(pick3)
    sk, sp, sm = {_key(*kpm): kpm for kpm in scores3}[judged["stage3"]["kept"]]
    steger = {"k_sigma": sk, "prominence": sp, "min_run": sm}
    # stage 4: the colour rule
    colour = {n: trackers.make(n, **chosen_params(n, family, frac_best, steger), **_unasked(n))
              for n in profile.colour_trackers}
    t4 = Tally(4, profile.hit_px, profile.max_false_rate)
    scores4 = {}
    coloured = [f for f in frames if f.rgb is not None]
    for rule in profile.colour_rules:
        key = f"rule={rule}"
        for f in coloured:
            frame = rotate_image(apply_rule(f.rgb, f.laser, rule), f.rotate)
            for n, t in colour.items():
                t4.add(key, n, f, t.track(frame).columns)
        scores4[rule] = t4.objective(key)
        say(f"stage 4: rule {rule} done")
    def pick4(held, photos):
        sc = {r: t4.objective(f"rule={r}", held_out=held, photographs=photos) for r in scores4}
        ok = t4.eligible(sc, lambda r: f"rule={r}", held_out=held, photographs=photos)
        return f"rule={choose_listed(ok, profile.colour_rules, profile.tie)}"

    judged["stage4"] = t4.judge(pick4)
    rule_best = {f"rule={r}": r for r in scores4}[judged["stage4"]["kept"]]
    chosen = {**family, "frac": frac_best, "steger": steger, "colour_rule": rule_best}
    # stage 5: the stripe question, chosen for each tracker at the settings chosen above
    per5 = run_stripe_stage(5, frames, profile.stripe_trackers, profile.stripe_tests,
                            lambda n: chosen_params(n, family, frac_best, steger), profile.hit_px, profile.tie, say,
                            max_false_rate=profile.max_false_rate)
    stages = [("stage1", t1, _key(k_best, p_best, m_best, w_best)), ("stage3", t3, _key(sk, sp, sm)),
              ("stage4", t4, f"rule={rule_best}")]
    if per5.per:
        chosen["stripe_test"] = per5.chosen
        judged.update(per5.judged)
        stages += per5.stages
    figures = {}
    for name, tally, key in stages:
        figures[name] = {g: {kd: detection_figures(c) for kd, c in kinds.items()}
                         for g, kinds in tally.by_group(key).items()}
        for g, kinds in tally.by_group(key).items():
            figures[name][g]["all"] = detection_figures(sum(kinds.values()))
    n_frames = {g: sum(1 for f in frames if f.group == g) for g in ("synthetic", "renders", "real")}
    blind = {f"stage{t.stage}": {k: v for k, v in t.blind.items() if v} for t in (t1, t3, t4)}
    blind.update(per5.blind)
    summary = {"profile": profile.name, "chosen": chosen, "n_frames": n_frames, "objective": "mean over groups of F1",
               "blind": blind,
               "stage1": {_key(*kpm): s for kpm, s in scores1.items()},
               "stage2_mae_px": {f"frac={f:g}": v for f, v in mae2.items()},
               "stage3": {_key(*kpm): s for kpm, s in scores3.items()},
               "stage4": {f"rule={r}": s for r, s in scores4.items()},
               "stage5": per5.scores,
               "unavoidable_blind_photographs": {name: tally.unavoidable(key) for name, tally, key in stages
                                                 if tally.unavoidable(key)},
               "max_false_rate": profile.max_false_rate, "above_false_rate_ceiling": above_ceiling(stages),
               "figures": figures, "photographs": judged}
    records = t1.records() + rec2 + t3.records() + t4.records() + per5.records()
    write_records(out, "tune.csv", records, summary, (*RECORD_FIELDS, "mae_px"))
    return chosen, summary, records


class StripeStage:
    """The stripe question's stage of a procedure, one choice per tracker (:func:`run_stripe_stage`).

    ``per[tracker] = (tally, scores, judgement, kept)``: its counts (one setting per candidate, named
    by :func:`stripe_key`), candidate index -> objective, the leave-one-rig-out judgement and the
    kept candidate. The other attributes are what a procedure's summary holds of the stage, each
    entry named ``stage<N>:<tracker>``.
    """

    def __init__(self, stage: int, tests, per: dict):
        self.per = per
        names = {n: f"stage{stage}:{n}" for n in per}
        #: tracker -> the kept candidate (None or a dict of settings): the procedure's ``chosen["stripe_test"]``
        self.chosen = {n: kept for n, (*_, kept) in per.items()}
        #: entry -> the leave-one-rig-out judgement (the summary's ``photographs``)
        self.judged = {names[n]: j for n, (_, _, j, _) in per.items()}
        #: (entry, tally, kept setting) per tracker, for the summary's ``figures``
        self.stages = [(names[n], t, stripe_key(kept)) for n, (t, _, _, kept) in per.items()]
        #: entry -> setting -> the plain frames it went blind on (settings that went blind somewhere)
        self.blind = {names[n]: {k: v for k, v in t.blind.items() if v} for n, (t, *_) in per.items()}
        #: tracker -> candidate -> objective (the summary's ``stage<N>``)
        self.scores = {n: {stripe_key(tests[i]): v for i, v in sc.items()} for n, (_, sc, _, _) in per.items()}

    def records(self) -> list[dict]:
        """The stage's records, tracker by tracker (:meth:`bench.studies.tuning.Tally.records`)."""
        return [r for t, *_ in self.per.values() for r in t.records()]


def run_stripe_stage(stage: int, frames, names, tests, params_of, hit_px: float, tie: float, say, *,
                     max_false_rate: float | None = None) -> StripeStage:
    """The stripe question's stage of a procedure, chosen for each tracker on its own outcomes.

    Each tracker reads the answer its own way (the threshold family before its chain, Steger after
    its ridge test, the DP trackers on the rows that support the path), and each has its own
    ``stripe_test``; so every tracker is scored with every candidate, its eligibility counts its
    own blindness, and its choice is judged leave one rig out against its own renders' choice
    (:func:`judge_stripe_tests`).

    Parameters
    ----------
    stage : int
        The stage's number (the ``stage`` column of the records).
    frames : list of bench.studies.tuning.TuningFrame
    names : list of str
        The trackers (each with a ``stripe_test`` parameter); empty: no such stage.
    tests : list
        The candidates (None or dicts of :class:`trackers.StripeTest` settings), in the order that
        breaks ties.
    params_of : callable
        Tracker name -> the settings the stages before chose for it.
    hit_px, tie : float
        The hit rule and the tie band.
    say : callable
        Progress lines.
    max_false_rate : float or None
        The false-report ceiling (:meth:`bench.studies.tuning.Tally.eligible`; None: none).

    Returns
    -------
    StripeStage
    """
    import trackers

    from bench.studies.tuning import Tally

    out = {}
    for n in names:
        tally = Tally(stage, hit_px, max_false_rate)
        scores = {}
        for i, test in enumerate(tests):
            t = trackers.make(n, stripe_test=test, **params_of(n))
            for f in frames:
                tally.add(stripe_key(test), n, f, f.track(t))
            scores[i] = tally.objective(stripe_key(test))
        judgement, kept = judge_stripe_tests(tally, scores, tests, tie)
        out[n] = (tally, scores, judgement, kept)
        say(f"stage {stage}: the stripe question for {n} done (kept {stripe_key(kept)})")
    return StripeStage(stage, tests, out)


def judge_stripe_tests(tally, scored, tests, tie: float):
    """The stripe-question stage's choice, judged leave one rig out (:meth:`bench.studies.tuning.Tally.judge`).

    Parameters
    ----------
    tally : bench.studies.tuning.Tally
        The stage's counts, one setting per candidate (named by :func:`stripe_key`).
    scored : iterable of int
        The indices into ``tests`` of the candidates scored.
    tests : sequence
        The candidates, in the order that breaks ties.
    tie : float
        Scores within ``tie`` of the best are tied.

    Returns
    -------
    (dict, object)
        The judgement and the kept candidate.
    """
    order = list(range(len(tests)))

    def pick(held, photos):
        sc = {i: tally.objective(stripe_key(tests[i]), held_out=held, photographs=photos) for i in scored}
        ok = tally.eligible(sc, lambda i: stripe_key(tests[i]), held_out=held, photographs=photos)
        return stripe_key(tests[choose_listed(ok, order, tie)])

    judged = tally.judge(pick)
    return judged, {stripe_key(t): t for t in tests}[judged["kept"]]


def stripe_key(test) -> str:
    """A stripe-question candidate's name in the tables (``stripe_test=none`` for the question not asked).

    Examples
    --------
    >>> stripe_key(None), stripe_key({}), stripe_key({"colour_min": None})
    ('stripe_test=none', 'stripe_test=defaults', 'stripe_test=colour_min=none')
    """
    from trackers._stripe import as_test

    return "stripe_test=" + ("none" if test is None else as_test(test).label())


def _unasked(name: str) -> dict:
    """``{"stripe_test": None}`` for a tracker with the stripe question, else ``{}`` (stages 1-4 do not ask it)."""
    import trackers

    return {"stripe_test": None} if "stripe_test" in trackers.make(name).get_params() else {}


def chosen_params(name: str, family: dict, frac: float, steger: dict) -> dict:
    """The detection settings a tracker takes from stages 1-3: Steger its own, ``com_bg`` the family's and
    ``frac``, the family's trackers theirs, any other none."""
    import trackers

    params = trackers.make(name).get_params()
    kw = dict(steger) if name == "steger" else dict(family) if "prominence" in params else {}
    if name == "com_bg":
        kw["frac"] = frac
    return kw


def _mean(vals):
    v = [x for x in vals if not np.isnan(x)]
    return float(np.mean(v)) if v else float("nan")


def figure_lines(figures: dict) -> list[str]:
    """One line per group of a stage's chosen setting: F1, recall and false-report rate, overall and by kind."""
    lines = []
    for g, kinds in figures.items():
        allf = kinds["all"]
        parts = ", ".join(f"{k} F1 {v['f1']:.3f} / FRR {v['false_report_rate']:.3f}" for k, v in kinds.items()
                          if k != "all")
        lines.append(f"  {g}: F1 {allf['f1']:.3f}, recall {allf['recall']:.3f}, false-report rate "
                     f"{allf['false_report_rate']:.3f} ({parts})")
    return lines


def study(*, profile=DEFAULT_PROFILE, out=DEFAULT_OUT, quiet: bool = False) -> int:
    """``stripebench tune threshold``: run the procedure on the tuning profile ``profile`` (a TOML path) into
    the folder ``out`` (created), print its choices and return 0; ``quiet``: no progress lines. A bad
    profile raises :class:`bench.config.ConfigError` (one line) before any work."""
    from bench.studies.tuning import judged_lines, run_study

    profile, out, (chosen, summary, _) = run_study(load_profile, run, profile, out, quiet)
    ceiling = summary.get("max_false_rate")

    def top(stage):
        best = sorted(summary[stage].items(), key=lambda kv: -kv[1])[:5]
        return ", ".join(f"{kk} {v:.4f}" for kk, v in best)

    key1 = _key(chosen["k_sigma"], chosen["prominence"], chosen["min_run"], chosen["width_ratio"])
    print(f"frames: {summary['n_frames']}; objective: the mean over groups of F1 over rows")
    print(f"stage 1: chosen {key1} (objective {summary['stage1'][key1]:.4f}; best five: {top('stage1')})")
    print("\n".join(figure_lines(summary["figures"]["stage1"])))
    print("\n".join(judged_lines(summary["photographs"]["stage1"], ceiling)))
    print("stage 2: chosen com_bg frac = {:g} (mean |error| of hits, px: {})".format(
        chosen["frac"], ", ".join(f"{kk} {v:.4f}" for kk, v in summary["stage2_mae_px"].items())))
    st = chosen["steger"]
    key3 = _key(st["k_sigma"], st["prominence"], st["min_run"])
    print(f"stage 3: chosen steger {key3} (objective {summary['stage3'][key3]:.4f}; best five: {top('stage3')})")
    print("\n".join(figure_lines(summary["figures"]["stage3"])))
    print("\n".join(judged_lines(summary["photographs"]["stage3"], ceiling)))
    print("stage 4: chosen colour rule = {} (objective: {})".format(
        chosen["colour_rule"], ", ".join(f"{kk} {v:.4f}" for kk, v in summary["stage4"].items())))
    print("\n".join(figure_lines(summary["figures"]["stage4"])))
    print("\n".join(judged_lines(summary["photographs"]["stage4"], ceiling)))
    for n, test in chosen.get("stripe_test", {}).items():
        key5, sc5 = stripe_key(test), summary["stage5"][n]
        print(f"stage 5 ({n}): chosen {key5} (objective {sc5[key5]:.4f}; all: "
              + ", ".join(f"{kk} {v:.4f}" for kk, v in sc5.items()) + ")")
        print("\n".join(figure_lines(summary["figures"][f"stage5:{n}"])))
        print("\n".join(judged_lines(summary["photographs"][f"stage5:{n}"], ceiling)))
    for stage, names in summary["unavoidable_blind_photographs"].items():
        print(f"{stage}: every setting goes blind on a plain photograph: {', '.join(names)}")
    print("\n".join(ceiling_lines(summary)))
    print(f"{out / 'tune.csv'}")
    return 0


def above_ceiling(stages) -> dict:
    """stage -> (tracker -> false-report rate on the photographs) of the trackers its kept setting leaves above the
    false-report ceiling (:meth:`bench.studies.tuning.Tally.loud`): where no setting of the stage keeps them within
    it. ``stages``: ``(name, tally, kept setting)`` triples."""
    return {name: tally.loud(key) for name, tally, key in stages if tally.loud(key)}


def ceiling_lines(summary) -> list[str]:
    """The lines a procedure prints of its false-report ceiling: the trackers no setting of a stage kept within it."""
    ceiling = summary.get("max_false_rate")
    if ceiling is None:
        return []
    lines = [f"false-report ceiling on the photographs: {ceiling:g} (a setting above it is eligible only where "
             "every setting not blind on a plain photograph is)"]
    for stage, loud in summary.get("above_false_rate_ceiling", {}).items():
        lines.append(f"{stage}: the kept setting leaves " + ", ".join(f"{t} ({r:.3f})" for t, r in loud.items())
                     + " above it")
    return lines

