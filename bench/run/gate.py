"""The regression gate: compare a run's metrics with a committed baseline.

``stripebench check RUN --baseline results/baselines/ci.json`` compares every
gated metric of every (experiment, tracker, region) with the baseline, each
with its own direction and tolerance, prints a table and exits 1 on any
regression (or on anything missing from either side), 0 otherwise.
``--update`` writes the run's metrics as the new baseline, on purpose.

A metric regresses when it moves in its bad direction by more than
``abs + rel * |baseline|``; a value that becomes NaN (or stops being NaN)
regresses too. Runtimes are not gated (they depend on the machine).

Detection is gated on both halves: precision, recall, F1, the false-report rate and
the average precision of the tracker's score (:mod:`bench.evaluate.outcomes`), over every
row (region ``all``); an ``object`` entry has none of the figures a false report moves
(:data:`bench.evaluate.tables.OBJECT_BLIND`: its rows off the object are unknown), so it
gates the stripe half and the errors only.
A real-photograph run (``stripebench real``) is gated the same way on its
own metrics (:data:`REAL_TOLERANCES`: hit rate, MAE on the hits, coverage
and the detection figures) per image x tracker and for the mean over images, e.g.
``stripebench check results/runs/real --baseline results/baselines/real.json``.

Baseline files are format 2 (:data:`FORMAT`): format 1 plus ``renderer`` (the
Mitsuba variant and LLVM target that rendered the baseline's frames, see
:func:`scenes.variant.renderer`; a run rendered otherwise is not comparable)
and ``tolerance_source`` (how the tolerances were derived: by
:mod:`bench.studies.gate_spread` from the spread measured across machine
configurations, or ``"defaults"``). Format 1 files are read as format 2 with
neither; any other format is refused in one line.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

from bench.errors import InputError

__all__ = ["TOLERANCES", "REAL_TOLERANCES", "Row", "baseline_from_run", "compare", "format_table", "write_baseline", "load_baseline",
           "validate_baseline", "comparability", "COMPARED_KEYS", "SAMPLING_KEYS", "rows_to_json", "FORMAT", "renderer_difference"]

# what must agree between two runs (or a run and a baseline) for their metrics to be comparable
COMPARED_KEYS = ("render", "experiments", "seed")

# a rate gated upwards (hit rates, detection) or downwards (reports that should not be there): one rule each
_RATE_UP = ("higher", 0.01, 0.0)
_RATE_DOWN = ("lower", 0.01, 0.05)
# detection, both halves (bench.evaluate.outcomes): reports that are hits, stripe rows hit, their F1,
# reports on stripe-less rows, and the average precision of the tracker's score; gated alike in both kinds of run
_DETECTION_TOLERANCES: dict[str, tuple[str, float, float]] = {
    "precision": _RATE_UP, "recall": _RATE_UP, "f1": _RATE_UP, "false_report_rate": _RATE_DOWN, "ap": _RATE_UP}
# metric -> (direction, absolute tolerance, relative tolerance)
TOLERANCES: dict[str, tuple[str, float, float]] = {
    "px_mae": ("lower", 0.05, 0.05),
    "px_rmse": ("lower", 0.10, 0.05),
    "px_p95": ("lower", 0.10, 0.05),
    "depth_mae_mm": ("lower", 0.10, 0.05),
    "depth_rmse_mm": ("lower", 0.20, 0.05),
    "depth_p95_mm": ("lower", 0.20, 0.05),
    **{m: _RATE_UP for m in ("coverage", "hit_rate")},
    **{m: _RATE_DOWN for m in ("false_lock_rate", "outlier_rate", "false_detections")},
    **_DETECTION_TOLERANCES,
}
#: The gated metrics of a real-photograph run (``stripebench real``, summary ``kind = "real"``).
REAL_TOLERANCES: dict[str, tuple[str, float, float]] = {
    "hit_rate": _RATE_UP, "mae_px": ("lower", 0.05, 0.05), "coverage": _RATE_UP,
    **_DETECTION_TOLERANCES,
}
#: The baseline format written; :data:`READ_FORMATS` are read (format 1 is upgraded on reading).
FORMAT = 2
READ_FORMATS = (1, 2)
_FORMAT = FORMAT


def tolerances_for(summary: dict) -> dict[str, tuple[str, float, float]]:
    """The gated metrics of a run: :data:`REAL_TOLERANCES` for a real-photograph
    run, :data:`TOLERANCES` otherwise."""
    return REAL_TOLERANCES if summary.get("kind") == "real" else TOLERANCES


@dataclass(frozen=True)
class Row:
    key: str  # experiment/tracker/region
    metric: str
    baseline: float | None
    now: float | None
    verdict: str  # ok, better, REGRESSED, MISSING IN RUN, NOT IN BASELINE

    @property
    def failed(self) -> bool:
        return self.verdict not in ("ok", "better")

    @property
    def delta(self) -> float | None:
        if self.baseline is None or self.now is None or _nan(self.baseline) or _nan(self.now):
            return None
        return self.now - self.baseline


def _nan(v) -> bool:
    return v is None or (isinstance(v, float) and math.isnan(v))


def _clean(v):
    v = float(v)
    return None if math.isnan(v) else v


def baseline_from_run(run_dir) -> dict:
    """The gated metrics of a finished run, as a baseline document (format :data:`FORMAT`,
    the default tolerances, ``tolerance_source = "defaults"``)."""
    from bench.store.runfolder import RunFolderError, load_metrics, load_summary

    run_dir = Path(run_dir)
    summary = load_summary(run_dir)
    metrics = load_metrics(run_dir)
    tols = tolerances_for(summary)
    missing = [m for m in tols if m not in metrics.columns]
    if missing:
        raise RunFolderError(f"{str(run_dir / 'metrics.parquet')!r} has no column {missing[0]!r}")
    from bench.evaluate.tables import OBJECT_BLIND

    entries = {}
    for r in metrics.to_dict("records"):
        key = f"{r['experiment']}/{r['tracker']}/{r['region']}"
        blind = OBJECT_BLIND if r["region"] == "object" else ()  # NaN by construction there: nothing to gate
        entries[key] = {m: _clean(r[m]) for m in tols if m not in blind}
    doc = {
        "format": _FORMAT,
        "config": summary["config"],
        "git_revision": summary.get("git_revision", "unknown"),
        "variants": summary.get("variants", []),
        "renderer": summary.get("renderer", ""),
        "tolerances": {m: {"direction": d, "abs": a, "rel": rel} for m, (d, a, rel) in tols.items()},
        "tolerance_source": "defaults",
        "metrics": entries,
    }
    if summary.get("kind") == "real":
        doc["kind"] = "real"
    return doc


def write_baseline(run_dir, path, *, tolerances: dict | None = None, tolerance_source=None,
                   entry_tolerances: dict | None = None) -> dict:
    """Write the run's metrics as the baseline at ``path`` (atomically).

    ``tolerances`` (``{metric: {direction, abs, rel}}``), ``tolerance_source`` and ``entry_tolerances``
    (``{entry: {metric: {abs, rel}}}``, wider tolerances of single entries, :func:`compare`) replace the
    defaults; without them, a valid baseline already at ``path`` whose tolerances were derived
    (``tolerance_source`` not ``"defaults"``) keeps its tolerances, entry tolerances and their source, so
    ``check --update`` does not undo :mod:`bench.studies.gate_spread`.
    """
    from bench.store.files import atomic_write_text

    doc = baseline_from_run(run_dir)
    if tolerances is None and Path(path).exists():
        try:
            old = load_baseline(path)
        except (FileNotFoundError, ValueError):
            old = None
        if old is not None and old.get("tolerance_source", "defaults") != "defaults" \
                and set(old.get("tolerances") or {}) == set(doc["tolerances"]):
            tolerances, tolerance_source = old["tolerances"], old["tolerance_source"]
            entry_tolerances = old.get("entry_tolerances")
    if tolerances is not None:
        doc["tolerances"] = tolerances
        doc["tolerance_source"] = tolerance_source if tolerance_source is not None else "given"
    if entry_tolerances:
        doc["entry_tolerances"] = entry_tolerances
    validate_baseline(doc, f"baseline for {str(path)!r}")
    atomic_write_text(path, json.dumps(doc, indent=1, sort_keys=True) + "\n")
    return doc


def _number_or_none(v) -> bool:
    return v is None or (isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v))


def validate_baseline(doc, where: str = "baseline") -> dict:
    """Check a baseline document's structure and values; returns it.

    Raises
    ------
    bench.errors.InputError (a ValueError)
        One line naming the first bad entry (``where`` names the file).

    Examples
    --------
    A format 1 document is upgraded in place (``renderer = ""``, ``tolerance_source = "defaults"``).

    Examples
    --------
    >>> validate_baseline({"format": 1, "metrics": {"e/t/all": {"px_mae": "x"}}})
    Traceback (most recent call last):
    ...
    bench.errors.InputError: baseline: `metrics.e/t/all.px_mae` must be a number or null, got 'x'
    >>> validate_baseline({"format": 3, "metrics": {}})
    Traceback (most recent call last):
    ...
    bench.errors.InputError: baseline is format 3: this stripebench reads baseline formats 1 and 2 (regenerate it with `stripebench check RUN --baseline FILE --update` or `stripebench spread`)
    """
    if isinstance(doc, dict) and "metrics" in doc and doc.get("format") not in READ_FORMATS \
            and isinstance(doc.get("format"), int) and not isinstance(doc.get("format"), bool):
        raise InputError(f"{where} is format {doc['format']}: this stripebench reads baseline formats "
                         f"{' and '.join(map(str, READ_FORMATS))} (regenerate it with `stripebench check RUN "
                         "--baseline FILE --update` or `stripebench spread`)")
    fmt = doc.get("format") if isinstance(doc, dict) else None
    if type(fmt) is not int or fmt not in READ_FORMATS or "metrics" not in doc:  # true == 1 and 1.0 == 1: not formats
        raise InputError(f"{where} is not a stripebench baseline (format {_FORMAT})"
                         + (f": `format` must be an integer, got {fmt!r:.20}" if isinstance(fmt, (bool, float)) else ""))
    if doc["format"] == 1:
        doc["format"] = FORMAT
        doc.setdefault("renderer", "")
        doc.setdefault("tolerance_source", "defaults")
    if not isinstance(doc.get("renderer", ""), str):
        raise InputError(f"{where}: `renderer` must be a string, got {doc['renderer']!r:.60}")
    src = doc.get("tolerance_source", "defaults")
    if not (isinstance(src, str) or (isinstance(src, dict) and isinstance(src.get("procedure"), str))):
        raise InputError(f"{where}: `tolerance_source` must be a string or an object with a `procedure`, "
                         f"got {src!r:.60}")
    def value(v, name):
        if not _number_or_none(v):
            raise InputError(f"{where}: `{name}` must be a number or null, got {v!r:.60}")

    _per_entry(doc["metrics"], "metrics", "metric values", value, where)
    tols = doc.get("tolerances")
    if tols is not None:
        if not isinstance(tols, dict):
            raise InputError(f"{where}: `tolerances` must be an object, got {tols!r:.60}")
        for m, t in tols.items():
            if not isinstance(t, dict) or set(t) != {"direction", "abs", "rel"}:
                raise InputError(f"{where}: `tolerances.{m}` must have exactly `direction`, `abs` and `rel`, "
                                 f"got {t!r:.80}")
            if t["direction"] not in ("lower", "higher"):
                raise InputError(f"{where}: `tolerances.{m}.direction` must be 'lower' or 'higher', "
                                 f"got {t['direction']!r}")
            _check_bounds(t, f"tolerances.{m}", where)
    def entry_tolerance(t, name):  # {abs, rel}, in the metric's direction
        if not isinstance(t, dict) or set(t) != {"abs", "rel"}:
            raise InputError(f"{where}: `{name}` must have exactly `abs` and `rel`, got {t!r:.80}")
        _check_bounds(t, name, where)

    if doc.get("entry_tolerances") is not None:
        _per_entry(doc["entry_tolerances"], "entry_tolerances", "metrics", entry_tolerance, where)
    cfg = doc.get("config")
    if not isinstance(cfg, dict):  # without it the comparability check would pass anything
        raise InputError(f"{where}: `config` must be the object of the run it was made from (its comparability "
                         f"is checked), got {cfg!r:.60}; regenerate the baseline with `stripebench check RUN "
                         "--baseline FILE --update`")
    return doc


def _per_entry(obj, name: str, what: str, check, where: str) -> None:
    """``obj``, a baseline's ``{entry: {metric: leaf}}`` (``metrics``, ``entry_tolerances``), checked: objects at both
    levels (one line naming ``name`` and the entry otherwise), each leaf by ``check(leaf, "name.entry.metric")``."""
    if not isinstance(obj, dict):
        raise InputError(f"{where}: `{name}` must be an object, got {obj!r:.60}")
    for key, per in obj.items():
        if not isinstance(per, dict):
            raise InputError(f"{where}: `{name}.{key}` must be an object of {what}, got {per!r:.60}")
        for m, leaf in per.items():
            check(leaf, f"{name}.{key}.{m}")


def _check_bounds(tol: dict, name: str, where: str) -> None:
    """A tolerance's ``abs`` and ``rel``: numbers >= 0 (one line naming ``name`` otherwise)."""
    for k in ("abs", "rel"):
        if tol[k] is None or not _number_or_none(tol[k]) or tol[k] < 0:
            raise InputError(f"{where}: `{name}.{k}` must be a number >= 0, got {tol[k]!r}")


def load_baseline(path) -> dict:
    """Read and check a baseline file (see :func:`validate_baseline`).

    Raises
    ------
    bench.errors.InputError
        Unreadable, not a regular UTF-8 file, not JSON (nested too deeply, a huge
        integer), or not a valid baseline.
    """
    from bench.store.textfiles import read_json

    doc = read_json(path, "baseline")  # a regular UTF-8 file, bounded nesting and integers
    return validate_baseline(doc, f"baseline {str(path)!r}")


SAMPLING_KEYS = ("spp", "ambient_spp")
"""The ``[render]`` keys that set only the renders' sample counts (``compare --across-sampling`` ignores them)."""


def comparability(config_a: dict | None, config_b: dict | None, *, across_sampling: bool = False) -> list[str]:
    """What differs between two runs' configurations among :data:`COMPARED_KEYS`
    (render size and spp, experiments, seed); empty when their metrics are comparable.

    ``across_sampling``: the renders' sample counts (:data:`SAMPLING_KEYS`) may differ (the same
    frames up to their Monte Carlo noise: a comparison of sampling choices).

    Examples
    --------
    >>> comparability({"seed": 0, "render": {"width": 64}, "experiments": []},
    ...               {"seed": 1, "render": {"width": 128}, "experiments": []})
    ["render ({'width': 64} vs {'width': 128})", 'seed (0 vs 1)']
    >>> comparability({"render": {"width": 64, "spp": 16}}, {"render": {"width": 64, "spp": "auto"}},
    ...               across_sampling=True)
    []
    """
    if config_a is None or config_b is None:
        return []
    out = []
    for k in COMPARED_KEYS:
        a, b = config_a.get(k), config_b.get(k)
        if k == "render" and across_sampling and isinstance(a, dict) and isinstance(b, dict):
            a, b = ({kk: v for kk, v in d.items() if kk not in SAMPLING_KEYS} for d in (a, b))
        if a != b:
            if k == "experiments" and isinstance(a, list) and isinstance(b, list):
                out.append(f"experiments ({len(a)} vs {len(b)}, or different scenes, materials, angles or overrides)")
            else:
                out.append(f"{k} ({a!r:.60} vs {b!r:.60})")
    return out


def renderer_difference(baseline: dict, current: dict) -> str:
    """Why two documents' frames were rendered differently (``""`` when alike or either is unknown).

    Examples
    --------
    >>> renderer_difference({"renderer": "llvm_ad_mono x86-64-v3/8"}, {"renderer": "scalar_rgb"})
    "renderer ('llvm_ad_mono x86-64-v3/8' vs 'scalar_rgb')"
    >>> renderer_difference({"renderer": ""}, {"renderer": "scalar_rgb"})
    ''
    """
    a, b = baseline.get("renderer") or "", current.get("renderer") or ""
    return f"renderer ({a!r} vs {b!r})" if a and b and a != b else ""


def rows_to_json(rows: list[Row], *, all_rows: bool = True) -> dict:
    """The counts over all rows and the rows (only the changed ones unless ``all_rows``) as a JSON-friendly dict."""
    failed = sum(r.failed for r in rows)
    better = sum(r.verdict == "better" for r in rows)
    return {"checks": len(rows), "failed": failed, "better": better, "unchanged": len(rows) - failed - better,
            "rows": [{"key": r.key, "metric": r.metric, "baseline": r.baseline, "now": r.now, "delta": r.delta,
                      "verdict": r.verdict} for r in rows if all_rows or r.verdict != "ok"]}


def _verdict(metric: str, base, now, tol: dict) -> str:
    if _nan(base) and _nan(now):
        return "ok"
    if _nan(base) != _nan(now):
        return "REGRESSED"
    worse = (now - base) if tol["direction"] == "lower" else (base - now)
    allowed = tol["abs"] + tol["rel"] * abs(base)
    if worse > allowed:
        return "REGRESSED"
    if worse < -allowed:
        return "better"
    return "ok"


def compare(baseline: dict, current: dict) -> list[Row]:
    """Every (entry, metric) of both documents with its verdict: the metric's tolerance, or the entry's own
    (``entry_tolerances``: an entry measured to move more between machines than its metric's tolerance allows,
    :mod:`bench.studies.gate_spread`), in the metric's direction.

    Examples
    --------
    >>> base = {"metrics": {"e/t/all": {"px_mae": 1.0}, "f/t/all": {"px_mae": 1.0}},
    ...         "entry_tolerances": {"f/t/all": {"px_mae": {"abs": 0.5, "rel": 0.0}}}}
    >>> now = {"metrics": {"e/t/all": {"px_mae": 1.3}, "f/t/all": {"px_mae": 1.3}}}
    >>> [r.verdict for r in compare(base, now)]
    ['REGRESSED', 'ok']
    """
    tols = baseline.get("tolerances") or {m: {"direction": d, "abs": a, "rel": r}
                                          for m, (d, a, r) in TOLERANCES.items()}
    entry_tols = baseline.get("entry_tolerances") or {}
    rows = []
    bm, cm = baseline["metrics"], current["metrics"]
    for key in sorted(set(bm) | set(cm)):
        if key not in cm:
            rows.append(Row(key, "*", None, None, "MISSING IN RUN"))
            continue
        if key not in bm:
            rows.append(Row(key, "*", None, None, "NOT IN BASELINE"))
            continue
        for metric in sorted(set(bm[key]) | set(cm[key])):
            if metric not in cm[key]:
                rows.append(Row(key, metric, bm[key][metric], None, "MISSING IN RUN"))
            elif metric not in bm[key] or metric not in tols:
                rows.append(Row(key, metric, None, cm[key][metric], "NOT IN BASELINE"))
            else:
                b, n = bm[key][metric], cm[key][metric]
                tol = {**tols[metric], **entry_tols.get(key, {}).get(metric, {})}
                rows.append(Row(key, metric, b, n, _verdict(metric, b, n, tol)))
    return rows


def _f(v) -> str:
    if v is None:
        return "–"
    if isinstance(v, float) and math.isnan(v):
        return "nan"
    return f"{v:.4g}"


def format_table(rows: list[Row], *, all_rows: bool = False) -> str:
    """A fixed-width table; by default the failing and improved rows only,
    then a one-line count."""
    shown = [r for r in rows if all_rows or r.verdict != "ok"]
    w = max([len(r.key) for r in shown] + [5])
    lines = [f"{'entry':<{w}}  {'metric':<17}{'baseline':>11}{'now':>11}{'delta':>11}  verdict"]
    for r in shown:
        d = r.delta
        lines.append(f"{r.key:<{w}}  {r.metric:<17}{_f(r.baseline):>11}{_f(r.now):>11}"
                     f"{(f'{d:+.3g}' if d is not None else '–'):>11}  {r.verdict}")
    failed = sum(r.failed for r in rows)
    better = sum(r.verdict == "better" for r in rows)
    lines.append(f"{len(rows)} checks: {failed} failed, {better} better, {len(rows) - failed - better} unchanged "
                 "within tolerance")
    return "\n".join(lines)
