"""What a run's figures show: Fig. 7's frame (``figdata.npz``) and the failure gallery (``gallery.npz``).

Both files carry a ``format`` array (3); files without one are format 1 (the
same arrays: read as they are), other numbers are refused. Format 3 adds Fig. 7's
DP cost field, computed by the run, so that the report draws it without recomputing. The readers return
the data as objects (:class:`FigData`, :class:`GalleryFrame`), so the array
keys below are written and parsed here only.

``figdata.npz``: ``experiment`` (), ``mirror_angle_deg`` (), ``image`` (H, W),
``background`` (H, W), ``truth_columns`` (H,) px, ``trackers`` (T,),
``columns/<name>`` (H,) px, ``cost_field`` (H, W) (format 3: the paper's accumulated cost,
4-connected, of ``image``), ``format`` ().

``gallery.npz``: ``keys`` (N,) = ``<experiment>/<frame index>`` in sorted order and
per key ``<key>/image`` (H, W), ``<key>/truth`` (H,) px, ``<key>/labels`` (T,),
``<key>/columns/<label>`` (H,) px; ``format`` ().
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bench.store.files import read_npz, save_npz

__all__ = ["FORMAT", "FigData", "GalleryFrame", "write_figdata", "read_figdata", "write_gallery", "read_gallery"]

FORMAT = 3
_READS = (1, 2, 3)


@dataclass(frozen=True)
class FigData:
    """The frame Fig. 7 shows: the image, the truth and every tracker's columns on it."""

    experiment: str
    mirror_angle_deg: float
    image: np.ndarray  # (H, W)
    background: np.ndarray | None  # (H, W) or None (format-1 files without one)
    truth_columns: np.ndarray  # (H,) px
    columns: dict  # tracker -> (H,) px
    cost_field: np.ndarray | None = None  # (H, W): Fig. 7b, the DP accumulated cost (None: an older file)


@dataclass(frozen=True)
class GalleryFrame:
    """One frame of the failure gallery."""

    experiment: str
    frame: int  # index into the experiment's mirror angles
    image: np.ndarray  # (H, W)
    truth_columns: np.ndarray  # (H,) px
    columns: dict  # label -> (H,) px, in the order written

    @property
    def key(self) -> str:
        return f"{self.experiment}/{self.frame}"


def _read_arrays(path) -> tuple[dict | None, str | None]:
    """:func:`~bench.store.files.read_npz` with the file's format checked: (arrays, None), (None, None)
    when missing, (None, why) when unreadable or of a format this code does not read."""
    a, why = read_npz(path)
    if a is None:
        return None, why
    f = a.get("format")
    if f is not None and (f.shape != () or f.dtype.kind not in "iu" or int(f) not in _READS):
        return None, f"of format {f.tolist()!r} (this stripebench reads format {', '.join(map(str, _READS))})"
    return a, None


def write_figdata(path, fig: FigData) -> None:
    """Write ``fig`` to ``path`` (format 3), atomically; ``OSError`` names the file."""
    arrays = {"experiment": np.array(fig.experiment), "mirror_angle_deg": np.array(float(fig.mirror_angle_deg)),
              "image": fig.image, "truth_columns": fig.truth_columns, "trackers": np.array(sorted(fig.columns)),
              "format": np.array(FORMAT), **{f"columns/{n}": c for n, c in fig.columns.items()}}
    if fig.background is not None:
        arrays["background"] = fig.background
    if fig.cost_field is not None:
        arrays["cost_field"] = fig.cost_field
    save_npz(path, **arrays)


def read_figdata(path) -> tuple[FigData | None, str | None]:
    """``figdata.npz`` checked: (FigData, None), (None, None) when missing, (None, why) when unusable."""
    fd, why = _read_arrays(path)
    if fd is None:
        return None, why
    need = {"experiment", "mirror_angle_deg", "image", "truth_columns", "trackers"}
    if not need <= set(fd):
        return None, f"missing {sorted(need - set(fd))[0]!r}"
    img = fd["image"]
    if img.ndim != 2:
        return None, f"image of shape {img.shape}, not 2-D"
    H = img.shape[0]
    if fd["truth_columns"].shape != (H,):
        return None, f"truth_columns of shape {fd['truth_columns'].shape} for an image of {H} rows"
    bg = fd.get("background")
    if bg is not None and bg.shape != img.shape:
        return None, f"background of shape {bg.shape} for an image of shape {img.shape}"
    cost = fd.get("cost_field")
    if cost is not None and cost.shape != img.shape:
        return None, f"cost_field of shape {cost.shape} for an image of shape {img.shape}"
    names = [str(n) for n in np.atleast_1d(fd["trackers"])]
    for n in names:
        c = fd.get(f"columns/{n}")
        if c is None or c.shape != (H,):
            return None, f"columns of {n!r} missing or not of shape ({H},)"
    return FigData(str(fd["experiment"]), float(fd["mirror_angle_deg"]), img, bg, fd["truth_columns"],
                   {n: fd[f"columns/{n}"] for n in names}, cost), None


def write_gallery(path, frames) -> None:
    """Write the gallery's :class:`GalleryFrame` s to ``path`` (format 2, sorted by key), atomically."""
    frames = sorted(frames, key=lambda g: g.key)
    arrays = {"keys": np.array([g.key for g in frames], dtype=str), "format": np.array(FORMAT)}
    for g in frames:
        arrays[f"{g.key}/image"] = g.image
        arrays[f"{g.key}/truth"] = g.truth_columns
        arrays[f"{g.key}/labels"] = np.array(list(g.columns), dtype=str)
        for n, c in g.columns.items():
            arrays[f"{g.key}/columns/{n}"] = c
    save_npz(path, **arrays)


def read_gallery(path) -> tuple[list[GalleryFrame] | None, str | None]:
    """``gallery.npz`` checked: (frames in key order, None), (None, None) when missing, (None, why)."""
    a, why = _read_arrays(path)
    if a is None:
        return None, why
    if "keys" not in a:
        return None, "no `keys` array"
    out = []
    for key in (str(k) for k in np.atleast_1d(a["keys"])):
        exp, _, frame = key.rpartition("/")
        if not exp or not frame.isdigit():
            return None, f"key {key!r} is not <experiment>/<frame>"
        parts = {p: a.get(f"{key}/{p}") for p in ("image", "truth", "labels")}
        if any(v is None for v in parts.values()):
            return None, f"frame {key!r} lacks {next(p for p, v in parts.items() if v is None)!r}"
        img, truth = parts["image"], parts["truth"]
        if img.ndim != 2 or truth.shape != (img.shape[0],):
            return None, f"frame {key!r}: image {img.shape} and truth {truth.shape} do not agree"
        labels = [str(n) for n in np.atleast_1d(parts["labels"])]
        cols = {}
        for n in labels:
            c = a.get(f"{key}/columns/{n}")
            if c is None or c.shape != truth.shape:
                return None, f"frame {key!r}: columns of {n!r} missing or not of shape {truth.shape}"
            cols[n] = c
        out.append(GalleryFrame(exp, int(frame), img, truth, cols))
    return out, None
