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
per-tracker means and bootstrap CIs, ``report.html``.
"""

from __future__ import annotations

import base64
import html
import sys
import time
from pathlib import Path

import numpy as np

from bench.evaluate.simreal import image_metrics
from bench.evaluate.stats import bootstrap_mean
from bench.run.track import STATUS, build_trackers, track_frame
from bench.store import realset as real
from bench.store.realrun import write_track_csv

__all__ = ["PALETTE", "REFERENCE_COLOUR", "track_images", "overlay", "run_real", "build_real_report"]

#: Marker colours (RGB) of the trackers, in the order given.
PALETTE = [(255, 0, 255), (0, 255, 255), (255, 255, 0), (0, 128, 255), (255, 128, 0), (0, 255, 0), (255, 0, 0),
           (128, 0, 255), (255, 255, 255), (0, 0, 255)]
REFERENCE_COLOUR = (0, 200, 0)


def _display_rgb(original: np.ndarray) -> np.ndarray:
    """An 8-bit RGB version of a photograph for drawing on."""
    img = np.asarray(original)
    if img.dtype != np.uint8:
        f = img.astype(np.float64)
        top = np.percentile(f, 99.9) if f.size else 1.0
        img = np.clip(np.rint(255.0 * f / max(top, 1e-12)), 0, 255).astype(np.uint8)
    if img.ndim == 2:
        img = np.repeat(img[..., None], 3, axis=2)
    return np.ascontiguousarray(img)


def overlay(original, tracks: dict, *, rotate_deg: int = 0, reference=None, radius: int = 1,
            dim: float = 0.6) -> np.ndarray:
    """The photograph (dimmed) with a square marker per row of every track.

    Parameters
    ----------
    original : ndarray, shape (H, W) or (H, W, 3)
        The photograph as read.
    tracks : dict
        label -> columns, shape (H',), of the frame turned by ``rotate_deg``.
    rotate_deg : int
    reference : array_like, shape (H',), optional
        Drawn first, in :data:`REFERENCE_COLOUR`, one pixel wide.
    radius : int
        Marker half-size in px.
    dim : float
        Factor on the photograph so the markers stand out.

    Returns
    -------
    ndarray of uint8, shape (H, W, 3)
    """
    out = (_display_rgb(original).astype(np.float64) * dim).astype(np.uint8)
    H, W = out.shape[:2]
    layers = []
    if reference is not None:
        layers.append((np.asarray(reference, float), REFERENCE_COLOUR, 0))
    for i, cols in enumerate(tracks.values()):
        layers.append((np.asarray(cols, float), PALETTE[i % len(PALETTE)], radius))
    for cols, colour, rad in layers:
        rows = np.arange(cols.size, dtype=float)
        ok = ~np.isnan(cols)
        r, c = real.unrotate_points(rows[ok], cols[ok], rotate_deg, (H, W))
        r = np.rint(r).astype(int)
        c = np.rint(c).astype(int)
        for dr in range(-rad, rad + 1):
            for dc in range(-rad, rad + 1):
                rr, cc = r + dr, c + dc
                keep = (rr >= 0) & (rr < H) & (cc >= 0) & (cc < W)
                out[rr[keep], cc[keep]] = colour
    return out


def _png_bytes(img: np.ndarray) -> bytes:
    import imageio.v3 as iio

    return iio.imwrite("<bytes>", img, extension=".png")


def _track_all(trackers: dict, frame, background):
    """label -> (Track, ms, status, message) by :func:`bench.run.track.track_frame`: a failing
    tracker (it raised, returned columns outside the image, timed out, crashed) gives an empty
    track and its :data:`~bench.run.track.STATUS` name; ``"ok"`` otherwise."""
    from trackers import Track

    out = {}
    for lab, t in trackers.items():
        r = track_frame(t, frame, background)
        tr = Track(r.columns, r.score) if r.ok else Track.empty(frame.shape[0])
        out[lab] = (tr, 1e3 * r.seconds, STATUS[r.status], r.message)
    return out


def track_images(paths, out_dir, specs, *, background=None, pair: bool = True, channel: str = "auto",
                 laser: str = "red", rotate_deg: int = 0, err=None, say=print, force: bool = False) -> int:
    """Run trackers on image files; returns the number of files that failed.

    A file that cannot be read (or whose background cannot) gets one line on
    ``err`` and the others go on. ``background`` (a path) is used for every
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
        return _track_locked(folder, todo, names, trackers, background, pair, channel, laser, rotate_deg, err, say)
    finally:
        folder.unlock()


def _track_locked(folder, todo, names, trackers, background, pair, channel, laser, rotate_deg, err, say) -> int:
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
            print(f"stripebench track: {exc}", file=err)
            failed += 1
            continue
        res = _track_all(trackers, frame, bg)
        tracks = {lab: r[0] for lab, r in res.items()}
        name = names[p]
        inputs[name] = str(p.resolve())
        write_inputs(out, inputs)  # before the outputs: an interrupted track still knows whose they are
        write_track_csv(out / f"{name}.csv", labels, tracks)
        folder.write_bytes(f"{name}_overlay.png",
                           _png_bytes(overlay(original, {k: v.columns for k, v in tracks.items()},
                                              rotate_deg=rotate_deg, radius=max(1, min(original.shape[:2]) // 300))))
        parts = []
        for lab, (tr, ms, status, msg) in res.items():
            n = int(tr.detected.sum())
            parts.append(f"{lab} {n}/{tr.height} rows {ms:.0f} ms" + (f" FAILED ({msg})" if status != "ok" else ""))
        say(f"{p.name}{' (background ' + bg_name + ')' if bg is not None else ''}: " + "; ".join(parts))
    colours = ", ".join(f"{lab}={'#%02x%02x%02x' % PALETTE[i % len(PALETTE)]}" for i, lab in enumerate(labels))
    say(f"stripebench track: wrote {out} (overlay colours: {colours})")
    return failed


# ---------------------------------------------------------------------------------------------------- real runs


def run_real(dataset, out_dir, specs, *, tol_px: float = 3.0, n_boot: int = 2000, seed: int = 0,
             quiet: bool = False, force: bool = False) -> Path:
    """Evaluate trackers on a real set; returns the run folder.

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
        return _real_locked(folder, dataset, images, specs, trackers, tol_px, n_boot, seed, quiet, t_start)
    finally:
        folder.unlock()


def _real_locked(folder, dataset, images, specs, trackers, tol_px, n_boot, seed, quiet, t_start) -> Path:
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
    for k, im in enumerate(images):
        frame, bg, original, ref = im.load()
        res = _track_all(trackers, frame, bg)
        tracks = {lab: r[0] for lab, r in res.items()}
        write_track_csv(out / LAYOUT["tracks"] / f"{im.name}.csv", labels, tracks)
        folder.write_bytes(f"{LAYOUT['overlays']}/{im.name}.png",
                           _png_bytes(overlay(original, {lab: t.columns for lab, t in tracks.items()},
                                              rotate_deg=im.rotate_deg, reference=ref)))
        for lab, (tr, ms, status, msg) in res.items():
            m = image_metrics(tr.columns, ref, tol_px)
            records.append({"experiment": im.name, "tracker": lab, "region": "real", **m, "ms_per_frame": ms,
                            "has_background": im.background_path is not None, "status": status, "message": msg})
        if not quiet:
            hr = ", ".join(f"{r['tracker']} {r['hit_rate']:.2f}" for r in records[-len(labels):])
            print(f"[{k + 1}/{len(images)}] {im.name}: hit rate {hr}", file=sys.stderr, flush=True)
    per_image = pd.DataFrame.from_records(records)
    means, summary_rows = [], {}
    for j, lab in enumerate(labels):
        sub = per_image[per_image["tracker"] == lab]
        stats = {}
        for metric in ("hit_rate", "mae_px", "coverage", "false_detections"):
            stats[metric] = bootstrap_mean(sub[metric].to_numpy(float), n_boot=n_boot, seed=seed + j)
        summary_rows[lab] = stats
        means.append({"experiment": "mean", "tracker": lab, "region": "real",
                      **{m: s["mean"] for m, s in stats.items()}, "n_ref": int(sub["n_ref"].sum()),
                      "ms_per_frame": float(sub["ms_per_frame"].median()), "has_background": False,
                      "status": "ok" if (sub["status"] == "ok").all() else "failed",
                      "message": "; ".join(sorted(set(sub["message"]) - {""}))[:200]})
    metrics = pd.concat([per_image, pd.DataFrame.from_records(means)], ignore_index=True)
    write_real_metrics(out, metrics)
    summary = build_summary("real", config=config, seed=seed, tol_px=tol_px, versions=versions(),
                            git_revision=git_revision(), run_dir=str(out), variants=[], trackers=summary_rows,
                            n_images=len(images), wall_s=time.perf_counter() - t_start)
    write_summary(out, summary)
    _report(out, metrics, summary, labels, images)
    return out


def build_real_report(run_dir) -> Path:
    """Rebuild ``report.html`` of a finished real run from its saved files
    (provenance columns only if the dataset is still where the run found it)."""
    from bench.store.realrun import load_real_run

    out = Path(run_dir)
    saved = load_real_run(out)
    summary, metrics = saved["summary"], saved["metrics"]
    labels = list(summary["trackers"])
    images, _ = real.validate_dataset(summary["config"]["dataset"])
    _report(out, metrics, summary, labels, images)
    return out / "report.html"


def _img_tag(path: Path, max_w: int = 360) -> str:
    import imageio.v3 as iio

    img = iio.imread(path)
    step = max(1, int(np.ceil(img.shape[1] / max_w)))
    small = img[::step, ::step]
    return f"<img src='data:image/png;base64,{base64.b64encode(_png_bytes(small)).decode()}' alt='{path.name}'>"


def _report(out: Path, metrics, summary: dict, labels: list[str], images) -> None:
    e = html.escape
    rows = []
    for lab in labels:
        s = summary["trackers"][lab]
        h, m, c = s["hit_rate"], s["mae_px"], s["coverage"]
        rows.append(f"<tr><td>{e(lab)}</td><td><b>{h['mean']:.3f}</b> [{h['lo']:.3f}, {h['hi']:.3f}]</td>"
                    f"<td>{m['mean']:.2f}</td><td>{c['mean']:.3f}</td></tr>")
    per = metrics[metrics["experiment"] != "mean"].pivot(index="experiment", columns="tracker", values="hit_rate")
    per = per[labels]
    head = "".join(f"<th>{e(lab)}</th>" for lab in labels)
    body = "".join(f"<tr><td>{e(str(name))}</td>" + "".join(f"<td>{v:.2f}</td>" for v in r) + "</tr>"
                   for name, r in zip(per.index, per.to_numpy()))
    legend = " ".join(f"<span style='background:#{''.join('%02x' % v for v in PALETTE[i % len(PALETTE)])};"
                      f"padding:0 6px'>&nbsp;</span> {e(lab)}" for i, lab in enumerate(labels))
    legend += f" <span style='background:#{''.join('%02x' % v for v in REFERENCE_COLOUR)};padding:0 6px'>&nbsp;</span> reference"
    worst = []
    for lab in labels:
        col = per[lab].sort_values()
        names = [n for n in col.index[:2]]
        tags = "".join(f"<figure>{_img_tag(out / 'overlays' / f'{n}.png')}<figcaption>{e(n)}: hit rate "
                       f"{col[n]:.2f}</figcaption></figure>" for n in names)
        worst.append(f"<h3>{e(lab)}</h3><div class='row'>{tags}</div>")
    notes = "".join(f"<tr><td>{e(im.name)}</td><td>{e(im.meta.get('source_repo', ''))}</td>"
                    f"<td>{e(im.meta.get('license', ''))}</td><td>{e(im.meta.get('notes', ''))}</td></tr>"
                    for im in images)
    page = f"""<!doctype html><html><head><meta charset='utf-8'><title>stripebench real</title>
<style>body{{font-family:sans-serif;margin:2em;max-width:1200px}} td,th{{padding:2px 8px;border-bottom:1px solid #ddd}}
.row{{display:flex;flex-wrap:wrap;gap:8px}} figure{{margin:0}} figcaption{{font-size:small}}</style></head><body>
<h1>Real photographs: {summary['n_images']} images, tolerance {summary['tol_px']:g} px</h1>
<p>Dataset {e(summary['config']['dataset'])}; git {e(summary['git_revision'])}; seed {summary['seed']};
means over images with 95 % bootstrap intervals over images.</p>
<table><tr><th>tracker</th><th>hit rate</th><th>MAE on hits (px)</th><th>coverage</th></tr>{''.join(rows)}</table>
<h2>Hit rate per image</h2><table><tr><th>image</th>{head}</tr>{body}</table>
<h2>The worst images per tracker</h2><p>{legend}</p>{''.join(worst)}
<h2>Images</h2><table><tr><th>image</th><th>source</th><th>license</th><th>notes</th></tr>{notes}</table>
</body></html>"""
    from bench.store.files import atomic_write_text
    from bench.store.realrun import LAYOUT

    atomic_write_text(out / LAYOUT["report"], page)
