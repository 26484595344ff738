"""The pictures and the page of real-photograph runs: ``stripebench track`` overlays and ``real`` reports.

:func:`overlay_png` draws a photograph with every tracker's columns (colours from
:mod:`bench.report.palette`, the same as every figure); :func:`build_real_report`
writes ``report.html`` of a finished real run from its saved files.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from bench.report.html import esc, fixed, interval, page, pct, png_img, table
from bench.report.palette import REFERENCE_COLOUR, tracker_colour, tracker_rgb
from bench.store import realset as real

__all__ = ["overlay", "overlay_png", "legend", "build_real_report", "ranked_trackers", "images_by_f1", "RANK_KEY"]

#: What a real run's tables rank by: F1 over rows (a miss and a false report priced alike).
RANK_KEY = "f1"


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
        label -> columns, shape (H',), of the frame turned by ``rotate_deg``; each label in its
        colour of :func:`bench.report.palette.tracker_colour`.
    rotate_deg : int
    reference : array_like, shape (H',), optional
        Drawn first, in :data:`bench.report.palette.REFERENCE_COLOUR`, one pixel wide.
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
        layers.append((np.asarray(reference, float), _rgb(REFERENCE_COLOUR), 0))
    for label, cols in tracks.items():
        layers.append((np.asarray(cols, float), tracker_rgb(label), radius))
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


def _rgb(hex_colour: str) -> tuple[int, int, int]:
    h = hex_colour.lstrip("#")
    return int(h[0:2], 16), int(h[2:4], 16), int(h[4:6], 16)


def _png_bytes(img: np.ndarray) -> bytes:
    import imageio.v3 as iio

    return iio.imwrite("<bytes>", img, extension=".png")


def overlay_png(original, tracks: dict, **kw) -> bytes:
    """:func:`overlay` as PNG bytes (what ``track`` and ``real`` write)."""
    return _png_bytes(overlay(original, tracks, **kw))


def legend(labels) -> str:
    """``label=#rrggbb, ...``: the overlay colours, for the command's last line."""
    return ", ".join(f"{lab}={tracker_colour(lab)}" for lab in labels)


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
    return png_img(_png_bytes(small), path.name, "")


def ranked_trackers(summary: dict) -> list[str]:
    """A real run's tracker labels by pooled F1 over rows (:data:`RANK_KEY`), best first (NaN last,
    then by label).

    >>> ranked_trackers({"trackers": {"a": {"detection": {"f1": 0.5}}, "b": {"detection": {"f1": 0.9}},
    ...                               "c": {"detection": {"f1": float("nan")}}}})
    ['b', 'a', 'c']
    """
    def key(lab):
        v = (summary["trackers"][lab].get("detection") or {}).get(RANK_KEY, float("nan"))
        return (-v if np.isfinite(v) else np.inf, lab)

    return sorted(summary["trackers"], key=key)


def images_by_f1(metrics, labels):
    """The per-photograph F1 (:data:`RANK_KEY`) of each tracker, one row per photograph, the photographs ordered
    by their mean F1 over the trackers, lowest (hardest) first; a photograph with no row of known state (F1
    NaN for every tracker) last."""
    per = metrics[metrics["experiment"] != "mean"].pivot(index="experiment", columns="tracker", values=RANK_KEY)
    per = per[list(labels)]
    mean = per.mean(axis=1, skipna=True)
    order = sorted(per.index, key=lambda n: (not np.isfinite(mean[n]), mean[n] if np.isfinite(mean[n]) else 0.0, n))
    return per.loc[order]


def _report(out: Path, metrics, summary: dict, labels: list[str], images) -> None:
    e = esc
    rows = []
    labels = ranked_trackers(summary)
    for lab in labels:
        s = summary["trackers"][lab]
        h, m, c = s["hit_rate"], s["mae_px"], s["coverage"]
        d = s.get("detection") or {}
        det = "".join(f"<td>{pct(d.get(k))} <small>{interval(d.get(k + '_lo'), d.get(k + '_hi'))}</small></td>"
                      for k in ("precision", "recall", "f1", "false_report_rate", "ap"))
        rows.append(f"<tr><td>{e(lab)}</td>{det}<td>{d.get('n_false', '–')} / "
                    f"{d.get('n_false', 0) + d.get('n_quiet', 0)}</td><td>{h['mean']:.3f} [{h['lo']:.3f}, "
                    f"{h['hi']:.3f}]</td><td>{m['mean']:.2f}</td><td>{c['mean']:.3f}</td></tr>")
    per = images_by_f1(metrics, labels)
    frr = metrics[metrics["experiment"] != "mean"].pivot(index="experiment", columns="tracker",
                                                         values="false_report_rate").reindex(per.index)[labels]
    hit = metrics[metrics["experiment"] != "mean"].pivot(index="experiment", columns="tracker",
                                                         values="hit_rate").reindex(per.index)[labels]
    per_image = table(["image"] + [e(lab) for lab in labels],
                      [[e(str(name))] + [f"<b>{fixed(f, '.2f')}</b> <small>{fixed(q, '.2f')} · {fixed(hr, '.2f')}</small>"
                                         for f, q, hr in zip(per.loc[name], frr.loc[name], hit.loc[name])]
                       for name in per.index])
    key = " ".join(f"<span style='background:{tracker_colour(lab)};padding:0 6px'>&nbsp;</span> {e(lab)}"
                   for lab in labels)
    key += f" <span style='background:{REFERENCE_COLOUR};padding:0 6px'>&nbsp;</span> reference"
    worst = []
    for lab in labels:
        col = per[lab].sort_values(na_position="last", kind="stable")
        names = [n for n in col.index[:2]]
        tags = "".join(f"<figure>{_img_tag(out / 'overlays' / f'{n}.png')}<figcaption>{e(n)}: F1 "
                       f"{fixed(col[n], '.2f')}, false reports {fixed(frr.loc[n, lab], '.2f')}, hit rate "
                       f"{fixed(hit.loc[n, lab], '.2f')}"
                       f"</figcaption></figure>" for n in names)
        worst.append(f"<h3>{e(lab)}</h3><div class='row'>{tags}</div>")
    notes = table(["image", "source", "license", "notes"],
                  [[e(im.name), e(im.meta.get("source_repo", "")), e(im.meta.get("license", "")),
                    e(im.meta.get("notes", ""))] for im in images])
    body = f"""<h1>Real photographs: {summary['n_images']} images, tolerance {summary['tol_px']:g} px</h1>
<p>Dataset {e(summary['config']['dataset'])}; git {e(summary['git_revision'])}; seed {summary['seed']}.
Trackers ranked by F1 over rows. Detection, both halves: every row of every photograph with a known state
(stripe, no stripe; the references' own states, or the fallback rule: a row without a reference at least 15
rows from any stripe row has no stripe; every other row is unknown and not scored) is a hit, wrong, missed,
false (a report where there is no stripe) or quiet; precision, recall, F1, the false-report rate and AP (the
tracker's score ranking its reports) pooled over the photographs' rows, with 95 % bootstrap intervals over
photographs. Hit rate (the stripe half alone), MAE and coverage: means over images with 95 % bootstrap
intervals over images.</p>
<table><tr><th>tracker</th><th>precision</th><th>recall</th><th>F1</th><th>false reports</th><th>AP</th>
<th>false / stripe-less rows</th><th>hit rate</th><th>MAE on hits (px)</th><th>coverage</th></tr>{''.join(rows)}</table>
<h2>F1 per image</h2><p>Each cell: F1 over the photograph's rows, then its false-report rate and hit rate (–: no
row of that kind). Hardest photographs (lowest mean F1 over the trackers) first.</p>{per_image}
<h2>The worst images per tracker (lowest F1)</h2><p>{key}</p>{''.join(worst)}
<h2>Images</h2>{notes}
"""
    from bench.store.files import atomic_write_text
    from bench.store.realrun import LAYOUT

    atomic_write_text(out / LAYOUT["report"], page("stripebench real", body, css=(
        "td,th{text-align:left}.row{display:flex;flex-wrap:wrap;gap:8px}figure{margin:0}"
        "figcaption{font-size:small}")))
