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
file.  Each file also stores its own key (``__key__``).  A file that fails to
load, holds another key or arrays whose shapes disagree is reported in one line
on stderr and treated as missing (re-rendered and overwritten).
Location: ``cache_dir`` argument, else ``$STRIPEBENCH_CACHE_DIR``, else
``~/.cache/stripebench``.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
import tempfile
from pathlib import Path
from typing import Dict, Optional

import numpy as np

__all__ = ["CODE_VERSION", "ENV_CACHE_DIR", "cache_root", "key", "path", "load", "store"]

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


def _problem(arrays: Dict[str, np.ndarray], k: str) -> Optional[str]:
    """Why the arrays read under ``k`` cannot be the entry for ``k`` (None if they can)."""
    stored = arrays.get(_KEY)
    if stored is not None and str(stored) != k:
        return f"it holds the entry {str(stored)[:12]}..."
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
            return arrays
    print(f"stripebench: render cache entry {p} is {why if why.startswith('unreadable') else 'wrong: ' + why}: "
          "re-rendering", file=sys.stderr)
    return None


def store(root: Path, k: str, arrays: Dict[str, np.ndarray]) -> Path:
    """Write ``arrays`` under ``k`` atomically; returns the file's path."""
    p = _path(root, k)
    p.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=".tmp-", suffix=".npz", dir=p.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            np.savez(f, **arrays, **{_KEY: np.array(k)})
        os.replace(tmp, p)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
    return p
