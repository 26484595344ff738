"""The files of a sweep folder: finished units, the tidy table, the summary.

Layout (``<runs root>/<name>-sweep-<hash>/`` by default)::

    run.json, .lock, config.json   as in every run folder (bench.store.runfolder), kind "sweep"
    units/<fingerprint>.json       a finished unit: {"format": 2, "checksum": ..., "result": {...}}
    sweep.parquet, sweep.csv       one row per experiment x grid point x repeat x tracker label
    summary.json                   kind "sweep" (bench.store.summary)
    figures/sweep.png, report.html

A unit file holds :func:`bench.run.sweep.run_unit`'s result and the SHA-256 of
its canonical JSON (:func:`bench.store.files.json_checksum`). :func:`read_unit`
refuses, with the reason in one phrase, a file that is not JSON, of another
format (format 1, the bare result, had no checksum), whose checksum does not
match (edited or damaged), or whose result lacks its fields or holds
non-finite times; the unit is then recomputed.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

from bench.store.files import (RunFolderError, atomic_write_text, json_checksum, non_file_reason, read_json,
                               write_table)
from bench.store.summary import read_summary

__all__ = ["UNIT_FORMAT", "LAYOUT", "unit_path", "write_unit", "read_unit", "verify_unit", "write_sweep_table",
           "load_sweep"]

UNIT_FORMAT = 2
LAYOUT = {"units": "units", "table_parquet": "sweep.parquet", "table_csv": "sweep.csv", "summary": "summary.json",
          "figures": "figures", "report": "report.html"}
_TIMES = ("render_s", "eval_s")
_FIELDS = {"rows": list, "source": str, "frames": int, "evaluations": int, "width": int, "height": int,
           "render_s": (int, float), "eval_s": (int, float)}


def unit_path(sweep_dir, fingerprint: str) -> Path:
    """The file of the unit with this fingerprint."""
    return Path(sweep_dir) / LAYOUT["units"] / f"{fingerprint}.json"


def write_unit(path, result: dict) -> None:
    """Write a unit's result with its checksum (format 2), atomically; ``OSError`` names the file."""
    atomic_write_text(path, json.dumps({"format": UNIT_FORMAT, "checksum": json_checksum(result), "result": result}))


def _result_problem(res: Any) -> str | None:
    if not isinstance(res, dict):
        return f"the result is {type(res).__name__}, not an object"
    for key, typ in _FIELDS.items():
        v = res.get(key)
        if not isinstance(v, typ) or isinstance(v, bool):
            return f"`{key}` missing or not of the right type"
    for key in _TIMES:
        if not (math.isfinite(res[key]) and res[key] >= 0):
            return f"`{key}` is {res[key]!r}, not a time"
    if not all(isinstance(r, dict) for r in res["rows"]):
        return "`rows` must hold objects"
    for r in res["rows"]:
        for k, v in r.items():
            if isinstance(v, float) and math.isinf(v):
                return f"row value `{k}` is {v!r}"
    return None


def read_unit(path, *, clear_bad: bool = False) -> tuple[dict | None, str | None]:
    """A finished unit's result, or None and why it cannot be used ((None, None): none yet).

    With ``clear_bad`` a directory or other non-file at ``path`` is removed (so the
    unit's write succeeds) and the reason ends in ``"(removed)"``.

    Examples
    --------
    >>> read_unit("/nonexistent/u.json")
    (None, None)
    """
    path = Path(path)
    why = non_file_reason(path, clear_bad)
    if why is not None:
        return None, why
    if not path.exists():
        return None, None
    doc, why = read_json(path)
    if why is not None:
        return None, why
    if not isinstance(doc, dict) or "format" not in doc:
        return None, f"of format 1 (this stripebench reads format {UNIT_FORMAT}, with a checksum)"
    if doc.get("format") != UNIT_FORMAT or isinstance(doc.get("format"), bool):
        return None, f"of format {doc.get('format')!r} (this stripebench reads format {UNIT_FORMAT})"
    res = doc.get("result")
    if doc.get("checksum") != json_checksum(res):
        return None, "edited or damaged (its checksum does not match its result)"
    why = _result_problem(res)
    if why:
        return None, f"damaged ({why})"
    return res, None


def verify_unit(path) -> str | None:
    """Why the unit file at ``path`` is unusable (None if it is a good one)."""
    res, why = read_unit(path)
    return why if res is None else None


def write_sweep_table(sweep_dir, table) -> None:
    """``sweep.parquet`` and ``sweep.csv`` of the tidy table, atomically (``RunFolderError`` naming the file)."""
    write_table(sweep_dir, table, LAYOUT["table_parquet"], LAYOUT["table_csv"])


def load_sweep(sweep_dir) -> dict[str, Any]:
    """The saved results of a finished sweep: ``table`` (DataFrame) and ``summary`` (dict).

    Raises
    ------
    RunFolderError
        Not a finished sweep, or its summary or table unreadable (one line naming the file).
    """
    import pandas as pd

    d = Path(sweep_dir)
    summary = read_summary(d / LAYOUT["summary"], kind="sweep")
    path = d / LAYOUT["table_parquet"]
    try:
        table = pd.read_parquet(path)
    except Exception as exc:  # pyarrow raises its own types for corrupt files
        raise RunFolderError(f"cannot read {str(path)!r}: {type(exc).__name__}; rerun the sweep to rewrite it") \
            from None
    return {"table": table, "summary": summary}
