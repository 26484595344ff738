"""A scan's checkpoint: :class:`ScanResult` (frames x rows of every tracker) in one ``.npz`` file.

Format 2 (this one) stores :meth:`ScanResult.to_arrays`, a ``format`` array (2)
and a ``checksum`` array: the SHA-256 of every other array
(:func:`bench.store.files.array_checksum`). :func:`read_checkpoint` refuses,
with the reason in one phrase, a file that is not a zip, a file of another
format (format 1 had no checksum: it is recomputed), one whose checksum does not
match its arrays (edited or damaged), arrays of disagreeing shapes, infinite
numbers, angles that are not finite or status codes that do not exist. Each
refusal means "recompute that scan"; nothing here raises on a bad file.

Arrays (``F`` frames, ``H`` rows; float64 unless said)::

    angles (F,)  truth_columns (F, H)  truth_points_cm (F, H, 3)  on_object (F, H) bool  done (F,) bool
    variant ()  width ()  render_seconds ()  fingerprint ()  trackers (T,) str
    columns/<name> (F, H)  scores/<name> (F, H)  seconds/<name> (F,)  status/<name> (F,) int
    messages/<name> (F,) str  [false_columns (F, H, FALSE_K)]  format ()  checksum ()
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bench.store.files import array_checksum, non_file_reason, read_npz, save_npz

__all__ = ["FORMAT", "STATUS", "FALSE_K", "ScanResult", "read_checkpoint", "write_checkpoint", "verify_checkpoint"]

FORMAT = 2
#: A tracker's status on a frame, as stored in ``status/<name>``.
#: Status codes of a tracker on a frame, as checkpoints store them (see :func:`bench.run.track.track_frame`).
STATUS = {0: "ok", 1: "raised", 2: "bad-output", 3: "out-of-image", 4: "timeout", 5: "crashed"}
FALSE_K = 8  # false-stripe columns kept per row (the nearest to the truth first are not needed: all, up to 8)


@dataclass
class ScanResult:
    """Everything one scan produced (arrays indexed frame x row)."""

    key: str
    angles: np.ndarray  # (F,) mirror angles, deg
    truth_columns: np.ndarray  # (F, H) px
    truth_points_cm: np.ndarray  # (F, H, 3) cm
    on_object: np.ndarray  # (F, H) bool
    columns: dict  # name -> (F, H) px
    scores: dict  # name -> (F, H)
    seconds: dict  # name -> (F,) s
    status: dict  # name -> (F,) int, a key of STATUS
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

    @classmethod
    def empty(cls, key: str, angles, height: int, names) -> "ScanResult":
        """A scan of ``angles`` (deg) at ``height`` rows with no frame done (NaN columns, status 0)."""
        F, H = len(angles), int(height)
        nanFH = lambda: np.full((F, H), np.nan)  # noqa: E731
        return cls(
            key=key, angles=np.asarray(angles, float), truth_columns=nanFH(),
            truth_points_cm=np.full((F, H, 3), np.nan), on_object=np.zeros((F, H), bool),
            columns={n: nanFH() for n in names}, scores={n: nanFH() for n in names},
            seconds={n: np.full(F, np.nan) for n in names}, status={n: np.zeros(F, np.int64) for n in names},
            messages={n: [""] * F for n in names}, done=np.zeros(F, bool), variant="", width=0, render_seconds=0.0,
        )

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The arrays of the checkpoint (without ``format`` and ``checksum``)."""
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
        """Rebuild from :meth:`to_arrays`'s output (``format``/``checksum`` are ignored here).

        Raises
        ------
        ValueError
            A missing array, arrays whose shapes do not agree, infinite numbers,
            non-finite angles or unknown status codes (a damaged or foreign checkpoint).
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
        _check_values(a, names)
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


def _check_values(a: dict, names: list[str]) -> None:
    """Finite-value checks: no infinity anywhere, finite angles, known status codes."""
    for k, v in a.items():
        if v.dtype.kind == "f" and np.isinf(v).any():
            raise ValueError(f"array {k!r} holds infinite numbers")
        if k not in ("variant", "fingerprint", "trackers", "format", "checksum") and not k.startswith("messages/") \
                and v.dtype.kind not in "fiub":
            raise ValueError(f"array {k!r} of dtype {v.dtype}, not numbers")
    if not np.isfinite(a["angles"]).all():
        raise ValueError("array 'angles' holds NaN")
    if not (np.isfinite(a["render_seconds"]) and float(a["render_seconds"]) >= 0):
        raise ValueError(f"render_seconds is {a['render_seconds']!r}, not a time")
    for n in names:
        bad = ~np.isin(a[f"status/{n}"], list(STATUS))
        if bad.any():
            raise ValueError(f"array 'status/{n}' holds the unknown status {a[f'status/{n}'][bad][0].item()!r}")


def _checked_false_columns(fc, F: int, H: int):
    if fc is None:
        return None
    if fc.ndim != 3 or fc.shape[:2] != (F, H):
        raise ValueError(f"array 'false_columns' has shape {fc.shape}, expected ({F}, {H}, K)")
    return fc


def write_checkpoint(path, result: ScanResult) -> None:
    """Write ``result`` to ``path`` (format 2, with its checksum), atomically.

    Raises
    ------
    OSError
        Naming ``path`` (a full disk, a read-only folder).
    """
    arrays = {**result.to_arrays(), "format": np.array(FORMAT)}
    save_npz(path, **arrays, checksum=np.array(array_checksum(arrays)))


def read_checkpoint(path, key: str = "", *, clear_bad: bool = False) -> tuple[ScanResult | None, str | None]:
    """The scan stored at ``path``, or None and why it cannot be used.

    Parameters
    ----------
    path : path-like
    key : str
        The experiment key given to the :class:`ScanResult`.
    clear_bad : bool
        Remove a directory or other non-file standing at ``path`` (so the scan's
        next write succeeds); the reason then ends in ``"(removed)"``.

    Returns
    -------
    (ScanResult, None) for a good checkpoint; (None, None) when there is none;
    (None, reason) otherwise: ``"unreadable (...)"``, ``"a directory, not a file"``,
    ``"of format 1, ..."``, ``"edited or damaged (...)"``, ``"damaged (...)"``.

    Examples
    --------
    >>> read_checkpoint("/nonexistent/a.npz")
    (None, None)
    """
    path = Path(path)
    why = non_file_reason(path, clear_bad)
    if why is not None:
        return None, why
    arrays, why = read_npz(path)
    if arrays is None:
        return None, None if why is None else f"unreadable ({why})"
    fmt = arrays.get("format")
    if fmt is None or fmt.shape != () or fmt.dtype.kind not in "iu" or int(fmt) != FORMAT:
        found = 1 if fmt is None else (fmt.item() if fmt.shape == () else fmt.shape)
        return None, f"of format {found!r} (this stripebench reads format {FORMAT}, with a checksum)"
    stored = arrays.pop("checksum", None)
    if stored is None or str(stored) != array_checksum(arrays):
        return None, "edited or damaged (its checksum does not match its arrays)"
    try:
        return ScanResult.from_arrays(key, arrays), None
    except (KeyError, ValueError, TypeError) as exc:
        return None, f"damaged ({exc})"


def verify_checkpoint(path) -> str | None:
    """Why the checkpoint at ``path`` is unusable (None if it is a good one, whatever scan it is of)."""
    res, why = read_checkpoint(path)
    return why if res is None else None
