"""Real photographs: image readers, the real-set layout and its validator.

File readers only: per-image metrics and the sim-to-real numbers are in
:mod:`bench.evaluate.simreal`, running in :mod:`bench.run.real`, the HTML in
:mod:`bench.report.simreal`.

A real set is a folder::

    manifest.csv      columns name, has_background (0/1), laser_colour, and optionally
                      rotate, channel, rig (the camera-and-laser set-up that took it: figures
                      are grouped and held out by it), condition (the class of photograph, free text; a run's
                      experiments with that `condition` are its synthetic match), source_repo,
                      source_commit, source_path, license, notes;
                      any other column is ignored (:func:`ignored_columns`)
    NAME.png          the laser-on photograph
    NAME_off.png      optional laser-off frame of the same view (has_background = 1)
    NAME_ref.csv      header ``row,col[,state]``: one line per row of the tracker's frame
                      (NAME.png turned by ``rotate``), ``col`` in px, empty where
                      there is no reference; ``state`` stripe, none or unknown
                      (:func:`read_reference_states`; without it, the fallback rule)

Coordinates follow the trackers: row 0 at the top, an integer column is the
centre of that pixel.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from bench.errors import StripebenchError
from bench.store.textfiles import loads_csv, read_text
# the pixel operations have their home in bench.evaluate.pixels; re-exported here for the readers' callers
from bench.evaluate.pixels import (CHANNELS, LASERS, ROTATIONS, rotate_image, select_channel,  # noqa: F401
                                   unrotate_points)
from bench.evaluate.outcomes import GAP_ROWS, NO_STRIPE, STATES, fallback_states

__all__ = ["SHIPPED", "CHANNELS", "LASERS", "ROTATIONS", "IMAGE_SUFFIXES", "ImageError", "DatasetError", "read_image",
           "select_channel", "rotate_image", "unrotate_points", "background_for", "load_frame", "RealImage",
           "load_dataset", "ignored_columns", "validate_dataset", "read_reference", "read_reference_states",
           "synthetic_hit_rates", "exif_orientation", "orientation_note", "reference_gives_states",
           "REFERENCE_HEADERS"]

#: The real set shipped with stripebench (its photographs and their rigs are listed in docs/real.md).
SHIPPED = Path(__file__).resolve().parents[1] / "data" / "real"
IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp")
MANIFEST_REQUIRED = ("name", "has_background", "laser_colour")
MANIFEST_OPTIONAL = ("rotate", "channel", "rig", "condition", "source_repo", "source_commit", "source_path", "license", "notes")


class ImageError(StripebenchError, ValueError):
    """A file that cannot be read as a photograph; ``str(err)`` is one line."""


class DatasetError(StripebenchError, ValueError):
    """A real set that breaks the layout; ``problems`` holds one line per problem."""

    def __init__(self, problems: list[str]):
        self.problems = list(problems)
        super().__init__(self.problems[0] if len(self.problems) == 1 else
                         f"{len(self.problems)} problems: " + "; ".join(self.problems))


#: The most pixels an image may have (134 M; Pillow's own guard warns from 89 M and refuses from 179 M);
#: larger files are refused in one line.
MAX_PIXELS = 2**27


def read_image(path) -> np.ndarray:
    """Read a PNG, JPEG, TIFF or BMP file (8 or 16 bit, grey or colour; 16-bit colour as TIFF).

    PNG, JPEG and BMP (a machine-vision camera's or MATLAB's frames) are read with Pillow, TIFF with tifffile
    (through imageio).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    ndarray, shape (H, W) or (H, W, 3)
        ``uint8`` or ``uint16`` (or float for float TIFFs) as stored; an alpha
        channel is dropped; a CMYK or palette image is converted to RGB. JPEG EXIF
        orientation is not applied.

    Raises
    ------
    ImageError
        Missing, unreadable, not an image, not 2-D / 3-channel, a 16-bit colour PNG or a
        multi-page TIFF (one line each).
    """
    import imageio.v3 as iio

    p = Path(path)
    if p.suffix.lower() not in IMAGE_SUFFIXES:
        raise ImageError(f"{str(p)!r}: not a PNG, JPEG, TIFF or BMP file (suffix {p.suffix!r})")
    if not p.is_file():
        raise ImageError(f"{str(p)!r}: no such file")
    try:
        data = p.read_bytes()
    except OSError as exc:
        raise ImageError(f"{str(p)!r}: cannot read file ({exc.strerror})") from None
    problem = _refused_layout(data, p.suffix.lower())
    if problem:
        raise ImageError(f"{str(p)!r}: {problem}")
    try:  # from bytes: imageio's plugin search leaves no open file behind on a bad file
        plugin = "tifffile" if p.suffix.lower() in (".tif", ".tiff") else "pillow"
        if plugin == "pillow":
            img = _read_pillow(data)
        else:
            img = np.asarray(iio.imread(data, plugin=plugin, extension=p.suffix.lower()))
    except Exception as exc:  # imageio raises many types for a bad file
        msg = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise ImageError(f"{str(p)!r}: cannot read image ({msg})") from None
    if img.ndim == 3 and img.shape[2] in (2, 4):  # grey+alpha, RGBA
        img = img[..., :1][..., 0] if img.shape[2] == 2 else img[..., :3]
    if img.ndim == 3 and img.shape[2] == 1:
        img = img[..., 0]
    if img.ndim not in (2, 3) or (img.ndim == 3 and img.shape[2] != 3) or img.size == 0:
        raise ImageError(f"{str(p)!r}: expected a grey or RGB image, got shape {img.shape}")
    if img.dtype.kind not in "uif":
        raise ImageError(f"{str(p)!r}: unsupported pixel type {img.dtype}")
    if img.size > 3 * MAX_PIXELS:
        raise ImageError(f"{str(p)!r}: {img.shape[1]}x{img.shape[0]} pixels, more than the {MAX_PIXELS:,} read")
    if img.dtype.kind == "f" and not np.isfinite(img).all():
        bad = int(np.count_nonzero(~np.isfinite(img)))
        raise ImageError(f"{str(p)!r}: {bad} NaN or infinite pixel value(s); a frame must be finite")
    return img


def _refused_layout(data: bytes, suffix: str) -> str | None:
    """Why a file's layout cannot be read faithfully, or None: a 16-bit colour PNG (Pillow reads
    it wrongly) or a multi-page TIFF (which page would be the frame?)."""
    if suffix == ".png" and data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) >= 26 and data[12:16] == b"IHDR":
        depth, colour_type = data[24], data[25]
        if depth == 16 and colour_type in (2, 6):
            return ("a 16-bit colour PNG is not supported (it would be read wrongly); save it as a 16-bit TIFF "
                    "or an 8-bit PNG")
    if suffix in (".tif", ".tiff"):
        import io

        import tifffile

        try:
            with tifffile.TiffFile(io.BytesIO(data)) as tf:
                n = len(tf.pages)
        except Exception:  # not a TIFF: the reader says so below
            return None
        if n > 1:
            return f"a multi-page TIFF ({n} pages); give one frame per file"
    return None


def _read_pillow(data: bytes) -> np.ndarray:
    """A PNG, JPEG or BMP through Pillow, CMYK (and other colour spaces) converted to RGB, palettes expanded."""
    import io

    from PIL import Image

    with warnings.catch_warnings():  # the size is bounded by MAX_PIXELS below, with its own one-line message
        warnings.simplefilter("ignore", Image.DecompressionBombWarning)
        im = Image.open(io.BytesIO(data))
    with im:
        if im.width * im.height > MAX_PIXELS:
            raise ValueError(f"{im.width}x{im.height} pixels, more than the {MAX_PIXELS:,} read")
        if im.mode in ("CMYK", "YCbCr", "LAB", "HSV", "P", "PA", "1"):
            im = im.convert("RGBA" if im.mode == "PA" or (im.mode == "P" and "transparency" in im.info) else "RGB")
        return np.asarray(im)


#: EXIF orientation -> the ``rotate_deg`` (:func:`rotate_image`, counter-clockwise) that shows the stored pixels
#: upright; orientations 2, 4, 5 and 7 also mirror the image, which no ``rotate_deg`` does.
EXIF_ROTATE = {1: 0, 3: 180, 6: 270, 8: 90}


def exif_orientation(path) -> int:
    """The EXIF orientation tag (1-8) of an image file, 1 (as stored) when it has none or cannot be read.

    :func:`read_image` never applies it: a frame is its file's pixels as stored, as a reference file's rows are.
    A phone's JPEG often asks to be shown turned (6: a quarter turn clockwise), so the stripe a user sees running
    down the photograph may run across the stored pixels (:func:`orientation_note`).

    Examples
    --------
    >>> import tempfile
    >>> from PIL import Image
    >>> exif = Image.Exif(); exif[0x0112] = 6
    >>> with tempfile.TemporaryDirectory() as d:
    ...     Image.new("RGB", (4, 2)).save(f"{d}/a.jpg", exif=exif)
    ...     Image.new("RGB", (4, 2)).save(f"{d}/b.jpg")
    ...     exif_orientation(f"{d}/a.jpg"), exif_orientation(f"{d}/b.jpg"), exif_orientation(f"{d}/none.jpg")
    (6, 1, 1)
    """
    from PIL import Image

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with Image.open(path) as im:
                value = im.getexif().get(0x0112, 1)
    except Exception:  # unreadable files are read_image's to name
        return 1
    return int(value) if isinstance(value, int) and 1 <= value <= 8 else 1


def orientation_note(path, rotate_deg: int = 0) -> str | None:
    """One line saying that ``path`` asks (EXIF) to be shown otherwise than its stored pixels, which are what the
    trackers see (turned by ``rotate_deg``), or None when it does not or when ``rotate_deg`` already shows it
    upright.

    Examples
    --------
    A phone's portrait photograph, stored sideways (orientation 6: shown a quarter turn clockwise), read as stored
    and then with the turn that shows it upright:

    >>> import tempfile
    >>> from PIL import Image
    >>> tmp = tempfile.TemporaryDirectory(); path = Path(tmp.name) / "a.jpg"
    >>> tags = Image.Exif(); tags[0x0112] = 6
    >>> Image.new("L", (4, 2)).save(path, exif=tags)
    >>> for turn in (0, 270):
    ...     print(orientation_note(path, turn))
    a.jpg: EXIF orientation 6 (shown turned); the trackers see the pixels as stored: if the stripe runs across them, give `--rotate 270`
    None
    >>> tmp.cleanup()
    """
    value = exif_orientation(path)
    turn = EXIF_ROTATE.get(value)
    if value == 1 or turn == rotate_deg:
        return None
    how = f"give `--rotate {turn}`" if turn is not None else "mirror the file as it is shown (no `--rotate` mirrors)"
    return (f"{Path(path).name}: EXIF orientation {value} (shown {'turned' if turn is not None else 'mirrored'}); the "
            f"trackers see the pixels as stored: if the stripe runs across them, {how}")


def background_for(path) -> Path | None:
    """The laser-off frame paired with ``path`` by name: ``NAME_off.EXT`` beside
    ``NAME.EXT`` (the same suffix, or any other image suffix), or None."""
    p = Path(path)
    for suffix in (p.suffix,) + tuple(s for s in IMAGE_SUFFIXES if s != p.suffix.lower()):
        cand = p.with_name(f"{p.stem}_off{suffix}")
        if cand.is_file():
            return cand
    return None


def load_frame(path, *, channel: str = "auto", laser: str = "red", rotate_deg: int = 0, downscale: int = 1):
    """Read a photograph as the 2-D frame a tracker sees, plus its original.

    ``downscale`` N > 1 first averages each N x N block of the file's pixels into one
    (:func:`bench.evaluate.pixels.downscale`, as the shipped set's photographs were shrunk).

    Returns
    -------
    frame : ndarray, shape (H', W')
        :func:`select_channel` then :func:`rotate_image`.
    original : ndarray, shape (H, W) or (H, W, 3)
        The file's pixels as read (shrunk with ``downscale``).
    """
    from bench.evaluate.pixels import downscale as shrink

    original = shrink(read_image(path), downscale)
    return rotate_image(select_channel(original, channel, laser), rotate_deg), original


# ---------------------------------------------------------------------------------------------------- the real set


@dataclass(frozen=True)
class RealImage:
    """One photograph of a real set (a manifest row, checked)."""

    name: str
    image_path: Path
    background_path: Path | None
    reference_path: Path
    laser_colour: str
    rotate_deg: int = 0
    channel: str = "auto"
    meta: dict = field(default_factory=dict)

    def load(self):
        """``(frame, background frame or None, original, reference columns)``;
        the frames as the trackers see them, the reference per row of the frame."""
        frame, original = load_frame(self.image_path, channel=self.channel, laser=self.laser_colour,
                                     rotate_deg=self.rotate_deg)
        bg = None
        if self.background_path is not None:
            bg, _ = load_frame(self.background_path, channel=self.channel, laser=self.laser_colour,
                               rotate_deg=self.rotate_deg)
        ref = read_reference(self.reference_path, frame.shape)
        return frame, bg, original, ref

    @property
    def rig(self) -> str:
        """The rig that took the photograph: the manifest's ``rig``, else its ``source_repo``, else the
        photograph's own name (a set that names no rig holds one rig per photograph)."""
        return self.meta.get("rig") or self.meta.get("source_repo") or self.name

    def reference(self, shape, gap_rows: int = GAP_ROWS) -> tuple[np.ndarray, np.ndarray]:
        """The reference's columns and row states for the tracker frame's ``shape``
        (:func:`read_reference_states`)."""
        cols, states, _ = read_reference_states(self.reference_path, shape, gap_rows)
        return cols, states


def read_reference(path, shape) -> np.ndarray:
    """The reference columns of ``NAME_ref.csv`` for a frame of ``shape`` (H, W):
    :func:`read_reference_states` without the states.

    Returns
    -------
    ndarray of float64, shape (H,)
        NaN where there is no reference.
    """
    return read_reference_states(path, shape)[0]


def reference_gives_states(path) -> bool:
    """Whether a ``NAME_ref.csv`` gives its rows' states (its header is ``row,col,state``), read from its first line
    alone: the convention a prediction for its photograph follows (``bench.run.predict_frames.Photo.fallback_rows``), not
    its labels. A file without it is read with the fallback rule (:func:`read_reference_states`).

    Raises
    ------
    DatasetError
        The file cannot be read, or its header is neither ``row,col`` nor ``row,col,state``.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     _ = Path(d, "a_ref.csv").write_text("row,col,state\\n0,3.0,stripe\\n")
    ...     _ = Path(d, "b_ref.csv").write_text("row,col\\n0,3.0\\n")
    ...     reference_gives_states(Path(d, "a_ref.csv")), reference_gives_states(Path(d, "b_ref.csv"))
    (True, False)
    """
    p = Path(path)
    try:
        with p.open(encoding="utf-8", newline="") as fh:
            first = fh.readline()
    except OSError as exc:
        raise DatasetError([f"{p.name}: cannot read reference ({exc.strerror})"]) from None
    except UnicodeDecodeError as exc:
        raise DatasetError([f"{p.name}: not UTF-8 text (byte {exc.start})"]) from None
    return _reference_header(first.lstrip("\ufeff").strip().split(","), p.name)


#: The headers a ``NAME_ref.csv`` may have: columns only (its rows' states by the fallback rule), or with states.
REFERENCE_HEADERS = (("row", "col"), ("row", "col", "state"))


def _reference_header(cells, name: str) -> bool:
    """Whether a reference's header ``cells`` (its first line's fields) give row states; ``DatasetError`` naming
    the file ``name`` for any header but :data:`REFERENCE_HEADERS`. The one home of the rule, read whole
    (:func:`read_reference_states`) or from the first line alone (:func:`reference_gives_states`)."""
    header = tuple(h.strip() for h in cells)
    if header not in REFERENCE_HEADERS:
        raise DatasetError([f"{name}: header must be 'row,col' or 'row,col,state', got {','.join(cells)!r}"])
    return len(header) == 3


def read_reference_states(path, shape, gap_rows: int = GAP_ROWS) -> tuple[np.ndarray, np.ndarray, bool]:
    """The reference of ``NAME_ref.csv`` for a frame of ``shape`` (H, W): columns and row states.

    The file has the header ``row,col`` or ``row,col,state`` and one line per row
    ``0 .. H-1`` in order; ``col`` is a number in ``[-0.5, W - 0.5]`` or empty. ``state``
    is ``stripe`` (``col`` given), ``none`` (the row has no stripe: a report there is a
    false one) or ``unknown`` (ambiguous, or occluded and unsure: not scored); ``none``
    and ``unknown`` rows leave ``col`` empty. A file without the ``state`` column is read
    with the fallback rule (:func:`bench.evaluate.outcomes.fallback_states`: a row without
    a column at least ``gap_rows`` rows from every row with one has no stripe, any
    other such row is unknown).

    Returns
    -------
    columns : ndarray of float64, shape (H,)
        NaN where there is no reference.
    states : ndarray of int8, shape (H,)
        :data:`bench.evaluate.outcomes.STRIPE`, ``NO_STRIPE`` or ``UNSURE`` per row.
    explicit : bool
        Whether the file gives the states (else they are the fallback's).

    Raises
    ------
    DatasetError
        One problem (the first) naming the file, the line and the value.
    """
    p = Path(path)
    H, W = int(shape[0]), int(shape[1])
    try:
        text = read_text(p, "reference", error=ValueError)  # a regular file only (never waits on a FIFO), bounded
    except ValueError as exc:
        raise DatasetError([f"{p.name}: {_why(exc, p)}"]) from None
    rows = loads_csv(text, p.name, error=lambda m: DatasetError([m]), header=False)
    explicit = _reference_header(rows[0] if rows else [], p.name)
    header = REFERENCE_HEADERS[explicit]
    body = [r for r in rows[1:] if r]
    if len(body) != H:
        raise DatasetError([f"{p.name}: {len(body)} rows for an image of height {H} (one line per row expected)"])
    out = np.full(H, np.nan)
    states = np.full(H, NO_STRIPE, dtype=np.int8)
    for i, r in enumerate(body):
        line = i + 2
        if len(r) != len(header):
            raise DatasetError([f"{p.name} line {line}: expected {len(header)} fields, got {r!r}"])
        try:
            row = int(r[0])
        except ValueError:
            raise DatasetError([f"{p.name} line {line}: row must be an integer, got {r[0]!r}"]) from None
        if row != i:
            raise DatasetError([f"{p.name} line {line}: rows must run 0..{H - 1} in order, got {row}"])
        if explicit:
            st = r[2].strip()
            if st not in STATES:
                raise DatasetError([f"{p.name} line {line}: state must be one of {', '.join(STATES)}, got {r[2]!r}"])
            states[i] = STATES[st]
            if (st == "stripe") != (r[1].strip() != ""):
                raise DatasetError([f"{p.name} line {line}: a {st!r} row must {'' if st == 'stripe' else 'not '}"
                                    f"have a col, got {r[1]!r}"])
        if r[1].strip() == "":
            continue
        try:
            col = float(r[1])
        except ValueError:
            raise DatasetError([f"{p.name} line {line}: col must be a number or empty, got {r[1]!r}"]) from None
        if not math.isfinite(col) or not -0.5 <= col <= W - 0.5:
            raise DatasetError([f"{p.name} line {line}: col must lie in [-0.5, {W - 0.5}], got {r[1]!r}"])
        out[i] = col
    if not explicit:
        states = fallback_states(out, gap_rows)
    return out, states, explicit


def _why(exc: Exception, path: Path) -> str:
    """:func:`bench.store.textfiles.read_text`'s message without the path (the callers name the file)."""
    return str(exc).replace(f" {str(path)!r}", "")


def _manifest(root: Path) -> tuple[list[dict], list[str]]:
    path = root / "manifest.csv"
    if not path.is_file():
        return [], [f"{str(root)!r}: no manifest.csv (not a real set)"]
    try:
        text = read_text(path, "manifest", error=ValueError)
    except ValueError as exc:
        return [], [f"manifest.csv: {_why(exc, path)}"]
    try:
        cols, rows = loads_csv(text, "manifest.csv", error=ValueError)
    except ValueError as exc:
        return [], [str(exc)]
    missing = [c for c in MANIFEST_REQUIRED if c not in cols]
    if missing:
        return [], [f"manifest.csv: missing column(s) {', '.join(missing)} (have {', '.join(cols) or 'none'})"]
    if not rows:
        return [], ["manifest.csv: no images listed"]
    return rows, []


def _check_row(root: Path, line: int, row: dict) -> tuple[RealImage | None, list[str]]:
    probs = []
    name = (row.get("name") or "").strip()
    where = f"manifest.csv line {line}"
    if not name or any(ch in name for ch in "/\\") or name.endswith("_off") or name.endswith("_ref"):
        return None, [f"{where}: bad name {name!r}"]
    hb = (row.get("has_background") or "").strip()
    if hb not in ("0", "1"):
        probs.append(f"{where} ({name}): has_background must be 0 or 1, got {hb!r}")
    laser = (row.get("laser_colour") or "").strip()
    if laser not in LASERS:
        probs.append(f"{where} ({name}): laser_colour must be one of {', '.join(LASERS)}, got {laser!r}")
    rot_s = (row.get("rotate") or "0").strip() or "0"
    rot = int(rot_s) if rot_s in {str(r) for r in ROTATIONS} else None  # ASCII only: '²'.isdigit() but int('²') fails
    if rot not in ROTATIONS:
        probs.append(f"{where} ({name}): rotate must be one of 0, 90, 180, 270, got {rot_s!r}")
    channel = (row.get("channel") or "auto").strip() or "auto"
    if channel not in CHANNELS:
        probs.append(f"{where} ({name}): channel must be one of {', '.join(CHANNELS)}, got {channel!r}")
    img = root / f"{name}.png"
    off = root / f"{name}_off.png"
    ref = root / f"{name}_ref.csv"
    if not img.is_file():
        probs.append(f"{name}: missing image {img.name}")
    if hb == "1" and not off.is_file():
        probs.append(f"{name}: has_background is 1 but {off.name} is missing")
    if hb == "0" and off.is_file():
        probs.append(f"{name}: {off.name} exists but has_background is 0")
    if not ref.is_file():
        probs.append(f"{name}: missing reference {ref.name}")
    if probs:
        return None, probs
    meta = {k: (row.get(k) or "").strip() for k in MANIFEST_OPTIONAL if k not in ("rotate", "channel")}
    return RealImage(name, img, off if hb == "1" else None, ref, laser, rot, channel, meta), []


def ignored_columns(root) -> list[str]:
    """The columns of ``root/manifest.csv`` that the layout does not use (in
    file order; empty if the manifest is missing or unreadable). They are
    accepted and ignored; ``stripebench real`` lists them once on stderr.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp()); _ = (d / "manifest.csv").write_text("name,surface,has_background,laser_colour,rows\\n")
    >>> ignored_columns(d)
    ['surface', 'rows']
    """
    path = Path(root) / "manifest.csv"
    try:
        header = loads_csv(read_text(path, "manifest", error=ValueError), "manifest.csv", error=ValueError)[0]
    except ValueError:
        return []
    return [c for c in header if c not in MANIFEST_REQUIRED + MANIFEST_OPTIONAL]


def validate_dataset(root) -> tuple[list[RealImage], list[str]]:
    """Check a real set: manifest, files, image shapes and references.

    Returns
    -------
    images : list of RealImage
        The images that passed every check.
    problems : list of str
        One line per problem (empty when the set is valid).
    """
    root = Path(root)
    rows, probs = _manifest(root)
    images, seen = [], set()
    for i, row in enumerate(rows):
        name = (row.get("name") or "").strip()
        if name in seen:
            probs.append(f"manifest.csv line {i + 2}: name {name!r} listed twice")
            continue
        seen.add(name)
        entry, p = _check_row(root, i + 2, row)
        if p:
            probs += p
            continue
        try:
            img = read_image(entry.image_path)
            shape = rotate_image(img[..., 0] if img.ndim == 3 else img, entry.rotate_deg).shape
            if entry.background_path is not None:
                off = read_image(entry.background_path)
                if off.shape != img.shape:
                    probs.append(f"{entry.name}: {entry.background_path.name} has shape {off.shape}, "
                                 f"{entry.image_path.name} has {img.shape}")
                    continue
            read_reference(entry.reference_path, shape)
        except ImageError as exc:
            probs.append(f"{entry.name}: {exc}")
            continue
        except DatasetError as exc:
            probs += exc.problems
            continue
        images.append(entry)
    return images, probs


def load_dataset(root) -> list[RealImage]:
    """The images of a valid real set.

    Raises
    ------
    DatasetError
        With every problem :func:`validate_dataset` finds.
    """
    images, probs = validate_dataset(root)
    if probs:
        raise DatasetError(probs)
    return images


# ---------------------------------------------------------------------------------------------------- sim-to-real


def synthetic_hit_rates(run_dir, region: str = "object") -> dict[str, float]:
    """label -> mean ``hit_rate`` over the experiments of a synthetic run
    (``metrics.parquet``, rows of ``region``)."""
    import pandas as pd

    m = pd.read_parquet(Path(run_dir) / "metrics.parquet")
    if "hit_rate" not in m.columns:
        raise ValueError(f"{str(run_dir)!r}: metrics.parquet has no hit_rate column (an older run?)")
    m = m[m["region"] == region]
    return {str(k): float(v) for k, v in m.groupby("tracker")["hit_rate"].mean().items()}
