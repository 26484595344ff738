"""Predict the trackers' figures on a rig's photographs from frames with truth made of them (``stripebench predict``).

Each photograph is measured (:func:`bench.evaluate.conditions.measure`), its own stripe found and moved both ways,
and itself kept in place (:mod:`bench.run.predict_frames`); the trackers are scored on those frames as a photograph
is scored (:mod:`bench.evaluate.outcomes`), and their figures pooled over the photographs. A photograph whose stripe
is wider than the reference window is predicted shrunk where that brings it in range, and labelled so; one with no
such answer is named with its reason (:func:`bench.evaluate.stripe.why_left_out`) and left out. What is stated, each
figure from its source with its interval, the pick and its chance of being best, follows the calibration judged
leave one rig out on the shipped set (:mod:`bench.evaluate.predict_loro`). The rules and their tuned values are
docs/predict.md's (:class:`bench.evaluate.predict_settings.PredictSettings`).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bench.evaluate import conditions as cond
from bench.evaluate.predict_settings import DEFAULT, PredictSettings
from bench.run.predict_frames import N_FULL, collect_photos, cut_counts, load_photo, photo_conditions, \
    transplant_outcomes, transplanted

__all__ = ["Made", "PREDICTED_NAMES", "run_predict", "laser_mismatch", "default_trackers"]

#: The names the prediction's tables give :func:`bench.evaluate.ranking.bootstrap_frames`' figures.
PREDICTED_NAMES = {"recall": "hit_rate", "false_report_rate": "false_report_rate", "f1": "f1"}


@dataclass(frozen=True)
class Made:
    """One photograph's frames with truth, or why it has none at its own size: ``out_of_range`` (the measures that
    put it out of the transplant's range, :func:`bench.run.predict_frames.transplanted`; empty: in range), ``shrink``
    (the shrink its frames were made at: the one asked for, or a coarser one that brought it in range; None: no
    answer), the two moved frames' shifts (px), the conditions of its first moved frame and their distance from the
    photograph's (:func:`bench.evaluate.conditions.distance`, scale units) and its stripe's width (px, FWHM).

    Examples
    --------
    >>> Made(("width_px",), shrink=2).answered, Made(("visible",)).answered, Made((), 1, 17, 21).shift_back_px
    (True, False, 21)
    """

    out_of_range: tuple
    shrink: int | None = None
    shift_px: int | None = None
    shift_back_px: int | None = None
    conditions: cond.Conditions | None = None
    distance: float = float("nan")
    width_px: float = float("nan")

    @property
    def answered(self) -> bool:
        """Whether the photograph has frames to predict from (at its own size or shrunk)."""
        return self.shrink is not None


def default_trackers() -> list[str]:
    """The trackers ``predict`` predicts by default: every listed one of the registry, and ``learned``.

    Examples
    --------
    >>> {"dp_gap", "learned", "threshold"} <= set(default_trackers())
    True
    """
    import trackers

    listed = trackers.available()
    return listed + [n for n in ("learned",) if n not in listed]


def laser_mismatch(photos, settings: PredictSettings = DEFAULT) -> list[tuple[str, str, str]]:
    """``(name, laser given, likelier laser)`` of every colour photograph whose trackers see the laser's colour and
    whose stripe stands out far more in another laser colour's excess
    (:func:`bench.evaluate.conditions.likelier_laser`)."""
    from bench.evaluate.pixels import rotate_image

    out = []
    for ph in photos:
        if ph.colour and ph.channel in settings.colour_guided:
            other = cond.likelier_laser(rotate_image(ph.original, ph.rotate_deg), ph.laser, settings=settings)
            if other is not None:
                out.append((ph.name, ph.laser, other))
    return out


def run_predict(folder, out_dir, specs, *, channel: str = "auto", laser: str = "red", rotate_deg: int = 0,
                downscale: int = 1, n_boot: int = 1000, seed: int = 0, settings: PredictSettings = DEFAULT,
                calibration=None, say=None, err=None) -> dict:
    """``stripebench predict``: measure the photographs, make frames with truth of each, score the trackers, and state
    what the calibration backs.

    Each photograph's stripe is moved both ways and kept in place (:func:`bench.run.predict_frames.transplanted`;
    ``seed`` seeds the clean plate's noise). A photograph whose stripe is wider than the reference window is made
    again shrunk by the least factor that brings it in range (:func:`bench.evaluate.stripe.shrink_for`), its frames
    then standing for trackers run on the shrunk photograph; one with no answer is named and left out.
    ``downscale``: every photograph is shrunk by this factor first. ``settings``: the tuned values, written into
    ``predict.json``. ``calibration``: :func:`bench.store.predictfiles.read_calibration`'s (None: every figure the
    method's own, labelled uncalibrated).

    Writes ``predicted.csv`` (per tracker: ``f1``, ``false_report_rate``, ``hit_rate`` as stated, each with its
    interval ``_lo``, ``_hi`` and ``_source``; the method's own ``_predicted`` with its bootstrap interval over the
    photographs; the ``_null``; ``chance_best``, ``pick``, ``tied``; ``n_photos``, ``n_frames``),
    ``predicted_photos.csv`` (per photograph answered and tracker: ``shrink``, the three figures on its frames' rows
    and the row-outcome counts), ``conditions.csv`` (per photograph: its image conditions and its first moved
    frame's, the distance, the shifts, ``status``: ``own size``, ``shrunk by N`` or ``out of range``, and why) and
    ``predict.json`` (the settings and the pick, :mod:`bench.store.predictfiles`) into ``out_dir``; returns what the
    report and the terminal need.

    Raises
    ------
    bench.store.realset.ImageError
        ``folder`` is not a folder, holds no readable photograph, or a laser colour the photographs do not show.
    """
    import pandas as pd

    from bench.evaluate import stripe as sp
    from bench.evaluate.outcomes import COUNT_KEYS, outcome_counts
    from bench.evaluate.ranking import bootstrap_frames
    from bench.evaluate.predict_loro import FIGURES, stated
    from bench.evaluate.prediction import predicted_figures
    from bench.run.track import build_trackers
    from bench.store import realset as real
    from bench.store.files import atomic_write_text
    from bench.store.predictfiles import write_predict_settings

    s = settings
    say = (lambda m: print(m, file=sys.stderr, flush=True)) if say is None else say

    def warn(m):  # a photograph left out or answered coarsely: said even when progress is not
        print(m, file=sys.stderr if err is None else err, flush=True)

    photos = collect_photos(folder, channel=channel, laser=laser, rotate_deg=rotate_deg, downscale=downscale,
                            err=err, settings=s)
    if not photos:
        raise real.ImageError(f"{str(folder)!r}: no readable photograph (PNG, JPEG, TIFF)")
    conds = {ph.name: _noted(ph, s, warn) for ph in photos}
    wrong = laser_mismatch(photos, s)
    if wrong:
        name, given, other = wrong[0]
        more = f" (and {len(wrong) - 1} more)" if len(wrong) > 1 else ""
        raise real.ImageError(f"{name}{more}: its stripe stands out far more in the {other} excess than in the "
                              f"{given} one the trackers see: the laser is {other}, not {given}; give `--laser {other}` "
                              "(a real set: its manifest's laser_colour)")
    trackers = build_trackers(specs)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    made, frames, answer = {}, {}, {}
    for ph in photos:
        c = conds[ph.name]
        made[ph.name], frames[ph.name], answer[ph.name] = _made(ph, c, seed, downscale, s)
        m = made[ph.name]
        why = sp.why_left_out(m.out_of_range, width_px=c.width_px, settings=s)
        if not m.answered:
            warn(f"stripebench predict: {ph.name}: out of range ({why}): left out; the stated figures count it at "
                 "the null's")
        elif m.out_of_range:
            warn(f"stripebench predict: {ph.name}: predicted shrunk by {m.shrink} ({why}): a coarse answer, for "
                 "trackers run on the shrunk photograph (predicted_photos.csv); the stated figures count it at the "
                 "null's")
        else:
            say(f"stripebench predict: {ph.name}: its stripe moved by {m.shift_px:+d} and {m.shift_back_px:+d} px "
                f"(distance {m.distance:.2f})")
    answered = [ph for ph in photos if made[ph.name].answered]
    pooled_photos = [ph for ph in answered if not made[ph.name].out_of_range]  # coarse answers are not pooled
    per_photo, sheet = {}, {}
    for i, ph in enumerate(answered):
        per_photo[ph.name] = transplant_outcomes(trackers, frames[ph.name], answer[ph.name].background, ph.laser)
        sheet[ph.name] = [(rgb if rgb.ndim == 3 else image, truth) for image, truth, _, rgb, _ in frames[ph.name]]
        say(f"stripebench predict: tracked {i + 1}/{len(answered)} ({ph.name})")
    labels = list(trackers)
    predicted = _pooled(per_photo, pooled_photos, labels, sheet, n_boot, seed)
    photo_rows, counts = [], np.zeros((len(pooled_photos), len(labels), len(COUNT_KEYS)), np.int64)
    for ph in answered:
        for j, lab in enumerate(labels):
            c = outcome_counts(np.concatenate([x.ravel() for x in per_photo[ph.name][lab][:N_FULL]]))
            if ph in pooled_photos:
                counts[pooled_photos.index(ph), j] = [c[k] for k in COUNT_KEYS]
            cut = cut_counts(per_photo[ph.name][lab])
            fig = predicted_figures({**c, **cut})
            photo_rows.append({"name": ph.name, "tracker": lab, "shrink": made[ph.name].shrink,
                               **{n: fig[k] for k, n in PREDICTED_NAMES.items()}, **c, **cut})
    per_photo_table = pd.DataFrame.from_records(photo_rows, columns=["name", "tracker", "shrink",
                                                                     *PREDICTED_NAMES.values(), *COUNT_KEYS,
                                                                     "n_false_cut", "n_quiet_cut"])
    share = len(pooled_photos) / len(photos)  # the rest count at the null's figure (docs/predict.md)
    said = stated({f: predicted[f"{f}_predicted"].to_numpy(float) for f in FIGURES}, labels, calibration,
                  counts if pooled_photos else None, answered=share, n_draws=s.pick_draws, tie_chance=s.tie_chance,
                  seed=seed)
    for f in FIGURES:
        predicted[f] = said[f]["value"]
        predicted[f"{f}_lo"], predicted[f"{f}_hi"] = said[f]["lo"], said[f]["hi"]
        predicted[f"{f}_source"] = said[f]["source"]
        predicted[f"{f}_null"] = [np.nan if calibration is None else calibration[f]["null"].get(t, np.nan)
                                  for t in labels]
    predicted["chance_best"] = said["chance"]
    predicted["pick"] = [t == said["pick"] for t in labels]
    predicted["tied"] = [t in said["tied"] for t in labels]
    first = ["tracker", *(k for f in FIGURES for k in (f, f"{f}_lo", f"{f}_hi", f"{f}_source")), "chance_best", "pick",
             "tied"]
    predicted = predicted[first + [c for c in predicted.columns if c not in first]]
    conditions_table = _conditions_table(photos, made, conds, s)
    atomic_write_text(out / "predicted.csv", predicted.to_csv(index=False, float_format="%.6g"))
    atomic_write_text(out / "conditions.csv", conditions_table.to_csv(index=False, float_format="%.6g"))
    atomic_write_text(out / "predicted_photos.csv", per_photo_table.to_csv(index=False, float_format="%.6g"))
    pick = {"tracker": said["pick"], "source": said["pick_source"], "tied": said["tied"],
            "chance": None if said["pick"] is None else float(said["chance"][labels.index(said["pick"])]),
            "loro_regret": None if calibration is None else calibration["pick"]["regret"]}
    doc = {"kind": "predict", "folder": str(Path(folder)), "trackers": [t.to_value() for t in specs],
           "channel": channel, "laser": laser, "rotate_deg": int(rotate_deg), "downscale": int(downscale),
           "n_boot": n_boot, "seed": seed, "fallback_rows": [ph.name for ph in photos if ph.fallback_rows],
           "out_of_range": {ph.name: list(made[ph.name].out_of_range) for ph in photos if made[ph.name].out_of_range},
           "shrunk": {ph.name: made[ph.name].shrink for ph in photos
                      if made[ph.name].answered and made[ph.name].shrink != downscale},
           "answered_share": share, "calibration": None if calibration is None else calibration.get("provenance"),
           "pick": pick}
    write_predict_settings(out, doc, s)
    return {"out": out, "photos": photos, "made": made, "conditions": conds, "frames": sheet,
            "predicted": predicted, "predicted_photos": per_photo_table, "conditions_table": conditions_table,
            "settings": doc, "predict_settings": s, "calibration": calibration, "pick": pick}


def _noted(ph, s: PredictSettings, warn):
    """The photograph's conditions, and one line each where its stripe seems to run across the frame or a line seems
    drawn over it."""
    from bench.evaluate import overlay
    from bench.evaluate.pixels import rotate_image

    c = photo_conditions(ph.frame, ph.background, ph.original, rotate_deg=ph.rotate_deg, laser=ph.laser, settings=s)
    turned = rotate_image(ph.original, ph.rotate_deg)  # the stripe runs down it, as the frame's
    drawn = overlay.drawn_over(turned) if ph.colour else 0  # the line's rows, where it counts as drawn over
    if drawn:
        warn(f"stripebench predict: {ph.name}: a thin dark line seems drawn over it in {drawn} "
             f"of its {turned.shape[0]} rows (a tracker's output saved with the frame?): the trackers and the "
             "prediction read that line, not the camera's pixels alone (docs/real.md, \"A line drawn over "
             "`ag_tape`'s stripe\")")
    if cond.runs_across(ph.frame, ph.background, c, settings=s):
        warn(f"stripebench predict: {ph.name}: its stripe seems to run across the frame, not down it (the "
             "trackers read one column per row): if it does, give `--rotate 90` or `--rotate 270`")
    return c


def _made(ph, c, seed: int, downscale: int, s: PredictSettings) -> tuple:
    """``(Made, frames, the photograph the frames were made of)``: at the shrink asked for, else, for a stripe too
    wide, at the least coarser shrink that brings it in range (:func:`bench.evaluate.stripe.shrink_for`)."""
    from bench.evaluate import stripe as sp
    from bench.store import realset as real

    made, bad = transplanted(ph, seed=seed, measured=c, settings=s)
    used = ph
    if bad == ("width_px",) and ph.source is not None and s.shrink_coarse:
        n = sp.shrink_for(c.width_px, downscale, settings=s)
        if n is not None:
            try:
                used = load_photo(ph.source, downscale=n, settings=s)
            except (real.ImageError, real.DatasetError):
                used = None
            if used is not None:
                made, _ = transplanted(used, seed=seed, settings=s)
                if made:
                    return _record(bad, n, made, used, c, s), made, used
    if bad:
        return Made(bad, width_px=c.width_px), [], None
    return _record((), downscale, made, used, c, s), made, used


def _record(bad, shrink: int, made: list, photo, c, s: PredictSettings) -> Made:
    image, _, _, rgb, shift = made[0]
    moved = cond.measure(image, photo.background, rgb=rgb if photo.colour else None, laser=photo.laser, settings=s)
    own = c if shrink == photo.downscale and not bad else photo_conditions(
        photo.frame, photo.background, photo.original, rotate_deg=photo.rotate_deg, laser=photo.laser, settings=s)
    return Made(tuple(bad), shrink, shift, made[1][4], moved, cond.distance(own, moved, settings=s), c.width_px)


def _pooled(per_photo: dict, answered: list, labels: list, sheet: dict, n_boot: int, seed: int):
    """Per tracker, the method's figures pooled over ``answered`` (the photographs answered at the size asked: a coarse
    answer made the rig's figure worse judged leave one rig out, and is not pooled), ``<figure>_predicted``, with 95 %
    bootstrap intervals over them: hit rate and F1 from the first ``N_FULL`` frames, the false-report rate from
    every frame."""
    import pandas as pd

    from bench.evaluate.ranking import bootstrap_frames

    rows = []
    for j, lab in enumerate(labels):
        codes = [np.concatenate([c.ravel() for c in per_photo[ph.name][lab][:N_FULL]]) for ph in answered]
        every = [np.concatenate([c.ravel() for c in per_photo[ph.name][lab]]) for ph in answered]
        extra = any(len(per_photo[ph.name][lab]) > N_FULL for ph in answered)
        rec = {"tracker": lab, "n_photos": len(answered), "n_frames": sum(len(sheet[ph.name]) for ph in answered)}
        if codes:
            b = bootstrap_frames(codes, n_boot=n_boot, seed=seed + j)
            b_all = bootstrap_frames(every, n_boot=n_boot, seed=seed + j) if extra else b
            for k, name in PREDICTED_NAMES.items():
                src = b_all if k == "false_report_rate" else b
                rec[f"{name}_predicted"], rec[f"{name}_predicted_lo"], rec[f"{name}_predicted_hi"] = \
                    src[k], src[f"{k}_lo"], src[f"{k}_hi"]
        else:
            for name in PREDICTED_NAMES.values():
                rec[f"{name}_predicted"] = rec[f"{name}_predicted_lo"] = rec[f"{name}_predicted_hi"] = float("nan")
        rows.append(rec)
    return pd.DataFrame.from_records(rows)


def _conditions_table(photos, made, conds, s: PredictSettings):
    """One line per photograph and side (``photo``, ``moved``): every measure, the distance, the shifts, the status
    and why (:func:`bench.evaluate.stripe.why_left_out`)."""
    import pandas as pd

    from bench.evaluate import stripe as sp

    rows = []
    for ph in photos:
        m = made[ph.name]
        status = ("out of range" if not m.answered else f"shrunk by {m.shrink}" if m.out_of_range else "own size")
        why = sp.why_left_out(m.out_of_range, width_px=m.width_px, settings=s) if m.out_of_range else ""
        base = {"name": ph.name, "status": status, "out_of_range": " ".join(m.out_of_range), "why": why,
                "shrink": m.shrink, "distance": m.distance, "shift_px": m.shift_px, "shift_back_px": m.shift_back_px}
        rows.append({**base, "side": "photo", **conds[ph.name].as_dict()})
        if m.conditions is not None:
            rows.append({**base, "side": "moved", **m.conditions.as_dict()})
    return pd.DataFrame.from_records(rows)
