"""Leave one rig out: how a choice made on photographs is judged.

A figure chosen and measured on the same photographs says how well the choice fits them, not how it does on
the next rig. Every choice made on photographs (an operating point, a rule, a prediction) is therefore judged
by folds that hold out one rig at a time: the choice is made on the other rigs and scored on the held-out
one, and the held-out scores are pooled over the folds. A *rig* is one camera-and-laser set-up
(:attr:`bench.store.realset.RealImage.rig`); photographs of one rig are never on both sides of a fold.

:func:`rig_folds` gives the folds; :func:`choose_by_fold` runs a choice on every fold from per-rig row-outcome
counts and pools what it scores on the held-out rigs; :func:`null_prediction` is the plain baseline every
prediction must beat: each item's mean over the other rigs; :func:`rig_figures` gives detection figures per rig,
with intervals over its photographs, and over all rigs with intervals over rigs.

Pure functions: arrays and dicts in, numbers out.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Hashable, Mapping, Sequence

import numpy as np

from bench.evaluate.outcomes import detection_figures

__all__ = ["Fold", "rig_folds", "FoldChoice", "choose_by_fold", "pooled_counts", "null_prediction", "RIG_FIGURES",
           "rig_figures"]


@dataclass(frozen=True, eq=False)
class Fold:
    """One fold: the rig held out and which items are on each side.

    Attributes
    ----------
    rig : str
        The held-out rig.
    test : ndarray of bool, shape (n,)
        The items of the held-out rig.
    train : ndarray of bool, shape (n,)
        Every other item (``~test``).
    """

    rig: str
    test: np.ndarray
    train: np.ndarray


def rig_folds(rigs: Sequence[str]) -> list[Fold]:
    """One fold per distinct rig, in sorted order of the rigs.

    Parameters
    ----------
    rigs : sequence of str, length n
        The rig of each item (photograph, record).

    Returns
    -------
    list of Fold
        No rig lies on both sides of a fold; every item is held out exactly once.

    Raises
    ------
    ValueError
        Fewer than two rigs (nothing to hold out against), or an empty rig name.

    Examples
    --------
    >>> [(f.rig, f.test.tolist()) for f in rig_folds(["b", "a", "b"])]
    [('a', [False, True, False]), ('b', [True, False, True])]
    """
    r = np.asarray([str(x) for x in rigs], dtype=object)
    if any(x == "" for x in r):
        raise ValueError("leave one rig out: an item has an empty rig name")
    names = sorted(set(r.tolist()))
    if len(names) < 2:
        raise ValueError(f"leave one rig out needs at least two rigs, got {len(names)}")
    return [Fold(name, r == name, r != name) for name in names]


def pooled_counts(counts: Mapping[str, np.ndarray], rigs) -> np.ndarray:
    """The row-outcome counts (6,) of ``counts`` (rig -> counts) summed over ``rigs`` (zeros if none)."""
    out = np.zeros(6, dtype=np.int64)
    for r in rigs:
        if r in counts:
            out += np.asarray(counts[r], dtype=np.int64)
    return out


@dataclass(frozen=True)
class FoldChoice:
    """What :func:`choose_by_fold` found: each fold's choice and the pooled held-out figures.

    Attributes
    ----------
    in_sample : hashable
        The candidate chosen with every rig in.
    by_rig : dict
        held-out rig -> the candidate chosen without it.
    loro_counts : ndarray, shape (6,)
        The held-out rigs' counts, each under its fold's choice, summed over the folds.
    in_sample_counts : ndarray, shape (6,)
        Every rig's counts under the in-sample choice.
    """

    in_sample: Hashable
    by_rig: dict
    loro_counts: np.ndarray
    in_sample_counts: np.ndarray

    @property
    def loro(self) -> dict:
        """:func:`bench.evaluate.outcomes.detection_figures` of the held-out counts."""
        return detection_figures(self.loro_counts)

    @property
    def in_sample_figures(self) -> dict:
        """:func:`bench.evaluate.outcomes.detection_figures` of the in-sample counts."""
        return detection_figures(self.in_sample_counts)

    @property
    def stable(self) -> bool:
        """Whether every fold chose the in-sample choice."""
        return all(c == self.in_sample for c in self.by_rig.values())


def choose_by_fold(real_counts: Mapping[Hashable, Mapping[str, np.ndarray]],
                   choose: Callable[[str | None], Hashable]) -> FoldChoice:
    """Run a choice leave one rig out, and score each fold's choice on its held-out rig.

    Parameters
    ----------
    real_counts : dict
        candidate -> (rig -> counts (6,) in :data:`bench.evaluate.outcomes.OUTCOMES` order): what each candidate
        scores on each rig's photographs (pooled over the trackers the choice is for).
    choose : callable
        ``choose(held_out) -> candidate``: the procedure's own rule (its objective over every group of frames, its
        eligibility and its tie rule) with the photographs of the rig ``held_out`` left out; ``None``: with every
        rig in. The other groups of frames (renders, synthetic) are the procedure's own and the same in every fold.

    Returns
    -------
    FoldChoice

    Examples
    --------
    >>> counts = {"loud": {"a": np.array([9, 0, 0, 5, 0, 0]), "b": np.array([9, 0, 0, 0, 0, 0])},
    ...           "quiet": {"a": np.array([8, 0, 1, 0, 5, 0]), "b": np.array([8, 0, 1, 0, 0, 0])}}
    >>> def f1(c):
    ...     return 2 * c[0] / (2 * c[0] + 2 * c[1] + c[2] + c[3]) if c.any() else 0.0
    >>> def choose(held_out):
    ...     keep = [r for r in "ab" if r != held_out]
    ...     return max(counts, key=lambda k: f1(pooled_counts(counts[k], keep)))
    >>> fc = choose_by_fold(counts, choose)
    >>> fc.in_sample, fc.by_rig
    ('quiet', {'a': 'loud', 'b': 'quiet'})
    >>> round(fc.loro["false_report_rate"], 2), round(fc.in_sample_figures["false_report_rate"], 2)
    (1.0, 0.0)
    """
    rigs = sorted({r for per in real_counts.values() for r in per})
    if not rigs:
        raise ValueError("leave one rig out: no rig has counts")
    in_sample = choose(None)
    by_rig, loro = {}, np.zeros(6, dtype=np.int64)
    for rig in rigs if len(rigs) > 1 else ():
        chosen = choose(rig)
        by_rig[rig] = chosen
        loro += pooled_counts(real_counts[chosen], [rig])
    return FoldChoice(in_sample, by_rig, loro, pooled_counts(real_counts[in_sample], rigs))


def null_prediction(values: Mapping[str, np.ndarray] | np.ndarray, rigs: Sequence[str] | None = None) -> dict:
    """The null prediction of each rig's figures: the mean of the other rigs' figures.

    Parameters
    ----------
    values : ndarray, shape (n, k), with ``rigs`` (length n), or dict rig -> ndarray (k,)
        Measured figures (e.g. F1 of k trackers) per item or per rig; NaN is left out of a mean.
        Items of one rig are first averaged into the rig's figure, so each rig weighs the same.

    Returns
    -------
    dict
        rig -> ndarray (k,): the mean over the other rigs (NaN where none has a value).

    Examples
    --------
    >>> p = null_prediction({"a": np.array([0.9, 0.1]), "b": np.array([0.7, 0.3]), "c": np.array([0.8, np.nan])})
    >>> p["a"].tolist(), p["c"].tolist()
    ([0.75, 0.3], [0.8, 0.2])
    """
    if not isinstance(values, Mapping):
        v = np.asarray(values, dtype=np.float64)
        if rigs is None or len(rigs) != v.shape[0]:
            raise ValueError("null_prediction: one rig per row of values is needed")
        r = np.asarray([str(x) for x in rigs], dtype=object)
        with np.errstate(invalid="ignore"):
            per = {name: np.nanmean(v[r == name], axis=0) if np.isfinite(v[r == name]).any() else
                   np.full(v.shape[1:], np.nan) for name in sorted(set(r.tolist()))}
    else:
        per = {k: np.asarray(x, dtype=np.float64) for k, x in values.items()}
    out = {}
    for rig in per:
        others = np.array([per[o] for o in per if o != rig])
        if others.size == 0:
            out[rig] = np.full(np.shape(per[rig]), np.nan)
            continue
        fin = np.isfinite(others)
        n = fin.sum(axis=0)
        s = np.where(fin, others, 0.0).sum(axis=0)
        out[rig] = np.where(n > 0, s / np.maximum(n, 1), np.nan)
    return out


#: The detection figures :func:`rig_figures` gives intervals for.
RIG_FIGURES = ("recall", "f1", "false_report_rate")


def _figures_of(pooled: np.ndarray) -> dict:
    """:data:`RIG_FIGURES` of pooled counts (..., 6), vectorised (NaN where undefined)."""
    c = np.asarray(pooled, dtype=np.float64)
    hit, wrong, missed, false, quiet = (c[..., i] for i in range(5))
    with np.errstate(invalid="ignore", divide="ignore"):
        recall = hit / (hit + wrong + missed)
        f1 = 2 * hit / (2 * hit + 2 * wrong + missed + false)
        frr = false / (false + quiet)
    return {"recall": recall, "f1": f1, "false_report_rate": frr}


def rig_figures(counts, rigs, *, n_boot: int = 2000, seed: int = 0, level: float = 0.95) -> dict:
    """Detection figures per rig and over all rigs, with percentile bootstrap intervals.

    Within a rig the photographs are resampled with replacement (NaN intervals with fewer than two); over all
    rigs the rigs are resampled, then each drawn rig's photographs: the spread a figure has from rig to rig,
    what a user of a rig nobody measured meets.

    Parameters
    ----------
    counts : array_like, shape (n, 6)
        Each photograph's row-outcome counts (:data:`bench.evaluate.outcomes.OUTCOMES` order).
    rigs : sequence of str, length n
        Each photograph's rig.
    n_boot : int
        Resamples, >= 1.
    seed : int
    level : float
        Interval coverage in (0, 1).

    Returns
    -------
    dict
        ``rigs``: rig -> ``n_photos``, :func:`bench.evaluate.outcomes.detection_figures` of its pooled rows and
        ``<figure>_lo``, ``<figure>_hi`` for each of :data:`RIG_FIGURES`; ``all``: the same over every rig
        (``n_rigs`` too), its intervals over rigs (NaN with fewer than two rigs).

    Examples
    --------
    >>> c = [[9, 0, 1, 0, 0, 0], [8, 0, 2, 1, 9, 0], [5, 0, 5, 0, 0, 0]]
    >>> r = rig_figures(c, ["a", "a", "b"], n_boot=200)
    >>> r["rigs"]["b"]["recall"], r["rigs"]["b"]["n_photos"], bool(np.isnan(r["rigs"]["b"]["recall_lo"]))
    (0.5, 1, True)
    >>> r["all"]["n_rigs"], round(r["all"]["recall"], 3)
    (2, 0.733)
    """
    c = np.asarray(counts, dtype=np.int64)
    if c.ndim != 2 or c.shape[1] != 6 or c.shape[0] != len(rigs):
        raise ValueError(f"`counts` must be (n, 6) with one rig per photograph, got {c.shape} and {len(rigs)} rigs")
    if not (isinstance(n_boot, int) and n_boot >= 1) or not 0.0 < level < 1.0:
        raise ValueError(f"`n_boot` must be an integer >= 1 and `level` in (0, 1), got {n_boot!r}, {level!r}")
    r = np.asarray([str(x) for x in rigs], dtype=object)
    names = sorted(set(r.tolist()))
    rng = np.random.default_rng(seed)
    q = (100 * (1 - level) / 2, 100 * (1 + level) / 2)

    def summarise(pooled, boot, extra):
        out = {**extra, **detection_figures(pooled)}
        figs = _figures_of(boot) if boot is not None else None
        for k in RIG_FIGURES:
            if figs is None:
                out[f"{k}_lo"] = out[f"{k}_hi"] = float("nan")
                continue
            v = figs[k][np.isfinite(figs[k])]
            lo, hi = np.percentile(v, q) if v.size else (np.nan, np.nan)
            out[f"{k}_lo"], out[f"{k}_hi"] = float(lo), float(hi)
        return out

    members = {name: c[r == name] for name in names}
    by_rig = {}
    for name in names:
        m = members[name]
        boot = None
        if m.shape[0] >= 2:
            idx = rng.integers(0, m.shape[0], size=(n_boot, m.shape[0]))
            boot = m[idx].sum(axis=1)
        by_rig[name] = summarise(m.sum(axis=0), boot, {"n_photos": int(m.shape[0])})
    boot = None
    if len(names) >= 2:  # rigs drawn with replacement (how often each: `times`), each draw its own photographs' draw
        n = len(names)
        times = rng.multinomial(n, np.full(n, 1.0 / n), size=n_boot)  # (n_boot, n)
        boot = np.zeros((n_boot, 6), dtype=np.int64)
        for j, name in enumerate(names):
            m = members[name]
            k = int(times[:, j].max())
            if k == 0:
                continue
            draws = m[rng.integers(0, m.shape[0], size=(n_boot, k, m.shape[0]))].sum(axis=2)  # (n_boot, k, 6)
            keep = np.arange(k)[None, :] < times[:, j][:, None]  # the first `times` draws of each resample
            boot += (draws * keep[..., None]).sum(axis=1)
    return {"rigs": by_rig, "all": summarise(c.sum(axis=0), boot, {"n_rigs": len(names), "n_photos": int(c.shape[0])})}
