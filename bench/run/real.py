"""Running trackers on photographs: ``stripebench track`` and ``stripebench real``.

``track`` writes, per image, ``NAME.csv`` (``row``, then ``col_<label>``,
``score_<label>`` per tracker; rows of the frame the trackers saw, i.e. the
image turned by ``--rotate``) and ``NAME_overlay.png`` (the photograph with a
marker per row and tracker, one colour per label, in the photograph's own
orientation), into an output folder guarded like every run folder (kind
``track``: locked, one tracker setting per folder unless ``force``; inputs
whose outputs would collide or that lie inside the folder refused).

``real`` evaluates trackers on a real set (layout in :mod:`bench.store.realset`) into a
run folder of kind ``real`` (its files: :mod:`bench.store.realrun`): per-image
and mean metrics, the tracks and overlays of every image, ``summary.json`` with
per-tracker means and bootstrap CIs, and detection per rig with intervals over its photographs and over rigs
(:func:`bench.evaluate.loro.rig_figures`); the command adds ``report.html``
(:mod:`bench.report.real`).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from bench.errors import one_line
from bench.evaluate.loro import rig_figures
from bench.evaluate.outcomes import COUNT_KEYS, FIGURE_KEYS, HIT_PX, outcome_counts, row_outcomes
from bench.evaluate.ranking import bootstrap_frames
from bench.evaluate.simreal import image_metrics
from bench.evaluate.stats import bootstrap_mean
from bench.run.camera_view import colour_of
from bench.run.track import STATUS, build_trackers, track_frame
from bench.store import realset as real
from bench.store.realrun import write_track_csv

__all__ = ["track_images", "run_real", "predict_real", "DETECTION_KEYS", "PER_IMAGE_MEANS"]

#: The detection figures of a real run's ``mean`` rows: pooled over the photographs' rows
#: (:func:`bench.evaluate.ranking.bootstrap_frames`; their intervals are in ``summary.json``).
DETECTION_KEYS = (*COUNT_KEYS, *FIGURE_KEYS, "ap")
#: The figures of a real run's ``mean`` rows that are means over photographs (bootstrap intervals over them in
#: ``summary.json``). Reports on stripe-less rows are priced by ``false_report_rate`` (rows of known state only).
PER_IMAGE_MEANS = ("hit_rate", "mae_px", "coverage")



def _track_all(trackers: dict, frame, background, colour=None):
    """label -> (Track, ms, status, message) by :func:`bench.run.track.track_frame`: a failing
    tracker (it raised, returned columns outside the image, timed out, crashed) gives an empty
    track and its :data:`~bench.run.track.STATUS` name; ``"ok"`` otherwise. ``colour``: the photograph's
    colour evidence (:func:`bench.run.camera_view.colour_of`), None for a grey one."""
    from trackers import Track

    out, done = {}, {}
    for lab, t in trackers.items():
        key = repr(t)  # one tracker setting under two labels (a run's `threshold` and `threshold_gaps`): tracked once
        if key not in done:
            r = track_frame(t, frame, background, colour)
            tr = Track(r.columns, r.score) if r.ok else Track.empty(frame.shape[0])
            done[key] = (tr, 1e3 * r.seconds, STATUS[r.status], r.message)
        out[lab] = done[key]
    return out


def track_images(paths, out_dir, specs, *, background=None, pair: bool = True, channel: str = "auto",
                 laser: str = "red", rotate_deg: int = 0, err=None, say=print, force: bool = False,
                 draw=None, legend=None) -> int:
    """Run trackers on image files; returns the number of files that failed.

    ``draw(original, tracks, rotate_deg=..., radius=...) -> PNG bytes`` makes each
    ``NAME_overlay.png`` and ``legend(labels) -> str`` names its colours (the command
    passes :func:`bench.report.real.overlay_png` and :func:`bench.report.real.legend`;
    drawing belongs to the report layer); without ``draw`` no overlay is written.

    A file that cannot be read (or whose background cannot) gets one line on
    ``err`` and the others go on; so does a file whose EXIF orientation asks for
    a turn ``rotate_deg`` does not give (it is tracked as stored:
    :func:`bench.store.realset.orientation_note`). ``background`` (a path) is used for every
    image; otherwise, with ``pair``, ``NAME_off.EXT`` beside ``NAME.EXT``; files
    that are the laser-off partner of another given file are not tracked.

    ``out_dir`` is a run folder of kind ``track``: locked while this runs and
    claimed for these tracker settings (another setting's folder, or a non-empty
    folder that is not one, is refused unless ``force``, which clears it).

    Raises
    ------
    bench.store.runfolder.RunFolderError
        The folder is locked, holds other settings' outputs (without ``force``),
        an input lies inside it, or two inputs would write the same outputs
        (:func:`bench.store.realrun.track_output_names`).
    """
    from bench.store.provenance import code_fingerprint
    from bench.store.realrun import track_output_names
    from bench.store.runfolder import RunFolder

    err = sys.stderr if err is None else err
    out = Path(out_dir)
    paths = [Path(p) for p in paths]
    given = {p.resolve() for p in paths}
    todo, seen = [], set()
    for p in paths:
        if pair and background is None and p.stem.endswith("_off"):
            partner = [p.with_name(p.stem[:-4] + s) for s in (p.suffix,) + real.IMAGE_SUFFIXES]
            if any(q.resolve() in given for q in partner):
                continue  # the laser-off frame of another input
        if p.resolve() not in seen:  # one file given twice is tracked once
            seen.add(p.resolve())
            todo.append(p)
    names = track_output_names(todo, out, extra_inputs=[background] if background is not None else [],
                               force=force)
    identity = {"trackers": [s.to_value() for s in specs], "channel": channel, "laser": laser,
                "rotate_deg": int(rotate_deg), "pair": bool(pair),
                "background": None if background is None else str(Path(background).resolve())}
    trackers = build_trackers(specs)
    folder = RunFolder(out, kind="track")
    folder.open(identity, code_fingerprint(trackers.values()), force=force, say=lambda m: print(m, file=err))
    try:
        return _track_locked(folder, todo, names, trackers, background, pair, channel, laser, rotate_deg, err, say,
                             draw, legend)
    finally:
        folder.unlock()


def _track_locked(folder, todo, names, trackers, background, pair, channel, laser, rotate_deg, err, say, draw,
                  legend) -> int:
    from bench.store.realrun import read_inputs, write_inputs

    out = folder.path
    labels = list(trackers)
    inputs = read_inputs(out)
    failed = 0
    bg_fixed = None
    if background is not None:
        bg_fixed = real.rotate_image(real.select_channel(real.read_image(background), channel, laser), rotate_deg)
    for p in todo:
        try:
            frame, original = real.load_frame(p, channel=channel, laser=laser, rotate_deg=rotate_deg)
            bg, bg_name = bg_fixed, (Path(background).name if background is not None else None)
            if bg is None and pair:
                q = real.background_for(p)
                if q is not None:
                    bg, _ = real.load_frame(q, channel=channel, laser=laser, rotate_deg=rotate_deg)
                    bg_name = q.name
            if bg is not None and bg.shape != frame.shape:
                raise real.ImageError(f"{str(p)!r}: background {bg_name} has shape {bg.shape}, the image {frame.shape}")
        except real.ImageError as exc:
            print(f"stripebench track: {one_line(exc)}", file=err)
            failed += 1
            continue
        note = real.orientation_note(p, rotate_deg)
        if note:
            print(f"stripebench track: {one_line(note)}", file=err)
        res = _track_all(trackers, frame, bg, colour_of(original, laser, rotate_deg))
        tracks = {lab: r[0] for lab, r in res.items()}
        name = names[p]
        inputs[name] = str(p.resolve())
        write_inputs(out, inputs)  # before the outputs: an interrupted track still knows whose they are
        write_track_csv(out / f"{name}.csv", labels, tracks)
        if draw is not None:
            folder.write_bytes(f"{name}_overlay.png",
                               draw(original, {k: v.columns for k, v in tracks.items()}, rotate_deg=rotate_deg,
                                    radius=max(1, min(original.shape[:2]) // 300)))
        parts = []
        for lab, (tr, ms, status, msg) in res.items():
            n = int(tr.detected.sum())
            parts.append(f"{lab} {n}/{tr.height} rows {ms:.0f} ms" + (f" FAILED ({msg})" if status != "ok" else ""))
        say(f"{p.name}{' (background ' + bg_name + ')' if bg is not None else ''}: " + "; ".join(parts))
    say(f"stripebench track: wrote {out}" + (f" (overlay colours: {legend(labels)})" if legend is not None else ""))
    return failed


# ---------------------------------------------------------------------------------------------------- real runs


def run_real(dataset, out_dir, specs, *, tol_px: float = HIT_PX, n_boot: int = 2000, seed: int = 0,
             quiet: bool = False, force: bool = False, draw=None) -> Path:
    """Evaluate trackers on a real set; returns the run folder.

    ``draw(original, tracks, rotate_deg=..., reference=...) -> PNG bytes`` makes each
    ``overlays/NAME.png`` (the command passes :func:`bench.report.real.overlay_png`, then
    builds ``report.html`` with :func:`bench.report.real.build_real_report`); without it
    the run writes its numbers only (as inside a synthetic run's sim-to-real comparison).

    The folder is a run folder of kind ``real`` (:class:`bench.store.runfolder.RunFolder`):
    locked while this runs, claimed for the dataset, trackers, tolerance, resamples
    and seed; another configuration's or kind's folder (or a non-empty folder that
    is not a run) is refused unless ``force``, which clears it.

    Raises
    ------
    bench.store.realset.DatasetError
        The set breaks the layout (every problem listed); checked before the folder is made.
    bench.store.runfolder.RunFolderError
        The folder is locked, of another configuration or kind (without ``force``), or cannot be written.
    """
    from bench.store.provenance import code_fingerprint
    from bench.store.runfolder import RunFolder

    t_start = time.perf_counter()
    images = real.load_dataset(dataset)
    trackers = build_trackers(specs)
    identity = {"dataset": str(Path(dataset).resolve()), "trackers": [s.to_value() for s in specs],
                "tol_px": tol_px, "n_boot": n_boot, "seed": seed}
    folder = RunFolder(out_dir, kind="real")
    folder.open(identity, code_fingerprint(trackers.values()), force=force,
                say=lambda m: print(m, file=sys.stderr, flush=True))
    try:
        return _real_locked(folder, dataset, images, specs, trackers, tol_px, n_boot, seed, quiet, t_start, draw)
    finally:
        folder.unlock()


def _real_locked(folder, dataset, images, specs, trackers, tol_px, n_boot, seed, quiet, t_start, draw) -> Path:
    import pandas as pd

    from bench.store.provenance import git_revision, versions
    from bench.store.realrun import LAYOUT, write_real_metrics
    from bench.store.runfolder import write_summary
    from bench.store.summary import build_summary

    out = folder.path
    config = {"dataset": str(Path(dataset)), "trackers": [s.to_value() for s in specs], "tol_px": tol_px,
              "n_boot": n_boot, "seed": seed, "images": [im.name for im in images]}
    labels = list(trackers)
    records = []
    outcomes = {lab: ([], []) for lab in labels}  # per tracker: each photograph's row outcomes and scores
    for k, im in enumerate(images):
        frame, bg, original, ref = im.load()
        _, states = im.reference(frame.shape)
        res = _track_all(trackers, frame, bg, colour_of(original, im.laser_colour, im.rotate_deg))
        tracks = {lab: r[0] for lab, r in res.items()}
        write_track_csv(out / LAYOUT["tracks"] / f"{im.name}.csv", labels, tracks)
        if draw is not None:
            folder.write_bytes(f"{LAYOUT['overlays']}/{im.name}.png",
                               draw(original, {lab: t.columns for lab, t in tracks.items()},
                                    rotate_deg=im.rotate_deg, reference=ref))
        for lab, (tr, ms, status, msg) in res.items():
            m = image_metrics(tr.columns, ref, tol_px, state=states, score=tr.score)
            outcomes[lab][0].append(row_outcomes(tr.columns, ref, states, tol_px))
            outcomes[lab][1].append(tr.score)
            records.append({"experiment": im.name, "tracker": lab, "region": "real", **m, "ms_per_frame": ms,
                            "has_background": im.background_path is not None, "status": status, "message": msg})
        if not quiet:
            hr = ", ".join(f"{r['tracker']} {r['f1']:.2f}/{r['false_report_rate']:.2f}/{r['hit_rate']:.2f}"
                           for r in records[-len(labels):])
            print(f"[{k + 1}/{len(images)}] {im.name}: F1/false-report rate/hit rate {hr}", file=sys.stderr,
                  flush=True)
    per_image = pd.DataFrame.from_records(records)
    means, summary_rows = [], {}
    for j, lab in enumerate(labels):
        sub = per_image[per_image["tracker"] == lab]
        stats = {}
        for metric in PER_IMAGE_MEANS:
            stats[metric] = bootstrap_mean(sub[metric].to_numpy(float), n_boot=n_boot, seed=seed + j)
        det = bootstrap_frames(*outcomes[lab], n_boot=n_boot, seed=seed + j)  # rows pooled over photographs
        stats["detection"] = det
        summary_rows[lab] = stats
        means.append({"experiment": "mean", "tracker": lab, "region": "real",
                      **{m: s["mean"] for m, s in stats.items() if m != "detection"},
                      **{k: det[k] for k in DETECTION_KEYS}, "ap_constant": det["ap_constant"],
                      "n_ref": int(sub["n_ref"].sum()),
                      "ms_per_frame": float(sub["ms_per_frame"].median()), "has_background": False,
                      "status": "ok" if (sub["status"] == "ok").all() else "failed",
                      "message": "; ".join(sorted(set(sub["message"]) - {""}))[:200]})
        stats["rigs"] = rig_figures([outcome_counts(c, axis=0) for c in outcomes[lab][0]], [im.rig for im in images],
                                    n_boot=n_boot, seed=seed + j)
    metrics = pd.concat([per_image, pd.DataFrame.from_records(means)], ignore_index=True)
    write_real_metrics(out, metrics)
    summary = build_summary("real", config=config, seed=seed, tol_px=tol_px, versions=versions(),
                            git_revision=git_revision(), run_dir=str(out), variants=[], trackers=summary_rows,
                            n_images=len(images), wall_s=time.perf_counter() - t_start)
    write_summary(out, summary)
    return out


def predict_real(dataset, run_dir, specs, *, n_boot: int = 1000, seed: int = 0, settings=None, say=None) -> dict:
    """``real --predict``: predict a real run's figures (:func:`bench.run.predict.run_predict` into
    ``RUN/predict``) and set them beside the measured ones, pooled, per rig and per photograph.

    Parameters
    ----------
    dataset : path
        The real set the run at ``run_dir`` evaluated.
    run_dir : path
        A finished real run (:func:`run_real`).
    specs : sequence of TrackerSpec
        Its trackers.
    n_boot, seed, settings, say
        As :func:`bench.run.predict.run_predict` (``settings`` None: the defaults).

    Returns
    -------
    dict
        ``result`` (``run_predict``'s, with ``comparison``, ``comparison_rigs`` and ``comparison_photos``
        added for the page) and ``doc`` (what ``RUN/predict/compare.json`` holds: the ``photographs`` in range,
        ``hit_rate`` and ``f1`` pooled, ``rigs`` (:attr:`bench.store.realset.RealImage.rig`; a photograph
        without one is a rig of its own; each also with its ``measured_reliability``) and ``per_photograph``, each as
        :func:`bench.evaluate.prediction.comparison_doc`, ``measured_reliability``, how repeatable the measured
        ranks are, :func:`bench.evaluate.prediction.rank_reliability`, and ``rank_interval``, how far the rank
        correlation rests on which photographs were taken, :func:`bench.evaluate.prediction.rank_interval`, each
        None with fewer than :data:`~bench.evaluate.prediction.RELIABILITY_MIN_PHOTOS` photographs; the rigs have
        both too); the page is the caller's
        (:func:`bench.report.predict.build_predict_report` of ``result``).
    """
    import json

    from bench.evaluate.stripe import why_left_out
    from bench.evaluate.prediction import (RELIABILITY_MIN_PHOTOS, compare_by_group, compare_with_real,
                                          comparison_doc, rank_interval, rank_reliability)
    from bench.evaluate.predict_settings import DEFAULT
    from bench.run.predict import run_predict
    from bench.store.files import atomic_write_text
    from bench.store.realrun import load_real_run

    out = Path(run_dir)
    result = run_predict(dataset, out / "predict", specs, n_boot=n_boot, seed=seed,
                         settings=DEFAULT if settings is None else settings, say=say)
    names = [n for n, m in result["made"].items() if m.answered and not m.out_of_range]  # coarse answers not pooled
    metrics = load_real_run(out)["metrics"]
    cmp = compare_with_real(result["predicted"], metrics, names)
    rig_of = {im.name: im.rig for im in real.load_dataset(dataset)}
    rigs = compare_by_group(result["predicted_photos"], metrics, {n: rig_of.get(n, n) for n in names})
    photos = compare_by_group(result["predicted_photos"], metrics, {n: n for n in names})
    result.update(comparison=cmp, comparison_rigs=rigs, comparison_photos=photos)

    def reliability(group):
        return rank_reliability(metrics, group, seed=seed) if len(group) >= RELIABILITY_MIN_PHOTOS else None

    def interval(group):
        return (rank_interval(result["predicted_photos"], metrics, group, seed=seed)
                if len(group) >= RELIABILITY_MIN_PHOTOS else None)

    s = result["predict_settings"]
    doc = {"photographs": names,
           "shrunk": {n: m.shrink for n, m in result["made"].items() if m.answered and m.out_of_range},
           "out_of_range": {n: list(m.out_of_range) for n, m in result["made"].items() if not m.answered},
           "why": {n: why_left_out(m.out_of_range, width_px=m.width_px, settings=s)
                   for n, m in result["made"].items() if m.out_of_range},
           **comparison_doc(cmp),
           "rigs": {g: {**comparison_doc(v), "measured_reliability": reliability(v["photographs"]),
                        "rank_interval": interval(v["photographs"])} for g, v in rigs.items()},
           "per_photograph": {g: comparison_doc(v) for g, v in photos.items()},
           "measured_reliability": reliability(names), "rank_interval": interval(names)}
    atomic_write_text(out / "predict" / "compare.json", json.dumps(doc, indent=1, default=float))
    return {"result": result, "doc": doc}
