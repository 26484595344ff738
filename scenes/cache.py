"""Disk cache of rendered passes and ground truth (the sensor runs afterwards).

One ``.npz`` file per frame holds the *unit* renders (laser pass per in-band
watt, ambient pass per unit in-band sky radiance: (H, W), or (H, W, 3) for the three
colour bands of a textured colour-camera frame) and the truth arrays.  Laser
power, ambient lux, illuminant, filter and sensor only scale or post-process
these, so they are not part of the key and changing them never re-renders.

The key is a SHA-256 of a canonical JSON of everything that changes the stored
arrays: the scene's geometry/material/laser-shape parameters, size, spp,
mirror angle, seed, Mitsuba and drjit versions, the variant and
:data:`CODE_VERSION` (bump it whenever rendering or truth code changes output).

Files are written to a temporary name in the same folder and moved into place
with ``os.replace`` (atomic on POSIX), so concurrent workers never see half a
file.  Each file also stores its own key (``__key__``) and the SHA-256 of its
arrays (``__sha256__``: every name, dtype, shape and the bytes; entries written
before it existed have none and are read unverified, so existing caches stay
valid).  A file that fails to load, holds another key, arrays whose shapes
disagree, arrays that do not match their checksum (edited or damaged), or a
laser or ambient pass that is not finite (NaN or infinity: the sensor's Poisson
noise would fail on it) is reported in one line on stderr and treated as
missing (re-rendered and overwritten).  A directory or other non-file where an
entry's file should be is reported in one line and removed.
Location: ``cache_dir`` argument, else ``$STRIPEBENCH_CACHE_DIR``, else
``~/.cache/stripebench``.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import sys
import tempfile
from pathlib import Path
from typing import Dict, Optional

import numpy as np

__all__ = ["CODE_VERSION", "ENV_CACHE_DIR", "cache_root", "key", "path", "load", "store", "checksum"]

CODE_VERSION = 1
ENV_CACHE_DIR = "STRIPEBENCH_CACHE_DIR"


def cache_root(cache_dir: Optional[os.PathLike] = None) -> Path:
    """The cache folder (not created here)."""
    if cache_dir is not None:
        return Path(cache_dir)
    env = os.environ.get(ENV_CACHE_DIR)
    if env:
        return Path(env)
    return Path.home() / ".cache" / "stripebench"


def _canonical(obj):
    if isinstance(obj, dict):
        return {str(k): _canonical(v) for k, v in sorted(obj.items())}
    if isinstance(obj, (list, tuple)):
        return [_canonical(v) for v in obj]
    if isinstance(obj, (np.floating, float)):
        return repr(float(obj))  # exact round trip
    if isinstance(obj, (np.integer,)):
        return int(obj)
    return obj


def key(fields: Dict) -> str:
    """Hex SHA-256 of ``fields`` (plus :data:`CODE_VERSION`) in canonical JSON."""
    payload = json.dumps(_canonical({"code_version": CODE_VERSION, **fields}), sort_keys=True)
    return hashlib.sha256(payload.encode()).hexdigest()


def _path(root: Path, k: str) -> Path:
    return root / k[:2] / f"{k}.npz"


def path(root: Path, k: str) -> Path:
    """The file that holds (or would hold) the entry ``k`` under ``root``."""
    return _path(root, k)


_KEY = "__key__"
_SUM = "__sha256__"
_FINITE = ("laser", "ambient")  # the passes the sensor turns into Poisson means


def checksum(arrays: Dict[str, np.ndarray]) -> str:
    """Hex SHA-256 of an entry's arrays: every name, dtype, shape and the bytes, in name order.

    Examples
    --------
    >>> checksum({"a": np.zeros(2)}) == checksum({"a": np.zeros(2)}), checksum({"a": np.zeros(2)}) == checksum({"a": np.ones(2)})
    (True, False)
    """
    h = hashlib.sha256()
    for name in sorted(arrays):
        v = np.ascontiguousarray(arrays[name])
        h.update(f"{name}\0{v.dtype.str}\0{v.shape}\0".encode())
        h.update(v.tobytes())
    return h.hexdigest()


def _problem(arrays: Dict[str, np.ndarray], k: str) -> Optional[str]:
    """Why the arrays read under ``k`` cannot be the entry for ``k`` (None if they can)."""
    stored = arrays.get(_KEY)
    if stored is not None and str(stored) != k:
        return f"it holds the entry {str(stored)[:12]}..."
    digest = arrays.get(_SUM)
    if digest is not None and str(digest) != checksum({n: v for n, v in arrays.items() if n != _SUM}):
        return "its checksum does not match its arrays (edited or damaged)"
    for name, v in arrays.items():
        if v.dtype.kind == "f" and (not np.isfinite(v).all() if name in _FINITE else np.isinf(v).any()):
            return f"`{name}` holds {'NaN or infinity' if name in _FINITE else 'infinity'}"
    laser = arrays.get("laser")
    if laser is None:
        return None
    if laser.ndim != 2:
        return f"`laser` has shape {laser.shape}, not (H, W)"
    H = laser.shape[0]
    ambient = arrays.get("ambient")
    if ambient is not None and ambient.shape not in (laser.shape, laser.shape + (3,)):
        return f"`ambient` has shape {ambient.shape}, expected {laser.shape} or {laser.shape + (3,)}"
    expect = {"columns": (H,), "points_cm": (H, 3), "on_object": (H,)}
    for name, shape in expect.items():
        if name in arrays and arrays[name].shape != shape:
            return f"`{name}` has shape {arrays[name].shape}, expected {shape}"
    return None


def load(root: Path, k: str) -> Optional[Dict[str, np.ndarray]]:
    """The arrays stored under ``k``, or None when absent, unreadable or mismatched.

    An unreadable file (truncated, corrupt, pickled), one that holds another
    key's entry or arrays whose shapes disagree gives one line on stderr and
    None, so the caller re-renders and overwrites it.
    """
    p = _path(root, k)
    if p.is_dir() or (p.exists() and not p.is_file()):
        _remove_non_file(p)
        return None
    if not p.exists():
        return None
    try:
        with open(p, "rb") as fh, np.load(fh, allow_pickle=False) as z:
            arrays = {name: z[name] for name in z.files}
    except Exception as exc:  # corrupt, truncated, foreign: re-render
        why = f"unreadable ({type(exc).__name__})"
    else:
        why = _problem(arrays, k)
        if why is None:
            arrays.pop(_KEY, None)
            arrays.pop(_SUM, None)
            return arrays
    print(f"stripebench: render cache entry {p} is {why if why.startswith('unreadable') else 'wrong: ' + why}: "
          "re-rendering", file=sys.stderr)
    return None


def _remove_non_file(p: Path) -> None:
    """Report (one line) and remove a directory or other non-file standing where an entry should be."""
    kind = "a directory" if p.is_dir() else "not a regular file"
    try:
        shutil.rmtree(p) if p.is_dir() and not p.is_symlink() else p.unlink()
        done = "removed; re-rendering"
    except OSError as exc:
        done = f"cannot be removed ({exc.strerror or exc}); remove it"
    print(f"stripebench: render cache entry {p} is {kind}, not a file: {done}", file=sys.stderr)


def store(root: Path, k: str, arrays: Dict[str, np.ndarray]) -> Path:
    """Write ``arrays`` under ``k`` atomically, with the key and the arrays' :func:`checksum`;
    returns the file's path.

    Raises
    ------
    OSError
        With ``filename`` = the entry's path (a full disk, a read-only cache, a directory in its place).
    """
    p = _path(root, k)
    p.parent.mkdir(parents=True, exist_ok=True)
    if p.is_dir() and not p.is_symlink():
        _remove_non_file(p)
    arrays = {**arrays, _KEY: np.array(k)}
    arrays[_SUM] = np.array(checksum(arrays))
    try:
        fd, tmp = tempfile.mkstemp(prefix=".tmp-", suffix=".npz", dir=p.parent)
    except OSError as exc:
        raise OSError(exc.errno, exc.strerror or str(exc), str(p)) from exc
    try:
        with os.fdopen(fd, "wb") as f:
            np.savez(f, **arrays)
        os.replace(tmp, p)
    except BaseException as exc:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if isinstance(exc, OSError) and exc.filename != str(p):
            raise OSError(exc.errno, exc.strerror or str(exc), str(p)) from exc
        raise
    return p
