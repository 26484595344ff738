"""Predict the trackers' figures on a rig's photographs from frames with truth made of them (``stripebench predict``).

Each photograph is measured (:func:`bench.evaluate.conditions.measure`), its own stripe found and moved both ways,
and itself kept in place (:mod:`bench.run.predict_frames`); the trackers are scored on those frames as a photograph
is scored (:mod:`bench.evaluate.outcomes`), and their figures pooled over the photographs with bootstrap intervals.
A photograph whose stripe is wider than the reference window, or whose moved stripe is seen in too few rows, is *out
of range*: named with its reason and left out. The rules and their tuned values are docs/predict.md's
(:class:`bench.evaluate.predict_settings.PredictSettings`).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bench.evaluate import conditions as cond
from bench.evaluate.predict_settings import DEFAULT, PredictSettings
from bench.run.predict_frames import N_FULL, collect_photos, cut_counts, downscale_for, photo_conditions, \
    transplant_outcomes, transplanted

__all__ = ["Made", "PREDICTED_NAMES", "run_predict"]

#: The names the prediction's tables give :func:`bench.evaluate.outcomes.bootstrap_frames`' figures.
PREDICTED_NAMES = {"recall": "hit_rate", "false_report_rate": "false_report_rate", "f1": "f1"}


@dataclass(frozen=True)
class Made:
    """One photograph's frames with truth, or why it has none: ``out_of_range`` (the measures that put it out of the
    transplant's range, :func:`bench.run.predict_frames.transplanted`; empty: in range), the two moved frames' shifts
    (px), the conditions of its first moved frame and their distance from the photograph's
    (:func:`bench.evaluate.conditions.distance`, scale units).

    Examples
    --------
    >>> Made(("width_px",)).out_of_range, Made((), 17, 21).shift_back_px
    (('width_px',), 21)
    """

    out_of_range: tuple
    shift_px: int | None = None
    shift_back_px: int | None = None
    conditions: cond.Conditions | None = None
    distance: float = float("nan")


def run_predict(folder, out_dir, specs, *, channel: str = "auto", laser: str = "red", rotate_deg: int = 0,
                downscale: int = 1, n_boot: int = 1000, seed: int = 0, settings: PredictSettings = DEFAULT,
                say=None, err=None) -> dict:
    """``stripebench predict``: measure the photographs, make frames with truth of each, score the trackers.

    Each photograph's stripe is moved both ways and kept in place (:func:`bench.run.predict_frames.transplanted`;
    ``seed`` seeds the clean plate's noise). A photograph whose moved stripe is seen in too few rows (``visible``) or
    whose stripe is wider than the reference window (``width_px``) is out of range: named with the measure and left
    out. ``downscale``: each photograph (and laser-off frame) is shrunk by this factor first
    (:func:`bench.run.predict_frames.collect_photos`), for trackers run on shrunk frames. ``settings``: the tuned
    values, written into ``predict.json``.

    Writes ``conditions.csv`` (one line per photograph and side, ``photo`` or ``moved``: every measure, the distance,
    the shifts, ``status`` matched / out of range and the measures out of range), ``predicted.csv`` (per tracker:
    ``hit_rate``, ``false_report_rate``, ``f1`` with 95 % bootstrap intervals over the photographs in range,
    ``n_photos``, ``n_frames``), ``predicted_photos.csv`` (per photograph in range and tracker: the three figures on
    its frames' rows and the row-outcome counts ``n_hit`` ...) and ``predict.json`` (the settings,
    :mod:`bench.store.predictfiles`) into ``out_dir``; returns what the report needs
    (:func:`bench.report.predict.build_predict_report`).

    Raises
    ------
    bench.store.realset.ImageError
        ``folder`` is not a folder, or holds no readable photograph.
    """
    import pandas as pd

    from bench.evaluate import overlay
    from bench.evaluate.outcomes import COUNT_KEYS, bootstrap_frames, outcome_counts
    from bench.evaluate.pixels import rotate_image
    from bench.evaluate.prediction import predicted_figures
    from bench.run.track import build_trackers
    from bench.store import realset as real
    from bench.store.files import atomic_write_text
    from bench.store.predictfiles import write_predict_settings

    s = settings
    say = (lambda m: print(m, file=sys.stderr, flush=True)) if say is None else say

    def warn(m):  # a photograph left out: said even when progress is not
        print(m, file=sys.stderr if err is None else err, flush=True)

    photos = collect_photos(folder, channel=channel, laser=laser, rotate_deg=rotate_deg, downscale=downscale,
                            err=err, settings=s)
    if not photos:
        raise real.ImageError(f"{str(folder)!r}: no readable photograph (PNG, JPEG, TIFF)")
    trackers = build_trackers(specs)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    made, conds, frames = {}, {}, {}

    def measured(ph):  # the photograph's conditions, and one line each where its stripe seems to run across the
        # frame or to be of another colour than the laser's, or a line seems drawn over it
        c = photo_conditions(ph.frame, ph.background, ph.original, rotate_deg=ph.rotate_deg, laser=ph.laser,
                             settings=s)
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
        if ph.colour and ph.channel in s.colour_guided:
            other = cond.likelier_laser(turned, ph.laser, settings=s)
            if other is not None:
                warn(f"stripebench predict: {ph.name}: its stripe stands out far more in the {other} excess than in "
                     f"the {ph.laser} one the trackers see: if the laser is {other}, give `--laser {other}` (a real "
                     "set: its manifest's laser_colour)")
        return c

    for ph in photos:
        conds[ph.name] = measured(ph)
        frames[ph.name], bad = transplanted(ph, seed=seed, measured=conds[ph.name], settings=s)
        if bad:
            made[ph.name] = Made(bad)
            w = conds[ph.name].width_px
            n = downscale_for(w, downscale, settings=s) if bad == ("width_px",) else None
            shrink = ("shrink the photographs" if n is None else
                      f"shrink the photographs: by {n} (`predict --downscale {n}`) it is about "
                      f"{w * downscale / n:.1f} px")
            why = (f"width_px: its stripe is {w:.1f} px wide, wider than the reference window's "
                   f"{s.max_width_px} px; {shrink}" if bad == ("width_px",) else
                   f"visible: the moved stripe is seen in fewer than {s.min_rows} rows")
            warn(f"stripebench predict: {ph.name}: out of range ({why}): left out")
            continue
        image, _, _, rgb, shift = frames[ph.name][0]
        back = frames[ph.name][1][4]
        c = cond.measure(image, ph.background, rgb=rgb if ph.colour else None, laser=ph.laser, settings=s)
        made[ph.name] = Made((), shift, back, c, cond.distance(conds[ph.name], c, settings=s))
        say(f"stripebench predict: {ph.name}: its stripe moved by {shift:+d} and {back:+d} px "
            f"(distance {made[ph.name].distance:.2f})")
    matched = [ph for ph in photos if not made[ph.name].out_of_range]
    per_photo, sheet = {}, {}
    for i, ph in enumerate(matched):
        per_photo[ph.name] = transplant_outcomes(trackers, frames[ph.name], ph.background)
        sheet[ph.name] = [(rgb if rgb.ndim == 3 else image, truth) for image, truth, _, rgb, _ in frames[ph.name]]
        say(f"stripebench predict: tracked {i + 1}/{len(matched)} ({ph.name})")
    rows = []
    for j, lab in enumerate(trackers):
        # hit rate and F1 from the first N_FULL frames; the false-report rate from every frame
        codes = [np.concatenate([c.ravel() for c in per_photo[ph.name][lab][:N_FULL]]) for ph in matched]
        every = [np.concatenate([c.ravel() for c in per_photo[ph.name][lab]]) for ph in matched]
        extra = any(len(per_photo[ph.name][lab]) > N_FULL for ph in matched)
        rec = {"tracker": lab, "n_photos": len(matched), "n_frames": sum(len(sheet[ph.name]) for ph in matched)}
        if codes:
            b = bootstrap_frames(codes, n_boot=n_boot, seed=seed + j)
            # the false-report rate from every frame: a second bootstrap only where there are more frames
            b_all = bootstrap_frames(every, n_boot=n_boot, seed=seed + j) if extra else b
            for k, name in PREDICTED_NAMES.items():
                src = b_all if k == "false_report_rate" else b
                rec[name], rec[f"{name}_lo"], rec[f"{name}_hi"] = src[k], src[f"{k}_lo"], src[f"{k}_hi"]
        else:
            for name in PREDICTED_NAMES.values():
                rec[name] = rec[f"{name}_lo"] = rec[f"{name}_hi"] = float("nan")
        rows.append(rec)
    predicted = pd.DataFrame.from_records(rows)
    photo_rows = []
    for ph in matched:
        for lab in trackers:
            counts = outcome_counts(np.concatenate([c.ravel() for c in per_photo[ph.name][lab][:N_FULL]]))
            cut = cut_counts(per_photo[ph.name][lab])
            fig = predicted_figures({**counts, **cut})
            photo_rows.append({"name": ph.name, "tracker": lab, **{n: fig[k] for k, n in PREDICTED_NAMES.items()},
                               **counts, **cut})
    per_photo_table = pd.DataFrame.from_records(
        photo_rows, columns=["name", "tracker", *PREDICTED_NAMES.values(), *COUNT_KEYS, "n_false_cut", "n_quiet_cut"])
    crow = []
    for ph in photos:
        m = made[ph.name]
        base = {"name": ph.name, "status": "out of range" if m.out_of_range else "matched",
                "out_of_range": " ".join(m.out_of_range), "distance": m.distance, "shift_px": m.shift_px,
                "shift_back_px": m.shift_back_px}
        crow.append({**base, "side": "photo", **conds[ph.name].as_dict()})
        if m.conditions is not None:
            crow.append({**base, "side": "moved", **m.conditions.as_dict()})
    conditions_table = pd.DataFrame.from_records(crow)
    atomic_write_text(out / "predicted.csv", predicted.to_csv(index=False, float_format="%.6g"))
    atomic_write_text(out / "conditions.csv", conditions_table.to_csv(index=False, float_format="%.6g"))
    atomic_write_text(out / "predicted_photos.csv", per_photo_table.to_csv(index=False, float_format="%.6g"))
    doc = {"kind": "predict", "folder": str(Path(folder)), "trackers": [sp.to_value() for sp in specs],
           "channel": channel, "laser": laser, "rotate_deg": int(rotate_deg), "downscale": int(downscale),
           "n_boot": n_boot, "seed": seed, "fallback_rows": [ph.name for ph in photos if ph.fallback_rows],
           "out_of_range": {ph.name: list(made[ph.name].out_of_range) for ph in photos if made[ph.name].out_of_range}}
    write_predict_settings(out, doc, s)
    return {"out": out, "photos": photos, "made": made, "conditions": conds, "frames": sheet,
            "predicted": predicted, "predicted_photos": per_photo_table, "conditions_table": conditions_table,
            "settings": doc, "predict_settings": s}
