"""The run folder of every kind of run: its layout, identity, lock, format version, writers and readers.

Every file of a run is written and read in :mod:`bench.store`: this module (the
folder, ``run.json``, the tables and the readers of a finished run),
:mod:`bench.store.checkpoint` (scan checkpoints), :mod:`bench.store.figdata`
(Fig. 7's frame, the failure gallery), :mod:`bench.store.summary`
(``summary.json``), :mod:`bench.store.sweepfiles` (sweep units and tables),
:mod:`bench.store.realrun` (``track`` and ``real`` outputs). Layout of a
synthetic run folder (``<runs root>/<name>-<config hash>/`` by default)::

    run.json           format, kind, configuration hash, code fingerprint: whose folder this is
    .lock              held (``fcntl.flock``) by the process writing the folder
    config.json        the validated configuration
    scans/<exp>.npz    per-experiment checkpoint (frames x rows of every tracker), with its checksum
    figdata.npz        the frame and fields Fig. 7 shows
    gallery.npz        per experiment, the frames where the trackers miss the truth most
    metrics.parquet    one record per tracker x experiment x region (no timings:
    metrics.csv        the same seed gives byte-identical files)
    timings.csv        ms_per_frame per tracker x experiment x region (machine dependent)
    samples.csv        the sample points, one depth-error column per tracker
    summary.json       config, seed, versions, git revision, machine, metrics.csv's sha256, statistics, wall times
    figures/*.png
    report.html        the report (its figures linked from figures/)

**One guard for every kind of run** (:data:`KINDS`: ``run``, ``real``,
``sweep``, ``track``, ``score``, ``export``): :meth:`RunFolder.open` locks the folder (a
second process is refused at once) and claims it for one kind and
configuration. A folder of another kind or configuration, a non-empty folder
that is not a run, or a ``run.json`` of a newer format is refused in one line
unless ``force=True``, which clears it first (a folder of the same kind and
configuration is resumed, with or without ``force``). When only the code
changed (trackers, scenes, plugin trackers' modules) the results are cleared and
recomputed, the resumable files (checkpoints, sweep units) kept: they check
their own fingerprints. An unreadable ``run.json`` is said in one line and the
folder recovered for this run (unless its ``config.json`` names another
configuration), keeping the checkpoints whose own checksums hold. A directory
where ``.lock`` or ``run.json`` should be is removed with one line. Every reader
validates what it reads and raises :class:`RunFolderError` (one line naming the
file and the problem).
"""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

from bench.store.files import (RunFolderError, atomic_write_bytes, atomic_write_text, check_format, clear_non_file,
                               config_hash, non_file_kind, os_error, read_json, read_npz, remove_path, runs_root,
                               save_npz, write_table)
from bench.store.summary import read_summary

__all__ = ["FORMAT", "KINDS", "LAYOUT", "RunFolderError", "RunFolder", "default_run_dir", "named_run_dir",
           "safe_dir_name", "read_npz", "save_npz", "write_tables", "write_summary", "write_figdata", "write_gallery",
           "load_summary", "load_metrics", "load_run", "METRIC_KEYS", "TIMING_COLUMNS", "write_metrics",
           "metrics_sha256"]

FORMAT = 2  # run.json: 1 had no `kind` (every such folder is a synthetic run)
_READS = (1, 2)
#: The kinds of run folder, and what each is called in messages.
KINDS = {"run": "run", "real": "real run", "sweep": "sweep", "track": "track output", "score": "score",
         "export": "exported frame set", "bundle": "participants' bundle"}
#: Per kind, the folder of resumable files kept when the code changes (each checks its own fingerprint).
RESUMABLE = {"run": "scans", "sweep": "units"}
#: Kinds whose folder gathers outputs over several commands: not cleared when the code changes.
ACCUMULATES = ("track",)
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


def named_run_dir(name: str, tag: str) -> Path:
    """``<runs root>/<safe name>-<tag>``: always inside the runs root, whatever ``name`` holds.

    Raises
    ------
    RunFolderError
        ``tag`` would leave the runs root (a programming error: tags are hashes).
    """
    root = runs_root()
    out = root / f"{safe_dir_name(name)}-{safe_dir_name(tag)}"
    if out.parent != root or not out.resolve().is_relative_to(root.resolve()):
        raise RunFolderError(f"run name {name!r} would place the run outside {str(root)!r}")
    return out


def default_run_dir(config) -> Path:
    """``<runs root>/<safe name>-<hash of the configuration>``, always inside the runs root."""
    return named_run_dir(config.name, config_hash(config.identity()))


class RunFolder:
    """One run folder: lock it, claim it for a kind and configuration, read and write its files.

    Parameters
    ----------
    path : path-like
        The folder (created by :meth:`open` if missing).
    kind : str
        One of :data:`KINDS` (default ``"run"``).
    """

    def __init__(self, path, kind: str = "run"):
        if kind not in KINDS:
            raise ValueError(f"`kind` must be one of {', '.join(KINDS)}, got {kind!r}")
        self.path = Path(path)
        self.kind = kind
        self._lock_fd: int | None = None

    def __repr__(self) -> str:
        return f"RunFolder({str(self.path)!r}, kind={self.kind!r})"

    # -- lock ---------------------------------------------------------------
    def lock(self, say=None) -> None:
        """Take the folder's lock or raise :class:`RunFolderError` at once if
        another process holds it. Released by :meth:`unlock` or when the process ends.
        A directory (or other non-file) where ``.lock`` should be is removed first, said to ``say``."""
        import fcntl

        if self._lock_fd is not None:
            return
        lock_path = self.path / LOCK_FILE
        kind = clear_non_file(lock_path)
        if kind is not None and say is not None:
            say(f"stripebench: {lock_path} was {kind}, not a lock file: removed")
        try:
            fd = os.open(lock_path, os.O_RDWR | os.O_CREAT, 0o666)
        except OSError as exc:
            raise os_error("write to run folder", self.path, exc) from None
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
    def open(self, config_dict: dict, code_fingerprint: str | None, *, force: bool = False,
             say=None) -> "RunFolder":
        """Create and lock the folder and claim it for this kind and ``config_dict``.

        Parameters
        ----------
        config_dict : dict
            The configuration (for a synthetic run ``Config.identity()``); its hash is the folder's identity
            and it is written to ``config.json``.
        code_fingerprint : str or None
            Hash of the code the results depend on (see :func:`bench.store.provenance.code_fingerprint`);
            None: not checked.
        force : bool
            Clear a folder that holds another kind's or configuration's run (or other files) instead of refusing.
        say : callable, optional
            Receives one-line notes (results recomputed because the code changed, a folder recovered).

        Raises
        ------
        RunFolderError
            The path is a file, not writable, locked by another process, or holds
            another kind's or configuration's run, or a newer format's (without ``force``).
        """
        if self.path.exists() and not self.path.is_dir():
            raise RunFolderError(f"run folder {str(self.path)!r} is a file, not a folder")
        try:
            self.path.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise os_error("create run folder", self.path, exc) from None
        if not os.access(self.path, os.W_OK | os.X_OK):
            raise RunFolderError(f"cannot write to run folder {str(self.path)!r}: permission denied")
        had_lock = (self.path / LOCK_FILE).exists()
        self.lock(say)
        try:
            self._claim(config_dict, code_fingerprint, force, say)
        except BaseException:
            self.unlock()
            if not had_lock:  # a refused folder is left as it was found
                try:
                    (self.path / LOCK_FILE).unlink()
                except OSError:
                    pass
            raise
        return self

    def _claim(self, config_dict, code_fingerprint, force, say) -> None:
        want = config_hash(config_dict)
        record, problem = self._read_record()
        recovered = False
        if problem is not None:  # run.json unreadable: recover unless config.json says it is another's
            stored = self._stored_config()
            if stored is not None and stored != config_dict:
                record = {"kind": "?", "config_hash": config_hash(stored), "name": stored.get("name", "?")
                          if isinstance(stored, dict) else "?"}
            else:
                record, recovered = {"kind": self.kind, "config_hash": want, "code": None}, True
        elif record is None and self._stored_config() == config_dict:
            record = {"kind": self.kind, "config_hash": want, "code": None}  # a run from before run.json
        others = [p.name for p in self.path.iterdir() if p.name != LOCK_FILE]
        rec_kind = None if record is None else record.get("kind", "run")
        mismatch = record is None or rec_kind != self.kind or record.get("config_hash") != want
        if others and mismatch:
            if not force:
                raise RunFolderError(self._refusal(record, rec_kind, others, want, problem))
            self.clear()
        elif (record is not None and record.get("code") != code_fingerprint and code_fingerprint is not None
              and self.kind not in ACCUMULATES) or recovered:
            if say is not None and record.get("code") is not None:
                say(f"stripebench: the code changed since the {KINDS[self.kind]} in {self.path} "
                    "(trackers, scenes or plugins): its results are recomputed")
            keep = RESUMABLE.get(self.kind)
            self.clear(keep=(keep,) if keep else ())
            if recovered:
                kept, removed = self._verify_resumable()
                if say is not None:
                    say(f"stripebench: {self.path / RUN_FILE} is {problem}: the folder is recovered for this "
                        f"{KINDS[self.kind]} (kept {kept} resumable file(s) whose checksums hold, removed {removed})")
        keep = RESUMABLE.get(self.kind)
        if keep is not None and (self.path / keep).exists() and not (self.path / keep).is_dir():
            try:  # a file where the checkpoints' folder should be
                (self.path / keep).unlink()
            except OSError as exc:
                raise os_error("clear", self.path / keep, exc) from None
            if say is not None:
                say(f"stripebench: {self.path / keep} was a file, not a folder: removed")
        doc = {"format": FORMAT, "kind": self.kind, "name": config_dict.get("name"), "config_hash": want,
               "code": code_fingerprint}
        self.write_text(RUN_FILE, json.dumps(doc, indent=1, sort_keys=True) + "\n")
        self.write_text(LAYOUT["config"], json.dumps(config_dict, indent=2))

    def _refusal(self, record, rec_kind, others, want, problem) -> str:
        where = f"run folder {str(self.path)!r}"
        tail = "choose another --out or pass --force to clear it"
        if record is None:
            return (f"{str(self.path)!r} is not empty and is not a stripebench run folder "
                    f"(holds {sorted(others)[0]!r}); {tail}")
        if "newer" in record:
            return (f"{where} was written by a newer stripebench ({RUN_FILE} of format {record['newer']!r}; "
                    f"this one reads format 1 or 2); {tail}")
        if rec_kind != self.kind and rec_kind in KINDS:
            return (f"{where} holds a {KINDS[rec_kind]} ({record.get('name', '?')!r}, hash "
                    f"{record.get('config_hash', '?')}), not a {KINDS[self.kind]}; {tail}")
        what = f" ({RUN_FILE} is {problem}; config.json names it)" if problem else ""
        return (f"{where} holds a {KINDS.get(rec_kind, 'run')} of another configuration{what} "
                f"({record.get('name', '?')!r}, hash {record.get('config_hash', '?')}, this one {want}); {tail}")

    def _stored_config(self):
        """``config.json`` as JSON, or None when missing or unreadable."""
        try:
            return json.loads((self.path / LAYOUT["config"]).read_text(encoding="utf-8"))
        except (OSError, ValueError, RecursionError):
            return None

    def _read_record(self) -> tuple[dict | None, str | None]:
        """``run.json``: (doc, None); (None, None) when missing; (None, why) when unreadable;
        ({"newer": N}, None) for a format this code does not read."""
        p = self.path / RUN_FILE
        kind = non_file_kind(p)
        if kind is not None:
            return None, f"{kind}, not a file"
        if not p.exists():
            return None, None
        doc, why = read_json(p, width=100)
        if why is not None:
            return None, why
        if not isinstance(doc, dict) or not isinstance(doc.get("config_hash"), str):
            return None, "unreadable (not a run record)"
        try:
            check_format(doc.get("format", 1), _READS, "run record", p)
        except RunFolderError:
            return {"newer": doc.get("format"), "kind": "?"}, None
        return doc, None

    def _verify_resumable(self) -> tuple[int, int]:
        """Remove the resumable files whose own checks fail; (kept, removed)."""
        keep = RESUMABLE.get(self.kind)
        if keep is None or not (self.path / keep).is_dir():
            return 0, 0
        if self.kind == "run":
            from bench.store.checkpoint import verify_checkpoint as verify
        else:
            from bench.store.sweepfiles import verify_unit as verify
        kept = removed = 0
        for p in sorted((self.path / keep).iterdir()):
            if verify(p) is None:
                kept += 1
                continue
            try:
                remove_path(p)
            except OSError as exc:
                raise os_error("clear", p, exc) from None
            removed += 1
        return kept, removed

    def clear(self, *, keep=(), keep_scans: bool = False) -> None:
        """Remove everything in the folder but its lock (and the folders named in ``keep``;
        ``keep_scans`` keeps ``scans``)."""
        keep = set(keep) | ({LAYOUT["scans"]} if keep_scans else set())
        for p in self.path.iterdir():
            if p.name == LOCK_FILE or p.name in keep:
                continue
            try:
                remove_path(p)
            except OSError as exc:
                raise os_error("clear", p, exc) from None

    # -- writers -------------------------------------------------------------
    def write_text(self, name: str, text: str) -> Path:
        """``<folder>/<name>`` written atomically; returns its path (``RunFolderError`` naming it on OSError)."""
        return self.write_bytes(name, text.encode("utf-8"))

    def write_bytes(self, name: str, data: bytes) -> Path:
        """``<folder>/<name>`` written atomically; returns its path (``RunFolderError`` naming it on OSError)."""
        path = self.path / name
        try:
            atomic_write_bytes(path, data)
        except OSError as exc:
            raise os_error("write", path, exc) from None
        return path

    def checkpoint(self, key: str) -> Path:
        """The checkpoint file of experiment ``key``."""
        return self.path / LAYOUT["scans"] / f"{key}.npz"


def _guard_write(path, fn) -> None:
    try:
        fn()
    except OSError as exc:
        raise os_error("write", path, exc) from None


def write_metrics(run_dir, metrics) -> None:
    """``metrics.parquet``/``metrics.csv`` without timing columns (:data:`TIMING_COLUMNS`: the same seed gives
    byte-identical files) and ``timings.csv`` with them (the machine's); each written atomically. The one writer of
    a run's metrics, synthetic (:func:`write_tables`) or real (:func:`bench.store.realrun.write_real_metrics`)."""
    run_dir = Path(run_dir)
    timing = [c for c in TIMING_COLUMNS if c in metrics.columns]
    timings = metrics[[*METRIC_KEYS, *timing]]
    write_table(run_dir, metrics.drop(columns=timing), LAYOUT["metrics_parquet"], LAYOUT["metrics_csv"])
    path = run_dir / LAYOUT["timings"]
    _guard_write(path, lambda: atomic_write_text(path, timings.to_csv(index=False)))


def write_tables(run_dir, metrics, samples) -> None:
    """:func:`write_metrics` and ``samples.csv``; each written atomically."""
    run_dir = Path(run_dir)
    write_metrics(run_dir, metrics)
    path = run_dir / LAYOUT["samples"]
    _guard_write(path, lambda: atomic_write_text(path, samples.to_csv(index=False)))


def write_summary(run_dir, summary: dict) -> None:
    """``summary.json`` (a :func:`bench.store.summary.build_summary` document), atomically."""
    from bench.store import summary as _summary

    _summary.write_summary(Path(run_dir) / LAYOUT["summary"], summary)


def write_figdata(run_dir, fig) -> None:
    """``figdata.npz`` (a :class:`bench.store.figdata.FigData`: the frame Fig. 7 shows), atomically."""
    from bench.store import figdata

    path = Path(run_dir) / LAYOUT["figdata"]
    _guard_write(path, lambda: figdata.write_figdata(path, fig))


def write_gallery(run_dir, frames) -> None:
    """``gallery.npz`` (:class:`bench.store.figdata.GalleryFrame` s: the failure gallery's frames), atomically."""
    from bench.store import figdata

    path = Path(run_dir) / LAYOUT["gallery"]
    _guard_write(path, lambda: figdata.write_gallery(path, frames))


# -- readers -------------------------------------------------------------------
def load_summary(run_dir) -> dict:
    """``summary.json`` of a finished run (synthetic or real), checked.

    Raises
    ------
    RunFolderError
        No summary (not a finished run), unreadable, not JSON, of another format, or missing a key.
    """
    if not Path(run_dir).is_dir():
        raise RunFolderError(f"RUN must be a finished run folder, got {str(run_dir)!r} (not a folder)")
    path = Path(run_dir) / LAYOUT["summary"]
    if not path.exists():
        raise RunFolderError(f"RUN must be a finished run folder (with summary.json), got {str(run_dir)!r}")
    return read_summary(path, kind=("run", "real", "score"))


def metrics_sha256(run_dir, summary: dict) -> str:
    """The sha256 of a run's ``metrics.csv``, checked against the one its summary recorded (runs that
    recorded none: unchecked). A run's committed copy (``results/paper/``) needs only ``summary.json``
    and ``metrics.csv``.

    Raises
    ------
    RunFolderError
        ``metrics.csv`` missing or unreadable, or not the file the summary was written with.
    """
    from bench.store.files import file_sha256

    path = Path(run_dir) / LAYOUT["metrics_csv"]
    kind = non_file_kind(path)
    if kind is not None or not path.exists():
        raise RunFolderError(f"RUN must hold the run's {LAYOUT['metrics_csv']}, got {str(path)!r} "
                             f"({kind or 'missing'})")
    try:
        digest = file_sha256(path)
    except OSError as exc:
        raise os_error("read", path, exc) from None
    recorded = summary.get("metrics_sha256")
    if isinstance(recorded, str) and recorded != digest:
        raise RunFolderError(f"{str(path)!r} is not the metrics file of this run's summary (sha256 {digest[:12]}, "
                             f"the summary recorded {recorded[:12]}): copy both files from one run")
    return digest


def load_metrics(run_dir, *, timings: bool = False):
    """``metrics.parquet`` checked (one row per experiment x tracker x region,
    finite or NaN numbers); with ``timings`` the columns of ``timings.csv`` joined in.

    Raises
    ------
    RunFolderError
        Missing, unreadable or not a metrics table.
    """
    import numpy as np
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
        if tpath.is_file():
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
        ``summary`` (dict), ``figdata`` (:class:`bench.store.figdata.FigData`, or None when
        missing or unusable), ``gallery`` (list of :class:`bench.store.figdata.GalleryFrame`, or None)
        and ``scans`` (experiment key -> :class:`bench.store.checkpoint.ScanResult`; unusable ones left out).

    Raises
    ------
    RunFolderError
        Not a finished run, or its summary, metrics or samples are unreadable.
    """
    import pandas as pd

    from bench.store.checkpoint import read_checkpoint
    from bench.store.figdata import read_figdata, read_gallery

    run_dir = Path(run_dir)
    summary = load_summary(run_dir)
    metrics = load_metrics(run_dir, timings=True)
    spath = run_dir / LAYOUT["samples"]
    try:
        samples = pd.read_csv(spath)
    except Exception as exc:
        raise RunFolderError(f"cannot read {str(spath)!r}: {type(exc).__name__}; rerun the run to rewrite it") from None
    fd, why = read_figdata(run_dir / LAYOUT["figdata"])
    if why and say is not None:
        say(f"stripebench: {run_dir / LAYOUT['figdata']} is unusable ({why}): Fig. 7 is left out; "
            "rerun the run to rewrite it")
    gallery, why = read_gallery(run_dir / LAYOUT["gallery"])
    if why and say is not None:
        say(f"stripebench: {run_dir / LAYOUT['gallery']} is unusable ({why}): the failure gallery is left out; "
            "rerun the run to rewrite it")
    scans = {}
    folder = run_dir / LAYOUT["scans"]
    for p in sorted(folder.glob("*.npz")) if folder.is_dir() else []:
        res, why = read_checkpoint(p, p.stem)
        if res is None:
            if say is not None:
                say(f"stripebench: checkpoint {p} is {why}: left out")
            continue
        scans[p.stem] = res
    return {"metrics": metrics, "samples": samples, "summary": summary, "figdata": fd, "gallery": gallery,
            "scans": scans}
