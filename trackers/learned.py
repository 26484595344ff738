"""``learned``: a small network, trained on renders only, decides each row's stripe among its candidate peaks.

Per row, the ``K`` strongest local maxima of the lightly smoothed row (of the laser-on minus
laser-off difference when a laser-off frame is given) are candidates; each gets a feature
vector (an 11 x 7 patch around it in the frame and in the difference, normalised by its
contrast, and a few scalars: :mod:`trackers._learned_kernels`) and a two-layer MLP gives its
stripe logit and a sub-pixel offset from a Gaussian 3-point fit. The row's column is the best
candidate's fit plus its offset; its ``score`` is the network's stripe probability (the
sigmoid of the logit) and the row is reported when that reaches ``threshold``.

The weights are ``trackers/models/learned.npz`` (format :data:`FORMAT_VERSION`), written by
``stripebench train`` (:mod:`bench.studies.train`) from rendered training sets
(``stripebench trainset``) and nothing else; the file records its data, seeds,
architecture, hyper-parameters, held-out numbers and provenance (``provenance`` key, JSON).
The forward pass is numpy and numba only.
"""

from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path

import numpy as np

from ._base import Track, Tracker
from ._params import Real

__all__ = ["LearnedTracker", "FORMAT_VERSION", "DEFAULT_WEIGHTS", "WeightsError", "load_weights", "weights_info",
           "PARAM_KEYS"]

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
    """A weights file that cannot be used; ``str(err)`` is one line naming the file."""


def load_weights(path=None) -> dict:
    """The network of a weights file (default :data:`DEFAULT_WEIGHTS`): ``PARAM_KEYS`` as float32 arrays,
    ``threshold`` (float), ``k`` (candidates per row) and ``provenance`` (dict).

    Raises
    ------
    WeightsError
        Missing or unreadable file, another format version, a network of another shape, or features
        of another layout than :mod:`trackers._learned_kernels` computes (one line).
    """
    p = Path(DEFAULT_WEIGHTS if path is None else path)
    return _load(str(p.resolve()), p.stat().st_mtime_ns if p.exists() else 0)


@lru_cache(maxsize=8)
def _load(path: str, _mtime: int) -> dict:
    from . import _learned_kernels as lk

    try:
        with np.load(path, allow_pickle=False) as z:
            data = {k: z[k] for k in z.files}
    except (OSError, ValueError) as exc:
        raise WeightsError(f"cannot read learned weights {path!r}: {exc}") from None
    version = int(data["format_version"]) if "format_version" in data else None
    if version != FORMAT_VERSION:
        raise WeightsError(f"learned weights {path!r} have format version {version}, this stripebench reads "
                           f"version {FORMAT_VERSION}: retrain with `stripebench train`")
    missing = [k for k in (*PARAM_KEYS, "threshold", "k", "layout") if k not in data]
    if missing:
        raise WeightsError(f"learned weights {path!r} lack {', '.join(missing)}")
    layout = json.loads(str(data["layout"]))
    want = feature_layout()
    if layout != want:
        raise WeightsError(f"learned weights {path!r} were trained on features {layout}, this code computes {want}")
    net = {k: np.ascontiguousarray(data[k], dtype=np.float32) for k in PARAM_KEYS}
    if net["w1"].shape[0] != lk.N_FEATURES or net["w3"].shape[1] != 2:
        raise WeightsError(f"learned weights {path!r}: a network of input {net['w1'].shape[0]} and output "
                           f"{net['w3'].shape[1]}, expected {lk.N_FEATURES} and 2")
    for a in net.values():
        a.flags.writeable = False
    prov = json.loads(str(data["provenance"])) if "provenance" in data else {}
    return {**net, "threshold": float(data["threshold"]), "k": int(data["k"]), "provenance": prov}


def feature_layout() -> dict:
    """What the features are: a weights file records it and is refused for another."""
    from . import _learned_kernels as lk

    return {"half_w": lk.HALF_W, "row_offsets": list(lk.ROW_OFFSETS), "scalars": list(lk.SCALARS),
            "n_features": lk.N_FEATURES}


def weights_info(path=None) -> dict:
    """The provenance a weights file records (data, seeds, architecture, hyper-parameters, validation)."""
    return load_weights(path)["provenance"]


def predict(image, background, net: dict):
    """Per row the best candidate's (column, probability), NaN-free arrays with -inf/0 where no candidate;
    also returns every candidate's logits for studies. ``net`` as :func:`load_weights` returns."""
    from . import _learned_kernels as lk

    feats, cols, base = lk.features(image, background, net["k"])
    H, K, F = feats.shape
    out = lk.mlp_forward(feats.reshape(H * K, F), net, has_background=background is not None).reshape(H, K, 2)
    logit = np.where(cols >= 0, out[..., 0].astype(np.float64), -np.inf)
    best = np.argmax(logit, axis=1)
    rows = np.arange(H)
    bl = logit[rows, best]
    off = np.clip(out[rows, best, 1].astype(np.float64), -MAX_OFFSET, MAX_OFFSET)
    col = base[rows, best] + off
    z = np.where(np.isfinite(bl), bl, 0.0)
    e = np.exp(-np.abs(z))  # a sigmoid that cannot overflow
    prob = np.where(np.isfinite(bl), np.where(z >= 0, 1.0 / (1.0 + e), e / (1.0 + e)), 0.0)
    return col, prob, logit


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

    Notes
    -----
    ``score`` is the network's stripe probability of the reported row (from the weights' threshold,
    0.3 for the committed weights, to 1 at the default operating point). With a laser-off frame the
    candidates are the difference's peaks, so light present in both frames is not a candidate, and a
    laser-off frame equal to the frame leaves none. Trained on renders only (``stripebench train``).

    Examples
    --------
    >>> from trackers.testing import make_stripe_image
    >>> img, truth = make_stripe_image(seed=1)
    >>> out = LearnedTracker().track(img)
    >>> err = np.abs(out.columns - truth)
    >>> bool(np.nanmedian(err) < 0.1), bool(np.nanmax(err) < 1.0), bool(np.all(out.score[out.detected] >= 0.3))
    (True, True, True)
    """

    name = "learned"
    subpixel = True
    uses_background = True

    def __init__(self, threshold=None, weights=None):
        self.threshold = threshold
        self.weights = weights

    parameter_constraints = {"threshold": Real(low=0, high=1, optional=True), "weights": _WeightsPath()}

    def find_stripe(self, image, background):
        net = load_weights(self.weights)
        thr = net["threshold"] if self.threshold is None else float(self.threshold)
        col, prob, _ = predict(image, background, net)
        ok = (prob >= thr) & (prob > 0) & np.isfinite(col)
        W = image.shape[1]
        col = np.clip(col, -0.5, W - 0.5)
        return Track(np.where(ok, col, np.nan), np.where(ok, prob, np.nan))
