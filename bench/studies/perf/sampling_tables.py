"""The sampling procedure's files: its measurements as JSON and its choices as ``scenes/sampling.py``'s tables.

:func:`write_tables` rewrites the generated block of :mod:`scenes.sampling` (which
``spp = "auto"`` and ``ambient_spp = "auto"`` read) from the choices of
:mod:`bench.studies.perf.sampling`; :func:`to_json` and :func:`from_json` are the
measurements' form in ``stripebench perf sampling --save`` / ``--from`` files.

Examples
--------
>>> ok = {"stripe": 0.5, "off": 0.4, "centre": 0.3, "energy": 0.999}
>>> result = {"laser": {("path", (8,)): {"worst": ok, "cost_s": 0.3, "pass": True}},
...           "ambient": {2: {"z": 0.6, "cost_s": 0.1, "pass": True}}, "cases": ["a"]}
>>> to_json(result)["laser"][0]["spp"]
[8]
>>> from_json(to_json(result))["laser"] == result["laser"]
True
"""

from __future__ import annotations

from pathlib import Path
from typing import Dict

__all__ = ["to_json", "from_json", "write_tables"]


def _records(cands: dict) -> list:
    return [{"label": c[0], "spp": list(c[1]), **rec} for c, rec in cands.items()]


def _from_records(records: list) -> dict:
    return {(r["label"], tuple(r["spp"])): {k: v for k, v in r.items() if k not in ("label", "spp")}
            for r in records}


def to_json(result: dict) -> dict:
    """One material's measurements (:func:`bench.studies.perf.sampling.measure`) as JSON-ready data."""
    return {"laser": _records(result["laser"]),
            "ambient": [{"spp": n, **rec} for n, rec in result["ambient"].items()],
            "object": {key: _records(c) for key, c in result.get("object", {}).items()},
            "cases": result["cases"], "checks": result.get("checks", [])}


def from_json(d: dict) -> dict:
    """The measurements back from :func:`to_json`'s data."""
    ambient = {int(r["spp"]): {k: v for k, v in r.items() if k != "spp"} for r in d["ambient"]}
    return {"laser": _from_records(d["laser"]), "ambient": ambient,
            "object": {key: _from_records(r) for key, r in d.get("object", {}).items()},
            "cases": d["cases"], "checks": d.get("checks", [])}


def write_tables(path, results: Dict[str, dict], chosen: Dict[str, tuple], objects: Dict[str, dict],
                 argv_text: str) -> None:
    """Replace the generated block of ``path`` (``scenes/sampling.py``) by the tables of the choices.

    Parameters
    ----------
    path : path
        The module to rewrite; only the text between ``# --- generated: begin ---`` and
        ``# --- generated: end ---`` changes.
    results : dict
        Per material, its measurements (:func:`bench.studies.perf.sampling.measure`).
    chosen : dict
        Per material, its choice (:func:`bench.studies.perf.sampling.choose`): (laser candidate, ambient spp).
    objects : dict
        Per material, the object pass's count per object (:func:`bench.studies.perf.sampling.choose_objects`).
    argv_text : str
        The command line recorded in the block.
    """
    from bench.store.files import atomic_write_text

    laser = {m: c[0][1] for m, c in chosen.items() if c[0] is not None}
    kinds = {m: c[0][0] for m, c in chosen.items() if c[0] is not None}
    ambient = {m: c[1] for m, c in chosen.items() if c[1] is not None}
    measured = {}
    for m, c in chosen.items():
        if c[0] is None or c[1] is None:
            continue
        w = results[m]["laser"][c[0]]["worst"]
        measured[m] = {"z_stripe": round(w["stripe"], 3), "z_off": round(w["off"], 3),
                       "centre": round(w["centre"], 3), "energy": round(w["energy"], 4),
                       "z_ambient": round(results[m]["ambient"][c[1]]["z"], 3), "cases": len(results[m]["cases"])}
    from scenes.sampling import FIXED_SPP

    object_spp, measured_object = {}, {}
    for m in chosen:
        for key, n in objects[m].items():
            if n is not None:
                object_spp.setdefault(m, {})[key] = n
            shown = FIXED_SPP if n is None else n
            rec = results[m]["object"][key].get(("path", (shown,)))
            if rec is not None:
                w = rec["worst"]
                measured_object.setdefault(m, {})[key] = {
                    "spp": shown, "certified": n is not None, "z_stripe": round(w["stripe"], 3),
                    "z_off": round(w["off"], 3), "centre": round(w["centre"], 3), "energy": round(w["energy"], 4)}
    path = Path(path)
    text = path.read_text()
    start, end = "# --- generated: begin ---\n", "# --- generated: end ---\n"
    head, rest = text.split(start)
    _, tail = rest.split(end)
    body = (f"# by `{argv_text}`\n"
            f"LASER_KIND = {kinds!r}\n"
            f"LASER_SPP = {laser!r}\n"
            f"AMBIENT_SPP = {ambient!r}\n"
            f"MEASURED = {measured!r}\n"
            f"OBJECT_SPP = {object_spp!r}\n"
            f"MEASURED_OBJECT = {measured_object!r}\n")
    atomic_write_text(path, head + start + body + end + tail)
