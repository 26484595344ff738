"""One experiment's scan: render every mirror angle, run every tracker on it.

The unit of work is :func:`bench.run.track.track_frame` (one frame, one tracker: pure). A scan
keeps its results in one ``.npz`` checkpoint, written atomically after every
few frames and when interrupted, so a rerun resumes where it stopped (the
renders themselves come back from the scenes' disk cache). The checkpoint's
format, its checksum and its reader are :mod:`bench.store.checkpoint`; a
checkpoint that is damaged, edited, of another format or made for other
settings is reported in one line and the scan recomputed.

A tracker that raises, returns something other than a :class:`trackers.Track`
of the frame's height, reports columns outside the image, times out or crashes
is recorded as *failed* for that frame (NaN columns, a status code of
:data:`bench.run.track.STATUS` and the message); the scan goes on.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from bench.run.camera_view import frame_colour, tracker_images
from bench.run.track import track_frame
from bench.store.checkpoint import FALSE_K, ScanResult, read_checkpoint, write_checkpoint

__all__ = ["run_scan", "pending_frames", "scan_fingerprint"]

_CHECKPOINT_S = 10.0




def _pad_false(cols: np.ndarray, k: int = FALSE_K) -> np.ndarray:
    """(H, K') NaN-padded columns to exactly (H, k) (extra columns dropped)."""
    out = np.full((cols.shape[0], k), np.nan)
    n = min(k, cols.shape[1])
    out[:, :n] = cols[:, :n]
    return out


def scan_fingerprint(scene, trackers_: dict, spp: int, seed: int) -> str:
    """Everything a scan's results depend on, hashed (plugin trackers' sources and the renderer included)."""
    from bench.store.files import config_hash
    from bench.store.provenance import code_fingerprint
    from scenes import variant

    params = {k: v for k, v in scene.params.items() if k not in ("cache", "cache_dir")}
    return config_hash({"scene": scene.name, "params": params, "spp": spp, "seed": seed,
                        "trackers": {n: repr(t) for n, t in sorted(trackers_.items())},
                        "renderer": variant.renderer(),
                        "source": code_fingerprint(trackers_.values())})


def _resume(key, scene, angles, names, fingerprint, checkpoint, clear_bad=False) -> tuple[ScanResult | None, str]:
    """The checkpoint's results when they belong to this scan (else None), and why not ("" if there is none)."""
    prev, why = read_checkpoint(checkpoint, key, clear_bad=clear_bad)
    if prev is not None:
        if (np.array_equal(prev.angles, angles) and sorted(prev.columns) == sorted(names)
                and prev.truth_columns.shape[1] == scene.rig.height and prev.fingerprint == fingerprint):
            return prev, ""
        why = "made by other code, trackers or settings" if prev.done.any() else None
        prev = None
    return None, why or ""


def pending_frames(key: str, scene, angles, trackers_: dict, *, spp: int, seed: int, checkpoint: Path) -> np.ndarray:
    """Which frames :func:`run_scan` with these arguments would render: (F,) bool, True for a frame
    its checkpoint does not hold (every frame when the checkpoint is missing, damaged or stale)."""
    angles = np.asarray(angles, float)
    res, _ = _resume(key, scene, angles, list(trackers_), scan_fingerprint(scene, trackers_, spp, seed), checkpoint)
    return np.ones(len(angles), bool) if res is None else ~res.done


def run_scan(key: str, scene, angles, trackers_: dict, *, spp: int, seed: int, checkpoint: Path,
             progress: bool = True, say=None, on_frame=None):
    """Render and track one scan, resuming from ``checkpoint`` if it matches.

    Parameters
    ----------
    key : str
        Experiment identifier (stored with the results).
    scene : scenes.Scene
    angles : sequence of float
        Mirror angles (deg).
    trackers_ : dict name -> Tracker
    spp, seed : int
        Rendering samples per pixel and seed.
    checkpoint : Path
        The scan's ``.npz`` file (read to resume, written atomically).
    progress : bool
        tqdm bar on stderr.
    say : callable, optional
        Receives a one-line note when the checkpoint is unreadable, damaged,
        edited (its checksum), of another format, a directory (removed) or made
        by other code or settings (it is then recomputed).
    on_frame : callable, optional
        Called with a frame's index (into ``angles``) just before that frame is
        rendered (the render-ahead helper follows the scan's position with it).

    Returns
    -------
    ScanResult
    """
    from tqdm import tqdm

    names = list(trackers_)
    angles = np.asarray(angles, float)
    fingerprint = scan_fingerprint(scene, trackers_, spp, seed)
    res, why = _resume(key, scene, angles, names, fingerprint, checkpoint, clear_bad=True)
    if why and say is not None:
        say(f"stripebench: checkpoint {checkpoint} is {why}: recomputing that scan")
    if res is None:
        res = ScanResult.empty(key, angles, scene.rig.height, names)
    res.fingerprint = fingerprint
    todo = [i for i in range(len(angles)) if not res.done[i]]
    if todo:  # first calls compile (numba); keep that out of the per-frame times
        H, W = scene.rig.height, scene.rig.width
        blank = np.zeros((H, W), np.uint8)
        for n in names:
            track_frame(trackers_[n], blank, blank)
    last_save = time.monotonic()
    bar = tqdm(todo, desc=key, unit="frame", file=sys.stderr, disable=not progress, leave=False)
    try:
        for i in bar:
            if on_frame is not None:
                on_frame(i)
            t0 = time.perf_counter()
            frame = scene.render(float(angles[i]), spp=spp, seed=seed)
            image, background = tracker_images(frame, scene.params)
            colour = frame_colour(frame, scene.params)
            res.render_seconds += time.perf_counter() - t0
            res.variant = frame.variant
            res.width = frame.image.shape[1]
            res.truth_columns[i] = frame.truth.columns
            res.truth_points_cm[i] = frame.truth.points_cm
            res.on_object[i] = frame.truth.on_object
            if frame.truth.false_mask is not None:
                if res.false_columns is None:
                    res.false_columns = np.full((len(angles), scene.rig.height, FALSE_K), np.nan)
                res.false_columns[i] = _pad_false(frame.truth.false_columns)
            for n in names:
                r = track_frame(trackers_[n], image, background, colour)
                res.columns[n][i] = r.columns
                res.scores[n][i] = r.score
                res.seconds[n][i] = r.seconds
                res.status[n][i] = r.status
                res.messages[n][i] = r.message
            res.done[i] = True
            if time.monotonic() - last_save > _CHECKPOINT_S:
                write_checkpoint(checkpoint, res)
                last_save = time.monotonic()
    finally:
        write_checkpoint(checkpoint, res)
    return res
