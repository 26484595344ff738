"""Files of a run: atomic writes, npz and JSON readers that say why they fail, content checksums.

Every writer here names the file in its ``OSError`` (a full disk during ``write``
or ``fsync`` has no file name of its own), so the command line's one-line
message says which file could not be written.
"""

from __future__ import annotations

import errno
import hashlib
import io
import json
import os
import shutil
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from bench.errors import StripebenchError

__all__ = ["RunFolderError", "os_error", "atomic_write_bytes", "atomic_write_text", "write_table", "save_npz",
           "load_npz", "read_npz", "read_json", "array_checksum", "json_checksum", "file_sha256", "clear_non_file", "remove_path",
           "non_file_kind", "non_file_reason", "check_format", "config_hash", "runs_root"]


class RunFolderError(StripebenchError, ValueError):
    """A run folder or one of its files that cannot be used as asked; ``str(err)`` is one line."""


def os_error(action: str, path, exc: OSError) -> RunFolderError:
    """One line for an ``OSError``: ``cannot <action> '<file>': <reason>`` (the file of the error, else ``path``).

    Examples
    --------
    >>> import errno
    >>> str(os_error("write", "/r/x.csv", OSError(errno.ENOSPC, "No space left on device")))
    "cannot write '/r/x.csv': no space left on the device"
    """
    reason = exc.strerror or str(exc)
    if exc.errno == errno.ENOSPC:
        reason = "no space left on the device"
    return RunFolderError(f"cannot {action} {str(exc.filename or path)!r}: {reason}")


def _named(exc: OSError, path: Path) -> OSError:
    """``exc`` with ``filename`` set to ``path`` (the file being written, not its temporary name)."""
    if exc.filename == str(path):
        return exc
    named = OSError(exc.errno, exc.strerror or str(exc), str(path))
    return named


def atomic_write_bytes(path, data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file and ``os.replace``:
    a reader never sees a half-written file, an interruption leaves the old one.

    Raises
    ------
    OSError
        With ``filename`` = ``path`` whatever step failed (``mkstemp``, ``write``,
        ``fsync``: a full disk, ``replace``: a directory in the file's place).
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as exc:
        raise _named(exc, path) from exc
    try:
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp's 0600 would hide reports from other users
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException as exc:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if isinstance(exc, OSError):
            raise _named(exc, path) from exc
        raise


def atomic_write_text(path, text: str) -> None:
    """:func:`atomic_write_bytes` of UTF-8 text."""
    atomic_write_bytes(path, text.encode("utf-8"))


def write_table(folder, table, parquet_name: str, csv_name: str) -> None:
    """A DataFrame as ``<folder>/<parquet_name>`` and ``<folder>/<csv_name>`` (no index), each written
    atomically (``RunFolderError`` naming the file on ``OSError``)."""
    d = Path(folder)
    buf = io.BytesIO()
    table.to_parquet(buf, index=False)
    for name, write in ((parquet_name, lambda p: atomic_write_bytes(p, buf.getvalue())),
                        (csv_name, lambda p: atomic_write_text(p, table.to_csv(index=False)))):
        try:
            write(d / name)
        except OSError as exc:
            raise os_error("write", d / name, exc) from None


def save_npz(path, **arrays) -> None:
    """``numpy.savez_compressed`` written atomically."""
    buf = io.BytesIO()
    np.savez_compressed(buf, **arrays)
    atomic_write_bytes(path, buf.getvalue())


def read_npz(path) -> tuple[dict[str, np.ndarray] | None, str | None]:
    """The arrays of an ``.npz`` file and None, or None and why it could not be read.

    A missing file gives ``(None, None)``; a truncated, corrupt (bad CRC, not a
    zip), pickled file or a directory in its place gives ``(None, reason)``, never an exception.

    Examples
    --------
    >>> read_npz("/nonexistent/x.npz")
    (None, None)
    """
    path = Path(path)
    if not path.exists() and not path.is_symlink():
        return None, None
    kind = non_file_kind(path)
    if kind is not None:
        return None, f"{kind} in its place"
    try:
        with open(path, "rb") as fh, np.load(fh, allow_pickle=False) as z:
            return {k: z[k] for k in z.files}, None
    except Exception as exc:  # BadZipFile, CRC errors, EOF, pickles, ...: all mean "recompute"
        return None, f"{type(exc).__name__}: {exc}".splitlines()[0][:200]


def read_json(path, width: int = 120) -> tuple[Any, str | None]:
    """The document of an existing JSON file and None, or None and why it could not be read:
    ``"unreadable (<reason>)"`` (an ``OSError``; not UTF-8, not JSON or nested beyond reason, the
    first line of the error cut to ``width`` characters), never an exception."""
    try:
        return json.loads(Path(path).read_text(encoding="utf-8")), None
    except OSError as exc:
        return None, f"unreadable ({exc.strerror or exc})"
    except (ValueError, RecursionError) as exc:  # not UTF-8, not JSON, nested beyond reason
        return None, f"unreadable ({type(exc).__name__}: {str(exc).splitlines()[0][:width]})"


def load_npz(path) -> dict[str, np.ndarray] | None:
    """The arrays of an ``.npz`` file, or None if it is missing or unreadable
    (truncated, bad CRC, not a zip); :func:`read_npz` also says why."""
    return read_npz(path)[0]


def array_checksum(arrays: dict[str, np.ndarray]) -> str:
    """Hex SHA-256 of named arrays: every name, dtype, shape and the bytes, in name order.

    Two dicts have the same checksum exactly when they hold the same names with
    arrays of the same dtype, shape and bytes (NaN payloads included).

    Examples
    --------
    >>> a = array_checksum({"x": np.arange(3.0)})
    >>> a == array_checksum({"x": np.arange(3.0)}), a == array_checksum({"x": np.arange(3.0) + 1e-12})
    (True, False)
    """
    from scenes.cache import checksum  # the render cache's checksum: one definition of the bytes hashed

    return checksum(arrays)


def json_checksum(doc: Any) -> str:
    """Hex SHA-256 of a JSON document in canonical form (sorted keys, no spaces; NaN kept as ``NaN``).

    Examples
    --------
    >>> json_checksum({"a": 1, "b": [1.5]}) == json_checksum({"b": [1.5], "a": 1})
    True
    """
    blob = json.dumps(doc, sort_keys=True, separators=(",", ":"), allow_nan=True)
    return hashlib.sha256(blob.encode()).hexdigest()


def file_sha256(path) -> str:
    """Hex SHA-256 of a file's bytes (read in 1 MiB blocks).

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = Path(d) / "m.csv"
    ...     _ = p.write_bytes(b"abc")
    ...     file_sha256(p)[:16]
    'ba7816bf8f01cfea'
    """
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def non_file_kind(path) -> str | None:
    """``"a directory"``, ``"a FIFO"``, ... when ``path`` exists and is not a regular file (or a link to one);
    None when it is a regular file or missing."""
    p = Path(path)
    if p.is_file() or not (p.exists() or p.is_symlink()):
        return None
    if p.is_symlink():
        return "a broken link"
    if p.is_dir():
        return "a directory"
    if p.is_fifo():
        return "a FIFO"
    if p.is_socket():
        return "a socket"
    return "a device or other non-file"


def clear_non_file(path) -> str | None:
    """Remove what stands where a stripebench file should be if it is not a regular file.

    Returns
    -------
    str or None
        What was removed (``"a directory"`` ...), None when ``path`` is a regular file or missing.

    Raises
    ------
    RunFolderError
        It could not be removed (one line naming it).
    """
    p = Path(path)
    kind = non_file_kind(p)
    if kind is None:
        return None
    try:
        remove_path(p)
    except OSError as exc:
        raise RunFolderError(f"{str(p)!r} is {kind} where stripebench keeps a file and cannot be removed "
                             f"({exc.strerror or exc}); remove it") from None
    return kind


def remove_path(path) -> None:
    """Remove a directory with all it holds, or a file, link or other non-directory (``OSError`` as raised)."""
    p = Path(path)
    if p.is_dir() and not p.is_symlink():
        shutil.rmtree(p)
    else:
        p.unlink()


def non_file_reason(path, clear_bad: bool = False) -> str | None:
    """Why a directory or other non-file stands where a file should (``"a directory, not a file"``;
    with ``clear_bad`` it is removed and the reason ends in ``"(removed)"``), or None for a file
    or nothing."""
    kind = non_file_kind(path)
    if kind is None:
        return None
    if clear_bad:
        clear_non_file(path)
        return f"{kind}, not a file (removed)"
    return f"{kind}, not a file"


def check_format(found: Any, supported: tuple[int, ...], what: str, path) -> int:
    """The format number ``found`` if this code reads it, else a one-line :class:`RunFolderError`.

    Examples
    --------
    >>> check_format(2, (1, 2), "checkpoint", "/r/scans/a.npz")
    2
    >>> check_format(7, (1, 2), "checkpoint", "/r/scans/a.npz")
    Traceback (most recent call last):
    ...
    bench.store.files.RunFolderError: '/r/scans/a.npz' is a checkpoint of format 7; this stripebench reads format 1 or 2
    """
    if isinstance(found, np.ndarray) and found.shape == ():
        found = found.item()
    if isinstance(found, bool) or not isinstance(found, (int, np.integer)) or int(found) not in supported:
        reads = " or ".join(str(s) for s in supported)
        raise RunFolderError(f"{str(path)!r} is a {what} of format {found!r}; this stripebench reads format {reads}")
    return int(found)


def config_hash(data: Any) -> str:
    """A short stable hash of JSON-serialisable data."""
    blob = json.dumps(data, sort_keys=True, separators=(",", ":"), default=str).encode()
    return hashlib.sha256(blob).hexdigest()[:10]


def runs_root() -> Path:
    """Where runs go: ``$STRIPEBENCH_RUNS`` or ``./results/runs``."""
    return Path(os.environ.get("STRIPEBENCH_RUNS", Path.cwd() / "results" / "runs"))
