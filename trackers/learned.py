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

import json
from functools import lru_cache
from pathlib import Path

import numpy as np

from ._base import Track, Tracker
from ._params import Real
from ._stripe import StripeSettings, answer

__all__ = ["LearnedTracker", "FORMAT_VERSION", "DEFAULT_WEIGHTS", "WeightsError", "load_weights", "weights_info",
           "PARAM_KEYS", "candidates", "choose"]

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
    # the chain's costs (:func:`choose`) came with round 3's operating point; a file without them decides rows alone
    costs = {k: float(data[k]) if k in data else 0.0 for k in ("jump_cost", "switch_cost")}
    return {**net, "threshold": float(data["threshold"]), "k": int(data["k"]), **costs, "provenance": prov}


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
