"""Every statistic of the harness: the paper's precision-improvement ratio with paired bootstrap intervals,
Wilson and Student-t intervals, robust summaries and scales, the bootstrap mean over images."""

from __future__ import annotations

import functools

import numpy as np

from bench.evaluate.outcomes import GROSS_MM, WITHIN_MM, gross, within

__all__ = ["spread", "improvement", "bootstrap_improvement", "resample_indices", "spread_resampled",
           "improvement_interval", "wilson_interval", "robust_summary", "bootstrap_mean", "t_interval", "mad_scale",
           "STATISTICS", "WITHIN_MM", "GROSS_MM"]

STATISTICS = ("rmse", "mae", "std")


def wilson_interval(k: int, n: int, level: float = 0.95) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion ``k / n`` (NaN, NaN if ``n == 0``).

    Examples
    --------
    >>> [round(x, 4) for x in wilson_interval(8, 10)]
    [0.4902, 0.9433]
    """
    from scipy.stats import norm

    if n <= 0:
        return float("nan"), float("nan")
    z = float(norm.ppf(0.5 + level / 2.0))
    p = k / n
    den = 1.0 + z * z / n
    centre = (p + z * z / (2 * n)) / den
    half = z * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / den
    return float(max(0.0, centre - half)), float(min(1.0, centre + half))


def robust_summary(errors_mm, *, within_mm: float = WITHIN_MM, gross_mm: float = GROSS_MM,
                   level: float = 0.95) -> dict[str, float]:
    """Robust figures of one tracker's depth errors at the sample points.

    Parameters
    ----------
    errors_mm : array_like, shape (n,)
        Signed depth errors (mm); NaN entries (no value) are dropped.
    within_mm, gross_mm : float
        Half-width of the band counted as "within" (the paper's ±5 mm) and the
        size of a gross error.

    Returns
    -------
    dict with ``n``, ``within`` (fraction with ``|e| <= within_mm``), ``within_low``,
    ``within_high`` (Wilson interval), ``median_abs_mm``, ``median_mm`` (the signed median: the
    systematic bias, e.g. of a translucent surface), ``p95_abs_mm``, ``n_gross`` (``|e| > gross_mm``)
    and ``rmse_mm``.

    Examples
    --------
    >>> r = robust_summary([1.0, -2.0, 7.0, 80.0])
    >>> r["within"], r["median_abs_mm"], r["median_mm"], r["n_gross"]
    (0.5, 4.5, 4.0, 1)
    """
    e = np.asarray(errors_mm, dtype=np.float64)
    signed = e[~np.isnan(e)]
    e = np.abs(signed)
    n = int(e.size)
    if n == 0:
        nan = float("nan")
        return {"n": 0, "within": nan, "within_low": nan, "within_high": nan, "median_abs_mm": nan,
                "median_mm": nan, "p95_abs_mm": nan, "n_gross": 0, "rmse_mm": nan}
    k = int(np.count_nonzero(within(e, within_mm)))
    lo, hi = wilson_interval(k, n, level)
    return {"n": n, "within": k / n, "within_low": lo, "within_high": hi, "median_abs_mm": float(np.median(e)),
            "median_mm": float(np.median(signed)), "p95_abs_mm": float(np.percentile(e, 95)), "n_gross": int(np.count_nonzero(gross(e, gross_mm))),
            "rmse_mm": float(np.sqrt(np.mean(e * e)))}


def spread(errors, statistic: str = "rmse") -> float:
    """RMSE, MAE or standard deviation of ``errors`` (NaNs are an error)."""
    e = np.asarray(errors, dtype=np.float64)
    if np.isnan(e).any():
        raise ValueError("`errors` must not contain NaN")
    if statistic == "rmse":
        return float(np.sqrt(np.mean(e * e)))
    if statistic == "mae":
        return float(np.mean(np.abs(e)))
    if statistic == "std":
        return float(np.std(e, ddof=1)) if e.size > 1 else float("nan")
    raise ValueError(f"`statistic` must be one of {STATISTICS}, got {statistic!r}")


def improvement(errors_dp, errors_base, statistic: str = "rmse") -> float:
    """``1 - S(errors_dp) / S(errors_base)``: the paper's "30 % more precise".

    Positive when DP's errors are smaller. Both arrays are errors at the same
    sample points (paired).
    """
    a, b = _paired(errors_dp, errors_base)
    return _ratio(spread(a, statistic), spread(b, statistic))


def _paired(errors_dp, errors_base) -> tuple[np.ndarray, np.ndarray]:
    a = np.asarray(errors_dp, dtype=np.float64)
    b = np.asarray(errors_base, dtype=np.float64)
    if a.shape != b.shape or a.ndim != 1:
        raise ValueError(f"`errors_dp` and `errors_base` must be 1-D of one length, got {a.shape} and {b.shape}")
    return a, b


def _ratio(s_dp: float, s_base: float) -> float:
    """``1 - s_dp / s_base`` (NaN when the baseline's spread is 0)."""
    return float("nan") if s_base == 0 else 1.0 - s_dp / s_base


@functools.lru_cache(maxsize=4)
def resample_indices(seed: int, n: int, n_boot: int) -> np.ndarray:
    """The (n_boot, n) resampling indices of ``numpy.random.default_rng(seed)`` (read-only, the last
    few kept: a run asks for the same ones for every tracker pair of a group and statistic).

    Examples
    --------
    >>> resample_indices(0, 3, 2).shape
    (2, 3)
    """
    idx = np.random.default_rng(seed).integers(0, n, size=(n_boot, n))
    idx.flags.writeable = False
    return idx


def bootstrap_improvement(errors_dp, errors_base, statistic: str = "rmse", *, n_boot: int = 2000, seed: int = 0,
                          level: float = 0.95) -> dict[str, float]:
    """The improvement and its percentile bootstrap confidence interval.

    Samples are resampled in pairs (the same points for both trackers), with
    ``numpy.random.default_rng(seed)``.

    Returns
    -------
    dict with ``value``, ``low``, ``high``, ``level``, ``n``, ``n_boot``.
    """
    a, b = _paired(errors_dp, errors_base)
    n = a.size
    idx = resample_indices(int(seed), int(n), int(n_boot))
    return improvement_interval(spread_resampled(a, statistic, idx), spread_resampled(b, statistic, idx), n, level)


def spread_resampled(errors, statistic: str, idx: np.ndarray) -> tuple[float, np.ndarray]:
    """``(S(errors), S of each resample)``: the spread (:func:`spread`) of ``errors`` (n,) and of each
    row of ``errors[idx]`` (``idx`` (n_boot, n) resampling indices), for :func:`improvement_interval`.
    One tracker's resampled spreads serve every pair it is in (same points, same indices)."""
    e = np.asarray(errors, dtype=np.float64)
    if statistic == "rmse":  # (x * x)[idx] is x[idx] * x[idx], bit for bit, at one gather
        boots = np.sqrt((e * e)[idx].mean(1))
    elif statistic == "mae":
        boots = np.abs(e)[idx].mean(1)
    else:
        boots = e[idx].std(1, ddof=1)
    return spread(e, statistic), boots


def improvement_interval(dp, base, n: int, level: float = 0.95) -> dict[str, float]:
    """:func:`bootstrap_improvement`'s result from the two trackers' :func:`spread_resampled` over the
    same ``n`` points."""
    (s_dp, boot_dp), (s_base, boot_base) = dp, base
    value = _ratio(s_dp, s_base)
    with np.errstate(divide="ignore", invalid="ignore"):
        boots = 1.0 - boot_dp / boot_base
    boots = boots[np.isfinite(boots)]
    alpha = (1.0 - level) / 2.0
    low, high = (np.quantile(boots, [alpha, 1 - alpha]) if boots.size else (np.nan, np.nan))
    return {"value": value, "low": float(low), "high": float(high), "level": level, "n": int(n),
            "n_boot": int(boot_dp.size)}


def bootstrap_mean(values, *, n_boot: int = 2000, seed: int = 0, level: float = 0.95) -> dict[str, float]:
    """Mean over images with a percentile bootstrap interval (images resampled
    with replacement; NaNs dropped first; seeded).

    Returns
    -------
    dict
        ``mean``, ``lo``, ``hi``, ``n`` (NaN bounds with fewer than 2 values).

    Examples
    --------
    >>> bootstrap_mean([1.0, 1.0, np.nan])
    {'mean': 1.0, 'lo': 1.0, 'hi': 1.0, 'n': 2}
    """
    v = np.asarray(values, dtype=np.float64)
    v = v[~np.isnan(v)]
    if v.size == 0:
        return {"mean": float("nan"), "lo": float("nan"), "hi": float("nan"), "n": 0}
    if v.size < 2:
        return {"mean": float(v.mean()), "lo": float("nan"), "hi": float("nan"), "n": int(v.size)}
    rng = np.random.default_rng(seed)
    idx = rng.integers(0, v.size, size=(n_boot, v.size))
    means = v[idx].mean(axis=1)
    a = (1.0 - level) / 2.0
    return {"mean": float(v.mean()), "lo": float(np.quantile(means, a)), "hi": float(np.quantile(means, 1 - a)),
            "n": int(v.size)}


def t_interval(x, level: float = 0.95) -> tuple[float, float, float]:
    """Mean of ``x`` (NaNs dropped) with its Student-t interval: ``(mean, lo, hi)``
    (NaN bounds with fewer than 2 values).

    Examples
    --------
    >>> [round(v, 4) for v in t_interval(np.array([1.0, 2.0, 3.0, np.nan]))]
    [2.0, -0.4841, 4.4841]
    """
    from scipy.stats import t

    x = np.asarray(x, dtype=np.float64)
    x = x[~np.isnan(x)]
    if x.size == 0:
        return float("nan"), float("nan"), float("nan")
    m = float(x.mean())
    if x.size < 2:
        return m, float("nan"), float("nan")
    half = float(t.ppf(0.5 + level / 2.0, x.size - 1) * x.std(ddof=1) / np.sqrt(x.size))
    return m, m - half, m + half


def mad_scale(d: np.ndarray) -> float:
    """``1.4826 median(|d - median(d)|)``: the standard deviation of a normal sample, robust to outliers.

    Examples
    --------
    >>> round(mad_scale(np.array([-1.0, 0.0, 1.0, 100.0])), 4)
    1.4826
    """
    d = np.asarray(d, float)
    d = d[np.isfinite(d)]
    return float(1.4826 * np.median(np.abs(d - np.median(d)))) if d.size else np.nan
