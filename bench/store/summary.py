"""``summary.json`` of every kind of run: one builder, one validator, one reader.

A summary is a JSON object with ``format`` (2), ``kind`` (``run``, ``real``,
``sweep`` or ``score``) and the kind's fields; :func:`build_summary` checks that the fields
each kind must have are there with the right types (and that everything is
JSON), :func:`check_summary` checks a document read back. A summary without
``format`` is format 1 (written before formats were numbered: the same fields,
its kind ``real`` if it says so, ``sweep`` if it holds a ``sweep`` table, else
``run``); another number is refused in one line.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from bench.store.files import RunFolderError, atomic_write_text, check_format, os_error

__all__ = ["FORMAT", "REQUIRED", "build_summary", "check_summary", "summary_kind", "write_summary", "read_summary",
           "json_default"]

FORMAT = 2
_READS = (1, 2)
#: The fields each kind of summary must have, with their types.
REQUIRED: dict[str, dict[str, type | tuple]] = {
    "run": {"config": dict, "seed": int, "improvement": list, "scans": list,
            # read by the report's header and provenance
            "git_revision": str, "paper_improvement": (int, float), "variants": list, "versions": dict,
            "wall_s": (int, float)},
    # a scored submission (bench.run.score): a run's fields and the submission's
    "score": {"config": dict, "seed": int, "improvement": list, "scans": list, "submission": dict,
              "git_revision": str, "paper_improvement": (int, float), "variants": list, "versions": dict,
              "wall_s": (int, float)},
    "real": {"config": dict, "seed": int, "trackers": dict, "n_images": int, "tol_px": (int, float)},
    "sweep": {"config": dict, "sweep": dict, "seed": int, "units": list, "curves": list, "engine": dict},
}


def json_default(o):
    """``json.dumps``'s ``default`` for NumPy scalars and arrays."""
    if isinstance(o, np.integer):
        return int(o)
    if isinstance(o, np.floating):
        return float(o)
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")


def summary_kind(doc: dict) -> str:
    """The kind of a summary (format 1 inferred as the module docstring says)."""
    kind = doc.get("kind")
    if kind is not None:
        return kind
    return "sweep" if isinstance(doc.get("sweep"), dict) else "run"


def _type_name(typ) -> str:
    name = " or ".join(t.__name__ for t in typ) if isinstance(typ, tuple) else typ.__name__
    return ("an " if name[0] in "aeiou" else "a ") + name


def _problem(doc: dict, kind: str) -> str | None:
    if kind not in REQUIRED:
        return f"`kind` is {kind!r}, not one of {', '.join(REQUIRED)}"
    for key, typ in REQUIRED[kind].items():
        v = doc.get(key)
        if not isinstance(v, typ) or isinstance(v, bool):
            return f"`{key}` missing or not {_type_name(typ)}"
    if kind in ("run", "score"):
        cfg = doc["config"]
        if not isinstance(cfg.get("render"), dict) or not isinstance(cfg.get("experiments"), list):
            return "`config` lacks `render` or `experiments`"
    return None


def build_summary(kind: str, **fields) -> dict[str, Any]:
    """A summary of ``kind``: ``format``, ``kind`` and ``fields`` (in the order given), checked.

    Raises
    ------
    ValueError
        A required field is missing or of another type, or a value is not JSON-serialisable
        (a programming error, never a user's).

    Examples
    --------
    >>> s = build_summary("real", config={"dataset": "d"}, seed=0, trackers={}, n_images=2, tol_px=3.0)
    >>> s["format"], s["kind"], list(s)[2:4]
    (2, 'real', ['config', 'seed'])
    """
    doc = {"format": FORMAT, "kind": kind, **fields}
    why = _problem(doc, kind)
    if why:
        raise ValueError(f"a {kind} summary: {why}")
    json.dumps(doc, default=json_default)  # raises TypeError for what JSON cannot hold
    return doc


def check_summary(doc: Any, path, kind: str | tuple[str, ...] | None = None) -> dict:
    """``doc`` read from ``path`` if it is a summary (of ``kind``, when given); else one-line :class:`RunFolderError`."""
    if not isinstance(doc, dict):
        raise RunFolderError(f"{str(path)!r} is not a run summary (a JSON object)")
    check_format(doc.get("format", 1), _READS, "run summary", path)
    found = summary_kind(doc)
    why = _problem(doc, found)
    if why:
        raise RunFolderError(f"{str(path)!r} is not a run summary: {why}")
    kinds = (kind,) if isinstance(kind, str) else kind
    if kinds is not None and found not in kinds:
        raise RunFolderError(f"{str(path)!r} is the summary of a {found}, not of a {' or '.join(kinds)}")
    return doc


def write_summary(path, doc: dict) -> None:
    """Write a :func:`build_summary` document to ``path`` atomically (``RunFolderError`` naming the file on OSError)."""
    check_summary(doc, path)
    try:
        atomic_write_text(path, json.dumps(doc, indent=2, default=json_default))
    except OSError as exc:
        raise os_error("write", path, exc) from None


def read_summary(path, kind: str | tuple[str, ...] | None = None) -> dict:
    """The summary at ``path``, checked (:func:`check_summary`).

    Raises
    ------
    RunFolderError
        Missing (not a finished run), a directory, unreadable, not JSON, of another format, lacking a field
        or of another kind: one line naming the file.
    """
    path = Path(path)
    if not path.exists():
        raise RunFolderError(f"RUN must be a finished run folder (with {path.name}), got {str(path.parent)!r}")
    from bench.store.textfiles import loads_json, read_text

    text = read_text(path, "run summary", error=RunFolderError)  # a regular UTF-8 file, bounded in size
    doc = loads_json(text, repr(str(path)), error=RunFolderError)  # bounded nesting and integers
    return check_summary(doc, path, kind)
