"""One experiment's scan: render every mirror angle, run every tracker on it.

The unit of work is :func:`track_frame` (one frame, one tracker: pure). A scan
keeps its results in one ``.npz`` checkpoint, written atomically after every
few frames and when interrupted, so a rerun resumes where it stopped (the
renders themselves come back from the scenes' disk cache).

A tracker that raises, returns something other than a :class:`trackers.Track`
of the frame's height, or reports columns outside the image is recorded as
*failed* for that frame (NaN columns, a status code and the message); the scan
goes on.
"""

from __future__ import annotations

import sys
import time
import traceback
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .runio import save_npz

__all__ = ["TrackResult", "track_frame", "ScanResult", "run_scan", "pending_frames", "scan_fingerprint",
           "source_fingerprint", "tracker_source_files", "code_fingerprint", "STATUS"]

STATUS = {0: "ok", 1: "raised", 2: "bad-output", 3: "out-of-image"}
_CHECKPOINT_S = 10.0


@dataclass(frozen=True)
class TrackResult:
    """One tracker on one frame."""

    columns: np.ndarray  # (H,) float64
    score: np.ndarray  # (H,) float64
    seconds: float
    status: int
    message: str


def track_frame(tracker, image, background) -> TrackResult:
    """Run ``tracker`` on one frame and check what it returns (never raises)."""
    import trackers

    H, W = image.shape
    nan = np.full(H, np.nan)
    t0 = time.perf_counter()
    try:
        out = tracker.track(image, background=background)
    except Exception as exc:  # a tracker's failure is data, not a crash
        dt = time.perf_counter() - t0
        tb = traceback.extract_tb(exc.__traceback__)[-1]
        return TrackResult(nan, nan, dt, 1, f"{type(exc).__name__}: {exc} ({Path(tb.filename).name}:{tb.lineno})")
    dt = time.perf_counter() - t0
    if not isinstance(out, trackers.Track):
        return TrackResult(nan, nan, dt, 2, f"returned {type(out).__name__}, not Track")
    if out.columns.shape != (H,):
        return TrackResult(nan, nan, dt, 2, f"returned {out.columns.shape[0]} rows for a frame of {H}")
    cols = out.columns
    bad = ~np.isnan(cols) & ((cols < -0.5) | (cols > W - 0.5))
    if bad.any():
        return TrackResult(nan, nan, dt, 3, f"{int(bad.sum())} column(s) outside the image, e.g. {cols[bad][0]!r}")
    return TrackResult(np.array(cols), np.array(out.score), dt, 0, "")


@dataclass
class ScanResult:
    """Everything one scan produced (arrays indexed frame x row)."""

    key: str
    angles: np.ndarray  # (F,)
    truth_columns: np.ndarray  # (F, H)
    truth_points_cm: np.ndarray  # (F, H, 3)
    on_object: np.ndarray  # (F, H) bool
    columns: dict  # name -> (F, H)
    scores: dict  # name -> (F, H)
    seconds: dict  # name -> (F,)
    status: dict  # name -> (F,) int
    messages: dict  # name -> list[str] (F)
    done: np.ndarray  # (F,) bool
    variant: str
    width: int
    render_seconds: float
    fingerprint: str = ""
    # (F, H, FALSE_K) columns of the false stripes (mirrored sheet) per row, NaN-padded;
    # None when the scene computes no false-stripe mask (non-shiny materials)
    false_columns: np.ndarray | None = None

    @property
    def complete(self) -> bool:
        return bool(self.done.all())

    def to_arrays(self) -> dict[str, np.ndarray]:
        out = {
            "angles": self.angles, "truth_columns": self.truth_columns, "truth_points_cm": self.truth_points_cm,
            "on_object": self.on_object, "done": self.done, "variant": np.array(self.variant),
            "width": np.array(self.width), "render_seconds": np.array(self.render_seconds),
            "trackers": np.array(sorted(self.columns)), "fingerprint": np.array(self.fingerprint),
        }
        if self.false_columns is not None:
            out["false_columns"] = self.false_columns
        for n in self.columns:
            out[f"columns/{n}"] = self.columns[n]
            out[f"scores/{n}"] = self.scores[n]
            out[f"seconds/{n}"] = self.seconds[n]
            out[f"status/{n}"] = self.status[n]
            out[f"messages/{n}"] = np.array(self.messages[n], dtype=str)
        return out

    @classmethod
    def from_arrays(cls, key: str, a: dict[str, np.ndarray]) -> "ScanResult":
        """Rebuild from :meth:`to_arrays`'s output.

        Raises
        ------
        ValueError
            A missing array or arrays whose shapes do not agree (a damaged or foreign checkpoint).
        """
        need = ("angles", "truth_columns", "truth_points_cm", "on_object", "done", "variant", "width",
                "render_seconds", "trackers")
        missing = [k for k in need if k not in a]
        if missing:
            raise ValueError(f"no array {missing[0]!r}")
        names = [str(n) for n in np.atleast_1d(a["trackers"])] if a["trackers"].size else []
        for n in names:
            for part in ("columns", "scores", "seconds", "status", "messages"):
                if f"{part}/{n}" not in a:
                    raise ValueError(f"no array '{part}/{n}'")
        F = a["angles"].shape[0] if a["angles"].ndim == 1 else -1
        H = a["truth_columns"].shape[1] if a["truth_columns"].ndim == 2 else -1
        shapes = {"truth_columns": (F, H), "truth_points_cm": (F, H, 3), "on_object": (F, H), "done": (F,),
                  **{f"{p}/{n}": (F, H) for n in names for p in ("columns", "scores")},
                  **{f"{p}/{n}": (F,) for n in names for p in ("seconds", "status", "messages")}}
        for k, shape in shapes.items():
            if F < 0 or H < 0 or a[k].shape != shape:
                raise ValueError(f"array {k!r} has shape {a[k].shape}, expected {shape}")
        return cls(
            key=key, angles=a["angles"], truth_columns=a["truth_columns"], truth_points_cm=a["truth_points_cm"],
            on_object=a["on_object"].astype(bool), done=a["done"].astype(bool), variant=str(a["variant"]),
            width=int(a["width"]), render_seconds=float(a["render_seconds"]),
            columns={n: a[f"columns/{n}"] for n in names}, scores={n: a[f"scores/{n}"] for n in names},
            seconds={n: a[f"seconds/{n}"] for n in names}, status={n: a[f"status/{n}"] for n in names},
            messages={n: [str(m) for m in a[f"messages/{n}"]] for n in names},
            fingerprint=str(a.get("fingerprint", "")),
            false_columns=_checked_false_columns(a.get("false_columns"), F, H),
        )


FALSE_K = 8  # false-stripe columns kept per row (the nearest to the truth first are not needed: all, up to 8)


def _checked_false_columns(fc, F: int, H: int):
    if fc is None:
        return None
    if fc.ndim != 3 or fc.shape[:2] != (F, H):
        raise ValueError(f"array 'false_columns' has shape {fc.shape}, expected ({F}, {H}, K)")
    return fc


def _pad_false(cols: np.ndarray, k: int = FALSE_K) -> np.ndarray:
    """(H, K') NaN-padded columns to exactly (H, k) (extra columns dropped)."""
    out = np.full((cols.shape[0], k), np.nan)
    n = min(k, cols.shape[1])
    out[:, :n] = cols[:, :n]
    return out


def _empty(key, angles, height, names) -> ScanResult:
    F, H = len(angles), height
    nanFH = lambda: np.full((F, H), np.nan)  # noqa: E731
    return ScanResult(
        key=key, angles=np.asarray(angles, float), truth_columns=nanFH(), truth_points_cm=np.full((F, H, 3), np.nan),
        on_object=np.zeros((F, H), bool), columns={n: nanFH() for n in names}, scores={n: nanFH() for n in names},
        seconds={n: np.full(F, np.nan) for n in names}, status={n: np.zeros(F, np.int64) for n in names},
        messages={n: [""] * F for n in names}, done=np.zeros(F, bool), variant="", width=0, render_seconds=0.0,
    )


def source_fingerprint() -> str:
    """A hash of the source of the packages whose code changes results
    (``trackers``, ``scenes``): a checkpoint made by other code is not resumed."""
    import hashlib

    import scenes
    import trackers

    h = hashlib.sha256()
    for pkg in (trackers, scenes):
        root = Path(pkg.__file__).parent
        for f in sorted(root.rglob("*.py")):
            h.update(str(f.relative_to(root)).encode())
            h.update(f.read_bytes())
    return h.hexdigest()[:16]


def tracker_source_files(trackers_) -> list[Path]:
    """The source files behind tracker objects, wherever their classes live.

    For every class in each tracker's MRO (the library's own ``trackers``
    package excepted, :func:`source_fingerprint` covers it): the ``.py`` files
    of its top-level package, or its module file when it is a plain module.
    Entry-point plugins are included, so editing a plugin invalidates its results.
    """
    seen: set[Path] = set()
    for t in trackers_:
        for cls in type(t).__mro__:
            top = cls.__module__.split(".")[0]
            if top in ("builtins", "abc", "trackers"):
                continue
            mod = sys.modules.get(top)
            if mod is None:
                continue
            paths = getattr(mod, "__path__", None)
            if paths is not None:
                for root in paths:
                    seen.update(Path(root).rglob("*.py"))
            elif getattr(mod, "__file__", None):
                seen.add(Path(mod.__file__))
    return sorted(p.resolve() for p in seen if p.is_file())


def code_fingerprint(trackers_=()) -> str:
    """:func:`source_fingerprint` plus the source of the given trackers' own modules (plugins)."""
    import hashlib

    h = hashlib.sha256(source_fingerprint().encode())
    for f in tracker_source_files(trackers_):
        h.update(str(f).encode())
        h.update(f.read_bytes())
    return h.hexdigest()[:16]


def scan_fingerprint(scene, trackers_: dict, spp: int, seed: int) -> str:
    """Everything a scan's results depend on, hashed (plugin trackers' sources and the renderer included)."""
    from .runio import config_hash

    from scenes import variant

    params = {k: v for k, v in scene.params.items() if k not in ("cache", "cache_dir")}
    return config_hash({"scene": scene.name, "params": params, "spp": spp, "seed": seed,
                        "renderer": variant.renderer(),
                        "trackers": {n: repr(t) for n, t in sorted(trackers_.items())},
                        "source": code_fingerprint(trackers_.values())})


def _resume(key, scene, angles, names, fingerprint, checkpoint) -> tuple[ScanResult | None, str]:
    """The checkpoint's results when they belong to this scan (else None), and why not ("" if none)."""
    from .runfolder import read_npz

    saved, why = read_npz(checkpoint)
    if saved is not None:
        try:
            prev = ScanResult.from_arrays(key, saved)
        except (KeyError, ValueError, TypeError) as exc:
            prev, why = None, f"damaged: {exc}"
        if prev is not None:
            if (np.array_equal(prev.angles, angles) and sorted(prev.columns) == sorted(names)
                    and prev.truth_columns.shape[1] == scene.rig.height
                    and str(saved.get("fingerprint", "")) == fingerprint):
                return prev, ""
            if prev.done.any():
                why = "made by other code, trackers or settings"
    return None, why or ""


def pending_frames(key: str, scene, angles, trackers_: dict, *, spp: int, seed: int, checkpoint: Path) -> np.ndarray:
    """Which frames :func:`run_scan` with these arguments would render: (F,) bool, True for a frame
    its checkpoint does not hold (every frame when the checkpoint is missing, damaged or stale)."""
    angles = np.asarray(angles, float)
    res, _ = _resume(key, scene, angles, list(trackers_), scan_fingerprint(scene, trackers_, spp, seed), checkpoint)
    return np.ones(len(angles), bool) if res is None else ~res.done


def run_scan(key: str, scene, angles, trackers_: dict, *, spp: int, seed: int, checkpoint: Path,
             progress: bool = True, keep_frame: int | None = None, say=None, on_frame=None):
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
    keep_frame : int, optional
        Index of a frame whose image to return as well (for figures).
    say : callable, optional
        Receives a one-line note when the checkpoint is unreadable, damaged or
        made by other code or settings (it is then recomputed).
    on_frame : callable, optional
        Called with a frame's index (into ``angles``) just before that frame is
        rendered (the render-ahead helper follows the scan's position with it).

    Returns
    -------
    ScanResult, and the kept frame's ``(image, background)`` or None.
    """
    from tqdm import tqdm

    names = list(trackers_)
    angles = np.asarray(angles, float)
    fingerprint = scan_fingerprint(scene, trackers_, spp, seed)
    res, why = _resume(key, scene, angles, names, fingerprint, checkpoint)
    if why and say is not None:
        say(f"stripebench: checkpoint {checkpoint} is {why if why.startswith('made') else 'unreadable (' + why + ')'}: "
            "recomputing that scan")
    if res is None:
        res = _empty(key, angles, scene.rig.height, names)
    res.fingerprint = fingerprint
    kept = None
    todo = [i for i in range(len(angles)) if not res.done[i] or (keep_frame is not None and i == keep_frame)]
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
            if i == keep_frame:
                kept = (frame.image, frame.background, frame.truth.columns)
                if res.done[i]:
                    continue
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
                r = track_frame(trackers_[n], frame.image, frame.background)
                res.columns[n][i] = r.columns
                res.scores[n][i] = r.score
                res.seconds[n][i] = r.seconds
                res.status[n][i] = r.status
                res.messages[n][i] = r.message
            res.done[i] = True
            if time.monotonic() - last_save > _CHECKPOINT_S:
                save_npz(checkpoint, **res.to_arrays())
                last_save = time.monotonic()
    finally:
        save_npz(checkpoint, **res.to_arrays())
    return res, kept
