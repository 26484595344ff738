"""``learned``: a small network, trained on renders only, decides each row's stripe among its candidate peaks.

Per row, the ``K`` strongest local maxima of the lightly smoothed row (of the laser-on minus
laser-off difference when a laser-off frame is given) are candidates; each gets a feature
vector (an 11 x 7 patch around it in the frame and in the difference, normalised by its
contrast, and a few scalars: :mod:`trackers._learned_kernels`) and a two-layer MLP gives its
stripe logit and a sub-pixel offset from a Gaussian 3-point fit. A row's column is its chosen
candidate's fit plus its offset and its ``score`` the network's stripe probability (the sigmoid of
the logit). With both chain costs 0 a row reports its most probable candidate when that reaches
``threshold``; otherwise the rows are decided together, as the best chain of candidates and *none*
down the frame (:func:`choose`, :func:`trackers._learned_kernels.decode`), so that a row in line with
sure neighbours may report below the threshold and a lone peak off the line may stay quiet.

The weights are ``trackers/models/learned.npz`` (format :data:`FORMAT_VERSION`), written by
``stripebench train`` (:mod:`bench.studies.train`) from rendered training sets
(``stripebench trainset``) and nothing else; the file records its data, seeds,
architecture, hyper-parameters, held-out numbers and provenance (``provenance`` key, JSON).
The forward pass is numpy and numba only.
"""

from __future__ import annotations

import errno
import io
import json
import os
import stat
import zipfile
from functools import lru_cache
from pathlib import Path

import numpy as np

from ._base import Track, Tracker
from ._params import Int, Real
from ._stripe import StripeSettings, answer

__all__ = ["LearnedTracker", "FORMAT_VERSION", "DEFAULT_WEIGHTS", "WeightsError", "load_weights", "check_weights",
           "weights_info", "PARAM_KEYS", "WEIGHT_SCALARS", "MAX_WEIGHTS_BYTES", "MAX_ARRAY_BYTES", "MAX_HIDDEN",
           "candidates", "choose"]

FORMAT_VERSION = 1
DEFAULT_WEIGHTS = Path(__file__).resolve().parent / "models" / "learned.npz"
PARAM_KEYS = ("mu", "sd", "w1", "b1", "w2", "b2", "w3", "b3")
MAX_OFFSET = 1.5  # px: the network's correction of the 3-point fit is clipped to this


class _WeightsPath:
    """A weights file's path (str or Path) or None."""

    def check(self, name: str, value) -> None:
        if value is not None and (isinstance(value, bool) or not isinstance(value, (str, Path))):
            raise ValueError(f"`{name}` must be a path to a .npz file or None, got {value!r}")

    def invalid(self) -> list:
        return [1, True, 2.5]


class WeightsError(ValueError):
    """A weights file that cannot be used; ``str(err)`` is one line naming the file and, where one is at
    fault, the key."""


#: The largest weights file read, bytes (the committed one is about 33 kB).
MAX_WEIGHTS_BYTES = 64 * 2**20
#: The largest total size of a weights file's arrays once uncompressed, bytes (a zip bomb is refused).
MAX_ARRAY_BYTES = 256 * 2**20
#: The largest hidden layer a weights file may declare (the committed network: 32 and 16).
MAX_HIDDEN = 4096
#: What each scalar of a weights file must be: key -> (kind, constraint); ``kind`` "int" or "real"
#: (a 0-d array of integers, or of real numbers), or "json" (a 0-d string holding JSON). Keys marked
#: optional may be absent (the chain's costs; 0 where a file has none).
WEIGHT_SCALARS = {
    "format_version": ("int", Int()),
    "layout": ("json", None),
    "threshold": ("real", Real(low=0, high=1)),
    "k": ("int", Int(low=1, high=64)),
    "jump_cost": ("real", Real(low=0, high=1e6, optional=True)),
    "switch_cost": ("real", Real(low=0, high=1e6, optional=True)),
    "provenance": ("json", None),
}
_OPTIONAL = ("jump_cost", "switch_cost", "provenance")

_KINDS = ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def load_weights(path=None) -> dict:
    """The network of a weights file (default :data:`DEFAULT_WEIGHTS`): ``PARAM_KEYS`` as float32 arrays,
    ``threshold`` (float), ``k`` (candidates per row), ``jump_cost``, ``switch_cost`` and ``provenance`` (dict).

    The whole file is checked before it is used (:func:`check_weights`): a regular file (a FIFO, a device
    or a folder is refused without waiting), at most :data:`MAX_WEIGHTS_BYTES`, an ``.npz`` archive whose
    every key is present and of its kind, the network's shapes consistent with each other and with the
    features this code computes, every number finite, the scalars within :data:`WEIGHT_SCALARS`.

    Raises
    ------
    WeightsError
        One line naming the file and the key at fault.
    """
    p = Path(DEFAULT_WEIGHTS if path is None else path)
    try:
        st = os.stat(p)
        stamp = (st.st_mtime_ns, st.st_size, st.st_ino)
    except OSError:
        stamp = None  # _load says why
    except ValueError as exc:  # an embedded NUL byte
        raise WeightsError(f"cannot read learned weights {str(p)!r}: {exc}") from None
    return _load(str(p.absolute()), stamp)


def _short(exc: BaseException, limit: int = 160) -> str:
    """An exception as ``Type: its first line``, at most ``limit`` characters of it."""
    text = (str(exc).splitlines() or [""])[0]
    text = text if len(text) <= limit else text[:limit] + "..."
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def _read_bytes(path: str) -> bytes:
    """The bytes of the regular file ``path`` (never blocks on a FIFO)."""
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    except OSError as exc:
        reason = "no such file" if exc.errno == errno.ENOENT else (exc.strerror or str(exc))
        raise WeightsError(f"cannot read learned weights {path!r}: {reason}") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            kind = next((name for test, name in _KINDS if test(st.st_mode)), "not a regular file")
            raise WeightsError(f"learned weights {path!r} are not a regular file ({kind})")
        if st.st_size > MAX_WEIGHTS_BYTES:
            raise WeightsError(f"learned weights {path!r} are too large ({st.st_size} bytes; at most "
                               f"{MAX_WEIGHTS_BYTES})")
        with os.fdopen(fd, "rb", closefd=True) as fh:
            fd = -1
            data = fh.read(MAX_WEIGHTS_BYTES + 1)
    except OSError as exc:
        raise WeightsError(f"cannot read learned weights {path!r}: {exc.strerror or exc}") from None
    finally:
        if fd >= 0:
            os.close(fd)
    if len(data) > MAX_WEIGHTS_BYTES:
        raise WeightsError(f"learned weights {path!r} are too large (more than {MAX_WEIGHTS_BYTES} bytes)")
    return data


def _read_arrays(path: str, data: bytes) -> dict:
    """Every array of an ``.npz`` archive's bytes."""
    if not data:
        raise WeightsError(f"learned weights {path!r} are an empty file, not an .npz archive")
    if data.startswith(b"\x93NUMPY"):
        raise WeightsError(f"learned weights {path!r} are one .npy array, not an .npz archive of named arrays "
                           "(stripebench train writes them)")
    if not data.startswith(b"PK"):
        raise WeightsError(f"learned weights {path!r} are not an .npz archive (not a zip file)")
    try:
        with zipfile.ZipFile(io.BytesIO(data)) as zf:
            total = sum(info.file_size for info in zf.infolist())
        if total > MAX_ARRAY_BYTES:
            raise WeightsError(f"learned weights {path!r} hold {total} bytes of arrays once uncompressed (at most "
                               f"{MAX_ARRAY_BYTES})")
        with np.load(io.BytesIO(data), allow_pickle=False) as z:
            names = list(z.files)
            out = {}
            for key in names:
                try:
                    out[key] = z[key]
                except Exception as exc:  # noqa: BLE001 - a damaged member: BadZipFile (CRC), zlib.error, EOFError...
                    raise WeightsError(f"learned weights {path!r}: `{key}` is unreadable ({_short(exc)})") from None
    except WeightsError:
        raise
    except Exception as exc:  # noqa: BLE001 - a damaged archive: BadZipFile, EOFError, ValueError, OSError...
        raise WeightsError(f"cannot read learned weights {path!r}: not a readable .npz archive ({_short(exc)})") \
            from None
    return out


def check_weights(data: dict, path: str = "<weights>") -> dict:
    """The network of a weights file's arrays (``key -> ndarray``), every key checked; see :func:`load_weights`.

    Raises
    ------
    WeightsError
        ``learned weights 'PATH': `KEY` ...``: a key missing, of another kind (a string where a number
        belongs, an array where a scalar belongs), a shape that does not fit the others, a NaN or
        infinite number, a value outside :data:`WEIGHT_SCALARS`, another format version or feature layout.
    """
    from . import _learned_kernels as lk

    where = f"learned weights {path!r}"
    missing = [k for k in (*WEIGHT_SCALARS, *PARAM_KEYS) if k not in data and k not in _OPTIONAL]
    if missing:
        raise WeightsError(f"{where} lack {', '.join(f'`{k}`' for k in missing)} (stripebench train writes them)")
    got = {}
    for key, (kind, constraint) in WEIGHT_SCALARS.items():
        if key not in data:
            got[key] = None
            continue
        a = data[key]
        if a.shape != ():
            raise WeightsError(f"{where}: `{key}` must be one value, got an array of shape {a.shape}")
        if kind == "json":
            if a.dtype.kind != "U":
                raise WeightsError(f"{where}: `{key}` must be a JSON string, got dtype {a.dtype}")
            try:
                got[key] = json.loads(str(a))
            except (ValueError, RecursionError) as exc:
                raise WeightsError(f"{where}: `{key}` is not valid JSON ({_short(exc)})") from None
            continue
        if a.dtype.kind not in ("iu" if kind == "int" else "iuf"):
            what = "an integer" if kind == "int" else "a real number"
            raise WeightsError(f"{where}: `{key}` must be {what}, got dtype {a.dtype}")
        v = int(a) if kind == "int" else float(a)
        try:
            constraint.check(key, v)
        except ValueError as exc:
            raise WeightsError(f"{where}: {exc}") from None
        got[key] = v
    if got["format_version"] != FORMAT_VERSION:
        raise WeightsError(f"{where} have format version {got['format_version']}, this stripebench reads "
                           f"version {FORMAT_VERSION}: retrain with `stripebench train`")
    want = feature_layout()
    if got["layout"] != want:
        raise WeightsError(f"{where}: `layout` says the network was trained on features "
                           f"{_clip(got['layout'])}, this code computes {want}")
    if got["provenance"] is not None and not isinstance(got["provenance"], dict):
        raise WeightsError(f"{where}: `provenance` must be a JSON object, got {type(got['provenance']).__name__}")
    net = {}
    for key in PARAM_KEYS:
        a = data[key]
        if a.dtype.kind not in "iuf":
            raise WeightsError(f"{where}: `{key}` must hold real numbers, got dtype {a.dtype}")
        with np.errstate(over="ignore"):
            net[key] = np.ascontiguousarray(a, dtype=np.float32)
    F = lk.N_FEATURES
    h1 = net["w1"].shape[1] if net["w1"].ndim == 2 else -1
    h2 = net["w2"].shape[1] if net["w2"].ndim == 2 else -1
    shapes = {"mu": (F,), "sd": (F,), "w1": (F, h1), "b1": (h1,), "w2": (h1, h2), "b2": (h2,), "w3": (h2, 2),
              "b3": (2,)}
    for key in ("w1", "w2", "w3", "mu", "sd", "b1", "b2", "b3"):  # the layers first: they fix H1 and H2
        if net[key].shape != shapes[key]:
            raise WeightsError(f"{where}: `{key}` has shape {net[key].shape}, expected {_shape_rule(key, F)} "
                               f"(an MLP of {F} features; w1 {data['w1'].shape}, w2 {data['w2'].shape})")
        if key in ("w1", "w2") and not 1 <= net[key].shape[1] <= MAX_HIDDEN:
            raise WeightsError(f"{where}: `{key}` has {net[key].shape[1]} columns; a hidden layer has 1 .. "
                               f"{MAX_HIDDEN}")
    for key in PARAM_KEYS:
        bad = int(net[key].size - np.count_nonzero(np.isfinite(net[key])))
        if bad:
            raise WeightsError(f"{where}: `{key}` holds {bad} NaN or infinite value(s) (in float32)")
    if not np.all(net["sd"] > 0):
        raise WeightsError(f"{where}: `sd` must be > 0 everywhere (the inputs are divided by it), got "
                           f"{int(np.count_nonzero(~(net['sd'] > 0)))} value(s) <= 0")
    for a in net.values():
        a.flags.writeable = False
    return {**net, "threshold": got["threshold"], "k": got["k"],
            "jump_cost": got["jump_cost"] or 0.0, "switch_cost": got["switch_cost"] or 0.0,
            "provenance": got["provenance"] or {}}


def _shape_rule(key: str, n_features: int) -> str:
    return {"mu": f"({n_features},)", "sd": f"({n_features},)", "w1": f"({n_features}, H1)", "b1": "(H1,)",
            "w2": "(H1, H2)", "b2": "(H2,)", "w3": "(H2, 2)", "b3": "(2,)"}[key]


def _clip(value, limit: int = 200) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[:limit] + f"... ({len(text)} characters)"


@lru_cache(maxsize=8)
def _load(path: str, _stamp) -> dict:
    return check_weights(_read_arrays(path, _read_bytes(path)), path)


def feature_layout() -> dict:
    """What the features are: a weights file records it and is refused for another."""
    from . import _learned_kernels as lk

    return {"half_w": lk.HALF_W, "row_offsets": list(lk.ROW_OFFSETS), "scalars": list(lk.SCALARS),
            "n_features": lk.N_FEATURES}


def weights_info(path=None) -> dict:
    """The provenance a weights file records (data, seeds, architecture, hyper-parameters, validation)."""
    return load_weights(path)["provenance"]


def candidates(image, background, net: dict):
    """Every candidate of every row: (logit, column, base), each (H, K) float64. ``logit``: the network's
    stripe logit (``-inf`` where a row has fewer than K candidates); ``column``: the candidate's base
    (its 3-point fit) plus the network's offset, clipped to :data:`MAX_OFFSET`; ``base``: the fit alone.
    ``net`` as :func:`load_weights` returns."""
    from . import _learned_kernels as lk

    feats, cols, base = lk.features(image, background, net["k"])
    H, K, F = feats.shape
    out = lk.mlp_forward(feats.reshape(H * K, F), net, has_background=background is not None).reshape(H, K, 2)
    logit = np.where(cols >= 0, out[..., 0].astype(np.float64), -np.inf)
    col = base + np.clip(out[..., 1].astype(np.float64), -MAX_OFFSET, MAX_OFFSET)
    return logit, col, base


def _sigmoid(z):
    z = np.asarray(z, np.float64)
    fin = np.isfinite(z)
    zz = np.where(fin, z, 0.0)
    e = np.exp(-np.abs(zz))  # a sigmoid that cannot overflow
    return np.where(fin, np.where(zz >= 0, 1.0 / (1.0 + e), e / (1.0 + e)), np.where(z > 0, 1.0, 0.0))


def _logit(p: float) -> float:
    p = min(max(float(p), 1e-12), 1.0 - 1e-12)
    return float(np.log(p / (1.0 - p)))


def choose(logit, col, base, threshold: float, jump_cost: float = 0.0, switch_cost: float = 0.0):
    """Each row's reported (column, probability, reported?) from its candidates (:func:`candidates`).

    With both costs 0 a row reports its most probable candidate when that probability reaches
    ``threshold``. Otherwise the rows are decided together (:func:`trackers._learned_kernels.decode`,
    with *none* scored at the logit of ``threshold``): a chain of candidates that stays in line is
    preferred to one that jumps (``jump_cost`` per px) or switches to and from no stripe
    (``switch_cost``), so an unsure row between sure ones in line is reported and a lone sure-looking
    peak off the line may not be. (Costs 0 give the same rows through the chain, a test checks; the
    direct rule is faster and compares probabilities exactly.)"""
    from . import _learned_kernels as lk

    rows = np.arange(logit.shape[0])
    if jump_cost == 0 and switch_cost == 0:
        pick = np.argmax(logit, axis=1)
        prob = _sigmoid(logit[rows, pick])
        ok = (prob >= threshold) & (prob > 0)
    else:
        chosen = lk.decode(logit, base, _logit(threshold), jump_cost, switch_cost)
        ok = chosen >= 0
        pick = np.where(ok, chosen, 0)
        prob = np.where(ok, _sigmoid(logit[rows, pick]), 0.0)
    c = col[rows, pick]
    return c, prob, ok & np.isfinite(c)


class LearnedTracker(Tracker):
    """Per row, the candidate peak a small network calls the stripe, if it is sure enough.

    Parameters
    ----------
    threshold : float or None, default None
        Least stripe probability of a reported row, in [0, 1]; None: the weights' own, chosen on
        held-out renders by F1 over rows (a miss and a false report priced alike).
    weights : str or None, default None
        A weights file (``.npz``, format :data:`FORMAT_VERSION`); None: the committed
        ``trackers/models/learned.npz``.
    jump_cost : float or None, default None
        Logit units per px of column change between consecutive reported rows (the rows are then decided
        together, :func:`choose`); None: the weights' own (0 when the file has none).
    switch_cost : float or None, default None
        Logit units per change between a reported row and an unreported one; None: the weights' own.
    stripe_test : dict or None, default None
        The stripe question's settings (:class:`trackers.StripeTest`; ``{}``: its defaults), asked of
        the rows it would report, on the frame (laser-on minus laser-off where a laser-off frame is
        given) with the laser-off frame and the colour evidence where given; a row it says no to
        reports nothing. None: not asked.

    Notes
    -----
    ``score`` is the network's stripe probability of the reported row (at least the weights' threshold,
    0.1 for the committed weights, when both chain costs are 0; with the chain, a row carried by its
    neighbours may score lower, so the score still ranks rows for AP). With a laser-off frame the
    candidates are the difference's peaks, so light present in both frames is not a candidate, and a
    laser-off frame equal to the frame leaves none. Trained on renders only (``stripebench train``).

    Examples
    --------
    >>> from trackers.testing import make_stripe_image
    >>> img, truth = make_stripe_image(seed=1)
    >>> out = LearnedTracker().track(img)
    >>> err = np.abs(out.columns - truth)
    >>> bool(np.nanmedian(err) < 0.1), bool(np.nanmax(err) < 1.0), bool(np.all(out.score[out.detected] >= 0.1))
    (True, True, True)
    """

    name = "learned"
    subpixel = True
    uses_background = True
    uses_colour = True

    def __init__(self, threshold=None, weights=None, jump_cost=None, switch_cost=None, stripe_test=None):
        self.threshold = threshold
        self.weights = weights
        self.jump_cost = jump_cost
        self.switch_cost = switch_cost
        self.stripe_test = stripe_test

    parameter_constraints = {"threshold": Real(low=0, high=1, optional=True), "weights": _WeightsPath(),
                             "jump_cost": Real(low=0, optional=True), "switch_cost": Real(low=0, optional=True),
                             "stripe_test": StripeSettings()}

    def validate_params(self) -> None:
        """The parameters' table, then the weights file, checked whole (:func:`load_weights`; a
        :class:`WeightsError`, a ``ValueError``, naming the file and the key): a configuration naming
        damaged weights is refused before any frame."""
        super().validate_params()
        load_weights(self.weights)

    def find_stripe(self, image, background, colour=None):
        net = load_weights(self.weights)
        thr = net["threshold"] if self.threshold is None else float(self.threshold)
        jc = net["jump_cost"] if self.jump_cost is None else float(self.jump_cost)
        sc = net["switch_cost"] if self.switch_cost is None else float(self.switch_cost)
        col, prob, ok = choose(*candidates(image, background, net), thr, jc, sc)
        W = image.shape[1]
        col = np.clip(col, -0.5, W - 0.5)
        if self.stripe_test is not None:
            frame = image if background is None else np.subtract(image, background, dtype=np.float64)
            said = answer(self.stripe_test, frame, np.where(ok, col, np.nan), image=image, background=background,
                          colour=colour)
            ok = ok & said.yes
        return Track(np.where(ok, col, np.nan), np.where(ok, prob, np.nan))
