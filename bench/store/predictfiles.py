"""The files of ``stripebench predict``: its provenance ``predict.json``, with the settings it ran with.

``predict.json`` (format :data:`SETTINGS_FORMAT`) holds what the prediction was asked (folder, trackers, channel,
laser, rotation, shrink, seed, ...) and ``settings``, the tuned values
(:meth:`bench.evaluate.predict_settings.PredictSettings.to_value`); :func:`read_predict_settings` reads both back.

Examples
--------
>>> import tempfile
>>> from bench.evaluate.predict_settings import PredictSettings
>>> with tempfile.TemporaryDirectory() as d:
...     _ = write_predict_settings(d, {"kind": "predict", "seed": 3}, PredictSettings(min_rows=12))
...     doc, s = read_predict_settings(d)
>>> doc["seed"], s.min_rows, s == PredictSettings(min_rows=12)
(3, 12, True)
"""

from __future__ import annotations

import json
from pathlib import Path

from bench.evaluate.predict_settings import PredictSettings
from bench.store.files import RunFolderError, atomic_write_text, check_format

__all__ = ["SETTINGS_FORMAT", "SETTINGS_NAME", "write_predict_settings", "read_predict_settings"]

#: The format of ``predict.json`` (bump when its keys change meaning).
SETTINGS_FORMAT = 1
#: Its name in a prediction's folder.
SETTINGS_NAME = "predict.json"


def write_predict_settings(folder, doc: dict, settings: PredictSettings) -> Path:
    """Write ``predict.json`` into ``folder``: ``doc`` (plain JSON data) with ``format`` and ``settings`` added."""
    path = Path(folder) / SETTINGS_NAME
    atomic_write_text(path, json.dumps({"format": SETTINGS_FORMAT, **doc, "settings": settings.to_value()}, indent=1))
    return path


def read_predict_settings(folder) -> tuple[dict, PredictSettings]:
    """``(doc, settings)`` of a prediction's ``predict.json`` (:func:`write_predict_settings`).

    Raises
    ------
    bench.store.files.RunFolderError
        No such file, not JSON, another format, or settings that are not a :class:`PredictSettings`' (one line).
    """
    from bench.store.textfiles import read_json

    path = Path(folder) / SETTINGS_NAME
    doc = read_json(path, "prediction settings", error=RunFolderError)
    if not isinstance(doc, dict):
        raise RunFolderError(f"{str(path)!r}: not a prediction's settings (a JSON object)")
    check_format(doc.get("format"), (SETTINGS_FORMAT,), "prediction's settings", path)
    try:
        settings = PredictSettings.from_value(doc.get("settings"))
    except ValueError as exc:
        raise RunFolderError(f"{str(path)!r}: {exc}") from None
    return doc, settings
