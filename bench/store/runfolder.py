"""The run folder: its layout, writers, readers, lock and format version.

Every file of a run is written and read here; :mod:`bench.run.experiment`,
:mod:`bench.run.gate`, :mod:`bench.report.run` and the command line go through this
module. Layout of a run folder (``<runs root>/<name>-<config hash>/`` by
default)::

    run.json           format, configuration hash, code fingerprint: whose folder this is
    .lock              held (``fcntl.flock``) by the process writing the folder
    config.json        the validated configuration
    scans/<exp>.npz    per-experiment checkpoint (frames x rows of every tracker)
    figdata.npz        the frame and fields Fig. 7 shows
    gallery.npz        per experiment, the frames where the trackers miss the truth most
    metrics.parquet    one record per tracker x experiment x region (no timings:
    metrics.csv        the same seed gives byte-identical files)
    timings.csv        ms_per_frame per tracker x experiment x region (machine dependent)
    samples.csv        the sample points, one depth-error column per tracker
    summary.json       config, seed, versions, git revision, statistics, wall times
    figures/*.png
    report.html        self-contained report

A folder belongs to one configuration: :meth:`RunFolder.open` refuses a folder
written for another configuration (or a non-empty folder that is not a run)
unless ``force=True``, which clears it first (a folder of the same
configuration is resumed, with or without ``force``). When only the code changed
(trackers, scenes, plugin trackers' modules), the results are recomputed in
place. Every reader validates what it reads and raises :class:`RunFolderError`
(one line naming the file and the problem).
"""

from __future__ import annotations

import errno
import json
import math
import os
import re
import shutil
from pathlib import Path
from typing import Any

import numpy as np

from bench.errors import StripebenchError
from bench.store.files import atomic_write_bytes, atomic_write_text, config_hash, save_npz, runs_root

__all__ = ["FORMAT", "LAYOUT", "RunFolderError", "RunFolder", "default_run_dir", "safe_dir_name", "read_npz",
           "write_tables", "write_summary", "write_figdata", "write_gallery", "load_summary", "load_metrics", "load_run",
           "METRIC_KEYS", "TIMING_COLUMNS"]

FORMAT = 1
RUN_FILE = "run.json"
LOCK_FILE = ".lock"
LAYOUT = {
    "run": RUN_FILE, "config": "config.json", "scans": "scans", "figdata": "figdata.npz",
    "gallery": "gallery.npz",
    "metrics_parquet": "metrics.parquet", "metrics_csv": "metrics.csv", "timings": "timings.csv",
    "samples": "samples.csv", "summary": "summary.json", "figures": "figures", "report": "report.html",
}
METRIC_KEYS = ("experiment", "tracker", "region")
REQUIRED_METRICS = ("hit_rate", "coverage")  # read by every report (runs and real runs)
TIMING_COLUMNS = ("ms_per_frame",)
_SUMMARY_KEYS = {"config": dict, "seed": int, "improvement": list, "scans": list,
                 # read by the report's header and provenance
                 "git_revision": str, "paper_improvement": (int, float), "variants": list, "versions": dict,
                 "wall_s": (int, float)}


class RunFolderError(StripebenchError, ValueError):
    """A run folder that cannot be used as asked; ``str(err)`` is one line."""


def safe_dir_name(name: str) -> str:
    """A folder name from a configuration's free-text ``name``: letters, digits,
    ``_``, ``-`` and ``.`` kept, anything else (``/``, ``..`` at the start) replaced.

    Examples
    --------
    >>> safe_dir_name("../../x")
    'x'
    >>> safe_dir_name("my run/2")
    'my_run_2'
    """
    slug = re.sub(r"[^A-Za-z0-9_.-]+", "_", str(name)).strip("._") or "run"
    return slug[:80]


def default_run_dir(config) -> Path:
    """``<runs root>/<safe name>-<hash of the configuration>``, always inside the runs root."""
    root = runs_root()
    out = root / f"{safe_dir_name(config.name)}-{config_hash(config.identity())}"
    if not out.resolve().is_relative_to(root.resolve()):  # cannot happen with safe_dir_name; kept as a guard
        raise RunFolderError(f"run name {config.name!r} would place the run outside {str(root)!r}")
    return out


def _os_error(action: str, path, exc: OSError) -> RunFolderError:
    reason = exc.strerror or str(exc)
    if exc.errno == errno.ENOSPC:
        reason = "no space left on the device"
    return RunFolderError(f"cannot {action} {str(exc.filename or path)!r}: {reason}")


class RunFolder:
    """One run folder: lock it, claim it for a configuration, read and write its files.

    Parameters
    ----------
    path : path-like
        The folder (created by :meth:`open` if missing).
    """

    def __init__(self, path):
        self.path = Path(path)
        self._lock_fd: int | None = None

    def __repr__(self) -> str:
        return f"RunFolder({str(self.path)!r})"

    # -- lock ---------------------------------------------------------------
    def lock(self) -> None:
        """Take the folder's lock or raise :class:`RunFolderError` at once if
        another process holds it. Released by :meth:`unlock` or when the process ends."""
        import fcntl

        if self._lock_fd is not None:
            return
        lock_path = self.path / LOCK_FILE
        try:
            fd = os.open(lock_path, os.O_RDWR | os.O_CREAT, 0o666)
        except OSError as exc:
            raise _os_error("write to run folder", self.path, exc) from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            raise RunFolderError(f"run folder {str(self.path)!r} is in use by another stripebench process "
                                 "(wait for it to finish or choose another --out)") from None
        self._lock_fd = fd

    def unlock(self) -> None:
        """Release the lock (closing the file descriptor releases ``flock``)."""
        if self._lock_fd is not None:
            os.close(self._lock_fd)
            self._lock_fd = None

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.unlock()

    # -- claim ---------------------------------------------------------------
    def open(self, config_dict: dict, code_fingerprint: str, *, force: bool = False, say=None) -> "RunFolder":
        """Create and lock the folder and claim it for ``config_dict``.

        Parameters
        ----------
        config_dict : dict
            The configuration (``Config.to_dict()``).
        code_fingerprint : str
            Hash of the code the results depend on (see :func:`bench.store.provenance.code_fingerprint`).
        force : bool
            Clear a folder that holds another configuration's run (or other files) instead of refusing.
        say : callable, optional
            Receives one-line notes (results recomputed because the code changed).

        Raises
        ------
        RunFolderError
            The path is a file, not writable, locked by another process, or holds
            another configuration's run (without ``force``).
        """
        if self.path.exists() and not self.path.is_dir():
            raise RunFolderError(f"run folder {str(self.path)!r} is a file, not a folder")
        try:
            self.path.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise _os_error("create run folder", self.path, exc) from None
        if not os.access(self.path, os.W_OK | os.X_OK):
            raise RunFolderError(f"cannot write to run folder {str(self.path)!r}: permission denied")
        self.lock()
        try:
            self._claim(config_dict, code_fingerprint, force, say)
        except BaseException:
            self.unlock()
            raise
        return self

    def _claim(self, config_dict, code_fingerprint, force, say) -> None:
        want = config_hash(config_dict)
        record = self._read_record()
        if record is None and self._old_layout_of(config_dict):
            record = {"config_hash": want, "code": None}  # a run of this configuration from before run.json
        others = [p.name for p in self.path.iterdir() if p.name != LOCK_FILE]
        mismatch = record is None or record.get("config_hash") != want
        if others and mismatch:
            if not force:
                if record is None:
                    raise RunFolderError(f"{str(self.path)!r} is not empty and is not a stripebench run folder "
                                         f"(holds {sorted(others)[0]!r}); choose another --out or pass --force "
                                         "to clear it")
                raise RunFolderError(
                    f"run folder {str(self.path)!r} holds a run of another configuration "
                    f"({record.get('name', '?')!r}, hash {record.get('config_hash', '?')}, this one {want}); "
                    "choose another --out or pass --force to clear it")
            self.clear()
        elif record is not None and record.get("code") != code_fingerprint:
            if say is not None and record.get("code") is not None:
                say(f"stripebench: the code changed since the run in {self.path} (trackers, scenes or plugins): "
                    "its results are recomputed")
            self.clear(keep_scans=True)  # the checkpoints check their own fingerprint
        doc = {"format": FORMAT, "name": config_dict.get("name"), "config_hash": want, "code": code_fingerprint}
        self._write(RUN_FILE, json.dumps(doc, indent=1, sort_keys=True) + "\n")
        self._write(LAYOUT["config"], json.dumps(config_dict, indent=2))

    def _old_layout_of(self, config_dict) -> bool:
        """Whether the folder is a run of ``config_dict`` written before ``run.json`` existed."""
        try:
            return json.loads((self.path / LAYOUT["config"]).read_text(encoding="utf-8")) == config_dict
        except (OSError, ValueError):
            return False

    def _read_record(self) -> dict | None:
        p = self.path / RUN_FILE
        if not p.exists():
            return None
        try:
            doc = json.loads(p.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return {"config_hash": "unreadable"}
        return doc if isinstance(doc, dict) else {"config_hash": "unreadable"}

    def clear(self, *, keep_scans: bool = False) -> None:
        """Remove everything in the folder but its lock (and the checkpoints with ``keep_scans``)."""
        for p in self.path.iterdir():
            if p.name == LOCK_FILE or (keep_scans and p.name == LAYOUT["scans"]):
                continue
            try:
                if p.is_dir() and not p.is_symlink():
                    shutil.rmtree(p)
                else:
                    p.unlink()
            except OSError as exc:
                raise _os_error("clear", p, exc) from None

    # -- writers -------------------------------------------------------------
    def _write(self, name: str, text: str) -> None:
        try:
            atomic_write_text(self.path / name, text)
        except OSError as exc:
            raise _os_error("write", self.path / name, exc) from None

    def checkpoint(self, key: str) -> Path:
        """The checkpoint file of experiment ``key``."""
        return self.path / LAYOUT["scans"] / f"{key}.npz"


def _guard_write(path, fn) -> None:
    try:
        fn()
    except OSError as exc:
        raise _os_error("write", path, exc) from None


def write_tables(run_dir, metrics, samples) -> None:
    """``metrics.parquet``/``metrics.csv`` without timing columns, ``timings.csv``
    with them, ``samples.csv``; each written atomically."""
    import io

    run_dir = Path(run_dir)
    timing = [c for c in TIMING_COLUMNS if c in metrics.columns]
    timings = metrics[[*METRIC_KEYS, *timing]]
    metrics = metrics.drop(columns=timing)
    buf = io.BytesIO()
    metrics.to_parquet(buf, index=False)
    for name, write in ((LAYOUT["metrics_parquet"], lambda p: atomic_write_bytes(p, buf.getvalue())),
                        (LAYOUT["metrics_csv"], lambda p: atomic_write_text(p, metrics.to_csv(index=False))),
                        (LAYOUT["timings"], lambda p: atomic_write_text(p, timings.to_csv(index=False))),
                        (LAYOUT["samples"], lambda p: atomic_write_text(p, samples.to_csv(index=False)))):
        _guard_write(run_dir / name, lambda: write(run_dir / name))


def _json_default(o):
    if isinstance(o, np.integer):
        return int(o)
    if isinstance(o, np.floating):
        return float(o)
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")


def write_summary(run_dir, summary: dict) -> None:
    """``summary.json``, atomically."""
    path = Path(run_dir) / LAYOUT["summary"]
    _guard_write(path, lambda: atomic_write_text(path, json.dumps(summary, indent=2, default=_json_default)))


def write_figdata(run_dir, **arrays) -> None:
    """``figdata.npz`` (the frame Fig. 7 shows), atomically."""
    path = Path(run_dir) / LAYOUT["figdata"]
    _guard_write(path, lambda: save_npz(path, **arrays))


def write_gallery(run_dir, **arrays) -> None:
    """``gallery.npz`` (the failure gallery's frames), atomically."""
    path = Path(run_dir) / LAYOUT["gallery"]
    _guard_write(path, lambda: save_npz(path, **arrays))


# -- readers -------------------------------------------------------------------
def read_npz(path) -> tuple[dict[str, np.ndarray] | None, str | None]:
    """The arrays of an ``.npz`` file and None, or None and why it could not be read.

    A missing file gives ``(None, None)``; a truncated, corrupt (bad CRC, not a
    zip) or pickled file gives ``(None, reason)``, never an exception.

    Examples
    --------
    >>> read_npz("/nonexistent/x.npz")
    (None, None)
    """
    path = Path(path)
    if not path.exists():
        return None, None
    try:
        with open(path, "rb") as fh, np.load(fh, allow_pickle=False) as z:
            return {k: z[k] for k in z.files}, None
    except Exception as exc:  # BadZipFile, CRC errors, EOF, pickles, ...: all mean "recompute"
        return None, f"{type(exc).__name__}: {exc}".splitlines()[0][:200]


def _figdata_problem(fd: dict) -> str | None:
    need = {"experiment", "mirror_angle_deg", "image", "truth_columns", "trackers"}
    if not need <= set(fd):
        return f"missing {sorted(need - set(fd))[0]!r}"
    img = fd["image"]
    if img.ndim != 2:
        return f"image of shape {img.shape}, not 2-D"
    H = img.shape[0]
    if fd["truth_columns"].shape != (H,):
        return f"truth_columns of shape {fd['truth_columns'].shape} for an image of {H} rows"
    for n in fd["trackers"]:
        c = fd.get(f"columns/{n}")
        if c is None or c.shape != (H,):
            return f"columns of {str(n)!r} missing or not of shape ({H},)"
    return None


def load_summary(run_dir) -> dict:
    """``summary.json`` of a finished run, checked.

    Raises
    ------
    RunFolderError
        No summary (not a finished run), unreadable, not JSON, or missing a key.
    """
    path = Path(run_dir) / LAYOUT["summary"]
    if not Path(run_dir).is_dir():
        raise RunFolderError(f"RUN must be a finished run folder, got {str(run_dir)!r} (not a folder)")
    if not path.exists():
        raise RunFolderError(f"RUN must be a finished run folder (with summary.json), got {str(run_dir)!r}")
    from bench.store.textfiles import loads_json, read_text

    text = read_text(path, "run summary", error=RunFolderError)  # a regular UTF-8 file
    doc = loads_json(text, repr(str(path)), error=RunFolderError)  # bounded nesting and integers
    if not isinstance(doc, dict):
        raise RunFolderError(f"{str(path)!r} is not a run summary (a JSON object)")
    if doc.get("kind") == "real":  # a real-photograph run (bench.run.real): its own summary
        if not isinstance(doc.get("config"), dict):
            raise RunFolderError(f"{str(path)!r} is not a run summary: `config` missing or not a dict")
        return doc
    for key, typ in _SUMMARY_KEYS.items():
        if not isinstance(doc.get(key), typ):
            what = "number" if isinstance(typ, tuple) else typ.__name__
            raise RunFolderError(f"{str(path)!r} is not a run summary: `{key}` missing or not a {what}")
    cfg = doc["config"]
    if not isinstance(cfg.get("render"), dict) or not isinstance(cfg.get("experiments"), list):
        raise RunFolderError(f"{str(path)!r} is not a run summary: `config` lacks `render` or `experiments`")
    return doc


def load_metrics(run_dir, *, timings: bool = False):
    """``metrics.parquet`` checked (one row per experiment x tracker x region,
    finite or NaN numbers); with ``timings`` the columns of ``timings.csv`` joined in.

    Raises
    ------
    RunFolderError
        Missing, unreadable or not a metrics table.
    """
    import pandas as pd

    path = Path(run_dir) / LAYOUT["metrics_parquet"]
    if not path.exists():
        raise RunFolderError(f"RUN must be a finished run folder (with metrics.parquet), got {str(run_dir)!r}")
    try:
        m = pd.read_parquet(path)
    except Exception as exc:  # pyarrow raises its own types for corrupt files
        raise RunFolderError(f"cannot read {str(path)!r}: {type(exc).__name__}: "
                             f"{str(exc).splitlines()[0][:160] if str(exc) else ''}; rerun the run to rewrite it") from None
    missing = [c for c in (*METRIC_KEYS, *REQUIRED_METRICS) if c not in m.columns]
    if missing:
        raise RunFolderError(f"{str(path)!r} is not a metrics table: no column {missing[0]!r}")
    for c in m.columns:
        if pd.api.types.is_numeric_dtype(m[c]) and np.isinf(m[c].to_numpy(float)).any():
            raise RunFolderError(f"{str(path)!r}: column {c!r} must hold finite numbers or NaN")
    if m.duplicated(list(METRIC_KEYS)).any():
        raise RunFolderError(f"{str(path)!r}: an experiment/tracker/region appears twice")
    if timings:
        tpath = Path(run_dir) / LAYOUT["timings"]
        t = None
        if tpath.exists():
            try:
                t = pd.read_csv(tpath)
            except Exception:
                t = None
        if t is not None and set(METRIC_KEYS) <= set(t.columns):
            m = m.merge(t, on=list(METRIC_KEYS), how="left")
        for c in TIMING_COLUMNS:
            if c not in m.columns:
                m[c] = float("nan")
    return m


def load_run(run_dir, *, say=None) -> dict:
    """The saved results of a finished run, validated.

    Returns
    -------
    dict
        ``metrics`` (DataFrame, timings joined in), ``samples`` (DataFrame),
        ``summary`` (dict), ``figdata`` (dict of arrays, or None when missing or
        corrupt) and ``scans`` (experiment key -> arrays; unreadable ones left out).

    Raises
    ------
    RunFolderError
        Not a finished run, or its summary, metrics or samples are unreadable.
    """
    import pandas as pd

    run_dir = Path(run_dir)
    summary = load_summary(run_dir)
    metrics = load_metrics(run_dir, timings=True)
    spath = run_dir / LAYOUT["samples"]
    try:
        samples = pd.read_csv(spath)
    except Exception as exc:
        raise RunFolderError(f"cannot read {str(spath)!r}: {type(exc).__name__}; rerun the run to rewrite it") from None
    fd, why = read_npz(run_dir / LAYOUT["figdata"])
    if fd is not None:
        why = _figdata_problem(fd)
        fd = None if why else fd
    if why and say is not None:
        say(f"stripebench: {run_dir / LAYOUT['figdata']} is unusable ({why}): Fig. 7 is left out; "
            "rerun the run to rewrite it")
    gallery, why = read_npz(run_dir / LAYOUT["gallery"])
    if gallery is not None and "keys" not in gallery:
        gallery, why = None, "no `keys` array"
    if why and say is not None and (run_dir / LAYOUT["gallery"]).exists():
        say(f"stripebench: {run_dir / LAYOUT['gallery']} is unusable ({why}): the failure gallery is left out; "
            "rerun the run to rewrite it")
    scans = {}
    for p in sorted((run_dir / LAYOUT["scans"]).glob("*.npz")):
        arrays, why = read_npz(p)
        if arrays is None:
            if say is not None:
                say(f"stripebench: checkpoint {p} is unreadable ({why}): left out")
            continue
        scans[p.stem] = arrays
    return {"metrics": metrics, "samples": samples, "summary": summary, "figdata": fd, "gallery": gallery,
            "scans": scans}


def finite_or_none(v) -> Any:
    """``float(v)``, or None for NaN (for JSON)."""
    v = float(v)
    return None if math.isnan(v) else v
