"""Choose the threshold trackers' detection defaults, ``com_bg``'s threshold-to-zero
and the ``auto`` colour rule by a fixed procedure (``stripebench tune threshold``).

The profile (default ``bench/config/profiles/tune_threshold.toml``) lists the
synthetic frames (kinds of :mod:`bench.studies.hard_frames` and seeds), whether the
shipped real set takes part, the grids and the criteria, which are written in
the profile's header. Three stages, each using the choices of the ones before:

1. ``k_sigma`` x ``prominence`` of the per-row detection
   (:func:`trackers._detect.detect_rows`), scored with the threshold trackers
   on the laser's channel of every synthetic frame and on the photographs as
   ``stripebench real`` gives them (the manifest's channel; ``auto`` is the
   committed rule, :data:`bench.evaluate.colour.AUTO_KNEE`, so the committed defaults
   are a fixed point of the procedure: rerun, it chooses them again);
2. ``com_bg``'s ``frac`` on the synthetic laser-on/laser-off pairs;
3. the ``auto`` colour rule (:func:`bench.evaluate.colour.saturation_blend` with a knee
   from the grid, the plain excess or the laser's channel) on the colour
   versions of every frame.

Output in ``OUT`` (default ``results/runs/tune_threshold/``): ``tune.csv``
(one line per stage, setting, tracker and frame: ``score``, ``hit``,
``quiet``, ``mae_px``, ``recall``), ``summary.json`` (the scores of every setting and
the choices) and one printed line per stage.
"""

from __future__ import annotations

import csv
import json
import pathlib
import sys

import numpy as np

from bench.config.tune import TuneThresholdProfile, load_threshold_profile  # noqa: F401  (the schema)

__all__ = ["TuneThresholdProfile", "load_profile", "frame_scores", "choose_grid", "choose_min", "choose_listed",
           "apply_rule", "run", "main"]

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


def frame_scores(columns, truth, hit_px: float, argmax_cols=None) -> dict[str, float]:
    """A tracker's scores on one frame with known stripe rows.

    Parameters
    ----------
    columns : array_like, shape (H,)
        The tracker's columns (px), NaN where it reports nothing.
    truth : array_like, shape (H,)
        The stripe's column (px), NaN on stripe-less rows.
    hit_px : float
    argmax_cols : array_like, shape (H,), optional
        The frame's brightest pixel per row (plateau middles); gives ``recall``.

    Returns
    -------
    dict
        ``hit``: stripe rows within ``hit_px`` over stripe rows; ``quiet``:
        stripe-less rows without a report over stripe-less rows; ``score``:
        their mean (the balanced accuracy; ``hit`` alone if there is no
        stripe-less row, ``quiet`` alone if there is no stripe row); ``mae_px``:
        mean |error| over the hits (NaN if none); ``recall``: of the stripe
        rows whose brightest pixel is within ``hit_px`` of the truth, the
        fraction the tracker reports within ``hit_px`` (NaN without
        ``argmax_cols`` or such rows).

    Examples
    --------
    >>> frame_scores([10.0, 14.0, np.nan, 3.0], [11.0, 10.0, np.nan, np.nan], 3.0, [10, 10, 0, 0])
    {'hit': 0.5, 'quiet': 0.5, 'score': 0.5, 'mae_px': 1.0, 'recall': 0.5}
    """
    c = np.asarray(columns, float)
    t = np.asarray(truth, float)
    has = np.isfinite(t)
    with np.errstate(invalid="ignore"):
        err = np.abs(c - t)
        hits = has & (err <= hit_px)
    hit = float(hits.sum() / has.sum()) if has.any() else float("nan")
    quiet = float(np.isnan(c[~has]).mean()) if (~has).any() else float("nan")
    parts = [v for v in (hit, quiet) if not np.isnan(v)]
    recall = float("nan")
    if argmax_cols is not None:
        with np.errstate(invalid="ignore"):
            right = has & (np.abs(np.asarray(argmax_cols, float) - t) <= hit_px)
        recall = float(hits[right].mean()) if right.any() else float("nan")
    return {"hit": hit, "quiet": quiet, "score": float(np.mean(parts)) if parts else float("nan"),
            "mae_px": float(err[hits].mean()) if hits.any() else float("nan"), "recall": recall}


def choose_grid(scores: dict, tie: float, recalls: dict | None = None, min_recall: float = 0.0):
    """The ``(k_sigma, prominence)`` of best score among the settings whose
    recall (``recalls``) is at least ``min_recall`` (all settings if none is);
    scores within ``tie`` of the best go to the larger prominence, then the
    larger k_sigma.

    Examples
    --------
    >>> choose_grid({(3.0, 1.1): 0.900, (5.0, 1.5): 0.899, (5.0, 1.1): 0.8}, tie=0.002)
    (5.0, 1.5)
    >>> choose_grid({(3.0, 1.1): 0.900, (8.0, 1.5): 0.95}, 0.002, {(3.0, 1.1): 0.97, (8.0, 1.5): 0.9}, 0.95)
    (3.0, 1.1)
    """
    if recalls is not None:
        ok = {key: s for key, s in scores.items() if recalls[key] >= min_recall}
        scores = ok or scores
    best = max(scores.values())
    near = [key for key, s in scores.items() if s >= best - tie]
    return max(near, key=lambda kp: (kp[1], kp[0]))


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
    """A colour photograph through a candidate rule of stage 3: ``'excess'``,
    ``'laser'`` or a knee of :func:`bench.evaluate.colour.saturation_blend`; a grey
    photograph (2-D, or three equal channels) is returned as it is."""
    from bench.evaluate.colour import LASER_INDEX, saturation_blend
    from bench.store.realset import select_channel

    img = np.asarray(rgb)
    if img.ndim == 2 or (np.array_equal(img[..., 0], img[..., 1]) and np.array_equal(img[..., 0], img[..., 2])):
        return np.ascontiguousarray(img if img.ndim == 2 else img[..., 0])
    if rule == "excess":
        return select_channel(img, "excess", laser)
    if rule == "laser":
        return np.ascontiguousarray(img[..., LASER_INDEX[laser]])
    return saturation_blend(img, laser, float(rule))


def _real_images(profile):
    """(name, frame, background or None, original, rotate, laser, reference) of every shipped photograph; the
    frames as ``stripebench real`` gives them to the trackers (the manifest's channel; ``auto``: the committed rule)."""
    from bench.store import realset as real

    if not profile.real:
        return []
    out = []
    for im in real.load_dataset(real.SHIPPED):
        frame, bg, original, ref = im.load()
        out.append((im.name, frame, bg, original, im.rotate_deg, im.laser_colour, ref))
    return out


def _mean(vals):
    v = [x for x in vals if not np.isnan(x)]
    return float(np.mean(v)) if v else float("nan")


def _setting_score(records, key) -> float:
    syn = _mean([r["score"] for r in records if r["setting"] == key and r["group"] == "synthetic"])
    rl = _mean([r["score"] for r in records if r["setting"] == key and r["group"] == "real"])
    return _mean([syn, rl])


def run(profile: TuneThresholdProfile, out: pathlib.Path, *, progress: bool = True):
    """Run the three stages.

    Returns
    -------
    chosen : dict
        ``k_sigma``, ``prominence``, ``frac``, ``colour_rule``.
    summary : dict
        The scores of every setting of every stage (``stage1``, ``stage2``,
        ``stage3``, keyed by the setting as a string) and ``chosen``.
    records : list of dict
        One per stage, setting, tracker and frame.
    """
    import trackers

    from bench.studies.hard_frames import hard_frame
    from bench.store.realset import rotate_image

    def say(msg):
        if progress:
            print(msg, file=sys.stderr, flush=True)

    out.mkdir(parents=True, exist_ok=True)
    synth = [hard_frame(k, s) for k in profile.kinds for s in profile.seeds]
    reals = _real_images(profile)
    records = []

    def add(stage, setting, tracker, group, name, cols, truth, scorer):
        m = scorer(cols, truth)
        records.append({"stage": stage, "setting": setting, "tracker": tracker, "group": group, "frame": name, **m})

    def real_scorer(cols, ref):
        from bench.evaluate.simreal import image_metrics

        m = image_metrics(cols, ref, profile.hit_px)
        return {"hit": m["hit_rate"], "quiet": float("nan"), "score": m["hit_rate"], "mae_px": m["mae_px"],
                "recall": float("nan")}

    from bench.studies.hard_frames import plateau_middles

    argmax = {id(f): plateau_middles(f.laser_channel) for f in synth}

    # stage 1: detection
    scores1, recall1 = {}, {}
    for k in profile.k_sigma:
        for p in profile.prominence:
            key = f"k_sigma={k:g},prominence={p:g}"
            for n in profile.trackers:
                t = trackers.make(n, k_sigma=k, prominence=p)
                for f in synth:
                    add(1, key, n, "synthetic", f"{f.kind}-{f.seed}", t.track(f.laser_channel).columns, f.truth,
                        lambda c, tr, f=f: frame_scores(c, tr, profile.hit_px, argmax[id(f)]))
                for name, frame, bg, _, _, _, ref in reals:
                    add(1, key, n, "real", name, t.track(frame, background=bg).columns, ref, real_scorer)
            scores1[(k, p)] = _setting_score(records, key)
            per_kind = {}
            for r in records:
                if r["setting"] == key and r["group"] == "synthetic":
                    per_kind.setdefault(r["frame"].rsplit("-", 1)[0], []).append(r["recall"])
            recall1[(k, p)] = min(_mean(v) for v in per_kind.values())  # the worst kind's mean recall
        say(f"stage 1: k_sigma = {k:g} done")
    k_best, p_best = choose_grid(scores1, profile.tie, recall1, profile.min_recall)
    # stage 2: com_bg's frac on laser-on/off pairs
    mae2 = {}
    for fr in profile.frac:
        key = f"frac={fr:g}"
        t = trackers.make("com_bg", k_sigma=k_best, prominence=p_best, frac=fr)
        for f in synth:
            add(2, key, "com_bg", "synthetic", f"{f.kind}-{f.seed}",
                t.track(f.laser_channel, background=f.laser_channel_off).columns, f.truth,
                lambda c, tr: frame_scores(c, tr, profile.hit_px))
        for name, frame, bg, _, _, _, ref in reals:
            if bg is not None:
                add(2, key, "com_bg", "real", name, t.track(frame, background=bg).columns, ref, real_scorer)
        mae2[fr] = _mean([r["mae_px"] for r in records if r["stage"] == 2 and r["setting"] == key
                          and r["group"] == "synthetic"])
    say("stage 2 done")
    frac_best = choose_min(mae2, profile.tie_px)
    # stage 3: the colour rule
    colour = {}
    for n in profile.colour_trackers:
        params = trackers.make(n).get_params()
        kw = {"k_sigma": k_best, "prominence": p_best} if "prominence" in params else {}
        if n == "com_bg":
            kw["frac"] = frac_best
        colour[n] = trackers.make(n, **kw)
    scores3 = {}
    for rule in profile.colour_rules:
        key = f"rule={rule}"
        for f in synth:
            frame = apply_rule(f.rgb, f.laser, rule)
            for n, t in colour.items():
                add(3, key, n, "synthetic", f"{f.kind}-{f.seed}", t.track(frame).columns, f.truth,
                    lambda c, tr: frame_scores(c, tr, profile.hit_px))
        for name, _, _, original, rot, laser, ref in reals:
            if np.asarray(original).ndim != 3:
                continue
            frame = rotate_image(apply_rule(original, laser, rule), rot)
            for n, t in colour.items():
                add(3, key, n, "real", name, t.track(frame).columns, ref, real_scorer)
        scores3[rule] = _setting_score(records, key)
        say(f"stage 3: rule {rule} done")
    rule_best = choose_listed(scores3, profile.colour_rules, profile.tie)
    chosen = {"k_sigma": k_best, "prominence": p_best, "frac": frac_best, "colour_rule": rule_best}
    summary = {"profile": profile.name, "chosen": chosen,
               "stage1": {f"k_sigma={k:g},prominence={p:g}": s for (k, p), s in scores1.items()},
               "stage1_recall": {f"k_sigma={k:g},prominence={p:g}": s for (k, p), s in recall1.items()},
               "stage2_mae_px": {f"frac={f:g}": v for f, v in mae2.items()},
               "stage3": {f"rule={r}": s for r, s in scores3.items()},
               "n_synthetic": len(synth), "n_real": len(reals)}
    fields = ["stage", "setting", "tracker", "group", "frame", "score", "hit", "quiet", "mae_px", "recall"]
    with open(out / "tune.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=fields)
        w.writeheader()
        for r in records:
            w.writerow({k: (f"{r[k]:.6f}" if isinstance(r[k], float) else r[k]) for k in fields})
    (out / "summary.json").write_text(json.dumps(summary, indent=2))
    return chosen, summary, records


def _by_kind(records, stage, setting, group="synthetic"):
    kinds = {}
    for r in records:
        if r["stage"] == stage and r["setting"] == setting and r["group"] == group:
            kinds.setdefault(r["frame"].rsplit("-", 1)[0], []).append(r["score"])
    return ", ".join(f"{k} {_mean(v):.3f}" for k, v in kinds.items())


def add_arguments(parser) -> None:
    """The procedure's options (``stripebench tune threshold``; ``python -m bench.studies.tune_threshold``)."""
    from bench.config.options import add_out, add_quiet

    parser.add_argument("--profile", type=pathlib.Path, default=DEFAULT_PROFILE, metavar="TOML",
                        help="tuning profile (default: bench/config/profiles/tune_threshold.toml)")
    add_out(parser, "output folder", default=DEFAULT_OUT)
    add_quiet(parser, "no progress lines")


def command(args) -> int:
    """Run the procedure with parsed options; a bad profile raises :class:`bench.config.ConfigError`
    (one line) before any work."""
    profile = load_profile(args.profile)
    out = pathlib.Path(args.out)
    chosen, summary, records = run(profile, out, progress=not args.quiet)
    k, p = chosen["k_sigma"], chosen["prominence"]
    s1 = summary["stage1"]
    key1 = f"k_sigma={k:g},prominence={p:g}"
    top = sorted(s1.items(), key=lambda kv: -kv[1])[:5]
    print(f"stage 1: chosen k_sigma = {k:g}, prominence = {p:g} (score {s1[key1]:.4f}; best five: "
          + ", ".join(f"{kk} {v:.4f}" for kk, v in top) + f"); by kind: {_by_kind(records, 1, key1)}")
    print("stage 2: chosen com_bg frac = {:g} (mean |error| of hits, px: {})".format(
        chosen["frac"], ", ".join(f"{kk} {v:.4f}" for kk, v in summary["stage2_mae_px"].items())))
    print("stage 3: chosen colour rule = {} (score: {})".format(
        chosen["colour_rule"], ", ".join(f"{kk} {v:.4f}" for kk, v in summary["stage3"].items())))
    print(f"{out / 'tune.csv'}")
    return 0


def main(argv=None) -> int:
    """``python -m bench.studies.tune_threshold``: ``stripebench tune threshold`` with the same options."""
    from bench.config.options import study_main

    return study_main("python -m bench.studies.tune_threshold", __doc__, add_arguments, command, argv)


if __name__ == "__main__":
    raise SystemExit(main())
