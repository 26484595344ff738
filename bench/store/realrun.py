"""The files of ``stripebench track`` and ``stripebench real``.

``track`` writes into its output folder (a run folder of kind ``track``,
:mod:`bench.store.runfolder`) per image ``NAME.csv`` (:func:`write_track_csv`)
and ``NAME_overlay.png``, and records in ``inputs.json`` which input each
``NAME`` was made from. :func:`track_output_names` gives every input its
``NAME`` and refuses, in one line, inputs whose outputs would collide (two
inputs with one file stem, ``a/same.png`` and ``b/same.png`` or ``dup.png`` and
``dup.jpg``), an input inside the output folder (its outputs could overwrite
it, and ``--force`` would clear it) and a ``NAME`` that an earlier ``track``
into the same folder wrote for another input (unless ``force``).

``real`` writes a run folder of kind ``real``::

    run.json, .lock, config.json   as in every run folder (dataset, trackers, tolerance, seed)
    metrics.parquet    one record per tracker x image (experiment = image name,
    metrics.csv        region = "real"), plus experiment = "mean"; no timings: the same
                       seed gives byte-identical files
    timings.csv        ms_per_frame per tracker x image (machine dependent)
    tracks/NAME.csv    the columns of every tracker (as ``track`` writes them)
    overlays/NAME.png  the photograph with every tracker's columns and the reference
    summary.json       kind = "real" (bench.store.summary)
    report.html
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from bench.store.files import RunFolderError, atomic_write_text, os_error
from bench.store.summary import read_summary

__all__ = ["LAYOUT", "INPUTS_FILE", "write_track_csv", "track_output_names", "read_inputs", "write_inputs",
           "write_real_metrics", "load_real_run", "real_run_means"]

LAYOUT = {"metrics_parquet": "metrics.parquet", "metrics_csv": "metrics.csv", "timings": "timings.csv",
          "tracks": "tracks",
          "overlays": "overlays", "summary": "summary.json", "report": "report.html"}
INPUTS_FILE = "inputs.json"


def write_track_csv(path, labels: list[str], results: dict) -> None:
    """``row``, then ``col_<label>``, ``score_<label>`` per label (empty where NaN), atomically.

    Parameters
    ----------
    path : path-like
    labels : list of str
    results : dict
        label -> :class:`trackers.Track` (columns in px, one per row).
    """
    H = next(iter(results.values())).columns.shape[0] if results else 0
    header = ["row"]
    cells = [[str(r) for r in range(H)]]
    for lab in labels:
        for kind, values in (("col", results[lab].columns), ("score", results[lab].score)):
            header.append(f"{kind}_{lab}")
            cells.append(["" if v != v else "%.4f" % v for v in np.asarray(values, dtype=np.float64).tolist()])
    text = "\n".join([",".join(header), *(",".join(r) for r in zip(*cells))]) + "\n"
    try:
        atomic_write_text(path, text)
    except OSError as exc:
        raise os_error("write", path, exc) from None


def read_inputs(out_dir) -> dict[str, str]:
    """``inputs.json`` of a track folder: output NAME -> the resolved input path ({} when absent or unreadable)."""
    try:
        doc = json.loads((Path(out_dir) / INPUTS_FILE).read_text(encoding="utf-8"))
    except (OSError, ValueError, RecursionError):
        return {}
    if not isinstance(doc, dict):
        return {}
    return {str(k): str(v) for k, v in doc.items() if isinstance(v, str)}


def write_inputs(out_dir, inputs: dict[str, str]) -> None:
    """Write ``inputs.json`` (sorted), atomically."""
    path = Path(out_dir) / INPUTS_FILE
    try:
        atomic_write_text(path, json.dumps(dict(sorted(inputs.items())), indent=1) + "\n")
    except OSError as exc:
        raise os_error("write", path, exc) from None


def track_output_names(paths, out_dir, *, extra_inputs=(), force: bool = False) -> dict[Path, str]:
    """The output ``NAME`` of each input (its file stem), checked against collisions.

    Parameters
    ----------
    paths : sequence of path-like
        The images to track.
    out_dir : path-like
        The output folder.
    extra_inputs : sequence of path-like
        Other files read (a ``--background``): they too must not lie inside ``out_dir``.
    force : bool
        Let a NAME that an earlier ``track`` into ``out_dir`` wrote for another input be replaced.

    Returns
    -------
    dict
        input path -> NAME (``NAME.csv``, ``NAME_overlay.png``).

    Raises
    ------
    RunFolderError
        An input inside ``out_dir``; two inputs with one NAME; a NAME recorded for another input (without ``force``).

    Examples
    --------
    >>> track_output_names(["a/same.png", "b/same.png"], "/tmp/nonexistent-out")
    Traceback (most recent call last):
    ...
    bench.store.files.RunFolderError: inputs 'a/same.png' and 'b/same.png' would both write same.csv and same_overlay.png; track them into separate --out folders
    """
    out = Path(out_dir).resolve()
    for p in [*paths, *extra_inputs]:
        if Path(p).resolve().is_relative_to(out):
            raise RunFolderError(f"input {str(p)!r} is inside the output folder {str(out_dir)!r}: its outputs "
                                 "could overwrite it; choose another --out")
    names: dict[Path, str] = {}
    by_name: dict[str, Path] = {}
    for p in (Path(q) for q in paths):
        name = p.stem
        if name in by_name and by_name[name].resolve() != p.resolve():
            raise RunFolderError(f"inputs {str(by_name[name])!r} and {str(p)!r} would both write {name}.csv and "
                                 f"{name}_overlay.png; track them into separate --out folders")
        by_name[name] = p
        names[p] = name
    if not force:
        before = read_inputs(out_dir)
        for p, name in names.items():
            was = before.get(name)
            if was is not None and was != str(p.resolve()):
                raise RunFolderError(f"{str(Path(out_dir) / (name + '.csv'))!r} was written for {was!r}, not for "
                                     f"{str(p)!r}; choose another --out or pass --force to replace it")
    return names


def write_real_metrics(run_dir, metrics) -> None:
    """``metrics.parquet`` and ``metrics.csv`` of a real run without its timings, and ``timings.csv`` with them,
    atomically (:func:`bench.store.runfolder.write_metrics`; ``RunFolderError`` naming the file)."""
    from bench.store.runfolder import write_metrics

    write_metrics(run_dir, metrics)


def load_real_run(run_dir) -> dict:
    """A finished real run's ``summary`` (kind ``real``) and ``metrics`` (DataFrame, ``timings.csv`` joined in),
    checked.

    Raises
    ------
    RunFolderError
        Not a finished real run, or its files unreadable (one line naming the file).
    """
    from bench.store.runfolder import load_metrics

    d = Path(run_dir)
    summary = read_summary(d / LAYOUT["summary"], kind="real")
    return {"summary": summary, "metrics": load_metrics(d, timings=True)}


def real_run_means(run_dir, metric: str = "hit_rate") -> dict[str, float]:
    """label -> a real run's ``metric`` of its ``mean`` rows (the mean hit rate over the images; the
    detection figures pooled over their rows)."""
    m = load_real_run(run_dir)["metrics"]
    m = m[m["experiment"] == "mean"]
    if metric not in m.columns:
        return {}
    return {str(t): float(v) for t, v in zip(m["tracker"], m[metric])}
