"""The files of ``stripebench predict``: its provenance ``predict.json``, and the calibration it states figures by.

``predict.json`` (format :data:`SETTINGS_FORMAT`) holds what the prediction was asked (folder, trackers, channel,
laser, rotation, shrink, seed, ...) and ``settings``, the tuned values
(:meth:`bench.evaluate.predict_settings.PredictSettings.to_value`); :func:`read_predict_settings` reads both back.
The calibration (format :data:`CALIBRATION_FORMAT`, shipped as :data:`CALIBRATION_PATH`, written by
``stripebench predictloro --calibration``) holds :func:`bench.evaluate.predict_loro.calibration` of the shipped set
with the leave-one-rig-out figures behind it and their provenance; :func:`read_calibration` reads it.

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

__all__ = ["SETTINGS_FORMAT", "SETTINGS_NAME", "write_predict_settings", "read_predict_settings", "CALIBRATION_FORMAT",
           "CALIBRATION_PATH", "write_calibration", "read_calibration"]

#: The format of ``predict.json`` (bump when its keys change meaning).
SETTINGS_FORMAT = 1
#: Its name in a prediction's folder.
SETTINGS_NAME = "predict.json"
#: The format of the calibration file.
CALIBRATION_FORMAT = 1
#: The calibration ``predict`` reads by default: the shipped set's, judged leave one rig out.
CALIBRATION_PATH = Path(__file__).resolve().parents[1] / "data" / "predict_calibration.json"


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


def write_calibration(path, doc: dict) -> Path:
    """Write a calibration (``doc``: :func:`bench.evaluate.predict_loro.calibration` with ``loro`` and ``provenance``
    added) to ``path``, with ``format``."""
    from bench.store.files import atomic_write_text

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(path, json.dumps({"format": CALIBRATION_FORMAT, **doc}, indent=1, default=float) + "\n")
    return path


def read_calibration(path=None) -> dict | None:
    """The calibration at ``path`` (default :data:`CALIBRATION_PATH`), or None where there is no such file.

    Raises
    ------
    bench.store.files.RunFolderError
        A file that is not JSON, of another format, or without a figure's ``source``, ``half_width`` or ``null``, the
        ``pick`` or the ``residuals`` (one line).
    """
    from bench.evaluate.predict_loro import FIGURES
    from bench.store.textfiles import read_json

    path = CALIBRATION_PATH if path is None else Path(path)
    if not path.exists():
        return None
    doc = read_json(path, "prediction calibration", error=RunFolderError)
    if not isinstance(doc, dict):
        raise RunFolderError(f"{str(path)!r}: not a prediction calibration (a JSON object)")
    check_format(doc.get("format"), (CALIBRATION_FORMAT,), "prediction calibration", path)
    for f in FIGURES:
        c = doc.get(f)
        if not (isinstance(c, dict) and c.get("source") in ("method", "null") and isinstance(c.get("null"), dict)
                and isinstance(c.get("half_width"), dict) and {"method", "null"} <= set(c["half_width"])):
            raise RunFolderError(f"{str(path)!r}: `{f}` is not a calibrated figure (source, half_width, null)")
    if not (isinstance(doc.get("pick"), dict) and doc["pick"].get("source") in ("method", "null")
            and isinstance(doc.get("residuals"), dict) and isinstance(doc.get("trackers"), list)):
        raise RunFolderError(f"{str(path)!r}: no `pick`, `residuals` or `trackers`")
    return doc
