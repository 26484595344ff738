"""Exported frame sets and the submissions scored against them: the files, their writers, readers and validators.

A frame set (``stripebench export``, :mod:`bench.run.export`) is a folder any
program can read, whatever its language::

    dataset.json        format, profile, configuration (and its hash), code revision, seed, the split's
                        rule, units, per experiment its rig (cm, mm, deg), Mitsuba variant, frame count
    frames.csv          frame,image,background,experiment,condition,split,angle_deg,height,width
    images/FRAME.png    the laser-on frame, 8-bit grey: the very uint8 array a tracker gets in a run
    images/FRAME_off.png  the laser-off frame (likewise)
    truth/FRAME.csv     per-row truth of the ``dev`` frames
    truth_test/FRAME.csv  per-row truth of the ``test`` frames (withhold this folder when publishing)
    run.json, config.json  the run folder's identity (kind ``export``)

A truth file has one line per row with a true stripe or a false stripe:
``row,col,part,x_cm,y_cm,z_cm,false_cols``: ``col`` the true stripe's continuous
column (px, pixel centres at integers; empty where the row has none), ``part``
what it lies on (``background``, ``object``, ``support``; empty where none),
``x_cm,y_cm,z_cm`` the true world point, ``false_cols`` the columns of the
false (mirrored) stripes on that row separated by ``;`` (empty where none; the
column is all empty for scenes without false stripes). Numbers are written
with Python's ``repr`` (17 significant digits): they read back exactly.

A submission (scored by :mod:`bench.run.score`) is a folder with
``submission.csv`` (``frame,row,col[,score]``: one line per reported row; a row
absent or with an empty ``col`` is no detection) and optionally ``times.csv``
(``frame,ms``: the program's time per frame). :func:`read_submission` reports
every problem, one line each.
"""

from __future__ import annotations

import csv
import hashlib
import io
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from bench.errors import quoted
from bench.store.files import RunFolderError, atomic_write_bytes, atomic_write_text, check_format
from bench.store.textfiles import loads_csv, read_json, read_text

__all__ = ["FORMAT", "SPLITS", "FRAME_COLUMNS", "TRUTH_COLUMNS", "SUBMISSION_COLUMNS", "TIMES_COLUMNS",
           "FrameSetError", "FrameSet", "Submission", "frame_id", "split_of", "png_bytes", "truth_csv",
           "write_frames_csv", "write_dataset_json", "read_frameset", "read_truth", "read_png", "read_submission",
           "submission_csv"]

FORMAT = 1
SPLITS = ("dev", "test")
FRAME_COLUMNS = ("frame", "image", "background", "experiment", "condition", "split", "angle_deg", "height", "width")
TRUTH_COLUMNS = ("row", "col", "part", "x_cm", "y_cm", "z_cm", "false_cols")
SUBMISSION_COLUMNS = ("frame", "row", "col")  # and an optional "score"
TIMES_COLUMNS = ("frame", "ms")
TRUTH_DIRS = {"dev": "truth", "test": "truth_test"}
MAX_PROBLEMS = 200  # lines of a submission's report before "... and N more"


class FrameSetError(RunFolderError):
    """A frame set that cannot be read; ``str(err)`` is one line naming the file."""


def frame_id(experiment: str, index: int) -> str:
    """The stable id of frame ``index`` of an experiment.

    >>> frame_id("cone-patchy", 7)
    'cone-patchy-007'
    """
    return f"{experiment}-{int(index):03d}"


def split_of(frame: str, seed: int, test_fraction: float) -> str:
    """``"test"`` or ``"dev"`` for one frame: seeded and stable.

    The frame's number ``u`` in [0, 1) is the first 8 bytes of
    ``sha256(f"{seed}:{frame}")``; it is a test frame when ``u < test_fraction``.
    A frame's split depends only on its id and the seed, never on the other
    frames of the set.

    >>> split_of("cone-patchy-000", 0, 0.0), split_of("cone-patchy-000", 0, 1.0)
    ('dev', 'test')
    """
    if not (isinstance(test_fraction, (int, float)) and 0.0 <= test_fraction <= 1.0):
        raise ValueError(f"`test_fraction` must be a number in [0, 1], got {test_fraction!r}")
    h = hashlib.sha256(f"{int(seed)}:{frame}".encode()).digest()
    u = int.from_bytes(h[:8], "big") / 2.0**64
    return "test" if u < test_fraction else "dev"


def png_bytes(image: np.ndarray) -> bytes:
    """An 8-bit grey PNG of ``image`` (H, W) uint8, byte-stable for the same pixels.

    Raises
    ------
    ValueError
        ``image`` is not a 2-D uint8 array.
    """
    import imageio.v3 as iio

    image = np.asarray(image)
    if image.ndim != 2 or image.dtype != np.uint8:
        raise ValueError(f"`image` must be an (H, W) uint8 array, got {image.dtype} {image.shape}")
    return iio.imwrite("<bytes>", image, extension=".png")


def read_png(path, shape=None) -> np.ndarray:
    """An exported frame: (H, W) uint8.

    Parameters
    ----------
    path : path-like
    shape : (int, int) or None
        The frame's size as ``frames.csv`` gives it (rows, columns); None: any.

    Raises
    ------
    FrameSetError
        Missing, unreadable, not 8-bit grey or not of ``shape`` (naming the file).
    """
    import imageio.v3 as iio

    path = Path(path)
    try:
        img = iio.imread(path.read_bytes(), extension=".png")
    except OSError as exc:
        raise FrameSetError(f"cannot read frame {str(path)!r}: {exc.strerror or exc}") from None
    except Exception as exc:  # imageio raises many types for a bad file
        raise FrameSetError(f"frame {str(path)!r} is not a PNG ({type(exc).__name__})") from None
    if img.ndim != 2 or img.dtype != np.uint8:
        raise FrameSetError(f"frame {str(path)!r} must be 8-bit grey, got {img.dtype} {img.shape}")
    if shape is not None and img.shape != tuple(shape):
        raise FrameSetError(f"frame {str(path)!r} is {img.shape[0]}x{img.shape[1]} (rows x columns), but frames.csv "
                            f"says {shape[0]}x{shape[1]}")
    return img


def _num(v: float) -> str:
    return "" if not math.isfinite(v) else repr(float(v))


def truth_csv(columns, points_cm, part, false_columns=None) -> str:
    """The text of one truth file (see the module docstring).

    Parameters
    ----------
    columns : numpy.ndarray, shape (H,), px
        True columns, NaN where none.
    points_cm : numpy.ndarray, shape (H, 3), cm
    part : numpy.ndarray, shape (H,), int
        Index into :data:`scenes.frame.PARTS`, -1 where none.
    false_columns : numpy.ndarray, shape (H, K), px, or None
        False-stripe columns per row, NaN-padded; None when the scene computes none.

    Examples
    --------
    >>> print(truth_csv(np.array([np.nan, 2.5]), np.array([[np.nan] * 3, [1.0, 2.0, 3.0]]),
    ...                 np.array([-1, 1])), end="")
    row,col,part,x_cm,y_cm,z_cm,false_cols
    1,2.5,object,1.0,2.0,3.0,
    """
    from scenes import PARTS

    buf = io.StringIO()
    buf.write(",".join(TRUTH_COLUMNS) + "\n")
    for r in range(len(columns)):
        fc = [] if false_columns is None else [c for c in false_columns[r] if math.isfinite(c)]
        if not math.isfinite(columns[r]) and part[r] < 0 and not fc:
            continue
        p = PARTS[int(part[r])] if part[r] >= 0 else ""
        x, y, z = (_num(v) for v in points_cm[r])
        buf.write(f"{r},{_num(columns[r])},{p},{x},{y},{z},{';'.join(repr(float(c)) for c in fc)}\n")
    return buf.getvalue()


def write_frames_csv(path, rows: list[dict]) -> None:
    """``frames.csv`` (:data:`FRAME_COLUMNS`), atomically; an angle that is NaN (a test frame of a
    participants' bundle) is written empty."""
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=FRAME_COLUMNS, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: (_num(float(r[k])) if k == "angle_deg" else r[k]) for k in FRAME_COLUMNS})  # NaN: empty
    atomic_write_text(path, buf.getvalue())


def write_dataset_json(path, doc: dict) -> None:
    """``dataset.json``, atomically (keys in the order given)."""
    atomic_write_bytes(path, (json.dumps(doc, indent=1) + "\n").encode("utf-8"))


@dataclass
class FrameSet:
    """An exported frame set, read and checked (:func:`read_frameset`).

    Attributes
    ----------
    root : Path
    meta : dict
        ``dataset.json``.
    frames : list of dict
        ``frames.csv`` rows in file order (``angle_deg`` float, ``height``/``width`` int).
    """

    root: Path
    meta: dict
    frames: list[dict]
    index: dict = field(default_factory=dict)  # frame id -> its row

    def experiment(self, key: str) -> dict:
        """The ``dataset.json`` entry of experiment ``key``."""
        return next(e for e in self.meta["experiments"] if e["key"] == key)

    def frames_of(self, key: str) -> list[dict]:
        """The frames of experiment ``key`` in scan order."""
        return [f for f in self.frames if f["experiment"] == key]

    def truth_path(self, frame: dict) -> Path:
        return self.root / TRUTH_DIRS[frame["split"]] / f"{frame['frame']}.csv"


#: The largest frame side read from ``frames.csv`` (px).
MAX_SIDE = 65536
#: The keys of ``dataset.json`` and of each of its experiments that scoring reads.
META_KEYS = {"config": dict, "config_hash": str, "experiments": list}
EXPERIMENT_KEYS = {"key": str, "rig": dict, "variant": str, "false_stripes": bool}


def _csv_rows(path: Path, what: str = "") -> list:
    """The rows after the header of the CSV file ``path``; ``FrameSetError`` naming it (after ``what``,
    e.g. ``truth``) when it cannot be read, is not UTF-8 text or is malformed."""
    return loads_csv(read_text(path, what or "file", error=FrameSetError), str(path), error=FrameSetError)[1]


def _check_meta(meta: dict, jpath) -> None:
    """One line naming the first key of ``dataset.json`` that scoring needs and that is missing or mistyped."""
    def need(doc, keys, where):
        for k, kind in keys.items():
            if not isinstance(doc.get(k), kind):
                got = "missing" if k not in doc else f"got {type(doc[k]).__name__} {doc[k]!r:.40}"
                raise FrameSetError(f"{str(jpath)!r}: `{where}{k}` must be a {kind.__name__} ({got})")

    need(meta, META_KEYS, "")
    for i, e in enumerate(meta["experiments"]):
        if not isinstance(e, dict):
            raise FrameSetError(f"{str(jpath)!r}: `experiments[{i}]` must be an object")
        need(e, EXPERIMENT_KEYS, f"experiments[{i}].")


def read_frameset(root) -> FrameSet:
    """The frame set at ``root``, checked: its ``dataset.json`` and ``frames.csv``.

    Raises
    ------
    FrameSetError
        Not a frame set, another format, or a malformed ``frames.csv`` (one line naming the file).
    """
    root = Path(root)
    jpath = root / "dataset.json"
    if not jpath.is_file():
        raise FrameSetError(f"DATASET must be an exported frame set (with dataset.json), got {str(root)!r}")
    meta = read_json(jpath, "frame set description", error=FrameSetError)  # bounded: size, depth, integers
    if not isinstance(meta, dict) or meta.get("kind") != "stripebench-frames":
        raise FrameSetError(f"{str(jpath)!r} is not a stripebench frame set")
    check_format(meta.get("format"), (FORMAT,), "frame set", jpath)
    _check_meta(meta, jpath)
    fpath = root / "frames.csv"
    rows = _csv_rows(fpath)
    frames, index = [], {}
    keys = {e["key"] for e in meta["experiments"]}
    sizes = {}
    top = root.resolve()
    for n, r in enumerate(rows, start=2):
        missing = [c for c in FRAME_COLUMNS if r.get(c) is None]
        if missing:
            raise FrameSetError(f"{str(fpath)!r} line {n}: no column {missing[0]!r}")
        try:
            f = dict(r, angle_deg=float(r["angle_deg"] or "nan"), height=int(r["height"]), width=int(r["width"]))
        except ValueError:
            raise FrameSetError(f"{str(fpath)!r} line {n}: angle_deg, height or width is not a number") from None
        if not math.isfinite(f["angle_deg"]) and not (f["split"] == "test" and meta.get("test_truth") == "withheld"):
            raise FrameSetError(f"{str(fpath)!r} line {n}: angle_deg must be a finite number (only a test frame of a "
                                f"participants' bundle has none), got {r['angle_deg']!r:.40}")
        if f["split"] not in SPLITS or f["experiment"] not in keys or f["frame"] in index:
            raise FrameSetError(f"{str(fpath)!r} line {n}: bad split, unknown experiment or repeated frame "
                                f"{quoted(f['frame'])}")
        if not (1 <= f["height"] <= MAX_SIDE and 1 <= f["width"] <= MAX_SIDE):
            raise FrameSetError(f"{str(fpath)!r} line {n}: height and width must be 1..{MAX_SIDE}, got "
                                f"{f['height']}x{f['width']}")
        if sizes.setdefault(f["experiment"], (f["height"], f["width"])) != (f["height"], f["width"]):
            raise FrameSetError(f"{str(fpath)!r} line {n}: frame {quoted(f['frame'])} is {f['height']}x{f['width']}, but "
                                f"experiment {f['experiment']!r} is {'x'.join(map(str, sizes[f['experiment']]))}")
        for col in ("image", "background"):
            rel = Path(f[col])
            inside = not rel.is_absolute() and top in (top / rel).resolve().parents
            if not inside:
                raise FrameSetError(f"{str(fpath)!r} line {n}: {col} {quoted(f[col])} must be a path inside the frame set")
        index[f["frame"]] = f
        frames.append(f)
    return FrameSet(root, meta, frames, index)


def read_truth(path, height: int, k: int | None):
    """One truth file as arrays.

    Parameters
    ----------
    path : path-like
    height : int
        The frame's rows ``H``.
    k : int or None
        Width of the false-stripe array (None: the scene has no false stripes).

    Returns
    -------
    columns : (H,) px, points_cm : (H, 3) cm, on_object : (H,) bool, false_columns : (H, k) px or None
        NaN where the file has no value.

    Raises
    ------
    FrameSetError
        Missing or malformed (naming the file and line).
    """
    path = Path(path)
    cols = np.full(height, np.nan)
    pts = np.full((height, 3), np.nan)
    on = np.zeros(height, bool)
    false = None if k is None else np.full((height, k), np.nan)
    rows = _csv_rows(path, "truth")
    f = lambda s: float(s) if s else np.nan  # noqa: E731
    for n, r in enumerate(rows, start=2):
        try:
            v = int(r["row"])
            if not 0 <= v < height:
                raise ValueError
            cols[v] = f(r["col"])
            pts[v] = [f(r["x_cm"]), f(r["y_cm"]), f(r["z_cm"])]
            on[v] = r["part"] == "object"
            if false is not None and r["false_cols"]:
                fc = [float(c) for c in r["false_cols"].split(";")][:k]
                false[v, :len(fc)] = fc
        except (KeyError, TypeError, ValueError):
            raise FrameSetError(f"truth {str(path)!r} line {n} is malformed") from None
    return cols, pts, on, false


@dataclass
class Submission:
    """A submission read against a frame set (:func:`read_submission`).

    Attributes
    ----------
    columns, scores : dict frame id -> numpy.ndarray, shape (H,), px / score
        NaN where the submission reports nothing (every frame of the set has an entry).
    ms : dict frame id -> float
        ``times.csv`` (NaN for a frame it does not list, or without the file).
    checksum : str
        SHA-256 of ``submission.csv`` and ``times.csv`` (what was scored).
    """

    columns: dict
    scores: dict
    ms: dict
    checksum: str


def _finite(text: str):
    try:
        v = float(text)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def _csv_reader(path: Path, columns, expected: str, digest, tag: bytes = b""):
    """Open a submission's CSV file ``path``: its bytes go into ``digest`` (after ``tag``) and its header
    must hold ``columns`` (``expected`` spells the header in the message). Returns (header, reader
    of the lines after it, None), or (None, None, the problem: one line naming the file)."""
    try:
        data = read_text(path, path.name, error=ValueError).encode("utf-8")  # a regular file, bounded, UTF-8
    except ValueError as exc:
        return None, None, f"{path}: {str(exc).replace(f' {str(path)!r}', '')}"
    digest.update(tag + data)
    text = data.decode("utf-8")
    try:
        reader = iter(loads_csv(text, str(path), error=ValueError, header=False))
    except ValueError as exc:
        return None, None, str(exc)
    header = [h.strip() for h in next(reader, [])]
    missing = [c for c in columns if c not in header]
    if missing:
        return None, None, (f"{path} line 1: missing header column(s) {', '.join(missing)} "
                            f"(expected {expected}, got {quoted(','.join(header))})")
    return header, reader, None


def _csv_lines(path: Path, header: list, reader, problems: list):
    """The (``"<path> line <n>"``, fields) of each non-blank line of ``reader`` with as many fields as
    ``header``; a line with another count is a problem (appended to ``problems``) and skipped."""
    for n, line in enumerate(reader, start=2):
        if not line or all(not c.strip() for c in line):
            continue
        where = f"{path} line {n}"
        if len(line) != len(header):
            problems.append(f"{where}: {len(line)} fields, the header has {len(header)}")
            continue
        yield where, line


def read_submission(folder, frameset: FrameSet) -> tuple[Submission | None, list[str]]:
    """Read and validate a submission folder against ``frameset``.

    Returns
    -------
    (Submission, []) when it is valid; (None, problems) otherwise: one line per
    problem, naming the file and line: a missing file or header column, an
    unknown frame, a row that is not an integer in [0, H), a ``col`` or
    ``score`` that is not a finite number, a ``col`` outside the image
    (``< -0.5`` or ``> W - 0.5``, the rule of :func:`bench.run.track.track_frame`),
    a (frame, row) given twice; in ``times.csv`` an unknown or repeated frame or
    ``ms`` that is not a finite number >= 0.

    Examples
    --------
    See ``tests/bench/store/test_frameset.py``.
    """
    folder = Path(folder)
    problems: list[str] = []
    sub = folder / "submission.csv"
    if not folder.is_dir():
        return None, [f"SUBMISSION must be a folder with submission.csv, got {str(folder)!r}"]
    if not (sub.exists() or sub.is_symlink()):
        return None, [f"{sub}: missing (a submission folder holds submission.csv and optionally times.csv)"]
    digest = hashlib.sha256()
    header, reader, problem = _csv_reader(sub, SUBMISSION_COLUMNS, "frame,row,col[,score]", digest)
    if problem is not None:
        return None, [problem]
    cols = {f: np.full(r["height"], np.nan) for f, r in frameset.index.items()}
    scores = {f: np.full(r["height"], np.nan) for f, r in frameset.index.items()}
    at = {c: header.index(c) for c in header}
    seen = set()
    for where, line in _csv_lines(sub, header, reader, problems):
        fr, row_s, col_s = (line[at[c]].strip() for c in SUBMISSION_COLUMNS)
        meta = frameset.index.get(fr)
        if meta is None:
            problems.append(f"{where}: unknown frame {quoted(fr)}")
            continue
        try:
            row = int(row_s)
        except ValueError:
            problems.append(f"{where}: row {quoted(row_s)} is not an integer")
            continue
        if not 0 <= row < meta["height"]:
            problems.append(f"{where}: row {row} out of range [0, {meta['height']}) of frame {quoted(fr)}")
            continue
        if (fr, row) in seen:
            problems.append(f"{where}: duplicate row {row} of frame {quoted(fr)}")
            continue
        seen.add((fr, row))
        if col_s:
            c = _finite(col_s)
            if c is None:
                problems.append(f"{where}: col {quoted(col_s)} is not a finite number")
                continue
            if c < -0.5 or c > meta["width"] - 0.5:
                problems.append(f"{where}: col {c!r} outside the image (-0.5 to {meta['width'] - 0.5!r})")
                continue
            cols[fr][row] = c
        if "score" in at and line[at["score"]].strip():
            s = _finite(line[at["score"]].strip())
            if s is None:
                problems.append(f"{where}: score {quoted(line[at['score']].strip())} is not a finite number")
                continue
            scores[fr][row] = s
    ms = {f: float("nan") for f in frameset.index}
    tpath = folder / "times.csv"
    if (tpath.exists() or tpath.is_symlink()) and not tpath.is_file():
        problems.append(f"{tpath}: not a regular file (times.csv is optional; remove it or make it a CSV file)")
    elif tpath.is_file():
        th, treader, problem = _csv_reader(tpath, TIMES_COLUMNS, "frame,ms", digest, b"\0times\0")
        if problem is not None:
            problems.append(problem)
        else:
            tseen = set()
            for where, line in _csv_lines(tpath, th, treader, problems):
                fr, v = line[th.index("frame")].strip(), line[th.index("ms")].strip()
                if fr not in frameset.index:
                    problems.append(f"{where}: unknown frame {quoted(fr)}")
                elif fr in tseen:
                    problems.append(f"{where}: duplicate frame {quoted(fr)}")
                elif _finite(v) is None or float(v) < 0:
                    problems.append(f"{where}: ms {quoted(v)} is not a finite number >= 0")
                else:
                    tseen.add(fr)
                    ms[fr] = float(v)
    if problems:
        if len(problems) > MAX_PROBLEMS:
            problems = problems[:MAX_PROBLEMS] + [f"... and {len(problems) - MAX_PROBLEMS} more problem(s)"]
        return None, problems
    return Submission(cols, scores, ms, digest.hexdigest()), []


def submission_csv(columns: dict, scores: dict | None = None) -> str:
    """The text of a ``submission.csv`` from frame id -> (H,) columns (NaN rows left out).

    Examples
    --------
    >>> print(submission_csv({"a-000": np.array([np.nan, 3.25])}), end="")
    frame,row,col,score
    a-000,1,3.25,
    """
    buf = io.StringIO()
    buf.write("frame,row,col,score\n")
    for fr, c in columns.items():
        s = None if scores is None else scores.get(fr)
        for r in np.flatnonzero(np.isfinite(c)):
            sv = "" if s is None or not np.isfinite(s[r]) else repr(float(s[r]))
            buf.write(f"{fr},{int(r)},{float(c[r])!r},{sv}\n")
    return buf.getvalue()
