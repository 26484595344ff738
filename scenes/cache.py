"""Disk cache of rendered passes and ground truth (the sensor runs afterwards).

One ``.npz`` file per frame holds the *unit* renders (laser pass per in-band
watt, ambient pass per unit in-band sky radiance) and the truth arrays.  Laser
power, ambient lux, illuminant, filter and sensor only scale or post-process
these, so they are not part of the key and changing them never re-renders.

The key is a SHA-256 of a canonical JSON of everything that changes the stored
arrays: the scene's geometry/material/laser-shape parameters, size, spp,
mirror angle, seed, Mitsuba and drjit versions, the variant and
:data:`CODE_VERSION` (bump it whenever rendering or truth code changes output).

Files are written to a temporary name in the same folder and moved into place
with ``os.replace`` (atomic on POSIX), so concurrent workers never see half a
file.  A file that fails to load is treated as missing (and overwritten).
Location: ``cache_dir`` argument, else ``$STRIPEBENCH_CACHE_DIR``, else
``~/.cache/stripebench``.
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from pathlib import Path
from typing import Dict, Optional

import numpy as np

__all__ = ["CODE_VERSION", "ENV_CACHE_DIR", "cache_root", "key", "load", "store"]

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


def load(root: Path, k: str) -> Optional[Dict[str, np.ndarray]]:
    """The arrays stored under ``k``, or None when absent or unreadable."""
    p = _path(root, k)
    if not p.exists():
        return None
    try:
        with open(p, "rb") as fh, np.load(fh, allow_pickle=False) as z:
            return {name: z[name] for name in z.files}
    except Exception:  # corrupt, truncated, foreign: re-render
        return None


def store(root: Path, k: str, arrays: Dict[str, np.ndarray]) -> Path:
    """Write ``arrays`` under ``k`` atomically; returns the file's path."""
    p = _path(root, k)
    p.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=".tmp-", suffix=".npz", dir=p.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            np.savez(f, **arrays)
        os.replace(tmp, p)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
    return p
