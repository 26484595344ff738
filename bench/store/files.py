"""Files of a run: atomic writes and the run folder."""

from __future__ import annotations

import hashlib
import io
import json
import os
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["atomic_write_bytes", "atomic_write_text", "save_npz", "load_npz", "config_hash", "runs_root"]


def atomic_write_bytes(path, data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file and ``os.replace``:
    a reader never sees a half-written file, an interruption leaves the old one."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp's 0600 would hide reports from other users
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def atomic_write_text(path, text: str) -> None:
    atomic_write_bytes(path, text.encode("utf-8"))


def save_npz(path, **arrays) -> None:
    """``numpy.savez_compressed`` written atomically."""
    buf = io.BytesIO()
    np.savez_compressed(buf, **arrays)
    atomic_write_bytes(path, buf.getvalue())


def load_npz(path) -> dict[str, np.ndarray] | None:
    """The arrays of an ``.npz`` file, or None if it is missing or unreadable
    (truncated, bad CRC, not a zip); :func:`bench.store.runfolder.read_npz` also says why."""
    try:
        with open(path, "rb") as fh, np.load(fh, allow_pickle=False) as z:
            return {k: z[k] for k in z.files}
    except Exception:  # noqa: BLE001 - any damage means "recompute"
        return None


def config_hash(data: Any) -> str:
    """A short stable hash of JSON-serialisable data."""
    blob = json.dumps(data, sort_keys=True, separators=(",", ":"), default=str).encode()
    return hashlib.sha256(blob).hexdigest()[:10]


def runs_root() -> Path:
    """Where runs go: ``$STRIPEBENCH_RUNS`` or ``./results/runs``."""
    return Path(os.environ.get("STRIPEBENCH_RUNS", Path.cwd() / "results" / "runs"))
